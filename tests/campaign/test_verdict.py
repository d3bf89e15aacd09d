"""The verdict of a campaign whose targets cannot all be met: on a surrogate with known
responses, the targets out of reach, the pairs that conflict and how close they come, and
the Pareto front of the runs seen."""

from types import SimpleNamespace

import numpy as np
import pytest

from rockcal.campaign.outputs.figures import _trade_off
from rockcal.campaign.procedure.verdict import trade_off, verdict_of

BOX = np.array([[0.0, 1.0], [0.0, 1.0]])


def _predict(x):
    """a and b both grow with x0 (a = 1 + x0, b = 1 + x0), c with x1 (c = 1 + x1)."""
    x = np.atleast_2d(x)
    return {"a": 1 + x[:, 0], "b": 1 + x[:, 0], "c": 1 + x[:, 1], "d": 1 + x[:, 1]}


def test_two_targets_on_one_parameter_conflict_and_one_out_of_the_box_is_out_of_reach():
    # a = 1 wants x0 = 0, b = 2 wants x0 = 1: at best both within 1/3 (x0 = 1/3); d = 10 needs x1 = 9
    targets = {"a": 1.0, "b": 2.0, "c": 1.5, "d": 10.0}
    verdict = verdict_of(targets, 0.05, BOX, _predict, seen=[], best_errors={"a": 0.3, "b": -0.3, "c": 0, "d": -0.8})
    assert verdict.unreachable == {"d": pytest.approx(0.8, abs=1e-3)}
    assert [c.targets for c in verdict.conflicts] == [["a", "b"]]
    assert verdict.conflicts[0].least_error == pytest.approx(1 / 3, abs=2e-3)
    assert verdict.trade_off.responses == ["a", "b"]
    assert "a and b conflict" in verdict.text and "d is out of reach" in verdict.text


def test_targets_a_point_meets_together_leave_no_conflict():
    targets = {"a": 1.5, "c": 1.2}
    verdict = verdict_of(targets, 0.05, BOX, _predict, seen=[], best_errors={"a": 0.1, "c": 0.07})
    assert verdict.conflicts == [] and verdict.unreachable == {}
    assert verdict.least_error_all < 0.01
    assert "budget ran out" in verdict.text
    assert verdict.trade_off.responses == ["a", "c"]  # the two largest errors at the best point


def test_the_pareto_front_holds_the_runs_no_other_beats_in_both():
    targets = {"a": 1.0, "b": 1.0}
    seen = [{"a": 1.1, "b": 1.4}, {"a": 1.2, "b": 1.2}, {"a": 1.3, "b": 1.3}, {"a": 0.6, "b": 1.05},
            {"a": 1.2, "b": 1.2}]
    front = trade_off(["a", "b"], targets, seen)
    assert front.errors[3] == pytest.approx([-0.4, 0.05])
    # run 2 is beaten by run 1 in both; run 4 ties run 1 and stays
    assert front.pareto == [0, 1, 4, 3]
    # a run that measured one of the two (its verification stopped after the UCS test) is left out
    assert trade_off(["a", "b"], targets, [{"a": 0.5}, *seen]) == front


def test_targets_that_conflict_only_together_are_named_by_those_that_bind():
    # a = 1 + x0 wants 1.5, b = 1 + x1 wants 1.5, e = 1 + x0 + x1 wants 2.5: each pair can be met
    # (x = (0.5, 0.5), (0.5, 1), (1, 0.5)), not all three; at the best compromise all three bind
    def predict(x):
        x = np.atleast_2d(x)
        return {"a": 1 + x[:, 0], "b": 1 + x[:, 1], "e": 1 + x[:, 0] + x[:, 1]}

    box = np.array([[0.0, 1.0], [0.0, 1.0]])
    verdict = verdict_of({"a": 1.5, "b": 1.5, "e": 2.5}, 0.05, box, predict, seen=[],
                         best_errors={"a": 0.1, "b": 0.1, "e": -0.12})
    assert verdict.conflicts == [] and verdict.unreachable == {} and verdict.least_error_all > 0.05
    assert set(verdict.binding) == {"a", "b", "e"}
    assert "conflict as a whole" in verdict.text and "held back by" in verdict.text


def test_a_verified_point_closer_than_the_surrogate_sets_how_close_the_targets_come():
    # the surrogate's a and b conflict (at best both within 1/3); a DEM-verified point met them
    # within 0.2 and 0.04: the verdict's least errors are the verified point's
    targets = {"a": 1.0, "b": 2.0}
    closer = {"a": 0.2, "b": -0.15}
    verdict = verdict_of(targets, 0.05, BOX, _predict, seen=[], best_errors=closer,
                         verified=[None, {"a": 0.5}, closer])
    assert verdict.conflicts[0].least_error == pytest.approx(0.2)
    assert verdict.least_error_all == pytest.approx(0.2)
    within = verdict_of(targets, 0.05, BOX, _predict, seen=[], best_errors=closer,
                        verified=[{"a": 0.04, "b": -0.03}])
    assert within.conflicts == [] and within.least_error_all == pytest.approx(0.04)


def test_the_trade_off_figure_draws_a_response_the_verification_did_not_run(tmp_path):
    # a campaign whose verification ran the UCS test alone (ucs_first) has no Brazilian error
    # at the identified point: the figure shows the search's runs without the best compromise
    runs = [[0.3, 0.5], [0.1, 0.9], [0.4, 0.2]]
    result = SimpleNamespace(verdict=SimpleNamespace(trade_off=SimpleNamespace(
        errors=runs, pareto=[1, 2], responses=["ucs_MPa", "sigma_t_MPa"])),
        errors={"ucs_MPa": 0.2}, tolerance=0.1)
    assert _trade_off(result, None, tmp_path / "trade_off.png") is None
    assert (tmp_path / "trade_off.png").stat().st_size > 10_000
