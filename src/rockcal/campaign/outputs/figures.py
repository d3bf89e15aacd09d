"""The report's figures, each drawn from the campaign's result and the runs in the store into
its PNG file. A figure whose piece the result or the store lacks (no sensitivity study, a failed
validation run) is left out, and says why in a note; drawing one never raises.
"""

from __future__ import annotations

import logging
from functools import partial
from pathlib import Path
from typing import Callable

import numpy as np

import rockcal.plots as plots
from rockcal.campaign.runs.pool import specimen_of
from rockcal.campaign.procedure.result import CalibrationResult
from rockcal.campaign.runs.store import RunStore, StoredRun
from rockcal.errors import InputError
from rockcal.dem.laws import BROKEN_SHEAR, BROKEN_TENSION
from rockcal.labtests.bending import beam_of, crack_reach, rig_circles
from rockcal.labtests.kind import SeriesFigure
from rockcal.labtests.registry import lab_test
from rockcal.labtests.rig import rig_for

logger = logging.getLogger(__name__)


# Each figure draws into `path` and returns None, or returns why it was left out.

def _range_analysis(result: CalibrationResult, store: RunStore, path: Path) -> str | None:
    """Range R of each factor per response, from the sensitivity study."""
    sensitivity = result.sensitivity
    if sensitivity is None:
        return ("No sensitivity study in this campaign (no [sensitivity] section): the "
                "parameters to invert were named in [search].bounds.")
    R = {r: {f: e.R for f, e in effects.items()} for r, effects in sensitivity.responses.items()}
    note = f", runs at R_min {sensitivity.rmin_mm:g} mm" if sensitivity.rmin_mm else ""
    plots.range_bars(R, sensitivity.chosen, path, note)
    return None


def _paired(rows: list, response: str) -> tuple[list, list]:
    """DEM and surrogate values of `response` over (dem, predicted) dicts that both have it."""
    kept = [(d[response], p[response]) for d, p in rows if d and p and response in d and response in p]
    return [d for d, _ in kept], [p for _, p in kept]


def _parity(result: CalibrationResult, store: RunStore, path: Path) -> str | None:
    """Surrogate against DEM at the check points and the verification points."""
    check = result.surrogate_check
    rows = {"check points": list(zip(check.dem, check.predicted)),
            "verification points": [(it.verified, it.predicted) for it in result.iterations]}
    points = {r: {label: _paired(pairs, r) for label, pairs in rows.items() if _paired(pairs, r)[0]}
              for r in result.targets}
    points = {r: series for r, series in points.items() if series}
    if not points:
        return "No point has both a DEM value and a surrogate prediction."
    plots.parity(points, check.tolerance, path)
    return None


def _convergence(result: CalibrationResult, store: RunStore, path: Path) -> str | None:
    """ACO history of the search that gave the result (the best iteration, else the last)."""
    iterations = result.iterations
    if not iterations:
        return "No ant colony search was run."
    k = min(result.best_iteration, len(iterations) - 1)
    if not iterations[k].history_fun:
        return "The ant colony search kept no history."
    plots.aco_convergence(iterations[k].history_fun, iterations[k].history_x, result.parameters, path,
                          f"Ant colony search on the surrogate (loop iteration {k + 1})")
    return None


def _loop(result: CalibrationResult, store: RunStore, path: Path) -> str | None:
    """Relative errors of the verified responses per loop iteration."""
    iterations = result.iterations
    if not any(it.errors for it in iterations):
        return "No verification run succeeded."
    errors = {r: [(it.errors or {}).get(r) for it in iterations] for r in result.targets}
    plots.loop_errors(errors, result.tolerance, path)
    return None


def _trade_off(result: CalibrationResult, store: RunStore, path: Path) -> str | None:
    """The two most conflicting targets, when no verified point met them all."""
    if result.verdict is None:
        return "Every target met: no trade-off to show."
    t = result.verdict.trade_off
    best = [result.errors.get(r) for r in t.responses]  # a response the verification did not run: none
    plots.trade_off(t.errors, t.pareto, None if None in best else best, t.responses, result.tolerance, path)
    return None


def _missing(run: StoredRun | None, what: str) -> str | None:
    """Why a stored run cannot be drawn, or None when it can."""
    if run is None:
        return f"The {what} is not in the run store."
    if run.status != "ok" or run.curve is None:
        return f"The {what} {run.status}: {run.message}"
    return None


def _stress_strain(result: CalibrationResult, store: RunStore, path: Path) -> str | None:
    """The stress-strain curve at the identified parameters, and the measured one if given."""
    run = store.run(result.final_ucs_run_key)
    if (why := _missing(run, "UCS run at the identified parameters")) is not None:
        return why
    measured = result.measured_curve
    fit = result.curve_fit
    title = "UCS test at the identified parameters"
    if fit:
        title += f"\nRE {fit.RE:.3f}, CC {fit.CC:.3f}"
    plots.calibrated_curve(run.curve, None if measured is None else np.asarray(measured, dtype=float),
                           path, title, lateral_strains(run))
    return None


