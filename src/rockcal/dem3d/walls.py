"""Walls: the vessel's faces during genesis, the platens of a compression test and the
triaxial cell's cylinder.

A planar wall is an infinite plane through a point, its unit normal pointing to the side the
spheres are on, moving at a prescribed velocity. A cylindrical wall (`with_cylinder`) is the
inner surface of an infinite cylinder about an axis through a point, the spheres inside it; its
radius changes at a prescribed radial speed (outward positive), as FISHTank's cylindrical
vessel's vertices move radially. A wall's contact with a sphere is PFC3D's ball-facet linear
contact under the deformability method with the wall as a rigid facet: L = R (the facet adds
no length), A = π R², so kn = E π R² / R = π E R, with E the wall's modulus; the walls are
frictionless with ks = 0, as FISHTank's platens and vessel walls, so a plane pushes along its
normal and a cylinder towards its axis only, and neither loads a moment.
"""

from __future__ import annotations

from enum import IntEnum
from typing import NamedTuple

import numpy as np
from numba import njit, uint64

from rockcal.dem3d.state import Load, Sphere


class Wall(IntEnum):
    """Columns of a wall's row in `Walls.table`."""

    PX = 0  # a point on the plane, m
    PY = 1
    PZ = 2
    NX = 3  # unit normal, towards the spheres
    NY = 4
    NZ = 5
    VX = 6  # velocity, m/s
    VY = 7
    VZ = 8
    MODULUS = 9  # E of its contacts, kn = π E R, Pa
    KIND = 10  # PLANE or CYLINDER (the point on its axis, the normal its axis)
    RADIUS = 11  # a cylinder's radius, m
    RADIAL_VEL = 12  # a cylinder's radius' rate, outward positive, m/s


WALL_WIDTH = len(Wall)
PLANE, CYLINDER = 0.0, 1.0


class Walls(NamedTuple):
    """The walls' rows and the force the spheres put on each in the last step (N): a plane's
    vector, a cylinder's summed radial push (outward positive) in its first column."""

    table: np.ndarray  # (walls, WALL_WIDTH)
    force: np.ndarray  # (walls, 3)

    @property
    def point(self) -> np.ndarray:
        return self.table[:, Wall.PX:Wall.PZ + 1]

    @property
    def normal(self) -> np.ndarray:
        return self.table[:, Wall.NX:Wall.NZ + 1]

    @property
    def vel(self) -> np.ndarray:
        return self.table[:, Wall.VX:Wall.VZ + 1]

    @property
    def cylinder(self) -> np.ndarray:
        """Which walls are cylinders."""
        return self.table[:, Wall.KIND] == CYLINDER

    def normal_force(self) -> np.ndarray:
        """Each wall's force along its normal, pushed by the spheres (compression positive), N;
        a cylinder's, its radial pushes summed."""
        return np.where(self.cylinder, self.force[:, 0], -np.einsum("wa,wa->w", self.force, self.normal))


def new_walls(points, normals, modulus_pa: float) -> Walls:
    """Walls at rest through `points` with normals `normals` (normalised here), their contacts'
    modulus `modulus_pa`."""
    points = np.asarray(points, float).reshape(-1, 3)
    normals = np.asarray(normals, float).reshape(-1, 3)
    table = np.zeros((len(points), WALL_WIDTH))
    table[:, Wall.PX:Wall.PZ + 1] = points
    table[:, Wall.NX:Wall.NZ + 1] = normals / np.linalg.norm(normals, axis=1)[:, None]
    table[:, Wall.MODULUS] = modulus_pa
    return Walls(table=table, force=np.zeros((len(points), 3)))


def with_cylinder(walls: Walls, axis_point, axis, radius_m: float, modulus_pa: float) -> Walls:
    """`walls` and, after them, a cylindrical wall at rest of `radius_m` about the axis through
    `axis_point` along `axis`, its contacts' modulus `modulus_pa`."""
    cylinder = new_walls(axis_point, axis, modulus_pa)
    cylinder.table[0, Wall.KIND] = CYLINDER
    cylinder.table[0, Wall.RADIUS] = radius_m
    return Walls(table=np.vstack([walls.table, cylinder.table]), force=np.vstack([walls.force, cylinder.force]))


def no_walls() -> Walls:
    return new_walls(np.empty((0, 3)), np.empty((0, 3)), 0.0)


