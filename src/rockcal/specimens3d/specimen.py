"""3D specimens made by PFC's material genesis: a cuboid packed in a cuboid vessel, a cylinder
carved out of one (a cuboid packing of the cylinder's diameter squared by its height, the
spheres whose centres lie inside the cylinder kept, then those left without a bond dropped), or
a cylinder packed in a cylindrical vessel (`packed_cylinder`: the triaxial cell's, whose
surface is its vessel's wall).

As in 2D (`rockcal.specimens.specimen`), a specimen is geometry (centres, radii, bonded pairs) plus
one uniform draw per bond and strength, its grains balls or rigid clumps of pebbles (`clump_of`,
`grain_shape`: `clump_genesis`); packings are kept on disk in 2D's cache folder, under
a hash of what their genesis depends on, and the bonds of an installation gap are found on
loading.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, replace

import numpy as np

from rockcal.specimens.genesis import Genesis
from rockcal.specimens.grain_limit import check_grains
from rockcal.specimens.packing import check_packing_pressure
from rockcal.specimens.specimen import STRENGTH_STREAM, _one_maker, cache_dir
from rockcal.dem.clumps import members
from rockcal.dem3d.clumps import union_properties
from rockcal.materials.clump_templates import DEFAULT_SHAPE, template
from rockcal.specimens3d.clump_genesis import clump_bonds, clumps_for_spheres, settle_clumps
from rockcal.specimens3d.genesis import DEFAULT_GENESIS_3D, floaters, install_bonds, sphere_contacts
from rockcal.dem3d.neighbours import SpheresScattered, spatial_order
from rockcal.specimens3d.packing import pack_vessel
from rockcal.dem3d.vectors import cubes
from rockcal.errors import InputError, fields_named
from rockcal.output_files import atomic_path

GENERATOR_VERSION_3D = 8
CLUMP_GENESIS_VERSION_3D = 1  # part of a clumped packing's key: raise it when `clump_genesis` changes
SHAPES = ("cylinder", "cuboid")
ROUND = ("cylinder", "disk", "half_disk")  # pi/4 of their box: a half disk's is D x t x D/2


@dataclass(frozen=True)
class Specimen3D:
    """Sphere centres (m), radii (m) and bonded pairs (i < j); a `shape` of `size_m`: a
    cylinder (diameter, diameter, height) about the vertical line through its centre, a
    cuboid (x, y, z sides), standing on z = 0, a disk (diameter, thickness, diameter) about
    the horizontal line along y through its centre (`carve_disk`), or a half disk (diameter,
    thickness, radius), that disk's lower half standing on its flat side (`carve_half_disk`).
    bond_draws: each bond's uniform draws in [0, 1) for its tensile strength and cohesion."""

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
    clump_of: np.ndarray | None = None  # per sphere its clump (None: balls), `clump_genesis`
    grain_shape: str = DEFAULT_SHAPE
    dimensions = 3  # PFC3D's spheres: the one place a lab test, a report or a figure asks

    @property
    def n_spheres(self) -> int:
        return len(self.radius)

    @property
    def n_particles(self) -> int:  # the 2D specimen's name, read by the lab tests' runners
        return self.n_spheres

    @property
    def volume_m3(self) -> float:
        x, y, z = self.size_m
        return np.pi / 4 * x * y * z if self.shape in ROUND else x * y * z

    @property
    def n_grains(self) -> int:
        """Grains: clumps, or balls."""
        return self.n_spheres if self.clump_of is None else int(self.clump_of.max()) + 1

    @property
    def porosity(self) -> float:
        """1 - the grains' volume over the specimen's (a clump's, its pebbles' union)."""
        if self.clump_of is None:
            return 1.0 - float(4 / 3 * np.pi * cubes(self.radius).sum()) / self.volume_m3
        first, pebbles = members(self.clump_of)
        solid = sum(union_properties(self.pos[own], self.radius[own])[0]
                    for own in np.split(pebbles, first[1:-1]))
        return 1.0 - solid / self.volume_m3

    def bonds_per_sphere(self) -> float:
        return 2.0 * len(self.bonds) / self.n_spheres

    def coordination(self) -> float:
        """Sphere-sphere contacts per sphere."""
        return float(sphere_contacts(self.pos, self.radius).mean())

    def description(self) -> dict:
        """What a PFC user reports of a specimen, under the 2D specimen's names, and that it
        is of PFC3D's spheres."""
        return {"dimensions": 3, "n_particles": self.n_spheres, "porosity": self.porosity,
                "coordination": self.coordination(), "bonds_per_particle": self.bonds_per_sphere(),
                "floaters": self.floaters}


