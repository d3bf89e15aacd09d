"""Virtual three-point bending of a notched beam (single edge notch at mid-span of the bottom
edge) and its fracture toughness K_IC from the peak load.

Supports and loading pin are rigid cylinders (radius PIN_RADIUS_MM at full size) built from
small driven disks on their surface (`rockcal.labtests.rig.pins`). The supports stay put; the
pin moves down at a quasi-static speed on the density-scaled beam. Loads are per metre of
thickness (PFC2D convention).

The test is one procedure in 2D and 3D, over the rig of the beam's dimension (`rig.rig_for`):
with the setting `dimensions` 3 (PFC3D) the beam is a prism `Beam.thickness_mm` thick (by
default eight of its largest spheres across, `thickness_3d_mm`), carved from a cuboid packing
of spheres with a straight-through notch (`notched_beam_3d`), between cylindrical pins along
its thickness (`rig.pins_3d`); its load is in N over the whole thickness, reported in kN
(P_max_kN), and K_IC is the same beam formula with that thickness.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import Callable, NamedTuple

import numpy as np
from pydantic import Field

from rockcal.specimens.carving import cut_bonds, grains, keep_particles, of_particles, outside_rectangle
from rockcal.materials.clump_templates import DEFAULT_SHAPE
from rockcal.specimens.genesis import Genesis
from rockcal.specimens3d.genesis import DEFAULT_GENESIS_3D
from rockcal.specimens.specimen import Specimen, check_geometry, random_packing
from rockcal.specimens3d.specimen import Specimen3D, check_vessel, notched, random_cuboid
from rockcal.errors import InputError, fields_named
from rockcal.labtests.kic import senb_kic
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
    NOTCH_TIP_DAMAGE,
    RAMP_STEPS_PER_ROW,
    Loading,
    Reading,
    check_stop_fraction,
    load_to_failure,
)
from rockcal.labtests.result import LabResult, run_fields
from rockcal.labtests.rig import rig_for
from rockcal.labtests.rig.pins import touching_centre_y
from rockcal.materials import BondedParams, as_params

PIN_RADIUS_MM = 5.0
# Quasi-static loading: the pin moves PIN_STEP_PER_RADIUS mean particle radii per time step.
# Peak deflection and the beam's flexural period both scale as S^2/W, so a pin step
# proportional to the particle size (whose time step sets the clock) keeps the same number of
# flexural periods to the peak for any beam size. Ramped in over RAMP_STEPS_PER_ROW x rows;
# slower where bonds break, full speed again once P_max is known (`rockcal.labtests.loading`).
PIN_STEP_PER_RADIUS = 2e-6
# Until the first bond breaks the beam is linear elastic and the pin runs at INTACT_PIN_SPEED x
# that speed; the granite's first bond breaks at 60-90 % of P_max. At 4x the mean K_IC of the
# granite's three full-size beams moves by -1.3 % at half the pin speed; 8x moves one beam's
# K_IC by -2 %, too much.
INTACT_PIN_SPEED = 4.0
DEFAULT_MAX_DISPLACEMENT_MM = 1.0
# The crack runs unstably from the peak on; by default the test goes on until the load has
# fallen below this fraction of the peak, so that the crack path is there to be seen. Once the
# peak is known (a fall below 0.8 of it has lasted as long as a swing could) this fall counts at
# once. A run for K_IC alone may stop earlier (`stop_fraction` 0.9: P_max is certain once the
# load has stayed below 0.9 of it for a flexural period).
POST_PEAK_FRACTION = 0.3
# A beam drawn for its crack runs on until the load has all but vanished: the crack has then
# crossed the ligament but for the pin's compression zone (a granite beam's: about two thirds
# of it at 0.3 of the peak, nearly all at 0.03, for about twice the steps of a run stopped at
# 0.9). Its peak, and so its K_IC, is the one a run stopped earlier reads.
RUN_ON_FRACTION = 0.03
# The beam rings at its first flexural period after the pin touches it or slows down: the load
# read at the pin swings about the one its travel gives (the pin touching a 220 x 50 mm beam
# at R_min 0.5 mm: from 5.05 down to 1.24 kN/m in 1 960 steps, half a period, with no bond
# broken). Loads read in the first TOUCH_FLEXURAL_PERIODS periods after the pin touches do not
# count, and a fall below a fraction of the peak (to full speed, to the end of the test) counts
# once it has lasted CONFIRM_FLEXURAL_PERIODS: a swing comes back within one period, a crack's
# fall does not.
TOUCH_FLEXURAL_PERIODS = 2.0
CONFIRM_FLEXURAL_PERIODS = 1.0
# The beam's grains are density-scaled (`simulate.scale_density`, as in the UCS test): it rings
# and its waves cross in fewer steps, and its pin runs this much faster with a ramp and window
# this much shorter. The fastest that keeps the granite's three-beam K_IC within 2 % at half
# the speed: 1.3x moves it by -2.1 %, because a beam's crack path follows its loading more than
# a UCS specimen's distributed damage does.
DENSITY_SCALED_SPEED = 1.15

# A 3D beam is by default this many of its largest spheres thick, twice the thinnest prism the
# 3D genesis packs (`specimens3d.specimen.check_vessel`): K_IC moves by a few per cent a doubling
# of the thickness from four across on, within the packings' spread (docs/validation/kic.md),
# and the source's beam holds less than half the spheres it holds as thick as it is deep.
DEFAULT_THICKNESS_DIAMETERS = 8


@dataclass(frozen=True)
class Beam:
    """Geometry of the notched beam and its supports (mm); a notch of width 0 is a cut (the
    bonds across the notch line removed), the sharp crack of the K formula. A 3D beam is
    `thickness_mm` thick (None: `thickness_3d_mm`'s default); a 2D beam has the slab's unit
    thickness."""

    length_mm: float = 220.0
    height_mm: float = 50.0
    notch_mm: float = 18.0
    notch_width_mm: float = 2.0
    span_mm: float = 160.0
    pin_radius_mm: float | None = None  # None: PIN_RADIUS_MM scaled with the depth (5 mm at 50 mm)
    thickness_mm: float | None = None  # a 3D beam's (None: `thickness_3d_mm`'s default)

    def __post_init__(self):
        if self.pin_radius_mm is None:
            object.__setattr__(self, "pin_radius_mm", PIN_RADIUS_MM * self.height_mm / 50.0)

    def check(self) -> None:
        """Reject geometry no test can be run on, naming the setting."""
        for name in ("length_mm", "height_mm", "notch_mm", "notch_width_mm", "span_mm",
                     "pin_radius_mm"):
            value, may_be_zero = getattr(self, name), name == "notch_width_mm"
            if not (np.isfinite(value) and (value > 0 or (may_be_zero and value == 0))):
                raise InputError(name, "must be a finite number "
                                 f"{'>= 0' if may_be_zero else '> 0'}, got {value}")
        if self.notch_mm >= self.height_mm:
            raise InputError("notch_mm", f"the notch ({self.notch_mm:g} mm) must be shallower "
                             f"than the beam ({self.height_mm:g} mm)")
        if self.span_mm >= self.length_mm:
            raise InputError("span_mm", f"the span ({self.span_mm:g} mm) must be shorter than "
                             f"the beam ({self.length_mm:g} mm)")
        if self.span_mm / 2 + self.pin_radius_mm > self.length_mm / 2:
            raise InputError("span_mm", f"supports of radius {self.pin_radius_mm:g} mm at "
                             f"+-{self.span_mm / 2:g} mm stick out of a {self.length_mm:g} mm beam")
        if self.notch_width_mm >= self.span_mm - 2 * self.pin_radius_mm:
            raise InputError("notch_width_mm", f"must be narrower than the span between the "
                             f"supports, got {self.notch_width_mm:g} mm")


def thickness_3d_mm(beam: Beam, rmin_mm: float, radius_ratio: float) -> float:
    """A 3D beam's thickness: its own, or DEFAULT_THICKNESS_DIAMETERS of its largest spheres
    (of R_min x radius_ratio) across."""
    if beam.thickness_mm is not None:
        return beam.thickness_mm
    return 2 * DEFAULT_THICKNESS_DIAMETERS * rmin_mm * radius_ratio


def check_beam(beam: Beam, rmin_mm: float, radius_ratio: float) -> None:
    """Reject a beam its particles cannot fill or no test can be run on, naming the Beam's
    field (the packing's width is the beam's length)."""
    with fields_named({"width_mm": "length_mm"}):
        check_geometry(beam.length_mm, beam.height_mm, rmin_mm, radius_ratio)
    beam.check()


@dataclass
class BendingResult(LabResult):
    """Responses of a notched-beam three-point bending test, 2D or 3D (`BendingResult2D`,
    `BendingResult3D` add the peak load); its curve's columns: pin displacement mm, load (kN
    per m of thickness in 2D, kN in 3D)."""

    K_IC_MPa_sqrt_m: float
    displacement_at_peak_mm: float
    beam: Beam
    first_break_xy: np.ndarray = field(repr=False)  # where the first bonds broke (m; 3D: x, y, z)

    @property
    def notch_tip_m(self) -> tuple[float, float]:
        """The notch tip seen from the front (along the beam, up), m."""
        return 0.5e-3 * self.beam.length_mm, 1e-3 * self.beam.notch_mm


@dataclass
class BendingResult2D(BendingResult):
    """A 2D beam's: its peak load per metre of the slab's unit thickness."""

    P_max_kN_per_m: float


@dataclass
class BendingResult3D(BendingResult):
    """A 3D beam's: its peak load, over its whole thickness."""

    P_max_kN: float


