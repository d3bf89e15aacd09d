"""What every lab test's result holds besides its own responses."""

from __future__ import annotations

import time
from dataclasses import dataclass, field, fields, is_dataclass

import numpy as np

from rockcal.dem import measure
from rockcal.dem.laws import BROKEN_SHEAR, BROKEN_TENSION


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


def run_fields(state, specimen, started: float) -> dict:
    """The fields every result takes from the test's final engine state: the specimen is its
    first `specimen.n_particles` particles (any after them are the test's rig); `started` is
    the test's `time.perf_counter()` at its start."""
    n = specimen.n_particles
    return dict(n_particles=n, n_bonds=len(specimen.bonds),
                n_broken_tension=state.n_broken(BROKEN_TENSION),
                n_broken_shear=state.n_broken(BROKEN_SHEAR), steps=state.step,
                wall_s=time.perf_counter() - started, positions=state.particles.pos[:n].copy(),
                radius=specimen.radius,
                cracks=measure.cracks(*state.breaks()))