def random_specimen(shape: str, width_mm: float, height_mm: float, rmin_mm: float,
                    radius_ratio: float = 1.65, seed: int = 1, genesis: Genesis | None = None,
                    cache: bool = True, grain_shape: str = DEFAULT_SHAPE) -> Specimen3D:
    """A cylinder of diameter `width_mm` or a square prism of side `width_mm`, `height_mm`
    tall, made by the 3D genesis (default settings `DEFAULT_GENESIS_3D`) of balls or of clumps
    of `grain_shape` (`clump_genesis`); its packing kept on disk unless `cache` is False."""
    if shape not in SHAPES:
        raise InputError("shape", f"must be one of {', '.join(SHAPES)}, got {shape!r}")
    genesis = genesis or DEFAULT_GENESIS_3D
    check_size(width_mm, height_mm, rmin_mm, radius_ratio, genesis.cloud_porosity, genesis.pressure_mpa)
    prism = random_cuboid((width_mm, width_mm, height_mm), rmin_mm, radius_ratio, seed, genesis, cache,
                          grain_shape)
    clumped = "" if grain_shape == DEFAULT_SHAPE else f", {grain_shape} clumps"
    prism = replace(prism, label=f"{shape} {width_mm:g}x{height_mm:g} mm, Rmin {rmin_mm:g} mm "
                                 f"x{radius_ratio:g}, gap {genesis.install_gap:g} Rmin, seed {seed}{clumped}")
    return carve_cylinder(prism) if shape == "cylinder" else prism


# The fewest spheres a 3D packing's cloud may hold: 4 x 4 x 4, a specimen 4 spheres across
MIN_SPHERES = 64


def expected_spheres(width_mm: float, height_mm: float, rmin_mm: float, radius_ratio: float,
                     cloud_porosity: float) -> float:
    """The sphere cloud's count in the width x width x height cuboid a specimen is packed in
    (`cloud_spheres`)."""
    return cloud_spheres(width_mm**2 * height_mm, rmin_mm, radius_ratio, cloud_porosity)


def cloud_spheres(volume_mm3: float, rmin_mm: float, radius_ratio: float, cloud_porosity: float) -> float:
    """The sphere cloud's count in a vessel of `volume_mm3`: (1 - n_c) x volume / mean sphere
    volume (radii uniform in [R_min, ratio R_min]), a float so that no size overflows."""
    lo, hi = rmin_mm, radius_ratio * rmin_mm
    mean_cube = (hi**4 - lo**4) / (4 * (hi - lo)) if hi > lo else lo**3
    return (1 - cloud_porosity) * volume_mm3 / (4 / 3 * np.pi * mean_cube)


# The loosest cloud the 3D genesis packs: a solid fraction of 0.55, the random loose packing of
# spheres (Onoda & Liniger 1990, 0.555). The genesis drops the cloud's spheres at their own size
# (shrunk to jamming, never grown: `packing.pack_vessel`), so a looser cloud has no contact
# network to carry P_m; its floater rounds then grow single spheres far past R_max, and the
# packing goes unstable (spheres leave the vessel, the neighbour grid outgrows memory).
MAX_CLOUD_POROSITY_3D = 0.45
def check_size(width_mm: float, height_mm: float, rmin_mm: float, radius_ratio: float,
               cloud_porosity: float, pressure_mpa: float = 0.1) -> None:
    """Before the genesis of a width x width x height packing (a cylinder's, a prism's): as
    `check_vessel`."""
    check_vessel((width_mm, width_mm, height_mm), rmin_mm, radius_ratio, cloud_porosity, pressure_mpa)