def notched_beam(beam: Beam = Beam(), rmin_mm: float = 0.25, radius_ratio: float = 1.65,
                 seed: int = 1, genesis: Genesis | None = None,
                 grain_shape: str = DEFAULT_SHAPE) -> Specimen:
    """The beam packing (of balls or of clumps of `grain_shape`) with the notch carved out of
    the middle of its bottom edge (or, for width 0, cut into it): a clump is removed whole where
    the disk of its area at its centroid overlaps the notch (`carving.grains`)."""
    check_beam(beam, rmin_mm, radius_ratio)
    spec = random_packing(beam.length_mm, beam.height_mm, rmin_mm, radius_ratio, seed, genesis,
                          grain_shape=grain_shape)
    half = 0.5e-3 * beam.notch_width_mm
    middle = 0.5e-3 * beam.length_mm
    label = f"{spec.label}, notch {beam.notch_mm:g} x {beam.notch_width_mm:g} mm"
    if beam.notch_width_mm == 0:
        return cut_bonds(spec, middle, 1e-3 * beam.notch_mm, label)
    keep = of_particles(spec, outside_rectangle(*grains(spec), middle - half, middle + half, -1.0,
                                                1e-3 * beam.notch_mm))
    return keep_particles(spec, keep, label)


def notched_beam_3d(beam: Beam = Beam(), rmin_mm: float = 0.75, radius_ratio: float = 1.65, seed: int = 1,
                    genesis: Genesis | None = None) -> Specimen3D:
    """The 3D beam: a prism of the beam's length (x), thickness (y) and depth (z) packed by
    the 3D genesis (`random_cuboid`, cached), with the notch carved through its thickness out
    of the middle of its bottom face (or, for width 0, cut into it: `specimens3d.specimen.notched`)."""
    check_beam_3d(beam, rmin_mm, radius_ratio, genesis)
    prism = random_cuboid((beam.length_mm, thickness_3d_mm(beam, rmin_mm, radius_ratio), beam.height_mm), rmin_mm,
                          radius_ratio, seed, genesis)
    beam_3d = notched(prism, 0.5e-3 * beam.length_mm, 1e-3 * beam.notch_width_mm, 1e-3 * beam.notch_mm)
    return replace(beam_3d, label=f"{prism.label}, notch {beam.notch_mm:g} x {beam.notch_width_mm:g} mm")


