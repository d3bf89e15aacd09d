"""Gauges on a 3D specimen, as the 2D rig's (`rockcal.labtests.rig.gauge`): the axial strain
from the spheres along its top and bottom faces, the lateral strain from those along its
side(s). Each reads the interquartile mean (the mean of the middle half) of its spheres' own
displacements: of displacements, since a sphere's start varies with its radius and a central
value of positions would jump from one sphere to the next; of the middle half, so that a flake
spalling off a side does not read as the whole specimen's strain (2D takes the median; in 3D a
few dozen spheres' median jumps too, and moved ν by 3 % when the loading speed was halved).
A cylinder's lateral strain is its outer spheres' radial strain Δr/r about the axis (which
follows the spheres' mean sideways drift); a prism's, the mean of its two widths'.
"""

from __future__ import annotations

import numpy as np

SIDES = (("left", "right"), ("front", "back"))
# The gauges' spheres: those within this many R_min of a face; about one sphere deep on the
# sides, so that a small cylinder's side gauge reads well over a hundred spheres (half an R_min
# reads about 25 of a 12 mm cylinder at R_min 0.6 mm).
END_BAND = 0.5
SIDE_BAND = 2.0


def faces(specimen) -> dict[str, np.ndarray]:
    """Indices of the spheres whose surface lies within END_BAND x R_min of the top and the
    bottom face and within SIDE_BAND x R_min of the side(s)."""
    pos, radius = specimen.pos, specimen.radius
    low, high = (pos - radius[:, None]).min(axis=0), (pos + radius[:, None]).max(axis=0)
    end, band = END_BAND * radius.min(), SIDE_BAND * radius.min()
    sets = {"bottom": np.flatnonzero(pos[:, 2] - radius < low[2] + end),
            "top": np.flatnonzero(pos[:, 2] + radius > high[2] - end)}
    if specimen.shape == "cylinder":
        reach = np.hypot(*(pos[:, :2] - 0.5 * (low[:2] + high[:2])).T) + radius
        sets["side"] = np.flatnonzero(reach > reach.max() - band)
    else:
        for a, (lo_name, hi_name) in enumerate(SIDES):
            sets[lo_name] = np.flatnonzero(pos[:, a] - radius < low[a] + band)
            sets[hi_name] = np.flatnonzero(pos[:, a] + radius > high[a] - band)
    return sets


def central_mean(values: np.ndarray) -> float:
    """The mean of the middle half of `values` (the interquartile mean)."""
    values = np.sort(values)
    quarter = len(values) // 4
    return float(values[quarter:len(values) - quarter].mean())


class Gauge3D:
    """Gauges on the spheres along the faces of `specimen` (as made, `faces`), zeroed at the
    spheres' positions `pos` now (a live view: read as they move)."""

    def __init__(self, specimen, pos: np.ndarray):
        self.pos, self.start = pos, pos.copy()
        self.sets = faces(specimen)
        self.axis = 0.5 * (self.start[:, :2].min(axis=0) + self.start[:, :2].max(axis=0))
        self.height = self._central(self.start, "top", 2) - self._central(self.start, "bottom", 2)

    def _central(self, pos, name, a):
        return central_mean(pos[self.sets[name], a])

    def strains(self) -> tuple[float, float]:
        """The axial strain (shortening positive) and the lateral strain (extension positive)."""
        moved = self.pos - self.start
        axial = (self._central(moved, "bottom", 2) - self._central(moved, "top", 2)) / self.height
        if "side" in self.sets:
            side = self.sets["side"]
            axis = self.axis + moved[:, :2].mean(axis=0)
            r0 = np.hypot(*(self.start[side, :2] - self.axis).T)
            r = np.hypot(*(self.pos[side, :2] - axis).T)
            return float(axial), central_mean((r - r0) / r0)
        widths = [(self._central(moved, hi, a) - self._central(moved, lo, a))
                  / (self._central(self.start, hi, a) - self._central(self.start, lo, a))
                  for a, (lo, hi) in enumerate(SIDES)]
        return float(axial), float(np.mean(widths))
