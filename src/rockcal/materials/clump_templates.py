"""Clump templates: the shapes of the grains of a clumped material (FISHTank's clumped
materials, `cm_shape`; PFC's `clump template`), by name.

A template is its pebbles' offsets and radii in units of the clump's equivalent radius, the
radius of a disk of the clump's area (overlaps counted once: `clumps.union_properties`), with
the clump's centroid at the origin. The grain size distribution applies to this equivalent
radius, as FISHTank sizes its clumps by their equivalent diameter: a clump of equivalent radius
R has pebbles at R x offset of radii R x radius, and the area π R² of a ball of radius R.

- "ball": one pebble, the ball itself;
- "two-pebble": two equal pebbles whose centres lie PEBBLE_SPACING pebble radii apart;
- "three-pebble": three equal pebbles at the corners of an equilateral triangle of side
  PEBBLE_SPACING pebble radii;
- "cloud": CLOUD_PEBBLES pebbles of random radii, each overlapping one pebble before it at a
  random offset, so that they make one body (`pebble_cloud`, drawn from CLOUD_SEED: the same
  template in every run).

Every template here reaches less than MAX_EXTENT equivalent radii from its centroid, so a
specimen at least 4 grain diameters wide (`specimen.check_geometry`) holds its largest clump.
"""

from __future__ import annotations

import functools
import math
import numpy as np

from rockcal.dem.clumps import union_properties
from rockcal.errors import InputError
from rockcal.materials.pebbles import PEBBLE_SPACING, ClumpTemplate

DEFAULT_SHAPE = "ball"
# the "cloud": its pebbles, their radii (in units of the largest possible) and each one's centre
# distance to the pebble it overlaps (a fraction of their radii's sum: < 1 overlaps), and its seed
CLOUD_PEBBLES = 4
CLOUD_RADII = (0.5, 1.0)
CLOUD_SPACING = (0.4, 0.8)
CLOUD_SEED = 2024
MAX_EXTENT = 4.0  # equivalent radii: a specimen 4 diameters wide holds such a clump


def from_pebbles(name: str, centres, radii, field: str = "grain_shape") -> ClumpTemplate:
    """A template of pebbles given in any length unit and placement: moved to put the union's
    centroid at the origin and scaled to unit equivalent radius. InputError naming `field` if
    there is no pebble, a radius is not positive, or the pebbles do not overlap into one body."""
    centres = np.asarray(centres, float).reshape(-1, 2)
    radii = np.asarray(radii, float).reshape(-1)
    if len(radii) == 0 or len(centres) != len(radii):
        raise InputError(field, f"template {name!r} needs one or more pebbles, each a centre and a radius")
    if not (np.isfinite(centres).all() and np.isfinite(radii).all() and (radii > 0).all()):
        raise InputError(field, f"template {name!r}: every pebble needs a finite centre and a radius > 0")
    if not _one_body(centres, radii):
        raise InputError(field, f"template {name!r}: its pebbles must overlap into one body "
                                "(each linked to the others through overlapping pebbles)")
    area, centroid, _ = union_properties(centres, radii)
    scale = math.sqrt(area / math.pi)
    return ClumpTemplate(name, (centres - centroid) / scale, radii / scale)


def _one_body(centres: np.ndarray, radii: np.ndarray) -> bool:
    """Whether the pebbles, linked where two overlap (centre distance < sum of radii), are all
    linked to the first."""
    d = np.hypot(*(centres[:, None, :] - centres[None, :, :]).transpose(2, 0, 1))
    linked = d < radii[:, None] + radii[None, :]
    reached = np.zeros(len(radii), bool)
    reached[0] = True
    while True:
        more = reached | linked[reached].any(axis=0)
        if (more == reached).all():
            return bool(reached.all())
        reached = more


def pebble_cloud(seed: int, n_pebbles: int = CLOUD_PEBBLES, name: str = "cloud") -> ClumpTemplate:
    """A template of `n_pebbles` pebbles of radii uniform in CLOUD_RADII, the first at the
    origin, each later one overlapping an earlier one drawn at random: its centre at a uniform
    fraction CLOUD_SPACING of their radii's sum from that one's, in a uniform direction. One
    body by construction; the same pebbles for the same seed."""
    if isinstance(n_pebbles, bool) or int(n_pebbles) != n_pebbles or n_pebbles < 1:
        raise InputError("grain_shape", f"template {name!r} needs one or more pebbles, got {n_pebbles!r}")
    rng = np.random.default_rng([seed, int(n_pebbles)])
    radii = rng.uniform(*CLOUD_RADII, int(n_pebbles))
    centres = np.zeros((int(n_pebbles), 2))
    for k in range(1, int(n_pebbles)):
        on = int(rng.integers(k))
        distance = rng.uniform(*CLOUD_SPACING) * (radii[k] + radii[on])
        angle = rng.uniform(0.0, 2.0 * math.pi)
        centres[k] = centres[on] + distance * np.array([math.cos(angle), math.sin(angle)])
    return from_pebbles(name, centres, radii)


def _polygon(corners: int, spacing: float) -> np.ndarray:
    """Centres of `corners` unit pebbles on a regular polygon of side `spacing`."""
    if corners == 1:
        return np.zeros((1, 2))
    circumradius = spacing / (2.0 * math.sin(math.pi / corners))
    angles = [2.0 * math.pi * k / corners for k in range(corners)]  # the C library's cos, sin
    return circumradius * np.array([[math.cos(a), math.sin(a)] for a in angles])


_MAKERS = {
    "ball": lambda: ClumpTemplate("ball", np.zeros((1, 2)), np.ones(1)),
    "two-pebble": lambda: from_pebbles("two-pebble", _polygon(2, PEBBLE_SPACING), np.ones(2)),
    "three-pebble": lambda: from_pebbles("three-pebble", _polygon(3, PEBBLE_SPACING), np.ones(3)),
    "cloud": lambda: pebble_cloud(CLOUD_SEED),
}
GRAIN_SHAPES = tuple(_MAKERS)


def template(name: str, field: str = "grain_shape", dimensions: int = 2) -> ClumpTemplate:
    """The template of that name in `dimensions` (a 3D one is a
    `clump_templates_3d.ClumpTemplate3D`); InputError naming `field` for a name no template of
    that dimension has."""
    makers = _makers(dimensions)
    if not isinstance(name, str) or name not in makers:
        where = " in 3D" if dimensions == 3 else ""
        raise InputError(field, f"no grain shape named {name!r}{where}; known{where}: {', '.join(makers)}")
    return _made(name, dimensions)


def _makers(dimensions: int) -> dict:
    if dimensions == 3:
        from rockcal.materials.clump_templates_3d import MAKERS_3D  # the 3D engine's: for 3D alone

        return MAKERS_3D
    return _MAKERS


@functools.cache
def _made(name: str, dimensions: int) -> ClumpTemplate:
    """A template, made when first asked for: a union's area (volume) is compiled code, which a
    command that runs no clump need not load."""
    return _makers(dimensions)[name]()