def _crack_stresses(result: CalibrationResult, store: RunStore, path: Path) -> str | None:
    """CI and CD on the UCS curve at the identified parameters, with the bonds broken."""
    run = store.run(result.final_ucs_run_key)
    if (why := _missing(run, "UCS run at the identified parameters")) is not None:
        return why
    if run.curve.shape[1] < 4:
        return "The UCS run at the identified parameters kept no count of broken bonds."
    plots.plot_crack_stresses(run.curve, path, "UCS test at the identified parameters", lateral_strains(run))
    return None


def lateral_strains(run: StoredRun) -> int:
    """The lateral strains of a stored compression run's volumetric strain, as its test read
    them (its specimen's rig: `rockcal.labtests.rig.Rig.lateral_strains`)."""
    return rig_for(specimen_of(run.kind, tuple(run.specimen.items()))).lateral_strains


def _series(keys: list[str], figure: SeriesFigure, title: str, result: CalibrationResult, store: RunStore,
            path: Path) -> str | None:
    """A figure of a series' runs at the identified parameters together (the envelope)."""
    runs = [store.run(key) for key in keys]
    for value, run in enumerate(runs):
        if (why := _missing(run, f"run {value + 1} of the series")) is not None:
            return why
    if len(runs) < figure.min_runs:
        return f"{figure.title}: needs {figure.min_runs} runs or more, the campaign has {len(runs)}."
    try:
        getattr(plots, figure.draw)([(run.responses, run.curve) for run in runs], path, title)
    except InputError as exc:  # the runs' peaks give no envelope: the figure's note, not the report's end
        return f"{figure.title}: no envelope through these runs ({exc.problem})."
    return None


def _cracks(key: str, what: str, store: RunStore, path: Path, title: Callable | None = None) -> str | None:
    """Broken bonds of a stored run over its undeformed specimen; `title(run, specimen)` gives
    the figure's title and the rig's circles (default: what it is, no rig)."""
    run = store.run(key)
    if (why := _missing(run, what)) is not None:
        return why
    if run.cracks is None:
        return f"The {what} kept no cracks."
    specimen = specimen_of(run.kind, tuple(run.specimen.items()))
    heading, rig = (f"{what[0].upper()}{what[1:]} —\nbroken bonds", ()) if title is None else title(run, specimen)
    plots.specimen_cracks(specimen, specimen.pos, by_mode(run.cracks), path, heading, rig, undeformed=title is None)
    return None


def by_mode(rows: np.ndarray) -> dict[str, np.ndarray]:
    """Stored crack rows (`pool.crack_rows`: the position's columns, then the mode) as the
    positions of each mode."""
    return {"tension": rows[rows[:, -1] == BROKEN_TENSION, :-1], "shear": rows[rows[:, -1] == BROKEN_SHEAR, :-1]}


def _ucs_cracks(result: CalibrationResult, store: RunStore, path: Path) -> str | None:
    """Crack pattern of the UCS specimen at the identified parameters."""
    return _cracks(result.final_ucs_run_key, "UCS run at the identified parameters", store, path)


def _bending_cracks(result: CalibrationResult, store: RunStore, path: Path) -> str | None:
    """Crack pattern of a notched beam at the identified parameters, with its pin and supports:
    the validation's first packing (run on until its crack has crossed the ligament) or, where
    K_IC is a target, the beam verified at the identified point."""
    validation = result.validation
    key = result.final_bending_run_key if validation is None else validation.run_key
    if key is None:
        return NO_VALIDATION

    def title(run: StoredRun, specimen) -> tuple[str, list]:
        beam = beam_of(run.specimen)
        seed = run.specimen["seed"]
        beams = 0 if validation is None else len(validation.seeds)
        which = f"packing {seed}" + ("" if beams == 0 else ", the validation's beam" if beams == 1
                                     else f", the first of the validation's {beams} beams")
        broken = run.cracks[:, :-1]  # the position's columns, less the mode
        peak = (f"{run.responses['P_max_kN_per_m']:.3g} kN/m" if "P_max_kN_per_m" in run.responses
                else f"{run.responses['P_max_kN']:.3g} kN")
        heading = (f"Notched beam at the identified parameters, {which}:\nK_IC "
                   f"{run.responses['K_IC_MPa_sqrt_m']:.3g} MPa·m^0.5, peak {peak}; "
                   f"the crack's tip at {crack_reach(beam, broken):.0%} of the ligament\n"
                   f"broken bonds on the undeformed beam, with the pin and the supports")
        return heading, rig_circles(beam, specimen.pos, specimen.radius)

    return _cracks(key, "notched-beam bending run", store, path, title)


def _bending_curve(result: CalibrationResult, store: RunStore, path: Path) -> str | None:
    """Load-displacement curve of the validation's bending test."""
    key = result.final_bending_run_key if result.validation is None else result.validation.run_key
    if key is None:
        return NO_VALIDATION
    run = store.run(key)
    if (why := _missing(run, "notched-beam bending run")) is not None:
        return why
    plots.load_displacement(run.curve, path, f"Three-point bending at the identified parameters, packing "
                                             f"{run.specimen['seed']}")
    return None


