"""Planar walls: the vessel's faces during genesis and the platens of a compression test.

A wall is an infinite plane through a point, its unit normal pointing to the side the spheres
are on, moving at a prescribed velocity. Its contact with a sphere is PFC3D's ball-facet
linear contact under the deformability method with the wall as a rigid facet: L = R (the
facet adds no length), A = π R², so kn = E π R² / R = π E R, with E the wall's modulus; the
walls are frictionless with ks = 0, as FISHTank's platens and vessel walls, so they push along
their normal only and load no moment.
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


WALL_WIDTH = len(Wall)


class Walls(NamedTuple):
    """The walls' rows and the force the spheres put on each in the last step (N)."""

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

    def normal_force(self) -> np.ndarray:
        """Each wall's force along its normal, pushed by the spheres (compression positive), N."""
        return -np.einsum("wa,wa->w", self.force, self.normal)


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
    return np.einsum("kwa,wa->kw", pos[:, None, :] - walls.point[None], walls.normal) \
        - radius[:, None]


def wall_springs(walls: Walls, pos: np.ndarray, radius: np.ndarray, reach: float) -> np.ndarray:
    """Each sphere's normal stiffness π E R summed over the walls within `reach` of it, N/m
    (the walls load no rotation)."""
    near = gaps(walls, pos, radius) < reach
    return np.pi * radius * (near * walls.table[:, Wall.MODULUS][None]).sum(axis=1)


@njit(inline="always", error_model="numpy")
def sphere_gap(bodies, k, walls, w):
    """Sphere k's gap to wall w along the wall's normal (negative: overlapping), m."""
    gap = -bodies[k, Sphere.RADIUS]
    for a in range(3):
        gap += (bodies[k, Sphere.X + a] - walls[w, Wall.PX + a]) * walls[w, Wall.NX + a]
    return gap


@njit(cache=True, error_model="numpy")
def add_wall_forces(first, last, bodies, loads, walls, wall_force):
    """The walls' pushes on spheres first..last-1, added to their loads; each wall's reaction
    summed into `wall_force` (walls, 3) in sphere order."""
    for k in range(uint64(first), uint64(last)):
        r = bodies[k, Sphere.RADIUS]
        for w in range(walls.shape[0]):
            gap = sphere_gap(bodies, k, walls, w)
            if gap < 0.0:
                push = -np.pi * walls[w, Wall.MODULUS] * r * gap
                for a in range(3):
                    f = push * walls[w, Wall.NX + a]
                    loads[k, Load.FX + a] += f
                    wall_force[w, a] -= f


@njit(cache=True, error_model="numpy")
def move_walls(walls, dt):
    for w in range(walls.shape[0]):
        for a in range(3):
            walls[w, Wall.PX + a] += walls[w, Wall.VX + a] * dt


@njit(cache=True, error_model="numpy")
def touching_counts(walls, bodies):
    """How many spheres (rows of `bodies`) overlap each wall: a servo's N_c."""
    counts = np.zeros(walls.shape[0], np.int64)
    for k in range(bodies.shape[0]):
        for w in range(walls.shape[0]):
            if sphere_gap(bodies, k, walls, w) < 0.0:
                counts[w] += 1
    return counts