def check_vessel(sides_mm, rmin_mm: float, radius_ratio: float, cloud_porosity: float,
                 pressure_mpa: float = 0.1) -> None:
    """Before the genesis of a cuboid packing of sides x, y, z `sides_mm`: the vessel at least
    4 of its largest spheres across each side, a cloud and pressure the genesis can pack
    (MAX_CLOUD_POROSITY_3D, `packing.MAX_PACKING_PRESSURE_MPA`), at least MIN_SPHERES spheres and within the
    grain limit (`specimens.grain_limit`, counted in spheres); an InputError naming the setting."""
    x, y, z = sides_mm
    for name, value in (("width_mm", x), ("thickness_mm", y), ("height_mm", z)):
        if not value >= 8 * rmin_mm * radius_ratio:
            raise InputError(name, f"{value:g} mm is too small for spheres of radius up to "
                             f"{rmin_mm * radius_ratio:g} mm (need at least 4 diameters)")
    check_genesis_3d(cloud_porosity, pressure_mpa)
    box = f"{x:g} x {y:g} x {z:g} mm"
    spheres = cloud_spheres(x * y * z, rmin_mm, radius_ratio, cloud_porosity)
    if spheres < MIN_SPHERES:
        raise InputError("cloud_porosity", f"a cloud porosity of {cloud_porosity:.10g} leaves about "
                                           f"{spheres:.3g} spheres in the {box} packing, fewer than "
                                           f"{MIN_SPHERES} (4 across): lower it, or make the specimen "
                                           "larger or R_min smaller")
    check_grains("rmin_mm", f"a {box} 3D packing of R_min {rmin_mm:g} mm (counted in spheres)", spheres)


def check_genesis_3d(cloud_porosity: float, pressure_mpa: float) -> None:
    """A cloud porosity and a material pressure the 3D genesis can pack; an InputError naming
    the setting."""
    if cloud_porosity > MAX_CLOUD_POROSITY_3D:
        raise InputError("cloud_porosity", f"{cloud_porosity:.10g} is looser than the 3D genesis can pack: "
                                           f"at most {MAX_CLOUD_POROSITY_3D:g} (a solid fraction of "
                                           f"{1 - MAX_CLOUD_POROSITY_3D:g}, spheres' random loose packing); "
                                           "FISHTank's 3D examples take 0.30-0.35")
    check_packing_pressure(pressure_mpa, "spheres")


def carve_cylinder(cuboid: Specimen3D) -> Specimen3D:
    """The spheres of a square prism whose centres lie inside its inscribed vertical cylinder,
    less those the cut leaves without a bond, with their bonds and draws (a clump's pebbles
    kept or dropped with its centroid: `_carved`). Centres, not whole
    spheres: the cut surface then lies on the cylinder on average, so that its nominal
    cross-section is the one that carries the load (keeping whole spheres only would lose a
    shell about a radius thick: a quarter of a 10 mm cylinder's section at R_min 0.6 mm)."""
    x, _, z = cuboid.size_m
    inside = np.hypot(cuboid.pos[:, 0] - x / 2, cuboid.pos[:, 1] - x / 2) <= x / 2
    return _carved(cuboid, inside, "cylinder", (x, x, z))


def packed_cylinder(width_mm: float, height_mm: float, rmin_mm: float, radius_ratio: float = 1.65,
                    seed: int = 1, genesis: Genesis | None = None, cache: bool = True) -> Specimen3D:
    """A cylinder of diameter `width_mm`, `height_mm` tall, packed by the 3D genesis in a
    cylindrical vessel of its size, as FISHTank's cylindrical material vessel packs it (its
    packing kept on disk unless `cache` is False). Its side is the vessel's smooth wall, which a
    triaxial cell's rigid wall bears on all round; a carved cylinder's side is rough by a
    sphere's radius, and a rigid wall holding sigma3 on it touches a few outermost spheres
    alone (4 of a 10 x 20 mm cylinder's 500), which confines it no more than no wall."""
    genesis = genesis or DEFAULT_GENESIS_3D
    check_size(width_mm, height_mm, rmin_mm, radius_ratio, genesis.cloud_porosity, genesis.pressure_mpa)
    return _packed("cylinder", (width_mm, width_mm, height_mm), rmin_mm, radius_ratio, seed, genesis, cache)


