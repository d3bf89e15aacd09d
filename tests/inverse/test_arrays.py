"""Orthogonal arrays: built orthogonal, broken ones caught, levels mapped to values."""

import numpy as np
import pytest

from rockcal.errors import InputError
from rockcal.inverse import ARRAY_NAMES, design, is_orthogonal, orthogonal_array, to_values

SHAPES = {"L9(3^4)": (9, 4, {3}), "L16(4^5)": (16, 5, {4}), "L18(2^1 3^7)": (18, 8, {2, 3}),
          "L27(3^13)": (27, 13, {3})}


@pytest.mark.parametrize("name", ARRAY_NAMES)
def test_every_array_is_orthogonal(name):
    assert is_orthogonal(orthogonal_array(name))


@pytest.mark.parametrize("name, shape", SHAPES.items())
def test_shapes_and_levels(name, shape):
    a = orthogonal_array(name)
    runs, cols, levels = shape
    assert a.shape == (runs, cols)
    assert {int(c.max()) + 1 for c in a.T} == levels
    assert a.min() == 0
    assert len({tuple(r) for r in a}) == runs  # no repeated run


def test_lookup_is_lenient_about_spelling():
    assert np.array_equal(orthogonal_array("l16 (4^5)"), orthogonal_array("L16(4^5)"))
    assert np.array_equal(orthogonal_array("L18"), orthogonal_array("L18(2^1 3^7)"))


def test_unknown_array_name():
    with pytest.raises(InputError, match="unknown orthogonal array"):
        orthogonal_array("L17(4^5)")


def test_broken_array_is_detected():
    a = orthogonal_array("L16(4^5)").copy()
    a[0, 2], a[1, 2] = a[1, 2], a[0, 2]  # swapping two cells keeps the column balanced
    assert not is_orthogonal(a)
    full_factorial_minus_one = np.array([[i, j] for i in range(3) for j in range(3)])[:-1]
    assert not is_orthogonal(full_factorial_minus_one)


def test_to_values_and_design_map_levels():
    levels = {"E_c": [15, 20, 25, 30], "kn_ks": [1.0, 1.67, 2.33, 3.0]}
    runs = to_values(orthogonal_array("L16(4^5)"), levels)
    assert sorted(set(runs["E_c"])) == [15, 20, 25, 30]
    assert all(np.sum(runs["kn_ks"] == v) == 4 for v in levels["kn_ks"])
    mixed = design("L18", {"a": [1, 2, 3], "switch": [0, 1], "b": [5, 6, 7]})
    assert sorted(set(mixed["switch"])) == [0, 1] and len(mixed["a"]) == 18
    with pytest.raises(InputError, match="levels.E_c"):
        to_values(orthogonal_array("L9(3^4)"), {"E_c": [1, 2, 3, 4]})


def test_l16_is_the_design_of_the_source_studys_table_3():
    """The source's 16 PFC2D runs (E_c, kn/ks, sigma_c, tau_c, mu of its Table 3, in order),
    so the campaign's sensitivity runs are the source's own and a store can share them."""
    table3 = [(15, 1.0, 20, 50, 0.3), (15, 1.67, 30, 70, 0.4), (15, 2.33, 40, 90, 0.5),
              (15, 3.0, 50, 110, 0.6), (20, 1.0, 30, 90, 0.6), (20, 1.67, 20, 110, 0.5),
              (20, 2.33, 50, 50, 0.4), (20, 3.0, 40, 70, 0.3), (25, 1.0, 40, 110, 0.4),
              (25, 1.67, 50, 90, 0.3), (25, 2.33, 20, 70, 0.6), (25, 3.0, 30, 50, 0.5),
              (30, 1.0, 50, 70, 0.5), (30, 1.67, 40, 50, 0.6), (30, 2.33, 30, 110, 0.3),
              (30, 3.0, 20, 90, 0.4)]
    levels = {"E_c": [15, 20, 25, 30], "kn_ks": [1.0, 1.67, 2.33, 3.0], "sigma_c": [20, 30, 40, 50],
              "tau_c": [50, 70, 90, 110], "mu": [0.3, 0.4, 0.5, 0.6]}
    runs = design("L16(4^5)", levels)
    np.testing.assert_array_equal(np.column_stack([runs[f] for f in levels]), np.array(table3))
