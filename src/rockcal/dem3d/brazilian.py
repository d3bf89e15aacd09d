"""The Brazilian (diametral compression) test on a 3D disk, as the 2D test
(`rockcal.labtests.brazilian`): a short cylinder of diameter D and thickness t (t = D/2 by
default, ISRM's ratio) whose axis is horizontal, along y, loaded along z, its vertical
diameter, between two frictionless flat platens (`platens.Platens3D`: FISHTank's, `dc.fis`;
the default) or between the same platens with a bearing strip on each (ASTM D3967's cushion,
`loading="strips"`). FISHTank's `dc.fis` loads along y with the disk's axis along z; rockcal
keeps z the loading direction of all its platens, so the disk is that one turned about x.

The disk is carved from a D x t x D cuboid packing (`specimen.random_cuboid`,
`specimen.carve_disk`: the spheres whose centres lie inside the cylinder, as the UCS cylinder
is carved), so that its cut surface lies on the nominal cylinder on average; D and t are the
nominal ones, the platens start touching the outermost spheres.

The loading is the 2D test's: the platens close at the UCS test's quasi-static speed
(`Platens3D`; no density scaling, as the 2D Brazilian test), ramped in, at the slowest speed
from the first broken bond on and at full speed again once the load has fallen below
`loading.PAST_PEAK_FRACTION` of the peak; the flat platens' test stops once the load has
fallen below the 2D test's POST_PEAK_FRACTION of the peak with the platens closed by one more
mean sphere radius since the peak, the strips' at the first fall below PAST_PEAK_FRACTION that
left a crack across the disk's middle (`broken_through`). Reading: sigma_t = 2 P / (pi D t) at
the peak load P (N); `split`: the bonds broken by just after the peak make a crack through
the centre (`central_split`: the 2D rule in the plane of the loaded diameter and the axis).

A bearing strip (`rockcal.labtests.rig.BearingStrip`, the 2D defaults: 1 GPa plywood 0.01 D
thick) under a sphere of radius R is a column of its cross-section pi R^2, stiffness
E_strip pi R^2 / thickness, in series with the bare platen's contact pi E_c R. The engine's
walls have one modulus per wall (a sphere's contact pi E R), so the strip's contact is the
series stiffness at the specimen's mean radius, as the 2D platens take it at the mean
diameter (`strip_modulus_pa`).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np

from rockcal.dem.genesis import Genesis
from rockcal.dem3d.laws import BROKEN_SHEAR, BROKEN_TENSION, INTACT
from rockcal.dem3d.material import wall_modulus_pa
from rockcal.dem3d.platens import BOTTOM, TOP, Platens3D
from rockcal.dem3d.simulate import advance
from rockcal.dem3d.specimen import Specimen3D, carve_disk, random_cuboid
from rockcal.dem3d.ucs import cracks_of
from rockcal.errors import InputError
from rockcal.labtests.brazilian import (
    DEFAULT_MAX_STRAIN,
    END_SLICES,
    POST_PEAK_FRACTION,
    SLICES,
    SPLIT_SHARE,
    STRIP_MODULUS_GPA,
    STRIP_THICKNESS_PER_DIAMETER,
    split_through_centre,
)
from rockcal.labtests.loading import (
    LOCALISED_DAMAGE,
    PAST_PEAK_FRACTION,
    RAMP_STEPS_PER_ROW,
    Loading,
    check_max_strain,
)
from rockcal.labtests.rig import BearingStrip
from rockcal.materials import as_params

LOADINGS_3D = ("flat", "strips")  # ISRM's curved jaws are not built in 3D yet
DEFAULT_THICKNESS_PER_DIAMETER = 0.5  # ISRM (1978): t about D / 2
CURVE_COLUMNS = ("displacement_mm", "load_kN", "broken_bonds", "bottom_load_kN", "top_load_kN")


@dataclass
class Brazilian3DResult:
    """Responses of a 3D Brazilian test and its curve (columns `CURVE_COLUMNS`: the platens'
    closure, the mean of their two loads, the bonds broken so far and each platen's load; a
    first row of zeros for the unloaded disk)."""

    sigma_t_MPa: float
    P_max_kN: float
    displacement_at_peak_mm: float
    diameter_mm: float
    thickness_mm: float
    loading: str
    split: float  # 1.0: the disk split through its centre; 0.0: crushed at a contact or split off it
    peak_cracks: dict = field(repr=False)  # positions (m) of the bonds broken by just after the peak, by mode
    curve: np.ndarray = field(repr=False)
    n_spheres: int
    n_bonds: int
    n_broken_tension: int
    n_broken_shear: int
    steps: int
    wall_s: float
    positions: np.ndarray = field(default=None, repr=False)  # the spheres' at the end, m
    cracks: dict = field(default_factory=dict, repr=False)  # every bond broken by the end, by mode


def tensile_strength_MPa(load_N: float, diameter_m: float, thickness_m: float) -> float:
    """The Brazilian tensile strength sigma_t = 2 P / (pi D t) (ISRM 1978; ASTM D3967), MPa."""
    return 2.0 * load_N / (np.pi * diameter_m * thickness_m) / 1e6


def check_disk_3d(diameter_mm: float, thickness_mm: float, rmin_mm: float,
                  radius_ratio: float) -> None:
    """Reject a disk its spheres cannot fill, naming the field: D and t at least 4 diameters
    of the largest sphere, as the 3D cylinder (`specimen.random_specimen`)."""
    for name, value in (("diameter_mm", diameter_mm), ("thickness_mm", thickness_mm)):
        if not (np.isfinite(value) and value > 0):
            raise InputError(name, f"must be a finite number > 0, got {value}")
        if not value >= 8 * rmin_mm * radius_ratio:
            raise InputError(name, f"{value:g} mm is too small for spheres of radius up to "
                             f"{rmin_mm * radius_ratio:g} mm (need at least 4 diameters)")


def brazilian_disk_3d(diameter_mm: float = 20.0, thickness_mm: float | None = None,
                      rmin_mm: float = 0.75, radius_ratio: float = 1.65, seed: int = 1,
                      genesis: Genesis | None = None, cache: bool = True) -> Specimen3D:
    """A disk of diameter `diameter_mm` and thickness `thickness_mm` (None: D / 2), its axis
    along y, carved from a D x t x D cuboid packed by the 3D genesis (`random_cuboid`, cached
    unless `cache` is False)."""
    if thickness_mm is None:
        thickness_mm = DEFAULT_THICKNESS_PER_DIAMETER * diameter_mm
    check_disk_3d(diameter_mm, thickness_mm, rmin_mm, radius_ratio)
    cuboid = random_cuboid((diameter_mm, thickness_mm, diameter_mm), rmin_mm, radius_ratio, seed,
                           genesis, cache)
    disk = carve_disk(cuboid)
    return replace(disk, label=f"{cuboid.label}, disk D {diameter_mm:g} x t {thickness_mm:g} mm")


def strip_modulus_pa(strip: BearingStrip, bare_modulus_pa: float, radius_m: float) -> float:
    """The platen's contact modulus with a bearing `strip` on it: E such that a sphere of
    `radius_m`'s contact pi E R is its strip column (E_strip pi R^2 / thickness) in series
    with the bare platen's contact (pi `bare_modulus_pa` R), Pa."""
    column = 1e9 * strip.modulus_GPa * np.pi * radius_m**2 / (1e-3 * strip.thickness_mm)
    bare = np.pi * bare_modulus_pa * radius_m
    return float(1.0 / (1.0 / column + 1.0 / bare) / (np.pi * radius_m))


