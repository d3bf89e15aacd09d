"""The least-squares line through points, in closed form: a lab test's readings (the elastic
line of a compression curve, a Mohr-Coulomb envelope) are then the same to the bit on every
processor, which a fit through LAPACK (`numpy.polyfit`) is not: its kernels are chosen by
processor and sum in another order."""

import numpy as np


def fit_line(x, y) -> tuple[float, float]:
    """Slope and intercept of the least-squares line y = slope x + intercept (inf or nan,
    without a warning, where the x do not spread: a curve of no load)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    x_mean, y_mean = np.mean(x), np.mean(y)
    dx = x - x_mean
    with np.errstate(divide="ignore", invalid="ignore"):
        slope = np.sum(dx * (y - y_mean)) / np.sum(dx * dx)
    return float(slope), float(y_mean - slope * x_mean)
