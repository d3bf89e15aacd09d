"""The campaign file's numbers as TOML gives them, checked before its schema: every one finite
(TOML allows inf and nan) and every integer within TOML's 64 bits, each refused under its key as
the file writes it (`targets.ucs.E_GPa`, `search.bounds.E_c[1]`)."""

from __future__ import annotations

import math

from rockcal.errors import InputError, key_text

INT_LIMIT = 2**63  # TOML integers are 64-bit signed


def check_numbers(data, key: str = "") -> None:
    """InputError naming the first key of `data` (a parsed TOML document) whose number is inf,
    nan or an integer beyond 64 bits."""
    if isinstance(data, dict):
        for name, value in data.items():
            part = key_text(str(name))
            check_numbers(value, f"{key}.{part}" if key else part)
    elif isinstance(data, list):
        for i, value in enumerate(data):
            check_numbers(value, f"{key}[{i}]")
    elif isinstance(data, float) and not math.isfinite(data):
        raise InputError(key, f"must be a finite number, got {data}")
    elif isinstance(data, int) and not isinstance(data, bool) and not -INT_LIMIT <= data < INT_LIMIT:
        raise InputError(key, f"{data} is beyond TOML's 64-bit integers")
