"""Making specimens: a random packing by PFC's material genesis, or a regular hexagonal one.

A specimen is geometry (centres, radii, bonded pairs) and one uniform draw per bond and
strength that fixes, with the micro-parameters that come later, each bond's strengths; so one
specimen serves every forward run of a calibration. Random packings are cached on disk by
(geometry, resolution, cloud porosity, pressure, seed, generator version), and rockcal ships
the packings of its embedded campaigns; the bonds of an installation gap are found on loading.
A random packing's grains are balls or rigid clumps of a template's pebbles (`grain_shape`,
`clump_templates`; `clump_genesis`), its key naming the shape only when it is not a ball.
"""

from __future__ import annotations

import hashlib
import json
import os
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rockcal.materials.flat_joint import flatjoint_draws
from rockcal.specimens.clump_genesis import CLUMP_GENESIS_VERSION, clump_bonds, floating_clumps, pack_clumps
from rockcal.materials.clump_templates import DEFAULT_SHAPE, template
from rockcal.dem.clumps import clump_properties, members
from rockcal.dem.neighbours import CONTACT_GAP, install_bonds, pair_gaps
from rockcal.specimens.genesis import Genesis, floaters, grain_contacts
from rockcal.specimens.grain_limit import check_grains, expected_grains
from rockcal.dem.neighbours import spatial_order
from rockcal.specimens.packing import pack_box
from rockcal.output_files import atomic_path
from rockcal.errors import InputError

try:
    import fcntl
except ImportError:  # Windows
    fcntl = None

GENERATOR_VERSION = 6
STRENGTH_STREAM = 1  # the bond strength draws' random stream, apart from the packing's
# The packings of the embedded campaigns (the granite and its quick look), exactly as genesis
# makes them, shipped so that a first run need not make them (a full-size beam's genesis takes
# half an hour to over an hour on one core); `benchmarks/shipped_specimens.py` makes and checks them.
SHIPPED_DIR = Path(__file__).with_name("shipped")


@dataclass(frozen=True)
class Specimen:
    """Disk centres (m), radii (m) and bonded pairs (i < j) in a width x height box (m);
    bond_draws holds each bond's uniform draws in [0, 1) for its tensile strength and cohesion;
    the pairs are a flat-jointed material's flat joints too. A clumped specimen's particles
    are the pebbles of rigid clumps (`clump_of`: each pebble's clump; None: every particle a
    ball), its grains the clumps."""

    pos: np.ndarray
    radius: np.ndarray
    bonds: np.ndarray
    width_m: float
    height_m: float
    label: str
    bond_draws: np.ndarray | None = None  # None: every bond at the mean strengths
    pressure_mpa: float = float("nan")  # mean wall stress at the end of packing
    floaters: int = 0  # grains the genesis left with fewer than 3 contacts (its rounds ran out)
    # a flat-jointed material's uniform draws per bonded pair (`materials.flat_joint.flatjoint_draws`);
    # None: those of seed 1
    joint_draws: np.ndarray | None = None
    clump_of: np.ndarray | None = None  # per particle its clump (`clumps.members`); None: balls
    dimensions = 2  # PFC2D's disks: the one place a lab test, a report or a figure asks

    @property
    def n_particles(self) -> int:
        return len(self.radius)

    @property
    def n_grains(self) -> int:
        """Grains: clumps, or balls."""
        return self.n_particles if self.clump_of is None else int(self.clump_of.max()) + 1

    @property
    def porosity(self) -> float:
        if self.clump_of is None:
            return 1.0 - float(np.pi * (self.radius**2).sum()) / (self.width_m * self.height_m)
        area = clump_properties(self.pos, self.radius, *members(self.clump_of))[0]
        return 1.0 - float(area.sum()) / (self.width_m * self.height_m)

    def coordination(self) -> float:
        """Grain-grain contacts per grain (of clumps: contacts between pebbles of different
        clumps, per clump, as PFC counts a clump's contacts)."""
        if self.clump_of is None:
            return float(grain_contacts(self.pos, self.radius).mean())
        pi, pj, _ = pair_gaps(self.pos, self.radius, CONTACT_GAP * self.radius.min())
        return 2.0 * np.count_nonzero(self.clump_of[pi] != self.clump_of[pj]) / self.n_grains

    def bonds_per_particle(self) -> float:
        return 2.0 * len(self.bonds) / self.n_particles

    def description(self) -> dict:
        """What a PFC user reports of a specimen."""
        return {"n_particles": self.n_particles, "porosity": self.porosity,
                "coordination": self.coordination(), "bonds_per_particle": self.bonds_per_particle(),
                "floaters": self.floaters}


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


