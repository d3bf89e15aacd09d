"""The forward runs of parameter sets: a parameter set on a specimen (`Point`) runs every lab
test calibrated against (a test with a series once per value of it), and their results fold
into one dict of responses per point. Shared by the procedure's steps and the validation's."""

from __future__ import annotations

from dataclasses import replace
from itertools import islice
from typing import TYPE_CHECKING

from rockcal.campaign.input.config import Campaign, SpecimenSettings, split_genesis
from rockcal.campaign.procedure.result import FailedRun
from rockcal.campaign.runs.store import DAMAGED
from rockcal.campaign.runs.spec import SPECIMEN_KEYS, RunResult, RunSpec, run_spec
from rockcal.errors import InputError
from rockcal.inverse import ant_colony
from rockcal.labtests.registry import PRIMARY_TEST, lab_test
from rockcal.labtests.seeds import mean_over_seeds, seed_list

if TYPE_CHECKING:
    from rockcal.campaign.procedure.state import CampaignState

Point = tuple[SpecimenSettings, dict]  # a parameter set on a specimen


class CalibrationFailed(Exception):
    """The campaign cannot go on (e.g. every forward run of a stage failed)."""


def spec_of(state: CampaignState, test: str, settings: SpecimenSettings, row: dict, own: dict | None = None) -> RunSpec:
    """The run of `test` with the parameters `row` (and the fixed ones) of the campaign's
    material, on the specimen `settings` with the genesis settings `row` searches, with `own`
    of the test's own settings (a value of its series)."""
    params, genesis = split_genesis(state.fixed | row)
    return run_spec(test, settings.model_copy(update=genesis), params, state.campaign.material.model, own)


def series_values(campaign: Campaign, test: str) -> list:
    """The values of a test's series as its [targets.<test>] gives them ([] for a test run once)."""
    return campaign.targets.given()[test].series()


def runs_of(campaign: Campaign, test: str) -> list[dict]:
    """A test's runs at one parameter set, as its own settings: one per value of its series,
    or one run."""
    setting = lab_test(test).series
    return [{setting.name: v} for v in series_values(campaign, test)] or [{}]


def specs_of_test(state: CampaignState, test: str, settings: SpecimenSettings, row: dict) -> list[RunSpec]:
    """The runs of `test` at one parameter set (`runs_of`)."""
    return [spec_of(state, test, settings, row, own) for own in runs_of(state.campaign, test)]


def packings_of(campaign: Campaign, test: str) -> int:
    """Over how many packings a test's responses are averaged at each parameter set (its
    [targets.<test>] packings)."""
    section = campaign.targets.given().get(test)
    return 1 if section is None else section.packings


def packings_at(campaign: Campaign, test: str, means: bool) -> int:
    """Over how many packings a test runs at a parameter set: its `packings_of` where the runs
    judge the parameters against the targets (`means`: the verification, the intervals), one
    where they train the surrogate (sensitivity, coarse and full-resolution samples, checks).
    The surrogate thus learns the first packing's responses cheaply, and the means at the
    verified points correct it to the packings' mean (`procedure`)."""
    return packings_of(campaign, test) if means else 1


def point_specs(state: CampaignState, points: list[Point], means: bool = False) -> list[RunSpec]:
    """The runs of every test calibrated against at each point, test by test, on each of the
    test's packings (`packings_at`)."""
    return [spec for test in state.goals.tests for settings, row in points
            for seed in seed_list(settings.seed, packings_at(state.campaign, test, means))
            for spec in specs_of_test(state, test, settings.model_copy(update={"seed": seed}), row)]


def grouped(state: CampaignState, points: list[Point], results: list[RunResult],
            means: bool = False) -> list[dict[str, list[RunResult]]]:
    """Each point's results by test, from results in `point_specs`'s order."""
    by_point: list[dict[str, list[RunResult]]] = [{} for _ in points]
    rest = iter(results)
    for test in state.goals.tests:
        k = len(runs_of(state.campaign, test)) * packings_at(state.campaign, test, means)
        for runs in by_point:
            runs[test] = list(islice(rest, k))
    return by_point


def first_packing(state: CampaignState, runs: dict[str, list[RunResult]]) -> dict[str, list[RunResult]]:
    """A point's runs by test on its first packing only."""
    return {test: results[:len(runs_of(state.campaign, test))] for test, results in runs.items()}


