"""Ant colony optimisation over box bounds, scipy-style: `ant_colony(fun, bounds) -> result`.

Two methods. Hand-written because no well-kept Python library offers both the source's
discretised Ant System and ACO_R behind one interface with seeded, vectorised runs.

"ant-system" — the source's form (50 ants, 200 iterations, α = 1, β = 5, ρ = 0.5). Each
parameter range is split into `nodes` equally spaced nodes; an ant builds a solution by
picking one node per parameter with probability ∝ τ^α η^β, where
- τ (pheromone) starts at 1 on every node; each iteration it evaporates, τ ← (1 − ρ) τ, and
  the `elite` best ants of the iteration plus the best-so-far ant deposit their quality
  Q = 1 / (1 + (f − f*) / s) on the nodes they used (the best-so-far deposits 1);
- η (heuristic desirability) of a node is the same quality computed from the best
  objective f_node seen through that node: η = 1 / (1 + (f_node − f*) / s), where f* is the
  best objective so far and s the median gap f_node − f* over the visited nodes, so η is in
  (0, 1], equals 1 on the best node and 1/2 at the median, whatever the unit or offset of f;
  nodes no ant has visited yet get η = 1 (optimism drives exploration).
  With β = 5 an ant rarely (1/32) picks a median node over the best one.
Local refinement (`shrink` < 1): when the best has not improved for `patience` iterations
the grid of every parameter shrinks by `shrink` around the best-so-far (which stays a node)
and τ, η restart; this turns the discrete search into a continuous one. `shrink=1` keeps the
source's fixed grid.

"acor" — ACO_R of Socha & Dorigo (2008): an archive of the `archive` best solutions ranked
by objective, with weights ω_l ∝ exp(−(l − 1)² / (2 q² k²)); each ant picks a guide l with
probability ∝ ω_l and samples every parameter from a Gaussian centred on the guide with
σ_i = ξ Σ_e |s_e,i − s_l,i| / (k − 1); samples leaving the bounds are reflected back. The
archive keeps the k best of itself and the new ants. Defaults k = 30, q = 0.05, ξ = 0.85 and
10 ants per iteration were chosen on benchmarks/aco_comparison.py.
"""

from __future__ import annotations

from typing import Callable

import numpy as np
from scipy.optimize import OptimizeResult

from rockcal.errors import InputError
from rockcal.inverse.bounds import check_bounds

METHODS = ("ant-system", "acor")
DEFAULT_METHOD = "acor"

_AS_DEFAULTS = {"ants": 50, "alpha": 1.0, "beta": 5.0, "rho": 0.5}
_ACOR_DEFAULTS = {"ants": 10, "archive": 30, "q": 0.05, "xi": 0.85}


class _Evaluator:
    """Counts evaluations; maps NaN to +inf so a failed run is simply the worst."""

    def __init__(self, fun, args, vectorized):
        self.fun, self.args, self.vectorized, self.nfev = fun, args, vectorized, 0

    def __call__(self, X: np.ndarray) -> np.ndarray:
        if self.vectorized:
            f = np.asarray(self.fun(X, *self.args), dtype=float).reshape(len(X))
        else:
            f = np.array([float(self.fun(x, *self.args)) for x in X])
        self.nfev += len(X)
        return np.where(np.isnan(f), np.inf, f)


def _positive(name, value, integer=False, upper=None):
    ok = np.isfinite(value) and value > 0 and (upper is None or value <= upper)
    if integer:
        ok = ok and int(value) == value
    if not ok:
        bound = f" and <= {upper}" if upper is not None else ""
        raise InputError(name, f"must be {'an integer' if integer else 'a number'} > 0{bound}, got {value}")
    return int(value) if integer else float(value)


def _quality(f, f_best, scale):
    return 1.0 / (1.0 + (f - f_best) / scale)


def _gap_scale(f_nodes, f_best):
    gaps = f_nodes[np.isfinite(f_nodes)] - f_best
    gaps = gaps[gaps > 0]
    return float(np.median(gaps)) if gaps.size else 1.0