def hexagonal(width_mm: float, height_mm: float, radius_mm: float, limited: bool = True) -> Specimen:
    """Equal disks on a triangular lattice, rows along x, every touching pair bonded; held to
    the grain limit unless not `limited` (rockcal's own lattices, not a user's specimen)."""
    check_geometry(width_mm, height_mm, radius_mm, 1.0)
    if limited:
        check_grains("specimen", f"a hexagonal {width_mm:g} x {height_mm:g} mm specimen of R {radius_mm:g} mm",
                     width_mm * height_mm / (2 * np.sqrt(3) * radius_mm**2))
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
    return Specimen(pos, radius, install_bonds(pos, radius, 0.0), 2 * r * len(pos) / rows,
                    rows * np.sqrt(3) * r,
                    f"hexagonal {width_mm:g}x{height_mm:g} mm, R {radius_mm:g} mm")


def random_packing(width_mm: float, height_mm: float, rmin_mm: float = 0.25,
                   radius_ratio: float = 1.65, seed: int = 1, genesis: Genesis | None = None,
                   cache: bool = True, grain_shape: str = DEFAULT_SHAPE) -> Specimen:
    """A specimen made by PFC's material genesis (`rockcal.specimens.genesis`); kept on disk (found
    in the cache, or among the packings shipped with rockcal) unless `cache` is False. Its
    grains are balls, or clumps of the template `grain_shape` (`clump_templates.GRAIN_SHAPES`)
    sized by their equivalent radii (`clump_genesis`)."""
    check_geometry(width_mm, height_mm, rmin_mm, radius_ratio)
    if isinstance(seed, bool) or int(seed) != seed or seed < 0:
        raise InputError("seed", f"must be a whole number >= 0, got {seed}")
    shape = template(grain_shape)
    genesis = genesis or Genesis()
    name = packing_name(width_mm, height_mm, rmin_mm, radius_ratio, seed, genesis, grain_shape)
    label = (f"random {width_mm:g}x{height_mm:g} mm, Rmin {rmin_mm:g} mm x{radius_ratio:g}, "
             f"gap {genesis.install_gap:g} Rmin, seed {seed}")
    if grain_shape != DEFAULT_SHAPE:
        label += f", {grain_shape} clumps"
    found = stored_packing(name) if cache else None
    if found is None and cache:
        with _one_maker(cache_dir() / name):
            found = stored_packing(name)  # made meanwhile by another process
            if found is None:
                found = _save(cache_dir() / name, *_pack(width_mm, height_mm, rmin_mm,
                                                         radius_ratio, seed, genesis, label, shape))
    if found is None:
        pos, radius, pressure, clump_of = _pack(width_mm, height_mm, rmin_mm, radius_ratio, seed,
                                                genesis, label, shape)
    else:
        data = np.load(found)
        pos, radius, pressure = data["pos"], data["radius"], float(data["pressure_mpa"])
        clump_of = data["clump_of"] if "clump_of" in data else None
    gap, width, height = genesis.install_gap * rmin_mm * 1e-3, width_mm * 1e-3, height_mm * 1e-3
    if clump_of is None:
        bonds = install_bonds(pos, radius, gap)
        left = np.count_nonzero(floaters(pos, radius, width, height))
    else:
        bonds = clump_bonds(pos, radius, clump_of, gap)
        left = np.count_nonzero(floating_clumps(pos, radius, clump_of, width, height))
    draws = np.random.default_rng([seed, STRENGTH_STREAM]).random((len(bonds), 2))
    return Specimen(pos, radius, bonds, width, height, label, draws, pressure,
                    int(left), flatjoint_draws(len(bonds), seed), clump_of)


