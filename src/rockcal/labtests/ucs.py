"""The virtual uniaxial compression test: frictionless platens closing at constant speed.

Readings as PFC users make them: UCS = peak axial stress; E and nu secant at half the peak;
nu from the lateral displacement of the sides; the crack-initiation and crack-damage stresses
from the curve and its count of broken bonds (`rockcal.labtests.damage`). The axial strain is
read from the platen separation (FISHTank's wall-based strain, "platen") or from the specimen's
own top and bottom particles, like gauges on a lab sample ("gauge"). The platens
(`rockcal.labtests.rig`) close at a quasi-static speed on the density-scaled specimen
(`simulate.scale_density`), slower where bonds break (`rockcal.labtests.loading`); the test
stops once the stress has fallen below a fraction of the peak (FISHTank's ct_loadFac), or at
the maximum axial strain.

The test is one procedure in 2D and 3D, over the rig of the specimen's dimension
(`rig.rig_for`): with the setting `dimensions` 3 (PFC3D) its specimen is a cylinder of the
width as diameter, its stress the platens' force over the nominal cross-section, its lateral
strain the outer spheres' radial strain and its volumetric strain axial - 2 x lateral.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Callable

import numpy as np
from pydantic import Field

from rockcal.dem import measure
from rockcal.materials.clump_templates import DEFAULT_SHAPE
from rockcal.specimens.genesis import Genesis
from rockcal.specimens.specimen import Specimen, check_geometry, hexagonal, random_packing
from rockcal.specimens3d.specimen import Specimen3D, check_size, random_specimen
from rockcal.errors import InputError
from rockcal.labtests.damage import CRACK_RESPONSES, crack_stresses
from rockcal.labtests.kind import (GENESIS, LabTest, Outline, Response, check_3d_settings, check_grain_cloud,
                                   genesis_of, in_3d)
from rockcal.labtests.lab_values import LabValues, read_curve
from rockcal.labtests.loading import (
    DISTRIBUTED_DAMAGE,
    RAMP_STEPS_PER_ROW,
    Loading,
    Reading,
    check_stop_fraction,
    load_to_failure,
)
from rockcal.labtests import snapshots
from rockcal.labtests.result import LabResult, run_fields
from rockcal.labtests.rig import rig_for
from rockcal.materials import BondedParams, as_params

POST_PEAK_FRACTION = 0.7
CRACK_TARGETS = ("ci_MPa", "ci_ratio", "cd_MPa", "cd_ratio")  # a lab reads these too
STRAIN_READINGS = ("gauge", "platen")
DEFAULT_STRAIN = "gauge"
DEFAULT_MAX_AXIAL_STRAIN = 0.02
# The specimen's masses are density-scaled (`simulate.scale_density`), so its platens close
# this much faster than an unscaled specimen's, and their ramp and the loading rule's window
# are this much shorter, for the same equilibrium: on three full-size granite specimens halving
# the speed moves E, nu and UCS by at most 1.0 %.
DENSITY_SCALED_SPEED = 1.6
COMPRESSION_CURVE = ("axial_strain", "lateral_strain", "axial_stress_MPa", "broken_bonds")


@dataclass
class UCSResult(LabResult):
    """Responses of a UCS test; its curve's columns: axial strain, lateral strain, stress MPa,
    bonds broken so far."""

    E_GPa: float
    nu: float
    strain: str  # how the axial strain was read: "gauge" or "platen"
    ucs_MPa: float
    peak_axial_strain: float
    ci_MPa: float
    ci_ratio: float
    ci_strain_MPa: float
    ci_strain_ratio: float
    cd_MPa: float
    cd_ratio: float


def check_reading(max_axial_strain: float, strain: str, stop_fraction: float) -> None:
    """The UCS test's reading options (in 2D and 3D); InputError naming the bad one."""
    if not 0 < max_axial_strain <= 0.5:
        raise InputError("max_axial_strain", f"must be in (0, 0.5], got {max_axial_strain}")
    if strain not in STRAIN_READINGS:
        raise InputError("strain", f"must be one of {', '.join(STRAIN_READINGS)}, got {strain!r}")
    check_stop_fraction(stop_fraction)


