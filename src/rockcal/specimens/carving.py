"""Cutting specimens out of a packing: a notch, a disk. Removed particles take their bonds along.
A notch of zero width is a cut: the bonds across a line are removed, no particle is.

Carving keeps the packing's contact forces and fabric (as when a lab specimen is cut from a
block); particles left with no bond at all would float, so they are removed as well.

A clumped specimen (`Specimen.clump_of`) is carved grain by grain: a clump is kept or removed
whole, judged as the disk of its area at its centroid (`grains`), and one is left floating
when none of its pebbles keeps a bond. The kept clumps are renumbered in their order.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from rockcal.dem.clumps import clump_properties, members
from rockcal.specimens.specimen import Specimen


def grains(spec: Specimen) -> tuple[np.ndarray, np.ndarray]:
    """Each grain's centre (m) and radius (m): a ball's own; a clump's centroid and equivalent
    radius (of a disk of its area), clump by clump."""
    if spec.clump_of is None:
        return spec.pos, spec.radius
    area, centroid, _ = clump_properties(spec.pos, spec.radius, *members(spec.clump_of))
    return centroid, np.sqrt(area / np.pi)


def of_particles(spec: Specimen, keep_grains: np.ndarray) -> np.ndarray:
    """A mask of the grains (`grains`' order) as a mask of the particles: each pebble its clump's."""
    return keep_grains if spec.clump_of is None else keep_grains[spec.clump_of]


def _over_clumps(spec: Specimen, mask: np.ndarray, whole: bool) -> np.ndarray:
    """The mask made the same for every pebble of a clump: set where all its pebbles are
    (`whole`) or where any one is."""
    if spec.clump_of is None:
        return mask
    reduce = np.logical_and if whole else np.logical_or
    per_clump = np.full(spec.n_grains, whole)
    reduce.at(per_clump, spec.clump_of, mask)
    return per_clump[spec.clump_of]


def keep_particles(spec: Specimen, keep: np.ndarray, label: str,
                   width_m: float | None = None, height_m: float | None = None) -> Specimen:
    """The specimen made of the kept particles (re-indexed, bonds between kept ones only); of a
    clumped specimen, of the clumps all of whose pebbles are kept (renumbered, in order)."""
    keep = _over_clumps(spec, np.asarray(keep, bool), whole=True)
    for _ in range(2):  # once for the cut, once for particles it left without any bond
        bonds = spec.bonds[keep[spec.bonds[:, 0]] & keep[spec.bonds[:, 1]]]
        bonded = np.zeros(spec.n_particles, bool)
        bonded[bonds.ravel()] = True
        keep = keep & _over_clumps(spec, bonded, whole=False)
    index = np.full(spec.n_particles, -1)
    index[keep] = np.arange(np.count_nonzero(keep))
    kept = keep[spec.bonds[:, 0]] & keep[spec.bonds[:, 1]]
    clump_of = None
    if spec.clump_of is not None:
        clump_of = np.unique(spec.clump_of[keep], return_inverse=True)[1].reshape(-1).astype(np.int64)
    return replace(spec, pos=spec.pos[keep].copy(), radius=spec.radius[keep].copy(),
                   bonds=index[spec.bonds[kept]], **_kept_draws(spec, kept), clump_of=clump_of,
                   width_m=width_m if width_m is not None else spec.width_m,
                   height_m=height_m if height_m is not None else spec.height_m, label=label)


def _kept_draws(spec: Specimen, kept: np.ndarray) -> dict:
    """The kept bonds' draws (for parallel bonds and for flat joints)."""
    return {name: None if draws is None else draws[kept] for name, draws in
            (("bond_draws", spec.bond_draws), ("joint_draws", spec.joint_draws))}


def outside_rectangle(pos: np.ndarray, radius: np.ndarray, x0: float, x1: float, y0: float,
                      y1: float) -> np.ndarray:
    """True for the disks that do not overlap the rectangle [x0, x1] x [y0, y1] (m)."""
    dx = np.maximum.reduce([x0 - pos[:, 0], np.zeros(len(pos)), pos[:, 0] - x1])
    dy = np.maximum.reduce([y0 - pos[:, 1], np.zeros(len(pos)), pos[:, 1] - y1])
    return dx**2 + dy**2 >= radius**2


def inside_circle(pos: np.ndarray, radius: np.ndarray, centre, circle_radius: float) -> np.ndarray:
    """True for the disks lying wholly inside the circle."""
    return np.hypot(pos[:, 0] - centre[0], pos[:, 1] - centre[1]) + radius <= circle_radius


def cut_bonds(spec: Specimen, x: float, y_top: float, label: str) -> Specimen:
    """The specimen with the bonds that cross the vertical line at `x` below `y_top` (m)
    removed: a crack of zero width, as sharp as the packing allows."""
    i, j = spec.bonds.T
    dx_i, dx_j = spec.pos[i, 0] - x, spec.pos[j, 0] - x
    crosses = dx_i * dx_j < 0
    along = np.divide(dx_i, dx_i - dx_j, out=np.zeros(len(i)), where=crosses)
    y_cross = spec.pos[i, 1] + along * (spec.pos[j, 1] - spec.pos[i, 1])
    keep = ~(crosses & (y_cross < y_top))
    return replace(spec, bonds=spec.bonds[keep], **_kept_draws(spec, keep), label=label)
