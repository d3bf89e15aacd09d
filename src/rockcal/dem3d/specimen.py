"""3D specimens made by PFC's material genesis: a cuboid packed in a cuboid vessel, or a
cylinder carved out of one (a cuboid packing of the cylinder's diameter squared by its height,
the spheres whose centres lie inside the cylinder kept, then those left without a bond dropped).

As in 2D (`rockcal.dem.specimen`), a specimen is geometry (centres, radii, bonded pairs) plus
one uniform draw per bond and strength; packings are kept on disk in 2D's cache folder, under
a hash of what their genesis depends on, and the bonds of an installation gap are found on
loading.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, replace

import numpy as np

from rockcal.dem.genesis import Genesis
from rockcal.dem.specimen import STRENGTH_STREAM, _one_maker, cache_dir
from rockcal.dem3d.genesis import DEFAULT_GENESIS_3D, floaters, install_bonds
from rockcal.dem3d.neighbours import spatial_order
from rockcal.dem3d.packing import pack_cuboid
from rockcal.errors import InputError
from rockcal.output_files import atomic_path

GENERATOR_VERSION_3D = 1
SHAPES = ("cylinder", "cuboid")


@dataclass(frozen=True)
class Specimen3D:
    """Sphere centres (m), radii (m) and bonded pairs (i < j); a `shape` of `size_m`: a
    cylinder (diameter, diameter, height) about the vertical line through its centre, or a
    cuboid (x, y, z sides), standing on z = 0. bond_draws: each bond's uniform draws in
    [0, 1) for its tensile strength and cohesion."""

    pos: np.ndarray
    radius: np.ndarray
    bonds: np.ndarray
    shape: str
    size_m: tuple[float, float, float]
    label: str
    bond_draws: np.ndarray
    pressure_mpa: float = float("nan")  # mean wall stress at the end of packing
    floaters: int = 0  # spheres the genesis left with fewer than 3 contacts in the vessel
    rmin_mm: float = float("nan")  # the cloud's R_min
    install_gap: float = float("nan")  # the bonds' installation gap / R_min

    @property
    def n_spheres(self) -> int:
        return len(self.radius)

    @property
    def volume_m3(self) -> float:
        x, y, z = self.size_m
        return np.pi / 4 * x * y * z if self.shape == "cylinder" else x * y * z

    @property
    def porosity(self) -> float:
        return 1.0 - float(4 / 3 * np.pi * (self.radius**3).sum()) / self.volume_m3

    def bonds_per_sphere(self) -> float:
        return 2.0 * len(self.bonds) / self.n_spheres


def random_specimen(shape: str, width_mm: float, height_mm: float, rmin_mm: float,
                    radius_ratio: float = 1.65, seed: int = 1, genesis: Genesis | None = None,
                    cache: bool = True) -> Specimen3D:
    """A cylinder of diameter `width_mm` or a square prism of side `width_mm`, `height_mm`
    tall, made by the 3D genesis (default settings `DEFAULT_GENESIS_3D`); its packing kept on
    disk unless `cache` is False."""
    if shape not in SHAPES:
        raise InputError("shape", f"must be one of {', '.join(SHAPES)}, got {shape!r}")
    for name, value in (("width_mm", width_mm), ("height_mm", height_mm)):
        if not value >= 8 * rmin_mm * radius_ratio:
            raise InputError(name, f"{value} mm is too small for spheres of radius up to "
                             f"{rmin_mm * radius_ratio:g} mm (need at least 4 diameters)")
    genesis = genesis or DEFAULT_GENESIS_3D
    vessel = np.array([width_mm, width_mm, height_mm]) * 1e-3
    pos, radius, pressure, left = packing(vessel, rmin_mm * 1e-3, radius_ratio, seed, genesis,
                                          cache)
    bonds = install_bonds(pos, radius, genesis.install_gap * rmin_mm * 1e-3)
    label = (f"{shape} {width_mm:g}x{height_mm:g} mm, Rmin {rmin_mm:g} mm x{radius_ratio:g}, "
             f"gap {genesis.install_gap:g} Rmin, seed {seed}")
    draws = np.random.default_rng([seed, STRENGTH_STREAM]).random((len(bonds), 2))
    specimen = Specimen3D(pos, radius, bonds, "cuboid", tuple(vessel), label, draws, pressure,
                          left, rmin_mm, genesis.install_gap)
    return carve_cylinder(specimen) if shape == "cylinder" else specimen


def carve_cylinder(cuboid: Specimen3D) -> Specimen3D:
    """The spheres of a square prism whose centres lie inside its inscribed vertical cylinder,
    less those the cut leaves without a bond, with their bonds and draws. Centres, not whole
    spheres: the cut surface then lies on the cylinder on average, so that its nominal
    cross-section is the one that carries the load (keeping whole spheres only would lose a
    shell about a radius thick: a quarter of a 10 mm cylinder's section at R_min 0.6 mm)."""
    x, _, z = cuboid.size_m
    keep = np.hypot(cuboid.pos[:, 0] - x / 2, cuboid.pos[:, 1] - x / 2) <= x / 2
    bi, bj = cuboid.bonds.T
    for _ in range(2):
        bonded = np.zeros(cuboid.n_spheres, bool)
        bonded[cuboid.bonds[keep[bi] & keep[bj]].ravel()] = True
        keep &= bonded
    kept = keep[bi] & keep[bj]
    index = np.full(cuboid.n_spheres, -1)
    index[keep] = np.arange(np.count_nonzero(keep))
    return replace(cuboid, pos=cuboid.pos[keep].copy(), radius=cuboid.radius[keep].copy(),
                   bonds=index[cuboid.bonds[kept]], shape="cylinder", size_m=(x, x, z),
                   bond_draws=cuboid.bond_draws[kept])


def packing(vessel, rmin: float, radius_ratio: float, seed: int, genesis: Genesis, cache: bool):
    """The packed vessel's centres and radii (m), pressure reached (MPa) and floaters left:
    from the cache, or made (and kept if `cache`)."""
    def make():
        return pack_cuboid(vessel, rmin, radius_ratio, seed, genesis.cloud_porosity,
                           genesis.pressure_mpa)

    if not cache:
        return _ordered(*make())
    path = cache_dir() / packing_name(vessel, rmin, radius_ratio, seed, genesis)
    with _one_maker(path):
        if not path.exists():
            pos, radius, pressure, left = _ordered(*make())
            with atomic_path(path) as tmp:
                np.savez(tmp, pos=pos, radius=radius, pressure_mpa=pressure, floaters=left)
    data = np.load(path)
    return data["pos"], data["radius"], float(data["pressure_mpa"]), int(data["floaters"])


def _ordered(pos, radius, pressure, left):
    order = spatial_order(pos, 4 * radius.max())
    return pos[order], radius[order], pressure, left


def packing_name(vessel, rmin: float, radius_ratio: float, seed: int, genesis: Genesis) -> str:
    """The file a 3D packing is kept in: a hash of what its genesis depends on, as 2D's
    (`rockcal.dem.specimen.packing_name`) with the vessel's three sides."""
    key = {"kind": "random_3d", "size_mm": [round(1e3 * float(v), 9) for v in vessel],
           "rmin_mm": round(1e3 * rmin, 9), "radius_ratio": float(radius_ratio),
           "seed": int(seed), "version": GENERATOR_VERSION_3D,
           "cloud_porosity": genesis.cloud_porosity, "pressure_mpa": genesis.pressure_mpa}
    return hashlib.sha1(json.dumps(key, sort_keys=True).encode()).hexdigest()[:16] + ".npz"


def vessel_floaters(specimen: Specimen3D) -> int:
    """Spheres of a cuboid specimen with fewer than 3 contacts in its vessel."""
    return int(np.count_nonzero(floaters(specimen.pos, specimen.radius, specimen.size_m)))
