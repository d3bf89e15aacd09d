"""The kinds of lab test a campaign can run, by name: the one place a test is known. A new
test is a module declaring its `TEST` (`rockcal.labtests.kind.LabTest`) and one line here
(or a `register` call)."""

from __future__ import annotations

from rockcal.errors import InputError
from rockcal.labtests import bending, biaxial, brazilian, direct_tension, scb, ucs
from rockcal.labtests.kind import LabTest

LAB_TESTS: dict[str, LabTest] = {test.name: test for test in (
    ucs.TEST,
    bending.TEST,
    brazilian.TEST,
    biaxial.TEST,
    direct_tension.TEST,
    scb.TEST,
)}
# The test every parameter set runs first: its runs count the campaign's budget, its readings
# come whole with the responses, its specimen describes the material.
PRIMARY_TEST = "ucs"


def register(test: LabTest) -> None:
    """Add a kind of lab test (a plug-in, or a test's own toy test) to the registry."""
    LAB_TESTS[test.name] = test


def lab_test(name: str) -> LabTest:
    """The lab test of that name; InputError for a name no test has."""
    try:
        return LAB_TESTS[name]
    except KeyError:
        raise InputError("test", f"no lab test named {name!r}; known: {', '.join(LAB_TESTS)}") from None