def point_responses(state: CampaignState, runs: dict[str, list[RunResult]]) -> tuple[dict | None, list[tuple[str, str]]]:
    """One point's responses from its runs by test (`merge_responses`), or None with why:
    (test, message) of each failed run, or of a series its test cannot combine (peaks that
    give no envelope)."""
    failures = [(t, r.message) for t, results in runs.items() for r in results if r.status != "ok"]
    if failures:
        return None, failures
    given = state.campaign.targets.given()
    for test, results in runs.items():
        wanted = [name for name in (given[test].measured() if test in given else {}) if name in lab_test(test).targets]
        missing = [name for r in results for name in wanted if name not in r.responses]
        if missing:  # only a stored run can lack one: from a damaged store or one of an older rockcal
            raise InputError("--out", f"a stored {lab_test(test).title} run lacks its response {missing[0]}, a target "
                                      f"of this campaign; {DAMAGED}")
    by_test = {}
    for test, results in runs.items():
        try:
            by_test[test] = responses_of_test(state.campaign, test, [r.responses for r in results])
        except Exception as exc:  # a series its test cannot combine: the point failed
            return None, [(test, f"{type(exc).__name__}: {exc}")]
    return merge_responses(by_test), []


def responses_of_test(campaign: Campaign, test: str, runs: list[dict]) -> dict:
    """A test's responses at one parameter set from its runs on each packing: on one packing,
    the primary test's whole (its other readings too), another's targets
    (`LabTest.point_responses`: a series folded); on several, their mean and sd over the
    packings (`mean_over_seeds`) over the first packing's."""
    n = len(runs_of(campaign, test))
    per_packing = [_on_one_packing(campaign, test, runs[i:i + n]) for i in range(0, len(runs), n)]
    if len(per_packing) == 1:
        return per_packing[0]
    return per_packing[0] | mean_over_seeds(per_packing)


def _on_one_packing(campaign: Campaign, test: str, runs: list[dict]) -> dict:
    if test == PRIMARY_TEST:
        return dict(runs[0])
    return lab_test(test).point_responses(runs, series_values(campaign, test))


def folded(state: CampaignState, stage: str, points: list[Point], results: list[RunResult],
           means: bool = False) -> tuple[CampaignState, list]:
    """The responses of each point from its runs (`point_specs`, with `means`; None when one
    failed), with the runs counted against the budget and the failures recorded;
    CalibrationFailed if every point failed."""
    per_point = grouped(state, points, results, means)
    primary = specs_keys(state, points)
    responses, failed = [], []
    for runs in per_point:
        found, failures = point_responses(state, runs)
        failed += [FailedRun(stage=stage if t == PRIMARY_TEST else f"{stage} ({t})", message=m)
                   for t, m in failures]
        responses.append(found)
    state = replace(state, dem_runs=state.dem_runs + tuple(k for k in dict.fromkeys(primary)
                                                            if k not in state.dem_runs),
                    failed_runs=state.failed_runs + tuple(failed),
                    specimen_description=_description(state, points, per_point)
                    if state.specimen_description is None else state.specimen_description)
    if failed and all(r is None for r in responses):
        raise CalibrationFailed(f"every forward run of stage '{stage}' failed; first: {failed[0].message}")
    return state, responses


def specs_keys(state: CampaignState, points: list[Point]) -> list[str]:
    """The keys of the primary test's runs at the points."""
    return [spec_of(state, PRIMARY_TEST, settings, row).key for settings, row in points]


def _description(state: CampaignState, points: list[Point], per_point: list[dict]) -> dict | None:
    """The specimen of the first primary-test run that succeeded on the campaign's specimen."""
    done = next((runs[PRIMARY_TEST][0].responses for runs, (settings, _) in zip(per_point, points)
                 if runs[PRIMARY_TEST][0].status == "ok" and settings == state.campaign.specimen), None)
    return None if done is None else {k: done[k] for k in SPECIMEN_KEYS if k in done}


def merge_responses(by_test: dict[str, dict]) -> dict:
    """One parameter set's responses: the primary test's (`responses_of_test`), then each other
    test's."""
    merged = dict(by_test[PRIMARY_TEST])
    for test, responses in by_test.items():
        if test != PRIMARY_TEST:
            merged |= responses
    return merged


def optimise(campaign: Campaign, objective, box, seed: int | None = None):
    """The campaign's ant colony search of `objective` in `box`."""
    o = campaign.optimizer
    seed = o.seed if seed is None else seed
    if o.method == "acor":
        return ant_colony(objective, box, method="acor", ants=o.ants, iterations=o.iterations,
                          seed=seed, vectorized=True)
    return ant_colony(objective, box, method="ant-system", ants=o.ants, iterations=o.iterations,
                      alpha=o.alpha, beta=o.beta, rho=o.rho, seed=seed, vectorized=True)
