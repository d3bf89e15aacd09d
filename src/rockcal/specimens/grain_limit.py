"""How many grains a specimen will hold, known before its genesis, and the limit past which
rockcal will not make one: a fine R_min can ask for hours of genesis and gigabytes at once.

The limit is $ROCKCAL_MAX_GRAINS (set by `rockcal --max-grains N`, and so seen by the pool's
worker processes too), else DEFAULT_MAX_GRAINS.
"""

from __future__ import annotations

import math
import os

from rockcal.errors import InputError

DEFAULT_MAX_GRAINS = 1_000_000
ENV = "ROCKCAL_MAX_GRAINS"
FLAG = "--max-grains"
BYTES_PER_GRAIN = 1_000  # a run's arrays per grain (state, neighbour pairs, bonds): about 1 kB


def expected_grains(width_mm: float, height_mm: float, rmin_mm: float, radius_ratio: float,
                    cloud_porosity: float) -> float:
    """The grain cloud's count: (1 - n_c) x area / mean grain area (radii uniform in
    [R_min, ratio R_min]), as a float so that no size overflows."""
    mean_area = math.pi * rmin_mm**2 * (1 + radius_ratio + radius_ratio**2) / 3
    return (1 - cloud_porosity) * width_mm * height_mm / mean_area


def max_grains() -> int:
    """The largest specimen rockcal makes, in grains."""
    text = os.environ.get(ENV, "").strip()
    if not text:
        return DEFAULT_MAX_GRAINS
    if not text.isdigit() or int(text) < 1:
        raise InputError(ENV, f"must be a whole number of grains >= 1, got {text!r}")
    return int(text)


def check_grains(field: str, what: str, grains: float) -> None:
    """InputError naming `field` when `what` (a specimen in words) would hold more grains than
    the limit: the count, the memory it needs and how to allow it."""
    limit = max_grains()
    if grains <= limit:
        return
    gib = grains * BYTES_PER_GRAIN / 2**30
    allow = f"{FLAG} {math.ceil(grains)}" if grains < 1e12 else f"{FLAG} N"
    raise InputError(field, f"{what} would hold about {_number(grains)} grains and need about "
                            f"{gib:.3g} GiB of memory, past the limit of {limit:,} grains; make "
                            f"the grains larger (R_min) or the specimen smaller, or allow it with "
                            f"rockcal {allow}")


def _number(x: float) -> str:
    return f"{x:,.0f}" if x < 1e9 else f"{x:.2g}"
