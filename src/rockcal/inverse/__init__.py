"""The inverse toolkit, independent of the DEM engine: orthogonal arrays and range analysis,
Latin hypercube sampling, a Gaussian RBF surrogate, the misfit objective, ant colony
optimisation and the goodness of fit of curves."""

from rockcal.inverse.aco import DEFAULT_METHOD, METHODS, ant_colony
from rockcal.inverse.arrays import ARRAY_NAMES, design, is_orthogonal, orthogonal_array, to_values
from rockcal.inverse.bounds import check_bounds
from rockcal.inverse.goodness import (GoodnessOfFit, common_abscissae, correlation_coefficient, curve_fit,
                                      relative_error)
from rockcal.inverse.objective import FORMS, Objective, misfit
from rockcal.inverse.range_analysis import FactorEffect, RangeAnalysis, range_analysis, read_results
from rockcal.inverse.sampling import latin_hypercube
from rockcal.inverse.surrogate import RBFSurrogate, HeldOutErrors, loo_errors

__all__ = ["ARRAY_NAMES", "DEFAULT_METHOD", "FORMS", "METHODS", "GoodnessOfFit", "FactorEffect", "Objective",
           "RBFSurrogate", "RangeAnalysis", "HeldOutErrors", "ant_colony", "check_bounds",
           "common_abscissae", "correlation_coefficient", "curve_fit", "design", "is_orthogonal",
           "latin_hypercube", "loo_errors", "misfit", "orthogonal_array", "range_analysis",
           "read_results", "relative_error", "to_values"]
