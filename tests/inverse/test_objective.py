"""The misfit: relative by default, weights, normalised and curve terms."""

import numpy as np
import pytest

from rockcal.errors import InputError
from rockcal.inverse import Objective, misfit

MEASURED = {"E": 41.5, "nu": 0.23, "UCS": 138.8}


def test_relative_by_default():
    computed = {"E": 41.5 * 1.05, "nu": 0.23, "UCS": 138.8 * 0.9}
    assert misfit(computed, MEASURED) == pytest.approx(0.05 ** 2 + 0.1 ** 2)
    assert misfit(computed, MEASURED, weights={"UCS": 0}) == pytest.approx(0.05 ** 2)


def test_normalised_and_vectorised():
    computed = {"E": np.array([41.5, 43.5]), "nu": np.array([0.23, 0.23]), "UCS": np.array([138.8, 138.8])}
    f = misfit(computed, MEASURED, form="normalised", scales={"E": 4.0, "nu": 0.1, "UCS": 20})
    np.testing.assert_allclose(f, [0, 0.25])
    with pytest.raises(InputError, match="scales.E"):
        misfit(computed, MEASURED, form="normalised")


def test_curve_term_and_objective_wrapper():
    x = np.linspace(0, 1, 20)
    model = lambda p: {"E": p[0], "curve": (x, p[1] * x)}
    obj = Objective(model, {"E": 2.0}, curves={"curve": (x, x)}, weights={"curve": 2.0})
    assert obj([2.0, 1.2]) == pytest.approx(2 * 0.2 ** 2)
    assert "RE^2" in obj.describe()


def test_bad_objective_inputs():
    with pytest.raises(InputError, match="weights.G"):
        Objective(lambda p: {}, MEASURED, weights={"G": 1})
    with pytest.raises(InputError, match="form"):
        misfit(MEASURED, MEASURED, form="plain")