def simulate_ucs(params: BondedParams | dict | None = None, specimen=None, *,
                 rate_factor: float = 1.0, max_axial_strain: float = DEFAULT_MAX_AXIAL_STRAIN,
                 strain: str = DEFAULT_STRAIN, stop_fraction: float = POST_PEAK_FRACTION,
                 contact_stiffness: str | None = None,
                 progress: Callable[[float, float], None] | None = None) -> UCSResult:
    """Run the UCS test; defaults: granite parameters on the paper's 50 x 100 mm specimen.

    specimen: a 2D `Specimen` or a 3D `Specimen3D` (a cylinder, or a prism); rate_factor
    scales the loading speed; strain is the axial strain reading ("gauge" or "platen"); the
    test stops past the peak once the stress is below stop_fraction x peak; contact_stiffness
    is PFC's convention for kn ("pfc5" or "pfc4", `dem.simulate`; None: the engine's default,
    3D's PFC 5's alone); progress(axial_strain, stress_MPa) is called as it goes.
    """
    started = time.perf_counter()
    params = as_params(params)
    check_reading(max_axial_strain, strain, stop_fraction)
    specimen = specimen or random_packing(50.0, 100.0)
    rig = rig_for(specimen)
    rig.check_gauges(specimen)

    def start() -> tuple:
        platens = rig.platens(specimen, params, DENSITY_SCALED_SPEED * rate_factor, contact_stiffness)
        platens.state.scale_density()
        loading = Loading(RAMP_STEPS_PER_ROW * platens.rows / DENSITY_SCALED_SPEED, DISTRIBUTED_DAMAGE)
        # bonds broken so far at each reading, after the unloaded first row
        return platens, rig.gauge(specimen, platens.state), loading, [0], []

    objects = snapshots.resume(start)  # a run stopped part way goes on from its snapshot
    platens, gauge, loading, broken, samples = objects
    state = platens.state
    started -= snapshots.earlier_s()

    def read() -> Reading:
        broken.append(state.n_broken())
        gauge_axial, lateral = gauge.strains()
        axial = platens.strain() if strain == "platen" else gauge_axial
        stress = platens.load() / platens.area_m2
        return Reading(stress, axial, (axial, lateral, stress / 1e6))

    curve = load_to_failure(platens, loading, read,
                            lambda reading: loading.fallen_below(stop_fraction, reading.load),
                            max_axial_strain, progress=progress, samples=samples,
                            snapshot=snapshots.saver(objects))
    curve = np.column_stack([curve, broken])
    axial, lateral, stress, broken = curve.T
    E_MPa, nu, k = measure.secant_at_half_peak(axial, lateral, stress)
    damage = crack_stresses(axial, lateral, stress, broken, rig.lateral_strains).responses
    return UCSResult(E_GPa=E_MPa / 1e3, nu=nu, strain=strain, ucs_MPa=float(stress[k]),
                     peak_axial_strain=float(axial[k]), curve=curve, **damage,
                     **run_fields(state, specimen, started))


def _check(s: dict) -> None:
    if in_3d(s):
        return _check_3d(s)
    check_geometry(s["width_mm"], s["height_mm"], s["rmin_mm"], s["radius_ratio"])
    check_grain_cloud(s["width_mm"], s["height_mm"], s)


def _check_3d(s: dict) -> None:
    """A 3D cylinder's settings: none of the 2D engine's alone, and the size and grains
    `specimens3d.specimen.check_size` asks for."""
    check_3d_settings(s)
    check_size(s["width_mm"], s["height_mm"], s["rmin_mm"], s["radius_ratio"], s["cloud_porosity"],
               s["pressure_mpa"])


def ucs_specimen(width_mm: float = 50.0, height_mm: float = 100.0, rmin_mm: float = 0.25,
                 radius_ratio: float = 1.65, seed: int = 1, genesis: Genesis | None = None,
                 grain_shape: str = DEFAULT_SHAPE) -> Specimen:
    """The UCS test's specimen: a random packing of balls, or of rigid clumps of the template
    `grain_shape` (`materials.clump_templates`: PFC's clumped materials), whose equivalent radii are
    drawn in [R_min, radius_ratio x R_min]."""
    return random_packing(width_mm, height_mm, rmin_mm, radius_ratio, seed, genesis,
                          grain_shape=grain_shape)


def _specimen(s: dict) -> Specimen | Specimen3D:
    if in_3d(s):  # a cylinder of the width as diameter, carved from a cached cuboid packing
        return random_specimen("cylinder", s["width_mm"], s["height_mm"], s["rmin_mm"],
                               s["radius_ratio"], s["seed"], genesis_of(s),
                               grain_shape=s.get("grain_shape", DEFAULT_SHAPE))
    return ucs_specimen(s["width_mm"], s["height_mm"], s["rmin_mm"], s["radius_ratio"], s["seed"],
                        genesis_of(s), s.get("grain_shape", DEFAULT_SHAPE))


