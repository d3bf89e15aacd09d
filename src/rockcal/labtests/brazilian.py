"""Virtual Brazilian (splitting tensile) test: a disk between two frictionless flat platens
(FISHTank's; the default), between the same platens with a bearing strip on each (ASTM D3967's
cushion, `loading="strips"`) or between ISRM's curved jaws (`rig.Jaws`, `loading="isrm"`).

The disk is carved from a square packing; the platens are the UCS test's
(`rockcal.labtests.rig`), closing at the same quasi-static speed (slower where bonds break,
full speed again past the peak; the test stops when the load has fallen below
POST_PEAK_FRACTION of the peak, as in the bending test: a bond breaking under a platen drops the
load for a while without splitting the disk). The jaws close at the same speed; their test, and
the strips', stops as a lab's at the first fall below loading.PAST_PEAK_FRACTION of the peak that
left a crack across the disk's middle (`broken_through`): the jaws and the strips hold the
pieces and would load them on.
Tensile strength sigma_t = 2 P / (pi D t) (ISRM 1978; ASTM D3967) with P the peak load (in 2D
per metre of the slab's unit thickness t); `split` says whether the disk split through its
centre (`central_split`) or not (crushed at a contact, or split off the centre).

The test is one procedure in 2D and 3D, over the rig of the disk's dimension (`rig.rig_for`):
with the setting `dimensions` 3 (PFC3D) the disk is D thick D / 2 (ISRM's ratio), its axis
horizontal along y, loaded along z between the flat platens, the strips or the curved jaws
(drawn out along its axis: `rig.jaws_3d`), carved from a D x t x D cuboid packing
(`specimens3d.specimen.random_disk`);
its load is the platens' force, reported in kN (P_max_kN; 2D's in kN per metre of thickness,
P_max_kN_per_m), and a crack counts over the disk's thickness (`crack_share`).

What the loading decides: a bare platen or jaw first bears on the one to three grains of the
rim that stand out (the rim is rough by a grain, far more than the contacts' overlap), so the
disk may fail at a contact before its centre splits. A bearing strip spreads the load over
many rim grains, as the cushion does in the lab.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from pydantic import Field

from rockcal.dem import measure
from rockcal.specimens.carving import grains, inside_circle, keep_particles, of_particles
from rockcal.materials.clump_templates import DEFAULT_SHAPE
from rockcal.specimens.genesis import Genesis
from rockcal.dem.laws import INTACT
from rockcal.specimens.specimen import Specimen, check_geometry, random_packing
from rockcal.specimens3d.specimen import check_disk as check_disk_3d
from rockcal.specimens3d.specimen import DISK_THICKNESS_PER_DIAMETER, check_vessel, random_disk
from rockcal.errors import InputError, fields_named
from rockcal.labtests.kind import (
    GENESIS,
    LabTest,
    Outline,
    Response,
    check_3d_settings,
    check_grain_cloud,
    genesis_of,
    in_3d,
    load_reading,
)
from rockcal.labtests.lab_values import LabValues
from rockcal.labtests.loading import (
    LOCALISED_DAMAGE,
    PAST_PEAK_FRACTION,
    RAMP_STEPS_PER_ROW,
    Loading,
    Reading,
    check_max_strain,
    load_to_failure,
)
from rockcal.labtests.result import LabResult, run_fields
from rockcal.labtests.rig import BearingStrip, Disk, rig_for
from rockcal.materials import BondedParams, as_params

DEFAULT_MAX_STRAIN = 0.02  # platen closure / diameter at which the test stops at the latest
# A platen first bears on one or two particles; when their bonds break the load drops and comes
# back. The disk counts as split only once the load has fallen below POST_PEAK_FRACTION of the
# peak (as in the bending test) with the platens closed by one more mean particle radius since.
POST_PEAK_FRACTION = 0.3
# The failure mode, read on the bonds broken by just after the peak (the first reading below
# loading.PAST_PEAK_FRACTION of it; where the jaws' test stops). A crack crosses a slice of the
# loaded diameter where at least half as many bonds broke in it as grains fit along it. On the
# full-size granite disks (benchmarks/brazilian_jaws.py: D 50 and 100 mm, packings 1-3) a
# central split leaves a crack within 0.1 D of the loaded diameter across most of its middle
# (D 50, flat, packing 2: all of it at once; packing 1: from the top contact, five sixths of
# it), at times two cracks up to 0.15 D apart (D 50 with a compliant platen contact); a crush
# leaves a fan of broken bonds within 0.1 D of a contact (D 50, flat, packing 3), or drives a
# wedge whose side cracks cross the middle 0.2-0.4 D off the diameter (D 50, jaws, packing 3;
# D 100, flat, packing 3); a load line off the centre (jaws first touching the grain-rough rim
# 12 degrees off the diameter: D 50, packings 1, 2) splits the disk along a chord 0.1-0.2 D
# off it, with no crack in the band. The runs lie far from the lines drawn: a crack in the band
# crosses 0.83-1 of the middle or at most a third of it, a side crack 0.83-1 or at most 0.17.
# So the middle is what lies more than 0.2 D from both contacts; a split is a crack in the band
# across half of it or more, and no crack across half of it beyond twice the band.
CENTRAL_BAND = 0.1  # the band's half-width, x D (plus a grain: a crack's path is known to one)
SLICES = 10  # of the loaded diameter, each D / 10 long
END_SLICES = 2  # at each contact: its crushed zone
SPLIT_SHARE = 0.5  # of the middle slices a crack crosses
CRACK_LINK = 1.5  # grains: broken bonds nearer each other are one crack
# the UCS test's flat platens; ISRM's curved jaws; the flat platens with a bearing strip on each
LOADINGS = ("flat", "isrm", "strips")
DEFAULT_LOADING = "flat"
# The bearing strip: thin plywood, ASTM D3967's cushion, about 0.01 D thick. Through its
# thickness a rotary-cut veneer is loaded along the wood's radial direction: E_R = 0.078 x
# E_L 13.9 GPa = 1.08 GPa for yellow birch, 0.068 x 13.4 = 0.91 GPa for Douglas-fir (USDA
# Wood Handbook, FPL-GTR-190, 2010: Tables 5-1 and 5-3a, 12 % moisture); 1 GPa. In PFC terms it
# sets the wall-ball contacts' kn (`rig.BearingStrip`): under the granite's 0.64 mm grains on a
# 50 mm disk the strip's column is 1.27 GN/m per m, 1.24 in series with the bare platen's
# 2 t E_c (43.3), 17 times softer than a grain-grain contact (t E_c, PFC 3.x/4.0's).
STRIP_MODULUS_GPA = 1.0
# The softest strip: a cardboard cushion (ISRM 1978's), about 10 MPa through its thickness.
# Softer, the strip would be squeezed past its own thickness well before a rock's disk splits
# (contact stresses of tens of MPa), and sigma_t would read the strip, not the rock.
MIN_STRIP_MODULUS_GPA = 0.01
STRIP_THICKNESS_PER_DIAMETER = 0.01


@dataclass
class BrazilianResult(LabResult):
    """Responses of a Brazilian test, 2D or 3D (`BrazilianResult2D`, `BrazilianResult3D` add the
    peak load); its curve's columns: platen closure mm, load (kN per m of thickness in 2D, kN in 3D)."""

    sigma_t_MPa: float
    displacement_at_peak_mm: float
    diameter_mm: float
    split: float  # 1.0: the disk split through its centre; 0.0: crushed at a contact or split off it
    peak_cracks: dict = field(repr=False)  # the bonds broken by just after the peak, by mode


