"""Confined (biaxial) compression of the UCS specimen, as FISHTank's compression test `ct`
with a confining pressure `ct_Pc` (`ct.fis`, ct_testType 0).

The specimen sits between four rigid frictionless walls: the platens and the side walls
(`rockcal.labtests.rig`). Seating: all four walls are servo-controlled to the confining stress
sigma3 until equilibrium (`rig.SideWalls.seat`). Axial loading: the strains are zeroed, the
platens close as in the UCS test (`rockcal.labtests.ucs`: same speed on the density-scaled
specimen, same loading rule) while the side walls keep sigma3. Readings as a lab makes them:
the deviatoric stress q = sigma1 - sigma3 (sigma1: the platens' force on the specimen's
original width; sigma3: the side walls' mean stress), E and nu secant at half the peak q, the
peak sigma1, CI and CD (`rockcal.labtests.damage`, in q). At sigma3 = 0 there is nothing to seat
and the side walls never touch: the test is the UCS test, to the last bit.

The test is one procedure in 2D and 3D, over the rig of the specimen's dimension
(`rig.rig_for`). With the setting `dimensions` 3 (PFC3D) the setting `confined_vessel` picks
the vessel: "cylinder" (the default), a cylinder of the width as diameter packed in a
cylindrical vessel (`specimens3d.specimen.packed_cylinder`) inside the triaxial cell, a
frictionless cylindrical wall whose radius is servo-controlled to sigma3 (`rig.cell_3d`), its
lateral strain the diametral strain; "prism", a square prism of the width's side between four
servo-controlled side walls (a polyaxial vessel, sigma2 = sigma3), its lateral strain the mean
of the two widths'. sigma1 is the platens' force over the original cross-section and the
volumetric strain axial - 2 x lateral.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Callable

import numpy as np
from pydantic import Field, model_validator

from rockcal.dem import measure
from rockcal.specimens.specimen import random_packing
from rockcal.errors import InputError
from rockcal.labtests import snapshots, ucs
from rockcal.labtests.damage import CRACK_RESPONSES, crack_stresses
from rockcal.labtests.envelope import envelope_responses
from rockcal.labtests.kind import (GENESIS, LabTest, Outline, Response, SeriesFigure, Setting, genesis_of, in_3d,
                                   series_name)
from rockcal.labtests.lab_values import LabValues
from rockcal.labtests.plausible import check_plausible
from rockcal.labtests.loading import (DISTRIBUTED_DAMAGE, RAMP_STEPS_PER_ROW, Loading, Reading,
                                      load_to_failure)
from rockcal.labtests.result import LabResult, run_fields
from rockcal.labtests.rig import rig_for
from rockcal.materials import BondedParams, as_params
from rockcal.params import MPa

MAX_CONFINEMENT_MPA = 1000.0
# The least confinement the side walls hold: a wall's stress scatters by about 0.1 MPa as the
# specimen loads, whatever sigma3 (`rig.servo`: 95 % of the readings within 0.05-0.2 MPa of
# sigma3 on 8 x 16 mm specimens at sigma3 0.01-5 MPa, within 0.01 MPa on 20 x 40 mm ones), so
# below it the confinement held is mostly that scatter; and near zero the seating, which
# settles each wall within 0.5 % of sigma3, cannot settle at all (1e-12 MPa: not in 40,000
# steps). 0 is the unconfined test (the UCS test, side walls away).
MIN_CONFINEMENT_MPA = 0.1
CURVE_COLUMNS = ("axial_strain", "lateral_strain", "deviatoric_stress_MPa", "broken_bonds",
                 "confinement_MPa")


@dataclass
class BiaxialResult(LabResult):
    """Responses of a confined compression test; its curve's columns: CURVE_COLUMNS (strains
    from the start of axial loading, q = sigma1 - sigma3 and sigma3 measured, MPa)."""

    confinement_MPa: float  # the sigma3 asked for
    sigma1_MPa: float  # peak axial stress
    q_MPa: float  # peak deviatoric stress
    E_GPa: float
    nu: float
    peak_axial_strain: float
    sigma3_MPa: float  # the side walls' mean stress over the loading up to the peak
    seating_steps: int
    ci_MPa: float
    ci_ratio: float
    ci_strain_MPa: float
    ci_strain_ratio: float
    cd_MPa: float
    cd_ratio: float


def check_confinement(confinement_mpa) -> None:
    """A confining stress is 0 (unconfined) or a number in [MIN_CONFINEMENT_MPA,
    MAX_CONFINEMENT_MPA] MPa: for the command's option and the campaign's targets alike."""
    if isinstance(confinement_mpa, (int, float)) and confinement_mpa > MAX_CONFINEMENT_MPA:
        check_plausible("confinement_mpa", "confinement_mpa", confinement_mpa)  # given in Pa?
    if not (isinstance(confinement_mpa, (int, float)) and not isinstance(confinement_mpa, bool)
            and 0 <= confinement_mpa <= MAX_CONFINEMENT_MPA):
        raise InputError("confinement_mpa", f"must be a number in [0, {MAX_CONFINEMENT_MPA:g}] MPa, "
                                            f"got {confinement_mpa!r}")
    if 0 < confinement_mpa < MIN_CONFINEMENT_MPA:
        raise InputError("confinement_mpa", f"must be 0 (unconfined, the UCS test) or at least "
                                            f"{MIN_CONFINEMENT_MPA:g} MPa (the side walls' servo holds "
                                            f"sigma3 to about {MIN_CONFINEMENT_MPA:g} MPa), got {confinement_mpa!r}")


# Confinements in one series: each is a DEM run (on every packing asked for), and a lab's
# strength envelope is read on a handful (the ISRM suggests at least 5)
MAX_CONFINEMENTS = 20


def check_confinements(values: list) -> None:
    """A series of confinements: not empty, at most MAX_CONFINEMENTS, each valid, increasing
    without repeats."""
    if len(values) == 0:
        raise InputError("confinement_mpa", "needs at least one confinement")
    if len(values) > MAX_CONFINEMENTS:
        raise InputError("confinement_mpa", f"at most {MAX_CONFINEMENTS} confinements in a series (each a DEM "
                                            f"run), got {len(values):,}")
    for value in values:
        check_confinement(value)
    repeated = sorted({a for a in values if values.count(a) > 1})
    if repeated:
        raise InputError("confinement_mpa", f"{repeated[0]:g} MPa is given {values.count(repeated[0])} times: "
                                            f"each confinement once, got {list(values)}")
    if any(b <= a for a, b in zip(values, values[1:])):
        raise InputError("confinement_mpa", f"must increase without repeats, got {list(values)}")


def simulate_biaxial(params: BondedParams | dict | None = None, specimen=None,
                     confinement_mpa: float = 10.0, *, rate_factor: float = 1.0,
                     max_axial_strain: float = ucs.DEFAULT_MAX_AXIAL_STRAIN,
                     strain: str = ucs.DEFAULT_STRAIN, stop_fraction: float = ucs.POST_PEAK_FRACTION,
                     contact_stiffness: str | None = None,
                     progress: Callable[[float, float], None] | None = None) -> BiaxialResult:
    """Run the confined compression test at `confinement_mpa` on a 2D specimen or a 3D prism;
    the other arguments as `ucs.simulate_ucs` (the stop fraction applies to q).
    progress(axial strain, q MPa)."""
    started = time.perf_counter()
    params = as_params(params)
    check_confinement(confinement_mpa)
    ucs.check_reading(max_axial_strain, strain, stop_fraction)
    specimen = specimen or random_packing(50.0, 100.0)
    rig = rig_for(specimen)
    rig.check_gauges(specimen)

    def start() -> tuple:
        sigma3 = confinement_mpa * MPa
        platens = rig.platens(specimen, params, ucs.DENSITY_SCALED_SPEED * rate_factor, contact_stiffness,
                              side_walls=sigma3 > 0)
        state = platens.state
        state.scale_density()
        sides = rig.side_walls(platens, specimen, sigma3) if sigma3 > 0 else None
        seating_steps = 0 if sides is None else sides.seat()
        platens.zero()
        read = ConfinedReadings(platens, rig.gauge(specimen, state), sides, strain)
        loading = Loading(RAMP_STEPS_PER_ROW * platens.rows / ucs.DENSITY_SCALED_SPEED,
                          DISTRIBUTED_DAMAGE)
        state.step, seated_at = 0, state.step  # the loading counts its own steps (its ramp)
        return platens, sides, read, loading, seating_steps, seated_at, []

    objects = snapshots.resume(start)  # a run stopped part way goes on from its snapshot
    platens, sides, read, loading, seating_steps, seated_at, samples = objects
    state = platens.state
    started -= snapshots.earlier_s()
    curve = load_to_failure(platens, loading, read,
                            lambda reading: loading.fallen_below(stop_fraction, reading.load),
                            max_axial_strain, progress=progress,
                            control=None if sides is None else sides.update,
                            control_steps=1 if sides is None else sides.steps,
                            samples=samples, snapshot=snapshots.saver(objects))
    state.step += seated_at
    curve = read.curve(curve)
    return BiaxialResult(**confined_readings(curve, confinement_mpa, rig.lateral_strains),
                         seating_steps=seating_steps, curve=curve, **run_fields(state, specimen, started))


class ConfinedReadings:
    """A confined test's reading after each chunk of its loading (2D or 3D rig alike): q =
    the `platens`' load over their original area less sigma3, the `sides`' mean stress (None:
    unconfined, sigma3 = 0), against the axial strain from the `gauge` or the platens
    (`strain`); and the bonds broken and sigma3 at each reading, from the start of loading."""

    def __init__(self, platens, gauge, sides, strain: str):
        self.platens, self.gauge, self.sides, self.strain = platens, gauge, sides, strain
        self.broken = [0]
        self.confining = [0.0 if sides is None else sides.stress_Pa() / MPa]

    def __call__(self) -> Reading:
        platens = self.platens
        self.broken.append(platens.state.n_broken())
        gauge_axial, lateral = self.gauge.strains()
        axial = platens.strain() if self.strain == "platen" else gauge_axial
        s3 = 0.0 if self.sides is None else self.sides.stress_Pa()
        self.confining.append(s3 / MPa)
        q = platens.load() / platens.area_m2 - s3
        return Reading(q, axial, (axial, lateral, q / 1e6))

    def curve(self, samples: np.ndarray) -> np.ndarray:
        """The test's curve (CURVE_COLUMNS) from `load_to_failure`'s samples."""
        return np.column_stack([samples, self.broken, self.confining])


def confined_readings(curve: np.ndarray, confinement_mpa: float, lateral_strains: int = 1) -> dict:
    """The responses of a confined test's `curve` (CURVE_COLUMNS) at `confinement_mpa`: E and
    nu secant at half the peak q, the peak q and sigma1 = q + sigma3 there, the side walls'
    mean sigma3 up to the peak, CI and CD in q from the volumetric strain axial -
    `lateral_strains` x lateral (1: 2D's areal strain; 2: a 3D prism's, two lateral strains)."""
    axial, lateral, q, broken, sigma3 = curve.T
    E_MPa, nu, k = measure.secant_at_half_peak(axial, lateral, q)
    return dict(confinement_MPa=float(confinement_mpa), sigma1_MPa=float(q[k] + sigma3[k]),
                q_MPa=float(q[k]), E_GPa=E_MPa / 1e3, nu=nu, peak_axial_strain=float(axial[k]),
                sigma3_MPa=float(sigma3[1:k + 1].mean()) if k else float(confinement_mpa),
                **crack_stresses(axial, lateral, q, broken, lateral_strains).responses)


def _run(params: BondedParams, specimen, s: dict, progress) -> BiaxialResult:
    return simulate_biaxial(params, specimen, s["confinement_mpa"], strain=s["strain"],
                            stop_fraction=s["stop_fraction"],
                            contact_stiffness=s["contact_stiffness"], progress=progress)


def _check(s: dict) -> None:
    ucs.TEST.check(s)  # in 3D: the specimen's size and spheres as the UCS cylinder's
    check_confinement(s["confinement_mpa"])
    if not in_3d(s) and s["confined_vessel"] != "prism":
        raise InputError("confined_vessel", f"the 2D confined test is a rectangle between two side walls "
                                            f"(prism); {s['confined_vessel']!r} is a 3D vessel (dimensions = 3)")
    if in_3d(s) and s.get("grain_shape", "ball") != "ball":  # its side walls' servo does not settle them yet
        raise InputError("grain_shape", f"the 3D confined test's specimen is of balls (grain_shape = \"ball\"), got "
                                        f"{s['grain_shape']!r} with dimensions = 3")


def _in_cell(s: dict) -> bool:
    return in_3d(s) and s["confined_vessel"] == "cylinder"


def _specimen(s: dict):
    if in_3d(s):  # a cylinder packed in its cell, or the cached cuboid the UCS cylinder is carved from
        from rockcal.specimens3d.specimen import packed_cylinder, random_specimen

        size = (s["width_mm"], s["height_mm"], s["rmin_mm"], s["radius_ratio"], s["seed"], genesis_of(s))
        if _in_cell(s):
            return packed_cylinder(*size)
        return random_specimen("cuboid", *size, grain_shape=s.get("grain_shape", "ball"))
    return ucs.TEST.make(s)


def _outline(s: dict) -> Outline:
    shape = "biaxial {0:g} x {1:g} mm"
    if in_3d(s):
        shape = "confined cylinder Ø{0:g} x {1:g} mm (triaxial cell)" if _in_cell(s) else \
            "confined (square prism, polyaxial walls) {0:g} x {0:g} x {1:g} mm"
    vessel = (s["width_mm"], s["width_mm"], s["height_mm"]) if in_3d(s) else None
    return Outline(shape.format(s["width_mm"], s["height_mm"]), s["width_mm"], s["height_mm"], vessel_mm=vessel,
                   vessel_cylinder=_in_cell(s), share=np.pi / 4 if _in_cell(s) else 1.0)


def envelope(runs: list[dict]) -> dict:
    """The peaks of a series of runs (their responses, confinements increasing) and, over two
    confinements or more, the strength envelope through them (`rockcal.labtests.envelope`)."""
    sigma3 = [r["confinement_MPa"] for r in runs]
    sigma1 = [r["sigma1_MPa"] for r in runs]
    peaks = {"confinement_MPa": sigma3, "sigma1_MPa": sigma1}
    return peaks | envelope_responses(sigma3, sigma1) if len(runs) > 1 else peaks


ENVELOPE_TARGETS = ("phi_deg", "c_MPa", "m_i", "sigma_ci_MPa")


class BiaxialValues(LabValues):
    """Lab results of confined compression at a series of confinements: the peaks, or the
    envelope fitted through them, or both."""

    confinement_mpa: list[float] = Field(description="The confinements σ3 tested, MPa: increasing, each 0 "
                                         f"(unconfined) or ≥ {MIN_CONFINEMENT_MPA:g}; each is one run at every "
                                         "parameter set.")
    sigma1_MPa: list[float] | None = Field(None, description="Peak σ1 at each confinement, MPa (named "
                                           "sigma1_MPa@<σ3>MPa in spread, weights and the report).")
    phi_deg: float | None = Field(None, gt=0, lt=90, description="Mohr–Coulomb friction angle φ, degrees.")
    c_MPa: float | None = Field(None, gt=0, description="Mohr–Coulomb cohesion c, MPa.")
    m_i: float | None = Field(None, gt=0, description="Hoek–Brown m_i of the intact rock.")
    sigma_ci_MPa: float | None = Field(None, gt=0, description="Hoek–Brown σ_ci of the intact rock, MPa.")

    def scalars(self) -> dict[str, float]:
        """The envelope's values given, then each peak by its confinement (sigma1_MPa@5MPa)."""
        given = {k: getattr(self, k) for k in ENVELOPE_TARGETS if getattr(self, k) is not None}
        return given | {series_name("sigma1_MPa", s3, "MPa"): s1
                        for s3, s1 in zip(self.confinement_mpa, self.sigma1_MPa or [])}

    @model_validator(mode="before")
    @classmethod
    def _confinements(cls, data):
        values = data.get("confinement_mpa") if isinstance(data, dict) else None
        if isinstance(values, list):
            try:
                check_confinements(values)
            except InputError as exc:
                raise ValueError(f"confinement_mpa: {exc.problem}") from None
        return data

    @model_validator(mode="after")
    def _peaks(self):
        s3, s1 = self.confinement_mpa, self.sigma1_MPa
        if s1 is not None and len(s1) != len(s3):
            raise ValueError(f"sigma1_MPa: one peak per confinement, got {len(s1)} for {len(s3)}")
        if s1 is not None and any(not a < b for a, b in zip(s3, s1)):
            raise ValueError(f"sigma1_MPa: each peak must exceed its confinement, got {s1} at {s3}")
        fitted = [k for k in ENVELOPE_TARGETS if getattr(self, k) is not None]
        if fitted and len(s3) < 2:
            raise ValueError(f"confinement_mpa: the envelope ({fitted[0]}) needs two confinements or more")
        if not fitted and s1 is None:
            raise ValueError(f"give sigma1_MPa or one of {', '.join(ENVELOPE_TARGETS)}")
        return self


