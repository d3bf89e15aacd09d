"""The loading pin and the two supports of three-point bending in 3D: rigid cylinders along the
specimen's thickness (y), each the 2D pin's arc of small driven spheres (`rig.arc`) repeated in
rows across the thickness. The pin moves down along z.
"""

from __future__ import annotations

import numpy as np

from rockcal.labtests.rig.arc import with_rigid_parts
from rockcal.labtests.rig.platens_3d import check_contact_stiffness
from rockcal.labtests.rig.pins import Pins, pin_disks, touching_centre_y

# Rows of a cylinder's spheres at most this many sphere radii apart across the thickness: a
# grain of the smallest radius between two of them sinks 6 % of its radius below the cylinder.
ROW_SPACING = 1.0


def pin_spheres(centre_xz, pin_radius: float, sphere_radius: float, facing_up: bool,
                thickness_m: float) -> np.ndarray:
    """Centres (x, y, z) of spheres whose envelope is the half of a cylinder along y, from y =
    0 to `thickness_m`, facing the specimen."""
    arc = pin_disks(centre_xz, pin_radius, sphere_radius, facing_up)
    rows = np.linspace(0.0, thickness_m, int(np.ceil(thickness_m / (ROW_SPACING * sphere_radius))) + 1)
    return np.array([(x, y, z) for y in rows for x, z in arc])


class Pins3D(Pins):
    """The 3D beam's pin and supports (`Pins`, along z): a pin touching the beam `specimen`
    (a `Specimen3D` of sides x, y, z) from above at `pin_x_m` and two supports touching it
    from below at `support_x_m`, all of radius `radius_m` across the beam's thickness, made of
    spheres of its smallest radius; the pin moves `step_m` per time step at full speed.
    `contact_stiffness`: PFC 5's, the 3D engine's only (None: it)."""

    UP = 2

    def __init__(self, specimen, params, pin_x_m: float, support_x_m: tuple[float, float],
                 radius_m: float, step_m: float, contact_stiffness: str | None = None):
        check_contact_stiffness(contact_stiffness)
        pos, radius = specimen.pos, specimen.radius
        xz, sphere, thickness = pos[:, [0, 2]], radius.min(), float(specimen.size_m[1])
        parts = [pin_spheres((pin_x_m, touching_centre_y(xz, radius, pin_x_m, radius_m, above=True)),
                             radius_m, sphere, False, thickness)]
        parts += [pin_spheres((x, touching_centre_y(xz, radius, x, radius_m, above=False)), radius_m,
                              sphere, True, thickness)
                  for x in support_x_m]
        self.state, (self.is_pin, *on_supports) = with_rigid_parts(specimen, params, parts)
        self._start(on_supports, step_m, specimen.size_m[2] / (2 * radius.mean()))
        self.thickness_m = thickness

    def contact_load(self, modulus_GPa: float) -> float:
        """The load of one contact of the modulus `modulus_GPa` (normal stiffness about E R of
        the smallest sphere) pressed by one pin step, N: a load above it is the pin touching
        the beam."""
        return 1e9 * modulus_GPa * float(self.state.particles.radius.min()) * self.step_m
