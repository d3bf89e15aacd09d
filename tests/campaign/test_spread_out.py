"""`spread_out` picks the samples that run every test: the same picks as the plain farthest-point
rule it was written as, in time linear in the picks (planning takes seconds at any accepted
number of samples)."""

import time

import numpy as np

from rockcal.campaign.input.config import MAX_DEM_RUNS
from rockcal.campaign.procedure.steps import spread_out


def _farthest_first(x, box, k):
    """The rule as first written: each pick the farthest from all picks before it (k^2 x n)."""
    unit = (x - box[:, 0]) / (box[:, 1] - box[:, 0])
    taken = [int(np.argmin(np.linalg.norm(unit - 0.5, axis=1)))]
    while len(taken) < min(k, len(x)):
        gap = np.min(np.linalg.norm(unit[:, None, :] - unit[taken][None, :, :], axis=2), axis=1)
        taken.append(int(np.argmax(gap)))
    return sorted(taken)


def test_spread_out_picks_as_the_farthest_first_rule():
    rng = np.random.default_rng(0)
    for trial in range(60):
        d, n = int(rng.integers(1, 7)), int(rng.integers(2, 80))
        k = int(rng.integers(1, n + 2))
        box = np.sort(rng.uniform(-5, 50, (d, 2)), axis=1)
        x = rng.uniform(box[:, 0], box[:, 1], (n, d))
        if trial % 3 == 0:
            x = np.round(x, 1)  # ties: the first of equals, as before
        assert spread_out(x, box, k) == _farthest_first(x, box, k)


def test_spread_out_of_the_most_samples_takes_seconds():
    box = np.array([[0.0, 1.0]] * 4)
    x = np.random.default_rng(1).uniform(0, 1, (MAX_DEM_RUNS // 2, 4))
    start = time.perf_counter()
    assert len(spread_out(x, box, len(x))) == len(x)
    assert time.perf_counter() - start < 4
