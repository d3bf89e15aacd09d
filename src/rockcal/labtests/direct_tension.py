"""Virtual direct tension of a prism held by rigid grips, as FISHTank's direct-tension test
(`tt.fis`): the grains whose centres lie within a grip length of either end are the grips
(`rockcal.labtests.rig.grips`), pulled apart at a quasi-static speed. Its grains are balls or
rigid clumps (`grain_shape`, the UCS test's specimen): a clump whose centroid lies in a grip
is gripped whole and translates with it, as FISHTank's test grips a clumped material.

Gripped ends rather than a dog-bone: the lab's direct tension test glues end caps to a plain
cylinder or prism (ISRM 1978 suggested method), which the rigid grips are; a dog-bone must be
carved from the packing, and its neck's curve then concentrates stress at a few particles,
while the grips keep the UCS test's specimen, packing and bonds, so that sigma_t and the UCS
come from the same virtual rock. The grips also hold the ends from contracting sideways, as
glued caps do.

sigma_t = P_max / (W t), P the force the specimen pulls each grip back with (mean of the two),
W the prism's width. The grips move at the UCS test's strain rate over the free length between
them, on the density-scaled specimen (`simulate.scale_density`); the speed drops to its
slowest from the first broken bond on (`loading.LOCALISED_DAMAGE`: one crack decides the peak)
and returns to full once the force has fallen well past the peak; the test stops once the
force is below POST_PEAK_FRACTION of the peak.

With the setting `dimensions` 3 (PFC3D) the specimen is the UCS test's cylinder of spheres,
gripped at its ends as the prism (`rig.grips_3d`): sigma_t = P_max / (pi D^2 / 4), P in N.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from rockcal.dem.simulate import DEFAULT_CONTACT_STIFFNESS
from rockcal.specimens.specimen import Specimen, random_packing
from rockcal.errors import InputError
from rockcal.labtests import ucs
from rockcal.labtests.kind import GENESIS, LabTest, Outline, Response, Setting, in_3d
from rockcal.labtests.loading import (LOCALISED_DAMAGE, RAMP_STEPS_PER_ROW, Loading, Reading,
                                      check_max_strain, load_to_failure)
from rockcal.labtests.result import LabResult, run_fields
from rockcal.labtests.rig import rig_for
from rockcal.labtests.rig.grips import check_grip_rows
from rockcal.materials import BondedParams, as_params

GRIP_FRACTION = 0.1  # grip length / prism height at each end (FISHTank's tt_tg default, 0.1 H)
POST_PEAK_FRACTION = 0.5
DEFAULT_MAX_STRAIN = 0.01  # grip opening / free length at which the test stops at the latest
CURVE_COLUMNS = ("axial_strain", "tensile_stress_MPa", "broken_bonds")


@dataclass
class DirectTensionResult(LabResult):
    """Responses of a direct tension test, 2D or 3D (`DirectTensionResult2D`, `DirectTensionResult3D`
    add the peak load); its curve's columns: CURVE_COLUMNS (the strain is the grips' opening over
    the free length between them)."""

    sigma_t_direct_MPa: float
    peak_axial_strain: float
    free_length_mm: float


@dataclass
class DirectTensionResult2D(DirectTensionResult):
    """A 2D prism's: its peak pull per metre of the slab's unit thickness."""

    P_max_kN_per_m: float


@dataclass
class DirectTensionResult3D(DirectTensionResult):
    """A 3D cylinder's: its peak pull."""

    P_max_kN: float


def check_grip(grip_fraction) -> None:
    """A grip holds a share of the prism's height in (0, 0.4] at each end."""
    if not (isinstance(grip_fraction, (int, float)) and 0 < grip_fraction <= 0.4):
        raise InputError("grip_fraction", f"must be in (0, 0.4], got {grip_fraction!r}")


