"""Latin hypercube: one point per stratum of every parameter, in physical units, seeded."""

import numpy as np
import pytest

from rockcal.errors import InputError
from rockcal.inverse import latin_hypercube

BOUNDS = [(20, 30), (1, 3), (30, 50)]


@pytest.mark.parametrize("optimization", ["random-cd", "maximin", "none"])
def test_one_point_per_stratum(optimization):
    n = 30
    x = latin_hypercube(BOUNDS, n, seed=4, optimization=optimization)
    assert x.shape == (n, 3)
    for j, (lo, hi) in enumerate(BOUNDS):
        strata = np.floor((x[:, j] - lo) / (hi - lo) * n).astype(int)
        assert sorted(strata) == list(range(n))


def test_seeded_and_maximin_spreads_points():
    from scipy.spatial.distance import pdist
    a = latin_hypercube(BOUNDS, 20, seed=1, optimization="maximin")
    assert np.array_equal(a, latin_hypercube(BOUNDS, 20, seed=1, optimization="maximin"))
    unit = lambda x: (x - [20, 1, 30]) / [10, 2, 20]
    plain = [pdist(unit(latin_hypercube(BOUNDS, 20, seed=s, optimization="none"))).min() for s in range(10)]
    assert pdist(unit(a)).min() > np.median(plain)


@pytest.mark.parametrize("bounds", [[(3, 1)], [(1, 1)], [(0, np.inf)], [(1,)]])
def test_bad_bounds(bounds):
    with pytest.raises(InputError, match="bounds"):
        latin_hypercube(bounds, 10)