def check_beam_3d(beam: Beam, rmin_mm: float, radius_ratio: float, genesis: Genesis | None = None) -> None:
    """Reject a 3D beam its spheres cannot fill or no test can be run on, naming the Beam's
    field (the packing's sides are the beam's length, thickness and depth)."""
    thickness = thickness_3d_mm(beam, rmin_mm, radius_ratio)
    if not (np.isfinite(thickness) and thickness > 0):
        raise InputError("thickness_mm", f"must be a finite number > 0, got {thickness}")
    beam.check()
    genesis = genesis or DEFAULT_GENESIS_3D
    with fields_named({"width_mm": "length_mm"}):
        check_vessel((beam.length_mm, thickness, beam.height_mm), rmin_mm, radius_ratio, genesis.cloud_porosity,
                     genesis.pressure_mpa)


def rig_circles(beam: Beam, pos: np.ndarray, radius: np.ndarray) -> list[tuple[float, float, float]]:
    """The pin and the two supports touching the beam's grains `pos`, `radius` (m) before the
    test, as circles (x, y, radius; m), as the test places them (a 3D beam's seen from the
    front, x and z)."""
    pos = pos[:, [0, -1]]
    r = 1e-3 * beam.pin_radius_mm
    middle, half_span = 0.5e-3 * beam.length_mm, 0.5e-3 * beam.span_mm
    pin = (middle, touching_centre_y(pos, radius, middle, r, above=True), r)
    return [pin, *((x, touching_centre_y(pos, radius, x, r, above=False), r)
                   for x in (middle - half_span, middle + half_span))]


