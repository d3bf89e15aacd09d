"""Search bounds: a (lower, upper) pair per parameter, checked once for every tool."""

from __future__ import annotations

import numpy as np

from rockcal.errors import InputError


def check_bounds(bounds) -> tuple[np.ndarray, np.ndarray]:
    """(lower, upper) arrays from [(lo, hi), ...], a dict name -> (lo, hi) or scipy Bounds.

    Every bound must be finite and lower < upper.
    """
    if hasattr(bounds, "lb") and hasattr(bounds, "ub"):
        pairs = list(zip(np.atleast_1d(bounds.lb), np.atleast_1d(bounds.ub)))
        names = [str(i) for i in range(len(pairs))]
    elif isinstance(bounds, dict):
        names, pairs = [str(k) for k in bounds], list(bounds.values())
    else:
        pairs = list(bounds)
        names = [str(i) for i in range(len(pairs))]
    if not pairs:
        raise InputError("bounds", "at least one parameter is needed")
    lower, upper = [], []
    for name, pair in zip(names, pairs):
        try:
            lo, hi = (float(v) for v in pair)
        except (TypeError, ValueError):
            raise InputError(f"bounds[{name}]", f"expected a (lower, upper) pair of numbers, got {pair!r}") from None
        if not (np.isfinite(lo) and np.isfinite(hi)):
            raise InputError(f"bounds[{name}]", f"bounds must be finite, got ({lo}, {hi})")
        if lo >= hi:
            raise InputError(f"bounds[{name}]", f"lower bound {lo:g} must be below upper bound {hi:g}")
        lower.append(lo)
        upper.append(hi)
    return np.array(lower), np.array(upper)
