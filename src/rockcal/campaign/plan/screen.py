"""What a campaign will run and about how long it will take: shown before it starts.

A run's time is the mean of the test's runs on the same specimen that the store already holds;
without any, it is scaled from a granite UCS run of the campaign's dimension (2D's full-size
specimen, 3D's 25 x 50 mm cylinder) on a reference machine by this machine's speed against the
reference machine's (`engine_speed`: a one-second probe). Work per step grows with the grains,
and the steps of a test with its rows of grains (the loading speed is set per row), so a run's
time goes about as (grains x rows)^1.1, in 3D ^1.35 (`cost`); a full-size 2D bending run about
2.7 times slower than that (its steps grow with span² / height; a 3D beam's and disk's with
neither), a Brazilian disk between bearing strips about six times, and a flat-jointed
material's runs twice a parallel-bonded one's in 2D, 16 times in 3D
(`Material.slower_than_parallel_bond`).
A stage runs in rounds of one run per worker; the runs of a last, short round share the
cores (a run alone on two cores goes LONE_RUN_SPEED_UP times faster than one of two at once).
Beside other work (the cores it asks for during the probe, past the cores if need be) the runs
get their share of the cores, and a lone run no more cores than the others leave free. The
genesis of the packings the cache lacks comes first (`cost.genesis_s`, one packing per worker at
a time), and on an install's first run what the workers still compile; the main process's own
work, the searches for the parameters' intervals and the report, comes on top, with its share too.
"""

from __future__ import annotations

import os

import numpy as np

from rockcal.campaign.input.config import Campaign, SpecimenSettings
from rockcal.campaign.plan.cost import (FIRST_RUN_COMPILE_S, WORK_EXPONENT, genesis_s, relative_time, specimen_size,
                                       time_factor)
from rockcal.campaign.plan.engine_speed import busy_cores, probe, probe_ms_per_step
from rockcal.campaign.plan.route import route_of
from rockcal.campaign.runs.retries import holds, retry_line
from rockcal.campaign.procedure.pinning import BISECTIONS, IDENTIFIABILITY, further_reads_tests
from rockcal.campaign.procedure.points import packings_of
from rockcal.campaign.procedure.steps import (STEPS, VERIFICATION, planning_state, series_values,
                                              verified_at_most)
from rockcal.campaign.runs.spec import RunSpec
from rockcal.specimens.specimen import stored_packing
from rockcal.labtests.kind import all_settings
from rockcal.labtests.registry import PRIMARY_TEST, lab_test
from rockcal.materials import material
from rockcal.pfc.header import PFC4_NOT_IN_FISHTANK, takes_pfc4_contacts

# grains x rows of each dimension's reference UCS specimen (`cost.work`): 2D the full-size
# granite's 50 x 100 mm, 3D the 3D granite's Ø25 x 50 mm cylinder at R_min 0.8 mm
REFERENCE_WORK = {2: 12933 * 151, 3: 3016 * 23.58}
# 2D: the embedded granite campaign's mean full-size UCS run (one thread, two at a time on idle
# cores) where engine_speed.probe_ms_per_step() gives REFERENCE_PROBE_MS: scaled by this
# machine's probe, it gives this machine's run time before the store holds a run. That run's
# time per probe-ms differs between machines of the project's kind (an AMD EPYC's 117 s, an
# Intel Xeon's 148 s): this is their geometric mean, 12 % from either. 3D: the 3D granite's UCS
# run (docs/campaigns/granite-3d-all-targets.toml's cylinder, one thread, processor time) per
# ms of the probe's step in the same process, times REFERENCE_PROBE_MS
# (`NUMBA_NUM_THREADS=1 python benchmarks/plan_3d.py STORE --rmin-mm 0.8` on that campaign's store)
REFERENCE_RUN_S = {2: 86.8, 3: 25.5}
REFERENCE_PROBE_MS = 0.66
LONE_RUN_SPEED_UP = 1.4  # a run alone on 2 threads against two at a time: a UCS run 1.6x, a beam 1.4x
# the main process's own work, on one core of a machine of the project's kind (numpy and
# matplotlib, not the engine, so not scaled by the probe): one search on the surrogate for the
# parameters' intervals, and the start, the first screen and the report with its figures
DRAW_S = 0.08
DRAW_EVALUATIONS = 50 * 200  # the surrogate evaluations of the search DRAW_S was timed on (ants x iterations)
MAIN_PROCESS_S = 10.0


