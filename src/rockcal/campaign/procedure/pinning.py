"""The identifiability stage, after an accepted point's packings and validation: which searched
parameters the lab sheet pins (`rockcal.inverse.identifiability`, on the surrogate of every
run), the DEM runs at the two ends of the widest range
it does not pin (the calibrated tests there verify the ends, and each lab test the sheet lacks
runs there) and those tests ranked by how much their response varies between the ends per run
of lab work: the test that would pin the parameters."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from rockcal.campaign.plan.cost import relative_time
from rockcal.campaign.procedure.points import CalibrationFailed, folded, point_specs, spec_of
from rockcal.campaign.procedure.result import Identifiability, ParameterRange, SpreadOfTest
from rockcal.campaign.procedure.rounding import rounded
from rockcal.errors import InputError
from rockcal.inverse.identifiability import (MAX_ENDS, bands, ends_of, kept, meeting_set, meets, parameter_ranges,
                                             within_bands)
from rockcal.labtests.registry import LAB_TESTS, PRIMARY_TEST
from rockcal.specimens.grain_limit import check_grains, expected_grains

IDENTIFIABILITY = "identifiability"  # the stage's name
CONFINEMENT_MPA = 10.0  # a confined test the sheet lacks runs at this confinement
# a test not named in [identifiability] tests whose run on the campaign's specimen settings
# costs more UCS runs than this is left out: the stage stays a small part of the campaign
MOST_UCS_RUNS = 4.0
# a test's lab work against a Brazilian disk's (its specimens' making, its rig): the ranking
# divides each test's spread by it; the UCS test's CI and CD are readings of tests already done
LAB_WORK = {PRIMARY_TEST: 0.5, "brazilian": 1.0, "bending": 1.5, "biaxial": 2.0, "direct_tension": 2.0}
READINGS = {"ci_MPa": "read the crack initiation stress (CI) of your UCS tests",
            "cd_MPa": "read the crack damage stress (CD) of your UCS tests"}
ADVICE = {"brazilian": "Brazilian (indirect tensile) strength", "direct_tension": "direct tensile strength",
          "biaxial": f"strength confined at {CONFINEMENT_MPA:g} MPa",
          "bending": "fracture toughness K_IC (notched-beam bending)"}


@dataclass(frozen=True)
class Candidate:
    """A response the ranking may name: a lab test the sheet lacks (its strength, at `own`
    settings) or a reading of the UCS test the sheet has not given."""

    test: str
    response: str
    own: dict
    label: str


def candidates(campaign) -> list[Candidate]:
    """[identifiability] tests, else every test the campaign's dimension and material can run on
    its specimen settings, a run for at most MOST_UCS_RUNS UCS runs, that it does not calibrate
    against (a validation check's included: the user has its value); and the UCS test's CI and
    CD where they are no target."""
    named, calibrated = campaign.identifiability.tests, campaign.target_sections()
    targets = {r for section in calibrated.values() for r in section.measured()}
    found = [Candidate(PRIMARY_TEST, r, {}, label) for r, label in READINGS.items()
             if r not in targets and (named is None or PRIMARY_TEST in named)]
    for test, kind in LAB_TESTS.items():
        if test == PRIMARY_TEST or test in calibrated or (named is not None and test not in named):
            continue
        own = {kind.series.name: CONFINEMENT_MPA} if kind.series else {}
        if not _runs_here(kind, campaign, own) or (named is None and relative_time(campaign, test) > MOST_UCS_RUNS):
            continue
        what = ADVICE.get(test, f"{kind.title} {kind.strength_response.name}")
        label = (f"calibrate against the {what} you have ([validation] tests names it a check only)"
                 if test in campaign.validation_tests() else f"measure the {what}")
        found.append(Candidate(test, kind.strength_response.name, own, label))
    return found


def _runs_here(kind, campaign, own: dict) -> bool:
    """Whether the test runs in the campaign's dimension and material, on a specimen its
    specimen settings make (in 2D, within the grain limit; a 3D test's check counts them)."""
    s = campaign.specimen
    try:
        kind.check_dimensions(s.dimensions, campaign.material.model)
        kind.check(kind.settings_of(s) | own)
        if s.dimensions == 2:
            p = kind.packing(s)
            check_grains(kind.name, kind.title, expected_grains(p["width_mm"], p["height_mm"], p["rmin_mm"],
                                                                p["radius_ratio"], p["genesis"].cloud_porosity))
    except InputError:
        return False
    return True


def most_runs(campaign) -> list[str]:
    """The test of each DEM run the stage asks for at most: the calibrated tests (a series once
    per value) and each candidate test at MAX_ENDS ends (none with [identifiability] runs off)."""
    if not campaign.identifiability.runs:
        return []
    per_set = [test for test, s in campaign.target_sections().items() for _ in range(max(1, len(s.series())))]
    tests = list(dict.fromkeys(c.test for c in candidates(campaign) if c.test != PRIMARY_TEST))
    return MAX_ENDS * (per_set + tests)


def pinning_runs(state, surrogate) -> tuple[list, Callable]:
    """The stage's runs at an accepted point (`surrogate`: the judged one, of every run) and
    the fold that records what they say (`Identifiability`) in the state's `final`."""
    campaign, names, box = state.campaign, state.names, state.box
    settings, targets = campaign.identifiability, state.goals.targets
    identified = state.identified()
    check = state.surrogate_check
    error = check.max_relative_error if check else None
    band = bands(targets, campaign.acceptance.tolerance, state.goals.spread, error)
    start = np.array([identified[n] for n in names])
    points = meeting_set(meets(surrogate.predict, band), box, start, seed=campaign.surrogate.seed)
    points = points if len(points) else start[None]  # the surrogate misses the sheet: the verified point
    ranges = parameter_ranges(points, box, names, settings.pinned_share)
    ends = [dict(zip(names, rounded(row, state.whole)))
            for row in ends_of(points, names, ranges, MAX_ENDS)] if settings.runs else []
    end_points = [(campaign.specimen, row) for row in ends]
    tests = candidates(campaign) if ends else []
    verify = point_specs(state, end_points)
    asked = [(c, [spec_of(state, c.test, campaign.specimen, row, c.own) for row in ends]) for c in tests]
    specs = list({spec.key: spec for spec in [*verify, *(s for _, runs in asked for s in runs)]}.values())

    def fold(results, progress):
        done = dict(zip((spec.key for spec in specs), results))
        try:
            new, found = folded(state, IDENTIFIABILITY, end_points, [done[spec.key] for spec in verify])
        except CalibrationFailed:  # every end failed: no end verified, the ranking stands
            new, found = state, [None] * len(end_points)
        ranked = sorted((_spread(c, [done[spec.key] for spec in runs]) for c, runs in asked),
                        key=lambda t: -t.score)
        errors = [None if v is None else {r: v[r] / t - 1 for r, t in targets.items()} for v in found]
        found_ranges = {n: ParameterRange(**r) for n, r in ranges.items()} | \
            _read_in_dem(state, ranges, ends, found, bands(targets, campaign.acceptance.tolerance, state.goals.spread,
                                                         None), settings.pinned_share)
        record = Identifiability(
            bands=band, pinned_share=settings.pinned_share, ranges=found_ranges, set_points=kept(points).tolist(),
            points=ends, end_errors=errors, tests=ranked, runs=len(specs),
            text=text_of(found_ranges, ranked, errors, campaign.acceptance.tolerance, settings.runs))
        return replace(new, final=new.final | {"identifiability": record})

    return specs, fold


def _read_in_dem(state, ranges: dict, ends: list[dict], found: list, band: dict, pinned_share: float) -> dict:
    """The range whose ends ran, read in the DEM: from the identified point towards each end
    as far as the DEM responses stay in their bands without the surrogate's error (none where
    an end's runs failed)."""
    if len(ends) != 2 or None in found:
        return {}
    best = state.iterations[state.best()]
    name = max((n for n in ranges if not ranges[n]["pinned"]), key=lambda n: ranges[n]["share"])
    low_box, high_box = state.bounds[name]
    x0 = best.x[state.names.index(name)]
    low, high = sorted(x0 + within_bands(best.verified, v, band) * (end[name] - x0) for end, v in zip(ends, found))
    share = (high - low) / (high_box - low_box)
    return {name: ParameterRange(low=low, high=high, share=share, pinned=share <= pinned_share, dem=True)}


def _spread(candidate: Candidate, results: list) -> SpreadOfTest:
    """A candidate's response at each point (None where its run failed) and their spread."""
    values = [_number(r.responses.get(candidate.response)) if r.status == "ok" else None for r in results]
    ok = [v for v in values if v is not None]
    spread = float((max(ok) - min(ok)) / abs(np.mean(ok))) if len(ok) > 1 and np.mean(ok) != 0 else 0.0
    return SpreadOfTest(test=candidate.test, response=candidate.response, label=candidate.label, values=values,
                        spread=spread, score=spread / LAB_WORK.get(candidate.test, 1.0))


def _number(value) -> float | None:
    """A response's value, None where the run gave none (a CI no crack marked)."""
    return float(value) if isinstance(value, (int, float)) and np.isfinite(value) else None


def text_of(ranges: dict[str, ParameterRange], ranked: list[SpreadOfTest], end_errors: list, tolerance: float,
            runs: bool) -> str:
    """What the stage found, in a sentence or two."""
    loose = {n: r for n, r in ranges.items() if not r.pinned}
    if not loose:
        widest = max(r.share for r in ranges.values())
        return (f"the sheet pins every searched parameter: among the points that meet your sheet, each ranges "
                f"over at most {100 * widest:.0f} % of its search box.")
    listed = ", ".join(f"{n} {r.low:.4g}–{r.high:.4g} ({100 * r.share:.0f} % of its box"
                       + (", its ends read in the DEM)" if r.dem else ")") for n, r in loose.items())
    text = f"the sheet does not pin {' and '.join(loose)}: the points that meet your sheet range over {listed}"
    confirmed = [e for e in end_errors if e is not None and all(abs(v) <= tolerance for v in e.values())]
    if end_errors:
        text += f"; the DEM confirms {len(confirmed)} of the {len(end_errors)} ends within ±{100 * tolerance:g} %"
    useful = [t for t in ranked if t.spread > 2 * tolerance]
    if useful:
        best = useful[0]
        return (text + f". {best.label[0].upper()}{best.label[1:]}: it varies {100 * best.spread:.0f} % across the "
                f"points that meet your sheet; add it to [targets] and resume (--resume keeps the runs done).")
    if not runs:
        return text + ". [identifiability] runs = false: no lab test was run to name one that would pin it."
    return (text + f". No lab test rockcal runs varies more than ±{100 * tolerance:g} % across them: narrow the "
            "search box with what you know of the parameter.")