def random_cuboid(sides_mm, rmin_mm: float, radius_ratio: float = 1.65, seed: int = 1,
                  genesis: Genesis | None = None, cache: bool = True,
                  grain_shape: str = DEFAULT_SHAPE) -> Specimen3D:
    """A cuboid of sides x, y, z `sides_mm` packed by the 3D genesis (as `random_specimen`'s
    square prism, of any three sides: the Brazilian disk's block is D x t x D), of balls or of
    clumps of `grain_shape`; its packing kept on disk unless `cache` is False. The sides are
    checked by the caller."""
    return _packed("cuboid", sides_mm, rmin_mm, radius_ratio, seed, genesis or DEFAULT_GENESIS_3D, cache,
                   grain_shape)


def _packed(shape: str, sides_mm, rmin_mm: float, radius_ratio: float, seed: int, genesis: Genesis,
            cache: bool, grain_shape: str = DEFAULT_SHAPE) -> Specimen3D:
    """A cuboid of sides `sides_mm` (of balls or clumps of `grain_shape`), or the vertical
    cylinder of balls inscribed in it, packed in a vessel of its own shape and bonded."""
    vessel = np.asarray(sides_mm, float) * 1e-3
    pos, radius, pressure, left = packing(vessel, rmin_mm * 1e-3, radius_ratio, seed, genesis,
                                          cache, cylinder=shape == "cylinder")
    gap = genesis.install_gap * rmin_mm * 1e-3
    clump_of = None
    if grain_shape != DEFAULT_SHAPE:
        pos, radius, clump_of, pressure = clumped_packing(vessel, rmin_mm * 1e-3, radius_ratio, seed, genesis,
                                                          grain_shape, cache, pos, radius)
        bonds = clump_bonds(pos, radius, clump_of, gap)
    else:
        bonds = install_bonds(pos, radius, gap)
    label = (f"{shape} {'x'.join(f'{v:g}' for v in sides_mm)} mm, Rmin {rmin_mm:g} mm "
             f"x{radius_ratio:g}, gap {genesis.install_gap:g} Rmin, seed {seed}")
    draws = np.random.default_rng([seed, STRENGTH_STREAM]).random((len(bonds), 2))
    return Specimen3D(pos, radius, bonds, shape, tuple(vessel), label, draws, pressure, left,
                      rmin_mm, genesis.install_gap, clump_of, grain_shape)


def carve_disk(cuboid: Specimen3D) -> Specimen3D:
    """The disk of a D x t x D cuboid: its spheres whose centres lie inside the cylinder of
    diameter D about the horizontal line along y through the cuboid's centre (its axis; the
    disk's faces are the cuboid's y faces), less those the cut leaves without a bond, with
    their bonds and draws; centres, not whole spheres, as `carve_cylinder`."""
    d, t, _ = cuboid.size_m
    inside = np.hypot(cuboid.pos[:, 0] - d / 2, cuboid.pos[:, 2] - d / 2) <= d / 2
    return _carved(cuboid, inside, "disk", (d, t, d))


DISK_THICKNESS_PER_DIAMETER = 0.5  # a Brazilian disk's, ISRM (1978): t about D / 2


def check_disk(diameter_mm: float, thickness_mm: float, rmin_mm: float, radius_ratio: float) -> None:
    """Reject a disk its spheres cannot fill, naming the field: D and t at least 4 diameters
    of the largest sphere, as the cylinder (`random_specimen`)."""
    for name, value in (("diameter_mm", diameter_mm), ("thickness_mm", thickness_mm)):
        if not (np.isfinite(value) and value > 0):
            raise InputError(name, f"must be a finite number > 0, got {value}")
        if not value >= 8 * rmin_mm * radius_ratio:
            raise InputError(name, f"{value:g} mm is too small for spheres of radius up to "
                             f"{rmin_mm * radius_ratio:g} mm (need at least 4 diameters)")


