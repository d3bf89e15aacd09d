"""Intervals of identified parameters, a twin experiment on a known forward model: the
surrogate and the ant colony the campaign uses, targets made at known parameters."""

import numpy as np
import pytest

from rockcal.inverse import Objective, RBFSurrogate, ant_colony, latin_hypercube
from rockcal.inverse.uncertainty import draw_targets, interval, parameter_intervals

BOX = np.array([[20.0, 30.0], [1.0, 3.0], [30.0, 50.0]])
NAMES = ["E_c", "kn_ks", "sigma_c"]
TRUE = np.array([24.0, 1.8, 38.0])


def model(x):
    """A smooth stand-in for the DEM: each response leans on one parameter, as E, nu, UCS do."""
    x = np.asarray(x, float)
    return {"E_GPa": 1.9 * x[..., 0] - 1.5 * x[..., 1], "nu": 0.05 + 0.09 * x[..., 1] - 0.001 * x[..., 0],
            "ucs_MPa": 3.7 * x[..., 2] + 0.3 * x[..., 0]}


@pytest.fixture(scope="module")
def surrogate():
    x = latin_hypercube(BOX, 40, seed=1)
    return RBFSurrogate(x, model(x), BOX)


def solver(surrogate, responses=("E_GPa", "nu", "ucs_MPa")):
    def solve(targets):
        objective = Objective(lambda x: {r: surrogate.predict(x)[r] for r in responses},
                              {r: targets[r] for r in responses})
        return ant_colony(objective, BOX, method="acor", ants=30, iterations=80, seed=1,
                          vectorized=True).x
    return solve


def intervals_for(surrogate, relative_spread, responses=("E_GPa", "nu", "ucs_MPa"), scatter=None):
    targets = {r: float(v) for r, v in model(TRUE).items() if r in responses}
    spread = {r: relative_spread * v for r, v in targets.items()}
    return parameter_intervals(solver(surrogate, responses), targets, spread, scatter or {}, BOX,
                               NAMES, draws=60, seed=3)["intervals"]


@pytest.mark.slow
def test_intervals_contain_the_truth_and_shrink_with_the_spread(surrogate):
    wide, narrow = intervals_for(surrogate, 0.03), intervals_for(surrogate, 0.01)
    for k, name in enumerate(NAMES):
        for result in (wide, narrow):
            assert result[name]["p5"] <= TRUE[k] <= result[name]["p95"], name
            assert result[name]["pinned"], name
        width = lambda r: r[name]["p95"] - r[name]["p5"]
        assert width(narrow) == pytest.approx(width(wide) / 3, rel=0.35), name


@pytest.mark.slow
def test_model_scatter_widens_the_intervals(surrogate):
    lab_only = intervals_for(surrogate, 0.01)
    with_scatter = intervals_for(surrogate, 0.01, scatter={"E_GPa": 0.03, "nu": 0.0, "ucs_MPa": 0.03})
    for name in ("E_c", "sigma_c"):
        assert (with_scatter[name]["p95"] - with_scatter[name]["p5"]
                > 2 * (lab_only[name]["p95"] - lab_only[name]["p5"]))


def test_a_parameter_no_response_depends_on_is_not_pinned(surrogate):
    """Without nu, kn/ks is free (E leans on it only slightly): wide, or at the bounds."""
    result = intervals_for(surrogate, 0.01, responses=("ucs_MPa",))
    assert result["sigma_c"]["pinned"]
    assert not result["kn_ks"]["pinned"]


def test_lab_draws_follow_the_given_spread():
    drawn = draw_targets({"E_GPa": 41.5, "nu": 0.23, "ucs_MPa": 138.8},
                         {"E_GPa": [39.95, 44.29], "nu": 0.01}, {}, 4000, seed=1)
    assert drawn["E_GPa"].min() >= 39.95 and drawn["E_GPa"].max() <= 44.29
    assert drawn["E_GPa"].mean() == pytest.approx((39.95 + 44.29) / 2, abs=0.1)
    assert drawn["nu"].std() == pytest.approx(0.01, rel=0.05)
    assert np.all(drawn["ucs_MPa"] == 138.8)


def test_interval_flags_draws_at_a_bound():
    at_edge = interval(np.r_[np.full(20, 1.0), np.linspace(1.5, 2.0, 80)], 1.0, 3.0)
    assert at_edge.at_bound == pytest.approx(0.2) and not at_edge.pinned
    inside = interval(np.linspace(1.5, 2.0, 100), 1.0, 3.0)
    assert inside.pinned and inside.p5 < inside.p50 < inside.p95
