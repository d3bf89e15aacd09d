"""The virtual uniaxial compression test on a 3D specimen, as the 2D test
(`rockcal.labtests.ucs`): frictionless platens close on the density-scaled specimen at the 2D
test's speed, ramped in and slowed where bonds break (`rockcal.labtests.loading.Loading`, its
UCS rule); the test stops once the stress has fallen below a fraction of the settled peak, or
at the maximum axial strain. Readings: UCS = the peak axial stress (platen force over the
nominal cross-section), E and ν secant at half the peak, the axial strain from gauges on the
top and bottom spheres (or the platens' separation), ν from the lateral strain of the outer
spheres (`gauge`), cracks = broken bonds by mode.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from rockcal.dem.measure import secant_at_half_peak
from rockcal.dem3d.gauge import Gauge3D
from rockcal.dem3d.laws import BROKEN_SHEAR, BROKEN_TENSION
from rockcal.dem3d.platens import Platens3D
from rockcal.dem3d.simulate import advance, scale_density
from rockcal.labtests import snapshots
from rockcal.labtests.loading import (
    DISTRIBUTED_DAMAGE,
    RAMP_STEPS_PER_ROW,
    Loading,
)
from rockcal.labtests.ucs import (
    DEFAULT_MAX_AXIAL_STRAIN,
    DENSITY_SCALED_SPEED,
    POST_PEAK_FRACTION,
    check_reading,
)
from rockcal.materials import as_params

CURVE_COLUMNS = ("axial_strain", "lateral_strain", "axial_stress_MPa", "broken_bonds")


@dataclass
class UCS3DResult:
    """Responses of a 3D UCS test and its curve (columns `CURVE_COLUMNS`, a first row of
    zeros for the unloaded specimen); the spheres' final centres (m) and where bonds broke,
    by mode ("tension", "shear": (n, 3) positions, m)."""

    E_GPa: float
    nu: float
    ucs_MPa: float
    peak_axial_strain: float
    strain: str  # how the axial strain was read: "gauge" or "platen"
    curve: np.ndarray
    n_spheres: int
    n_bonds: int
    n_broken_tension: int
    n_broken_shear: int
    steps: int
    wall_s: float
    positions: np.ndarray = field(default=None, repr=False)
    cracks: dict = field(default_factory=dict, repr=False)


def simulate_ucs_3d(params, specimen, *, rate_factor: float = 1.0,
                    max_axial_strain: float = DEFAULT_MAX_AXIAL_STRAIN, strain: str = "gauge",
                    stop_fraction: float = POST_PEAK_FRACTION,
                    progress: Callable[[float, float], None] | None = None) -> UCS3DResult:
    """Run the UCS test on a 3D `specimen` (`specimen.Specimen3D`) of the material `params`
    (2D's MicroParams or a dict of their names, `material`); the arguments mean what they mean
    in the 2D test (`rockcal.labtests.ucs.simulate_ucs`)."""
    started = time.perf_counter()
    params = as_params(params)
    check_reading(max_axial_strain, strain, stop_fraction)

    def start() -> tuple:
        platens = Platens3D(specimen, params, DENSITY_SCALED_SPEED * rate_factor)
        scale_density(platens.state)
        loading = Loading(RAMP_STEPS_PER_ROW * platens.rows / DENSITY_SCALED_SPEED, DISTRIBUTED_DAMAGE)
        return platens, Gauge3D(specimen, platens.state.spheres.pos), loading, [(0.0, 0.0, 0.0, 0)]

    objects = snapshots.resume(start)  # a run stopped part way goes on from its snapshot
    platens, gauge, loading, rows = objects
    state = platens.state
    started -= snapshots.earlier_s()
    save = snapshots.saver(objects)
    while True:
        platens.move(loading.speed(state.step, state.n_broken(), platens.chunk))
        advance(state, platens.chunk)
        gauge_axial, lateral = gauge.strains()
        axial = platens.strain() if strain == "platen" else gauge_axial
        stress = platens.load() / platens.area_m2
        rows.append((axial, lateral, stress / 1e6, state.n_broken()))
        loading.update(state.step, stress, axial)
        if progress:
            progress(axial, stress / 1e6)
        if loading.fallen_below(stop_fraction, stress) or axial >= max_axial_strain:
            break
        if save is not None:
            save()
    curve = np.array(rows, float)
    E_MPa, nu, k = secant_at_half_peak(curve[:, 0], curve[:, 1], curve[:, 2])
    return UCS3DResult(E_GPa=E_MPa / 1e3, nu=nu, ucs_MPa=float(curve[k, 2]),
                       peak_axial_strain=float(curve[k, 0]), strain=strain, curve=curve,
                       n_spheres=specimen.n_spheres, n_bonds=len(specimen.bonds),
                       n_broken_tension=state.n_broken(BROKEN_TENSION),
                       n_broken_shear=state.n_broken(BROKEN_SHEAR), steps=state.step,
                       wall_s=time.perf_counter() - started,
                       positions=state.spheres.pos[:specimen.n_spheres].copy(),
                       cracks=cracks_of(state.bonds))


def cracks_of(bonds) -> dict[str, np.ndarray]:
    """Where the bonds broke (m), by mode."""
    return {mode: bonds.break_xyz[bonds.state == code].copy()
            for mode, code in (("tension", BROKEN_TENSION), ("shear", BROKEN_SHEAR))}