@dataclass
class BrazilianResult2D(BrazilianResult):
    """A 2D disk's: its peak load per metre of the slab's unit thickness."""

    P_max_kN_per_m: float


@dataclass
class BrazilianResult3D(BrazilianResult):
    """A 3D disk's: its peak load, over its whole thickness."""

    P_max_kN: float


def check_disk(diameter_mm: float, rmin_mm: float, radius_ratio: float) -> None:
    """Reject a disk its particles cannot fill, naming the field (the square packing it is
    carved from is the diameter wide and high)."""
    if not (np.isfinite(diameter_mm) and diameter_mm > 0):
        raise InputError("diameter_mm", f"must be a finite number > 0, got {diameter_mm}")
    with fields_named({"width_mm": "diameter_mm", "height_mm": "diameter_mm"}):
        check_geometry(diameter_mm, diameter_mm, rmin_mm, radius_ratio)


def brazilian_disk(diameter_mm: float = 50.0, rmin_mm: float = 0.25, radius_ratio: float = 1.65,
                   seed: int = 1, genesis: Genesis | None = None,
                   grain_shape: str = DEFAULT_SHAPE) -> Specimen:
    """A disk of the given diameter carved from a square packing of the same size, of balls or
    of clumps of `grain_shape` (a clump kept whole where the disk of its area at its centroid
    lies inside the disk: `carving.grains`)."""
    check_disk(diameter_mm, rmin_mm, radius_ratio)
    spec = random_packing(diameter_mm, diameter_mm, rmin_mm, radius_ratio, seed, genesis,
                          grain_shape=grain_shape)
    r = 0.5e-3 * diameter_mm
    keep = of_particles(spec, inside_circle(*grains(spec), (r, r), r))
    return keep_particles(spec, keep, f"{spec.label}, disk D {diameter_mm:g} mm")


