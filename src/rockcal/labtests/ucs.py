"""The virtual uniaxial compression test: frictionless platens closing at constant speed.

Readings as PFC users make them: UCS = peak axial stress; E and nu secant at half the peak;
nu from the lateral displacement of the sides. The axial strain is read from the platen
separation (FISHTank's wall-based strain, "platen") or from the specimen's own top and bottom
particles, like gauges on a lab sample ("gauge"). The test stops once the stress has fallen
below a fraction of the peak (FISHTank's ct_loadFac), or at the maximum axial strain.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Callable

import numpy as np

from rockcal.dem import measure
from rockcal.dem.laws import BROKEN_SHEAR, BROKEN_TENSION
from rockcal.dem.simulate import BOTTOM, TOP, THICKNESS_M, advance, new_state
from rockcal.dem.specimen import Specimen, check_geometry, random_packing
from rockcal.errors import InputError
from rockcal.labtests.kind import GENESIS, LabTest, Outline, Response, genesis_of
from rockcal.labtests.loading import DISTRIBUTED_DAMAGE, Loading
from rockcal.labtests.result import LabResult
from rockcal.params import MicroParams, make_params

POST_PEAK_FRACTION = 0.7
STRAIN_READINGS = ("gauge", "platen")
DEFAULT_STRAIN = "gauge"
DEFAULT_MAX_AXIAL_STRAIN = 0.02
# Quasi-static loading: axial strain per step = STRAIN_PER_STEP_PER_ROW / (rows of particles),
# so the number of wave transits to the peak is the same for every specimen size, ramped in
# over RAMP_STEPS_PER_ROW x rows steps. The elastic part is rate-insensitive; where bonds break
# the platens slow down (`rockcal.labtests.loading`).
STRAIN_PER_STEP_PER_ROW = 2e-5
RAMP_STEPS_PER_ROW = 10


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
                 progress: Callable[[float, float], None] | None = None) -> UCSResult:
    """Run the UCS test; defaults: granite parameters on the paper's 50 x 100 mm specimen.

    rate_factor scales the loading speed; strain is the axial strain reading ("gauge" or
    "platen"); the test stops past the peak once the stress is below stop_fraction x peak;
    progress(axial_strain, stress_MPa) is called as it goes.
    """
    started = time.perf_counter()
    if not isinstance(params, MicroParams):
        params = make_params(params or {})
    if not 0 < max_axial_strain <= 0.5:
        raise InputError("max_axial_strain", f"must be in (0, 0.5], got {max_axial_strain}")
    if strain not in STRAIN_READINGS:
        raise InputError("strain", f"must be one of {', '.join(STRAIN_READINGS)}, got {strain!r}")
    if not 0 < stop_fraction < 1:
        raise InputError("stop_fraction", f"must be in (0, 1), got {stop_fraction}")
    specimen = specimen or random_packing(50.0, 100.0)
    pos, radius = specimen.pos, specimen.radius
    bottom, top = (pos[:, 1] - radius).min(), (pos[:, 1] + radius).max()
    state = new_state(pos, radius, specimen.bonds, params, walls=(0.0, 0.0, bottom, top),
                      wall_active=(False, False, True, True), bond_draws=specimen.bond_draws)
    rows = (top - bottom) / (2 * radius.mean())
    strain_per_step = rate_factor * STRAIN_PER_STEP_PER_ROW / rows
    speed = 0.5 * strain_per_step * (top - bottom) / state.dt
    chunk = max(5, int(rows / 8))

    sets = measure.boundary_sets(pos, radius, 0.5 * radius.min())
    width0, height0 = measure.gauge_lengths(state.pos, sets)
    area = specimen.width_m * THICKNESS_M
    rows_out = [(0.0, 0.0, 0.0)]
    loading = Loading(RAMP_STEPS_PER_ROW * rows, DISTRIBUTED_DAMAGE)
    while True:
        factor = loading.speed(state.step, np.count_nonzero(state.bond_state), chunk)
        state.wall_vel[BOTTOM], state.wall_vel[TOP] = speed * factor, -speed * factor
        advance(state, chunk)
        width, height = measure.gauge_lengths(state.pos, sets)
        if strain == "platen":
            axial = 1.0 - (state.walls[TOP] - state.walls[BOTTOM]) / (top - bottom)
        else:
            axial = (height0 - height) / height0
        lateral = (width - width0) / width0
        f = state.total_wall_force()
        stress = 0.5 * (f[BOTTOM] + f[TOP]) / area
        rows_out.append((axial, lateral, stress / 1e6))
        loading.update(state.step, stress)
        if progress:
            progress(axial, stress / 1e6)
        if loading.fallen_below(stop_fraction, stress) or axial >= max_axial_strain:
            break

    curve = np.array(rows_out)
    E_MPa, nu, k = measure.secant_at_half_peak(curve[:, 0], curve[:, 1], curve[:, 2])
    return UCSResult(
        E_GPa=E_MPa / 1e3, nu=nu, strain=strain, ucs_MPa=float(curve[k, 2]),
        peak_axial_strain=float(curve[k, 0]),
        n_particles=specimen.n_particles, n_bonds=len(specimen.bonds),
        n_broken_tension=state.n_broken(BROKEN_TENSION),
        n_broken_shear=state.n_broken(BROKEN_SHEAR), steps=state.step,
        wall_s=time.perf_counter() - started, curve=curve, positions=state.pos.copy(),
        radius=radius, cracks=measure.cracks(state.bond_state, state.bond_break_xy))


def _check(s: dict) -> None:
    check_geometry(s["width_mm"], s["height_mm"], s["rmin_mm"], s["radius_ratio"])


def _specimen(s: dict) -> Specimen:
    return random_packing(s["width_mm"], s["height_mm"], s["rmin_mm"], s["radius_ratio"], s["seed"],
                          genesis_of(s))


def _run(params: MicroParams, specimen: Specimen, s: dict, progress) -> UCSResult:
    return simulate_ucs(params, specimen, strain=s["strain"], stop_fraction=s["stop_fraction"],
                        progress=progress)


TEST = LabTest(
    name="ucs", title="UCS",
    responses=(Response("E_GPa", "GPa"), Response("nu", ""), Response("ucs_MPa", "MPa"),
               Response("peak_axial_strain", "", target=False)),
    settings=("width_mm", "height_mm", "rmin_mm", "radius_ratio", "seed", *GENESIS, "strain",
              "stop_fraction"),
    check=_check, make=_specimen, run=_run,
    reading=lambda strain, stress_MPa: f"strain {100 * strain:.3f} %, {stress_MPa:.1f} MPa",
    outline=lambda s: Outline(f"UCS {s['width_mm']:g} x {s['height_mm']:g} mm", s["width_mm"],
                              s["height_mm"]))
