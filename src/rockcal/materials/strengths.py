"""The strength draw every bonded material shares: a normal distribution truncated at zero, as
PFC's FISHTank draws bond strengths, joint strengths and gaps (`ft_valNormDist` redraws negative
values). A value comes from a uniform draw u through the truncated normal's inverse
distribution function, so a bond keeps its rank whatever the mean and sd: one specimen and
seed serve every parameter set."""

from __future__ import annotations

import numpy as np
from scipy import special


def truncated_normal(mean: float, sd: float, u: np.ndarray) -> np.ndarray:
    """Values of a normal distribution (mean, sd) truncated at zero at uniform draws u in
    [0, 1); with sd 0, the mean (0 if negative)."""
    u = np.asarray(u, float)
    if sd == 0:
        return np.full(u.shape, max(mean, 0.0))
    below = special.ndtr(-mean / sd)  # probability mass cut off below zero
    return np.maximum(0.0, mean + sd * special.ndtri(below + u * (1.0 - below)))
