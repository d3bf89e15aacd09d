"""Virtual semi-circular bend (SCB) test, ISRM's suggested method for K_IC (Kuruppu et al.
2014): a half disk of radius R with a straight edge notch of length a up from the middle of its
flat side, on two supports S either side of the notch, loaded by a pin at the top of its arc;
K_IC = Y' P_max sqrt(pi a) / (2 R B) (`kic.scb_kic`).

The loading is the notched beam's (`bending.load_three_point`: the same pins, pin speed and
stop rule), the half disk loading as a beam 2R long and R deep over a span 2S. In 2D the half
disk is carved from a 2R x R packing and B is the slab's unit thickness (its load per metre);
with the setting `dimensions` 3 it is SCB_THICKNESS_PER_RADIUS x R thick, carved from a cuboid
packing of spheres with the notch straight through its thickness, between the 3D pins.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace

import numpy as np
from pydantic import Field

from rockcal.errors import InputError, fields_named
from rockcal.labtests.bending import PIN_RADIUS_MM, POST_PEAK_FRACTION, Beam, load_three_point
from rockcal.labtests.kic import scb_kic
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
from rockcal.labtests.result import LabResult
from rockcal.materials import BondedParams, as_params
from rockcal.materials.clump_templates import DEFAULT_SHAPE
from rockcal.specimens.carving import cut_bonds, grains, inside_circle, keep_particles, of_particles, \
    outside_rectangle
from rockcal.specimens.genesis import Genesis
from rockcal.specimens.specimen import Specimen, check_geometry, random_packing
from rockcal.specimens3d.genesis import DEFAULT_GENESIS_3D
from rockcal.specimens3d.specimen import Specimen3D, carve_half_disk, check_vessel, notched, random_cuboid

# ISRM's specimen (Kuruppu et al. 2014): notch length 0.4 <= a/R <= 0.6, supports at 0.5 <= S/R
# <= 0.8, thickness B >= 0.4 D; Y' is fitted over these span ratios.
NOTCH_RATIOS = (0.4, 0.6)
SPAN_RATIOS = (0.5, 0.8)
SCB_THICKNESS_PER_RADIUS = 0.8  # a 3D half disk's B / R: ISRM's least, 0.4 D


@dataclass(frozen=True)
class HalfDisk:
    """Geometry of the SCB specimen (mm): radius R, notch length a and width (0: a cut, the
    bonds across the notch line removed), supports at +-`span_ratio` x R from the centre, pins
    of `pin_radius_mm` (None: the beam's PIN_RADIUS_MM scaled with R, 5 mm at 50 mm); a 3D half
    disk is `thickness_mm` thick (None: SCB_THICKNESS_PER_RADIUS x R)."""

    radius_mm: float = 50.0
    notch_mm: float = 25.0
    span_ratio: float = 0.8
    notch_width_mm: float = 2.0
    pin_radius_mm: float | None = None
    thickness_mm: float | None = None

    def __post_init__(self):
        if self.pin_radius_mm is None:
            object.__setattr__(self, "pin_radius_mm", PIN_RADIUS_MM * self.radius_mm / 50.0)

    @property
    def half_span_mm(self) -> float:
        return self.span_ratio * self.radius_mm

    @property
    def thickness_3d_mm(self) -> float:
        return SCB_THICKNESS_PER_RADIUS * self.radius_mm if self.thickness_mm is None else self.thickness_mm

    def loading(self) -> Beam:
        """The beam the half disk loads as (`bending.load_three_point`): 2R long and R deep,
        its supports 2S apart, its notch; its flexural period sets the loading's waits."""
        return Beam(2 * self.radius_mm, self.radius_mm, self.notch_mm, self.notch_width_mm,
                    2 * self.half_span_mm, self.pin_radius_mm)

    def check(self) -> None:
        """Reject a half disk outside ISRM's specimen or no test can be run on, naming the field."""
        for name in ("radius_mm", "notch_mm", "span_ratio", "notch_width_mm", "pin_radius_mm"):
            value, may_be_zero = getattr(self, name), name == "notch_width_mm"
            if not (np.isfinite(value) and (value > 0 or (may_be_zero and value == 0))):
                raise InputError(name, f"must be a finite number {'>= 0' if may_be_zero else '> 0'}, got {value}")
        low, high = NOTCH_RATIOS
        if not low <= self.notch_mm / self.radius_mm <= high:
            raise InputError("notch_mm", f"must be {low:g}-{high:g} x the radius (ISRM), got {self.notch_mm:g} mm "
                                         f"for a radius of {self.radius_mm:g} mm")
        low, high = SPAN_RATIOS
        if not low <= self.span_ratio <= high:
            raise InputError("span_ratio", f"S/R must be in [{low:g}, {high:g}] (ISRM, and Y' is fitted "
                                           f"there), got {self.span_ratio:g}")
        if self.half_span_mm + self.pin_radius_mm > self.radius_mm:
            raise InputError("span_ratio", f"supports of radius {self.pin_radius_mm:g} mm at +-{self.half_span_mm:g} "
                                           f"mm stick out of a half disk of radius {self.radius_mm:g} mm")
        if self.notch_width_mm >= 2 * (self.half_span_mm - self.pin_radius_mm):
            raise InputError("notch_width_mm", f"must be narrower than the span between the supports, got "
                                               f"{self.notch_width_mm:g} mm")


@dataclass
class ScbResult(LabResult):
    """Responses of an SCB test, 2D or 3D (`ScbResult2D`, `ScbResult3D` add the peak load); its
    curve's columns: pin displacement mm, load (kN per m of thickness in 2D, kN in 3D)."""

    K_IC_scb_MPa_sqrt_m: float
    displacement_at_peak_mm: float
    half_disk: HalfDisk
    first_break_xy: np.ndarray = field(repr=False)  # where the first bonds broke (m; 3D: x, y, z)


@dataclass
class ScbResult2D(ScbResult):
    """A 2D half disk's: its peak load per metre of the slab's unit thickness."""

    P_max_kN_per_m: float


@dataclass
class ScbResult3D(ScbResult):
    """A 3D half disk's: its peak load, over its whole thickness."""

    P_max_kN: float


def half_disk(hd: HalfDisk = HalfDisk(), rmin_mm: float = 0.25, radius_ratio: float = 1.65, seed: int = 1,
              genesis: Genesis | None = None, grain_shape: str = DEFAULT_SHAPE) -> Specimen:
    """The 2D half disk: the grains of a 2R x R packing wholly inside the circle of radius R
    about the middle of its bottom edge (a clump by the disk of its area at its centroid,
    `carving.grains`), the notch carved out of the middle of that edge (or, of width 0, cut
    into it)."""
    check_half_disk(hd, rmin_mm, radius_ratio)
    r = 1e-3 * hd.radius_mm
    spec = random_packing(2 * hd.radius_mm, hd.radius_mm, rmin_mm, radius_ratio, seed, genesis,
                          grain_shape=grain_shape)
    centre, notch, half = grains(spec), 1e-3 * hd.notch_mm, 0.5e-3 * hd.notch_width_mm
    keep = inside_circle(*centre, (r, 0.0), r)
    if hd.notch_width_mm > 0:
        keep &= outside_rectangle(*centre, r - half, r + half, -1.0, notch)
    label = f"{spec.label}, half disk R {hd.radius_mm:g} mm, notch {hd.notch_mm:g} x {hd.notch_width_mm:g} mm"
    carved = keep_particles(spec, of_particles(spec, keep), label)
    return cut_bonds(carved, r, notch, label) if hd.notch_width_mm == 0 else carved


def half_disk_3d(hd: HalfDisk = HalfDisk(), rmin_mm: float = 0.75, radius_ratio: float = 1.65, seed: int = 1,
                 genesis: Genesis | None = None) -> Specimen3D:
    """The 3D half disk: carved from a 2R x B x R cuboid packing of spheres (`carve_half_disk`,
    the packing cached), its axis along y, with the notch straight through its thickness
    (`specimens3d.specimen.notched`)."""
    check_half_disk_3d(hd, rmin_mm, radius_ratio, genesis)
    cuboid = random_cuboid((2 * hd.radius_mm, hd.thickness_3d_mm, hd.radius_mm), rmin_mm, radius_ratio, seed,
                           genesis)
    carved = notched(carve_half_disk(cuboid), 1e-3 * hd.radius_mm, 1e-3 * hd.notch_width_mm, 1e-3 * hd.notch_mm)
    return replace(carved, label=f"{cuboid.label}, half disk R {hd.radius_mm:g} x B {hd.thickness_3d_mm:g} mm, "
                                 f"notch {hd.notch_mm:g} x {hd.notch_width_mm:g} mm")


def check_half_disk(hd: HalfDisk, rmin_mm: float, radius_ratio: float) -> None:
    """Reject a 2D half disk its grains cannot fill (its packing 2R x R) or no test can be run on."""
    hd.check()
    with fields_named({"width_mm": "radius_mm", "height_mm": "radius_mm"}):
        check_geometry(2 * hd.radius_mm, hd.radius_mm, rmin_mm, radius_ratio)


def check_half_disk_3d(hd: HalfDisk, rmin_mm: float, radius_ratio: float, genesis: Genesis | None = None) -> None:
    """Reject a 3D half disk its spheres cannot fill (its packing 2R x B x R) or no test can be run on."""
    hd.check()
    if not (np.isfinite(hd.thickness_3d_mm) and hd.thickness_3d_mm > 0):
        raise InputError("thickness_mm", f"must be a finite number > 0, got {hd.thickness_3d_mm}")
    genesis = genesis or DEFAULT_GENESIS_3D
    derived = {"thickness_mm": "radius_mm"} if hd.thickness_mm is None else {}  # B of 0.8 R
    with fields_named({"width_mm": "radius_mm", "height_mm": "radius_mm"} | derived):
        check_vessel((2 * hd.radius_mm, hd.thickness_3d_mm, hd.radius_mm), rmin_mm, radius_ratio,
                     genesis.cloud_porosity, genesis.pressure_mpa)


def simulate_scb(params: BondedParams | dict | None = None, specimen: Specimen | Specimen3D | None = None,
                 hd: HalfDisk = HalfDisk(), **options) -> ScbResult:
    """Run the SCB test; defaults: granite parameters, a half disk of radius 50 mm.

    `specimen` must be `half_disk(hd, ...)` (2D) or `half_disk_3d(hd, ...)` (3D); `options` are
    `bending.load_three_point`'s: rate_factor, max_displacement_mm, stop_fraction,
    contact_stiffness, progress, reactions.
    """
    started = time.perf_counter()
    params = as_params(params)
    hd.check()
    specimen = specimen or half_disk(hd)
    bent = load_three_point(params, specimen, hd.loading(), started, **options)
    K_IC = scb_kic(bent.P_max, 1e-3 * hd.radius_mm, 1e-3 * hd.notch_mm, 1e-3 * hd.half_span_mm, bent.thickness_m)
    if specimen.dimensions == 3:
        return ScbResult3D(K_IC_scb_MPa_sqrt_m=K_IC / 1e6, P_max_kN=bent.P_max / 1e3,
                           half_disk=replace(hd, thickness_mm=1e3 * bent.thickness_m), **bent.fields)
    return ScbResult2D(K_IC_scb_MPa_sqrt_m=K_IC / 1e6, P_max_kN_per_m=bent.P_max / 1e3, half_disk=hd, **bent.fields)


# The specimen setting of each of the HalfDisk's fields.
HALF_DISK_SETTINGS = {"radius_mm": "scb_radius_mm", "notch_mm": "scb_notch_mm", "span_ratio": "scb_span_ratio",
                      "notch_width_mm": "scb_notch_width_mm"}


def half_disk_of(settings: dict) -> HalfDisk:
    """The half disk of a test's specimen settings."""
    return HalfDisk(**{name: settings[setting] for name, setting in HALF_DISK_SETTINGS.items()})


def _check(s: dict) -> None:
    with fields_named(HALF_DISK_SETTINGS):
        if in_3d(s):
            check_3d_settings(s)
            return check_half_disk_3d(half_disk_of(s), s["rmin_mm"], s["radius_ratio"], genesis_of(s))
        check_half_disk(half_disk_of(s), s["rmin_mm"], s["radius_ratio"])
    check_grain_cloud(2 * s["scb_radius_mm"], s["scb_radius_mm"], s)


def _specimen(s: dict):
    if in_3d(s):
        return half_disk_3d(half_disk_of(s), s["rmin_mm"], s["radius_ratio"], s["seed"], genesis_of(s))
    return half_disk(half_disk_of(s), s["rmin_mm"], s["radius_ratio"], s["seed"], genesis_of(s),
                     s.get("grain_shape", DEFAULT_SHAPE))


def _run(params: BondedParams, specimen, s: dict, progress) -> ScbResult:
    return simulate_scb(params, specimen, half_disk_of(s), stop_fraction=s["stop_fraction"],
                        contact_stiffness=s["contact_stiffness"], progress=progress)


def _outline(s: dict) -> Outline:
    r = s["scb_radius_mm"]
    if in_3d(s):
        b = half_disk_of(s).thickness_3d_mm
        return Outline(f"half disk R {r:g} x B {b:g} mm", 2 * r, r, share=np.pi / 4 * b / (2 * r),
                       vessel_mm=(2 * r, b, r))
    return Outline(f"half disk R {r:g} mm", 2 * r, r, share=np.pi / 4)


class ScbValues(LabValues):
    """Lab result of the semi-circular bend test."""

    K_IC_scb_MPa_sqrt_m: float = Field(gt=0, description="Fracture toughness K_IC of the SCB test (ISRM 2014), "
                                                         "MPa·m^0.5.")


RESPONSES = (Response("K_IC_scb_MPa_sqrt_m", "MPa·m^0.5", label="K_IC (SCB)"),
             Response("P_max_kN_per_m", "kN/m", target=False, label="peak load"),
             Response("displacement_at_peak_mm", "mm", target=False, label="pin displacement at peak"))
RESPONSES_3D = tuple(Response("P_max_kN", "kN", target=False, label="peak load") if r.name == "P_max_kN_per_m"
                     else r for r in RESPONSES)

TEST = LabTest(
    lab_values=ScbValues,
    name="scb", title="semi-circular bend",
    help="Semi-circular bend test of a notched half disk (ISRM 2014): peak load, load-displacement curve, K_IC.",
    responses=RESPONSES,
    curve_columns=("displacement_mm", "load_kN_per_m"), plot="load_displacement",
    flags=tuple((setting, name) for name, setting in HALF_DISK_SETTINGS.items()),
    defaults=(("stop_fraction", POST_PEAK_FRACTION),),
    # grain_shape and dimensions last: at their defaults (kind.LATER_SETTINGS) out of a run's key
    settings=(*HALF_DISK_SETTINGS.values(), "rmin_mm", "radius_ratio", "seed", *GENESIS,
              "stop_fraction", "contact_stiffness", "grain_shape", "dimensions"),
    check=_check, make=_specimen, run=_run, reading=load_reading("kN/m"), outline=_outline,
    changes_3d=(("responses", RESPONSES_3D), ("curve_columns", ("displacement_mm", "load_kN")),
                ("reading", load_reading("kN"))))