def simulate_direct_tension(params: BondedParams | dict | None = None,
                            specimen: Specimen | None = None, *,
                            grip_fraction: float = GRIP_FRACTION, rate_factor: float = 1.0,
                            max_strain: float = DEFAULT_MAX_STRAIN,
                            contact_stiffness: str = DEFAULT_CONTACT_STIFFNESS,
                            progress: Callable[[float, float], None] | None = None
                            ) -> DirectTensionResult:
    """Pull the prism (or a 3D cylinder) apart; defaults: granite parameters on the UCS test's
    50 x 100 mm prism of balls (a clumped specimen's clumps are gripped whole, `rig.grips`).
    progress(axial strain, stress MPa) is called as the test goes."""
    started = time.perf_counter()
    params = as_params(params)
    check_grip(grip_fraction)
    check_max_strain(max_strain)
    specimen = specimen or random_packing(50.0, 100.0)
    speed = ucs.DENSITY_SCALED_SPEED * rate_factor
    grips = rig_for(specimen).grips(specimen, params, grip_fraction, speed, contact_stiffness)
    state = grips.state
    state.scale_density()
    broken = [0]

    def read() -> Reading:
        broken.append(state.n_broken())
        strain = grips.strain()
        pull = grips.load()  # N per m (2D) or N, tension positive
        return Reading(pull, strain, (strain, pull / grips.area_m2 / 1e6))

    loading = Loading(RAMP_STEPS_PER_ROW * grips.rows / ucs.DENSITY_SCALED_SPEED, LOCALISED_DAMAGE)
    curve = load_to_failure(grips, loading, read,
                            lambda reading: loading.fallen_below(POST_PEAK_FRACTION, reading.load),
                            max_strain, full_speed_past_peak=True, progress=progress)
    curve = np.column_stack([curve, broken])
    k = int(np.argmax(curve[:, 1]))
    result = dict(sigma_t_direct_MPa=float(curve[k, 1]), peak_axial_strain=float(curve[k, 0]),
                  free_length_mm=1e3 * grips.free_length_m, curve=curve, **run_fields(state, specimen, started))
    P_max_kN = float(curve[k, 1] * grips.area_m2 * 1e3)
    if specimen.dimensions == 3:
        return DirectTensionResult3D(P_max_kN=P_max_kN, **result)
    return DirectTensionResult2D(P_max_kN_per_m=P_max_kN, **result)


def _check(s: dict) -> None:
    ucs.TEST.check(s)  # in 3D: the cylinder's size and spheres
    check_grip(s["grip_fraction"])
    check_grip_rows(s["grip_fraction"], s["height_mm"], s["rmin_mm"] * (1 + s["radius_ratio"]))


def _run(params: BondedParams, specimen: Specimen, s: dict, progress) -> DirectTensionResult:
    return simulate_direct_tension(params, specimen, grip_fraction=s["grip_fraction"],
                                   contact_stiffness=s["contact_stiffness"], progress=progress)


GRIP = Setting("grip_fraction", GRIP_FRACTION, "", check_grip,
               "grip length / prism height at each end (FISHTank's tt_tg / H), in (0, 0.4]; the "
               "grip reaches at least one mean grain diameter into the prism")


def _outline(s: dict) -> Outline:
    if in_3d(s):  # the UCS test's cylinder
        text = f"direct tension cylinder Ø{s['width_mm']:g} x {s['height_mm']:g} mm"
        return replace(ucs.TEST.outline(s), text=text)
    return Outline(f"direct tension {s['width_mm']:g} x {s['height_mm']:g} mm", s["width_mm"], s["height_mm"])


RESPONSES = (Response("sigma_t_direct_MPa", "MPa", label="direct tensile strength"),
             Response("P_max_kN_per_m", "kN/m", target=False, label="peak load"),
             Response("peak_axial_strain", "", target=False, label="axial strain at peak"))
RESPONSES_3D = tuple(Response("P_max_kN", "kN", target=False, label="peak load") if r.name == "P_max_kN_per_m"
                     else r for r in RESPONSES)

TEST = LabTest(
    name="direct_tension", title="direct tension",
    responses=RESPONSES,
    # the later settings last: at their old values (kind.LATER_SETTINGS) a run's key leaves them out
    settings=("width_mm", "height_mm", "rmin_mm", "radius_ratio", "seed", *GENESIS,
              "grip_fraction", "contact_stiffness", "grain_shape", "dimensions"),
    check=_check, make=ucs.TEST.make, run=_run,
    reading=lambda strain, stress_MPa: f"strain {100 * strain:.4f} %, {stress_MPa:.2f} MPa",
    outline=_outline,
    setting_help=(("width_mm", "Prism width W, mm (in 3D the cylinder's diameter)."),
                  ("height_mm", "Prism height, mm, along the pull.")),
    curve_columns=CURVE_COLUMNS, own_settings=(GRIP,), plot="tension_curve",
    changes_3d=(("responses", RESPONSES_3D),))
