"""A value as FISH reads it (`fish_value`), for every FISH file rockcal writes."""

from __future__ import annotations


def fish_value(value) -> str:
    """A value as FISH reads it: a string quoted, a boolean and an integer as one, a float to
    15 significant digits (a double's own precision: no 8190300.000000001 from a product) and
    always with a point or an exponent, so FISH reads a float."""
    if isinstance(value, str):
        return f"'{value}'"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    text = f"{float(value):.15g}"
    return text if any(c in text for c in ".en") else text + ".0"
