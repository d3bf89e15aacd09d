"""Targets read as the mean over packings, on a synthetic forward model (no DEM) whose UCS
differs from packing to packing: with `packings = 3` the surrogate's runs take the specimen's
seed, each verification that seed and the next two, and the campaign recovers the parameters
that made the packings' mean; on one packing it recovers that packing's bias."""

import pytest

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.plan.screen import describe, specimens, stages
from rockcal.campaign.procedure.steps import calibrate
from rockcal.campaign.runs.store import RunStore
from rockcal.campaign.runs.spec import RunResult
from tiny import StandInExecutor

TRUE = {"E_c": 22.0, "kn_ks": 1.8, "sigma_c": 40.0}
PACKING_BIAS = {1: 1.06, 2: 0.94, 3: 1.0}  # the UCS of packings 1-3 over their mean; others 1


def ucs(p: dict, seed: int) -> dict:
    return {"E_GPa": 2.0 * p["E_c"], "nu": 0.1 * p["kn_ks"],
            "ucs_MPa": 3.0 * p["sigma_c"] * PACKING_BIAS.get(seed, 1.0)}


class Executor(StandInExecutor):
    """The stand-in for every run; it keeps the packing seed of each run asked for."""

    def __init__(self):
        self.seeds = []

    def result(self, spec):
        seed = dict(spec.specimen)["seed"]
        self.seeds.append(seed)
        return RunResult("ok", ucs(dict(spec.params), seed) | {"n_particles": 100}, None, 0.0)


def campaign_text(packings: int, coarse_samples: int = 0) -> str:
    targets = ucs(TRUE, seed=0)
    return f"""
[targets.ucs]
E_GPa = {targets["E_GPa"]!r}
nu = {targets["nu"]!r}
ucs_MPa = {targets["ucs_MPa"]!r}
packings = {packings}
[search]
bounds = {{ E_c = [15, 30], kn_ks = [1, 3], sigma_c = [30, 50] }}
fixed = {{ tau_c = 80 }}
[surrogate]
coarse_samples = {coarse_samples}
samples = 12
checks = 2
[optimizer]
iterations = 80
[acceptance]
tolerance = 0.005
max_dem_runs = 40
[uncertainty]
enabled = true
draws = 10
packings = 2
"""


def test_a_target_over_three_packings_recovers_the_parameters_of_their_mean(tmp_path):
    executor = Executor()
    record = calibrate(planned(parse_campaign(campaign_text(packings=3), tmp_path)), executor)
    assert record.accepted
    assert record.identified["sigma_c"] == pytest.approx(TRUE["sigma_c"], rel=0.01)
    assert record.verified["ucs_MPa_std"] == pytest.approx(0.06 * 3 * record.identified["sigma_c"], rel=0.01)
    ends = 3 * len(record.identifiability.end_runs)  # the identifiability stage's, last, on the three packings
    seeds = executor.seeds[:len(executor.seeds) - ends]
    samples, verifications = seeds[:14], seeds[14:-6]
    assert samples == [1] * 14  # the surrogate's runs, on packing 1 only
    assert len(verifications) >= 3 and verifications == [1, 2, 3] * (len(verifications) // 3)
    assert sorted(seeds[-6:]) == [1, 2, 3, 4, 5, 6]  # the intervals' two disjoint sets of three
    assert executor.seeds[len(seeds):] == [1, 2, 3] * (ends // 3)


def test_a_target_on_one_packing_recovers_that_packings_bias(tmp_path):
    record = calibrate(planned(parse_campaign(campaign_text(packings=1), tmp_path)), Executor())
    assert record.identified["sigma_c"] == pytest.approx(TRUE["sigma_c"] / 1.06, rel=0.01)


def test_the_first_screen_counts_every_packing(tmp_path):
    """Three packings make a verified point dear: one is verified a round (`plan.route`)."""
    campaign = planned(parse_campaign(campaign_text(packings=3), tmp_path))
    assert stages(campaign) == [("samples and checks", "ucs", 14), ("verification", "ucs", 3),
                                ("packings and validation", "ucs", 3), ("identifiability", "ucs", 18)]
    assert sorted(s.seed for _, s in specimens(campaign)) == [1, 2, 3, 4, 5, 6]
    lines = describe(campaign, RunStore(tmp_path / "out"), workers=None)
    assert lines[1].endswith("each parameter set runs UCS (verified on 3 packings, their mean; "
                             "the surrogate's runs on one)")


def test_coarse_runs_take_one_packing_and_the_verified_means_correct_them(tmp_path):
    executor = Executor()
    campaign = planned(parse_campaign(campaign_text(packings=3, coarse_samples=16), tmp_path))
    record = calibrate(campaign, executor)
    assert record.identified["sigma_c"] == pytest.approx(TRUE["sigma_c"], rel=0.01)
    assert executor.seeds[:30] == [1] * 30  # the coarse samples, the samples and checks
    assert stages(campaign)[0] == ("coarse samples", "ucs", 16)