def planned_runs(campaign: Campaign) -> list[tuple[str, RunSpec]]:
    """(stage, run) of every run the procedure's steps ask for at the planning state, in the
    order they run (the verification loop: its first round's search optimum); a run asked for
    again is run once."""
    state, planned = planning_state(campaign), {}
    for step in STEPS:
        for spec in step.runs(state).specs:
            planned.setdefault(spec.key, (step.stage, spec))
    return list(planned.values())


def stages(campaign: Campaign, store=None) -> list[tuple[str, str, int]]:
    """(stage, test, runs) in the order they run, as the procedure's steps plan them; with a
    store, less the runs it holds."""
    counts: dict[tuple[str, str], int] = {}
    for stage, spec in planned_runs(campaign):
        counts[stage, spec.kind] = counts.get((stage, spec.kind), 0) + (store is None or not holds(store, spec))
    return [(stage, test, n) for (stage, test), n in counts.items()]


def specimens(campaign: Campaign) -> list[tuple[str, SpecimenSettings]]:
    """(test, specimen settings) of the specimens the planned runs are on, one per packing they
    are cut from."""
    found = {}
    for _, spec in planned_runs(campaign):
        settings = _settings_of(campaign, spec)
        found.setdefault(packing_file(spec.kind, settings) or spec.key, (spec.kind, settings))
    return list(found.values())


def _settings_of(campaign: Campaign, spec: RunSpec) -> SpecimenSettings:
    """The campaign's specimen settings with those a run is keyed by."""
    fields = SpecimenSettings.model_fields
    return campaign.specimen.model_copy(update={k: v for k, v in all_settings(dict(spec.specimen)).items()
                                                if k in fields})


def packing_file(test: str, settings: SpecimenSettings) -> str | None:
    """The file name of the packing a test's specimen is cut from (None: it makes none)."""
    return lab_test(test).packing_file(settings)


def specimens_to_make(campaign: Campaign) -> list[tuple[str, SpecimenSettings]]:
    """The campaign's specimens whose packing is neither in the cache nor shipped with rockcal:
    their genesis comes first."""
    return [(test, settings) for test, settings in specimens(campaign)
            if (name := packing_file(test, settings)) is not None and stored_packing(name) is None]


def genesis_times(campaign: Campaign) -> list[tuple[str, float]]:
    """The specimens whose packing must be made first (`specimens_to_make`): each in words, and
    its genesis on one thread of this machine, s."""
    probe_ms = probe_ms_per_step()
    return [(specimen_size(test, s)[0], genesis_s(test, s, probe_ms)) for test, s in specimens_to_make(campaign)]


def genesis_wall_s(campaign: Campaign, workers: int) -> float:
    """The genesis of the packings to make, s: one per worker at a time (the longest at least),
    beside the other work the probe saw."""
    times = [t for _, t in genesis_times(campaign)]
    if not times:
        return 0.0
    at_once = min(workers, len(times))
    return max(max(times), sum(times) / at_once) * _share(at_once)


def stage_runs(campaign: Campaign) -> dict[str, int]:
    """The forward runs of each stage, in the order they run."""
    runs: dict[str, int] = {}
    for stage, _, n in stages(campaign):
        runs[stage] = runs.get(stage, 0) + n
    return runs


def stored_runs_s(store, test: str, specimen: SpecimenSettings) -> list[float]:
    """Wall times of the finished runs of a test on this specimen in the store."""
    wanted = lab_test(test).key_settings(specimen)
    return [wall for settings, wall in store.wall_times(test) if settings == wanted]


