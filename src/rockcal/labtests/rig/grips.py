"""Rigid grips pulling a prism apart, as FISHTank's direct-tension test (`tt.fis`): the grains
whose centres lie within a grip length of either end are the grips (their velocities prescribed,
their spin held at zero, as PFC's `ball fix velocity spin`). They open at the platens' strain
rate (`rockcal.labtests.rig.platens`) over the free length between them.

Of a clumped specimen the grains are the clumps, judged at their centroids (as `specimens.carving`
judges them): a clump is gripped whole when its centroid lies in a grip, and then moves with
the grip as a gripped ball does, translating without turning (a driven clump of
`dem.clump_motion`, its body's velocity prescribed, its spin zero). The centroid, not any
pebble: the grip then holds the same share of the prism as for balls of the same equivalent
sizes, and a clump that only reaches into the grip with a pebble is left free, as a ball whose
centre lies outside it is.
"""

from __future__ import annotations

import numpy as np

from rockcal.errors import InputError
from rockcal.specimens.carving import grains, of_particles
from rockcal.dem.simulate import DEFAULT_CONTACT_STIFFNESS, THICKNESS_M
from rockcal.specimens.specimen import Specimen
from rockcal.labtests.rig.platens import STRAIN_PER_STEP_PER_ROW
from rockcal.materials import new_state


def check_grip_rows(grip_fraction: float, height_mm: float, grain_diameter_mm: float) -> None:
    """A grip reaches at least one mean grain diameter into the specimen: it then holds the end
    row of grains and the row behind it (rows lie about 0.87 diameters apart), and pulls on the
    specimen across its width; a shorter one may hold a few grains of the end row, which the
    specimen's first bonds tear out."""
    grip_mm = grip_fraction * height_mm
    if grip_mm < grain_diameter_mm:
        raise InputError("grip_fraction", f"the grips ({grip_fraction:g} x {height_mm:g} mm = {grip_mm:.3g} mm) must "
                                          f"reach at least one mean grain diameter ({grain_diameter_mm:.3g} mm) "
                                          "into the prism, to hold two rows of grains: give at least "
                                          f"{grain_diameter_mm / height_mm:.3g}, a taller prism or smaller grains")


def grip_grains(specimen: Specimen, grip_fraction: float) -> tuple[np.ndarray, np.ndarray]:
    """The grains (balls, or clumps in their order) of the bottom and top grips: centres (a
    clump's centroid) within grip_fraction x height of the prism's ends."""
    y = grains(specimen)[0][:, 1]
    grip = grip_fraction * specimen.height_m
    return np.flatnonzero(y < y.min() + grip), np.flatnonzero(y > y.max() - grip)


def particles_of(specimen: Specimen, grain_indices: np.ndarray) -> np.ndarray:
    """The particles of some grains, in increasing order: the balls, or every pebble of the
    clumps."""
    mask = np.zeros(specimen.n_grains, bool)
    mask[grain_indices] = True
    return np.flatnonzero(of_particles(specimen, mask))


class Grips:
    """The grips of `grip_fraction` x the height at each end of `specimen`: the engine `state`,
    the grains of the `bottom` and `top` grips (`grip_grains`), their particles
    (`bottom_particles`, `top_particles`: a clump's pebbles), the `free_length_m` and `rows` of
    grains between them, the `chunk` of steps between readings and the prism's loaded `area_m2`
    (width x thickness)."""

    def __init__(self, specimen: Specimen, params, grip_fraction: float, rate_factor: float,
                 contact_stiffness: str = DEFAULT_CONTACT_STIFFNESS):
        check_grip_rows(grip_fraction, 1e3 * specimen.height_m, 2e3 * float(grains(specimen)[1].mean()))
        self.bottom, self.top = grip_grains(specimen, grip_fraction)
        self.bottom_particles = particles_of(specimen, self.bottom)
        self.top_particles = particles_of(specimen, self.top)
        self.state = new_state(params, specimen,
                               driven=np.concatenate([self.bottom_particles, self.top_particles]),
                               contact_stiffness=contact_stiffness)
        y = self._grain_centres()[:, 1]
        self.free_length_m = free_length = (y[self.top].min() - y[self.bottom].max())
        self.rows = free_length / (2 * specimen.radius.mean())
        self.speed = (0.5 * rate_factor * STRAIN_PER_STEP_PER_ROW / self.rows * free_length
                      / self.state.dt)
        self.chunk = max(5, int(self.rows / 8))
        self.area_m2 = specimen.width_m * THICKNESS_M
        self.opening0 = self._opening()

    def _grain_centres(self) -> np.ndarray:
        """Each grain's centre now, m: a ball's, a clump's centroid (its body's)."""
        clumps = self.state.clumps
        return self.state.particles.pos if clumps is None else clumps.pos

    def _opening(self) -> float:
        """The height between the first grain of each grip, m."""
        y = self._grain_centres()[:, 1]
        return y[self.top[0]] - y[self.bottom[0]]

    def move(self, factor: float) -> None:
        """Pull the grips apart at `factor` x the full speed: a gripped clump's body and then
        its pebbles (`Clumps.carry_pebbles`), as a gripped ball."""
        clumps = self.state.clumps
        vel = self.state.particles.vel if clumps is None else clumps.vel
        vel[self.bottom, 1] = -self.speed * factor
        vel[self.top, 1] = self.speed * factor
        if clumps is not None:
            clumps.carry_pebbles(self.state.particles)

    def load(self) -> float:
        """The force the prism pulls each grip back with (mean of the two), N per m of thickness,
        tension positive: summed over the grips' particles (the forces between a grip's own
        grains cancel in the sum; pebbles of one clump bear none on each other)."""
        force = self.state.particles.force
        return 0.5 * (force[self.bottom_particles, 1].sum() - force[self.top_particles, 1].sum())

    def strain(self) -> float:
        """The grips' opening over the free length between them."""
        return (self._opening() - self.opening0) / self.free_length_m
