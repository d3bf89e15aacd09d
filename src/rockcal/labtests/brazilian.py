"""Virtual Brazilian (splitting tensile) test: a disk between two frictionless platens.

The disk is carved from a square packing; the platens are the UCS test's
(`rockcal.labtests.rig`), closing at the same quasi-static speed (slower where bonds break,
full speed again past the peak; the test stops when the load has fallen below
POST_PEAK_FRACTION of the peak, as in the bending test: a bond breaking under a platen drops the
load for a while without splitting the disk). Tensile strength sigma_t = 2 P / (pi D t)
(ISRM 1978; ASTM D3967) with P the peak load per metre of thickness.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Callable

import numpy as np
from pydantic import Field

from rockcal.dem.carving import inside_circle, keep_particles
from rockcal.dem.genesis import Genesis
from rockcal.dem.simulate import DEFAULT_CONTACT_STIFFNESS
from rockcal.dem.specimen import Specimen, check_geometry, random_packing
from rockcal.errors import InputError, fields_named
from rockcal.labtests.kind import (
    GENESIS,
    LabTest,
    Outline,
    Response,
    check_grain_cloud,
    genesis_of,
    load_reading,
)
from rockcal.labtests.lab_values import LabValues
from rockcal.labtests.loading import (
    LOCALISED_DAMAGE,
    RAMP_STEPS_PER_ROW,
    Loading,
    Reading,
    load_to_failure,
)
from rockcal.labtests.result import LabResult, run_fields
from rockcal.labtests.rig import Platens
from rockcal.materials import BondedParams, as_params

DEFAULT_MAX_STRAIN = 0.02  # platen closure / diameter at which the test stops at the latest
# A platen first bears on one or two particles; when their bonds break the load drops and comes
# back. The disk counts as split only once the load has fallen below POST_PEAK_FRACTION of the
# peak (as in the bending test) with the platens closed by one more mean particle radius since.
POST_PEAK_FRACTION = 0.3


@dataclass
class BrazilianResult(LabResult):
    """Responses of a Brazilian test; its curve's columns: platen closure mm, load kN per m."""

    sigma_t_MPa: float
    P_max_kN_per_m: float
    displacement_at_peak_mm: float
    diameter_mm: float


def check_disk(diameter_mm: float, rmin_mm: float, radius_ratio: float) -> None:
    """Reject a disk its particles cannot fill, naming the field (the square packing it is
    carved from is the diameter wide and high)."""
    if not (np.isfinite(diameter_mm) and diameter_mm > 0):
        raise InputError("diameter_mm", f"must be a finite number > 0, got {diameter_mm}")
    with fields_named({"width_mm": "diameter_mm", "height_mm": "diameter_mm"}):
        check_geometry(diameter_mm, diameter_mm, rmin_mm, radius_ratio)


def brazilian_disk(diameter_mm: float = 50.0, rmin_mm: float = 0.25, radius_ratio: float = 1.65,
                   seed: int = 1, genesis: Genesis | None = None) -> Specimen:
    """A disk of the given diameter carved from a square packing of the same size."""
    check_disk(diameter_mm, rmin_mm, radius_ratio)
    spec = random_packing(diameter_mm, diameter_mm, rmin_mm, radius_ratio, seed, genesis)
    r = 0.5e-3 * diameter_mm
    keep = inside_circle(spec.pos, spec.radius, (r, r), r)
    return keep_particles(spec, keep, f"{spec.label}, disk D {diameter_mm:g} mm")


def simulate_brazilian(params: BondedParams | dict | None = None, specimen: Specimen | None = None,
                       *, rate_factor: float = 1.0, max_strain: float = DEFAULT_MAX_STRAIN,
                       contact_stiffness: str = DEFAULT_CONTACT_STIFFNESS,
                       progress: Callable[[float, float], None] | None = None) -> BrazilianResult:
    """Run the Brazilian test; defaults: granite parameters on a 50 mm disk.

    contact_stiffness: PFC's convention for kn ("pfc5" or "pfc4", `dem.simulate`);
    progress(closure_mm, load_kN_per_m) is called as the test goes.
    """
    started = time.perf_counter()
    params = as_params(params)
    if not 0 < max_strain <= 0.5:
        raise InputError("max_strain", f"must be in (0, 0.5], got {max_strain}")
    specimen = specimen or brazilian_disk()
    platens = Platens(specimen, params, rate_factor, contact_stiffness)
    state = platens.state
    diameter = platens.top - platens.bottom

    def read() -> Reading:
        closure = platens.closure_m()
        load = platens.load()
        return Reading(load, closure, (1e3 * closure, load / 1e3))

    def split(reading: Reading) -> bool:
        return (loading.fallen_below(POST_PEAK_FRACTION, reading.load) and state.n_broken() > 0
                and reading.travel > loading.peak_travel + specimen.radius.mean())

    loading = Loading(RAMP_STEPS_PER_ROW * platens.rows, LOCALISED_DAMAGE)
    curve = load_to_failure(platens, loading, read, split,
                            max_strain * diameter, full_speed_past_peak=True, progress=progress)
    k = int(np.argmax(curve[:, 1]))
    P_max = 1e3 * curve[k, 1]
    return BrazilianResult(
        sigma_t_MPa=2 * P_max / (np.pi * diameter * platens.thickness_m) / 1e6,
        P_max_kN_per_m=P_max / 1e3,
        displacement_at_peak_mm=float(curve[k, 0]), diameter_mm=1e3 * diameter, curve=curve,
        **run_fields(state, specimen, started))


def _check(s: dict) -> None:
    with fields_named({"diameter_mm": "disk_diameter_mm"}):
        check_disk(s["disk_diameter_mm"], s["rmin_mm"], s["radius_ratio"])
    check_grain_cloud(s["disk_diameter_mm"], s["disk_diameter_mm"], s)


def _specimen(s: dict) -> Specimen:
    return brazilian_disk(s["disk_diameter_mm"], s["rmin_mm"], s["radius_ratio"], s["seed"], genesis_of(s))


def _run(params: BondedParams, specimen: Specimen, s: dict, progress) -> BrazilianResult:
    return simulate_brazilian(params, specimen, contact_stiffness=s["contact_stiffness"],
                              progress=progress)



class BrazilianValues(LabValues):
    """Lab result of the Brazilian (splitting tensile) test."""

    sigma_t_MPa: float = Field(gt=0, description="Brazilian tensile strength σ_t = 2P/(πDt), MPa.")


TEST = LabTest(
    lab_values=BrazilianValues,
    name="brazilian", title="Brazilian",
    help="Brazilian test of a disk between platens: sigma_t = 2P/(pi D t), load-closure curve.",
    responses=(Response("sigma_t_MPa", "MPa", label="tensile strength sigma_t"),
               Response("P_max_kN_per_m", "kN/m", target=False, label="peak load"),
               Response("displacement_at_peak_mm", "mm", target=False, label="platen closure at peak")),
    curve_columns=("displacement_mm", "load_kN_per_m"), plot="load_displacement",
    flags=(("disk_diameter_mm", "diameter_mm"),),
    settings=("disk_diameter_mm", "rmin_mm", "radius_ratio", "seed", *GENESIS, "contact_stiffness"),
    check=_check, make=_specimen, run=_run, reading=load_reading,
    outline=lambda s: Outline(f"disk D {s['disk_diameter_mm']:g} mm", s["disk_diameter_mm"],
                              s["disk_diameter_mm"], share=np.pi / 4))
