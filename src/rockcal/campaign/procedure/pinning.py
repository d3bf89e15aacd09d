"""The identifiability stage, after an accepted point's packings and validation: which searched
parameters the lab sheet pins, and which lab test it lacks would pin the others.

On the surrogate of every run, the points whose predicted responses meet every target
(`rockcal.inverse.identifiability`: each within the tolerance, or the lab's spread where wider,
plus the surrogate's error at the verified points) give each parameter's range. That set is an
outer bound only as far as the surrogate is right, so the ranges it does not pin are read in the
DEM, loosest first (the value found farthest from a point of it): the calibrated tests run at a
range's two ends, then each side is bisected, at most BISECTIONS times, between its farthest
point that met the sheet (the bands without the surrogate's error) and its nearest beyond that
missed, while they lie more than EDGE_GAP of the box apart, each run training the surrogate. The
range kept reaches from the points the DEM found meeting the sheet, and the read's runs that
miss it by no more than the surrogate's error (the DEM's scatter), out to the nearest runs of
the read beyond that miss it by more, or to the box's bounds: the set's edges along the read lie
between. It decides that parameter's verdict (a range none of whose ends met the sheet keeps the
surrogate's); where the DEM pins it, the next range not pinned is read. Each lab test the sheet
lacks runs at the two ends kept of the first range the DEM leaves not pinned, ranked by how much
its response varies between them per run of lab work: the test that would pin the parameter."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Callable

import numpy as np

from rockcal.campaign.plan.cost import relative_time
from rockcal.campaign.procedure.points import (CalibrationFailed, first_packing, folded, grouped, point_responses,
                                              point_specs, spec_of)
from rockcal.campaign.procedure.result import EndRun, Identifiability, ParameterRange, SpreadOfTest
from rockcal.campaign.procedure.rounding import rounded, stand_in
from rockcal.campaign.runs.spec import RunSpec
from rockcal.errors import InputError
from rockcal.inverse.identifiability import (bands, ends_of, in_bands, kept, meeting_set, meets,
                                             largest_error, parameter_ranges, pins, worst_errors)
from rockcal.labtests.registry import LAB_TESTS, PRIMARY_TEST, lab_test
from rockcal.specimens.grain_limit import check_grains, expected_grains
from rockcal.specimens.specimen import SHIPPED_DIR

if TYPE_CHECKING:
    from rockcal.campaign.procedure.state import CampaignState

IDENTIFIABILITY = "identifiability"  # the stage's name
SIDES = ("low", "high")  # the two ends of the range the DEM reads
BISECTIONS = 2  # runs a side of a range read adds at most after its end's, each halfway in or out
# of the box: a side whose farthest run that met the sheet and nearest beyond that missed lie
# this near each other is settled, its edge of the set found closely enough for a verdict
EDGE_GAP = 0.05
CONFINEMENT_MPA = 10.0  # a confined test the sheet lacks runs at this confinement
# a test not named in [identifiability] tests runs only where its two runs cost at most this
# many UCS runs and rockcal ships its packing (a genesis takes longer than the runs): the stage
# stays the ends' runs of the calibrated tests and little more, a small part of the campaign
MOST_UCS_RUNS = 1.0
# a test's lab work against a Brazilian disk's (its specimens' making, its rig): the ranking
# divides each test's spread by it; the UCS test's CI and CD are readings of tests already done
LAB_WORK = {PRIMARY_TEST: 0.5, "brazilian": 1.0, "bending": 1.5, "scb": 1.0, "biaxial": 2.0, "direct_tension": 2.0}
READINGS = {"ci_MPa": "read the crack initiation stress (CI) of your UCS tests",
            "cd_MPa": "read the crack damage stress (CD) of your UCS tests"}
ADVICE = {"brazilian": "Brazilian (indirect tensile) strength", "direct_tension": "direct tensile strength",
          "biaxial": f"strength confined at {CONFINEMENT_MPA:g} MPa",
          "bending": "fracture toughness K_IC (notched-beam bending)",
          "scb": "fracture toughness K_IC (semi-circular bend)"}


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
    its specimen settings that costs little (`_cheap`), that it does not calibrate against (a
    validation check's included: the user has its value); and the UCS test's CI and CD where
    they are no target."""
    named, calibrated = campaign.identifiability.tests, campaign.target_sections()
    targets = {r for section in calibrated.values() for r in section.measured()}
    found = [Candidate(PRIMARY_TEST, r, {}, label) for r, label in READINGS.items()
             if r not in targets and (named is None or PRIMARY_TEST in named)]
    for test, kind in LAB_TESTS.items():
        if test == PRIMARY_TEST or test in calibrated or (named is not None and test not in named):
            continue
        own = {kind.series.name: CONFINEMENT_MPA} if kind.series else {}
        if not _runs_here(kind, campaign, own) or (named is None and not _cheap(campaign, test)):
            continue
        what = ADVICE.get(test, f"{kind.title} {kind.strength_response.name}")
        label = (f"calibrate against the {what} you have ([validation] tests names it a check only)"
                 if test in campaign.validation_tests() else f"measure the {what}")
        found.append(Candidate(test, kind.strength_response.name, own, label))
    return found