def crack_share(crack_xy: np.ndarray, disk: Disk, grain_m: float) -> float:
    """The share of the middle slices of the loaded diameter (of the SLICES slices it is cut
    into, all but END_SLICES at each contact) that a crack crosses: where at least half as
    many bonds broke (at `crack_xy`, m) as grains of `grain_m` (m) fit in the slice's patch of
    the crack plane, (D / SLICES) x the disk's `grains_deep` (one grain in 2D, its thickness
    in 3D). Isolated breaks do not make a crack."""
    along = (crack_xy[:, disk.axis] - disk.centre[1]) / disk.diameter_m  # in diameters from the centre
    counts = np.bincount(np.clip(np.floor((along + 0.5) * SLICES), 0, SLICES - 1).astype(int),
                         minlength=SLICES)[END_SLICES:SLICES - END_SLICES]
    grains = (disk.diameter_m / SLICES / grain_m) * disk.grains_deep
    return float(np.mean(counts >= max(1.0, 0.5 * grains)))


def central_split(crack_xy: np.ndarray, disk: Disk, grain_m: float) -> bool:
    """Whether the bonds broken at `crack_xy` split the disk through its centre
    (`split_through_centre` in the plane of the loaded diameter and the disk's axis, each
    crack's share of the middle by `crack_share`)."""
    return split_through_centre(crack_xy, disk.centre[0], disk.diameter_m, grain_m,
                                lambda where: crack_share(where, disk, grain_m))


def split_through_centre(crack_xy: np.ndarray, centre_x: float, diameter: float, grain_m: float,
                         share: Callable[[np.ndarray], float]) -> bool:
    """The rule, in 2D and 3D: a crack within CENTRAL_BAND x D plus a grain (its path is known
    to a grain) of the loaded diameter (at x = `centre_x`) crosses SPLIT_SHARE of its middle or
    more, and no crack (`separate_cracks`) crosses it with its part beyond twice that (the side
    of a wedge a crushed contact drives); `share(broken bonds)` is the share they cross. Short
    side cracks that open beside a split, each across less of the middle, leave it a split."""
    band = CENTRAL_BAND * diameter + grain_m
    off = np.abs(crack_xy[:, 0] - centre_x)
    return bool(share(crack_xy[off < band]) >= SPLIT_SHARE
                and all(share(crack[np.abs(crack[:, 0] - centre_x) >= 2 * band]) < SPLIT_SHARE
                        for crack in separate_cracks(crack_xy, grain_m)))


