"""The multi-fidelity surrogate: ρ ŷ_l + δ meets the high-fidelity runs exactly, and a
high-fidelity response that is a multiple of the low one is recovered everywhere from a few runs
(from one, ρ alone)."""

import numpy as np
import pytest

from rockcal.inverse import RBFSurrogate, latin_hypercube
from rockcal.inverse.multifidelity import CorrectedSurrogate

BOX = [[0.0, 1.0], [0.0, 2.0]]


def _low(x):
    x = np.atleast_2d(x)
    return {"y": 1.0 + x[:, 0] ** 2 + np.sin(x[:, 1])}


def _corrected(high, n_high=4):
    x_low = latin_hypercube(BOX, 40, seed=1)
    low = RBFSurrogate(x_low, _low(x_low), BOX)
    x_high = latin_hypercube(BOX, n_high, seed=2) if n_high > 1 else np.array([[0.3, 1.1]])
    return CorrectedSurrogate(low, x_high, high(x_high), BOX), x_high


def test_it_meets_the_high_fidelity_runs():
    surrogate, x_high = _corrected(lambda x: {"y": 0.7 * _low(x)["y"] + 0.2 * np.atleast_2d(x)[:, 0]})
    expected = 0.7 * _low(x_high)["y"] + 0.2 * x_high[:, 0]
    assert surrogate.predict(x_high)["y"] == pytest.approx(expected, rel=1e-9)


def test_a_multiple_of_the_low_fidelity_response_is_recovered_everywhere():
    surrogate, _ = _corrected(lambda x: {"y": 1.25 * _low(x)["y"]})
    assert surrogate.rho["y"] == pytest.approx(1.25, rel=1e-3)
    probe = latin_hypercube(BOX, 200, seed=3)
    assert surrogate.predict(probe)["y"] == pytest.approx(1.25 * _low(probe)["y"], rel=2e-3)


def test_one_high_fidelity_run_scales_the_low_fidelity_surrogate():
    surrogate, x_high = _corrected(lambda x: {"y": 0.9 * _low(x)["y"]}, n_high=1)
    assert surrogate.predict(x_high[0])["y"] == pytest.approx(0.9 * _low(x_high)["y"][0], rel=1e-9)
    probe = latin_hypercube(BOX, 50, seed=3)
    assert surrogate.predict(probe)["y"] == pytest.approx(0.9 * surrogate.low.predict(probe)["y"], rel=1e-4)


def test_a_response_not_measured_at_a_run_is_corrected_by_the_other_runs():
    """NaN marks a high-fidelity response a run did not measure: ρ and δ of that response are
    those of the other runs, to the bit."""
    x_low = latin_hypercube(BOX, 40, seed=1)
    low = RBFSurrogate(x_low, {"y": _low(x_low)["y"], "z": _low(x_low)["y"]}, BOX)
    x_high = latin_hypercube(BOX, 5, seed=2)
    y = 0.8 * _low(x_high)["y"] + 0.1 * x_high[:, 1]
    gapped = y.copy()
    gapped[2] = np.nan
    keep = [0, 1, 3, 4]
    probe = latin_hypercube(BOX, 30, seed=3)
    both = CorrectedSurrogate(low, x_high, {"y": gapped, "z": y}, BOX)
    assert np.array_equal(both.predict(probe)["y"],
                          CorrectedSurrogate(low, x_high[keep], {"y": y[keep]}, BOX).predict(probe)["y"])
    assert np.array_equal(both.predict(probe)["z"], CorrectedSurrogate(low, x_high, {"z": y}, BOX).predict(probe)["z"])
