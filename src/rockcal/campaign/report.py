"""The calibration report: one self-contained HTML page (figures embedded as base64 PNG, also
written next to it) made from the campaign record and the runs in the store.

A piece the record lacks (no sensitivity study, a failed validation run) leaves its figure out
with a note; writing the report never fails because of it.
"""

from __future__ import annotations

import base64
import html
import logging
from pathlib import Path
from typing import Callable

import numpy as np

from rockcal import plots
from rockcal.campaign.forward import specimen_of
from rockcal.campaign.store import RunStore, StoredRun
from rockcal.dem.laws import BROKEN_SHEAR, BROKEN_TENSION

logger = logging.getLogger(__name__)

REPORT_NAME = "report.html"


def stored_run(store: RunStore, key: str | None) -> StoredRun | None:
    """The run stored under `key`, or None when there is no key or no such run."""
    return None if key is None else store.run(key)


# -- figures: each draws into `path` and returns None, or returns why it was left out --------

def _range_analysis(record: dict, store: RunStore, path: Path) -> str | None:
    """Range R of each factor per response, from the sensitivity study."""
    sensitivity = record.get("sensitivity")
    if not sensitivity:
        return ("No sensitivity study in this campaign (no [sensitivity] section): the "
                "parameters to invert were named in [search].bounds.")
    R = {r: {f: e["R"] for f, e in effects.items()} for r, effects in sensitivity["responses"].items()}
    plots.range_bars(R, sensitivity.get("chosen") or [], path)
    return None


def _paired(rows: list, response: str) -> tuple[list, list]:
    """DEM and surrogate values of `response` over (dem, predicted) dicts that both have it."""
    kept = [(d[response], p[response]) for d, p in rows if d and p and response in d and response in p]
    return [d for d, _ in kept], [p for _, p in kept]


def _parity(record: dict, store: RunStore, path: Path) -> str | None:
    """Surrogate against DEM at the check points and the verification points."""
    check = record.get("surrogate_check") or {}
    rows = {"check points": list(zip(check.get("dem") or [], check.get("predicted") or [])),
            "verification points": [(it.get("verified"), it.get("predicted"))
                                    for it in record.get("iterations") or []]}
    points = {r: {label: _paired(pairs, r) for label, pairs in rows.items() if _paired(pairs, r)[0]}
              for r in record.get("targets", {})}
    points = {r: series for r, series in points.items() if series}
    if not points:
        return "No point has both a DEM value and a surrogate prediction."
    plots.parity(points, check.get("tolerance", record.get("tolerance", 0.05)), path)
    return None


def _convergence(record: dict, store: RunStore, path: Path) -> str | None:
    """ACO history of the search that gave the result (the best iteration, else the last)."""
    iterations = record.get("iterations") or []
    if not iterations:
        return "No ant colony search was run."
    best = record.get("best_iteration")
    k = best if best is not None and best < len(iterations) else len(iterations) - 1
    if not iterations[k].get("history_fun"):
        return "The ant colony search kept no history."
    plots.aco_convergence(iterations[k]["history_fun"], iterations[k]["history_x"],
                          record.get("parameters", []), path,
                          f"Ant colony search on the surrogate (loop iteration {k + 1})")
    return None


def _loop(record: dict, store: RunStore, path: Path) -> str | None:
    """Relative errors of the verified responses per loop iteration."""
    iterations = record.get("iterations") or []
    if not any(it.get("errors") for it in iterations):
        return "No verification run succeeded."
    errors = {r: [(it.get("errors") or {}).get(r) for it in iterations] for r in record.get("targets", {})}
    plots.loop_errors(errors, record.get("tolerance", 0.05), path)
    return None


def _missing(run: StoredRun | None, what: str) -> str | None:
    """Why a stored run cannot be drawn, or None when it can."""
    if run is None:
        return f"The {what} is not in the run store."
    if run.status != "ok" or run.curve is None:
        return f"The {what} {run.status}: {run.message}"
    return None