def separate_cracks(crack_xy: np.ndarray, grain_m: float) -> list[np.ndarray]:
    """The broken bonds at `crack_xy` (m; in 2D or 3D) as separate cracks: bonds broken within
    CRACK_LINK grains of each other belong to one."""
    # here: scipy's sparse graphs and trees take 0.1 s to import, and every command would wait
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    if len(crack_xy) == 0:
        return []
    near = cKDTree(crack_xy).query_pairs(CRACK_LINK * grain_m, output_type="ndarray")
    links = coo_matrix((np.ones(len(near)), (near[:, 0], near[:, 1])), shape=(len(crack_xy),) * 2)
    count, label = connected_components(links, directed=False)
    return [crack_xy[label == k] for k in range(count)]


def broken_through(crack_xy: np.ndarray, disk: Disk, grain_m: float) -> bool:
    """Whether the bonds broken at `crack_xy` cross SPLIT_SHARE of the loaded diameter's middle
    or more, anywhere across the disk: more than a crush at the contacts."""
    return crack_share(crack_xy, disk, grain_m) >= SPLIT_SHARE


def simulate_brazilian(params: BondedParams | dict | None = None, specimen=None,
                       *, loading: str = DEFAULT_LOADING, rate_factor: float = 1.0,
                       max_strain: float = DEFAULT_MAX_STRAIN,
                       contact_stiffness: str | None = None,
                       strip_modulus_GPa: float = STRIP_MODULUS_GPA, strip_thickness_mm: float | None = None,
                       progress: Callable[[float, float], None] | None = None) -> BrazilianResult:
    """Run the Brazilian test; defaults: granite parameters on a 50 mm disk between flat platens.

    specimen: a 2D disk (`brazilian_disk`) or a 3D one (`specimens3d.specimen.random_disk`);
    loading: "flat" (the UCS test's platens), "isrm" (ISRM's curved jaws, `rig.Jaws`, `rig.Jaws3D`) or
    "strips" (the flat platens with a bearing strip of `strip_modulus_GPa` and
    `strip_thickness_mm`, None: STRIP_THICKNESS_PER_DIAMETER x D, on each; `rig.BearingStrip`);
    contact_stiffness: PFC's convention for kn ("pfc5" or "pfc4", `dem.simulate`; None: the
    engine's default); progress(closure_mm, load) is called as the test goes, the load in kN
    per m of thickness (2D) or kN (3D).
    """
    started = time.perf_counter()
    params = as_params(params)
    if loading not in LOADINGS:
        raise InputError("loading", f"must be one of {', '.join(LOADINGS)}, got {loading!r}")
    check_max_strain(max_strain)
    specimen = specimen or brazilian_disk()
    rig = rig_for(specimen)
    disk = rig.disk(specimen)
    diameter = disk.diameter_m
    strip, squeeze = None, 0.0  # the strips, and how far they may close the platens at most
    if loading == "strips":
        strip = BearingStrip(strip_modulus_GPa, strip_thickness_mm if strip_thickness_mm is not None
                             else 1e3 * STRIP_THICKNESS_PER_DIAMETER * diameter)
        squeeze = 2e-3 * strip.thickness_mm
    if loading == "isrm":
        loader = rig.jaws(specimen, params, rate_factor, contact_stiffness)
    else:
        loader = rig.platens(specimen, params, rate_factor, contact_stiffness, strip)
    state = loader.state
    grain = 2 * specimen.radius.mean()
    peak, after_peak = 0.0, None  # the largest load so far; the bonds broken just after it

    def cracks_now() -> np.ndarray:
        modes, where = state.breaks()
        return where[modes != INTACT]

    def read() -> Reading:
        nonlocal peak, after_peak
        closure = loader.closure_m()
        load = loader.load()
        if load > peak:
            peak, after_peak = load, None
        elif after_peak is None and load < PAST_PEAK_FRACTION * peak:
            after_peak = state.breaks()[0].copy()
        return Reading(load, closure, (1e3 * closure, load / 1e3))

    def failed(reading: Reading) -> bool:
        if loading != "flat":  # as a lab, at the first fall that broke the disk: the jaws (the
            # strips) would load its pieces on; a fall from a crush at a contact is the disk seating
            return (schedule.fallen_below(PAST_PEAK_FRACTION, reading.load)
                    and broken_through(cracks_now(), disk, grain))
        return (schedule.fallen_below(POST_PEAK_FRACTION, reading.load) and state.n_broken() > 0
                and reading.travel > schedule.peak_travel + specimen.radius.mean())

    schedule = Loading(RAMP_STEPS_PER_ROW * loader.rows, LOCALISED_DAMAGE)
    curve = load_to_failure(loader, schedule, read, failed, max_strain * diameter + squeeze,
                            full_speed_past_peak=True,
                            progress=progress)
    k = int(np.argmax(curve[:, 1]))
    P_max = 1e3 * curve[k, 1]
    modes, where = state.breaks()
    if loading != "flat" or after_peak is None:  # the jaws and the strips stop just after the peak
        after_peak = modes
    cracks = measure.cracks(after_peak, where)
    result = dict(
        sigma_t_MPa=2 * P_max / (np.pi * diameter * disk.thickness_m) / 1e6,
        displacement_at_peak_mm=float(curve[k, 0]), diameter_mm=1e3 * diameter,
        split=float(central_split(np.vstack(list(cracks.values())), disk, grain)),
        peak_cracks=cracks, curve=curve, **run_fields(state, specimen, started))
    if rig.dimensions == 3:
        return BrazilianResult3D(P_max_kN=P_max / 1e3, **result)
    return BrazilianResult2D(P_max_kN_per_m=P_max / 1e3, **result)