def disk_centre(specimen: Specimen3D) -> tuple[float, float]:
    """The centre of the disk's outline in the loaded plane (x, z): the middle of its
    spheres' extent each way, m."""
    pos, radius = specimen.pos, specimen.radius
    return tuple(float(0.5 * ((pos[:, a] - radius).min() + (pos[:, a] + radius).max()))
                 for a in (0, 2))


def crack_share(crack_xyz: np.ndarray, centre, diameter: float, thickness: float,
                grain_m: float) -> float:
    """The share of the middle slices of the loaded (vertical, z) diameter (of the SLICES
    slices it is cut into, all but END_SLICES at each contact) that a crack crosses: where at
    least half as many bonds broke (at `crack_xyz`, m) as grains of `grain_m` fit in the
    slice's patch of the crack plane, (D / SLICES) x t: the 2D rule (half the grains along the
    slice) over the disk's thickness. On a disk of `diameter` and `thickness` (m) whose
    outline is centred at `centre` (x, z). Isolated breaks do not make a crack."""
    z = (np.asarray(crack_xyz)[:, 2] - centre[1]) / diameter  # in diameters from the centre
    counts = np.bincount(np.clip(np.floor((z + 0.5) * SLICES), 0, SLICES - 1).astype(int),
                         minlength=SLICES)[END_SLICES:SLICES - END_SLICES]
    grains = (diameter / SLICES / grain_m) * (thickness / grain_m)
    return float(np.mean(counts >= max(1.0, 0.5 * grains)))


