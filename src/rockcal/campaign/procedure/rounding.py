"""The one rounding of every point a campaign runs (samples, checks, stand-ins and verified
optima): stable store keys, whole-number parameters whole; and the planning state's stand-in
for a point only a search finds."""

from __future__ import annotations

import numpy as np

from rockcal.campaign.input.config import nearest_whole

SIGNIFICANT_DIGITS = 4  # parameters of verification runs are rounded to this (stable store keys)
GOLDEN = (np.sqrt(5) - 1) / 2  # the stand-in's place on the box's diagonal


def rounded(x: np.ndarray, whole: np.ndarray | None = None) -> np.ndarray:
    """A point to be run, rounded to SIGNIFICANT_DIGITS (stable store keys), the parameters
    marked `whole` to the nearest whole number (halves up), the one rounding of every point
    run: samples, checks, stand-ins and verified optima."""
    whole = np.zeros(len(x), bool) if whole is None else whole
    return np.array([nearest_whole(v) if w else float(f"{v:.{SIGNIFICANT_DIGITS}g}") for v, w in zip(x, whole)])


def rounded_rows(x: np.ndarray, whole: np.ndarray | None = None) -> np.ndarray:
    return np.array([rounded(row, whole) for row in x])


def stand_in(box: np.ndarray, whole: np.ndarray | None = None) -> np.ndarray:
    """A point on the box's diagonal, at the golden ratio so that it falls on no design's
    level: where the planning state puts the point only a search finds (the first round's
    optimum, which is also the identified point)."""
    return rounded(box[:, 0] + GOLDEN * (box[:, 1] - box[:, 0]), whole)