def random_disk(diameter_mm: float = 20.0, thickness_mm: float | None = None, rmin_mm: float = 0.75,
                radius_ratio: float = 1.65, seed: int = 1, genesis: Genesis | None = None,
                cache: bool = True, grain_shape: str = DEFAULT_SHAPE) -> Specimen3D:
    """A disk of diameter `diameter_mm` and thickness `thickness_mm` (None: D / 2), its axis
    along y, carved from a D x t x D cuboid packed by the 3D genesis (`random_cuboid`, cached
    unless `cache` is False, of balls or clumps of `grain_shape`): a Brazilian disk."""
    if thickness_mm is None:
        thickness_mm = DISK_THICKNESS_PER_DIAMETER * diameter_mm
    check_disk(diameter_mm, thickness_mm, rmin_mm, radius_ratio)
    genesis = genesis or DEFAULT_GENESIS_3D
    with fields_named({"width_mm": "diameter_mm", "height_mm": "diameter_mm"}):
        check_vessel((diameter_mm, thickness_mm, diameter_mm), rmin_mm, radius_ratio, genesis.cloud_porosity,
                     genesis.pressure_mpa)
    cuboid = random_cuboid((diameter_mm, thickness_mm, diameter_mm), rmin_mm, radius_ratio, seed,
                           genesis, cache, grain_shape)
    disk = carve_disk(cuboid)
    return replace(disk, label=f"{cuboid.label}, disk D {diameter_mm:g} x t {thickness_mm:g} mm")


def carve_half_disk(cuboid: Specimen3D) -> Specimen3D:
    """The half disk of a D x t x D/2 cuboid: its spheres whose centres lie within D / 2 of
    the line along y through the middle of its bottom face (the disk's axis; its flat side
    on z = 0), less those the cut leaves without a bond; centres, as `carve_disk`."""
    d, t, _ = cuboid.size_m
    inside = np.hypot(cuboid.pos[:, 0] - d / 2, cuboid.pos[:, 2]) <= d / 2
    return _carved(cuboid, inside, "half_disk", (d, t, d / 2))


def notched(specimen: Specimen3D, middle_m: float, width_m: float, depth_m: float) -> Specimen3D:
    """The specimen with a straight-through notch (along y) up from its bottom face at x =
    `middle_m`, `width_m` wide and `depth_m` deep: the spheres that overlap it removed (and
    those left without a bond), as the 2D notch's disks; of width 0, a cut: the bonds that
    cross the plane x = `middle_m` below z = `depth_m` removed, every sphere kept."""
    pos, radius = specimen.pos, specimen.radius
    if width_m == 0:
        i, j = specimen.bonds.T
        dx_i, dx_j = pos[i, 0] - middle_m, pos[j, 0] - middle_m
        crosses = dx_i * dx_j < 0
        along = np.divide(dx_i, dx_i - dx_j, out=np.zeros(len(i)), where=crosses)
        kept = ~(crosses & (pos[i, 2] + along * (pos[j, 2] - pos[i, 2]) < depth_m))
        return replace(specimen, bonds=specimen.bonds[kept], bond_draws=specimen.bond_draws[kept])
    dx = np.maximum(np.abs(pos[:, 0] - middle_m) - width_m / 2, 0.0)
    dz = np.maximum(pos[:, 2] - depth_m, 0.0)
    return _carved(specimen, dx**2 + dz**2 >= radius**2, specimen.shape, specimen.size_m)


def _carved(cuboid: Specimen3D, inside: np.ndarray, shape: str, size_m) -> Specimen3D:
    """The spheres of `cuboid` `inside` the cut, less those it leaves without a bond (twice:
    a sphere may lose its last bond with the first ones), with their bonds and draws. A
    clump's pebbles go together: a clump is inside where the mean of its pebbles' `inside` is
    at least 1/2, kept where any of its pebbles keeps a bond."""
    grains = _whole_clumps(cuboid.clump_of)
    keep = grains(inside)
    bi, bj = cuboid.bonds.T
    for _ in range(2):
        bonded = np.zeros(cuboid.n_spheres, bool)
        bonded[cuboid.bonds[keep[bi] & keep[bj]].ravel()] = True
        keep &= grains(bonded)
    kept = keep[bi] & keep[bj]
    index = np.full(cuboid.n_spheres, -1)
    index[keep] = np.arange(np.count_nonzero(keep))
    clump_of = None
    if cuboid.clump_of is not None:  # the kept clumps renumbered 0.. in order
        clump_of = np.unique(cuboid.clump_of[keep], return_inverse=True)[1].astype(np.int64)
    return replace(cuboid, pos=cuboid.pos[keep].copy(), radius=cuboid.radius[keep].copy(),
                   bonds=index[cuboid.bonds[kept]], shape=shape, size_m=tuple(size_m),
                   bond_draws=cuboid.bond_draws[kept], clump_of=clump_of)