def _stress_strain(record: dict, store: RunStore, path: Path) -> str | None:
    """The stress-strain curve at the identified parameters, and the measured one if given."""
    run = stored_run(store, record.get("final_ucs_run_key"))
    if (why := _missing(run, "UCS run at the identified parameters")) is not None:
        return why
    measured = record.get("measured_curve")
    fit = record.get("curve_fit")
    title = "UCS test at the identified parameters"
    if fit:
        title += f"\nRE {fit['RE']:.3f}, CC {fit['CC']:.3f}"
    plots.calibrated_curve(run.curve, None if measured is None else np.asarray(measured, dtype=float),
                           path, title)
    return None


def _cracks(key: str | None, what: str, store: RunStore, path: Path) -> str | None:
    """Broken bonds of a stored run over its undeformed specimen."""
    run = stored_run(store, key)
    if (why := _missing(run, what)) is not None:
        return why
    if run.cracks is None:
        return f"The {what} kept no cracks."
    specimen = specimen_of(run.kind, tuple(run.specimen.items()))
    modes = {"tension": run.cracks[run.cracks[:, 2] == BROKEN_TENSION, :2],
             "shear": run.cracks[run.cracks[:, 2] == BROKEN_SHEAR, :2]}
    plots.crack_pattern(specimen.pos, specimen.radius, modes, path,
                        f"{what[0].upper()}{what[1:]} —\nbroken bonds (undeformed specimen)")
    return None


def _ucs_cracks(record: dict, store: RunStore, path: Path) -> str | None:
    """Crack pattern of the UCS specimen at the identified parameters."""
    return _cracks(record.get("final_ucs_run_key"), "UCS run at the identified parameters", store, path)


def _bending_cracks(record: dict, store: RunStore, path: Path) -> str | None:
    """Crack pattern of the notched beam of the validation."""
    validation = record.get("validation")
    if validation is None:
        return NO_VALIDATION
    return _cracks(validation.get("run_key"), "notched-beam bending run", store, path)


def _bending_curve(record: dict, store: RunStore, path: Path) -> str | None:
    """Load-displacement curve of the validation's bending test."""
    validation = record.get("validation")
    if validation is None:
        return NO_VALIDATION
    run = stored_run(store, validation.get("run_key"))
    if (why := _missing(run, "notched-beam bending run")) is not None:
        return why
    plots.load_displacement(run.curve, path, "Three-point bending at the identified parameters")
    return None


def _parameter_draws(record: dict, store: RunStore, path: Path) -> str | None:
    u = record.get("uncertainty")
    if not u:
        return "No intervals in this campaign (no lab spread in [targets.ucs], or [uncertainty] off)."
    plots.parameter_draws(u["samples"], record["parameters"], record["bounds"], record["identified"], path)
    return None


NO_VALIDATION = "No bending validation in this campaign (no [targets.bending])."
Figure = Callable[[dict, RunStore, Path], "str | None"]
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
    ("Parameter intervals", "parameter_draws.png",
     "Each point: the parameters the surrogate gives for one target set drawn from the lab's "
     "spread and the model's scatter over packings; +: the identified point.", _parameter_draws),
    ("Stress–strain curve", "stress_strain.png",
     "UCS test at the identified parameters; the measured curve when one was given.", _stress_strain),
    ("Crack pattern, UCS", "cracks_ucs.png",
     "Broken bonds: tension red, shear blue.", _ucs_cracks),
    ("Crack pattern, bending", "cracks_bending.png",
     "Broken bonds: tension red, shear blue.", _bending_cracks),
    ("Load–displacement, bending", "bending_curve.png",
     "Load per metre of thickness against the load-point displacement.", _bending_curve),
)


def _draw(name: str, draw: Figure, record: dict, store: RunStore, path: Path) -> str | None:
    """Draw one figure; an error is logged and becomes the figure's note."""
    try:
        note = draw(record, store, path)
    except Exception as exc:  # a figure that cannot be drawn must not lose the report
        logger.warning("report figure %s not drawn", name, exc_info=True)
        note = f"This figure could not be drawn ({type(exc).__name__}: {exc})."
    if note is not None:
        path.unlink(missing_ok=True)
    return note


# -- HTML --------------------------------------------------------------------------------------

def _num(value) -> str:
    """A number to 4 significant digits, a dash for none."""
    return "—" if value is None else f"{value:.4g}"


def _pct(value) -> str:
    """A relative error in per cent with its sign, a dash for none."""
    return "—" if value is None else f"{100 * value:+.1f} %"


