"""The inverse procedure as a declared list of steps: sensitivity (orthogonal array, range
analysis), coarse Latin hypercube samples (multi-fidelity, when asked for), Latin hypercube
samples and the surrogate's checks, the search on the surrogate and
its DEM verification (a loop, until a verified point is accepted), then the packings and
validation runs at the identified point (the parameters' intervals, the curve fit, the checks),
and last, at an accepted point, which parameters the sheet pins and which test would pin the others.

A step is a function of the results so far (`state.CampaignState`) that returns the forward
runs it needs and how to fold their results into the next state (`Runs`). `calibrate` passes
the runs to the executor it is given (serial, process pool or Dask) and folds; the first screen
(`rockcal.campaign.plan.screen`) asks the same steps for their runs at the planning state
(`planning_state`), so what is planned is what runs (but for a verification round's other
optima and further rounds, and the identifiability stage's bisections, which the first screen
names: `verification_runs`, `pinning`). Each parameter
set runs every lab test calibrated against (a test with a series, such as confined compression
at several confinements, one run per value, folded by the test's `combine`), and their
responses make one dict: the steps see one forward model whatever the tests behind it.

Every forward run goes through the executor and its store, and every other step is seeded,
so running a campaign again (after a kill, or to rebuild a report) gives the same answer and
runs only what the store does not hold.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from rockcal.campaign.input.config import Campaign, SpecimenSettings, middle_levels, split_genesis
from rockcal.campaign.procedure.goals import goals_of, goals_of_tests
from rockcal.campaign.procedure.result import (CalibrationResult, Iteration, Samples, Sensitivity,
                                     SurrogateCheck, on_bounds)
from rockcal.campaign.runs.spec import RunResult, RunSpec
from rockcal.campaign.procedure.points import (CalibrationFailed, first_packing, folded, grouped, optimise,
                                             packings_of, point_responses, point_specs,
                                             series_values, spec_of, specs_keys, specs_of_test)
from rockcal.campaign.procedure.rounding import rounded, rounded_rows, stand_in
from rockcal.campaign.procedure.state import CampaignState, Round
from rockcal.campaign.procedure.verdict import verdict_of
from rockcal.campaign.procedure.pinning import IDENTIFIABILITY, pinning_runs, planned_runs
from rockcal.campaign.procedure.final import KIC_TEST, checks_of, curve_fit_of, uncertainty_of, validation_of
from rockcal.inverse import RBFSurrogate, Objective, design, latin_hypercube, range_analysis
from rockcal.inverse.multifidelity import CorrectedSurrogate
from rockcal.inverse.surrogate import minimum_runs
from rockcal.labtests.bending import RUN_ON_FRACTION
from rockcal.labtests.registry import PRIMARY_TEST
from rockcal.labtests.seeds import seed_list
from rockcal.materials import DEFAULT_MATERIAL, material

DISTINCT = 0.05  # optima closer than this (box-normalised distance) are one optimum
SEARCHES_PER_CANDIDATE = 2  # searches tried for each other candidate optimum before giving up

Progress = Callable[[str, int, int], None]  # progress(stage, done, total)

SAMPLES_AND_CHECKS = "samples and checks"  # the stage of the Latin hypercube runs and checks
COARSE_SAMPLES = "coarse samples"  # the stage of the multi-fidelity search's coarse runs
VERIFICATION = "verification"  # the stage of the verification loop's rounds
# the stage of the runs at the identified point: the other packings and the validation tests
PACKINGS_AND_VALIDATION = "packings and validation"


Fold = Callable[[list[RunResult], Progress], CampaignState]


@dataclass(frozen=True)
class Runs:
    """What a step asks for: the forward runs, and how their results (in the same order) make
    the next state."""

    specs: list[RunSpec]
    fold: Fold


@dataclass(frozen=True)
class Step:
    """A step of the procedure: its stage name (the progress bar's and the first screen's),
    the runs it needs from the state so far, whether it runs again (the verification loop) and
    the specimen settings its runs use (their resolution)."""

    stage: str
    runs: Callable[[CampaignState], Runs]
    again: Callable[[CampaignState], bool] = lambda state: False
    specimen: Callable[[Campaign], SpecimenSettings] = lambda campaign: campaign.specimen


def calibrate(campaign: Campaign, executor, progress: Progress | None = None) -> CalibrationResult:
    """Run the campaign's steps with `executor` (its `run(specs, progress)` returns results in
    order); returns what the campaign found. A note a step leaves in the state (a parameter the
    targets barely see) goes to `progress.note(text)` as soon as the step is done, if it has one."""
    progress = progress or (lambda stage, done, total: None)
    state, told = start(campaign), 0
    for step in STEPS:
        while True:
            runs = step.runs(state)
            shown = lambda done, total, stage=step.stage: progress(stage, done, total)  # noqa: E731
            results = executor.run(runs.specs, shown) if runs.specs else []
            state = runs.fold(results, progress)
            if not step.again(state):
                break
        for note in state.notes[told:]:
            getattr(progress, "note", lambda text: None)(note)
        told = len(state.notes)
    return result_of(state)


def start(campaign: Campaign) -> CampaignState:
    """The state before any run: the campaign, its targets, its fixed parameters."""
    return CampaignState(campaign=campaign, goals=goals_of(campaign), fixed=campaign.fixed_params())


def planning_state(campaign: Campaign) -> CampaignState:
    """The state every step plans its runs from before the campaign starts: the search box
    known before any run ([search] bounds, else every sensitivity factor's levels), with
    a stand-in (`stand_in`) for the point a search finds: the first verification round's
    optimum, also the identified point."""
    levels = campaign.sensitivity.levels if campaign.sensitivity else {}
    bounds, fixed = search_space(campaign, list(levels))
    return replace(start(campaign), bounds=bounds, fixed=fixed, planning=True)


# -- step 1: sensitivity -------------------------------------------------------------------------

def sensitivity_rows(campaign: Campaign) -> list[dict]:
    """The orthogonal array's parameter sets (none without [sensitivity])."""
    if campaign.sensitivity is None:
        return []
    runs = design(campaign.sensitivity.array, campaign.sensitivity.levels)
    n = len(next(iter(runs.values())))
    return [{f: float(v[i]) for f, v in runs.items()} for i in range(n)]


def search_space(campaign: Campaign, chosen: list[str]) -> tuple[dict, dict]:
    """The search bounds ([search] bounds, else the levels of the factors the range analysis
    chose) and the fixed parameters, with the middle level of each factor neither searched
    nor fixed (`middle_levels`)."""
    bounds, fixed = dict(campaign.search.bounds), campaign.fixed_params()
    levels = campaign.sensitivity.levels if campaign.sensitivity else {}
    if not bounds:
        bounds = {f: (min(levels[f]), max(levels[f])) for f in chosen}
    return bounds, fixed | middle_levels(campaign, bounds)


def sensitivity_runs(state: CampaignState) -> Runs:
    """The orthogonal-array runs (their values override [search] fixed), then range analysis."""
    campaign = state.campaign
    rows = sensitivity_rows(campaign)
    specimen = campaign.sensitivity_specimen()
    points = [(specimen, row) for row in rows]

    def fold(results, progress) -> CampaignState:
        if not rows:
            bounds, fixed = search_space(campaign, [])
            return replace(state, bounds=bounds, fixed=fixed)
        new, responses = folded(state, "sensitivity", points, results)
        settings = campaign.sensitivity
        names = list(state.goals.targets)
        table = _fill_failed({r: [None if v is None else v[r] for v in responses] for r in names})
        analysis = range_analysis({f: np.array([row[f] for row in rows]) for f in rows[0]}, table)
        bounds, fixed = search_space(campaign, analysis.chosen(settings.threshold))
        unseen = analysis.unseen(state.goals.targets, campaign.acceptance.tolerance, list(bounds))
        study = Sensitivity(array=settings.array, runs=rows, run_responses=responses,
                            imputed_runs=[i for i, v in enumerate(responses) if v is None],
                            rmin_mm=specimen.rmin_mm if specimen != campaign.specimen else None,
                            unseen=unseen or None, **analysis.to_dict(settings.threshold))
        notes = tuple(unseen_note(name, campaign.acceptance.tolerance) for name in unseen)
        return replace(new, bounds=bounds, fixed=fixed, sensitivity=study, notes=new.notes + notes)

    return Runs(point_specs(state, points), fold)


def unseen_note(name: str, tolerance: float) -> str:
    """The warning of a searched parameter the targets barely see (`RangeAnalysis.unseen`)."""
    return (f"{name}'s effect on every target is below the tolerance (±{100 * tolerance:g} %) in the sensitivity "
            "runs: these targets will not pin it")


# -- step 2: coarse samples (multi-fidelity), samples, surrogate and its check -------------------

def coarse_sample_runs(state: CampaignState) -> Runs:
    """The Latin hypercube runs at coarse resolution ([surrogate] coarse_samples): with the
    sensitivity runs that are runs of the search at that resolution, they train the
    low-fidelity surrogate that the full-resolution samples correct (none: no runs)."""
    campaign, names, box = state.campaign, state.names, state.box
    s = campaign.surrogate
    if not s.coarse_samples:
        return Runs([], lambda results, progress: state)
    x = rounded_rows(latin_hypercube(box, s.coarse_samples, seed=s.seed + 2), state.whole)
    specimen = campaign.coarse_specimen()
    points = [(specimen, dict(zip(names, row))) for row in x]

    def fold(results, progress) -> CampaignState:
        new, y = folded(state, COARSE_SAMPLES, points, results)
        reused = _reusable(new, names, box, specimen)
        coarse_x, coarse_y = _usable(np.vstack([x, _points(new.sensitivity, reused, names)]),
                                     y + [new.sensitivity.run_responses[i] for i in reused])
        return replace(new, coarse=Samples(x=x.tolist(), responses=y, reused_sensitivity_runs=reused or None),
                       low_fidelity=RBFSurrogate(_enough_runs(new, coarse_x), _responses(new, coarse_y), box))

    return Runs(point_specs(state, points), fold)


def sample_runs(state: CampaignState) -> Runs:
    """The Latin hypercube runs and the check runs as one batch; the surrogate on the samples
    (with the sensitivity runs that are runs of the search), checked on the check points.
    The checks and [surrogate] samples_every_test of the samples (`spread_out`) run every
    test; the other samples run the UCS test alone."""
    campaign, names, box = state.campaign, state.names, state.box
    s = campaign.surrogate
    x, checks = sample_points(box, s, state.whole)
    every = spread_out(x, box, len(x) if s.samples_every_test is None else s.samples_every_test)
    ucs_only = [i for i in range(len(x)) if i not in every]
    points = [(campaign.specimen, dict(zip(names, row))) for row in [*x[every], *checks]]
    ucs_points = [(campaign.specimen, dict(zip(names, row))) for row in x[ucs_only]]
    ucs_state = replace(state, goals=goals_of_tests(state.goals, [PRIMARY_TEST]))
    specs = point_specs(state, points)

    def fold(results, progress) -> CampaignState:
        new, y_all = folded(state, SAMPLES_AND_CHECKS, points, results[:len(specs)])
        if ucs_points:
            new, y_ucs = folded(replace(new, goals=ucs_state.goals), SAMPLES_AND_CHECKS, ucs_points,
                                results[len(specs):])
            new = replace(new, goals=state.goals)
        y = [None] * len(x)
        for i, v in zip([*every, *ucs_only], y_all[:len(every)] + (y_ucs if ucs_points else [])):
            y[i] = v
        y_checks = y_all[len(every):]
        reused = _reusable(new, names, box, campaign.specimen)
        train_x, train_y = _usable(np.vstack([x, _points(new.sensitivity, reused, names)]),
                                   y + [new.sensitivity.run_responses[i] for i in reused])
        surrogate = _fit(new, train_x, train_y)
        check_x, check_y = _usable(checks, y_checks)
        return replace(new, samples=Samples(x=x.tolist(), responses=y, reused_sensitivity_runs=reused or None),
                       surrogate_check=_check(new, surrogate, checks, y_checks, check_x, check_y),
                       train_x=np.vstack([train_x, check_x]), train_y=train_y + check_y)

    return Runs(specs + point_specs(ucs_state, ucs_points), fold)


def spread_out(x: np.ndarray, box: np.ndarray, k: int) -> list[int]:
    """k of the points x, each the farthest (in the box scaled to a unit cube) from those
    taken before it, the first the nearest the box's centre: few runs that still span it."""
    unit = (x - box[:, 0]) / (box[:, 1] - box[:, 0])
    taken = [int(np.argmin(np.linalg.norm(unit - 0.5, axis=1)))]
    gap = np.full(len(x), np.inf)  # each point's distance to the nearest taken: k x n work, not k^2 x n
    while len(taken) < min(k, len(x)):
        gap = np.minimum(gap, np.linalg.norm(unit - unit[taken[-1]], axis=1))
        taken.append(int(np.argmax(gap)))
    return sorted(taken)


def _check(state: CampaignState, surrogate: RBFSurrogate, checks, y_checks, check_x, check_y) -> SurrogateCheck:
    """The surrogate against the DEM at the check points."""
    tolerance = state.campaign.surrogate.tolerance
    validation = surrogate.validate(check_x, {r: np.array([v[r] for v in check_y]) for r in state.goals.targets},
                                    tolerance) if len(check_x) else None
    return SurrogateCheck(
        x=checks.tolist(), dem=y_checks, predicted=[surrogate.predict(row) for row in checks],
        max_relative_error=None if validation is None else validation.max_relative_error,
        trusted=None if validation is None else validation.trusted,
        tolerance=tolerance, epsilon=surrogate.epsilon)


def _reusable(state: CampaignState, names: list[str], box: np.ndarray, specimen: SpecimenSettings) -> list[int]:
    """The sensitivity runs that are runs of the search on `specimen`: inside the box, with
    every other parameter at its fixed value (the very run a sample at that point would be)."""
    study, campaign = state.sensitivity, state.campaign
    if study is None or campaign.sensitivity_specimen() != specimen:
        return []
    keep = []
    for i, (row, responses) in enumerate(zip(study.runs, study.run_responses)):
        point = {n: row[n] for n in names if n in row}
        same = len(point) == len(names) and \
            _params(state, row) == _params(state, point)
        if responses is not None and same and _inside(point, names, box):
            keep.append(i)
    return keep


def _params(state: CampaignState, row: dict) -> dict:
    params, genesis = split_genesis(state.fixed | row)
    return material(state.campaign.material.model).make(params).key() | genesis


# -- step 3: search on the surrogate and DEM verification (a loop) -------------------------------

def verification_runs(state: CampaignState) -> Runs:
    """One round of the loop: the surrogate on every run so far, the search's optimum and
    other distinct optima on it ([acceptance] candidates), their DEM runs; the round settles
    the loop when a verified point is accepted, the budget is spent or nothing new was found.
    With [acceptance] ucs_first, a round has two stages: the UCS runs at its points, then
    every test's at the points whose UCS responses met the tolerance of the targets or of the
    surrogate's prediction (`pending`: their UCS runs come from the store); a point that
    missed both is recorded with its UCS responses only."""
    campaign, names = state.campaign, state.names
    if state.planning:
        # the plan counts the search's optimum, the one point every round verifies: the other
        # candidates are verified only where the surrogate has other distinct optima
        # (`_candidates`), and the first screen says so (`plan.screen`)
        points = [(campaign.specimen, dict(zip(names, stand_in(state.box, state.whole))))]
        return Runs(point_specs(state, points, means=True), _not_folded)
    if state.pending is not None:
        round_ = state.pending
        points = [(campaign.specimen, dict(zip(names, x))) for x in round_.xs]
        return Runs(point_specs(state, points, means=True),
                    lambda results, progress: replace(_recorded(state, round_, points, results), pending=None))
    surrogate = _judged(state)
    objective = Objective(surrogate.predict, state.goals.targets, weights=state.goals.weights or None)
    found = _candidates(state, objective, surrogate)
    round_ = Round(found, [rounded(opt.x, state.whole) for opt in found], surrogate, objective.describe(),
                   loop=len({it.loop for it in state.iterations}))
    points = [(campaign.specimen, dict(zip(names, x))) for x in round_.xs]
    if not _ucs_first(state):
        return Runs(point_specs(state, points, means=True),
                    lambda results, progress: _recorded(state, round_, points, results))
    first = replace(state, goals=goals_of_tests(state.goals, [PRIMARY_TEST]))

    def fold(results, progress) -> CampaignState:
        per_point = grouped(first, points, results, means=True)
        tolerance, targets = campaign.acceptance.tolerance, first.goals.targets
        met = []
        for x, runs in zip(round_.xs, per_point):
            responses, predicted = point_responses(first, runs)[0], round_.surrogate.predict(x)
            # a miss the surrogate foresaw is the search's trade-off with the other tests, which
            # only their runs can settle: they run there too
            foreseen = {r: predicted[r] for r in targets}
            met.append(_within(_errors(targets, responses), tolerance)
                       or _within(_errors(foreseen, responses), tolerance))
        missed, passed = [i for i, ok in enumerate(met) if not ok], [i for i, ok in enumerate(met) if ok]
        new = first
        if missed:
            new = _recorded(first, round_.only(missed), [points[i] for i in missed],
                            [r for i in missed for r in per_point[i][PRIMARY_TEST]])
        new = replace(new, goals=state.goals)
        return replace(new, pending=round_.only(passed), settled=False) if passed else new

    return Runs(point_specs(first, points, means=True), fold)


def _ucs_first(state: CampaignState) -> bool:
    """Whether a round verifies the UCS test before the others ([acceptance] ucs_first)."""
    return state.campaign.acceptance.ucs_first and len(state.goals.tests) > 1


def _recorded(state: CampaignState, round_: Round, points: list, results: list[RunResult]) -> CampaignState:
    """The state with the round's points verified by `results` (their runs of the tests of
    `state.goals`): their iterations, the surrogate's new training runs (first packing) and
    means, whether one was accepted and whether the loop is settled."""
    campaign = state.campaign
    new, verified = folded(state, VERIFICATION, points, results, means=True)
    per_point = grouped(state, points, results, means=True)
    first = [point_responses(new, first_packing(new, runs))[0] for runs in per_point]
    iterations = [_iteration(new, opt, x, round_.surrogate, v, round_.loop)
                  for opt, x, v in zip(round_.found, round_.xs, verified)]
    fresh = _unseen(round_.xs, first, new.train_x)
    passed = [i for i, it in enumerate(iterations)
              if _within(it.errors, campaign.acceptance.tolerance) and len(it.errors) == len(new.goals.targets)]
    start_at = len(new.iterations)
    curves = dict(zip(specs_keys(new, points), (runs[PRIMARY_TEST][0].curve for runs in per_point)))
    if _averaged(campaign):
        new = _with_means(new, _unseen(round_.xs, verified, new.means_x))
    return replace(
        new, iterations=new.iterations + tuple(iterations), objective=round_.objective,
        train_x=np.vstack([new.train_x, *[x for x, _ in fresh]]), train_y=new.train_y + [v for _, v in fresh],
        accepted=start_at + passed[0] if passed else state.accepted, curves=new.curves | curves,
        settled=bool(passed) or len(new.dem_runs) >= campaign.acceptance.max_dem_runs or not fresh)


def _averaged(campaign: Campaign) -> bool:
    """Whether some target is a mean over packings."""
    return any(packings_of(campaign, test) > 1 for test in campaign.target_sections())


def _unseen(xs: list, responses: list, seen: np.ndarray | None) -> list[tuple]:
    """(x, responses) of the points that succeeded and are none of the points `seen`."""
    seen = [] if seen is None else seen
    return [(x, v) for x, v in zip(xs, responses) if v is not None and not any(np.allclose(x, row) for row in seen)]


def _with_means(state: CampaignState, new: list[tuple]) -> CampaignState:
    """The state with the means over packings (x, means) of newly verified points."""
    if not new:
        return state
    seen = [] if state.means_x is None else list(state.means_x)
    return replace(state, means_x=np.array(seen + [x for x, _ in new]), means_y=state.means_y + [v for _, v in new])


def _candidates(state: CampaignState, objective: Objective, surrogate: RBFSurrogate) -> list:
    """The search's optimum on the surrogate, then up to [acceptance] candidates - 1 other
    distinct optima within the run budget: the searches with the next seeds whose optimum
    the surrogate predicts within the tolerance of every target (none when the surrogate
    has a single optimum)."""
    campaign, box = state.campaign, state.box
    found, wanted = [optimise(campaign, objective, box)], _wanted(state)
    tolerance, seed = campaign.acceptance.tolerance, campaign.optimizer.seed
    for k in range(1, SEARCHES_PER_CANDIDATE * (wanted - 1) + 1):
        if len(found) >= wanted:
            break
        opt = optimise(campaign, objective, box, seed=seed + k)
        predicted = surrogate.predict(rounded(opt.x, state.whole))
        close = _within({r: predicted[r] / t - 1 for r, t in state.goals.targets.items()}, tolerance)
        if close and all(_distinct(opt.x, other.x, box) for other in found):
            found.append(opt)
    return found


def verified_at_most(campaign: Campaign) -> int:
    """The points a verification round of the campaign verifies at most (the first screen's
    wording): [acceptance] candidates, within the run budget."""
    return _wanted(start(campaign))


def _wanted(state: CampaignState) -> int:
    """The points a verification round verifies at most: [acceptance] candidates, within the
    run budget left."""
    left = state.campaign.acceptance.max_dem_runs - len(state.dem_runs)
    return max(1, min(state.campaign.acceptance.candidates, left))


def _not_folded(results, progress):
    raise RuntimeError("the planning state's runs are counted, never run")


def _iteration(state: CampaignState, opt, x, surrogate: RBFSurrogate, verified: dict | None, loop: int) -> Iteration:
    errors = _errors(state.goals.targets, verified)
    return Iteration(
        x=x.tolist(), objective_surrogate=float(opt.fun), predicted=surrogate.predict(x),
        verified=verified, errors=errors, history_fun=list(map(float, opt.history_fun)),
        history_x=[list(map(float, h)) for h in opt.history_x], nfev=int(opt.nfev), loop=loop)


# -- step 4: packings and validation at the identified point -------------------------------------

def final_runs(state: CampaignState) -> Runs:
    """The runs at the identified point, as one batch that keeps the workers busy to its end:
    the validation tests' (the longest, first), then the other packings of the calibrated tests
    (the parameters' intervals); folded into the intervals, the curve fit and the checks."""
    campaign, identified = state.campaign, state.identified()
    validation = {test: [spec for s in validation_seeds(campaign, test) for spec in
                         specs_of_test(state, test, _validation_specimen(campaign, test, s), identified)]
                  for test in campaign.validation_tests()}
    packings = [(campaign.specimen.model_copy(update={"seed": s}), identified)
                for s in packing_seeds(campaign)] if campaign.wants_uncertainty() else []
    specs = [spec for runs in validation.values() for spec in runs] + point_specs(state, packings, means=True)

    def fold(results, progress) -> CampaignState:
        done = dict(zip((spec.key for spec in specs), results))
        final = {"curve_fit": curve_fit_of(state, identified)}
        if packings:
            final["uncertainty"] = uncertainty_of(state, packings, point_specs(state, packings, means=True), done,
                                                  _judged(state), progress)
        final["validation"] = validation_of(campaign, validation.get(KIC_TEST), done)
        final["checks"] = checks_of(campaign, validation, done)
        return replace(state, final=final)

    return Runs(specs, fold)


def _validation_specimen(campaign: Campaign, test: str, seed: int) -> SpecimenSettings:
    """The specimen of a validation run on packing `seed`: the campaign's; the first beam of
    the K_IC validation runs on until its crack has crossed the ligament, for the report's
    crack figure (its K_IC is the one it would read stopping earlier)."""
    update = {"seed": seed}
    if test == KIC_TEST and seed == campaign.specimen.seed:
        update["stop_fraction"] = min(campaign.specimen.stop_fraction, RUN_ON_FRACTION)
    return campaign.specimen.model_copy(update=update)


def packing_seeds(campaign: Campaign) -> list[int]:
    """The packings whose scatter the parameters' intervals take in: the campaign's specimen's
    seed and the next ones; where targets are means over packings, the first seeds of as
    many disjoint sets of them."""
    window = max(packings_of(campaign, test) for test in campaign.target_sections())
    return [campaign.specimen.seed + k * window for k in range(campaign.uncertainty.packings)]


def validation_seeds(campaign: Campaign, test: str) -> list[int]:
    """The packings a validation test runs on: as many as its section's `packings` or, where
    the specimen settings have it, `specimen.<test>_seeds` (the bending test's `bending_seeds`)."""
    s = campaign.specimen
    return seed_list(s.seed, max(packings_of(campaign, test), getattr(s, f"{test}_seeds", 1)))


# -- step 5: identifiability ------------------------------------------------------------------

def identifiability_runs(state: CampaignState) -> Runs:
    """At an accepted point: which searched parameters the sheet pins, a batch at a time
    (`pinning`): the DEM runs at the ends of the widest range not pinned, then the lacking
    tests' there. The plan: both ends meet the sheet at their first runs (`planned_runs`)."""
    if state.planning:
        return Runs(planned_runs(state), _not_folded)
    if state.accepted is None:
        return Runs([], lambda results, progress: state)
    return Runs(*pinning_runs(state, _judged))


# -- the list ----------------------------------------------------------------------------------

STEPS: tuple[Step, ...] = (
    Step("sensitivity", sensitivity_runs, specimen=lambda c: c.sensitivity_specimen()),
    Step(COARSE_SAMPLES, coarse_sample_runs, specimen=lambda c: c.coarse_specimen()),
    Step(SAMPLES_AND_CHECKS, sample_runs),
    Step(VERIFICATION, verification_runs, again=lambda state: not state.settled),
    Step(PACKINGS_AND_VALIDATION, final_runs),
    Step(IDENTIFIABILITY, identifiability_runs, again=lambda state: state.narrowing is not None),
)


def result_of(state: CampaignState) -> CalibrationResult:
    """What the campaign found, from the last state."""
    campaign, goals, best = state.campaign, state.goals, state.best()
    identified = state.identified()
    params, genesis = split_genesis(state.fixed | identified)
    final_ucs_run_key = spec_of(state, PRIMARY_TEST, campaign.specimen, identified).key
    final_bending_run_key = spec_of(state, KIC_TEST, campaign.specimen, identified).key \
        if KIC_TEST in goals.tests else None
    series_runs = {test: [spec.key for spec in specs_of_test(state, test, campaign.specimen, identified)]
                   for test in campaign.tests() if series_values(campaign, test)}
    return CalibrationResult(
        rock=campaign.rock.name, targets=goals.targets, target_tests=goals.tests,
        weights=goals.weights or None, specimen=campaign.specimen.model_copy(update=genesis),
        measured_curve=None if goals.curve is None else goals.curve.tolist(),
        failed_runs=list(state.failed_runs), ucs_specimen=state.specimen_description,
        sensitivity=state.sensitivity, parameters=state.names, bounds=state.bounds, fixed=state.fixed,
        coarse_samples=state.coarse, samples=state.samples, surrogate_check=state.surrogate_check,
        iterations=list(state.iterations), accepted=state.accepted is not None, identified=identified,
        identified_params=material(campaign.material.model).make(params).key(),
        material=None if campaign.material.model == DEFAULT_MATERIAL else campaign.material.model,
        verified=state.iterations[best].verified, errors=state.iterations[best].errors,
        tolerance=campaign.acceptance.tolerance, objective=state.objective, dem_runs=len(state.dem_runs),
        best_iteration=best, dem_run_keys=list(state.dem_runs), final_ucs_run_key=final_ucs_run_key,
        final_bending_run_key=final_bending_run_key, series_runs=series_runs or None,
        verdict=None if state.accepted is not None else _verdict(state),
        at_bounds=on_bounds(identified, state.bounds) or None, **state.final)


def _verdict(state: CampaignState):
    """Which targets conflict, read on the surrogate of every run, the verified points and the
    runs seen."""
    surrogate = _judged(state)
    return verdict_of(state.goals.targets, state.campaign.acceptance.tolerance, state.box,
                      surrogate.predict, state.train_y, state.iterations[state.best()].errors,
                      [it.errors for it in state.iterations])


# -- shared pieces -------------------------------------------------------------------------------

def _fit(state: CampaignState, x, y) -> RBFSurrogate | CorrectedSurrogate:
    """The surrogate of the full-resolution runs x, y; with coarse samples, the low-fidelity
    surrogate of the coarse runs corrected by them."""
    if state.low_fidelity is None:
        return RBFSurrogate(_enough_runs(state, x), _responses(state, y), state.box)
    return CorrectedSurrogate(state.low_fidelity, x, _responses(state, y), state.box)


def _enough_runs(state: CampaignState, x: np.ndarray) -> np.ndarray:
    """The runs `x` a surrogate is fitted on (none corrected: `minimum_runs`);
    CalibrationFailed when too many failed."""
    need = minimum_runs(len(state.box))
    if len(x) < need:
        first = f"; first: {state.failed_runs[0].message}" if state.failed_runs else ""
        raise CalibrationFailed(f"{len(x)} runs succeeded where a surrogate needs {need} "
                                f"({len(state.failed_runs)} failed{first})")
    return x


def _judged(state: CampaignState) -> RBFSurrogate | CorrectedSurrogate:
    """The surrogate of what the targets are judged on: `_fit` of every full-resolution run,
    corrected by the means at the verified points where targets are means over packings (the
    runs that train it are on the first packing)."""
    surrogate = _fit(state, state.train_x, state.train_y)
    if not state.means_y:
        return surrogate
    return CorrectedSurrogate(surrogate, state.means_x, _responses(state, state.means_y), state.box)


def _responses(state: CampaignState, rows: list[dict]) -> dict[str, np.ndarray]:
    """The target responses of runs, response by response (NaN where a run has none: a point
    whose verification stopped after its UCS test)."""
    return {r: np.array([v.get(r, np.nan) for v in rows]) for r in state.goals.targets}


def _fill_failed(table: dict[str, list]) -> dict[str, np.ndarray]:
    """Responses of the array's runs with each failed run (None) given the mean of the runs that
    succeeded: the design stays balanced, and a failed run pulls no level up or down."""
    filled = {}
    for response, values in table.items():
        done = [v for v in values if v is not None]
        filled[response] = np.array([np.mean(done) if v is None else v for v in values])
    return filled


def sample_points(box: np.ndarray, s, whole: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The Latin hypercube points and the surrogate's random check points in the box (rounded,
    `whole` parameters to whole numbers: stable store keys), as the campaign's [surrogate]
    settings and seed make them."""
    x = rounded_rows(latin_hypercube(box, s.samples, seed=s.seed), whole)
    rng = np.random.default_rng(s.seed + 1)
    checks = rounded_rows(box[:, 0] + rng.random((s.checks, len(box))) * (box[:, 1] - box[:, 0]), whole)
    return x, checks


def _usable(x: np.ndarray, y: list) -> tuple[np.ndarray, list]:
    keep = [i for i, v in enumerate(y) if v is not None]
    return x[keep].reshape(len(keep), x.shape[1]), [y[i] for i in keep]


def _points(study: Sensitivity | None, runs: list[int], names: list[str]) -> np.ndarray:
    """The search-box points of some sensitivity runs, as rows."""
    return np.array([[study.runs[i][n] for n in names] for i in runs]).reshape(len(runs), len(names))


def _inside(point: dict, names: list[str], box: np.ndarray) -> bool:
    return all(low <= point[n] <= high for n, (low, high) in zip(names, box))


def _errors(targets: dict[str, float], responses: dict | None) -> dict | None:
    """Relative errors of responses against their targets (None: the runs failed)."""
    return None if responses is None else {r: responses[r] / t - 1 for r, t in targets.items()}


def _within(errors: dict | None, tolerance: float) -> bool:
    """The source's acceptance rule: every response within the tolerance of its target."""
    return errors is not None and all(abs(e) <= tolerance for e in errors.values())


def _distinct(a: np.ndarray, b: np.ndarray, box: np.ndarray) -> bool:
    """Two optima further apart than DISTINCT of the box (box-normalised distance)."""
    return float(np.linalg.norm((np.asarray(a) - b) / (box[:, 1] - box[:, 0]))) > DISTINCT
