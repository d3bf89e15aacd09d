"""The calibration report: one self-contained HTML page (figures embedded as base64 PNG, also
written next to it, `rockcal.campaign.outputs.figures`) made from the campaign's result and the runs in
the store.

A piece the result lacks (no sensitivity study, a failed validation run) leaves its figure out
with a note; writing the report never fails because of it.
"""

from __future__ import annotations

import base64
import html
import math
from pathlib import Path

from rockcal.campaign.input.config import SpecimenSettings
from rockcal.campaign.outputs.figures import draw, figures_of
from rockcal.campaign.procedure.result import CalibrationResult, SurrogateCheck
from rockcal.campaign.runs.store import RunStore
from rockcal.campaign.procedure.pinning import LAB_WORK
from rockcal.inverse.identifiability import largest_error
from rockcal.labtests.registry import PRIMARY_TEST, lab_test
from rockcal.output_files import write_atomic

REPORT_NAME = "report.html"


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


def _overview(result: CalibrationResult) -> str:
    """The campaign at a glance: rock, verdict, objective, runs, surrogate check, curve fit."""
    tolerance = result.tolerance
    verdict = (f"accepted: every response within ±{100 * tolerance:g} %" if result.accepted else
               f"not accepted: no verification within ±{100 * tolerance:g} %; the closest "
               f"(loop iteration {_num(result.best_iteration + 1)}) is reported")
    titles = [lab_test(test).title for test in result.responses_by_test()]
    runs = "DEM runs used (UCS)" if titles == ["UCS"] else \
        f"DEM runs used (parameter sets, each run in {' and '.join(titles)})"
    rows = [["rock", result.rock], ["result", verdict]]
    if result.verdict is not None:
        rows.append(["why", result.verdict.text])
    rows += [["warning", warning] for warning in result.at_bounds or []]
    rows += [["objective", result.objective],
            [runs, result.dem_runs],
            ["surrogate check", _check_text(result.surrogate_check)]]
    if result.coarse_samples is not None:
        rows.append(["multi-fidelity", f"{len(result.coarse_samples.x)} coarse runs train the surrogate, "
                     f"{len(result.samples.x)} full-resolution samples correct it"])
    fit = result.curve_fit
    if fit:
        rows.append(["stress–strain fit", f"RE {fit.RE:.3f}, CC {fit.CC:.3f}"])
    rows += [["model", MODELS[result.specimen.dimensions]],
             ["specimens", _specimen_text(result.specimen, result.tests())]]
    return _table(None, rows)


MODELS = {2: "2D (PFC2D): bonded disks in a slab of unit thickness", 3: "3D (PFC3D): bonded spheres"}


def _specimen_text(s: SpecimenSettings, tests: list[str]) -> str:
    """The specimen of each test the campaign ran, in a line (mm; each test's outline, a
    notched beam's notch and span), then the particles' radii and the packing seed."""
    texts = []
    for test in tests:
        kind = lab_test(test)
        text = kind.outline(kind.settings_of(s)).text
        if test == "bending":
            text += f", notch {s.notch_mm:g} × {s.notch_width_mm:g} mm, span {s.span_mm:g} mm"
        texts.append(text)
    return "; ".join([*texts, f"radii {s.rmin_mm:g} to {s.rmin_mm * s.radius_ratio:.3g} mm, packing seed {s.seed}"])


def _check_text(check: SurrogateCheck) -> str:
    """Largest relative error of the surrogate at the check points, per response."""
    errors = check.max_relative_error
    if errors is None:
        return "not checked (no check run succeeded)"
    listed = ", ".join(f"{r} {100 * e:.1f} %" for r, e in errors.items())
    trusted = "trusted" if check.trusted else "NOT trusted"
    return f"largest relative error {listed}: {trusted} (tolerance {100 * check.tolerance:g} %)"


def _responses(result: CalibrationResult) -> str:
    """Each test's targets, surrogate and verified DEM responses, their errors against the
    tolerance, and their weights when some are not 1."""
    tolerance, verified, errors = result.tolerance, result.verified, result.errors
    iterations, best, weights = result.iterations, result.best_iteration, result.weights
    predicted = iterations[best].predicted if best < len(iterations) else {}
    rows = []
    for test, names in result.responses_by_test().items():
        for r in names:
            rows.append([lab_test(test).title, r, _num(result.targets[r]), _num(predicted.get(r)),
                         _num(verified.get(r)), _pct(errors.get(r)),
                         "—" if errors.get(r) is None else ("yes" if abs(errors[r]) <= tolerance else "no")]
                        + ([_num(weights.get(r, 1.0))] if weights else []))
    return _table(["test", "response", "target", "surrogate", "DEM (verified)", "relative error",
                   f"within ±{100 * tolerance:g} %"] + (["weight"] if weights else []), rows)


