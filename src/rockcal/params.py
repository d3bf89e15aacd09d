"""Micro-parameters as users give them: the default material's (`MicroParams`, `make_params`,
`NAMES`: the parallel bond's, defined in `rockcal.materials.parallel_bond`), the units they are
quoted in, and `NAME=VALUE` assignments from the command line."""

from __future__ import annotations

from rockcal.errors import InputError
from rockcal.materials.parallel_bond import NAMES, MicroParams, make_params
from rockcal.materials.units import GPa, MPa

__all__ = ["GPa", "MPa", "MicroParams", "NAMES", "make_params", "parse_assignments"]


def parse_assignments(items: list[str]) -> dict[str, float]:
    """Parse CLI `NAME=VALUE` strings into numbers."""
    values: dict[str, float] = {}
    for item in items:
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise InputError("--set", f"expected NAME=VALUE, got {item!r}")
        try:
            values[name] = float(text)
        except ValueError:
            raise InputError(name, f"not a number: {text.strip()!r}") from None
    return values