def central_split(crack_xyz: np.ndarray, centre, diameter: float, thickness: float,
                  grain_m: float) -> bool:
    """Whether the bonds broken at `crack_xyz` split the disk through its centre, the 2D rule
    (`rockcal.labtests.brazilian.split_through_centre`) with the band a slab about the plane of the
    loaded diameter and the axis (x = the centre's x): a crack within CENTRAL_BAND x D plus a
    grain of it crosses SPLIT_SHARE of the middle or more, and no crack crosses it with its
    part beyond twice that (the side of a wedge a crushed contact drives)."""
    return split_through_centre(
        np.asarray(crack_xyz, float).reshape(-1, 3), centre[0], diameter, grain_m,
        lambda where: crack_share(where, centre, diameter, thickness, grain_m))


def broken_through(crack_xyz: np.ndarray, centre, diameter: float, thickness: float,
                   grain_m: float) -> bool:
    """Whether the bonds broken at `crack_xyz` cross SPLIT_SHARE of the loaded diameter's
    middle or more, anywhere across the disk: more than a crush at the contacts."""
    return crack_share(np.asarray(crack_xyz, float).reshape(-1, 3), centre, diameter, thickness,
                       grain_m) >= SPLIT_SHARE


def simulate_brazilian_3d(params, specimen: Specimen3D, *, loading: str = "flat",
                          rate_factor: float = 1.0, max_strain: float = DEFAULT_MAX_STRAIN,
                          strip_modulus_GPa: float = STRIP_MODULUS_GPA,
                          strip_thickness_mm: float | None = None,
                          progress: Callable[[float, float], None] | None = None,
                          ) -> Brazilian3DResult:
    """Run the Brazilian test on the 3D disk `specimen` (`brazilian_disk_3d`) of the material
    `params` (2D's MicroParams or a dict of their names, `material`).

    loading: "flat" or "strips" (a bearing strip of `strip_modulus_GPa` and
    `strip_thickness_mm`, None: STRIP_THICKNESS_PER_DIAMETER x D, on each platen);
    max_strain: the platens' closure / D at which the test stops at the latest;
    progress(closure_mm, load_kN) is called as the test goes.
    """
    started = time.perf_counter()
    params = as_params(params)
    if loading not in LOADINGS_3D:
        raise InputError("loading", f"must be one of {', '.join(LOADINGS_3D)} in 3D, got {loading!r}")
    check_max_strain(max_strain)
    if specimen.shape != "disk":
        raise InputError("specimen", f"the Brazilian test needs a disk, got a {specimen.shape}")
    diameter, thickness, _ = specimen.size_m
    modulus, squeeze = wall_modulus_pa(params), 0.0  # squeeze: how far the strips may close in
    if loading == "strips":
        strip = BearingStrip(strip_modulus_GPa, strip_thickness_mm if strip_thickness_mm is not None
                             else 1e3 * STRIP_THICKNESS_PER_DIAMETER * diameter)
        modulus = strip_modulus_pa(strip, modulus, float(specimen.radius.mean()))
        squeeze = 2e-3 * strip.thickness_mm
    platens = Platens3D(specimen, params, rate_factor, modulus)
    state = platens.state
    centre, grain = disk_centre(specimen), 2 * float(specimen.radius.mean())
    peak, after_peak = 0.0, None  # the largest load so far; the bonds' state just after it

    def cracks_now() -> np.ndarray:
        return state.bonds.break_xyz[state.bonds.state != INTACT]

    def failed(load: float, closure: float) -> bool:
        if loading != "flat":  # as a lab, at the first fall that broke the disk: the strips
            # would load its pieces on; a fall from a crush at a contact is the disk seating
            return (schedule.fallen_below(PAST_PEAK_FRACTION, load)
                    and broken_through(cracks_now(), centre, diameter, thickness, grain))
        return (schedule.fallen_below(POST_PEAK_FRACTION, load) and state.n_broken() > 0
                and closure > schedule.peak_travel + specimen.radius.mean())

    schedule = Loading(RAMP_STEPS_PER_ROW * platens.rows, LOCALISED_DAMAGE)
    rows = [(0.0,) * len(CURVE_COLUMNS)]
    while True:  # `loading.load_to_failure`'s loop, with full speed past the peak, on the 3D engine
        platens.move(schedule.speed(state.step, state.n_broken(), platens.chunk, schedule.peak_known))
        advance(state, platens.chunk)
        closure, load = platens.closure_m(), platens.load()
        if load > peak:
            peak, after_peak = load, None
        elif after_peak is None and load < PAST_PEAK_FRACTION * peak:
            after_peak = state.bonds.state.copy()
        each = state.walls.normal_force()
        rows.append((1e3 * closure, load / 1e3, state.n_broken(), each[BOTTOM] / 1e3, each[TOP] / 1e3))
        schedule.update(state.step, load, closure)
        if not schedule.peak_known:
            schedule.peak_known = (schedule.fallen_below(PAST_PEAK_FRACTION, load)
                                   and state.n_broken() > 0)
        if progress:
            progress(1e3 * closure, load / 1e3)
        if failed(load, closure) or closure >= max_strain * diameter + squeeze:
            break
    curve = np.array(rows, float)
    k = int(np.argmax(curve[:, 1]))
    P_max = 1e3 * curve[k, 1]
    if loading != "flat" or after_peak is None:  # the strips stop just after the peak
        after_peak = state.bonds.state
    where = state.bonds.break_xyz
    cracks = {"tension": where[after_peak == BROKEN_TENSION].copy(),
              "shear": where[after_peak == BROKEN_SHEAR].copy()}
    split = central_split(np.vstack(list(cracks.values())), centre, diameter, thickness, grain)
    return Brazilian3DResult(
        sigma_t_MPa=tensile_strength_MPa(P_max, diameter, thickness), P_max_kN=P_max / 1e3,
        displacement_at_peak_mm=float(curve[k, 0]), diameter_mm=1e3 * diameter,
        thickness_mm=1e3 * thickness, loading=loading, split=float(split), peak_cracks=cracks,
        curve=curve, n_spheres=specimen.n_spheres, n_bonds=len(specimen.bonds),
        n_broken_tension=state.n_broken(BROKEN_TENSION),
        n_broken_shear=state.n_broken(BROKEN_SHEAR), steps=state.step,
        wall_s=time.perf_counter() - started,
        positions=state.spheres.pos[:specimen.n_spheres].copy(), cracks=cracks_of(state.bonds))
