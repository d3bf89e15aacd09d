"""The record comparison of tests run on another processor: round-off allowed only where BLAS
or scipy computes, nothing else."""

import copy
import math

from same_record import ROUNDOFF, differences

PREDICTED = 100.01239127583673
RECORD = {"identified": {"E_c": 21.94}, "verified": {"ucs_MPa": 98.84123538323941},
          "iterations": [{"x": [21.94], "predicted": {"ucs_MPa": PREDICTED}, "nfev": 400}],
          "accepted": True}


def _with(*path, value):
    record = copy.deepcopy(RECORD)
    *head, last = path
    target = record
    for key in head:
        target = target[key]
    target[last] = value
    return record


def test_a_prediction_may_differ_by_round_off_only():
    assert not differences(_with("iterations", 0, "predicted", "ucs_MPa", value=PREDICTED * (1 + 1e-14)), RECORD)
    assert differences(_with("iterations", 0, "predicted", "ucs_MPa", value=PREDICTED * (1 + 10 * ROUNDOFF)), RECORD)


def test_the_engines_numbers_parameters_and_counts_must_be_the_same_to_the_bit():
    assert not differences(copy.deepcopy(RECORD), RECORD)
    assert differences(_with("verified", "ucs_MPa", value=math.nextafter(98.84123538323941, 200)), RECORD)
    assert differences(_with("identified", "E_c", value=math.nextafter(21.94, 0)), RECORD)
    assert differences(_with("iterations", 0, "x", 0, value=math.nextafter(21.94, 0)), RECORD)
    assert differences(_with("iterations", 0, "nfev", value=401), RECORD)
    assert differences(_with("accepted", value=1), RECORD)  # a number is not a verdict
    assert differences(_with("accepted", value=False), RECORD)


def test_the_objective_near_its_zero_may_differ_by_the_round_off_of_its_root():
    record = _with("iterations", 0, "objective_surrogate", value=2.1265966404937364e-13)
    assert not differences(_with("iterations", 0, "objective_surrogate", value=2.1265966455223155e-13), record)
    assert differences(_with("iterations", 0, "objective_surrogate", value=2.2e-13), record)
