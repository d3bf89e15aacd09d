"""What every lab test's result holds besides its own responses."""

from __future__ import annotations

import contextlib
import time
from dataclasses import dataclass, field, fields, is_dataclass

import numpy as np

from rockcal.dem import measure
from rockcal.dem.laws import BROKEN_SHEAR, BROKEN_TENSION
from rockcal.engine import ModelBroke


class RunFailed(RuntimeError):
    """A lab test's run that could not go on: the physics failed, not the input (which was
    checked before the run). Its message says what failed and what to try."""


@contextlib.contextmanager
def failed_run():
    """A model that broke while the test ran (`rockcal.engine.ModelBroke`) as the test's
    RunFailed: one line, the run not stored as done."""
    try:
        yield
    except ModelBroke as exc:
        raise RunFailed(f"the model broke while the test ran ({exc}): the loading or the time step is too "
                        "much for these micro-parameters; check them, or try a finer specimen") from None


# The range of a response of an elastic solid, open at both ends: a reading outside it is no
# solid's. A 2D specimen is a plane of disks, an isotropic 2D solid of area (bulk) modulus
# K > 0 and shear modulus G > 0, whose nu = -lateral / axial strain = (K - G) / (K + G) lies
# in (-1, 1); E = 4 K G / (K + G) > 0. (A 3D solid's nu in (-1, 0.5] reads as itself in plane
# stress and as nu / (1 - nu) in (-0.5, 1] in plane strain: within the same bounds.) Not the
# lab's range of rock (0 < nu < 0.5): a 2D packing may read nu above 0.5 and still be a solid.
SOLID_RANGE = {"nu": (-1.0, 1.0), "E_GPa": (0.0, float("inf"))}


def out_of_range(responses: dict) -> list[str]:
    """Each response outside SOLID_RANGE, in words: no reading of an elastic solid."""
    found = []
    for name, (low, high) in SOLID_RANGE.items():
        value = responses.get(name)
        if isinstance(value, (int, float)) and not low < value < high:
            found.append(f"{name} = {value:.4g} is outside ({low:g}, {high:g}), the range of an elastic "
                         "2D solid: no elastic reading (too few grains for the gauges, too few bonds, or "
                         "a specimen that did not load as a solid)")
    return found


NOT_FAILED = ("no bond broke: the specimen did not fail, and its peak is no strength (a contact slipping "
              "or the specimen seating; too few grains for the test?): give a larger specimen or a smaller R_min")


def warnings_of(summary: dict) -> list[str]:
    """What makes a run's responses meaningless, in words: a reading outside an elastic solid's
    range (`out_of_range`), a run that broke no bond (its summary's `failed` False)."""
    return out_of_range(summary) + ([NOT_FAILED] if summary.get("failed") is False else [])


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

    def __post_init__(self):
        for f in fields(self):  # numpy scalars as Python's: a result reads as plain numbers
            value = getattr(self, f.name)
            if isinstance(value, np.generic):
                setattr(self, f.name, value.item())

    def summary(self) -> dict:
        """The scalar responses, the test's own first, as JSON-ready values, and whether it failed."""
        shown = [f.name for f in fields(self) if f.repr]
        shared = [f.name for f in fields(LabResult) if f.repr]
        summary = {}
        for name in [n for n in shown if n not in shared] + shared:
            value = getattr(self, name)
            summary[name] = vars(value) if is_dataclass(value) else value  # e.g. the Beam
        return summary | {"failed": self.failed}

    @property
    def failed(self) -> bool:
        """Whether the specimen failed, broke a bond at least: a peak without a broken bond is
        no strength."""
        return self.n_broken_tension + self.n_broken_shear > 0


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
