"""The gauges of the 3D rig, as the 2D rig's (`rockcal.labtests.rig.gauge`): the axial strain
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
from numba import njit

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


def check_gauges(specimen) -> None:
    """Nothing to check: a 3D specimen's size (`specimens3d.specimen.check_size`) puts spheres on
    every face."""


class Gauge3D:
    """Gauges on the spheres along the faces of `specimen` (as made, `faces`), zeroed at the
    spheres' positions in `state` now (read as they move)."""

    def __init__(self, specimen, state):
        pos = state.particles.pos
        self.pos, self.start = pos, pos.copy()
        self.sets = faces(specimen)
        self.axis = 0.5 * (self.start[:, :2].min(axis=0) + self.start[:, :2].max(axis=0))
        self.height = self._central(self.start, "top", 2) - self._central(self.start, "bottom", 2)
        if "side" in self.sets:  # the side spheres' distances from the axis as made
            self.r0 = np.hypot(*(self.start[self.sets["side"], :2] - self.axis).T)
        else:
            self.widths0 = [self._central(self.start, hi, a) - self._central(self.start, lo, a)
                            for a, (lo, hi) in enumerate(SIDES)]

    def _central(self, pos, name, a):
        return central_mean(pos[self.sets[name], a])

    def _displacement(self, name, a):
        return _central_displacement(self.pos, self.start, self.sets[name], a)

    def strains(self) -> tuple[float, float]:
        """The axial strain (shortening positive) and the lateral strain (extension positive)."""
        axial = (self._displacement("bottom", 2) - self._displacement("top", 2)) / self.height
        if "side" in self.sets:
            return axial, _radial_strain(self.pos, self.start, self.sets["side"], self.axis, self.r0)
        widths = [(self._displacement(hi, a) - self._displacement(lo, a)) / self.widths0[a]
                  for a, (lo, hi) in enumerate(SIDES)]
        return axial, float(np.mean(widths))


# The readings are compiled (a test reads its gauges every few steps), with numpy's sums in
# numpy's order, so that they give its numbers to the bit.

@njit(cache=True)
def _numpy_sum(values, first, count):
    """numpy's sum of values[first:first + count] (its pairwise summation)."""
    if count < 8:
        total = 0.0
        for k in range(first, first + count):
            total += values[k]
        return total
    if count <= 128:
        r = values[first:first + 8].copy()
        end = first + count - count % 8
        for k in range(first + 8, end, 8):
            for u in range(8):
                r[u] += values[k + u]
        total = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]))
        for k in range(end, first + count):
            total += values[k]
        return total
    half = count // 2
    half -= half % 8
    return _numpy_sum(values, first, half) + _numpy_sum(values, first + half, count - half)


@njit(cache=True, error_model="numpy")
def central_mean(values):
    """The mean of the middle half of `values` (the interquartile mean)."""
    values = np.sort(values)
    quarter = values.shape[0] // 4
    count = values.shape[0] - 2 * quarter
    return _numpy_sum(values, quarter, count) / count


@njit(cache=True)
def _central_displacement(pos, start, members, a):
    """The central mean of the `members`' displacements along axis `a`."""
    moved = np.empty(members.shape[0])
    for q in range(members.shape[0]):
        moved[q] = pos[members[q], a] - start[members[q], a]
    return central_mean(moved)


@njit(cache=True, error_model="numpy")
def _radial_strain(pos, start, side, axis, r0):
    """The central mean of the `side` spheres' radial strains about the axis, which follows
    the mean sideways drift of all the spheres (numpy sums a column's rows in turn)."""
    n = pos.shape[0]
    drift_x = pos[0, 0] - start[0, 0]
    drift_y = pos[0, 1] - start[0, 1]
    for k in range(1, n):
        drift_x += pos[k, 0] - start[k, 0]
        drift_y += pos[k, 1] - start[k, 1]
    x, y = axis[0] + drift_x / n, axis[1] + drift_y / n
    strain = np.empty(side.shape[0])
    for q in range(side.shape[0]):
        k = side[q]
        strain[q] = (np.hypot(pos[k, 0] - x, pos[k, 1] - y) - r0[q]) / r0[q]
    return central_mean(strain)