def _ant_system(evaluate, lower, upper, rng, *, ants, iterations, alpha, beta, rho, nodes,
                elite, patience, shrink, step):
    d = len(lower)
    lo, hi = lower.copy(), upper.copy()
    grid = np.linspace(lo, hi, nodes).T                      # (d, nodes)
    tau = np.ones((d, nodes))
    f_node = np.full((d, nodes), np.inf)
    x_best, f_best, stall, best_pick = None, np.inf, 0, None
    rows = np.arange(d)[:, None]
    for it in range(iterations):
        if np.isfinite(f_best):
            s = _gap_scale(f_node, f_best)
            eta = np.where(np.isfinite(f_node), _quality(f_node, f_best, s), 1.0)
        else:
            s, eta = 1.0, np.ones_like(tau)
        weight = tau ** alpha * eta ** beta
        cum = np.cumsum(weight, axis=1)
        pick = np.empty((ants, d), dtype=int)
        for j in range(d):
            pick[:, j] = np.searchsorted(cum[j], rng.random(ants) * cum[j, -1], side="right")
        pick = np.minimum(pick, nodes - 1)
        X = grid[np.arange(d), pick]                         # (ants, d)
        f = evaluate(X)
        for j in range(d):
            np.minimum.at(f_node[j], pick[:, j], f)
        i = int(np.argmin(f))
        if f[i] < f_best or x_best is None:
            improved = not np.isfinite(f_best) or f_best - f[i] > 1e-12 * max(1.0, abs(f_best))
            x_best, f_best, best_pick = X[i].copy(), float(f[i]), pick[i].copy()
            stall = 0 if improved else stall + 1
        else:
            stall += 1
        # evaporation, then deposits of the elite ants and of the best-so-far
        tau *= 1.0 - rho
        s = _gap_scale(f_node, f_best)
        order = np.argsort(f)[:elite]
        finite = order[np.isfinite(f[order])]
        np.add.at(tau, (np.broadcast_to(rows, (d, len(finite))), pick[finite].T),
                  _quality(f[finite], f_best, s))
        if best_pick is not None:
            tau[np.arange(d), best_pick] += 1.0
        if shrink < 1 and stall >= patience:
            half = 0.5 * shrink * (hi - lo)
            lo = np.maximum(lower, x_best - half)
            hi = np.minimum(upper, x_best + half)
            grid = np.linspace(lo, hi, nodes).T
            best_pick = np.argmin(np.abs(grid - x_best[:, None]), axis=1)
            grid[np.arange(d), best_pick] = x_best
            tau = np.ones((d, nodes))
            f_node = np.full((d, nodes), np.inf)
            f_node[np.arange(d), best_pick] = f_best
            stall = 0
        if step(it + 1, x_best, f_best):
            break


def _acor(evaluate, lower, upper, rng, *, ants, iterations, archive, q, xi, step):
    d = len(lower)
    k = archive
    S = lower + rng.random((k, d)) * (upper - lower)
    f = evaluate(S)
    order = np.argsort(f, kind="stable")
    S, f = S[order], f[order]
    rank = np.arange(k)
    w = np.exp(-rank ** 2 / (2.0 * (q * k) ** 2))
    p = w / w.sum()
    for it in range(iterations):
        guide = rng.choice(k, size=ants, p=p)
        sigma = xi * np.abs(S[None, :, :] - S[guide][:, None, :]).sum(axis=1) / (k - 1)
        X = S[guide] + sigma * rng.standard_normal((ants, d))
        # reflect into the bounds (twice covers overshoots up to one box width), then clip
        for _ in range(2):
            X = np.where(X < lower, 2 * lower - X, X)
            X = np.where(X > upper, 2 * upper - X, X)
        X = np.clip(X, lower, upper)
        fx = evaluate(X)
        S, f = np.vstack([S, X]), np.concatenate([f, fx])
        order = np.argsort(f, kind="stable")[:k]
        S, f = S[order], f[order]
        if step(it + 1, S[0].copy(), float(f[0])):
            break