SERIES_FIGURES = (
    SeriesFigure("Strength envelope", "Peak σ1 at each confinement σ3 with the least-squares "
                 "Mohr–Coulomb line and Hoek's regression of the intact Hoek–Brown curve.", "strength_envelope",
                 min_runs=2),
    SeriesFigure("Confined compression curves", "Deviatoric stress q = σ1 − σ3 against the axial "
                 "(solid) and lateral (dashed) strain at each confinement.", "confined_curves"),
)

CONFINEMENT = Setting("confinement_mpa", 0.0, "MPa", check_confinement,
                      f"confining stress sigma3 (side walls servo-controlled), MPa: 0 or at least "
                      f"{MIN_CONFINEMENT_MPA:g}; a list, e.g. 0,5,10,20, runs one test per value and "
                      "fits the envelope",
                      series=True, check_series=check_confinements)

TEST = LabTest(
    lab_values=BiaxialValues,
    name="biaxial", title="confined compression",
    help="Confined compression at sigma3 (a list: one run each, and the strength envelope): in 2D a "
         "rectangle between two servo side walls, with --dimensions 3 a cylinder in a triaxial cell "
         "(servo-controlled radius) or, --confined-vessel prism, a square prism between four servo walls.",
    responses=(Response("sigma1_MPa", "MPa", label="peak axial stress sigma1"),
               Response("confinement_MPa", "MPa", target=False, label="confinement set"),
               Response("q_MPa", "MPa", target=False), Response("E_GPa", "GPa", target=False),
               Response("nu", "", target=False),
               Response("peak_axial_strain", "", target=False),
               Response("sigma3_MPa", "MPa", target=False, label="sigma3 the walls held at peak"),
               *CRACK_RESPONSES),
    # the later settings last: at their old values (kind.LATER_SETTINGS) a run's key leaves them out
    settings=("width_mm", "height_mm", "rmin_mm", "radius_ratio", "seed", *GENESIS, "strain",
              "stop_fraction", "contact_stiffness", "confinement_mpa", "grain_shape", "dimensions",
              "confined_vessel"),
    check=_check, make=_specimen, run=_run,
    reading=lambda strain, q_MPa: f"strain {100 * strain:.3f} %, q {q_MPa:.1f} MPa",
    outline=_outline,
    setting_help=(("width_mm", "Specimen width, mm (in 3D the cylinder's diameter, the square prism's side)."),
                  ("height_mm", "Specimen height, mm.")),
    # the full-size granite's confined runs at sigma3 0, 5, 10, 20 MPa took 1.0, 1.8, 1.7 and
    # 2.2 x its UCS run (the seating, and a higher peak further on)
    time_factor=lambda s: 1.7,
    curve_columns=CURVE_COLUMNS, own_settings=(CONFINEMENT,), combine=envelope,
    plot="deviatoric_stress_strain", series_figures=SERIES_FIGURES,
    combined_responses=(
        Response("phi_deg", "degrees", label="friction angle phi"), Response("c_MPa", "MPa", label="cohesion c"),
        Response("m_i", "", label="Hoek-Brown m_i"), Response("sigma_ci_MPa", "MPa", label="Hoek-Brown sigma_ci"),
        Response("mc_sigma_c_MPa", "MPa", target=False, label="Mohr-Coulomb UCS"),
        Response("mc_r2", "", target=False, label="Mohr-Coulomb R²"),
        Response("mc_rms_MPa", "MPa", target=False, label="Mohr-Coulomb rms misfit"),
        Response("hb_r2", "", target=False, label="Hoek-Brown R²"),
        Response("hb_rms_MPa", "MPa", target=False, label="Hoek-Brown rms misfit")))
