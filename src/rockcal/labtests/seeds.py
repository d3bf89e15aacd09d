"""Responses over packing seeds. One virtual specimen is one random packing; where a few bonds
decide the result (the notch tip of a bending test, the loaded diameter of a Brazilian disk),
the rock's value is the mean over packings seed, seed + 1, ..."""

from __future__ import annotations

import numpy as np


def seed_list(seed: int, count: int) -> list[int]:
    """The packing seeds of a seed-averaged test."""
    return list(range(seed, seed + count))


def mean_over_seeds(responses: list[dict]) -> dict:
    """Each numeric response averaged over the packings, with its sample standard deviation
    (0 for one packing) as `<name>_std`."""
    numeric = [k for k, v in responses[0].items()
               if isinstance(v, (int, float)) and not isinstance(v, bool)]
    averaged = {}
    for name in numeric:
        values = np.array([r[name] for r in responses], float)
        averaged[name] = float(values.mean())
        averaged[f"{name}_std"] = float(values.std(ddof=1)) if len(values) > 1 else 0.0
    return averaged
