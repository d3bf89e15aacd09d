"""Confined compression of a 3D square prism, as the 2D test (`rockcal.labtests.biaxial`):
FISHTank's compression test with a confining pressure in a polyaxial vessel, sigma2 = sigma3
(a conventional triaxial state). The prism stands between two frictionless platens (z) and
four frictionless side walls (±x, ±y, `sides.SideWalls3D`). Seating: all six walls are
servo-controlled to sigma3 until equilibrium. Axial loading: the strains are zeroed, the
platens close as in the 3D UCS test (`dem3d.ucs`: the same speed on the density-scaled
specimen, the same loading and stop rules) while the side walls keep sigma3. Readings as the
2D test's: q = sigma1 - sigma3 (sigma1 the platens' force over the prism's original
cross-section, sigma3 the side walls' mean stress), E and nu secant at half the peak q, the
peak sigma1, CI and CD from the volumetric strain axial - 2 x lateral (the mean of the two
widths' strains, `gauge`).

At sigma3 = 0 the vessel has no side walls: the test is the 3D UCS test on the prism, to the
last bit, so that an envelope is read on one specimen shape.
"""

from __future__ import annotations

import time
from collections.abc import Callable

from rockcal.dem3d.gauge import Gauge3D
from rockcal.dem3d.laws import BROKEN_SHEAR, BROKEN_TENSION
from rockcal.dem3d.platens import Platens3D
from rockcal.dem3d.sides import SideWalls3D
from rockcal.dem3d.simulate import advance, scale_density
from rockcal.dem3d.ucs import cracks_of
from rockcal.labtests import snapshots
from rockcal.labtests.biaxial import (
    BiaxialResult,
    ConfinedReadings,
    check_confinement,
    confined_readings,
)
from rockcal.labtests.loading import (
    DISTRIBUTED_DAMAGE,
    RAMP_STEPS_PER_ROW,
    Loading,
    load_to_failure,
)
from rockcal.labtests.ucs import (
    DEFAULT_MAX_AXIAL_STRAIN,
    DENSITY_SCALED_SPEED,
    POST_PEAK_FRACTION,
    check_reading,
)
from rockcal.materials import as_params
from rockcal.params import MPa


def simulate_triaxial_3d(params, specimen, confinement_mpa: float = 10.0, *, rate_factor: float = 1.0,
                         max_axial_strain: float = DEFAULT_MAX_AXIAL_STRAIN, strain: str = "gauge",
                         stop_fraction: float = POST_PEAK_FRACTION,
                         progress: Callable[[float, float], None] | None = None) -> BiaxialResult:
    """Run the confined test at `confinement_mpa` on a 3D prism `specimen` (`Specimen3D`,
    shape "cuboid"); the other arguments as the 2D test's (`biaxial.simulate_biaxial`).
    The result is the 2D test's, its spheres' centres and cracks in 3D (m)."""
    started = time.perf_counter()
    params = as_params(params)
    check_confinement(confinement_mpa)
    check_reading(max_axial_strain, strain, stop_fraction)

    def start() -> tuple:
        sigma3 = confinement_mpa * MPa
        platens = Platens3D(specimen, params, DENSITY_SCALED_SPEED * rate_factor, side_walls=sigma3 > 0)
        state = platens.state
        scale_density(state)
        sides = SideWalls3D(platens, specimen, sigma3) if sigma3 > 0 else None
        seating_steps = 0 if sides is None else sides.seat()
        platens.zero()
        read = ConfinedReadings(platens, Gauge3D(specimen, state.spheres.pos), sides, strain)
        loading = Loading(RAMP_STEPS_PER_ROW * platens.rows / DENSITY_SCALED_SPEED, DISTRIBUTED_DAMAGE)
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
                            control_steps=1 if sides is None else sides.steps, advance_steps=advance,
                            samples=samples, snapshot=snapshots.saver(objects))
    state.step += seated_at
    curve = read.curve(curve)
    return BiaxialResult(**confined_readings(curve, confinement_mpa, lateral_strains=2),
                         seating_steps=seating_steps, curve=curve, n_particles=specimen.n_spheres,
                         n_bonds=len(specimen.bonds), n_broken_tension=state.n_broken(BROKEN_TENSION),
                         n_broken_shear=state.n_broken(BROKEN_SHEAR), steps=state.step,
                         wall_s=time.perf_counter() - started,
                         positions=state.spheres.pos[:specimen.n_spheres].copy(), radius=specimen.radius,
                         cracks=cracks_of(state.bonds))
