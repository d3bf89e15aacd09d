"""What every lab test's result holds besides its own responses."""

from __future__ import annotations

from dataclasses import dataclass, field, fields, is_dataclass

import numpy as np


@dataclass
class LabResult:
    """The specimen's size, the bonds broken and the cost of the run, then the curve and the
    broken specimen. A test's result adds its responses; the fields shown in its repr are its
    summary."""

    n_particles: int
    n_bonds: int
    n_broken_tension: int
    n_broken_shear: int
    steps: int
    wall_s: float
    curve: np.ndarray = field(repr=False)
    positions: np.ndarray = field(repr=False)
    radius: np.ndarray = field(repr=False)
    cracks: dict = field(repr=False)

    def summary(self) -> dict:
        """The scalar responses, the test's own first, as JSON-ready values."""
        shown = [f.name for f in fields(self) if f.repr]
        shared = [f.name for f in fields(LabResult) if f.repr]
        summary = {}
        for name in [n for n in shown if n not in shared] + shared:
            value = getattr(self, name)
            summary[name] = vars(value) if is_dataclass(value) else value  # e.g. the Beam
        return summary
