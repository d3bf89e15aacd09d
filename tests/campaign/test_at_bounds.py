"""A parameter the search leaves on its bound is told in the summary, the record and the
report: on a synthetic forward model (no DEM) whose UCS target needs sigma_c beyond its box."""

import pytest

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.procedure.result import CalibrationResult, on_bounds
from rockcal.campaign.procedure.steps import calibrate
from rockcal.campaign.runs.spec import RunResult
from rockcal.cli.calibrate import summary
from tiny import StandInExecutor, tiny_campaign


class Executor(StandInExecutor):
    """E = E_c, UCS = sigma_c: the tiny campaign's targets (20 GPa, 40 MPa) at E_c 20, sigma_c 40."""

    def result(self, spec):
        p = dict(spec.params)
        return RunResult("ok", {"E_GPa": p["E_c"], "nu": 0.2, "ucs_MPa": p["sigma_c"], "n_particles": 100}, None, 0.0)


def test_a_parameter_on_its_bound_is_told_and_one_inside_is_not():
    bounds = {"E_c": (10.0, 30.0), "sigma_c": (20.0, 60.0)}
    assert on_bounds({"E_c": 20.0, "sigma_c": 59.7}, bounds) == [
        "sigma_c is at its upper bound 60: widen search.bounds.sigma_c and resume (the runs done are kept)"]
    assert on_bounds({"E_c": 10.1, "sigma_c": 40.0}, bounds)[0].startswith("E_c is at its lower bound 10:")
    assert on_bounds({"E_c": 10.3, "sigma_c": 59.3}, bounds) == []  # 1.5 % and 1.75 % of the box inside


@pytest.mark.parametrize("ucs_MPa, warned", [(40.0, False), (75.0, True)])
def test_a_calibration_whose_target_lies_beyond_the_box_warns(tmp_path, ucs_MPa, warned):
    text = tiny_campaign().replace("ucs_MPa = 40.0", f"ucs_MPa = {ucs_MPa}")
    result = calibrate(planned(parse_campaign(text, tmp_path)), Executor())
    assert (result.identified["sigma_c"] > 59.4) == warned
    told = summary(result)["at_bounds"]
    assert told == (["sigma_c is at its upper bound 60: widen search.bounds.sigma_c and resume "
                     "(the runs done are kept)"] if warned else [])
    assert CalibrationResult.from_json(result.to_json()).at_bounds == (told or None)  # the record keeps it
