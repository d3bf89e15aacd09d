"""The engine as a lab test sees it, whatever the dimension: a model's state that steps in
time, scales its masses for a quasi-static test and counts its cracks. Two engines implement
it: `rockcal.dem` (PFC2D's disks, and clumps of them) and `rockcal.dem3d` (PFC3D's spheres).
A lab test's rig (`rockcal.labtests.rig`) builds the state of its specimen's dimension; the
test's procedure then asks only this protocol.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np


class ModelBroke(FloatingPointError):
    """The model is no packing any more (a position not a number, or the particles scattered
    far beyond the specimen): its run cannot go on. A lab test ends such a run in one line."""


class Bodies(Protocol):
    """The particles' arrays: centres (n, dimensions) and radii, m."""

    pos: np.ndarray
    radius: np.ndarray


class ModelState(Protocol):
    """A bonded-particle model's state: its `particles` (a specimen's first, a rig's after
    them), the steps run so far and the time step (s)."""

    step: int
    dt: float

    @property
    def particles(self) -> Bodies: ...

    @property
    def n_particles(self) -> int: ...

    def advance(self, n_steps: int) -> None:
        """Run `n_steps` time steps."""

    def scale_density(self) -> float:
        """Scale the free bodies' masses for a quasi-static test (PFC's timestep scaling)."""

    def breaks(self) -> tuple[np.ndarray, np.ndarray]:
        """How each bond broke (INTACT 0, BROKEN_TENSION 1, BROKEN_SHEAR 2) and where (m)."""

    def n_broken(self, mode: int | None = None) -> int:
        """Bonds broken so far, in `mode` or (None) either."""