def crack_reach(beam: Beam, broken_xy: np.ndarray) -> float:
    """How far up the ligament the crack has run: the highest broken bond (m; x, y in 2D, x,
    y, z in 3D: along, then up last) within half a ligament of the notch plane, as a fraction
    of the ligament (0 at the notch tip, 1 at the beam's top)."""
    ligament = 1e-3 * (beam.height_mm - beam.notch_mm)
    near = broken_xy[np.abs(broken_xy[:, 0] - 0.5e-3 * beam.length_mm) <= 0.5 * ligament]
    if not len(near):
        return 0.0
    return float(np.clip((near[:, -1].max() - 1e-3 * beam.notch_mm) / ligament, 0.0, 1.0))


def wave_speed_m_per_s(params: BondedParams, porosity: float, mass_scale: float = 1.0) -> float:
    """The bar wave speed sqrt(E / rho) of the bonded rock, with E estimated as its material's
    bonded modulus (`bonded_modulus_GPa`: contacts and parallel bonds side by side,
    E_c + lambda Ebar_c, 43.3 GPa where the source's point measures 40.6; a flat joint's
    lambda E*), and rho the grains' density (times mass_scale where density-scaled) times
    their share of the box."""
    modulus_Pa = 1e9 * params.bonded_modulus_GPa
    return float(np.sqrt(modulus_Pa / (params.density * mass_scale * (1.0 - porosity))))


def flexural_period_s(beam: Beam, wave_speed_m_per_s: float) -> float:
    """The first flexural period of the beam simply supported over its span (Euler-Bernoulli,
    unnotched): 2 pi / omega with omega = (pi / S)^2 c W / sqrt(12)."""
    span_m, depth_m = 1e-3 * beam.span_mm, 1e-3 * beam.height_mm
    return 2.0 * np.sqrt(12.0) * span_m**2 / (np.pi * depth_m * wave_speed_m_per_s)


def period_steps(beam: Beam, params: BondedParams, specimen: Specimen | Specimen3D, dt_s: float,
                 mass_scale: float = 1.0) -> float:
    """The beam's first flexural period in steps (its grains' masses scaled by mass_scale)."""
    period_s = flexural_period_s(beam, wave_speed_m_per_s(params, specimen.porosity, mass_scale))
    return period_s / dt_s


class Bent(NamedTuple):
    """A three-point bending run: its peak load (N per m of thickness in 2D, N in 3D), the
    thickness it is over (m), and the fields every bending test's result has."""

    P_max: float
    thickness_m: float
    fields: dict  # displacement_at_peak_mm, curve, first_break_xy and `result.run_fields`