def run_times(campaign: Campaign, store, sizes: dict) -> tuple[dict[str, float], bool]:
    """Expected time of one run of each test on one worker, and whether the UCS run's is
    measured (the mean of this store's runs) rather than scaled from the reference run."""
    s, d = campaign.specimen, campaign.specimen.dimensions
    measured = {test: stored_runs_s(store, test, s) for test in sizes}
    ucs_work = sizes[PRIMARY_TEST][2]
    ucs_s = float(np.mean(measured[PRIMARY_TEST])) if measured[PRIMARY_TEST] else \
        reference_run_s(d) * (ucs_work / REFERENCE_WORK[d]) ** WORK_EXPONENT[d] * \
        material(campaign.material.model).slower_in(d)
    times = {test: float(np.mean(measured[test])) if measured[test] else
             ucs_s * (size[2] / ucs_work) ** WORK_EXPONENT[d] * time_factor(test, s)
             for test, size in sizes.items()}
    return times, bool(measured[PRIMARY_TEST])


def machine_speed() -> float:
    """This machine's engine speed over the reference machine's (the probe's times inverted)."""
    return REFERENCE_PROBE_MS / probe_ms_per_step()


def reference_run_s(dimensions: int = 2) -> float:
    """The reference UCS run's expected time on this machine in `dimensions` (s)."""
    return REFERENCE_RUN_S[dimensions] / machine_speed()


