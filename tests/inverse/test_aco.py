"""Both ant colony methods find known minima, deterministically with a seed."""

import numpy as np
import pytest

from rockcal.errors import InputError
from rockcal.inverse import ant_colony

CENTRE = np.array([0.3, -1.2, 2.0])


def quadratic(x):
    return float(np.sum((x - CENTRE[:len(x)]) ** 2 * [1, 4, 9][:len(x)]))


def rosenbrock(X):
    return (1 - X[:, 0]) ** 2 + 100 * (X[:, 1] - X[:, 0] ** 2) ** 2


@pytest.mark.parametrize("method", ["ant-system", "acor"])
@pytest.mark.parametrize("d", [2, 3])
def test_quadratic(method, d):
    res = ant_colony(quadratic, [(-5, 5)] * d, method=method, seed=2, iterations=100)
    np.testing.assert_allclose(res.x, CENTRE[:d], atol=1e-3)
    assert res.fun < 1e-6
    assert res.nit == 100 and len(res.history_fun) == 100 and res.history_x.shape == (100, d)
    assert np.all(np.diff(res.history_fun) <= 0)


@pytest.mark.parametrize("method", ["ant-system", "acor"])
def test_rosenbrock(method):
    res = ant_colony(rosenbrock, [(-2, 2)] * 2, method=method, seed=1, vectorized=True, iterations=400)
    np.testing.assert_allclose(res.x, [1, 1], atol=2e-2)
    assert res.fun < 1e-3


@pytest.mark.parametrize("method", ["ant-system", "acor"])
def test_deterministic_with_seed(method):
    a = ant_colony(rosenbrock, [(-2, 2)] * 2, method=method, seed=7, vectorized=True, iterations=30)
    b = ant_colony(rosenbrock, [(-2, 2)] * 2, method=method, seed=7, vectorized=True, iterations=30)
    c = ant_colony(rosenbrock, [(-2, 2)] * 2, method=method, seed=8, vectorized=True, iterations=30)
    assert np.array_equal(a.history_x, b.history_x) and a.fun == b.fun and a.nfev == b.nfev
    assert not np.array_equal(a.history_x, c.history_x)


def test_ant_system_source_settings_and_counts():
    res = ant_colony(rosenbrock, [(-2, 2)] * 2, method="ant-system", vectorized=True, seed=0, iterations=5)
    assert res.nfev == 5 * 50 and res.history_nfev[-1] == res.nfev
    res = ant_colony(quadratic, [(-5, 5)] * 2, method="acor", seed=0, iterations=5)
    assert res.nfev == 30 + 5 * 10


def test_stops_on_target_and_callback():
    res = ant_colony(quadratic, [(-5, 5)] * 2, seed=0, target=1e-2)
    assert res.fun <= 1e-2 and res.nit < 200 and "target" in res.message
    seen = []
    res = ant_colony(quadratic, [(-5, 5)] * 2, seed=0, callback=lambda r: seen.append(r.fun) or len(seen) == 3)
    assert res.nit == 3 and seen == list(res.history_fun)


def test_bad_options():
    with pytest.raises(InputError, match="bounds"):
        ant_colony(quadratic, [(1, -1)])
    with pytest.raises(InputError, match="alpha"):
        ant_colony(quadratic, [(-1, 1)], method="acor", alpha=1.0)
    with pytest.raises(InputError, match="method"):
        ant_colony(quadratic, [(-1, 1)], method="bees")
    with pytest.raises(InputError, match="rho"):
        ant_colony(quadratic, [(-1, 1)], method="ant-system", rho=1.5)
