"""A lab test's specimen settings from values by name (the campaign file's [specimen] keys and
the test's own settings), the rest at the test's defaults, checked as a campaign's are."""

from __future__ import annotations

import math

from pydantic import ValidationError

from rockcal.errors import InputError, from_validation_error
from rockcal.labtests.kind import LabTest
from rockcal.labtests.specimen_settings import SpecimenSettings  # the [specimen] keys' model


def specimen_settings(test: LabTest, values: dict) -> dict:
    """The settings of one run of `test`; InputError naming the key of a value that is not
    one of its settings, not finite or not valid."""
    unknown = sorted(set(values) - set(test.settings))
    if unknown:
        raise InputError(unknown[0], f"not a setting of the {test.title} test; its settings: {', '.join(test.settings)}")
    own = {s.name: s for s in test.own_settings}
    given = {k: v for k, v in test.defaults if k in test.settings} | {k: s.default for k, s in own.items()} | values
    for name, value in given.items():
        if isinstance(value, float) and not math.isfinite(value):
            raise InputError(name, f"must be a finite number, got {value}")
    try:
        shared = SpecimenSettings(**{k: v for k, v in given.items() if k not in own})
    except ValidationError as exc:
        raise from_validation_error(exc, SpecimenSettings) from None
    for name, setting in own.items():
        setting.check(given[name])
    settings = test.settings_of(shared) | {name: given[name] for name in own}
    test.check(settings)
    return settings