def _parameters(result: CalibrationResult) -> str:
    """The identified parameters with their search ranges, then every micro-parameter."""
    u = result.uncertainty
    intervals = {} if u is None else u.intervals
    header = ["parameter", "identified", "search range"]
    if intervals:
        header += ["5 %", "95 %", "pinned down by the data"]
    rows = []
    for n, v in result.identified.items():
        row = [n, _num(v), " – ".join(map(_num, result.bounds.get(n, [])))]
        if n in intervals:
            i = intervals[n]
            row += [_num(i.p5), _num(i.p95), "yes" if i.pinned else
                    f"no ({100 * i.at_bound:.0f} % of draws at a bound)"]
        rows.append(row)
    table = _table(header, rows)
    if intervals:
        table += "<p>" + html.escape(
            f"Intervals: {u.draws} target sets drawn from the lab spread "
            f"({', '.join(f'{r} {s}' for r, s in u.spread.items()) or 'none'}) and the model's "
            f"scatter over {len(u.packing_responses)} packings (relative sd "
            f"{', '.join(f'{r} {100 * s:.1f} %' for r, s in u.scatter.items())}), each solved "
            "on the surrogate.") + "</p>"
    table += "<p>All micro-parameters: " + html.escape(
        ", ".join(f"{k} = {_num(v)}" for k, v in result.identified_params.items())) + "</p>"
    return table


def _largest_error(low: float, high: float, found: float) -> str:
    """The value found's largest relative error against a point of its range, in per cent."""
    error = largest_error(low, high, found)
    return f"{100 * error:.1f} %" if math.isfinite(error) else "the range reaches 0"


def _pinned_rule(found) -> str:
    """The verdict's rule in a column's head: the value found's largest error, and the share of
    the box where that is a condition (a record made before the error's: the share alone)."""
    rule = [] if found.pinned_within is None else [f"within {100 * found.pinned_within:g} %"]
    return ", ".join(rule + ([f"≤ {100 * found.pinned_share:g} % of the box"] if found.pinned_share < 1 else []))


def _identifiability(result: CalibrationResult) -> str:
    """Which parameters the sheet pins, the DEM runs at the ends of the range read there, and
    the tests it lacks ranked by how much they vary between the ends kept (none when the
    campaign was not accepted)."""
    found = result.identifiability
    if found is None:
        return ""
    basis = ("Ranges: over the points whose responses the surrogate predicts in these bands: "
             + ", ".join(f"{r} {_num(low)}–{_num(high)}" for r, (low, high) in found.bands.items())
             + " (each target's tolerance, or the lab's spread where wider, plus the surrogate's error at the "
             "verified points: " + ", ".join(f"{r} {100 * e:.1f} %" for r, e in found.surrogate_error.items())
             + "); a range read in the DEM reaches from the points its runs found meeting the sheet, and those "
             "missing it within the surrogate's error, out to the nearest runs beyond that miss it by more, or the "
             "box's bounds: the set's edges along the read lie between.")
    text = f"<h3>Identifiability</h3><p>{html.escape(found.text[0].upper() + found.text[1:])}</p>"
    text += _table(["parameter", "low", "high", "largest error of the value found", "share of its box",
                    f"pinned ({_pinned_rule(found)})", "read in the DEM"],
                   [[n, _num(r.low), _num(r.high), _largest_error(r.low, r.high, result.identified[n]),
                     f"{100 * r.share:.0f} %", "yes" if r.pinned else "no",
                     "—" if r.verified_ends is None else f"ends met: {', '.join(r.verified_ends) or 'none'}"
                     + ("" if r.met_low is None else f"; met over {_num(r.met_low)}–{_num(r.met_high)}")]
                    for n, r in found.ranges.items()])
    text += f"<p>{html.escape(basis)}</p>"
    if found.end_runs:
        targets = list(found.bands)
        text += _table(["end", *result.parameters, *targets, "met the sheet"],
                       [[r.side, *(_num(r.point[n]) for n in result.parameters),
                         *(_pct(None if r.errors is None else r.errors[t]) for t in targets), "yes" if r.met else "no"]
                        for r in found.end_runs])
    if found.tests:
        text += _table(["rank", "what to measure", "response", "spread between the ends", "values"],
                       [[k + 1, t.label, t.response, f"{100 * t.spread:.0f} %",
                         ", ".join(_num(v) for v in t.values)] for k, t in enumerate(found.tests)])
        work = ", ".join(f"{'a reading of the UCS tests done' if t == PRIMARY_TEST else lab_test(t).title} {w:g}"
                         for t, w in LAB_WORK.items())
        text += "<p>" + html.escape(
            f"Each test ran at the {len(found.points)} ends kept ({found.runs} DEM runs in this stage); ranked by "
            f"its spread per run of lab work ({work}).") + "</p>"
    return text


def _validation(result: CalibrationResult) -> str:
    """Simulated K_IC against the lab's, or why there is none; the P_max/K_IC warning."""
    v = result.validation
    if v is None:  # the beam is a target
        return "<p class='note'>No bending validation in this campaign: K_IC is calibrated against.</p>"
    if v.status != "ok":
        text = f"<p class='note'>The bending run {html.escape(v.status)}: " \
               f"{html.escape(v.message or '')}</p>"
    else:
        seeds = v.ok_seeds or []
        text = _table(["K_IC lab (MPa·m^0.5)", "K_IC simulated (MPa·m^0.5)", "error",
                       "P_max (kN/m)", "displacement at peak (mm)", "packing seeds"],
                      [[_num(v.lab_K_IC_MPa_sqrt_m),
                        f"{_num(v.K_IC_MPa_sqrt_m)} ± {_num(v.K_IC_MPa_sqrt_m_std)}",
                        _pct(v.K_IC_error), _num(v.P_max_kN_per_m), _num(v.displacement_at_peak_mm),
                        ", ".join(f"{s}: {_num(k)}" for s, k in zip(seeds, v.K_IC_per_seed or []))]])
        text += _verdict(result)
    if v.warning:
        text += f"<p class='warn'>{html.escape(v.warning)}</p>"
    return text


