"""The closed-form least-squares line: exact on points of a line, and its residuals are
orthogonal to 1 and x (the normal equations), as numpy's LAPACK fit's are."""

import numpy as np
import pytest

from rockcal.labtests.line_fit import fit_line


def test_points_on_a_line_give_that_line():
    x = np.array([0.0, 5.0, 10.0, 20.0])
    assert fit_line(x, 3.5 * x + 12.0) == pytest.approx((3.5, 12.0), rel=1e-14)


def test_residuals_satisfy_the_normal_equations():
    rng = np.random.default_rng(3)
    x = rng.uniform(0, 100, 50)
    y = 0.02 * x + 1.0 + rng.normal(0, 0.3, 50)
    slope, intercept = fit_line(x, y)
    residual = y - (slope * x + intercept)
    assert abs(residual.sum()) < 1e-12 * np.abs(y).sum()
    assert abs((residual * x).sum()) < 1e-12 * np.abs(y * x).sum()
    assert (slope, intercept) == pytest.approx(tuple(np.polyfit(x, y, 1)), rel=1e-12)