def ant_colony(fun: Callable, bounds, *, method: str = DEFAULT_METHOD, ants: int | None = None,
               iterations: int = 200, alpha: float | None = None, beta: float | None = None,
               rho: float | None = None, nodes: int = 50, elite: int | None = None,
               patience: int = 3, shrink: float = 0.5, archive: int | None = None,
               q: float | None = None, xi: float | None = None, seed=None,
               callback: Callable | None = None, vectorized: bool = False,
               target: float | None = None, args: tuple = ()) -> OptimizeResult:
    """Minimise fun over box bounds by ant colony optimisation (see the module doc).

    fun(x, *args) -> float with x of shape (d,); with vectorized=True, fun(X, *args) takes
    X of shape (n, d) and returns n values. Ant System options: ants (50), alpha (1), beta (5),
    rho (0.5), nodes (50 per parameter), elite (ants // 10), patience (3), shrink (0.5).
    ACO_R options: ants (10 per iteration), archive (30), q (0.05), xi (0.85); alpha, beta and
    rho do not exist in ACO_R and are refused. callback(intermediate_result) is called after
    each iteration; returning True (or raising StopIteration) stops the search, as does the
    best objective reaching `target`. The same seed gives the same result.

    Returns an OptimizeResult with x, fun, nfev, nit, success, message, method, and per
    iteration history_fun (best objective), history_x (best parameters) and history_nfev.
    """
    lower, upper = check_bounds(bounds)
    if method not in METHODS:
        raise InputError("method", f"must be one of {', '.join(METHODS)}, got {method!r}")
    iterations = _positive("iterations", iterations, integer=True)
    rng = np.random.default_rng(seed)
    evaluate = _Evaluator(fun, tuple(args), vectorized)
    hist_f, hist_x, hist_n = [], [], []
    state = {"message": f"maximum number of iterations ({iterations}) reached"}

    def step(nit, x_best, f_best) -> bool:
        hist_f.append(f_best)
        hist_x.append(np.array(x_best, dtype=float))
        hist_n.append(evaluate.nfev)
        if target is not None and f_best <= target:
            state["message"] = f"target {target:g} reached"
            return True
        if callback is not None:
            try:
                stop = callback(OptimizeResult(x=x_best, fun=f_best, nit=nit, nfev=evaluate.nfev))
            except StopIteration:
                stop = True
            if stop:
                state["message"] = "stopped by the callback"
                return True
        return False

    if method == "ant-system":
        for name, value in (("archive", archive), ("q", q), ("xi", xi)):
            if value is not None:
                raise InputError(name, "is an ACO_R option; method 'ant-system' has no archive, q or xi")
        ants = _positive("ants", _AS_DEFAULTS["ants"] if ants is None else ants, integer=True)
        alpha = float(_AS_DEFAULTS["alpha"] if alpha is None else alpha)
        if not (np.isfinite(alpha) and alpha >= 0):
            raise InputError("alpha", f"must be a number >= 0, got {alpha}")
        beta = float(_AS_DEFAULTS["beta"] if beta is None else beta)
        if not (np.isfinite(beta) and beta >= 0):
            raise InputError("beta", f"must be a number >= 0, got {beta}")
        rho = _positive("rho", _AS_DEFAULTS["rho"] if rho is None else rho, upper=1.0)
        nodes = _positive("nodes", nodes, integer=True)
        if nodes < 2:
            raise InputError("nodes", f"need at least 2 nodes per parameter, got {nodes}")
        elite = _positive("elite", max(1, ants // 10) if elite is None else elite, integer=True)
        _ant_system(evaluate, lower, upper, rng, ants=ants, iterations=iterations, alpha=alpha,
                    beta=beta, rho=rho, nodes=nodes, elite=min(elite, ants),
                    patience=_positive("patience", patience, integer=True),
                    shrink=_positive("shrink", shrink, upper=1.0), step=step)
    else:
        for name, value in (("alpha", alpha), ("beta", beta), ("rho", rho)):
            if value is not None:
                raise InputError(name, "is an Ant System option; ACO_R has no alpha, beta or rho "
                                       "(use archive, q and xi)")
        ants = _positive("ants", _ACOR_DEFAULTS["ants"] if ants is None else ants, integer=True)
        archive = _positive("archive", _ACOR_DEFAULTS["archive"] if archive is None else archive, integer=True)
        if archive < 2:
            raise InputError("archive", f"needs at least 2 solutions, got {archive}")
        _acor(evaluate, lower, upper, rng, ants=ants, iterations=iterations, archive=archive,
              q=_positive("q", _ACOR_DEFAULTS["q"] if q is None else q),
              xi=_positive("xi", _ACOR_DEFAULTS["xi"] if xi is None else xi), step=step)

    return OptimizeResult(x=hist_x[-1], fun=hist_f[-1], nfev=evaluate.nfev, nit=len(hist_f),
                          success=bool(np.isfinite(hist_f[-1])), message=state["message"],
                          method=method, history_fun=np.array(hist_f), history_x=np.array(hist_x),
                          history_nfev=np.array(hist_n))