def stage_rounds(runs: int, workers: int, cores: int | None = None) -> float:
    """A stage's time in runs of one thread two at a time: full rounds of one run per worker,
    then a last round whose runs take the cores left free (the pool shares them out as it goes;
    a single worker runs each run on all cores)."""
    cores = cores or os.cpu_count() or 1
    shared = 1 / LONE_RUN_SPEED_UP
    if workers == 1:
        return runs * (shared if cores >= 2 else 1.0)
    full, last = divmod(runs, workers)
    return full + (0.0 if not last else shared if cores // last >= 2 else 1.0)


def test_times(campaign: Campaign, store) -> dict[tuple[str, str], tuple[int, float]]:
    """(stage, test): the runs still to do and their time on one worker, s (a stage on coarser
    grains: its runs' time scaled from the campaign specimen's by their work)."""
    planned = stages(campaign, store)
    sizes = {test: specimen_size(test, campaign.specimen) for test in [PRIMARY_TEST, *(t for _, t, _ in planned)]}
    times, _ = run_times(campaign, store, sizes)
    specimen = {step.stage: step.specimen(campaign) for step in STEPS}
    return {(stage, test): (n, n * times[test] * (specimen_size(test, specimen[stage])[2] / sizes[test][2])
                            ** WORK_EXPONENT[campaign.specimen.dimensions])
            for stage, test, n in planned}


def stage_times(campaign: Campaign, store, workers: int) -> dict[str, tuple[int, float]]:
    """Each stage's runs still to do and their expected wall time (s): in rounds of one run per
    worker (`stage_rounds`) of the stage's mean run (a stage of several tests runs them as one
    batch)."""
    return _stage_walls(test_times(campaign, store), workers)


def _stage_walls(per_test: dict[tuple[str, str], tuple[int, float]], workers: int) -> dict[str, tuple[int, float]]:
    """`stage_times` from `test_times`."""
    work: dict[str, tuple[int, float]] = {}  # stage: runs, their one-worker seconds
    for (stage, _), (n, seconds) in per_test.items():
        runs, total = work.get(stage, (0, 0.0))
        work[stage] = (runs + n, total + seconds)
    cores, busy = busy_cores()
    free = max(1, round(cores - busy))
    shared = _share(min(workers, cores))
    return {stage: (runs, shared * stage_rounds(runs, workers, free) * seconds / runs if runs else 0.0)
            for stage, (runs, seconds) in work.items()}


def dry_run(campaign: Campaign, store, workers: int) -> dict:
    """The plan as data (`rockcal calibrate --dry-run --json`): per stage and per test, the runs
    still to do, the packings they are cut from and the expected wall time (a stage's time
    shared among its tests by their one-worker time), and the campaign's expected time."""
    packings: dict[tuple[str, str], set[str]] = {}
    for stage, spec in planned_runs(campaign):
        settings = _settings_of(campaign, spec)
        packings.setdefault((stage, spec.kind), set()).add(packing_file(spec.kind, settings))
    per_test = test_times(campaign, store)
    walls = _stage_walls(per_test, workers)
    plan: dict[str, dict] = {}
    for (stage, test), (runs, seconds) in per_test.items():
        stage_runs_s, stage_wall_s = walls[stage]
        one_worker_s = sum(s for (other, _), (_, s) in per_test.items() if other == stage)
        share = seconds / one_worker_s if one_worker_s else 0.0
        entry = plan.setdefault(stage, {"runs": stage_runs_s, "expected_s": round(stage_wall_s, 1), "tests": {}})
        entry["tests"][test] = {"runs": runs, "packings": len(packings[stage, test]),
                                "expected_s": round(share * stage_wall_s, 1)}
    genesis = genesis_wall_s(campaign, workers)
    return {"rock": campaign.rock.name, "workers": workers, "stages": plan,
            "runs": sum(runs for runs, _ in walls.values()),
            "specimens_to_make": len(genesis_times(campaign)), "genesis_expected_s": round(genesis, 1),
            "expected_s": round(compile_s(campaign) + genesis + sum(wall for _, wall in walls.values())
                                + _main_process_s(campaign), 1),
            "ucs_runs_time": round(ucs_runs_time(campaign, store), 1), "route": _route_data(campaign, store, workers),
            IDENTIFIABILITY: _identifiability_data(campaign)}


def _identifiability_data(campaign: Campaign) -> dict:
    """The identifiability stage's runs and their time in UCS runs', [planned, at most]."""
    runs, ucs_runs = identifiability_cost(campaign)
    return {"runs": list(runs), "ucs_runs_time": [round(t, 1) for t in ucs_runs]}


def ucs_runs_time(campaign: Campaign, store) -> float:
    """The runs still to do on one worker, in UCS runs' time: what a route costs, whatever the
    machine and the workers."""
    return sum(stage_ucs_runs_time(campaign, store).values())


def stage_ucs_runs_time(campaign: Campaign, store) -> dict[str, float]:
    """`ucs_runs_time` of each stage."""
    sizes = {test: specimen_size(test, campaign.specimen) for test in campaign.tests()}
    ucs_s = run_times(campaign, store, sizes)[0][PRIMARY_TEST]
    stages: dict[str, float] = {}
    for (stage, _), (_, seconds) in test_times(campaign, store).items():
        stages[stage] = stages.get(stage, 0.0) + seconds / ucs_s
    return stages


def _cost(campaign: Campaign, store) -> str:
    """A route's cost in UCS runs' time, as planned (the search's optimum verified) and, where
    a round verifies up to [acceptance] candidates, with the other optima's runs too: the
    routes may differ only there."""
    stages, candidates = stage_ucs_runs_time(campaign, store), verified_at_most(campaign)
    planned = sum(stages.values())
    if candidates == 1:
        return f"about {planned:.0f}"
    most = planned + (candidates - 1) * stages.get(VERIFICATION, 0.0)
    return f"about {planned:.0f}, {most:.0f} when a round verifies {candidates} optima"


def _route_data(campaign: Campaign, store, workers: int) -> dict | None:
    """The route the defaults took and the other route's cost (None: the defaults stayed)."""
    route = route_of(campaign)
    if route is None:
        return None
    return {"name": route.name, "why": route.why,
            "other": {"name": route.other_name, "expected_s": round(expected_s(route.other, store, workers), 1),
                      "ucs_runs_time": round(ucs_runs_time(route.other, store), 1)}}


def _share(processes: int) -> float:
    """How much slower `processes` CPU-bound processes run beside the other work seen by the
    probe than on cores of their own: each gets its share of the cores."""
    cores, busy = busy_cores()
    return max(1.0, (busy + processes) / cores)


def expected_s(campaign: Campaign, store, workers: int) -> float:
    """The campaign's expected wall time: what is left to compile on an install's first run,
    the genesis of the packings to make, its stages' runs and the main process's own work."""
    total = sum(seconds for _, seconds in stage_times(campaign, store, workers).values())
    return compile_s(campaign) + genesis_wall_s(campaign, workers) + total + _main_process_s(campaign)


def compile_s(campaign: Campaign) -> float:
    """What the workers still compile, s, where the probe found numba's cache without the
    engine (an install's first run); 0 on later runs."""
    if not probe().compiled_here:
        return 0.0
    return FIRST_RUN_COMPILE_S[campaign.specimen.dimensions] * probe_ms_per_step() * _share(1)


def _main_process_s(campaign: Campaign) -> float:
    """The main process's own work, s: the searches for the parameters' intervals, the start
    and the report."""
    search_s = DRAW_S * max(1.0, campaign.optimizer.ants * campaign.optimizer.iterations / DRAW_EVALUATIONS)
    draws = campaign.uncertainty.draws * search_s if campaign.wants_uncertainty() else 0.0
    return (draws + MAIN_PROCESS_S) * _share(1)


def describe(campaign: Campaign, store, workers: int | None) -> list[str]:
    """The lines of the first screen: specimens, stages and run counts, PFC 3.x/4.0's contacts
    (which no FISHTank file reproduces), expected time."""
    s = campaign.specimen
    sizes = {test: specimen_size(test, s) for test in campaign.tests()}
    runs: dict[str, int] = {}
    for _, test, n in stages(campaign, store):
        runs[test] = runs.get(test, 0) + n
    titles = [_runs_text(campaign, test) for test in campaign.target_sections()]
    lines = [
        "specimens: " + "; ".join(f"{text}, about {grains} grains" for text, grains, _ in sizes.values())
        + f" (R {s.rmin_mm:g} to {s.rmin_mm * s.radius_ratio:.3g} mm)",
        "stages: " + _stages_text(campaign)
        + (f"; each parameter set runs {' and '.join(titles)}" if titles != [lab_test(PRIMARY_TEST).title] else ""),
        f"runs of this campaign already in the store: {sum(stage_runs(campaign).values()) - sum(runs.values())} "
        "(a run done is never run again)",
    ]
    route = route_of(campaign)
    if route is not None:
        lines.append(f"route: {route.name}: {route.why}")
    retry = retry_line(store)
    if retry:
        lines.append(retry)
    if takes_pfc4_contacts(s, campaign.material.model):
        lines.append(f"contacts: PFC 3.x/4.0's (contact_stiffness = \"pfc4\", kn = t E_c whatever the radii); "
                     + PFC4_NOT_IN_FISHTANK)
    if workers:
        times, measured = run_times(campaign, store, sizes)
        reference = "3D" if s.dimensions == 3 else "full-size"
        basis = ("the mean of this store's UCS runs" if measured else
                 f"scaled from the {reference} granite run by this machine's engine speed, "
                 f"{machine_speed():.2g}x the reference machine's")
        cores, busy = busy_cores()
        if busy >= 0.5:
            basis += f"; other work asks for {busy:.1f} cores of this machine's {cores}"
        lines.append(f"expected: about {_duration(expected_s(campaign, store, workers))} on "
                     f"{workers} worker{'s' if workers > 1 else ''}: " + _genesis(campaign, workers)
                     + f"the {' and '.join(f'{n} {lab_test(t).title}' for t, n in runs.items())} runs "
                     f"still to do ({_duration(times[PRIMARY_TEST])} per UCS run on one worker: {basis})")
        if route is not None:
            lines.append(f"cost: the runs' time is {_cost(campaign, store)} UCS runs' on this "
                         f"route; {route.other_name}: {_cost(route.other, store)} "
                         f"({_duration(expected_s(route.other, store, workers))} here)")
    return lines


def _stages_text(campaign: Campaign) -> str:
    """The stages and their runs as planned, and what may add to them: a verification round
    plans the search's optimum (the point it always verifies); it verifies up to [acceptance]
    candidates - 1 more where the surrogate has other distinct optima, and more rounds follow
    while no verified point passes; the identifiability stage may read more ranges."""
    runs, candidates = stage_runs(campaign), verified_at_most(campaign)
    listed = ", ".join(f"{name} {n}" + _resolution(campaign, name)
                       + (" a round" + _other_optima(n, candidates) if name == VERIFICATION else "")
                       + (_identifiability_text(campaign) if name == IDENTIFIABILITY else "")
                       for name, n in runs.items())
    point = "run" if runs.get(VERIFICATION) == 1 else "runs"
    others = "" if candidates == 1 else f"a second optimum's {point} and " if candidates == 2 else \
        f"other optima's {point} and "
    return (f"{listed}: {sum(runs.values())} runs, plus {others}more rounds if needed "
            f"(at most {campaign.acceptance.max_dem_runs} UCS runs)")


def identifiability_cost(campaign: Campaign) -> tuple[tuple[int, int], tuple[float, float]]:
    """The identifiability stage's DEM runs, as planned (one range read: each end run
    1 + `pinning.BISECTIONS` times) and at most (every searched parameter's range read), and
    their time in UCS runs' (`cost.relative_time`); a sheet that pins every parameter runs none."""
    planned = [spec.kind for stage, spec in planned_runs(campaign) if stage == IDENTIFIABILITY]
    most = planned + further_reads_tests(campaign, len(planning_state(campaign).names)) if planned else []
    return (len(planned), len(most)), tuple(sum(relative_time(campaign, t) for t in tests)
                                            for tests in (planned, most))


def _identifiability_text(campaign: Campaign) -> str:
    """The identifiability stage's runs as a range, in words."""
    (planned, most), (planned_time, most_time) = identifiability_cost(campaign)
    return (f" to {most} (about {planned_time:.0f} to {most_time:.0f} UCS runs' time: each range it reads in the "
            f"DEM runs each end {1 + BISECTIONS} times, the widest range not pinned first, the next where the DEM "
            "pins it, every searched parameter's at most; none where the sheet pins every parameter)")


def _other_optima(point_runs: int, candidates: int) -> str:
    """A verification round's runs where the surrogate has optima other than the search's."""
    if candidates == 1:
        return ""
    if candidates == 2:
        return f" ({2 * point_runs} when the surrogate has a second optimum)"
    return f" (up to {candidates * point_runs} when the surrogate has other optima)"


def _runs_text(campaign: Campaign, test: str) -> str:
    """A test's runs at each parameter set in words: its title, and the values of its series."""
    kind, values, n = lab_test(test), series_values(campaign, test), packings_of(campaign, test)
    text = kind.title if not values else (f"{kind.title} at {len(values)} values of {kind.series.name} "
                                          f"({', '.join(f'{v:g}' for v in values)} {kind.series.unit})")
    return text + (f" (verified on {n} packings, their mean; the surrogate's runs on one)" if n > 1 else "")


def _genesis(campaign: Campaign, workers: int) -> str:
    """The expected time's first part in words: the genesis of the packings not yet made, or
    that every one is ready."""
    compiling = (f"first compiling the engine (this install's first run), about {_duration(compile_s(campaign))}, "
                 if compile_s(campaign) else "")
    made = genesis_times(campaign)
    if not made:
        return compiling + "every specimen is ready (cached, or shipped with rockcal); "
    texts = sorted({text for text, _ in made})
    return (compiling + f"{'then' if compiling else 'first'} the genesis of {len(made)} "
            f"specimen{'s' if len(made) > 1 else ''} ({', '.join(texts)}), "
            f"about {_duration(genesis_wall_s(campaign, workers))}, then ")


def _resolution(campaign: Campaign, stage: str) -> str:
    """A stage's own R_min, where it differs from the campaign's."""
    own = next(step.specimen(campaign).rmin_mm for step in STEPS if step.stage == stage)
    return f" (R_min {own:g} mm)" if own != campaign.specimen.rmin_mm else ""


def _duration(seconds: float) -> str:
    if seconds < 90:
        return f"{seconds:.0f} s"
    minutes = seconds / 60
    return f"{minutes:.0f} min" if minutes < 90 else f"{minutes / 60:.1f} h"
