"""Rigid grips pulling a prism apart, as FISHTank's direct-tension test (`tt.fis`): the grains
whose centres lie within a grip length of either end are the grips (their velocities prescribed,
their spin held at zero, as PFC's `ball fix velocity spin`). They open at the platens' strain
rate (`rockcal.labtests.rig.platens`) over the free length between them.
"""

from __future__ import annotations

import numpy as np

from rockcal.dem.simulate import DEFAULT_CONTACT_STIFFNESS, THICKNESS_M
from rockcal.dem.specimen import Specimen
from rockcal.labtests.rig.platens import STRAIN_PER_STEP_PER_ROW
from rockcal.materials import new_state


def grip_grains(specimen: Specimen, grip_fraction: float) -> tuple[np.ndarray, np.ndarray]:
    """The grains of the bottom and top grips: centres within grip_fraction x height of the
    prism's ends."""
    y = specimen.pos[:, 1]
    grip = grip_fraction * specimen.height_m
    return np.flatnonzero(y < y.min() + grip), np.flatnonzero(y > y.max() - grip)


class Grips:
    """The grips of `grip_fraction` x the height at each end of `specimen`: the engine `state`,
    the grains of the `bottom` and `top` grips, the `free_length_m` and `rows` of grains between
    them, the `chunk` of steps between readings and the prism's loaded `area_m2` (width x
    thickness)."""

    def __init__(self, specimen: Specimen, params, grip_fraction: float, rate_factor: float,
                 contact_stiffness: str = DEFAULT_CONTACT_STIFFNESS):
        self.bottom, self.top = grip_grains(specimen, grip_fraction)
        self.state = new_state(params, specimen, driven=np.concatenate([self.bottom, self.top]),
                               contact_stiffness=contact_stiffness)
        y = self.state.particles.pos[:, 1]
        self.free_length_m = free_length = (y[self.top].min() - y[self.bottom].max())
        self.rows = free_length / (2 * specimen.radius.mean())
        self.speed = (0.5 * rate_factor * STRAIN_PER_STEP_PER_ROW / self.rows * free_length
                      / self.state.dt)
        self.chunk = max(5, int(self.rows / 8))
        self.area_m2 = specimen.width_m * THICKNESS_M
        self.opening0 = self._opening()

    def _opening(self) -> float:
        """The height between the first grain of each grip, m."""
        y = self.state.particles.pos[:, 1]
        return y[self.top[0]] - y[self.bottom[0]]

    def move(self, factor: float) -> None:
        """Pull the grips apart at `factor` x the full speed."""
        vel = self.state.particles.vel
        vel[self.bottom, 1] = -self.speed * factor
        vel[self.top, 1] = self.speed * factor

    def load(self) -> float:
        """The force the prism pulls each grip back with (mean of the two), N per m of thickness,
        tension positive."""
        force = self.state.particles.force
        return 0.5 * (force[self.bottom, 1].sum() - force[self.top, 1].sum())

    def strain(self) -> float:
        """The grips' opening over the free length between them."""
        return (self._opening() - self.opening0) / self.free_length_m
