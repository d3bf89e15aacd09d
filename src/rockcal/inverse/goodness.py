"""Goodness of fit of a computed curve to a measured one: RE and CC on common abscissae.

Both curves are put on common abscissae first: the measured abscissae that fall inside the
strain range the two curves share (or `points` equally spaced abscissae over that range),
with linear interpolation (np.interp). Then
RE = ‖y^C − y^M‖ / ‖y^M‖ and CC = Pearson correlation of y^C and y^M.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rockcal.errors import InputError


def _curve(name: str, x, y) -> tuple[np.ndarray, np.ndarray]:
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    if x.ndim != 1 or x.shape != y.shape:
        raise InputError(name, f"abscissae and ordinates need the same 1-D shape, got {x.shape} and {y.shape}")
    if len(x) < 2:
        raise InputError(name, "a curve needs at least 2 points")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise InputError(name, "curve contains non-finite values")
    if np.any(np.diff(x) <= 0):
        i = int(np.flatnonzero(np.diff(x) <= 0)[0])
        raise InputError(name, f"abscissae must increase strictly (point {i + 2}: {x[i + 1]:g} after {x[i]:g})")
    return x, y


def common_abscissae(x_c, y_c, x_m, y_m, points: int | None = None):
    """(x, y_c, y_m): both curves interpolated on common abscissae over their overlap."""
    x_c, y_c = _curve("computed", x_c, y_c)
    x_m, y_m = _curve("measured", x_m, y_m)
    lo, hi = max(x_c[0], x_m[0]), min(x_c[-1], x_m[-1])
    if lo >= hi:
        raise InputError("curves", f"computed [{x_c[0]:g}, {x_c[-1]:g}] and measured "
                                   f"[{x_m[0]:g}, {x_m[-1]:g}] abscissae do not overlap")
    if points is None:
        x = x_m[(x_m >= lo) & (x_m <= hi)]
        if len(x) < 2:
            x = np.linspace(lo, hi, max(len(x_m), 2))
    else:
        if points < 2:
            raise InputError("points", f"need at least 2, got {points}")
        x = np.linspace(lo, hi, int(points))
    return x, np.interp(x, x_c, y_c), np.interp(x, x_m, y_m)


@dataclass(frozen=True)
class GoodnessOfFit:
    """RE and CC of a computed curve against a measured one, and the range compared."""

    RE: float
    CC: float
    points: int
    x_range: tuple[float, float]


def curve_fit(x_c, y_c, x_m, y_m, points: int | None = None) -> GoodnessOfFit:
    """RE = ‖y^C − y^M‖ / ‖y^M‖ and Pearson CC on common abscissae (see module doc).

    CC is NaN when either curve is constant over the compared range.
    """
    x, c, m = common_abscissae(x_c, y_c, x_m, y_m, points)
    norm = np.linalg.norm(m)
    if norm == 0:
        raise InputError("measured", "the measured curve is zero everywhere on the compared range")
    re = float(np.linalg.norm(c - m) / norm)
    dc, dm = c - c.mean(), m - m.mean()
    denom = np.sqrt(np.sum(dc ** 2) * np.sum(dm ** 2))
    cc = float(np.sum(dc * dm) / denom) if denom > 0 else float("nan")
    return GoodnessOfFit(RE=re, CC=cc, points=len(x), x_range=(float(x[0]), float(x[-1])))


def relative_error(x_c, y_c, x_m, y_m, points: int | None = None) -> float:
    """RE = ‖y^C − y^M‖ / ‖y^M‖ on common abscissae."""
    return curve_fit(x_c, y_c, x_m, y_m, points).RE


def correlation_coefficient(x_c, y_c, x_m, y_m, points: int | None = None) -> float:
    """Pearson CC of the two curves on common abscissae."""
    return curve_fit(x_c, y_c, x_m, y_m, points).CC
