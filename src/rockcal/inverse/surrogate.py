"""Gaussian radial basis function surrogate of a forward model, one model per response.

Inputs are scaled to [0, 1] over the search bounds, so one shape parameter suits every
parameter whatever its unit. The kernel is scipy's φ(r) = exp(-(ε r)²) (γ = ε² in the
source's notation), plus a polynomial tail of degree `degree` (default 1, linear; -1 gives
the source's pure ŷ = Σ w_i φ(‖x - x_i‖)). ε is chosen per response by leave-one-out
cross-validation over a log grid, using Rippa's formula e_i = c_i / (A⁻¹)_ii on the full
(kernel + polynomial) system, so one factorisation per ε gives all n LOO errors; shapes
that make the system too ill-conditioned to solve reliably are skipped, and of shapes whose
errors tie to round-off the smallest is taken (the choice must not follow the processor).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import RBFInterpolator
from scipy.spatial.distance import cdist

from rockcal.errors import InputError
from rockcal.inverse.bounds import check_bounds

EPSILON_GRID = np.logspace(-1, 1.5, 36)
MAX_CONDITION = 1e12
SCORE_TIE = 1e-9  # relative: shapes whose leave-one-out errors differ less are equally good


def _monomials(u: np.ndarray, degree: int) -> np.ndarray:
    """Polynomial tail columns (1; x_j) for degree 0 or 1, none for -1."""
    n = len(u)
    if degree < 0:
        return np.empty((n, 0))
    if degree == 0:
        return np.ones((n, 1))
    if degree == 1:
        return np.column_stack([np.ones(n), u])
    raise InputError("degree", f"must be -1, 0 or 1, got {degree}")


def loo_errors(u: np.ndarray, y: np.ndarray, epsilon: float, *, smoothing: float = 0.0,
               degree: int = 1) -> np.ndarray:
    """Leave-one-out residuals y_i - ŷ_{-i}(u_i) of the Gaussian RBF fit (Rippa's formula).

    Returns NaNs when the system is too ill-conditioned (condition number > MAX_CONDITION).
    """
    n = len(u)
    K = np.exp(-(epsilon * cdist(u, u)) ** 2) + smoothing * np.eye(n)
    P = _monomials(u, degree)
    m = P.shape[1]
    A = np.block([[K, P], [P.T, np.zeros((m, m))]])
    if np.linalg.cond(A) > MAX_CONDITION:
        return np.full(n, np.nan)
    A_inv = np.linalg.inv(A)
    c = A_inv[:, :n] @ y
    return c[:n] / np.diag(A_inv)[:n]


@dataclass(frozen=True)
class HeldOutErrors:
    """Relative errors |ŷ - y| / |y| of the surrogate on held-out runs, per response."""

    relative_error: dict[str, np.ndarray]
    tolerance: float

    @property
    def max_relative_error(self) -> dict[str, float]:
        return {r: float(np.max(e)) for r, e in self.relative_error.items()}

    @property
    def trusted(self) -> bool:
        """True when every response of every held-out run is within the tolerance."""
        return all(e <= self.tolerance for e in self.max_relative_error.values())


def minimum_runs(dimensions: int, degree: int = 1) -> int:
    """The fewest runs a surrogate of `dimensions` parameters with a polynomial tail of
    `degree` is fitted on."""
    return {-1: 1, 0: 2, 1: dimensions + 2}.get(degree, 2)


class RBFSurrogate:
    """Gaussian RBF per response, fitted on runs x (n, d) in physical units.

    responses: {name: values per run}; a NaN is a response not measured at that run, which its
    response's model is fitted without. epsilon: None (LOO over `epsilons`), a number, or
    {response: number}. smoothing: 0 interpolates the runs exactly; > 0 smooths noisy
    responses (same value for every response, or a dict).
    """

    def __init__(self, x, responses: dict[str, np.ndarray], bounds, *, epsilon=None,
                 smoothing=0.0, degree: int = 1, epsilons=EPSILON_GRID):
        self.lower, self.upper = check_bounds(bounds)
        x = np.asarray(x, dtype=float)
        if x.ndim != 2 or x.shape[1] != len(self.lower):
            raise InputError("x", f"expected runs as rows of {len(self.lower)} parameters, got shape {x.shape}")
        if not responses:
            raise InputError("responses", "at least one response is needed")
        n = len(x)
        minimum = minimum_runs(x.shape[1], degree)
        if n < minimum:
            raise InputError("x", f"{n} runs are too few for this surrogate (need at least {minimum})")
        if not np.all(np.isfinite(x)):
            raise InputError("x", "runs contain non-finite parameter values")
        self.x = x
        self.names = tuple(responses)
        self.degree = degree
        self.y, measured_at = {}, {}
        for name, values in responses.items():
            values = np.asarray(values, dtype=float)
            if values.shape != (n,):
                raise InputError(name, f"expected {n} values (one per run), got shape {values.shape}")
            if np.any(np.isinf(values)):
                raise InputError(name, f"run {np.flatnonzero(np.isinf(values))[0] + 1} has an infinite value")
            measured = ~np.isnan(values)
            if measured.sum() < minimum:
                raise InputError(name, f"measured at {measured.sum()} runs, too few for this surrogate (need at "
                                       f"least {minimum})")
            self.y[name], measured_at[name] = values[measured], measured
        self.epsilon, self.smoothing, self.loo_rms, self._models = {}, {}, {}, {}
        for name in self.names:
            u = self.scale(x[measured_at[name]])
            s = float(smoothing[name] if isinstance(smoothing, dict) else smoothing)
            if s < 0:
                raise InputError("smoothing", f"must be >= 0, got {s}")
            eps = epsilon[name] if isinstance(epsilon, dict) else epsilon
            if eps is None:
                eps, rms = self._choose_epsilon(u, self.y[name], s, np.asarray(epsilons, dtype=float))
            else:
                eps = float(eps)
                if not eps > 0:
                    raise InputError("epsilon", f"must be > 0, got {eps}")
                rms = float(np.sqrt(np.mean(loo_errors(u, self.y[name], eps, smoothing=s, degree=degree) ** 2)))
            self.epsilon[name], self.smoothing[name], self.loo_rms[name] = eps, s, rms
            self._models[name] = RBFInterpolator(u, self.y[name], kernel="gaussian", epsilon=eps,
                                                 smoothing=s, degree=degree)

    def _choose_epsilon(self, u, y, smoothing, grid) -> tuple[float, float]:
        scores = [np.sqrt(np.mean(loo_errors(u, y, e, smoothing=smoothing, degree=self.degree) ** 2))
                  for e in grid]
        scores = np.array(scores)
        if np.all(np.isnan(scores)):
            raise InputError("x", "every shape parameter gives an ill-conditioned RBF system "
                                  "(duplicate runs?)")
        # the first shape within round-off of the least error: where the errors tie (a fit the
        # polynomial tail decides alone), round-off must not pick the shape
        best = int(np.flatnonzero(scores <= np.nanmin(scores) * (1 + SCORE_TIE))[0])
        return float(grid[best]), float(scores[best])

    def scale(self, x) -> np.ndarray:
        """Physical parameters -> [0, 1] over the bounds."""
        return (np.asarray(x, dtype=float) - self.lower) / (self.upper - self.lower)

    def predict(self, x) -> dict[str, np.ndarray]:
        """{response: predictions} at x, (d,) for one point (scalars out) or (m, d)."""
        x = np.asarray(x, dtype=float)
        single = x.ndim == 1
        u = self.scale(np.atleast_2d(x))
        if u.shape[1] != len(self.lower):
            raise InputError("x", f"expected {len(self.lower)} parameters, got {u.shape[1]}")
        out = {name: model(u) for name, model in self._models.items()}
        return {name: float(v[0]) for name, v in out.items()} if single else out

    def validate(self, x, responses: dict[str, np.ndarray], tolerance: float = 0.05) -> HeldOutErrors:
        """Relative errors on held-out runs; trusted if all are within `tolerance` (5 %)."""
        pred = self.predict(np.atleast_2d(x))
        errors = {}
        for name in self.names:
            if name not in responses:
                raise InputError("responses", f"held-out runs lack response {name!r}")
            y = np.asarray(responses[name], dtype=float)
            with np.errstate(divide="ignore", invalid="ignore"):
                errors[name] = np.abs(pred[name] - y) / np.abs(y)
        return HeldOutErrors(errors, tolerance)
