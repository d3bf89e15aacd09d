"""Measuring a specimen: gauge lengths from its boundary particles, secant moduli, cracks."""

from __future__ import annotations

import numpy as np
from numba import njit

from rockcal.dem.laws import BROKEN_SHEAR, BROKEN_TENSION


def boundary_sets(pos: np.ndarray, radius: np.ndarray, band: float) -> dict[str, np.ndarray]:
    """Indices of the particles whose edge lies within `band` of each side of the specimen."""
    left, right = (pos[:, 0] - radius).min(), (pos[:, 0] + radius).max()
    bottom, top = (pos[:, 1] - radius).min(), (pos[:, 1] + radius).max()
    return {
        "left": np.flatnonzero(pos[:, 0] - radius < left + band),
        "right": np.flatnonzero(pos[:, 0] + radius > right - band),
        "bottom": np.flatnonzero(pos[:, 1] - radius < bottom + band),
        "top": np.flatnonzero(pos[:, 1] + radius > top - band),
    }


def gauge_lengths(pos: np.ndarray, sets: dict[str, np.ndarray]) -> tuple[float, float]:
    """Distance between the mean centres of opposite boundary sets: (horizontal, vertical), m.

    Strains taken from these are those of the specimen itself, like strain gauges on a lab
    sample: the compliance of the platen contacts does not enter. Medians, not means: a flake
    spalling off a free side must not read as lateral strain of the whole specimen.
    """
    width = _median(pos, sets["right"], 0) - _median(pos, sets["left"], 0)
    height = _median(pos, sets["top"], 1) - _median(pos, sets["bottom"], 1)
    return float(width), float(height)


@njit(cache=True)
def _median(pos, members, axis):
    """np.median(pos[members, axis]), compiled: a test reads its gauges every few steps."""
    return np.median(pos[members, axis])


def secant_at_half_peak(axial_strain, lateral_strain, stress) -> tuple[float, float, int]:
    """Secant modulus and Poisson's ratio at half the peak stress (PFC users' reading).

    Returns (E, nu, index of the peak); E in the units of stress, nu = lateral / axial strain,
    both interpolated on the rising branch where the stress first reaches half the peak.
    """
    peak = int(np.argmax(stress))
    half = 0.5 * stress[peak]
    k = int(np.argmax(stress[: peak + 1] >= half))
    if k == 0:
        e_a, e_l = axial_strain[0], lateral_strain[0]
    else:
        w = (half - stress[k - 1]) / (stress[k] - stress[k - 1])
        e_a = axial_strain[k - 1] + w * (axial_strain[k] - axial_strain[k - 1])
        e_l = lateral_strain[k - 1] + w * (lateral_strain[k] - lateral_strain[k - 1])
    if e_a <= 0:
        return float("nan"), float("nan"), peak
    return float(half / e_a), float(e_l / e_a), peak


def cracks(bond_state: np.ndarray, bond_break_xy: np.ndarray) -> dict[str, np.ndarray]:
    """Positions (m) of the broken bonds, by failure mode."""
    return {"tension": bond_break_xy[bond_state == BROKEN_TENSION],
            "shear": bond_break_xy[bond_state == BROKEN_SHEAR]}