def _check(s: dict) -> None:
    strip, loading = s.get("strip_modulus_gpa", STRIP_MODULUS_GPA), s.get("brazilian_loading", DEFAULT_LOADING)
    if not strip >= MIN_STRIP_MODULUS_GPA:
        raise InputError("strip_modulus_gpa", f"must be at least {MIN_STRIP_MODULUS_GPA:g} GPa (a cardboard "
                                              f"cushion's; a softer strip is squeezed through before the disk "
                                              f"splits), got {strip:g}; plywood's is {STRIP_MODULUS_GPA:g}")
    if strip != STRIP_MODULUS_GPA and loading != "strips":
        raise InputError("strip_modulus_gpa", f"{strip:g} GPa is a bearing strip's: it acts only with "
                                              f"brazilian_loading = \"strips\", got {loading!r}")
    if in_3d(s):
        return _check_3d(s)
    with fields_named({"diameter_mm": "disk_diameter_mm"}):
        check_disk(s["disk_diameter_mm"], s["rmin_mm"], s["radius_ratio"])
    check_grain_cloud(s["disk_diameter_mm"], s["disk_diameter_mm"], s)


def _check_3d(s: dict) -> None:
    """A 3D disk's settings (D x D/2, `specimens3d.specimen.random_disk`): none of the 2D engine's
    alone, and a disk its spheres fill."""
    check_3d_settings(s)
    d, largest = s["disk_diameter_mm"], s["rmin_mm"] * s["radius_ratio"]
    if np.isfinite(d) and d / 2 < 8 * largest:  # the thickness, 4 of the largest spheres
        raise InputError("disk_diameter_mm", f"a 3D disk is D / 2 thick: {d:g} mm leaves {d / 2:g} mm for "
                                             f"spheres of radius up to {largest:g} mm (need D of at least "
                                             f"{16 * largest:g} mm)")
    with fields_named({"diameter_mm": "disk_diameter_mm", "width_mm": "disk_diameter_mm",
                       "height_mm": "disk_diameter_mm", "thickness_mm": "disk_diameter_mm"}):
        check_disk_3d(d, d / 2, s["rmin_mm"], s["radius_ratio"])
        check_vessel((d, d / 2, d), s["rmin_mm"], s["radius_ratio"], s["cloud_porosity"], s["pressure_mpa"])