def _pack(width_mm, height_mm, rmin_mm, radius_ratio, seed, genesis, label, shape):
    """Genesis of the grains: centres in spatial order, radii, the final pressure in MPa and
    (clumps) each pebble's clump, else None."""
    check_grains("specimen", f"a {label}",
                 expected_grains(width_mm, height_mm, rmin_mm, radius_ratio, genesis.cloud_porosity))
    box = (width_mm * 1e-3, height_mm * 1e-3, rmin_mm * 1e-3, radius_ratio, seed,
           genesis.cloud_porosity, genesis.pressure_mpa)
    if shape.name != DEFAULT_SHAPE:
        return pack_clumps(shape, *box)
    pos, radius, pressure = pack_box(*box)
    order = spatial_order(pos, 4 * radius_ratio * rmin_mm * 1e-3)
    return pos[order], radius[order], pressure, None


def _save(path: Path, pos, radius, pressure, clump_of=None) -> Path:
    with atomic_path(path) as tmp:  # whole or not at all; a killed write's file is cleaned later
        if clump_of is None:
            np.savez(tmp, pos=pos, radius=radius, pressure_mpa=pressure)
        else:
            np.savez(tmp, pos=pos, radius=radius, pressure_mpa=pressure, clump_of=clump_of)
    return path


@contextmanager
def _one_maker(path: Path):
    """One process at a time makes the packing at `path`: another that needs it waits, then
    finds it made (an advisory lock on a file beside it; none where there is no flock)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    if fcntl is None:
        yield
        return
    fd = os.open(path.with_suffix(".lock"), os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)


def packing_name(width_mm: float, height_mm: float, rmin_mm: float, radius_ratio: float,
                 seed: int, genesis: Genesis, grain_shape: str = DEFAULT_SHAPE) -> str:
    """The file a random packing is kept in: a hash of what its genesis depends on (the
    installation gap only places bonds, which are found on loading); the grain shape named
    only when not a ball, so that ball packings keep the names they had before clumps."""
    key = dict(kind="random", width_mm=float(width_mm), height_mm=float(height_mm),  # 50 and 50.0: one key
               rmin_mm=float(rmin_mm), radius_ratio=float(radius_ratio), seed=int(seed), version=GENERATOR_VERSION,
               cloud_porosity=genesis.cloud_porosity, pressure_mpa=genesis.pressure_mpa)
    if grain_shape != DEFAULT_SHAPE:  # the template's pebbles too: a changed template, new packings
        shape = template(grain_shape)
        key |= dict(grain_shape=grain_shape, pebble_offsets=shape.offsets.ravel().tolist(),
                    pebble_radii=shape.radii.tolist(), clump_genesis=CLUMP_GENESIS_VERSION)
    return hashlib.sha1(json.dumps(key, sort_keys=True).encode()).hexdigest()[:16] + ".npz"


def stored_packing(name: str) -> Path | None:
    """The packing file of that name in the cache, else among those shipped with rockcal
    (SHIPPED_DIR); None if it must be made."""
    for folder in (cache_dir(), SHIPPED_DIR):
        if (folder / name).exists():
            return folder / name
    return None


def cache_dir() -> Path:
    """Where specimens are kept: $ROCKCAL_CACHE, else ~/.cache/rockcal/specimens."""
    root = os.environ.get("ROCKCAL_CACHE")
    return Path(root) if root else Path.home() / ".cache" / "rockcal" / "specimens"