def _parameter_draws(result: CalibrationResult, store: RunStore, path: Path) -> str | None:
    u = result.uncertainty
    if u is None:
        return "No intervals in this campaign (no lab spread in [targets.ucs], or [uncertainty] off)."
    plots.parameter_draws(u.samples, result.parameters, result.bounds, result.identified, path)
    return None


def _meeting_set(result: CalibrationResult, store: RunStore, path: Path) -> str | None:
    found = result.identifiability
    if found is None:
        return "Not judged: no verified point was accepted."
    plots.parameter_draws(found.set_points, result.parameters, result.bounds, result.identified, path,
                          "Points whose predicted responses meet every target (on the surrogate)")
    return None


NO_VALIDATION = "No notched beam in this campaign (no [targets.bending])."
Figure = Callable[[CalibrationResult, RunStore, Path], "str | None"]
FIGURES: tuple[tuple[str, str, str, Figure], ...] = (
    ("Range analysis", "range_analysis.png",
     "R = max k<sub>i</sub> − min k<sub>i</sub> of each factor, per response.", _range_analysis),
    ("Surrogate parity", "surrogate_parity.png",
     "RBF surrogate prediction against the DEM at the check points and the verification points.",
     _parity),
    ("Ant colony convergence", "aco_convergence.png",
     "Best objective and best parameters per ACO iteration, in the search that gave the result.",
     _convergence),
    ("Verification loop", "loop_errors.png",
     "Relative error of the DEM responses at each optimum found on the surrogate.", _loop),
    ("Trade-off", "trade_off.png",
     "When no verified point meets every target: the relative errors of the two targets that "
     "conflict most at every DEM run of the search, and the runs no other beats in both.", _trade_off),
    ("Parameter intervals", "parameter_draws.png",
     "Each point: the parameters the surrogate gives for one target set drawn from the lab's "
     "spread and the model's scatter over packings; +: the identified point.", _parameter_draws),
    ("Identifiability", "meeting_set.png",
     "The points whose predicted responses meet every target (within its tolerance, or the lab's spread "
     "where wider, plus the surrogate's error at the verified points), pair by pair; +: the identified point. "
     "A parameter whose range over them reaches farther from the value found than [identifiability] "
     "pinned_within is not pinned by the sheet, unless its range read in the DEM is narrower.", _meeting_set),
    ("Stress–strain curve", "stress_strain.png",
     "UCS test at the identified parameters; the measured curve when one was given; CI (onset of "
     "cracking) and CD (reversal of the volumetric strain) dotted.", _stress_strain),
    ("Crack initiation and crack damage, UCS", "crack_stresses_ucs.png",
     "Up to the peak: the stress against the axial, lateral and volumetric strain (in 2D the "
     "areal strain), and the bonds broken and the crack volumetric strain against the stress; CI "
     "(onset of cracking, and by the crack volumetric strain) and CD (reversal of the volumetric "
     "strain) marked.", _crack_stresses),
    ("Crack pattern, UCS", "cracks_ucs.png",
     "Broken bonds: tension red, shear blue.", _ucs_cracks),
    ("Crack pattern, bending", "cracks_bending.png",
     "Broken bonds on the undeformed beam: tension red, shear blue; the pin and the supports dark grey.",
     _bending_cracks),
    ("Load–displacement, bending", "bending_curve.png",
     "Load per metre of thickness against the load-point displacement.", _bending_curve),
)


def figures_of(result: CalibrationResult) -> list[tuple[str, str, str, Figure]]:
    """FIGURES (a notched beam's only where the campaign has one), then the figures of
    each test run as a series at the identified parameters (a confined compression test's
    envelope and curves), as its registry entry declares them."""
    beam = "bending" in result.tests()
    figures = [f for f in FIGURES if beam or f[3] not in (_bending_cracks, _bending_curve)]
    extra = []
    for test, keys in (result.series_runs or {}).items():
        kind = lab_test(test)
        for figure in kind.series_figures:
            title = figure.heading(kind.title)
            extra.append((title, figure.file(test), figure.caption,
                          partial(_series, keys, figure, f"{title}\nat the identified parameters")))
    return [*figures, *extra]


def draw(name: str, figure: Figure, result: CalibrationResult, store: RunStore, path: Path) -> str | None:
    """Draw one figure; an error is logged and becomes the figure's note, except a file's
    (a full or read-only disk) or a damaged store's, which fails the report as a whole."""
    try:
        note = figure(result, store, path)
    except Exception as exc:  # a figure that cannot be drawn must not lose the report
        if isinstance(exc, InputError) or (isinstance(exc, OSError) and exc.errno is not None):
            raise
        logger.warning("report figure %s not drawn", name, exc_info=True)
        note = f"This figure could not be drawn ({type(exc).__name__}: {exc})."
    if note is not None:
        path.unlink(missing_ok=True)
    return note