def _cheap(campaign, test: str) -> bool:
    """Whether a test's runs at the two ends take at most MOST_UCS_RUNS UCS runs' time on a
    packing rockcal ships (the campaign's seed's)."""
    name = lab_test(test).packing_file(campaign.specimen)
    shipped = name is None or (SHIPPED_DIR / name).exists()
    return shipped and len(SIDES) * relative_time(campaign, test) <= MOST_UCS_RUNS


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


@dataclass(frozen=True)
class Narrowing:
    """The stage between its batches of runs: the record as the surrogate's set gives it, the
    parameter whose range the DEM reads, the DEM runs at its ends so far and each side's point
    to run next (None: settled, `_settled`)."""

    found: Identifiability
    name: str
    next: tuple[dict | None, dict | None]
    keys: tuple[str, ...] = ()  # of the runs asked for so far
    first: int = 0  # the first of found.end_runs at this parameter's ends


def pinning_runs(state: CampaignState, judged: Callable) -> tuple[list[RunSpec], Callable]:
    """The stage's next batch at an accepted point and the fold that records what it says:
    the ends' runs of the calibrated tests while a side is not settled, then the lacking
    tests' at the ends kept (`Identifiability` in the state's `final`; `judged(state)`: the
    surrogate of every run)."""
    n = state.narrowing
    if n is None:
        surrogate = judged(state)
        found, points = surrogate_set(state, surrogate)
        if _loosest_unread(found, state.identified()) is None or not state.campaign.identifiability.runs:
            done = found.model_copy(update={"text": text_of(found, state.campaign, state.identified())})
            return [], lambda results, progress: replace(state, final=state.final | {"identifiability": done})
        state = _narrowing(state, found, surrogate, points, ())
    elif all(row is None for row in n.next):
        read = _read_range(state)
        found = n.found.model_copy(update={"ranges": n.found.ranges | {n.name: read}})
        if _loose(read) or _loosest_unread(found, state.identified()) is None:
            return _ranking_runs(replace(state, narrowing=replace(n, found=found)), read)
        surrogate = judged(state)
        state = _narrowing(state, found, surrogate, surrogate_set(state, surrogate)[1], n.keys)
    return _end_runs(state, judged)


def _loose(read: ParameterRange) -> bool:
    """Whether a range read in the DEM leaves its parameter not pinned, between ends that met the sheet."""
    return not read.pinned and bool(read.verified_ends)


def _loosest_unread(found: Identifiability, identified: dict) -> str | None:
    """The parameter not pinned whose value `identified` may lie farthest from the truth
    (`largest_error`; then the widest share of its box) that the DEM has not read (None: none)."""
    loose = {n: r for n, r in found.ranges.items() if not r.pinned and r.verified_ends is None}
    return max(loose, key=lambda n: (largest_error(loose[n].low, loose[n].high, identified[n]), loose[n].share)) \
        if loose else None


def _narrowing(state: CampaignState, found: Identifiability, surrogate, points: np.ndarray,
               keys: tuple) -> CampaignState:
    """The state reading the loosest unread range not pinned (`_loosest_unread`) in the DEM
    next: its two ends (`ends_of` the set `points` of the `surrogate`)."""
    name = _loosest_unread(found, state.identified())
    worst = worst_errors(surrogate.predict, state.goals.targets, points)
    ends = [dict(zip(state.names, rounded(row, state.whole)))
            for row in ends_of(points, state.names.index(name), worst)]
    return replace(state, narrowing=Narrowing(found, name, tuple(ends), keys, first=len(found.end_runs)))


