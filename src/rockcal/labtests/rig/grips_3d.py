"""Rigid grips pulling a 3D cylinder apart along its axis, as the 2D grips (`grips`) a prism: the
spheres whose centres lie within a grip length of either end are the grips (their velocities
prescribed, their spin held at zero: driven spheres), opening at the platens' strain rate over
the free length between them. The pull is in N and the loaded area the nominal cross-section
(pi D^2 / 4 of a cylinder).
"""

from __future__ import annotations

import numpy as np

from rockcal.labtests.rig.grips import check_grip_rows
from rockcal.labtests.rig.platens import STRAIN_PER_STEP_PER_ROW
from rockcal.materials import new_state


class Grips3D:
    """The grips of `grip_fraction` x the height at each end of the 3D `specimen`: the engine
    `state`, the spheres of the `bottom` and `top` grips, the `free_length_m` and `rows` of
    spheres between them, the `chunk` of steps between readings and the loaded `area_m2`
    (`contact_stiffness` as the 2D grips', for one signature: the 3D material has one)."""

    def __init__(self, specimen, params, grip_fraction: float, rate_factor: float, contact_stiffness: str = "pfc5"):
        check_grip_rows(grip_fraction, 1e3 * specimen.size_m[2], 2e3 * float(specimen.radius.mean()))
        z = specimen.pos[:, 2]
        grip = grip_fraction * specimen.size_m[2]
        self.bottom, self.top = np.flatnonzero(z < z.min() + grip), np.flatnonzero(z > z.max() - grip)
        self.state = new_state(params, specimen, driven=np.concatenate([self.bottom, self.top]))
        self.free_length_m = free_length = float(z[self.top].min() - z[self.bottom].max())
        self.rows = free_length / (2 * specimen.radius.mean())
        self.speed = 0.5 * rate_factor * STRAIN_PER_STEP_PER_ROW / self.rows * free_length / self.state.dt
        self.chunk = max(5, int(self.rows / 8))
        x, y, _ = specimen.size_m
        self.area_m2 = np.pi / 4 * x * y if specimen.shape == "cylinder" else x * y
        self.opening0 = self._opening()

    def _opening(self) -> float:
        """The height between the first sphere of each grip, m."""
        z = self.state.spheres.pos[:, 2]
        return float(z[self.top[0]] - z[self.bottom[0]])

    def move(self, factor: float) -> None:
        """Pull the grips apart at `factor` x the full speed."""
        vel = self.state.spheres.vel
        vel[self.bottom, 2] = -self.speed * factor
        vel[self.top, 2] = self.speed * factor

    def load(self) -> float:
        """The force the cylinder pulls each grip back with (mean of the two), N, tension
        positive (the forces between a grip's own spheres cancel in the sum)."""
        force = self.state.spheres.force
        return 0.5 * float(force[self.bottom, 2].sum() - force[self.top, 2].sum())

    def strain(self) -> float:
        """The grips' opening over the free length between them."""
        return (self._opening() - self.opening0) / self.free_length_m
