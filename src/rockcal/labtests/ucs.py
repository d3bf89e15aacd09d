"""The virtual uniaxial compression test: frictionless platens closing at constant speed.

Readings as PFC users make them: UCS = peak axial stress; E and nu secant at half the peak;
nu from the lateral displacement of the sides. The axial strain is read from the platen
separation (FISHTank's wall-based strain, "platen") or from the specimen's own top and bottom
particles, like gauges on a lab sample ("gauge"). The platens (`rockcal.labtests.platens`)
close at a quasi-static speed on the density-scaled specimen (`simulate.scale_density`), slower
where bonds break (`rockcal.labtests.loading`); the test stops once the stress has fallen below
a fraction of the peak (FISHTank's ct_loadFac), or at the maximum axial strain.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Callable

from rockcal.dem import measure
from rockcal.dem.simulate import BOTTOM, DEFAULT_CONTACT_STIFFNESS, TOP, THICKNESS_M, scale_density
from rockcal.dem.specimen import Specimen, check_geometry, random_packing
from rockcal.errors import InputError
from rockcal.labtests.kind import GENESIS, LabTest, Outline, Response, genesis_of
from rockcal.labtests.loading import (DISTRIBUTED_DAMAGE, RAMP_STEPS_PER_ROW, Loading, Reading,
                                      check_stop_fraction, load_to_failure)
from rockcal.labtests.platens import Platens
from rockcal.labtests.result import LabResult, run_fields
from rockcal.params import MicroParams, make_params

POST_PEAK_FRACTION = 0.7
STRAIN_READINGS = ("gauge", "platen")
DEFAULT_STRAIN = "gauge"
DEFAULT_MAX_AXIAL_STRAIN = 0.02
# The specimen's masses are density-scaled (`simulate.scale_density`), so its platens close
# this much faster than an unscaled specimen's, and their ramp and the loading rule's window
# are this much shorter, for the same equilibrium: on three full-size granite specimens halving
# the speed moves E, nu and UCS by at most 1.0 %.
DENSITY_SCALED_SPEED = 1.6


@dataclass
class UCSResult(LabResult):
    """Responses of a UCS test; its curve's columns: axial strain, lateral strain, stress MPa."""

    E_GPa: float
    nu: float
    strain: str  # how the axial strain was read: "gauge" or "platen"
    ucs_MPa: float
    peak_axial_strain: float


def simulate_ucs(params: MicroParams | dict | None = None, specimen: Specimen | None = None, *,
                 rate_factor: float = 1.0, max_axial_strain: float = DEFAULT_MAX_AXIAL_STRAIN,
                 strain: str = DEFAULT_STRAIN, stop_fraction: float = POST_PEAK_FRACTION,
                 contact_stiffness: str = DEFAULT_CONTACT_STIFFNESS,
                 progress: Callable[[float, float], None] | None = None) -> UCSResult:
    """Run the UCS test; defaults: granite parameters on the paper's 50 x 100 mm specimen.

    rate_factor scales the loading speed; strain is the axial strain reading ("gauge" or
    "platen"); the test stops past the peak once the stress is below stop_fraction x peak;
    contact_stiffness is PFC's convention for kn ("pfc5" or "pfc4", `dem.simulate`);
    progress(axial_strain, stress_MPa) is called as it goes.
    """
    started = time.perf_counter()
    if not isinstance(params, MicroParams):
        params = make_params(params or {})
    if not 0 < max_axial_strain <= 0.5:
        raise InputError("max_axial_strain", f"must be in (0, 0.5], got {max_axial_strain}")
    if strain not in STRAIN_READINGS:
        raise InputError("strain", f"must be one of {', '.join(STRAIN_READINGS)}, got {strain!r}")
    check_stop_fraction(stop_fraction)
    specimen = specimen or random_packing(50.0, 100.0)
    platens = Platens(specimen, params, DENSITY_SCALED_SPEED * rate_factor, contact_stiffness)
    state, bottom, top = platens.state, platens.bottom, platens.top
    scale_density(state)
    sets = measure.boundary_sets(specimen.pos, specimen.radius, 0.5 * specimen.radius.min())
    width0, height0 = measure.gauge_lengths(state.particles.pos, sets)
    area = specimen.width_m * THICKNESS_M

    def read() -> Reading:
        width, height = measure.gauge_lengths(state.particles.pos, sets)
        if strain == "platen":
            axial = 1.0 - (state.walls.pos[TOP] - state.walls.pos[BOTTOM]) / (top - bottom)
        else:
            axial = (height0 - height) / height0
        stress = platens.load() / area
        return Reading(stress, axial, (axial, (width - width0) / width0, stress / 1e6))

    loading = Loading(RAMP_STEPS_PER_ROW * platens.rows / DENSITY_SCALED_SPEED, DISTRIBUTED_DAMAGE)
    curve = load_to_failure(state, loading, platens.chunk, platens.move, read,
                            lambda reading: loading.fallen_below(stop_fraction, reading.load),
                            max_axial_strain, progress=progress)
    E_MPa, nu, k = measure.secant_at_half_peak(curve[:, 0], curve[:, 1], curve[:, 2])
    return UCSResult(E_GPa=E_MPa / 1e3, nu=nu, strain=strain, ucs_MPa=float(curve[k, 2]),
                     peak_axial_strain=float(curve[k, 0]), curve=curve,
                     **run_fields(state, specimen, started))


def _check(s: dict) -> None:
    check_geometry(s["width_mm"], s["height_mm"], s["rmin_mm"], s["radius_ratio"])


def _specimen(s: dict) -> Specimen:
    return random_packing(s["width_mm"], s["height_mm"], s["rmin_mm"], s["radius_ratio"], s["seed"],
                          genesis_of(s))


def _run(params: MicroParams, specimen: Specimen, s: dict, progress) -> UCSResult:
    return simulate_ucs(params, specimen, strain=s["strain"], stop_fraction=s["stop_fraction"],
                        contact_stiffness=s["contact_stiffness"], progress=progress)


TEST = LabTest(
    name="ucs", title="UCS",
    responses=(Response("E_GPa", "GPa"), Response("nu", ""), Response("ucs_MPa", "MPa"),
               Response("peak_axial_strain", "", target=False)),
    settings=("width_mm", "height_mm", "rmin_mm", "radius_ratio", "seed", *GENESIS, "strain",
              "stop_fraction", "contact_stiffness"),
    check=_check, make=_specimen, run=_run,
    reading=lambda strain, stress_MPa: f"strain {100 * strain:.3f} %, {stress_MPa:.1f} MPa",
    outline=lambda s: Outline(f"UCS {s['width_mm']:g} x {s['height_mm']:g} mm", s["width_mm"],
                              s["height_mm"]),
    revision=3)  # part of every stored UCS run's key: raise it when the test's numbers change
                 # (what changed in each revision: CHANGELOG.md)
