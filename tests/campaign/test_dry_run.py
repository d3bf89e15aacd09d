"""The first screen plans from the procedure's own steps: on a campaign that settles in its
first verification round, the runs `rockcal calibrate --dry-run` plans for each stage and test
are the runs the campaign then executes, with one candidate per round and with two, where the
surrogate's second optimum adds its runs to the verification, and the identifiability stage's
ends run as planned, their bisections where needed (a synthetic forward model: no DEM); the dry
run writes nothing."""

import json

import pytest

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.plan.screen import identifiability_cost, stages
from rockcal.campaign.procedure.steps import calibrate
from rockcal.campaign.runs.spec import RunResult
from rockcal.cli import app

# E only: sigma_c is free along a valley of optima, so a second search finds a distinct one
CAMPAIGN = """
[targets.ucs]
E_GPa = 44.0
packings = 2
spread = {{ E_GPa = 1.0 }}
[targets.bending]
K_IC_MPa_sqrt_m = 1.0
[specimen]
bending_seeds = 2
[search]
bounds = {{ E_c = [15, 30], sigma_c = [30, 50] }}
[surrogate]
samples = 8
checks = 2
[optimizer]
iterations = 40
[acceptance]
candidates = {candidates}
[uncertainty]
packings = 2
draws = 10
"""


class Recorder:
    """Runs each distinct run once, as the store does, and counts the runs of each stage and
    test; `stage` is set by the campaign's progress, which the run reports to first."""

    def __init__(self):
        self.stage, self.done, self.executed = None, set(), {}

    def run(self, specs, progress):
        progress(0, len(specs))
        for spec in specs:
            if spec.key not in self.done:
                self.done.add(spec.key)
                counted = (self.stage, spec.kind)
                self.executed[counted] = self.executed.get(counted, 0) + 1
        return [self.result(spec) for spec in specs]

    @staticmethod
    def result(spec):
        p, seed = dict(spec.params), dict(spec.specimen)["seed"]
        if spec.kind == "bending":
            return RunResult("ok", {"K_IC_MPa_sqrt_m": 1.0 + 0.01 * seed, "P_max_kN_per_m": 1.0,
                                    "displacement_at_peak_mm": 0.1}, None, 0.0)
        return RunResult("ok", {"E_GPa": 2.0 * p["E_c"] * (1 + 0.01 * seed), "nu": 0.2,
                                "ucs_MPa": 3.0 * p["sigma_c"], "n_particles": 100}, None, 0.0)


@pytest.mark.parametrize("candidates", [1, 2])
def test_the_plan_is_what_runs(tmp_path, candidates):
    campaign = planned(parse_campaign(CAMPAIGN.format(candidates=candidates), tmp_path))
    recorder = Recorder()
    record = calibrate(campaign, recorder, lambda stage, done, total: setattr(recorder, "stage", stage))
    assert record.accepted and len({it.loop for it in record.iterations}) == 1  # settled in the first round
    assert len(record.iterations) == candidates
    # the plan counts the search's optimum; a second optimum's runs come on top of it
    # E alone leaves sigma_c free: the identifiability stage runs at the two ends of its range,
    # planned three times each; both meet the sheet within EDGE_GAP of the box's bounds, so
    # neither is bisected (each end on both packings)
    plan = [(stage, test, n * candidates if stage == "verification" else n) for stage, test, n in stages(campaign)]
    assert plan[-1] == ("identifiability", "ucs", 2 * 2 * 3)
    assert plan[:-1] + [("identifiability", "ucs", 2 * 2)] == [(stage, test, n) for (stage, test), n
                                                                in recorder.executed.items()]
    assert not record.identifiability.ranges["sigma_c"].pinned and len(record.identifiability.end_runs) == 2


def test_the_dry_run_prints_the_plan_and_writes_nothing(tmp_path, capsys, monkeypatch):
    campaign_file = tmp_path / "rock.toml"
    campaign_file.write_text(CAMPAIGN.format(candidates=2))
    out = tmp_path / "out"
    monkeypatch.setattr("sys.argv", ["rockcal", "calibrate", str(campaign_file), "--out", str(out), "--dry-run",
                                     "--json", "--workers", "2"])
    with pytest.raises(SystemExit) as done:
        app.main()
    assert done.value.code == 0 and not out.exists()
    plan = json.loads(capsys.readouterr().out)
    expected = stages(planned(parse_campaign(campaign_file.read_text(), tmp_path)))
    assert [(stage, test, entry["runs"]) for stage, tests in plan["stages"].items()
            for test, entry in tests["tests"].items()] == expected
    assert plan["runs"] == sum(n for _, _, n in expected)
    assert plan["stages"]["packings and validation"]["tests"]["bending"]["packings"] == 2
    assert plan["expected_s"] > 0
    (runs, most), times = identifiability_cost(planned(parse_campaign(campaign_file.read_text(), tmp_path)))
    assert plan["identifiability"] == {"runs": [runs, most], "ucs_runs_time": [round(t, 1) for t in times]}
    assert runs == plan["stages"]["identifiability"]["runs"] and most > runs
