"""Clump templates in 3D: the grain shapes of a clumped material of spheres (PFC3D's `clump
template`), under the 2D shapes' names (`clump_templates`) where they mean the same.

A template is its pebbles' offsets and radii in units of the clump's equivalent radius, the
radius of a sphere of the clump's volume (overlaps counted once: `dem3d.clumps.union_properties`),
its centroid at the origin. The grain size distribution applies to this equivalent radius: a
clump of equivalent radius R has pebbles at R x offset of radii R x radius and the volume
4/3 π R³ of a ball of radius R.

- "ball": one pebble, the ball itself;
- "two-pebble": two equal pebbles whose centres lie PEBBLE_SPACING pebble radii apart;
- "three-pebble": three equal pebbles at the corners of an equilateral triangle of side
  PEBBLE_SPACING pebble radii (a flat grain).

The 2D "cloud" has no 3D template yet.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rockcal.dem3d.clumps import union_properties
from rockcal.materials.pebbles import PEBBLE_SPACING, ClumpTemplate


@dataclass(frozen=True)
class ClumpTemplate3D(ClumpTemplate):
    """A clump's pebbles: `offsets` (k, 3) from its centroid and `radii` (k,), both in units of
    its equivalent radius (module docstring)."""

    @property
    def extent(self) -> float:
        """The farthest reach of a pebble from the centroid, in equivalent radii."""
        return float((np.sqrt((self.offsets**2).sum(axis=1)) + self.radii).max())

    def pebbles(self, size_m: float, rotation: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The offsets (m) and radii (m) of a clump of equivalent radius `size_m` turned by the
        rotation matrix `rotation` (3, 3)."""
        o = self.offsets  # the products written out: BLAS's @ rounds by processor
        turned = np.stack([rotation[a, 0] * o[:, 0] + rotation[a, 1] * o[:, 1] + rotation[a, 2] * o[:, 2]
                           for a in range(3)], axis=-1)
        return size_m * turned, size_m * self.radii


def from_pebbles(name: str, centres, radii) -> ClumpTemplate3D:
    """A template of pebbles given in any length unit and placement: moved to put the union's
    centroid at the origin and scaled to unit equivalent radius."""
    centres = np.asarray(centres, float).reshape(-1, 3)
    radii = np.asarray(radii, float)
    volume, centroid, _ = union_properties(centres, radii)
    scale = (volume / (4.0 / 3.0 * math.pi)) ** (1.0 / 3.0)
    return ClumpTemplate3D(name, (centres - centroid) / scale, radii / scale)


def _polygon(corners: int, spacing: float) -> np.ndarray:
    """Centres of `corners` unit pebbles on a regular polygon of side `spacing` in the x-y plane."""
    circumradius = spacing / (2.0 * math.sin(math.pi / corners))
    angles = [2.0 * math.pi * k / corners for k in range(corners)]  # the C library's cos, sin
    return circumradius * np.array([[math.cos(a), math.sin(a), 0.0] for a in angles])


MAKERS_3D = {  # `clump_templates.template(name, dimensions=3)` makes them
    "ball": lambda: ClumpTemplate3D("ball", np.zeros((1, 3)), np.ones(1)),
    "two-pebble": lambda: from_pebbles("two-pebble", _polygon(2, PEBBLE_SPACING), np.ones(2)),
    "three-pebble": lambda: from_pebbles("three-pebble", _polygon(3, PEBBLE_SPACING), np.ones(3)),
}
GRAIN_SHAPES_3D = tuple(MAKERS_3D)


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    """A rotation matrix drawn uniformly over orientations (from a uniform unit quaternion)."""
    w, x, y, z = rng.normal(size=4)
    norm = math.sqrt(w * w + x * x + y * y + z * z)
    return rotation_matrix(w / norm, x / norm, y / norm, z / norm)


def rotation_matrix(w: float, x: float, y: float, z: float) -> np.ndarray:
    """The rotation of the unit quaternion w + x i + y j + z k."""
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