def _specimen(s: dict):
    if in_3d(s):  # a disk D thick D / 2 carved from a cached D x D/2 x D packing of spheres
        return random_disk(s["disk_diameter_mm"], None, s["rmin_mm"], s["radius_ratio"], s["seed"], genesis_of(s),
                           grain_shape=s.get("grain_shape", DEFAULT_SHAPE))
    return brazilian_disk(s["disk_diameter_mm"], s["rmin_mm"], s["radius_ratio"], s["seed"], genesis_of(s),
                          s.get("grain_shape", DEFAULT_SHAPE))


def _run(params: BondedParams, specimen, s: dict, progress) -> BrazilianResult:
    return simulate_brazilian(params, specimen, loading=s["brazilian_loading"],
                              strip_modulus_GPa=s["strip_modulus_gpa"],
                              contact_stiffness=s["contact_stiffness"], progress=progress)


def _outline(s: dict) -> Outline:
    d = s["disk_diameter_mm"]
    if in_3d(s):  # the disk keeps pi/4 of its D x D/2 x D packing: pi/8 of a D x D x D one
        return Outline(f"disk D {d:g} x t {d / 2:g} mm", d, d, share=np.pi / 8,
                       vessel_mm=(d, DISK_THICKNESS_PER_DIAMETER * d, d))
    return Outline(f"disk D {d:g} mm", d, d, share=np.pi / 4)


class BrazilianValues(LabValues):
    """Lab result of the Brazilian (splitting tensile) test."""

    sigma_t_MPa: float = Field(gt=0, description="Brazilian tensile strength σ_t = 2P/(πDt), MPa.")


RESPONSES = (Response("sigma_t_MPa", "MPa", label="tensile strength sigma_t"),
             Response("P_max_kN_per_m", "kN/m", target=False, label="peak load"),
             Response("displacement_at_peak_mm", "mm", target=False, label="platen closure at peak"),
             Response("split", "", target=False, label="split through the centre (1) or not (0)"))
RESPONSES_3D = tuple(Response("P_max_kN", "kN", target=False, label="peak load") if r.name == "P_max_kN_per_m"
                     else r for r in RESPONSES)

# A disk's run time between bearing strips over a UCS run's of the same work: the platens close
# several times further to the peak (the strips' squeeze), at the slowest loading from the first
# break; between bare platens the disk takes about its work's time.
STRIPS_SLOWER = 6.0


TEST = LabTest(
    lab_values=BrazilianValues,
    time_factor=lambda s: STRIPS_SLOWER if s.get("brazilian_loading") == "strips" else 1.0,
    steps_follow_rows=lambda s: not in_3d(s),  # a 3D disk's: `plan.cost.TRAVEL_ROWS_3D`
    name="brazilian", title="Brazilian",
    help="Brazilian test of a disk between flat platens, flat platens with bearing strips or ISRM's "
         "curved jaws (--loading): "
         "sigma_t = 2P/(pi D t), load-closure curve, whether the disk split through its centre.",
    responses=RESPONSES,
    curve_columns=("displacement_mm", "load_kN_per_m"), plot="load_displacement",
    flags=(("disk_diameter_mm", "diameter_mm"), ("brazilian_loading", "loading")),
    # brazilian_loading, grain_shape, dimensions and strip_modulus_gpa last: at their defaults
    # ("flat", "ball", 2, 1: kind.LATER_SETTINGS) a run's key leaves them out
    settings=("disk_diameter_mm", "rmin_mm", "radius_ratio", "seed", *GENESIS, "contact_stiffness",
              "brazilian_loading", "grain_shape", "dimensions", "strip_modulus_gpa"),
    check=_check, make=_specimen, run=_run, reading=load_reading("kN/m"), outline=_outline,
    # a 3D disk has a thickness: its load in kN, and the 3D runs stored with it per m run again
    changes_3d=(("responses", RESPONSES_3D), ("curve_columns", ("displacement_mm", "load_kN")),
                ("reading", load_reading("kN")), ("revision", 3)),
    revision=2)  # part of every stored Brazilian run's key: raise it when the test's numbers change