def load_three_point(params: BondedParams, specimen, beam: Beam, started: float, *, rate_factor: float = 1.0,
                     max_displacement_mm: float = DEFAULT_MAX_DISPLACEMENT_MM,
                     stop_fraction: float = POST_PEAK_FRACTION, contact_stiffness: str | None = None,
                     progress: Callable[[float, float], None] | None = None,
                     reactions: list | None = None):
    """Load `specimen` in three-point bending until its crack has run (the load has stayed
    below stop_fraction x the peak, `CONFIRM_FLEXURAL_PERIODS`) over the rig of its dimension:
    the pin at the middle of `beam`, the supports `beam.span_mm` apart, of `beam.pin_radius_mm`;
    the beam's flexural period sets the loading's waits; `started`, the test's
    `time.perf_counter()` at its start. Its curve's columns: pin displacement mm, load kN per m
    of thickness in 2D, kN in 3D. rate_factor scales the pin speed; contact_stiffness is PFC's convention for kn
    ("pfc5" or "pfc4" in 2D, `dem.simulate`; None: the engine's default); progress(displacement_mm,
    load) is called as the test goes; `reactions`, a list, gets the two supports' reactions
    (N per m, or N) at each reading."""
    contact_GPa = getattr(params, params.CONTACT_MODULUS)  # E_c, or the flat joint's lnm_emod
    if contact_GPa <= 0:
        raise InputError(params.CONTACT_MODULUS, "must be > 0 in a bending test: the pins push through contacts")
    if not 0 < max_displacement_mm <= beam.height_mm:
        raise InputError("max_displacement_mm", f"must be in (0, {beam.height_mm:g}], got "
                         f"{max_displacement_mm}")
    check_stop_fraction(stop_fraction)
    rig = rig_for(specimen)
    middle, half_span = 0.5e-3 * beam.length_mm, 0.5e-3 * beam.span_mm
    pin_step = DENSITY_SCALED_SPEED * rate_factor * PIN_STEP_PER_RADIUS * specimen.radius.mean()
    pins = rig.pins(specimen, params, middle, (middle - half_span, middle + half_span),
                    1e-3 * beam.pin_radius_mm, pin_step, contact_stiffness)
    state = pins.state
    mass_scale = state.scale_density()
    first_break = np.empty((0, rig.dimensions))
    period = period_steps(beam, params, specimen, state.dt, mass_scale)
    touch_load = pins.contact_load(contact_GPa)
    touched = False

    def read() -> Reading:
        nonlocal first_break, touched
        if not len(first_break) and state.n_broken():
            mode, where = state.breaks()
            first_break = where[mode > 0]
        displacement = pins.displacement_m()
        load = pins.load()
        if reactions is not None:
            reactions.append(pins.reactions())
        if not touched and load > touch_load:  # the pin hits the beam: it rings
            touched = True
            loading.wait(state.step, TOUCH_FLEXURAL_PERIODS * period)
        return Reading(load, displacement, (1e3 * displacement, load / 1e3))

    def crack_has_run(reading: Reading) -> bool:
        return loading.fallen_below(stop_fraction, reading.load) and state.n_broken() > 0

    loading = Loading(RAMP_STEPS_PER_ROW * pins.rows / DENSITY_SCALED_SPEED, NOTCH_TIP_DAMAGE,
                      CONFIRM_FLEXURAL_PERIODS * period, intact_speed=INTACT_PIN_SPEED)
    curve = load_to_failure(pins, loading, read, crack_has_run,
                            1e-3 * max_displacement_mm, full_speed_past_peak=True, progress=progress)
    k = int(np.argmax(curve[:, 1]))
    return Bent(1e3 * curve[k, 1], pins.thickness_m,
                dict(displacement_at_peak_mm=float(curve[k, 0]), curve=curve, first_break_xy=first_break,
                     **run_fields(state, specimen, started)))


def simulate_bending(params: BondedParams | dict | None = None, specimen: Specimen | Specimen3D | None = None,
                     beam: Beam = Beam(), **options) -> BendingResult:
    """Run the notched-beam test; defaults: granite parameters, the source's 220 x 50 mm beam.

    `specimen` must be `notched_beam(beam, ...)` (2D) or `notched_beam_3d(beam, ...)` (3D);
    `options` are `load_three_point`'s: rate_factor, max_displacement_mm, stop_fraction,
    contact_stiffness, progress, reactions.
    """
    started = time.perf_counter()
    params = as_params(params)
    beam.check()
    specimen = specimen or notched_beam(beam)
    bent = load_three_point(params, specimen, beam, started, **options)
    K_IC = senb_kic(bent.P_max, 1e-3 * beam.span_mm, 1e-3 * beam.height_mm, 1e-3 * beam.notch_mm, bent.thickness_m)
    if specimen.dimensions == 3:
        return BendingResult3D(K_IC_MPa_sqrt_m=K_IC / 1e6, P_max_kN=bent.P_max / 1e3,
                               beam=replace(beam, thickness_mm=1e3 * bent.thickness_m), **bent.fields)
    return BendingResult2D(K_IC_MPa_sqrt_m=K_IC / 1e6, P_max_kN_per_m=bent.P_max / 1e3, beam=beam, **bent.fields)


# The specimen setting of each of the Beam's fields.
BEAM_SETTINGS = {"length_mm": "beam_length_mm", "height_mm": "beam_height_mm", "notch_mm": "notch_mm",
                 "notch_width_mm": "notch_width_mm", "span_mm": "span_mm", "thickness_mm": "beam_thickness_mm"}


def beam_of(settings: dict) -> Beam:
    """The beam of a test's specimen settings (a run's key leaves out the thickness at its default)."""
    return Beam(**{field: settings[name] for field, name in BEAM_SETTINGS.items() if name in settings})


