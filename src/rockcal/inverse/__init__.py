"""The inverse toolkit, independent of the DEM engine: orthogonal arrays and range analysis,
Latin hypercube sampling, a Gaussian RBF surrogate, the misfit objective, ant colony
optimisation and the goodness of fit of curves."""

import importlib

from rockcal.inverse.arrays import ARRAY_NAMES, design, is_orthogonal, orthogonal_array, to_values
from rockcal.inverse.bounds import check_bounds
from rockcal.inverse.goodness import (GoodnessOfFit, common_abscissae, correlation_coefficient, curve_fit,
                                      relative_error)
from rockcal.inverse.objective import FORMS, Objective, misfit
from rockcal.inverse.range_analysis import FactorEffect, RangeAnalysis, range_analysis, read_results

# These on first use: their modules load scipy's optimize, interpolate and spatial, which every
# command would otherwise wait for (the command line reads only the arrays, `design`).
_LATER = {"DEFAULT_METHOD": "aco", "METHODS": "aco", "ant_colony": "aco", "latin_hypercube": "sampling",
          "RBFSurrogate": "surrogate", "HeldOutErrors": "surrogate", "loo_errors": "surrogate"}

__all__ = ["ARRAY_NAMES", "DEFAULT_METHOD", "FORMS", "METHODS", "GoodnessOfFit", "FactorEffect", "Objective",
           "RBFSurrogate", "RangeAnalysis", "HeldOutErrors", "ant_colony", "check_bounds",
           "common_abscissae", "correlation_coefficient", "curve_fit", "design", "is_orthogonal",
           "latin_hypercube", "loo_errors", "misfit", "orthogonal_array", "range_analysis",
           "read_results", "relative_error", "to_values"]


def __getattr__(name: str):
    if name not in _LATER:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f"{__name__}.{_LATER[name]}"), name)


def __dir__():
    return __all__
