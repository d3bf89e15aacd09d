"""Gaussian RBF surrogate: interpolates, LOO error tracks the true error, validation report."""

import numpy as np
import pytest

from rockcal.errors import InputError
from rockcal.inverse import RBFSurrogate, latin_hypercube

BOUNDS = [(20, 30), (1, 3), (30, 50)]


def model(x):
    x = np.atleast_2d(x)
    return {"E": 1.5 * x[:, 0] * (1 - 0.09 * x[:, 1]) + 2 * np.sin(x[:, 2] / 8),
            "UCS": 2.9 * x[:, 2] ** 1.1 * np.exp(-0.05 * x[:, 1]) + 0.02 * x[:, 0] ** 2}


@pytest.fixture(scope="module")
def fitted():
    x = latin_hypercube(BOUNDS, 40, seed=3)
    return x, RBFSurrogate(x, model(x), BOUNDS)


def test_interpolates_its_samples(fitted):
    x, s = fitted
    y, p = model(x), s.predict(x)
    for name in y:
        np.testing.assert_allclose(p[name], y[name], rtol=1e-8)


def test_loo_error_tracks_held_out_error(fitted):
    _, s = fitted
    xt = latin_hypercube(BOUNDS, 300, seed=11)
    yt, pt = model(xt), s.predict(xt)
    for name in yt:
        true_rms = np.sqrt(np.mean((pt[name] - yt[name]) ** 2))
        assert 0.1 < s.loo_rms[name] / true_rms < 10, (name, s.loo_rms[name], true_rms)
        assert true_rms < 0.01 * np.mean(np.abs(yt[name]))


def test_validation_report(fitted):
    _, s = fitted
    xt = np.array([[24.0, 1.7, 44.0], [28.0, 2.5, 33.0], [21.0, 1.2, 48.0]])
    report = s.validate(xt, model(xt))
    assert report.trusted and max(report.max_relative_error.values()) < 0.05
    wrong = {k: 1.2 * v for k, v in model(xt).items()}
    assert not s.validate(xt, wrong).trusted


def test_smoothing_stops_interpolating_noise():
    x = latin_hypercube(BOUNDS, 40, seed=5)
    noisy = {"UCS": model(x)["UCS"] + np.random.default_rng(0).normal(0, 2, 40)}
    smooth = RBFSurrogate(x, noisy, BOUNDS, smoothing=1e-1)
    assert np.max(np.abs(smooth.predict(x)["UCS"] - noisy["UCS"])) > 0.1
    single = smooth.predict(x[0])
    assert isinstance(single["UCS"], float)


def test_bad_surrogate_inputs():
    x = latin_hypercube(BOUNDS, 10, seed=1)
    with pytest.raises(InputError, match="bounds"):
        RBFSurrogate(x, model(x), [(30, 20), (1, 3), (30, 50)])
    y = model(x)
    y["E"][2] = np.inf
    with pytest.raises(InputError, match="E: run 3 has an infinite value"):
        RBFSurrogate(x, y, BOUNDS)
    y["E"][:6] = np.nan
    with pytest.raises(InputError, match="E: measured at 4 runs, too few"):
        RBFSurrogate(x, y, BOUNDS)


def test_a_response_not_measured_at_a_run_is_fitted_without_that_run():
    """NaN marks a response a run did not measure: that response's model is the one fitted
    on the other runs, to the bit, and the other responses keep every run."""
    x = latin_hypercube(BOUNDS, 12, seed=2)
    y = model(x)
    gapped = {"E": y["E"].copy(), "UCS": y["UCS"]}
    gapped["E"][[3, 7]] = np.nan
    kept = np.ones(12, bool)
    kept[[3, 7]] = False
    probe = latin_hypercube(BOUNDS, 20, seed=4)
    with_gaps = RBFSurrogate(x, gapped, BOUNDS).predict(probe)
    assert np.array_equal(with_gaps["E"], RBFSurrogate(x[kept], {"E": y["E"][kept]}, BOUNDS).predict(probe)["E"])
    assert np.array_equal(with_gaps["UCS"], RBFSurrogate(x, {"UCS": y["UCS"]}, BOUNDS).predict(probe)["UCS"])
