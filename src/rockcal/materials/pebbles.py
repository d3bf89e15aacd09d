"""A clump template's pebbles (`ClumpTemplate`), the 2D form that the 3D one
(`clump_templates_3d.ClumpTemplate3D`) extends, and the named shapes' pebble spacing: what the
templates of both dimensions share (`clump_templates`, `clump_templates_3d`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

# centre distance of neighbouring pebbles / pebble radius: one pebble radius makes a grain half
# again as long as it is wide (elongated grains that interlock, as Cho et al. (2007) build theirs)
PEBBLE_SPACING = 1.0


@dataclass(frozen=True)
class ClumpTemplate:
    """A clump's pebbles: `offsets` (k, 2) from its centroid and `radii` (k,), both in units of
    its equivalent radius (module docstring)."""

    name: str
    offsets: np.ndarray
    radii: np.ndarray

    @property
    def n_pebbles(self) -> int:
        return len(self.radii)

    @property
    def extent(self) -> float:
        """The farthest reach of a pebble from the centroid, in equivalent radii."""
        return float((np.hypot(*self.offsets.T) + self.radii).max())

    def pebbles(self, size_m: float, angle_rad: float) -> tuple[np.ndarray, np.ndarray]:
        """The offsets (m) and radii (m) of a clump of equivalent radius `size_m` turned by
        `angle_rad` counter-clockwise."""
        c, s = math.cos(angle_rad), math.sin(angle_rad)
        x, y = self.offsets[:, 0], self.offsets[:, 1]
        turned = np.stack([c * x - s * y, s * x + c * y], axis=-1)  # not @: BLAS rounds by processor
        return size_m * turned, size_m * self.radii