def box_walls(lo, hi, modulus_pa: float) -> Walls:
    """The six faces of the cuboid [lo, hi] (m), facing in: -x, +x, -y, +y, -z, +z in order."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    points, normals = [], []
    for a in range(3):
        for at, sign in ((lo, 1.0), (hi, -1.0)):
            point = 0.5 * (lo + hi)
            point[a] = at[a]
            points.append(point)
            normals.append(sign * np.eye(3)[a])
    return new_walls(points, normals, modulus_pa)


def gaps(walls: Walls, pos: np.ndarray, radius: np.ndarray) -> np.ndarray:
    """(spheres, walls): each sphere's gap to each wall (negative: overlap), m."""
    offset = pos[:, None, :] - walls.point[None]
    along = np.einsum("kwa,wa->kw", offset, walls.normal)
    off_axis = np.linalg.norm(offset - along[:, :, None] * walls.normal[None], axis=2)
    return np.where(walls.cylinder, walls.table[:, Wall.RADIUS] - off_axis, along) - radius[:, None]


def wall_springs(walls: Walls, pos: np.ndarray, radius: np.ndarray, reach: float) -> np.ndarray:
    """Each sphere's normal stiffness π E R summed over the walls within `reach` of it, N/m
    (the walls load no rotation)."""
    near = gaps(walls, pos, radius) < reach
    return np.pi * radius * (near * walls.table[:, Wall.MODULUS][None]).sum(axis=1)


@njit(inline="always", error_model="numpy")
def _along(bodies, k, walls, w):
    """Sphere k's centre's distance from wall w's point along its normal (a cylinder's axis), m."""
    along = 0.0
    for a in range(3):
        along += (bodies[k, Sphere.X + a] - walls[w, Wall.PX + a]) * walls[w, Wall.NX + a]
    return along


@njit(inline="always", error_model="numpy")
def _off_axis(bodies, k, walls, w, a, along):
    """Component a of sphere k's centre's offset from cylinder w's axis, m."""
    return bodies[k, Sphere.X + a] - walls[w, Wall.PX + a] - along * walls[w, Wall.NX + a]


@njit(inline="always", error_model="numpy")
def _axis_distance(bodies, k, walls, w, along):
    """Sphere k's centre's distance from cylinder w's axis, m."""
    squared = 0.0
    for a in range(3):
        squared += _off_axis(bodies, k, walls, w, a, along) ** 2
    return np.sqrt(squared)


@njit(inline="always", error_model="numpy")
def sphere_gap(bodies, k, walls, w):
    """Sphere k's gap to wall w (negative: overlapping), m: along a plane's normal, or
    inward from a cylinder's surface."""
    if walls[w, Wall.KIND] == CYLINDER:
        distance = _axis_distance(bodies, k, walls, w, _along(bodies, k, walls, w))
        return walls[w, Wall.RADIUS] - distance - bodies[k, Sphere.RADIUS]
    gap = -bodies[k, Sphere.RADIUS]
    for a in range(3):
        gap += (bodies[k, Sphere.X + a] - walls[w, Wall.PX + a]) * walls[w, Wall.NX + a]
    return gap


@njit(cache=True, error_model="numpy")
def add_wall_forces(first, last, bodies, loads, walls, wall_force):
    """The walls' pushes on spheres first..last-1, added to their loads; each wall's reaction
    summed into `wall_force` (walls, 3) in sphere order (a cylinder's radial push in its first
    column)."""
    for k in range(uint64(first), uint64(last)):
        r = bodies[k, Sphere.RADIUS]
        for w in range(walls.shape[0]):
            gap = sphere_gap(bodies, k, walls, w)
            if gap < 0.0:
                push = -np.pi * walls[w, Wall.MODULUS] * r * gap
                if walls[w, Wall.KIND] == CYLINDER:  # towards the axis
                    along = _along(bodies, k, walls, w)
                    inward = -push / _axis_distance(bodies, k, walls, w, along)
                    for a in range(3):
                        loads[k, Load.FX + a] += inward * _off_axis(bodies, k, walls, w, a, along)
                    wall_force[w, 0] += push
                    continue
                for a in range(3):
                    f = push * walls[w, Wall.NX + a]
                    loads[k, Load.FX + a] += f
                    wall_force[w, a] -= f


@njit(cache=True, error_model="numpy")
def move_walls(walls, dt):
    for w in range(walls.shape[0]):
        for a in range(3):
            walls[w, Wall.PX + a] += walls[w, Wall.VX + a] * dt
        walls[w, Wall.RADIUS] += walls[w, Wall.RADIAL_VEL] * dt


@njit(cache=True, error_model="numpy")
def touching_counts(walls, bodies):
    """How many spheres (rows of `bodies`) overlap each wall: a servo's N_c."""
    counts = np.zeros(walls.shape[0], np.int64)
    for k in range(bodies.shape[0]):
        for w in range(walls.shape[0]):
            if sphere_gap(bodies, k, walls, w) < 0.0:
                counts[w] += 1
    return counts
