"""The geometry of PFC's material genesis in 3D (FISHTank `ft.fis`; Potyondy & Cundall 2004):
the sphere cloud, contacts in a cuboid vessel (or the vertical cylinder inscribed in it, as
FISHTank's cylindrical material vessel), floaters and the bonds of an installation gap.
The settings are the 2D genesis' (`rockcal.specimens.genesis.Genesis`, PFC's names); the steps that
move spheres are in `packing`.
"""

from __future__ import annotations

import numpy as np

from rockcal.dem.neighbours import CONTACT_GAP
from rockcal.specimens.genesis import MIN_CONTACTS, Genesis
from rockcal.dem3d.neighbours import check_grid, near_pairs
from rockcal.dem3d.vectors import cubes, norms

# The 2D default cloud porosity (0.09) would fill a 3D vessel far beyond the spheres' random
# close packing (a solid fraction of about 0.64): FISHTank's 3D examples take pk_nc 0.30-0.35.
DEFAULT_GENESIS_3D = Genesis(cloud_porosity=0.35)


def cloud_radii(rng: np.random.Generator, volume: float, rmin: float, radius_ratio: float,
                cloud_porosity: float) -> np.ndarray:
    """Radii drawn uniform in [R_min, ratio R_min] one after another until the spheres' volume
    reaches (1 - n_c) x `volume` (m³), overlaps not counted (FISHTank's `pk_nc`)."""
    lo, hi = rmin, radius_ratio * rmin
    mean_cube = (hi**4 - lo**4) / (4 * (hi - lo)) if hi > lo else lo**3
    target = (1.0 - cloud_porosity) * volume
    radius = rng.uniform(lo, hi, int(1.2 * target / (4 / 3 * np.pi * mean_cube)) + 16)
    count = int(np.searchsorted(np.cumsum(4 / 3 * np.pi * cubes(radius)), target)) + 1
    return radius[:count]


def pair_gaps(pos: np.ndarray, radius: np.ndarray, reach: float):
    """Pairs (i, j), i < j, with a surface gap below `reach` (m), and their gaps."""
    check_grid(pos, radius, reach)
    pi, pj = near_pairs(pos, radius, reach)
    gap = norms(pos[pj] - pos[pi]) - radius[pi] - radius[pj]
    return pi, pj, gap


def sphere_contacts(pos: np.ndarray, radius: np.ndarray) -> np.ndarray:
    """Number of sphere-sphere contacts of each sphere."""
    pi, pj, _ = pair_gaps(pos, radius, CONTACT_GAP * radius.min())
    return np.bincount(np.concatenate([pi, pj]), minlength=len(radius))


def wall_gaps(pos: np.ndarray, radius: np.ndarray, size, cylinder: bool = False) -> np.ndarray:
    """Gap of each sphere to the six faces of the vessel [0, size] (m): -x, +x, -y, +y, -z, +z;
    or of the `cylinder` inscribed in it: -z, +z, its side."""
    size = np.asarray(size, float)
    low, high = pos - radius[:, None], size - pos - radius[:, None]
    if cylinder:
        side = 0.5 * size[0] - np.hypot(*(pos[:, :2] - 0.5 * size[:2]).T) - radius
        return np.column_stack([low[:, 2], high[:, 2], side])
    return np.column_stack([low[:, 0], high[:, 0], low[:, 1], high[:, 1], low[:, 2], high[:, 2]])


def vessel_contacts(pos: np.ndarray, radius: np.ndarray, size, cylinder: bool = False) -> np.ndarray:
    """Contacts of each sphere in the vessel: with spheres and with the walls."""
    touching = wall_gaps(pos, radius, size, cylinder) <= CONTACT_GAP * radius.min()
    return sphere_contacts(pos, radius) + touching.sum(axis=1)


def floaters(pos: np.ndarray, radius: np.ndarray, size, cylinder: bool = False) -> np.ndarray:
    """True for the spheres with fewer than MIN_CONTACTS contacts in the vessel, walls counted."""
    return vessel_contacts(pos, radius, size, cylinder) < MIN_CONTACTS


def enlarge_floaters(pos: np.ndarray, radius: np.ndarray, size, overlap,
                     cylinder: bool = False) -> np.ndarray:
    """Radii with every floater grown until it overlaps its MIN_CONTACTS-th nearest sphere or
    wall by `overlap` (one for all, or one per sphere) x its radius (Potyondy & Cundall 2004
    enlarge floaters rather than delete them); the packing must then be cycled so that its
    neighbours make room."""
    overlap = np.broadcast_to(overlap, radius.shape)
    grown = radius.copy()
    walls = wall_gaps(pos, radius, size, cylinder)
    for k in np.flatnonzero(floaters(pos, radius, size, cylinder)):
        gaps = norms(pos - pos[k]) - radius - radius[k]
        gaps[k] = np.inf
        nearest = np.partition(np.concatenate([gaps, walls[k]]), MIN_CONTACTS - 1)
        grown[k] += max(0.0, nearest[MIN_CONTACTS - 1]) + overlap[k] * radius[k]
    return grown


def install_bonds(pos: np.ndarray, radius: np.ndarray, gap: float) -> np.ndarray:
    """Pairs i < j whose gap is <= `gap` (m): the bonds of PFC's installation gap."""
    tolerance = CONTACT_GAP * radius.min()
    pi, pj, g = pair_gaps(pos, radius, gap + tolerance)
    keep = g <= gap + tolerance
    return np.column_stack([pi[keep], pj[keep]]).astype(np.int64)
