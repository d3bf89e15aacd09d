"""Making specimens: a dense random packing by radius expansion, or a regular hexagonal one.

A specimen is geometry only (centres, radii, bonded pairs); micro-parameters come later, so
one specimen serves every forward run of a calibration. Random packings are cached on disk
by (geometry, resolution, seed, generator version).
"""

from __future__ import annotations

import hashlib
import json
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rockcal.errors import InputError

GENERATOR_VERSION = 4
PACKING_MODULUS_GPA = 1.0  # frictionless contacts used only to make the packing
ISOTROPIC_STRESS_MPA = 0.1  # installed before bonding (Potyondy & Cundall 2004): overlaps ~1e-4 R
BOND_GAP = 0.02  # pairs nearer than this fraction of R_min count as touching, and are bonded
JAMMING_FRACTION = 0.845  # solid fraction of frictionless 2D polydisperse disks at jamming


@dataclass(frozen=True)
class Specimen:
    """Disk centres (m), radii (m) and bonded pairs (i < j) in a width x height box (m)."""

    pos: np.ndarray
    radius: np.ndarray
    bonds: np.ndarray
    width_m: float
    height_m: float
    label: str

    @property
    def n_particles(self) -> int:
        return len(self.radius)

    @property
    def porosity(self) -> float:
        return 1.0 - float(np.pi * (self.radius**2).sum()) / (self.width_m * self.height_m)

    def coordination(self) -> float:
        return 2.0 * len(self.bonds) / self.n_particles


def check_geometry(width_mm: float, height_mm: float, rmin_mm: float, radius_ratio: float) -> None:
    """Reject geometry a packing cannot be made of, naming the field."""
    if not rmin_mm > 0:
        raise InputError("rmin_mm", f"must be > 0, got {rmin_mm}")
    if not 1.0 <= radius_ratio <= 10.0:
        raise InputError("radius_ratio", f"must be in [1, 10], got {radius_ratio}")
    for name, value in (("width_mm", width_mm), ("height_mm", height_mm)):
        if not value > 0:
            raise InputError(name, f"must be > 0, got {value}")
        if value < 8 * rmin_mm * radius_ratio:
            raise InputError(name, f"{value} mm is too small for particles of radius up to "
                             f"{rmin_mm * radius_ratio:g} mm (need at least 4 diameters)")


def hexagonal(width_mm: float, height_mm: float, radius_mm: float) -> Specimen:
    """Equal disks on a triangular lattice, rows along x, every touching pair bonded."""
    check_geometry(width_mm, height_mm, radius_mm, 1.0)
    r = radius_mm * 1e-3
    width, height = width_mm * 1e-3, height_mm * 1e-3
    rows = int((height - 2 * r) / (np.sqrt(3) * r)) + 1
    centres = []
    for row in range(rows):
        shift = r if row % 2 else 0.0
        count = int((width - 2 * r - shift) / (2 * r)) + 1
        x = r + shift + 2 * r * np.arange(count)
        centres.append(np.column_stack([x, np.full(count, r + row * np.sqrt(3) * r)]))
    pos = np.vstack(centres)
    radius = np.full(len(pos), r)
    # the lattice's own width: each disk spans 2r of its row, rows alternate n and n - 1 disks
    return Specimen(pos, radius, touching_pairs(pos, radius, 1e-9 * r), 2 * r * len(pos) / rows,
                    rows * np.sqrt(3) * r,
                    f"hexagonal {width_mm:g}x{height_mm:g} mm, R {radius_mm:g} mm")


def touching_pairs(pos: np.ndarray, radius: np.ndarray, gap: float) -> np.ndarray:
    """Pairs i < j whose gap R_i + R_j - d is below `gap` (m)."""
    from rockcal.dem.neighbours import near_pairs

    pi, pj = near_pairs(pos, radius, gap)
    return np.column_stack([pi, pj]).astype(np.int64)


def random_packing(width_mm: float, height_mm: float, rmin_mm: float = 0.25,
                   radius_ratio: float = 1.65, seed: int = 1, cache: bool = True) -> Specimen:
    """Dense polydisperse packing (radii uniform in [rmin, ratio*rmin]), cached on disk."""
    check_geometry(width_mm, height_mm, rmin_mm, radius_ratio)
    key = dict(kind="random", width_mm=width_mm, height_mm=height_mm, rmin_mm=rmin_mm,
               radius_ratio=radius_ratio, seed=seed, version=GENERATOR_VERSION)
    path = cache_dir() / (hashlib.sha1(json.dumps(key, sort_keys=True).encode()).hexdigest()[:16] + ".npz")
    label = f"random {width_mm:g}x{height_mm:g} mm, Rmin {rmin_mm:g} mm x{radius_ratio:g}, seed {seed}"
    if cache and path.exists():
        data = np.load(path)
        return Specimen(data["pos"], data["radius"], data["bonds"], width_mm * 1e-3,
                        height_mm * 1e-3, label)
    from rockcal.dem.packing import pack_box

    pos, radius = pack_box(width_mm * 1e-3, height_mm * 1e-3, rmin_mm * 1e-3, radius_ratio, seed)
    gap = BOND_GAP * rmin_mm * 1e-3
    pos, radius = remove_floaters(pos, radius, width_mm * 1e-3, height_mm * 1e-3, gap)
    pos, radius = in_memory_order(pos, radius, 4 * radius_ratio * rmin_mm * 1e-3)
    spec = Specimen(pos, radius, touching_pairs(pos, radius, gap), width_mm * 1e-3,
                    height_mm * 1e-3, label)
    if cache:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(f".{os.getpid()}.tmp.npz")
        np.savez(tmp, pos=spec.pos, radius=spec.radius, bonds=spec.bonds)
        os.replace(tmp, path)
    return spec


def remove_floaters(pos: np.ndarray, radius: np.ndarray, width: float, height: float, gap: float,
                    min_contacts: int = 3):
    """Drop the particles touching fewer than `min_contacts` neighbours or box walls (one pass)."""
    count = np.bincount(touching_pairs(pos, radius, gap).ravel(), minlength=len(radius))
    count += (pos[:, 0] - radius < gap).astype(int) + (pos[:, 0] + radius > width - gap)
    count += (pos[:, 1] - radius < gap).astype(int) + (pos[:, 1] + radius > height - gap)
    keep = count >= min_contacts
    return pos[keep], radius[keep]


def in_memory_order(pos: np.ndarray, radius: np.ndarray, strip: float):
    """Number particles strip by strip (strips of height `strip`, then by x) so that
    neighbours sit close in memory: the pair loops then run from cache, not from RAM."""
    order = np.lexsort((pos[:, 0], np.floor(pos[:, 1] / strip)))
    return pos[order], radius[order]


def cache_dir() -> Path:
    """Where specimens are kept: $ROCKCAL_CACHE, else ~/.cache/rockcal/specimens."""
    root = os.environ.get("ROCKCAL_CACHE")
    return Path(root) if root else Path.home() / ".cache" / "rockcal" / "specimens"
