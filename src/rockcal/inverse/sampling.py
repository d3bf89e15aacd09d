"""Latin hypercube designs over search bounds, in physical units."""

from __future__ import annotations

import functools

import numpy as np
from scipy.spatial.distance import pdist

from rockcal.errors import InputError
from rockcal.inverse.bounds import check_bounds

OPTIMIZATIONS = ("random-cd", "maximin", "none")


def latin_hypercube(bounds, n: int, *, seed=None, optimization: str = "random-cd",
                    candidates: int = 50) -> np.ndarray:
    """n points (rows) over `bounds`, one point in each of the n strata of every parameter.

    optimization: "random-cd" (scipy's centred-discrepancy improvement), "maximin" (the
    design with the largest smallest pairwise distance among `candidates` seeded random
    Latin hypercubes, in scaled units) or "none". The same seed gives the same design.
    """
    lower, upper = check_bounds(bounds)
    if int(n) != n or n < 2:
        raise InputError("n", f"a Latin hypercube needs at least 2 points, got {n}")
    if optimization not in OPTIMIZATIONS:
        raise InputError("optimization", f"must be one of {', '.join(OPTIMIZATIONS)}, got {optimization!r}")
    if optimization == "maximin" and candidates < 1:
        raise InputError("candidates", f"must be at least 1, got {candidates}")
    from scipy.stats import qmc  # here: scipy.stats takes 0.4 s to import, and every command would wait

    d = len(lower)
    if isinstance(seed, (int, np.integer)):  # planning asks for the same design several times: it is made once
        unit = _unit_design(d, int(n), int(seed), optimization, candidates)
    else:
        unit = _unit_design.__wrapped__(d, int(n), seed, optimization, candidates)
    return qmc.scale(unit, lower, upper)


@functools.lru_cache(maxsize=8)
def _unit_design(d: int, n: int, seed, optimization: str, candidates: int) -> np.ndarray:
    """The design in the unit cube (read-only: it may be shared)."""
    from scipy.stats import qmc

    rng = np.random.default_rng(seed)
    if optimization == "maximin":
        sampler = qmc.LatinHypercube(d, seed=rng)
        best, best_gap = None, -np.inf
        for _ in range(candidates):
            unit = sampler.random(n)
            gap = pdist(unit).min()
            if gap > best_gap:
                best, best_gap = unit, gap
        unit = best
    else:
        opt = None if optimization == "none" or d < 2 else optimization
        unit = qmc.LatinHypercube(d, optimization=opt, seed=rng).random(n)
    unit.flags.writeable = False
    return unit