def _run(params: BondedParams, specimen: Specimen | Specimen3D, s: dict, progress) -> UCSResult:
    """The test on the specimen `_specimen` made of `s`."""
    return simulate_ucs(params, specimen, strain=s["strain"], stop_fraction=s["stop_fraction"],
                        contact_stiffness=s["contact_stiffness"], max_axial_strain=s["max_axial_strain"],
                        progress=progress)


def _hexagonal(s: dict) -> Specimen:
    if in_3d(s):
        raise InputError("packing", "a hexagonal lattice is a 2D specimen; with dimensions = 3 the "
                                    "UCS specimen is a random packing")
    if s.get("grain_shape", DEFAULT_SHAPE) != DEFAULT_SHAPE:
        raise InputError("packing", f"a hexagonal lattice is of balls, not of {s['grain_shape']} clumps: take "
                                    "the random packing, or grain_shape = \"ball\"")
    return hexagonal(s["width_mm"], s["height_mm"], s["rmin_mm"])


def _outline(s: dict) -> Outline:
    if in_3d(s):  # the cylinder keeps pi/4 of its cuboid packing's spheres
        return Outline(f"UCS cylinder Ø{s['width_mm']:g} x {s['height_mm']:g} mm", s["width_mm"],
                       s["height_mm"], np.pi / 4, (s["width_mm"], s["width_mm"], s["height_mm"]))
    return Outline(f"UCS {s['width_mm']:g} x {s['height_mm']:g} mm", s["width_mm"], s["height_mm"])


class UCSValues(LabValues):
    """Lab results of the uniaxial compression test (at least one response)."""

    E_GPa: float | None = Field(None, gt=0, description="Young's modulus E, GPa (secant at half the peak).")
    nu: float | None = Field(None, gt=0, lt=0.5, description="Poisson's ratio ν (secant at half the peak).")
    ucs_MPa: float | None = Field(None, gt=0, description="Uniaxial compressive strength, MPa.")
    ci_MPa: float | None = Field(None, gt=0, description="Crack initiation stress CI, MPa (the onset of cracking).")
    ci_ratio: float | None = Field(None, gt=0, le=1, description="CI / UCS.")
    cd_MPa: float | None = Field(None, gt=0, description="Crack damage stress CD, MPa (the reversal of the volumetric strain).")
    cd_ratio: float | None = Field(None, gt=0, le=1, description="CD / UCS.")
    curve: Path | None = Field(None, description="CSV of the measured curve: axial strain, axial stress (MPa); "
                               "gives E and UCS when they are not given, and the curve's fit (RE, CC).")

    def derived(self) -> tuple[str, ...]:
        return ("E_GPa", "ucs_MPa") if self.curve is not None else ()

    def measured(self) -> dict[str, float]:
        """The responses given, completed from the measured curve: E secant at half the peak,
        UCS = the peak."""
        targets = self.scalars()
        curve = self.measured_curve()
        if curve is not None:
            E_MPa, _, peak = measure.secant_at_half_peak(curve[:, 0], np.zeros(len(curve)), curve[:, 1])
            targets.setdefault("E_GPa", E_MPa / 1e3)
            targets.setdefault("ucs_MPa", float(curve[peak, 1]))
        return targets

    def measured_curve(self):
        if self.curve is None:
            return None
        return read_curve(self.curve)


TEST = LabTest(
    lab_values=UCSValues,
    name="ucs", title="UCS",
    help="Uniaxial compression test: E and nu (secant at half peak), UCS, stress-strain curve.",
    responses=(Response("E_GPa", "GPa", label="E"), Response("nu", "", label="Poisson's ratio"),
               Response("ucs_MPa", "MPa", label="UCS"),
               Response("peak_axial_strain", "", target=False, label="axial strain at peak"),
               *(replace(r, target=r.name in CRACK_TARGETS) for r in CRACK_RESPONSES)),
    settings=("width_mm", "height_mm", "rmin_mm", "radius_ratio", "seed", *GENESIS, "strain",
              "stop_fraction", "contact_stiffness", "max_axial_strain", "grain_shape",
              "dimensions"),  # the later settings last, at their defaults out of a run's key
    strength="ucs_MPa",
    setting_help=(("width_mm", "Specimen width, mm (in 3D the cylinder's diameter)."),
                  ("height_mm", "Specimen height, mm.")),
    plot="stress_strain",
    hexagonal=_hexagonal,
    check=_check, make=_specimen, run=_run,
    reading=lambda strain, stress_MPa: f"strain {100 * strain:.3f} %, {stress_MPa:.1f} MPa",
    outline=_outline,
    curve_columns=COMPRESSION_CURVE,
    revision=4)  # part of every stored UCS run's key: raise it when the test's numbers change
                 # (what changed in each revision: CHANGELOG.md)
