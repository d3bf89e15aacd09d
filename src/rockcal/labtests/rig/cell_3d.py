"""The triaxial cell of the 3D rig: a cylinder between its platens inside a frictionless
cylindrical wall (`dem3d.walls.with_cylinder`) whose radius is servo-controlled to sigma3, as a
lab's Hoek cell holds its oil pressure and as FISHTank's cylindrical vessel moves its wall
radially at the servo's speed (sigma1 > sigma2 = sigma3 on a round specimen, where the
polyaxial prism of `sides_3d` has four flat walls).

The servo is the side walls' (`sides_3d`, `rig.servo`) with the wall's radius for a position:
its speed, G (sigma - sigma3) plus the integral term, is the radius' rate. The cell's stress is
the wall's radial pushes summed over its face 2 pi r h, h the platens' span and r the
specimen's radius, D / 2 moved as the wall has since it was built (touching the outermost
spheres); seating, the platens' face is pi r^2. The cylinder is to be packed in its cell
(`specimens3d.specimen.packed_cylinder`): its side is then the wall's, which bears on it all
round.
"""

from __future__ import annotations

import numpy as np

from rockcal.dem3d.walls import Wall
from rockcal.labtests.rig.platens_3d import BOTTOM, CYLINDER, TOP, Platens3D
from rockcal.labtests.rig.sides_3d import SideWalls3D, WallServo3D


class CellServo(WallServo3D):
    """Some of the cell's walls (the platens, the cylinder) servo-controlled to `target_Pa`;
    `radius_m` the specimen's radius now."""

    def __init__(self, state, walls: tuple[int, ...], target_Pa: float, limit: float, radius_m):
        super().__init__(state, walls, target_Pa, limit)
        self.radius_m = radius_m

    def faces(self) -> np.ndarray:
        """Each wall's present face (bottom, top, the cylinder), m²."""
        r, z = self.radius_m(), self.state.walls.point[:, 2]
        return np.array([np.pi * r**2, np.pi * r**2, 2 * np.pi * r * float(z[TOP] - z[BOTTOM])])

    def drive(self, w: int, speed: float) -> None:
        """Move wall w outward at `speed` (m/s): the cylinder's radius grows at it."""
        if w == CYLINDER:
            self.state.walls.table[w, Wall.RADIAL_VEL] = speed
        else:
            super().drive(w, speed)


class Cell3D(SideWalls3D):
    """The cell's cylindrical wall about the cylinder `specimen` of `platens` (built with
    `side_walls`), servo-controlled to `target_Pa` as `SideWalls3D`'s four walls are."""

    walls = (CYLINDER,)

    def __init__(self, platens: Platens3D, specimen, target_Pa: float):
        self.wall_start_m = float(platens.state.walls.table[CYLINDER, Wall.RADIUS])
        self.nominal_m = 0.5 * float(specimen.size_m[0])
        super().__init__(platens, specimen, target_Pa)

    def radius_m(self) -> float:
        """The specimen's radius now: D / 2 moved as the wall has, m."""
        return self.nominal_m + float(self.state.walls.table[CYLINDER, Wall.RADIUS]) - self.wall_start_m

    def servo_of(self, walls: tuple[int, ...], target_Pa: float) -> CellServo:
        return CellServo(self.state, walls, target_Pa, self.limit, self.radius_m)


def confining_walls(platens: Platens3D, specimen, target_Pa: float) -> SideWalls3D:
    """The vessel about a 3D specimen: the cell about a cylinder, four side walls about a prism."""
    return (Cell3D if specimen.shape == "cylinder" else SideWalls3D)(platens, specimen, target_Pa)