def surrogate_set(state: CampaignState, surrogate) -> tuple[Identifiability, np.ndarray]:
    """The record as the surrogate gives it and the points that meet every target within its
    band with the surrogate's error at the verified points (`surrogate_error`): each
    parameter's range over them."""
    campaign, names, box = state.campaign, state.names, state.box
    error = surrogate_error(state)
    band = bands(state.goals.targets, campaign.acceptance.tolerance, state.goals.spread, error)
    start = np.array([state.identified()[n] for n in names])
    points = meeting_set(meets(surrogate.predict, band), box, start, seed=campaign.surrogate.seed)
    points = points if len(points) else start[None]  # the surrogate misses the sheet: the verified point
    within, share = campaign.identifiability.pinned_within, campaign.identifiability.pinned_share
    ranges = {n: ParameterRange(**r) for n, r in parameter_ranges(points, box, names, start, within, share).items()}
    return Identifiability(bands=band, surrogate_error=error, pinned_within=within, pinned_share=share, ranges=ranges,
                           set_points=kept(points).tolist(), end_runs=[], points=[], tests=[], runs=0,
                           text=""), points


def surrogate_error(state: CampaignState) -> dict[str, float]:
    """Each target's largest relative error of the surrogate's predictions at the verified
    points (before their runs trained it): its error near the accepted point, where the
    verification loop's points lie."""
    pairs = [(it.predicted, it.verified) for it in state.iterations if it.verified is not None]
    return {r: max((abs(p[r] / v[r] - 1) for p, v in pairs if r in p and r in v and v[r]), default=0.0)
            for r in state.goals.targets}


def _end_runs(state: CampaignState, judged: Callable) -> tuple[list[RunSpec], Callable]:
    """The calibrated tests' runs at each side's next point (on their packings, as a verified
    point's), and the fold that moves each side on (`_next_points`)."""
    n, campaign = state.narrowing, state.campaign
    pending = [(side, row) for side, row in zip(SIDES, n.next) if row is not None]
    points = [(campaign.specimen, row) for _, row in pending]
    specs = point_specs(state, points, means=True)
    sheet = bands(state.goals.targets, campaign.acceptance.tolerance, state.goals.spread, None)

    def fold(results, progress):
        try:
            new, found = folded(state, IDENTIFIABILITY, points, results, means=True)
        except CalibrationFailed:  # every run failed: the sides' next points
            new, found = state, [None] * len(points)
        runs = [EndRun(side=side, point=row, errors=_errors(state.goals.targets, v),
                       met=v is not None and in_bands(v, sheet), parameter=n.name)
                for (side, row), v in zip(pending, found)]
        end_runs = n.found.end_runs + runs
        # the runs train the surrogate: where the set it gives is off the DEM's, it learns so there
        new = _trained(new, points, grouped(new, points, results, means=True))
        sides = {side: [r for r in end_runs[n.first:] if r.side == side] for side, _ in pending}
        next_ = _next_points(new, judged, {side: runs for side, runs in sides.items()
                                           if not _settled(new, side, runs)})
        found_now = n.found.model_copy(update={"end_runs": end_runs})
        # the calibration's run budget (dem_runs) counts none of the stage's runs
        return replace(new, dem_runs=state.dem_runs,
                       narrowing=replace(n, found=found_now, next=tuple(next_.get(side) for side in SIDES),
                                         keys=n.keys + tuple(s.key for s in specs)))

    return specs, fold


def _trained(state: CampaignState, points: list, per_point: list[dict]) -> CampaignState:
    """The state with the points whose runs succeeded among the surrogate's training runs
    (their first packing's responses, as a verified point's)."""
    rows = [(np.array([row[n] for n in state.names]), point_responses(state, first_packing(state, runs))[0])
            for (_, row), runs in zip(points, per_point)]
    fresh = [(x, v) for x, v in rows if v is not None and not any(np.allclose(x, seen) for seen in state.train_x)]
    if not fresh:
        return state
    return replace(state, train_x=np.vstack([state.train_x, *[x for x, _ in fresh]]),
                   train_y=state.train_y + [v for _, v in fresh])


