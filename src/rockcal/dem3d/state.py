"""The spheres' arrays: one row per sphere in `bodies` (what the force loops gather of it) and
in `loads` (the force and moment summed on it). SI units throughout."""

from enum import IntEnum
from typing import NamedTuple

import numpy as np

from rockcal.dem3d.vectors import cubes


class Sphere(IntEnum):
    """Columns of a sphere's row in `bodies` (16 floats, two cache lines)."""

    X = 0
    Y = 1
    Z = 2
    VX = 3
    VY = 4
    VZ = 5
    WX = 6  # angular velocity, rad/s
    WY = 7
    WZ = 8
    RADIUS = 9
    INV_MASS = 10  # 0: a driven sphere, whose velocity and spin are prescribed
    INV_INERTIA = 11


BODY_WIDTH = 16


class Load(IntEnum):
    """Columns of a sphere's row in `loads` (8 floats, one cache line)."""

    FX = 0
    FY = 1
    FZ = 2
    MX = 3
    MY = 4
    MZ = 5


LOAD_COMPONENTS = len(Load)  # the columns of `loads` a sum fills
LOAD_WIDTH = 8


class Spheres(NamedTuple):
    """Views into the two arrays the engine works on (`Sphere`, `Load` columns)."""

    pos: np.ndarray  # (n, 3), m
    vel: np.ndarray  # (n, 3), m/s
    spin: np.ndarray  # (n, 3), rad/s
    radius: np.ndarray  # m
    inv_mass: np.ndarray  # 1/kg
    inv_inertia: np.ndarray  # 1/(kg m²)
    force: np.ndarray  # (n, 3): the last step's force, N
    moment: np.ndarray  # (n, 3): the last step's moment, N m
    bodies: np.ndarray
    loads: np.ndarray


def solid_sphere(radius, density: float):
    """Mass m = ρ 4/3 π R³ (kg) and moment of inertia I = 2/5 m R² (kg m²) of solid spheres."""
    radius = np.asarray(radius, float)
    mass = density * 4.0 / 3.0 * np.pi * cubes(radius)
    return mass, 0.4 * mass * radius**2


def new_spheres(pos, radius, density: float, driven=None) -> Spheres:
    """Solid spheres of `density` (kg/m³) at rest; the `driven` ones (indices) keep the
    velocity and spin they are given."""
    pos = np.asarray(pos, float)
    n = pos.shape[0]
    mass, inertia = solid_sphere(radius, density)
    bodies = _aligned_zeros(n, BODY_WIDTH)
    loads = _aligned_zeros(n, LOAD_WIDTH)
    bodies[:, Sphere.X:Sphere.Z + 1] = pos
    bodies[:, Sphere.RADIUS] = radius
    bodies[:, Sphere.INV_MASS] = 1.0 / mass
    bodies[:, Sphere.INV_INERTIA] = 1.0 / inertia
    if driven is not None:
        bodies[driven, Sphere.INV_MASS] = 0.0
        bodies[driven, Sphere.INV_INERTIA] = 0.0
    return Spheres(pos=bodies[:, Sphere.X:Sphere.Z + 1], vel=bodies[:, Sphere.VX:Sphere.VZ + 1],
                   spin=bodies[:, Sphere.WX:Sphere.WZ + 1], radius=bodies[:, Sphere.RADIUS],
                   inv_mass=bodies[:, Sphere.INV_MASS],
                   inv_inertia=bodies[:, Sphere.INV_INERTIA],
                   force=loads[:, Load.FX:Load.FZ + 1], moment=loads[:, Load.MX:Load.MZ + 1],
                   bodies=bodies, loads=loads)


def _aligned_zeros(n: int, width: int) -> np.ndarray:
    """Zeros of shape (n, width) float64 starting on a 64-byte boundary."""
    buffer = np.zeros(n * width + 8)
    skip = (-buffer.ctypes.data % 64) // 8
    return buffer[skip:skip + n * width].reshape(n, width)