def _whole_clumps(clump_of):
    """A per-sphere mask made whole clump by clump: each pebble takes whether at least half its
    clump's pebbles are marked (balls: the mask itself)."""
    if clump_of is None:
        return lambda mask: mask.copy()
    counts = np.bincount(clump_of)
    return lambda mask: (2 * np.bincount(clump_of, mask.astype(float), len(counts)) >= counts)[clump_of]


def clumped_packing(vessel, rmin: float, radius_ratio: float, seed: int, genesis: Genesis, grain_shape: str,
                    cache: bool, pos, radius):
    """The balls' packing (`pos`, `radius`, of `packing`'s arguments) with clumps of `grain_shape`
    in place of its spheres, settled to the pressure (`clump_genesis`): pebble centres, radii,
    clump numbers and the pressure reached (MPa); from the cache, or made (and kept if `cache`)."""
    def make():
        shape = template(grain_shape, dimensions=3)
        centres, radii, clump_of = clumps_for_spheres(pos, radius, shape, seed)
        centres, radii, pressure = settle_clumps(centres, radii, clump_of, vessel, genesis.pressure_mpa)
        return centres, radii, clump_of, pressure

    if not cache:
        return make()
    path = cache_dir() / packing_name(vessel, rmin, radius_ratio, seed, genesis, grain_shape=grain_shape)
    if not path.exists():  # read without a lock: a cache may be read-only
        with _one_maker(path):
            if not path.exists():
                centres, radii, clump_of, pressure = make()
                with atomic_path(path) as tmp:
                    np.savez(tmp, pos=centres, radius=radii, clump_of=clump_of, pressure_mpa=pressure)
    data = np.load(path)
    return data["pos"], data["radius"], data["clump_of"], float(data["pressure_mpa"])


def packing(vessel, rmin: float, radius_ratio: float, seed: int, genesis: Genesis, cache: bool,
            cylinder: bool = False):
    """The packed vessel's (or the `cylinder` inscribed in it) centres and radii (m), pressure
    reached (MPa) and floaters left: from the cache, or made (and kept if `cache`)."""
    def make():
        try:
            return pack_vessel(vessel, rmin, radius_ratio, seed, genesis.cloud_porosity,
                               genesis.pressure_mpa, cylinder)
        except SpheresScattered as exc:
            raise InputError("cloud_porosity", f"the 3D genesis went unstable ({exc}): lower the cloud "
                                               "porosity or pressure_mpa") from None

    if not cache:
        return _ordered(*make())
    path = cache_dir() / packing_name(vessel, rmin, radius_ratio, seed, genesis, cylinder)
    if not path.exists():  # read without a lock: a cache may be read-only
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


def packing_name(vessel, rmin: float, radius_ratio: float, seed: int, genesis: Genesis,
                 cylinder: bool = False, grain_shape: str = DEFAULT_SHAPE) -> str:
    """The file a 3D packing is kept in: a hash of what its genesis depends on, as 2D's
    (`rockcal.specimens.specimen.packing_name`) with the vessel's three sides (and its shape
    where it is the `cylinder` inscribed in them); a clumped packing's with its grain shape
    (`clumped_packing`)."""
    clumped = {} if grain_shape == DEFAULT_SHAPE else {"grain_shape": grain_shape,
                                                       "clump_version": CLUMP_GENESIS_VERSION_3D}
    key = clumped | {"kind": "random_3d", "size_mm": [round(1e3 * float(v), 9) for v in vessel],
           "rmin_mm": round(1e3 * rmin, 9), "radius_ratio": float(radius_ratio),
           "seed": int(seed), "version": GENERATOR_VERSION_3D,
           "cloud_porosity": genesis.cloud_porosity, "pressure_mpa": genesis.pressure_mpa}
    if cylinder:  # a cuboid's key as it was before cylinders were packed
        key["vessel"] = "cylinder"
    return hashlib.sha1(json.dumps(key, sort_keys=True).encode()).hexdigest()[:16] + ".npz"


def vessel_floaters(specimen: Specimen3D) -> int:
    """Spheres of a cuboid specimen with fewer than 3 contacts in its vessel."""
    return int(np.count_nonzero(floaters(specimen.pos, specimen.radius, specimen.size_m)))