def _table(header: list[str] | None, rows: list[list]) -> str:
    """An HTML table; cells are escaped."""
    head = "" if header is None else "<tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in header) + "</tr>"
    body = "".join("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in row) + "</tr>"
                   for row in rows)
    return f"<table>{head}{body}</table>"


def _overview(record: dict) -> str:
    """The campaign at a glance: rock, verdict, objective, runs, surrogate check, curve fit."""
    tolerance = record.get("tolerance", 0.05)
    accepted = record.get("accepted")
    best = record.get("best_iteration")
    verdict = (f"accepted: every response within ±{100 * tolerance:g} %" if accepted else
               f"not accepted: no verification within ±{100 * tolerance:g} %; the closest "
               f"(loop iteration {_num(None if best is None else best + 1)}) is reported")
    rows = [["rock", record.get("rock", "—")], ["result", verdict],
            ["objective", record.get("objective", "—")],
            ["DEM runs used (UCS)", record.get("dem_runs", "—")],
            ["surrogate check", _check_text(record.get("surrogate_check") or {})]]
    fit = record.get("curve_fit")
    if fit:
        rows.append(["stress–strain fit", f"RE {fit['RE']:.3f}, CC {fit['CC']:.3f}"])
    specimen = record.get("specimen") or (record.get("campaign") or {}).get("specimen")
    if specimen:
        rows.append(["specimens", _specimen_text(specimen)])
    return _table(None, rows)


def _specimen_text(s: dict) -> str:
    """The virtual specimens in a line (mm)."""
    try:
        return (f"UCS {s['width_mm']:g} × {s['height_mm']:g} mm; beam {s['beam_length_mm']:g} × "
                f"{s['beam_height_mm']:g} mm, notch {s['notch_mm']:g} × {s['notch_width_mm']:g} mm, "
                f"span {s['span_mm']:g} mm; radii {s['rmin_mm']:g} to "
                f"{s['rmin_mm'] * s['radius_ratio']:.3g} mm, packing seed {s['seed']}")
    except (KeyError, TypeError, ValueError):
        return ", ".join(f"{k} {v}" for k, v in s.items())


def _check_text(check: dict) -> str:
    """Largest relative error of the surrogate at the check points, per response."""
    errors = check.get("max_relative_error")
    if errors is None:
        return "not checked (no check run succeeded)"
    if not isinstance(errors, dict):
        errors = {"all responses": errors}
    listed = ", ".join(f"{r} {100 * e:.1f} %" for r, e in errors.items())
    trusted = "trusted" if check.get("trusted") else "NOT trusted"
    return f"largest relative error {listed}: {trusted} (tolerance {100 * check.get('tolerance', 0.05):g} %)"


def _responses(record: dict) -> str:
    """Targets, surrogate and verified DEM responses, and their errors against the tolerance."""
    tolerance = record.get("tolerance", 0.05)
    verified = record.get("verified") or {}
    errors = record.get("errors") or {}
    iterations = record.get("iterations") or []
    best = record.get("best_iteration")
    predicted = iterations[best].get("predicted", {}) if best is not None and best < len(iterations) else {}
    rows = [[r, _num(t), _num(predicted.get(r)), _num(verified.get(r)), _pct(errors.get(r)),
             "—" if errors.get(r) is None else ("yes" if abs(errors[r]) <= tolerance else "no")]
            for r, t in record.get("targets", {}).items()]
    return _table(["response", "target", "surrogate", "DEM (verified)", "relative error",
                   f"within ±{100 * tolerance:g} %"], rows)


def _parameters(record: dict) -> str:
    """The identified parameters with their search ranges, then every micro-parameter."""
    bounds = record.get("bounds", {})
    intervals = (record.get("uncertainty") or {}).get("intervals", {})
    header = ["parameter", "identified", "search range"]
    if intervals:
        header += ["5 %", "95 %", "pinned down by the data"]
    rows = []
    for n, v in record.get("identified", {}).items():
        row = [n, _num(v), " – ".join(map(_num, bounds.get(n, [])))]
        if n in intervals:
            i = intervals[n]
            row += [_num(i["p5"]), _num(i["p95"]), "yes" if i["pinned"] else
                    f"no ({100 * i['at_bound']:.0f} % of draws at a bound)"]
        rows.append(row)
    table = _table(header, rows)
    if intervals:
        u = record["uncertainty"]
        table += "<p>" + html.escape(
            f"Intervals: {u['draws']} target sets drawn from the lab spread "
            f"({', '.join(f'{r} {s}' for r, s in u['spread'].items()) or 'none'}) and the model's "
            f"scatter over {len(u['packing_responses'])} packings (relative sd "
            f"{', '.join(f'{r} {100 * s:.1f} %' for r, s in u['scatter'].items())}), each solved "
            "on the surrogate.") + "</p>"
    everything = record.get("identified_params")
    if everything:
        table += "<p>All micro-parameters: " + html.escape(
            ", ".join(f"{k} = {_num(v)}" for k, v in everything.items())) + "</p>"
    return table