def _settled(state: CampaignState, side: str, runs: list[EndRun]) -> bool:
    """Whether a side's runs so far settle it: its bisections done, or its edge (`_edge`)
    found within EDGE_GAP of the box."""
    name = state.narrowing.name
    inner, outer = _edge(state, side, runs)
    reach = (outer or {name: state.bounds[name][SIDES.index(side)]})[name]
    box_low, box_high = state.bounds[name]
    return len(runs) > BISECTIONS or abs(reach - inner[name]) <= EDGE_GAP * (box_high - box_low)


def _edge(state: CampaignState, side: str, runs: list[EndRun]) -> tuple[dict, dict | None]:
    """A side's farthest point that met the sheet (the accepted point before one did) and its
    nearest run farther out that missed it (None: none did, the box's bound stands for it)."""
    name, out = state.narrowing.name, 1 if side == "high" else -1
    met = [r.point for r in runs if r.met]
    inner = max(met, key=lambda row: out * row[name]) if met else state.identified()
    missed = [r.point for r in runs if not r.met and out * (r.point[name] - inner[name]) > 0]
    return inner, min(missed, key=lambda row: out * row[name]) if missed else None


def _next_points(state: CampaignState, judged: Callable, sides: dict[str, list[EndRun]]) -> dict[str, dict]:
    """Each side's next point, by bisection of the parameter read across its edge (`_edge`):
    halfway between its farthest point that met the sheet and its nearest beyond that missed,
    the other parameters where the set of the surrogate the runs trained lies there (its end on
    that side among its points no farther out), or halfway too where no point of that set lies
    between them; halfway to the box's bound where no run beyond missed. On a ridge that curves,
    a straight line from the accepted point leaves the DEM's set."""
    name = state.narrowing.name
    k = state.names.index(name)
    if any(not r.met for runs in sides.values() for r in runs):  # a point to pull in: the retrained set
        surrogate = judged(state)
        points = surrogate_set(state, surrogate)[1]
        worst = worst_errors(surrogate.predict, state.goals.targets, points)
    found = {}
    for side, runs in sides.items():
        inner, outer = _edge(state, side, runs)
        if outer is None:  # pushed out towards the box's bound, unless on it
            bound = state.bounds[name][SIDES.index(side)]
            if not np.isclose(inner[name], bound):
                found[side] = _rounded(state, inner | {name: (inner[name] + bound) / 2})
            continue
        halfway = (inner[name] + outer[name]) / 2
        between = (points[:, k] >= halfway) & (points[:, k] <= inner[name]) if side == "low" else \
            (points[:, k] <= halfway) & (points[:, k] >= inner[name])
        if between.any():
            end = ends_of(points[between], k, worst[between])[SIDES.index(side)]
            found[side] = _rounded(state, dict(zip(state.names, end)) | {name: halfway})
        else:
            found[side] = _rounded(state, {n: (inner[n] + outer[n]) / 2 for n in state.names})
    return found


def _rounded(state: CampaignState, row: dict) -> dict:
    return dict(zip(state.names, rounded(np.array([row[n] for n in state.names]), state.whole)))


def _errors(targets: dict[str, float], responses: dict | None) -> dict | None:
    return None if responses is None else {r: responses[r] / t - 1 for r, t in targets.items()}


def _ends_read(state: CampaignState, name: str, within_scatter: bool = False) -> list[dict]:
    """The two ends kept of a parameter's range read in the DEM: of every point the DEM found
    meeting the sheet (the accepted point, and each end run of the stage that met it, whichever
    range it read) and, `within_scatter`, each run of that parameter's read that misses it by
    no more than the DEM's scatter (`_beyond_scatter`), those where it is lowest and highest."""
    met = [state.identified()] + [r.point for r in state.narrowing.found.end_runs if r.met or (
        within_scatter and r.parameter == name and r.errors is not None and not _beyond_scatter(state, r))]
    return [min(met, key=lambda row: row[name]), max(met, key=lambda row: row[name])]


