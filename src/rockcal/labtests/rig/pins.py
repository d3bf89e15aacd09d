"""The loading pin and the two supports of three-point bending: rigid cylinders built from small
driven disks on their surface, so that the engine's ordinary linear contacts (with the rock's
friction) carry the load and the neighbour grid stays fine. The supports stay put; the pin moves
down.
"""

from __future__ import annotations

import math

import numpy as np

from rockcal.dem.simulate import DEFAULT_CONTACT_STIFFNESS, THICKNESS_M
from rockcal.dem.specimen import Specimen
from rockcal.materials import new_state


def pin_disks(centre, pin_radius: float, disk_radius: float, facing_up: bool) -> np.ndarray:
    """Centres of small disks whose envelope is the half of a cylinder facing the beam."""
    arc = pin_radius - disk_radius
    count = int(np.ceil(np.pi * arc / (0.5 * disk_radius))) + 1
    angle = np.linspace(0.0, np.pi, count) if facing_up else np.linspace(np.pi, 2 * np.pi, count)
    # the C library's cos and sin: numpy's AVX-512 ones round otherwise on some angles
    cos, sin = np.array([math.cos(a) for a in angle]), np.array([math.sin(a) for a in angle])
    return np.column_stack([centre[0] + arc * cos, centre[1] + arc * sin])


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
    holds the beam's grains, then the pin's and the supports' disks (`is_pin`, `is_support`);
    `rows` of grains across the beam's depth, `chunk` steps between readings."""

    def __init__(self, specimen: Specimen, params, pin_x_m: float, support_x_m: tuple[float, float],
                 radius_m: float, step_m: float, contact_stiffness: str = DEFAULT_CONTACT_STIFFNESS):
        pos, radius = specimen.pos, specimen.radius
        n = specimen.n_particles
        disk = radius.min()
        pin = pin_disks((pin_x_m, touching_centre_y(pos, radius, pin_x_m, radius_m, above=True)),
                        radius_m, disk, facing_up=False)
        supports = [pin_disks((x, touching_centre_y(pos, radius, x, radius_m, above=False)), radius_m,
                              disk, facing_up=True)
                    for x in support_x_m]
        rigid = np.vstack([pin, *supports])
        self.is_pin = np.zeros(n + len(rigid), bool)
        self.is_pin[n:n + len(pin)] = True
        self.is_support = np.zeros(n + len(rigid), bool)
        self.is_support[n + len(pin):] = True
        self.state = new_state(params, specimen, np.vstack([pos, rigid]),
                               np.concatenate([radius, np.full(len(rigid), disk)]),
                               driven=self.is_pin | self.is_support,
                               contact_stiffness=contact_stiffness)
        self.step_m = step_m
        self.rows = specimen.height_m / (2 * radius.mean())
        self.chunk = max(10, int(self.rows / 4))
        self.y0 = self.state.particles.pos[self.is_pin, 1].mean()

    def move(self, factor: float) -> None:
        """Move the pin down at `factor` x the full speed."""
        self.state.particles.vel[self.is_pin, 1] = -self.step_m * factor / self.state.dt

    def load(self) -> float:
        """The load on the beam (mean of the pin's and the supports'), N per m of thickness."""
        force = self.state.particles.force
        return 0.5 * (force[self.is_pin, 1].sum() + -force[self.is_support, 1].sum())

    def displacement_m(self) -> float:
        """How far the pin has moved down, m."""
        return self.y0 - self.state.particles.pos[self.is_pin, 1].mean()

    def contact_load(self, modulus_GPa: float) -> float:
        """The load of one contact of the modulus `modulus_GPa` (normal stiffness E t) pressed
        by one pin step, N per m: a load above it is the pin touching the beam."""
        return 1e9 * modulus_GPa * THICKNESS_M * self.step_m
