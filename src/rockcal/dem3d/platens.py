"""Two frictionless platens closing on a 3D specimen at a quasi-static speed (the 2D rig's
rule, `rockcal.labtests.rig.platens`): an axial strain per step of STRAIN_PER_STEP_PER_ROW /
(rows of spheres between them), so the number of wave transits to the peak is the same for
every specimen size; `rockcal.labtests.loading` ramps them in and slows them where bonds break.
"""

from __future__ import annotations

import numpy as np

from rockcal.dem3d.material import material_state, wall_modulus_pa
from rockcal.dem3d.walls import new_walls
from rockcal.labtests.rig.platens import STRAIN_PER_STEP_PER_ROW

BOTTOM, TOP = 0, 1
SIDES = (2, 3, 4, 5)  # with side walls: -x, +x, -y, +y, after the platens


class Platens3D:
    """A specimen between a bottom and a top platen (walls normal to z) that touch it: the
    engine `state`, the platens' starting heights (m), the `rows` of spheres between them, the
    `chunk` of steps between readings and the loaded `area_m2` (the nominal cross-section).
    `modulus_pa`: the platens' contact modulus, if not the material's (`wall_modulus_pa`).
    With `side_walls`, the state has four more walls of that modulus at rest (SIDES: -x, +x,
    -y, +y) touching the specimen's outermost spheres (a confining vessel, `dem3d.sides`)."""

    def __init__(self, specimen, params, rate_factor: float, modulus_pa: float | None = None,
                 side_walls: bool = False):
        pos, radius = specimen.pos, specimen.radius
        self.bottom, self.top = (pos[:, 2] - radius).min(), (pos[:, 2] + radius).max()
        centre = pos.mean(axis=0)
        points, normals = [(centre[0], centre[1], self.bottom), (centre[0], centre[1], self.top)], \
            [(0, 0, 1), (0, 0, -1)]
        if side_walls:
            low, high = (pos - radius[:, None]).min(axis=0), (pos + radius[:, None]).max(axis=0)
            for a in (0, 1):
                for at, facing in ((low, 1.0), (high, -1.0)):
                    point = centre.copy()
                    point[a] = at[a]
                    points.append(tuple(point))
                    normals.append(tuple(facing * np.eye(3)[a]))
        walls = new_walls(points, normals, wall_modulus_pa(params) if modulus_pa is None else modulus_pa)
        self.state = material_state(params, specimen, walls)
        height = self.top - self.bottom
        self.rows = height / (2 * radius.mean())
        self.speed = 0.5 * rate_factor * STRAIN_PER_STEP_PER_ROW / self.rows * height / self.state.dt
        self.chunk = max(5, int(self.rows / 8))
        x, y, _ = specimen.size_m
        self.area_m2 = np.pi / 4 * x * y if specimen.shape == "cylinder" else x * y

    def move(self, factor: float) -> None:
        """Close the platens at `factor` x the full speed."""
        vel = self.state.walls.vel
        vel[BOTTOM, 2], vel[TOP, 2] = self.speed * factor, -self.speed * factor

    def load(self) -> float:
        """The force on the platens (mean of the two), N."""
        return float(self.state.walls.normal_force()[[BOTTOM, TOP]].mean())

    def strain(self) -> float:
        """The axial strain from the platens' separation, shortening positive."""
        z = self.state.walls.point[:, 2]
        return 1.0 - (z[TOP] - z[BOTTOM]) / (self.top - self.bottom)

    def closure_m(self) -> float:
        """How far the platens have closed in since the start (both together), m."""
        z = self.state.walls.point[:, 2]
        return float((z[BOTTOM] - self.bottom) + (self.top - z[TOP]))

    def zero(self) -> None:
        """Read strain and closure from the platens' present heights on (after a seating)."""
        z = self.state.walls.point[:, 2]
        self.bottom, self.top = float(z[BOTTOM]), float(z[TOP])