def _spanning(state: CampaignState, name: str, verified_ends: list[str]) -> ParameterRange:
    """A parameter's range read in the DEM and its verdict: from its ends kept within the DEM's
    scatter (`_ends_read`) out to the nearest runs of its read beyond that miss the sheet by
    more (`_beyond_scatter`), or to the box's bounds where none did. The set's edges along the
    read lie between; it pins the parameter only where they all lie close. `met_low` and
    `met_high` span the points found meeting the sheet."""
    met_low, met_high = (end[name] for end in _ends_read(state, name))
    maybe_low, maybe_high = (end[name] for end in _ends_read(state, name, within_scatter=True))
    missed = [r.point[name] for r in state.narrowing.found.end_runs
              if r.parameter == name and r.errors is not None and _beyond_scatter(state, r)]
    box_low, box_high = state.bounds[name]
    low = max((x for x in missed if x < maybe_low), default=box_low)
    high = min((x for x in missed if x > maybe_high), default=box_high)
    share, found = (high - low) / (box_high - box_low), state.narrowing.found
    pinned = pins(low, high, state.identified()[name], share, found.pinned_within, found.pinned_share)
    return ParameterRange(low=low, high=high, share=share, pinned=pinned,
                          verified_ends=verified_ends, met_low=met_low, met_high=met_high)


def _beyond_scatter(state: CampaignState, run: EndRun) -> bool:
    """Whether a run misses a target by more than the tolerance (or the lab's spread) and the
    surrogate's error at the verified points: outside the band the surrogate's set uses. The
    surrogate's error there is mostly the DEM's scatter between nearby points, so a run that
    misses by less may lie beside points of the set that meet it."""
    responses = {r: t * (1 + run.errors[r]) for r, t in state.goals.targets.items()}
    return not in_bands(responses, state.narrowing.found.bands)


def _read_range(state: CampaignState) -> ParameterRange:
    """The range the DEM read (`_spanning`); where no end of this range met the sheet, the DEM
    found no point of the set to read: the surrogate's range and verdict stay, marked read."""
    n = state.narrowing
    met = [side for side in SIDES if any(r.met and r.side == side for r in n.found.end_runs[n.first:])]
    return _spanning(state, n.name, met) if met else n.found.ranges[n.name].model_copy(update={"verified_ends": []})


def _ranking_runs(state: CampaignState, read: ParameterRange) -> tuple[list[RunSpec], Callable]:
    """Each lacking test's runs at the two ends kept within the DEM's scatter (`_ends_read`) of
    the range the DEM `read` where it is not pinned: points the sheet cannot tell apart, as far
    as the DEM's scatter lets it; and the fold that ranks them and records the stage."""
    n, campaign = state.narrowing, state.campaign
    ends = _ends_read(state, n.name, within_scatter=True)
    tests = candidates(campaign) if _loose(read) else []
    asked = [(c, [spec_of(state, c.test, campaign.specimen, row, c.own) for row in ends]) for c in tests]
    specs = list({spec.key: spec for _, runs in asked for spec in runs}.values())
    keys = set(n.keys) | {spec.key for spec in specs}

    def fold(results, progress):
        done = dict(zip((spec.key for spec in specs), results))
        ranked = sorted((_spread(c, [done[spec.key] for spec in runs]) for c, runs in asked), key=lambda t: -t.score)
        # each range read between ends that met the sheet spans every point later reads found meeting it too
        ranges = {name: _spanning(state, name, r.verified_ends) if r.verified_ends else r
                  for name, r in (n.found.ranges | {n.name: read}).items()}
        found = n.found.model_copy(update={"ranges": ranges, "points": ends if tests else [],
                                           "tests": ranked, "runs": len(keys - set(state.dem_runs))})
        found = found.model_copy(update={"text": text_of(found, campaign, state.identified())})
        return replace(state, narrowing=None, final=state.final | {"identifiability": found})

    return specs, fold


def planned_runs(state: CampaignState) -> list[RunSpec]:
    """The stage's runs as the first screen plans them (the planning state): the first
    searched parameter's range read, each end run 1 + BISECTIONS times, and each lacking
    test's runs at its two ends; none with [identifiability] runs = false."""
    campaign = state.campaign
    if not campaign.identifiability.runs:
        return []
    x = stand_in(state.box, state.whole)
    ends = [rounded(np.r_[x[0] + (state.box[0, k] - x[0]) / 2 ** j, x[1:]], state.whole)
            for k in (0, 1) for j in range(1 + BISECTIONS)]
    specs = point_specs(state, [(campaign.specimen, dict(zip(state.names, row))) for row in ends], means=True)
    specs += [spec_of(state, c.test, campaign.specimen, dict(zip(state.names, row)), c.own)
              for c in candidates(campaign) for row in ends[::1 + BISECTIONS]]
    return list({spec.key: spec for spec in specs}.values())


