"""The loading pin and the two supports of three-point bending: rigid cylinders built from small
driven disks on their surface (`rig.arc`), so that the engine's ordinary linear contacts (with
the rock's friction) carry the load and the neighbour grid stays fine. The supports stay put;
the pin moves down.
"""

from __future__ import annotations

import numpy as np

from rockcal.dem.simulate import DEFAULT_CONTACT_STIFFNESS, THICKNESS_M
from rockcal.specimens.specimen import Specimen
from rockcal.labtests.rig.arc import arc_disks, with_rigid_parts


def pin_disks(centre, pin_radius: float, disk_radius: float, facing_up: bool) -> np.ndarray:
    """Centres of small disks whose envelope is the half of a cylinder facing the beam."""
    start = 0.0 if facing_up else np.pi
    return arc_disks(centre, pin_radius - disk_radius, start, start + np.pi, disk_radius)


def touching_centre_y(pos, radius, x: float, pin_radius: float, above: bool) -> float:
    """Height of a cylinder's centre at `x` such that it just touches the specimen from above
    (or below): every disk is then at a distance >= pin_radius + its radius."""
    reach = pin_radius + radius
    near = np.abs(pos[:, 0] - x) < reach
    rise = np.sqrt(reach[near] ** 2 - (pos[near, 0] - x) ** 2)
    return float((pos[near, 1] + rise).max() if above else (pos[near, 1] - rise).min())


class Pins:
    """A pin touching the beam `specimen` from above at `pin_x_m` and two supports touching it
    from below at `support_x_m`, all of radius `radius_m` and made of disks of the beam's
    smallest radius; the pin moves `step_m` per time step at full speed. The engine `state`
    holds the beam's grains, then the pin's and the supports' disks (`is_pin`, `on_supports`
    each support's, `is_support` both); `rows` of grains across the beam's depth, `chunk`
    steps between readings, the beam's `thickness_m` (2D's unit thickness). The pin moves
    along the axis `UP` (y in 2D, z in 3D: `Pins3D`)."""

    UP = 1

    def __init__(self, specimen: Specimen, params, pin_x_m: float, support_x_m: tuple[float, float],
                 radius_m: float, step_m: float, contact_stiffness: str | None = None):
        pos, radius = specimen.pos, specimen.radius
        disk = radius.min()
        pin = pin_disks((pin_x_m, touching_centre_y(pos, radius, pin_x_m, radius_m, above=True)),
                        radius_m, disk, facing_up=False)
        supports = [pin_disks((x, touching_centre_y(pos, radius, x, radius_m, above=False)), radius_m,
                              disk, facing_up=True)
                    for x in support_x_m]
        self.state, (self.is_pin, *on_supports) = with_rigid_parts(
            specimen, params, [pin, *supports], contact_stiffness=contact_stiffness or DEFAULT_CONTACT_STIFFNESS)
        self._start(on_supports, step_m, specimen.height_m / (2 * radius.mean()))
        self.thickness_m = THICKNESS_M

    def _start(self, on_supports: list[np.ndarray], step_m: float, rows: float) -> None:
        """The supports' masks, the pin's step, the rows across the depth, the readings' chunk
        and the pin's starting height, once the state is built."""
        self.on_supports = on_supports
        self.is_support = np.any(on_supports, axis=0)
        self.step_m = step_m
        self.rows = rows
        self.chunk = max(10, int(self.rows / 4))
        self.y0 = self.state.particles.pos[self.is_pin, self.UP].mean()

    def move(self, factor: float) -> None:
        """Move the pin down at `factor` x the full speed."""
        self.state.particles.vel[self.is_pin, self.UP] = -self.step_m * factor / self.state.dt

    def load(self) -> float:
        """The load on the beam (mean of the pin's and the supports'), N per m of thickness
        (2D) or N (3D)."""
        force = self.state.particles.force[:, self.UP]
        return 0.5 * (force[self.is_pin].sum() + -force[self.is_support].sum())

    def reactions(self) -> list[float]:
        """Each support's reaction, in the unit of `load`."""
        force = self.state.particles.force[:, self.UP]
        return [float(-force[on].sum()) for on in self.on_supports]

    def displacement_m(self) -> float:
        """How far the pin has moved down, m."""
        return self.y0 - self.state.particles.pos[self.is_pin, self.UP].mean()

    def contact_load(self, modulus_GPa: float) -> float:
        """The load of one contact of the modulus `modulus_GPa` (normal stiffness E t) pressed
        by one pin step, N per m: a load above it is the pin touching the beam."""
        return 1e9 * modulus_GPa * THICKNESS_M * self.step_m