def _validation(record: dict) -> str:
    """Simulated K_IC against the lab's, or why there is none; the P_max/K_IC warning."""
    v = record.get("validation")
    if v is None:
        return "<p class='note'>No bending validation in this campaign.</p>"
    if v.get("status") != "ok":
        text = f"<p class='note'>The bending run {html.escape(str(v.get('status')))}: " \
               f"{html.escape(v.get('message') or '')}</p>"
    else:
        seeds = v.get("ok_seeds") or []
        text = _table(["K_IC lab (MPa·m^0.5)", "K_IC simulated (MPa·m^0.5)", "error",
                       "P_max (kN/m)", "displacement at peak (mm)", "packing seeds"],
                      [[_num(v.get("lab_K_IC_MPa_sqrt_m")),
                        f"{_num(v.get('K_IC_MPa_sqrt_m'))} ± {_num(v.get('K_IC_MPa_sqrt_m_std'))}",
                        _pct(v.get("K_IC_error")), _num(v.get("P_max_kN_per_m")),
                        _num(v.get("displacement_at_peak_mm")),
                        ", ".join(f"{s}: {_num(k)}" for s, k in zip(seeds, v.get("K_IC_per_seed", [])))]])
    if v.get("warning"):
        text += f"<p class='warn'>{html.escape(v['warning'])}</p>"
    return text


def _failed(record: dict) -> str:
    """The failed and timed-out forward runs, by stage."""
    failed = record.get("failed_runs") or []
    if not failed:
        return ""
    return "<h3>Failed or timed-out runs</h3>" + _table(
        ["stage", "message"], [[f.get("stage", "—"), f.get("message", "")] for f in failed])


def _figure(title: str, caption: str, path: Path, note: str | None) -> str:
    """A figure section: the embedded PNG, or the note saying why it is left out."""
    if note is not None:
        return f"<h2>{html.escape(title)}</h2><p class='note'>{html.escape(note)}</p>"
    data = base64.b64encode(path.read_bytes()).decode()
    return (f"<h2>{html.escape(title)}</h2><figure><img alt='{html.escape(title)}' "
            f"src='data:image/png;base64,{data}'><figcaption>{caption}</figcaption></figure>")


CSS = """body{font-family:sans-serif;max-width:960px;margin:2em auto;color:#222}
table{border-collapse:collapse;margin:0.5em 0}td,th{border:1px solid #bbb;padding:3px 8px;
text-align:left;vertical-align:top}th{background:#eee}img{max-width:100%}
.note{color:#666;font-style:italic}.warn{color:#a60}figcaption{color:#555;font-size:90%}"""


def write_report(record: dict, store: RunStore, out: Path) -> Path:
    """Write the figures and OUT/report.html of a calibration record; returns the HTML path."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    figures = "\n".join(_figure(title, caption, out / name, _draw(name, draw, record, store, out / name))
                      for title, name, caption, draw in FIGURES)
    rock = html.escape(str(record.get("rock", "rock")))
    page = (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>rockcal calibration — {rock}"
            f"</title><style>{CSS}</style></head><body><h1>Calibration of {rock}</h1>"
            f"\n<h2>Summary</h2>{_overview(record)}\n<h3>Responses</h3>{_responses(record)}"
            f"\n<h3>Identified parameters</h3>{_parameters(record)}"
            f"\n<h3>Validation: notched-beam bending</h3>{_validation(record)}\n{_failed(record)}"
            f"\n{figures}\n</body></html>\n")
    path = out / REPORT_NAME
    path.write_text(page, encoding="utf-8")
    return path