def _check(s: dict) -> None:
    if in_3d(s):
        check_3d_settings(s)
        with fields_named(BEAM_SETTINGS):
            return check_beam_3d(beam_of(s), s["rmin_mm"], s["radius_ratio"], genesis_of(s))
    if s.get("beam_thickness_mm") is not None:
        raise InputError("beam_thickness_mm", "a 2D beam is PFC2D's slab of unit thickness (its load per metre); "
                                              "a thickness is a 3D beam's, with dimensions = 3")
    with fields_named(BEAM_SETTINGS):
        check_beam(beam_of(s), s["rmin_mm"], s["radius_ratio"])
    check_grain_cloud(s["beam_length_mm"], s["beam_height_mm"], s)


def _specimen(s: dict) -> Specimen | Specimen3D:
    if in_3d(s):
        return notched_beam_3d(beam_of(s), s["rmin_mm"], s["radius_ratio"], s["seed"], genesis_of(s))
    return notched_beam(beam_of(s), s["rmin_mm"], s["radius_ratio"], s["seed"], genesis_of(s),
                        s.get("grain_shape", DEFAULT_SHAPE))


def _run(params: BondedParams, specimen, s: dict, progress) -> BendingResult:
    return simulate_bending(params, specimen, beam_of(s), stop_fraction=s["stop_fraction"],
                            contact_stiffness=s["contact_stiffness"], progress=progress)


def _outline(s: dict) -> Outline:
    length, depth = s["beam_length_mm"], s["beam_height_mm"]
    if in_3d(s):
        thickness = thickness_3d_mm(beam_of(s), s["rmin_mm"], s["radius_ratio"])
        return Outline(f"beam {length:g} x {depth:g} mm, {thickness:g} mm thick", length, depth,
                       share=thickness / length, vessel_mm=(length, thickness, depth))
    return Outline(f"beam {length:g} x {depth:g} mm", length, depth)


class BendingValues(LabValues):
    """Lab results of the notched three-point bending test."""

    K_IC_MPa_sqrt_m: float = Field(gt=0, description="Fracture toughness K_IC, MPa·m^0.5.")
    P_max_kN: float | None = Field(None, gt=0, description="Peak load of the lab's round bar, kN, to cross-check "
                                   "K_IC with Ouchterlony's formula.")
    diameter_mm: float = Field(50.0, gt=0, description="The lab bar's diameter D, mm.")
    notch_mm: float = Field(18.0, gt=0, description="The lab bar's notch depth a, mm.")
    span_mm: float = Field(160.0, gt=0, description="The lab bar's support span S, mm.")


RESPONSES = (Response("K_IC_MPa_sqrt_m", "MPa·m^0.5", label="K_IC"),
             Response("P_max_kN_per_m", "kN/m", target=False, label="peak load"),
             Response("displacement_at_peak_mm", "mm", target=False, label="pin displacement at peak"))
RESPONSES_3D = tuple(Response("P_max_kN", "kN", target=False, label="peak load") if r.name == "P_max_kN_per_m"
                     else r for r in RESPONSES)

TEST = LabTest(
    lab_values=BendingValues,
    # its steps grow with span² / height, not with its rows (in 3D: `plan.cost.TRAVEL_ROWS_3D`)
    time_factor=lambda s: 1.0 if in_3d(s) else 1.75, steps_follow_rows=lambda s: not in_3d(s),
    name="bending", title="bending",
    help="Three-point bending of a notched beam: peak load, load-displacement curve, K_IC.",
    responses=RESPONSES,
    curve_columns=("displacement_mm", "load_kN_per_m"), plot="load_displacement",
    flags=(("beam_length_mm", "length_mm"), ("beam_height_mm", "height_mm"), ("beam_thickness_mm", "thickness_mm")),
    defaults=(("stop_fraction", POST_PEAK_FRACTION),),
    # grain_shape, dimensions and the thickness last: at their defaults (kind.LATER_SETTINGS) out of a run's key
    settings=("beam_length_mm", "beam_height_mm", "notch_mm", "notch_width_mm", "span_mm", "rmin_mm",
              "radius_ratio", "seed", *GENESIS, "stop_fraction", "contact_stiffness", "grain_shape", "dimensions",
              "beam_thickness_mm"),
    check=_check, make=_specimen, run=_run, reading=load_reading("kN/m"), outline=_outline,
    # a 3D beam has a thickness: its load in kN
    changes_3d=(("responses", RESPONSES_3D), ("curve_columns", ("displacement_mm", "load_kN")),
                ("reading", load_reading("kN")), ("revision", 2)),
    revision=8)  # part of every stored bending run's key: raise it when the test's numbers change
# (what changed in each revision: CHANGELOG.md)