def further_reads_tests(campaign, searched: int) -> list[str]:
    """The test of each run the stage may add to the planned runs, at most: every other
    searched parameter's range read too (the DEM pins each read before it)."""
    if not campaign.identifiability.runs:
        return []
    per_point = [test for test, s in campaign.target_sections().items()
                 for _ in range(max(1, len(s.series())) * s.packings)]
    return (searched - 1) * len(SIDES) * (1 + BISECTIONS) * per_point


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


def text_of(found: Identifiability, campaign, identified: dict) -> str:
    """What the stage found at the `identified` point, in a sentence or two."""
    tolerance = campaign.acceptance.tolerance
    loose = {n: r for n, r in found.ranges.items() if not r.pinned}
    read = [n for n, r in found.ranges.items() if r.verified_ends is not None]
    if loose:
        listed = ", ".join(f"{n} {r.low:.4g}–{r.high:.4g} ({_error_text(r, identified[n])}, "
                           + ("on the surrogate" if r.verified_ends is None else
                              f"read in the DEM: {_ends_text(r)}") + ")" for n, r in loose.items())
        text = f"the sheet does not pin {' and '.join(loose)}: the points that meet it lie within {listed}"
    else:
        most = max(largest_error(r.low, r.high, identified[n]) for n, r in found.ranges.items())
        text = (f"the sheet pins every searched parameter: each value found lies within {100 * most:.1f} % of every "
                "point that meets it in that parameter, so of the truth")
    unbounded = [n for n, r in loose.items() if r.met_low is not None
                 and pins(r.met_low, r.met_high, identified[n], _met_share(r), found.pinned_within, found.pinned_share)]
    if unbounded:
        text += (f"; in {' and '.join(unbounded)} the points found meeting it lie within "
                 f"{100 * found.pinned_within:g} % of the value found, but the runs did not bound the set that closely")
    pinned_read = [n for n in read if n not in loose]
    if pinned_read:
        text += "; read in the DEM, " + "; ".join(
            f"{n}'s range is {r.low:.4g}–{r.high:.4g} ({_error_text(r, identified[n])}: {_ends_text(r)})"
            for n, r in ((n, found.ranges[n]) for n in pinned_read))
    if read:
        text += f" ({len(found.end_runs)} runs in the DEM)"
    useful = [t for t in found.tests if t.spread > 2 * tolerance]
    if useful:
        best = useful[0]
        return (text + f". {best.label[0].upper()}{best.label[1:]}: it varies {100 * best.spread:.0f} % between the "
                f"ends; add it to [targets] and resume (--resume keeps the runs done).")
    if loose and not campaign.identifiability.runs:
        return text + ". [identifiability] runs = false: no lab test was run to name one that would pin it."
    if not any(n in loose and found.ranges[n].verified_ends for n in read):
        return text + "."
    ran = ", ".join(dict.fromkeys(t.response for t in found.tests)) or "none"
    return (text + f". No response run at the ends ({ran}) varies more than ±{100 * tolerance:g} % between them: "
            "name dearer tests in [identifiability] tests, or narrow the search box with what you know of the "
            "parameter.")


def _error_text(r: ParameterRange, found: float) -> str:
    """How far from the value found a range reaches (`largest_error`) and its share of the box, in words."""
    error = largest_error(r.low, r.high, found)
    return (f"±{100 * error:.1f} % of the value found" if np.isfinite(error) else "reaching zero") \
        + f", {100 * r.share:.0f} % of its box"


def _met_share(read: ParameterRange) -> float:
    """The share of its box the points a range read in the DEM found meeting the sheet span."""
    return read.share * (read.met_high - read.met_low) / (read.high - read.low)


def _ends_text(read: ParameterRange) -> str:
    """Which ends of a range read in the DEM met the sheet there and over what span, in words."""
    ends = read.verified_ends
    if not ends:
        return "no end met the sheet, the surrogate's range kept"
    other = "high" if ends == ["low"] else "low"
    which = "both ends met the sheet" if len(ends) == 2 else \
        f"its {ends[0]} end met the sheet, its {other} end is the farthest other point found meeting it"
    return (f"{which}; met over {read.met_low:.4g}–{read.met_high:.4g}, bounded by runs that miss it beyond the "
            "surrogate's error or by the box")
