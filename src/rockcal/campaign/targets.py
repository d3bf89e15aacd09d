"""The lab targets of a campaign file: one section per lab test ([targets.ucs],
[targets.brazilian], [targets.bending]), each with the lab's spread and the weight of each
response, and [validation]: which of the tests given are validation checks only.

UCS is always calibrated against; a Brazilian test given is too, and bending is a validation
check unless [validation] tests leaves it out.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import ClassVar

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from rockcal.labtests.registry import LAB_TESTS, lab_test

# the lab's spread of a response: its sd, or the [min, max] of the lab's samples
Spread = dict[str, float | tuple[float, float]]


class Section(BaseModel):
    """A section of the campaign file: an unknown key is an error."""

    model_config = ConfigDict(extra="forbid", frozen=True)


class LabTargets(Section):
    """A lab test's results the calibration can fit (the test's measured responses), the lab's
    spread of each and its weight in the objective (default 1)."""

    test: ClassVar[str]
    spread: Spread = Field({}, description="The lab's spread of a response: its sd, or the [min, max] of the lab's "
                           "samples; turns the parameters' intervals on.")
    weights: dict[str, float] = Field({}, description="Weight of a response in the objective (default 1).")

    def scalars(self) -> dict[str, float]:
        """The responses given, by name."""
        return {k: getattr(self, k) for k in lab_test(self.test).targets if getattr(self, k) is not None}

    def derived(self) -> tuple[str, ...]:
        """Responses the section gives another way (from a measured curve)."""
        return ()

    @model_validator(mode="after")
    def _spread_and_weights(self):
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


class UCSTargets(LabTargets):
    """Lab results of the uniaxial compression test (at least one response)."""

    test: ClassVar[str] = "ucs"
    E_GPa: float | None = Field(None, gt=0, description="Young's modulus E, GPa (secant at half the peak).")
    nu: float | None = Field(None, gt=0, lt=0.5, description="Poisson's ratio ν (secant at half the peak).")
    ucs_MPa: float | None = Field(None, gt=0, description="Uniaxial compressive strength, MPa.")
    curve: Path | None = Field(None, description="CSV of the measured curve: axial strain, axial stress (MPa); "
                               "gives E and UCS when they are not given, and the curve's fit (RE, CC).")

    def derived(self) -> tuple[str, ...]:
        return ("E_GPa", "ucs_MPa") if self.curve is not None else ()


class BrazilianTargets(LabTargets):
    """Lab result of the Brazilian (splitting tensile) test."""

    test: ClassVar[str] = "brazilian"
    sigma_t_MPa: float = Field(gt=0, description="Brazilian tensile strength σ_t = 2P/(πDt), MPa.")


class BendingTargets(LabTargets):
    """Lab results of the notched three-point bending test."""

    test: ClassVar[str] = "bending"
    K_IC_MPa_sqrt_m: float = Field(gt=0, description="Fracture toughness K_IC, MPa·m^0.5.")
    P_max_kN: float | None = Field(None, gt=0, description="Peak load of the lab's round bar, kN, to cross-check "
                                   "K_IC with Ouchterlony's formula.")
    diameter_mm: float = Field(50.0, gt=0, description="The lab bar's diameter D, mm.")
    notch_mm: float = Field(18.0, gt=0, description="The lab bar's notch depth a, mm.")
    span_mm: float = Field(160.0, gt=0, description="The lab bar's support span S, mm.")


class Targets(Section):
    """The lab results, one section per lab test."""

    ucs: UCSTargets
    brazilian: BrazilianTargets | None = None
    bending: BendingTargets | None = None

    def given(self) -> dict[str, LabTargets]:
        """The sections given, by test name."""
        return {name: getattr(self, name) for name in type(self).model_fields
                if getattr(self, name) is not None}


class ValidationTests(Section):
    """The tests given in [targets] that are validation checks only, run at the identified
    parameters (default: bending); the others are calibrated against."""

    tests: list[str] = Field(["bending"], description="Tests given in [targets] that are checks only, run at the "
                             "identified parameters: bending, brazilian.")

    @field_validator("tests")
    @classmethod
    def _tests(cls, tests):
        for name in tests:
            if name not in LAB_TESTS:
                raise ValueError(f"no lab test named {name!r}; known: {', '.join(LAB_TESTS)}")
            if name == "ucs":
                raise ValueError("ucs is always calibrated against; name bending or brazilian")
        return tests
