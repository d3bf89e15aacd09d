"""The lab targets of a campaign file: one section per lab test, [targets.<test>] for any test
in the lab-test registry (each test declares its section, `LabTest.lab_values`), and
[validation]: which of the tests given are validation checks only.

The primary test (UCS) is always calibrated against; another test given is too, unless
[validation] tests names it (default: bending, a validation check).
"""

from __future__ import annotations

from pydantic import ConfigDict, Field, ValidationError, field_validator, model_validator

from rockcal.errors import from_validation_error
from rockcal.labtests.lab_values import LabValues, Section, Spread, values_model  # noqa: F401
from rockcal.labtests.registry import LAB_TESTS, PRIMARY_TEST, lab_test

LabTargets = LabValues  # a test's section of [targets]


class Targets(Section):
    """[targets]: a section per lab test, by the test's name, the primary test's required."""

    model_config = ConfigDict(extra="allow", frozen=True)

    @model_validator(mode="before")
    @classmethod
    def _sections(cls, data):
        if not isinstance(data, dict):
            raise ValueError("a table of lab tests, e.g. [targets.ucs]")
        if PRIMARY_TEST not in data:
            raise ValueError(f"{PRIMARY_TEST}: a [targets.{PRIMARY_TEST}] section is required")
        return {name: _section(name, value) for name, value in data.items()}

    def given(self) -> dict[str, LabValues]:
        """The sections given, by test name, in the registry's order."""
        sections = self.model_extra or {}
        return {name: sections[name] for name in LAB_TESTS if name in sections}

    def __getattr__(self, name: str):
        if name in LAB_TESTS:  # a test the registry knows that is not given: None
            return (self.model_extra or {}).get(name)
        return super().__getattr__(name)


def _section(name: str, value) -> LabValues:
    """One [targets.<name>] section, validated by its test's model; an error names its key."""
    if name not in LAB_TESTS:
        raise ValueError(f"{name}: no lab test named {name!r}; known: {', '.join(LAB_TESTS)}")
    if isinstance(value, LabValues):
        return value
    try:
        section = values_model(lab_test(name)).model_validate(value)
    except ValidationError as exc:
        error = from_validation_error(exc, values_model(lab_test(name)))
        field = name if error.field == "input" else f"{name}.{error.field}"
        raise ValueError(f"{field}: {error.problem}") from None
    if name != PRIMARY_TEST and not section.measured():  # the primary's: `Campaign` checks it
        raise ValueError(f"{name}: no lab value given; give at least one of {', '.join(lab_test(name).targets)}")
    return section


class ValidationTests(Section):
    """The tests given in [targets] that are validation checks only, run at the identified
    parameters (default: bending); the others are calibrated against."""

    tests: list[str] = Field(["bending"], description="Tests given in [targets] that are checks only, run at the "
                             "identified parameters: bending, brazilian, biaxial, direct_tension, scb.")

    @field_validator("tests")
    @classmethod
    def _tests(cls, tests):
        for name in tests:
            if name not in LAB_TESTS:
                raise ValueError(f"no lab test named {name!r}; known: {', '.join(LAB_TESTS)}")
            if name == PRIMARY_TEST:
                raise ValueError(f"{PRIMARY_TEST} is always calibrated against; name another test")
        return tests
