"""A lab's values for one kind of test, as a campaign file gives them ([targets.<test>]): the
responses measured, the lab's spread of each and its weight in the objective. Each test module
declares its own section (`LabTest.lab_values`); a test that declares none gets one with each
of its target responses as an optional number > 0 (`values_model`)."""

from __future__ import annotations

import io
import math
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, ClassVar

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, create_model, model_validator

from rockcal.errors import InputError
from rockcal.labtests.plausible import implausible
from rockcal.user_files import read_user_text

if TYPE_CHECKING:
    from rockcal.labtests.kind import LabTest

# the lab's spread of a response: its sd, or the [min, max] of the lab's samples
Spread = dict[str, float | tuple[float, float]]


class Section(BaseModel):
    """A section of the campaign file: an unknown key is an error."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


class LabValues(Section):
    """A lab test's results the calibration can fit (the test's measured responses), the lab's
    spread of each and its weight in the objective (default 1)."""

    kind: ClassVar[LabTest]  # the test whose section this is: its `LabTest` sets it
    spread: Spread = Field({}, description="The lab's spread of a response: its sd, or the [min, max] of the lab's "
                           "samples; turns the parameters' intervals on.")
    weights: dict[str, float] = Field({}, description="Weight of a response in the objective (default 1).")
    packings: int = Field(1, ge=1, le=100, description="Its target is the mean over this many packings (the specimen's "
                          "seed, seed + 1, ...), run at each verified point: for a response a few grains decide.")

    def scalars(self) -> dict[str, float]:
        """The responses given, by name."""
        return {k: getattr(self, k) for k in self.kind.targets if getattr(self, k) is not None}

    def series(self) -> list:
        """The values of its test's series setting given here (a run each at every parameter
        set: the confinements of confined compression), or [] for a test run once."""
        setting = self.kind.series
        return list(getattr(self, setting.name, None) or []) if setting else []

    def derived(self) -> tuple[str, ...]:
        """Responses the section gives another way (from a measured curve)."""
        return ()

    def measured(self) -> dict[str, float]:
        """The targets: the responses given, completed from a measured curve if any."""
        return self.scalars()

    def measured_curve(self):
        """The measured curve the calibrated curve is compared with (None: none given)."""
        return None

    @model_validator(mode="after")
    def _spread_and_weights(self):
        for name in type(self).model_fields:  # a value in the wrong unit first: the rest follows from it
            problem = implausible(name, getattr(self, name))
            if problem:
                raise ValueError(f"{name}: {problem}")
        given = self.scalars()
        for key, values in (("spread", self.spread), ("weights", self.weights)):
            for name in values:
                if name not in given and name not in self.derived():
                    raise ValueError(f"{key}.{name}: not a target given here ({', '.join(given)})")
        for name, s in self.spread.items():
            value = given.get(name)
            if isinstance(s, tuple):
                holds = value is None or s[0] <= value <= s[1]
                if not (math.isfinite(s[0]) and math.isfinite(s[1]) and s[0] < s[1] and holds):
                    raise ValueError(f"spread.{name}: [min, max] must hold the target {value}, got {list(s)}")
            elif not (math.isfinite(s) and s > 0):
                raise ValueError(f"spread.{name}: an sd must be > 0, got {s}")
        for name, w in self.weights.items():
            if not (math.isfinite(w) and w > 0):
                raise ValueError(f"weights.{name}: a weight must be a finite number > 0, got {w}")
        return self




@lru_cache(maxsize=None)
def values_model(test) -> type[LabValues]:
    """The section model of a lab test: its own, or one made from its target responses."""
    if test.lab_values is not None:
        return test.lab_values
    fields = {name: (float | None, Field(None, gt=0)) for name in test.targets}
    model = create_model(f"{test.name.title()}Values", __base__=LabValues,
                         __doc__=f"Lab results of the {test.title} test.", **fields)
    model.kind = test
    return model


def read_curve(path: Path, field: str = "targets.ucs.curve") -> np.ndarray:
    """A measured stress-strain curve: rows of (axial strain, axial stress MPa), strain rising."""
    text = read_user_text(path, field)
    try:
        rows = np.genfromtxt(io.StringIO(text), delimiter=",", dtype=float, invalid_raise=True)
    except ValueError as exc:
        raise InputError(field, f"cannot read {path}: {exc}") from None
    if rows.ndim == 2 and rows.shape[1] >= 2 and np.isnan(rows[0]).all():
        rows = rows[1:]  # a header line
    if rows.ndim != 2 or rows.shape[1] < 2 or len(rows) < 3:
        raise InputError(field, f"{path}: need at least 3 rows of 'strain, stress_MPa'")
    rows = rows[:, :2]
    if not np.isfinite(rows).all():
        bad = int(np.flatnonzero(~np.isfinite(rows).all(axis=1))[0]) + 1
        raise InputError(field, f"{path}: data row {bad} is not two numbers")
    if np.any(np.diff(rows[:, 0]) <= 0):
        bad = int(np.flatnonzero(np.diff(rows[:, 0]) <= 0)[0]) + 2
        raise InputError(field, f"{path}: strain must increase, it does not at data row {bad}")
    return rows
