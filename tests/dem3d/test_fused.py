"""The laws' fused multiply-add is a × b + c rounded once, as IEEE 754 defines it: the exact
value rounded to the nearest float, so every processor gives the same bits, in a scalar and in
a vector loop alike."""

from fractions import Fraction

import numpy as np
from numba import njit

from rockcal.dem3d.fused import fma


@njit
def _one(a, b, c):
    return fma(a, b, c)


@njit
def _each(a, b, c):
    out = np.empty_like(a)
    for k in range(a.shape[0]):
        out[k] = fma(a[k], b[k], c[k])
    return out


def _exact(a, b, c) -> float:
    return float(Fraction(a) * Fraction(b) + Fraction(c))  # Fraction to float rounds to nearest


def test_one_rounding_where_a_product_and_a_sum_take_two():
    assert 0.1 * 10.0 - 1.0 == 0.0  # the product rounds to 1 first
    assert _one(0.1, 10.0, -1.0) == _exact(0.1, 10.0, -1.0) == 2.0**-54  # 0.1 is 2⁻⁵⁴ / 10 above 1 / 10


def test_the_exact_value_rounded_in_scalar_and_vector_loops():
    rng = np.random.default_rng(1)
    a, b = rng.normal(size=(2, 1000)) * np.exp(rng.uniform(-20, 20, (2, 1000)))
    c = -a * b * (1 + rng.normal(0, 1e-12, 1000))  # near cancellation: the hardest case
    c[::3] = rng.normal(size=c[::3].shape)
    expected = [_exact(*x) for x in zip(a, b, c)]
    assert _each(a, b, c).tolist() == expected
    assert [_one(*x) for x in zip(a, b, c)] == expected
