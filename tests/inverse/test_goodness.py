"""RE and CC of curves on common abscissae."""

import numpy as np
import pytest

from rockcal.errors import InputError
from rockcal.inverse import curve_fit

STRAIN = np.linspace(0, 0.005, 60)
STRESS = 40e3 * STRAIN - 2e6 * STRAIN ** 2


def test_identical_curves():
    fit = curve_fit(STRAIN, STRESS, STRAIN, STRESS)
    assert fit.RE == 0 and fit.CC == pytest.approx(1, abs=1e-12)


def test_scaled_curve_on_other_abscissae():
    x_c = np.linspace(-0.001, 0.006, 500)  # wider and denser; linear curves interpolate exactly
    fit = curve_fit(STRAIN, 1.1 * STRESS, STRAIN, STRESS)
    assert fit.RE == pytest.approx(0.1, rel=1e-12) and fit.CC == pytest.approx(1, abs=1e-12)
    linear = curve_fit(x_c, 1.1 * 30 * x_c, STRAIN, 30 * STRAIN)
    assert linear.RE == pytest.approx(0.1, rel=1e-9) and linear.x_range == (0.0, 0.005)


def test_only_overlap_is_compared():
    fit = curve_fit(STRAIN[:30], STRESS[:30], STRAIN, STRESS)
    assert fit.x_range == (0.0, STRAIN[29]) and fit.points == 30 and fit.RE == 0


def test_abscissae_must_increase():
    with pytest.raises(InputError, match="increase"):
        curve_fit(STRAIN[::-1], STRESS, STRAIN, STRESS)
    with pytest.raises(InputError, match="overlap"):
        curve_fit(STRAIN + 1, STRESS, STRAIN, STRESS)
