"""The strength envelope: Mohr-Coulomb and Hoek-Brown fits recover the parameters of synthetic
peaks exactly, and say how well they fit."""

import math

import numpy as np
import pytest

from rockcal.errors import InputError
from rockcal.labtests.envelope import envelope_responses, fit_hoek_brown, fit_mohr_coulomb
from rockcal.plots import plot_envelope

SIGMA3 = np.array([0.0, 5.0, 10.0, 20.0])


def mohr_coulomb_peaks(phi_deg, c_MPa, sigma3=SIGMA3):
    """sigma1 = 2 c cos(phi) / (1 - sin(phi)) + (1 + sin(phi)) / (1 - sin(phi)) sigma3."""
    s = math.sin(math.radians(phi_deg))
    return 2 * c_MPa * math.cos(math.radians(phi_deg)) / (1 - s) + (1 + s) / (1 - s) * sigma3


def hoek_brown_peaks(sigma_ci, m_i, sigma3=SIGMA3):
    return sigma3 + sigma_ci * np.sqrt(m_i * sigma3 / sigma_ci + 1)


@pytest.mark.parametrize("phi_deg, c_MPa", [(35.0, 25.0), (52.0, 30.0), (10.0, 4.0)])
def test_mohr_coulomb_recovers_phi_and_c(phi_deg, c_MPa):
    fit = fit_mohr_coulomb(SIGMA3, mohr_coulomb_peaks(phi_deg, c_MPa))
    assert fit.phi_deg == pytest.approx(phi_deg, rel=1e-12)
    assert fit.c_MPa == pytest.approx(c_MPa, rel=1e-12)
    assert fit.r2 == pytest.approx(1.0, abs=1e-12) and fit.rms_MPa < 1e-9


@pytest.mark.parametrize("sigma_ci, m_i", [(200.0, 32.0), (150.0, 10.0), (80.0, 5.0)])
def test_hoek_brown_recovers_sigma_ci_and_m_i(sigma_ci, m_i):
    """Granite (m_i 32 in Hoek's table) and softer rocks: Hoek's regression is exact on exact
    peaks."""
    fit = fit_hoek_brown(SIGMA3, hoek_brown_peaks(sigma_ci, m_i))
    assert fit.sigma_ci_MPa == pytest.approx(sigma_ci, rel=1e-12)
    assert fit.m_i == pytest.approx(m_i, rel=1e-12)
    assert fit.r2 == pytest.approx(1.0, abs=1e-12) and fit.rms_MPa < 1e-9


def test_the_fit_quality_is_that_of_the_misfit():
    """A line through curved (Hoek-Brown) peaks misfits: R^2 below 1, rms the misfit's; the
    least-squares line's residuals sum to zero. Noise on Hoek-Brown peaks lowers r^2."""
    s1 = hoek_brown_peaks(200.0, 32.0)
    mc = fit_mohr_coulomb(SIGMA3, s1)
    residual = s1 - mc.sigma1(SIGMA3)
    assert abs(residual.sum()) < 1e-9
    assert mc.rms_MPa == pytest.approx(np.sqrt(np.mean(residual**2)))
    assert 0.9 < mc.r2 < 1.0 and mc.rms_MPa > 1.0
    noisy = fit_hoek_brown(SIGMA3, s1 + np.array([2.0, -3.0, 1.0, 2.0]))
    assert 0.9 < noisy.r2 < 1.0 and noisy.rms_MPa > 0.5
    assert noisy.m_i == pytest.approx(32.0, rel=0.2)


def test_envelope_responses_name_both_fits():
    r = envelope_responses(SIGMA3, hoek_brown_peaks(200.0, 32.0))
    assert set(r) == {"phi_deg", "c_MPa", "m_i", "sigma_ci_MPa", "mc_sigma_c_MPa", "mc_r2",
                      "mc_rms_MPa", "hb_r2", "hb_rms_MPa"}
    assert r["m_i"] == pytest.approx(32.0) and 40 < r["phi_deg"] < 70


@pytest.mark.parametrize("sigma3, sigma1, field", [
    ([10.0], [200.0], "confinement_mpa"),
    ([10.0, 10.0], [200.0, 210.0], "confinement_mpa"),
    ([0.0, 10.0], [200.0, 205.0], "sigma1_MPa"),  # k < 1: no positive friction angle
    ([0.0, 10.0], [200.0, 5.0], "sigma1_MPa"),  # a peak below its confinement
])
def test_peaks_no_envelope_can_be_fitted_to_name_the_field(sigma3, sigma1, field):
    with pytest.raises(InputError) as error:
        fit_mohr_coulomb(sigma3, sigma1)
    assert error.value.field == field


def test_the_figure_is_written(tmp_path):
    path = tmp_path / "envelope.png"
    plot_envelope(SIGMA3, hoek_brown_peaks(200.0, 32.0), path)
    assert path.stat().st_size > 10_000


def test_peaks_without_an_intact_hoek_brown_envelope_still_draw_their_mohr_coulomb_line(tmp_path):
    # (σ1 - σ3)² growing faster than linearly in σ3: Hoek's regression has σ_ci² < 0
    peaks = np.array([98.0, 162.0, 261.0, 460.0])
    with pytest.raises(InputError):
        fit_hoek_brown(SIGMA3, peaks)
    path = tmp_path / "envelope.png"
    plot_envelope(SIGMA3, peaks, path)
    assert path.stat().st_size > 10_000