def _verdict(result: CalibrationResult) -> str:
    """What the validation says of the model, in plain words: does it reproduce the rock's
    toughness, and if not, how its UCS / K_IC ratio compares with the rock's."""
    v, tolerance = result.validation, result.tolerance
    if abs(v.K_IC_error) <= tolerance:
        return (f"<p>The calibrated model reproduces the rock's fracture toughness: K_IC within "
                f"{_pct(v.K_IC_error)} of the lab's (tolerance {100 * tolerance:.0f} %).</p>")
    text = (f"<p class='warn'>The calibrated model does not reproduce the rock's fracture "
            f"toughness: its K_IC is {_pct(v.K_IC_error)} from the lab's, beyond the "
            f"{100 * tolerance:.0f} % tolerance.")
    ucs, lab_ucs = result.verified.get("ucs_MPa"), result.targets.get("ucs_MPa")
    if ucs and lab_ucs:
        text += (f" Its UCS / K_IC is {ucs / v.K_IC_MPa_sqrt_m:.0f} m^-0.5 against the rock's "
                 f"{lab_ucs / v.lab_K_IC_MPa_sqrt_m:.0f}: the model is "
                 f"{'tougher' if v.K_IC_error > 0 else 'more brittle'} for its compressive "
                 "strength than this rock.")
        text += (" Constant bond strengths, a wider installation gap and a cut notch raise "
                 "UCS / K_IC, a narrower gap lowers it.")
    return text + (" Use these parameters where the UCS responses matter; where fracture "
                   "matters, calibrate with K_IC as a target ([targets.bending] with "
                   "[validation] tests = []) and weigh the two fits.</p>")


def _checks(result: CalibrationResult) -> str:
    """Each other validation test: its lab and simulated responses and their errors."""
    out = ""
    for c in result.checks or []:
        out += f"<h3>Validation: {html.escape(lab_test(c.test).title)} test</h3>"
        if c.status != "ok":
            out += f"<p class='note'>The run {html.escape(c.status)}: {html.escape(c.message or '')}</p>"
            continue
        out += _table(["response", "lab", "simulated", "error"],
                      [[r, _num(v), _num(c.responses[r]), _pct(c.errors[r])] for r, v in c.lab.items()])
    return out


def _failed(result: CalibrationResult) -> str:
    """The failed and timed-out forward runs, by stage."""
    if not result.failed_runs:
        return ""
    return "<h3>Failed or timed-out runs</h3>" + _table(
        ["stage", "message"], [[f.stage, f.message] for f in result.failed_runs])


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


def _title(result: CalibrationResult) -> str:
    """The page's heading: what it is, of which rock, in which dimension."""
    what = "Quick look at" if result.quick_look else "Calibration of"
    return f"{what} {html.escape(result.rock)} ({result.specimen.dimensions}D)"


def _bending(result: CalibrationResult) -> str:
    """The bending validation's section, when the campaign has a notched beam."""
    if "bending" not in result.tests():
        return ""
    return f"\n<h3>Validation: notched-beam bending</h3>{_validation(result)}"


def _quick_look(result: CalibrationResult) -> str:
    """The quick look's label, first thing on the page (nothing for a calibration)."""
    return f"<p class='warn'><b>{html.escape(result.quick_look)}.</b></p>" if result.quick_look else ""


def write_report(result: CalibrationResult, store: RunStore, out: Path) -> Path:
    """Write the figures and OUT/report.html of a calibration; returns the HTML path."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    figures = "\n".join(_figure(title, caption, out / name, _drawn(name, figure, result, store, out))
                      for title, name, caption, figure in figures_of(result))
    rock = html.escape(result.rock)
    page = (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>rockcal calibration — {rock}"
            f"</title><style>{CSS}</style></head><body><h1>{_title(result)}</h1>{_quick_look(result)}"
            f"\n<h2>Summary</h2>{_overview(result)}\n<h3>Responses</h3>{_responses(result)}"
            f"\n<h3>Identified parameters</h3>{_parameters(result)}{_identifiability(result)}"
            f"{_bending(result)}\n{_checks(result)}"
            f"\n{_failed(result)}"
            f"\n{figures}\n</body></html>\n")
    return write_atomic(out / REPORT_NAME, page)


def _drawn(name: str, figure, result: CalibrationResult, store: RunStore, out: Path) -> str | None:
    """Draw a figure into OUT/name (saved whole by `rockcal.plots`; a figure left out removes
    its file): its note, or None when drawn."""
    return draw(name, figure, result, store, out / name)
