"""The set of points that meet a sheet, on a known forward model: a parameter no target sees
spans its box and is not pinned, the others are pinned to the tolerance's band; the ends of
the free one are the set's points at its bounds predicted nearest the targets."""

import numpy as np
import pytest

from rockcal.inverse.identifiability import (END_SLAB, bands, ends_of, meeting_set, meets, parameter_ranges,
                                             worst_errors)

BOX = np.array([[0.0, 1.0], [0.0, 1.0], [10.0, 30.0]])
TARGETS = {"a": 1.5, "b": 1.5}


def predict(x):
    """a sees x0, b sees x1; nothing sees x2."""
    x = np.atleast_2d(x)
    return {"a": 1 + x[:, 0], "b": 1 + x[:, 1]}


def test_a_parameter_no_target_sees_spans_its_box_and_the_others_are_pinned():
    inside = meets(predict, bands(TARGETS, 0.02, {}, None))  # a within 1.5 ± 0.03: x0 within 0.5 ± 0.03
    points = meeting_set(inside, BOX, np.array([0.5, 0.5, 20.0]))
    assert len(points) > 100 and inside(points).all()
    # 0.5 found lies within 0.03 / 0.47 = 6.4 % of every point of x0's and x1's ranges: pinned within 10 %
    ranges = parameter_ranges(points, BOX, ["x0", "x1", "x2"], np.array([0.5, 0.5, 20.0]), 0.1, 1.0)
    for name in ("x0", "x1"):
        assert 0.47 - 1e-9 <= ranges[name]["low"] < 0.48 and 0.52 < ranges[name]["high"] <= 0.53 + 1e-9
        assert ranges[name]["share"] == pytest.approx(0.06, abs=0.01) and ranges[name]["pinned"]
    assert ranges["x2"]["share"] > 0.95 and not ranges["x2"]["pinned"]
    worst = worst_errors(predict, TARGETS, points)  # 0 at x0 = x1 = 0.5, the set's middle
    assert worst.max() <= 0.02 + 1e-9
    low, high = ends_of(points, 2, worst)
    slab = END_SLAB * (ranges["x2"]["high"] - ranges["x2"]["low"])
    assert low[2] <= ranges["x2"]["low"] + slab and high[2] >= ranges["x2"]["high"] - slab
    assert np.abs(low[:2] - 0.5).max() < 0.01 and np.abs(high[:2] - 0.5).max() < 0.01
    assert inside(np.array([low, high])).all()


def test_a_sheet_no_point_meets_gives_an_empty_set():
    inside = meets(predict, bands({"a": 5.0, "b": 1.5}, 0.02, {}, None))
    assert len(meeting_set(inside, BOX, np.array([0.5, 0.5, 20.0]))) == 0


def test_a_band_is_the_tolerance_or_the_spread_where_wider_and_the_surrogate_error_widens_it():
    found = bands({"a": 10.0, "b": 10.0, "c": 10.0}, 0.02, {"b": [9.0, 10.1], "c": 0.05}, {"a": 0.01, "b": np.nan})
    assert found == {"a": (pytest.approx(9.7), pytest.approx(10.3)), "b": (9.0, pytest.approx(10.2)),
                     "c": (pytest.approx(9.8), pytest.approx(10.2))}  # c: 2 sd = 0.1 < the tolerance's 0.2


def test_a_thin_ridge_is_walked_from_its_one_known_point():
    """a sees x0 + x1 only: the set is a thin band across the box, which few probes hit; the
    walks follow it from the start to both ends."""
    def along(x):
        x = np.atleast_2d(x)
        return {"a": 1 + 0.5 * (x[:, 0] + x[:, 1]), "b": 1 + 0 * x[:, 0]}

    inside = meets(along, {"a": (1.497, 1.503), "b": (0.99, 1.01)})
    points = meeting_set(inside, BOX[:2], np.array([0.5, 0.5]))
    ranges = parameter_ranges(points, BOX[:2], ["x0", "x1"], np.array([0.5, 0.5]), 0.1, 1.0)
    assert ranges["x0"]["low"] < 0.05 and ranges["x0"]["high"] > 0.95 and not ranges["x0"]["pinned"]
