"""`rockcal simulate <test>`: one virtual lab test with given micro-parameters, a command per
test of the lab-test registry, each with the same shared options (`--set`, `--model`,
`--seed`, `--seeds`, `--json`, `--out`, `--threads`) and an option per specimen setting the
test reads (its default and help from the campaign file's [specimen] keys)."""

from __future__ import annotations

import inspect
import os
import sys
import typing
from contextlib import nullcontext
from enum import Enum
from pathlib import Path
from typing import Optional

import numpy as np
import typer

from rockcal.output_files import json_text
from rich.console import Console
from rich.progress import Progress, SpinnerColumn, TextColumn, TimeElapsedColumn
from rich.table import Table

from rockcal.labtests.specimen_settings import DEFAULTS_3D, MAX_PACKINGS, SpecimenSettings

from rockcal.errors import InputError, fields_named
from rockcal.labtests.kind import LabTest
from rockcal.labtests.settings import specimen_settings
from rockcal.labtests.result import RunFailed, warnings_of
from rockcal.labtests.seeds import mean_over_seeds, seed_list
from rockcal.materials import DEFAULT_MATERIAL, MATERIALS, material, parameters
from rockcal.cli.threads import use_threads_option
from rockcal.params import parse_assignments

SET_HELP = ("Micro-parameter NAME=VALUE, repeatable. Parallel bond: E_c, Ebar_c (GPa), kn_ks, "
            "knbar_ksbar, sigma_c, tau_c, sigma_c_sd, tau_c_sd (MPa) or sigma_c_cv, tau_c_cv "
            "(sd / mean), phi_b (degrees), mcf, mu, lambda. Flat joint (--model flatjoint): "
            "fj_emod, lnm_emod (GPa), fj_kratio, lnm_krat, fj_ten, fj_coh (MPa) and their _sd "
            "(MPa) or _cv, fj_fa (degrees), fj_fric, lnm_fric, fj_nr, fj_rmul, fjm_rmulCode, "
            "fjm_B_frac, fjm_G_frac, fjm_G_m, fjm_G_sd (mm), fj_cohres (MPa) with fj_resmode 1. Both: "
            "density (kg/m3), damping.")
Model = Enum("Model", [(name, name) for name in MATERIALS], type=str)
Packing = Enum("Packing", [("random", "random"), ("hexagonal", "hexagonal")], type=str)
SHARED = {  # the options of every test: name -> (annotation, typer option)
    "set_": (list[str], typer.Option([], "--set", help=SET_HELP)),
    "model": (Model, typer.Option(Model(DEFAULT_MATERIAL), help="The bonded material (rockcal.materials).")),
    "seeds": (int, typer.Option(1, help="Average over this many packings (seed, seed + 1, ...): mean and spread.")),
    "as_json": (bool, typer.Option(False, "--json", help="Print one JSON object.")),
    "out": (Optional[Path], typer.Option(None, help="Write curve CSV, summary JSON and PNGs here.")),
    "threads": (Optional[int], typer.Option(None, min=1, help="Run the engine on this many threads "
                                            "(default: one per free core, looked at as it runs). "
                                            "The numbers do not depend on it.")),
}


def build_app() -> typer.Typer:
    """The `simulate` command group: a command per lab test in the registry."""
    from rockcal.labtests.registry import LAB_TESTS

    app = typer.Typer(no_args_is_help=True, rich_markup_mode=None, help="Run one virtual lab test.")
    for test in LAB_TESTS.values():
        app.command(test.name.replace("_", "-"), help=test.help or f"The {test.title} test.")(_command(test))
    return app


def _command(test: LabTest):
    """The function typer reads a test's command from: its signature is the options."""
    def command(ctx: typer.Context, **options) -> None:
        simulate(test, _given(ctx, options))

    parameters = [inspect.Parameter("ctx", inspect.Parameter.POSITIONAL_OR_KEYWORD, annotation=typer.Context)]
    parameters += [inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=option, annotation=kind)
                   for name, (kind, option) in {**_setting_options(test), **SHARED}.items()]
    command.__signature__ = inspect.Signature(parameters)
    return command


def flag_of(test: LabTest, setting: str) -> str:
    """The CLI flag of a specimen setting in a test's command."""
    return "--" + dict(test.flags).get(setting, setting).replace("_", "-")


def _setting_options(test: LabTest) -> dict:
    """An option per specimen setting the test reads (and --packing where it has a lattice)."""
    options, own = {}, {s.name: s for s in test.own_settings}
    for setting in test.settings:
        if setting in own:
            o = own[setting]
            kind, default = (str, f"{o.default:g}") if o.series else (type(o.default), o.default)
            options[setting] = (kind, typer.Option(default, flag_of(test, setting), help=o.help))
            continue
        info = SpecimenSettings.model_fields[setting]
        kind = info.annotation
        default = dict(test.defaults).get(setting, info.default)
        if typing.get_origin(kind) is typing.Literal:
            kind = Enum(setting, [(v, v) for v in typing.get_args(kind)], type=str)
            default = kind(default)
        shown = True  # a default that differs in 3D: each dimension's
        if setting in DEFAULTS_3D and "dimensions" in test.settings:
            shown = f"{getattr(default, 'value', default)} in 2D, {DEFAULTS_3D[setting]} with --dimensions 3"
        text = dict(test.setting_help).get(setting, info.description)
        options[setting] = (kind, typer.Option(default, flag_of(test, setting), help=text, show_default=shown))
    if "dimensions" not in test.settings:  # told in one line: no 3D implementation yet
        options["dimensions"] = (int, typer.Option(2, hidden=True))
    if test.hexagonal is not None:
        options["packing"] = (Packing, typer.Option(Packing("random"), help="Specimen packing (hexagonal: "
                                                    "a lattice of grains of radius --rmin-mm)."))
    return options


def simulate(test: LabTest, options: dict) -> None:
    """Run a test on `--seeds` packings, show (or print as JSON) its responses, write its files."""
    options = {k: v.value if isinstance(v, Enum) else v for k, v in options.items()}
    chosen = material(options.pop("model"), "--model")
    params = parameters(chosen, parse_assignments(options.pop("set_")))
    seeds, as_json, out = options.pop("seeds"), options.pop("as_json"), options.pop("out")
    use_threads_option(options.pop("threads"))
    if out is not None:
        check_out_folder(out)
    packing = options.pop("packing", "random")
    if not 1 <= seeds <= MAX_PACKINGS:
        raise InputError("--seeds", f"must be a number of packings in [1, {MAX_PACKINGS}], got {seeds}")
    # 3D (--dimensions 3): a test and a material the 3D engine has (a test without 3D: its hidden option)
    dimensions = options.get("dimensions", 2) if "dimensions" in test.settings else options.pop("dimensions")
    with fields_named({"model": "--model", test.name: test.name.replace("_", "-")}):
        test.check_dimensions(dimensions, chosen.name)
    series, values = _series(test, options)
    settings = _checked_settings(test, options)
    test = test.of_dimensions(dimensions)  # its responses as a run in these dimensions reports them
    run = {"params": params.key(), "contact_stiffness": settings.get("contact_stiffness")}
    if chosen.name != DEFAULT_MATERIAL:
        run["model"] = chosen.name
    if series is None:
        summary, _ = _on_packings(test, params, settings, packing, seeds, run, as_json, out, test.name)
        return _show(test, summary, as_json)
    done = [_on_packings(test, params, settings | {series: v}, packing, seeds, run, as_json, out,
                         f"{test.name}_{series}_{v:g}") for v in values]
    runs = [summary for summary, _ in done]
    for summary in runs if not as_json else []:
        _show(test, summary, as_json=False)
    combined = test.combine(runs) | run | {"runs": runs}
    if out is not None:
        _write_text(out / f"{test.name}_summary.json", json_text(combined, indent=2))
        _draw_series(test, done, out)
    _show_combined(test, combined, as_json)


def check_out_folder(out: Path) -> None:
    """Refuse --out before any run: a file, a path through a file, or a folder not writable."""
    existing = next((p for p in (out, *out.parents) if p.exists()), None)
    if existing is None:
        return
    if not existing.is_dir():
        raise InputError("--out", f"{existing} is a file, not a folder")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise InputError("--out", f"cannot write in {existing}: permission denied")


def _given(ctx: typer.Context, options: dict) -> dict:
    """The options less those of DEFAULTS_3D not given, which the specimen settings then take
    at their default for the dimensions chosen."""
    return {name: value for name, value in options.items()
            if not (name in DEFAULTS_3D and ctx.get_parameter_source(name).name == "DEFAULT")}


def _draw_series(test: LabTest, done: list[tuple[dict, np.ndarray]], out: Path) -> None:
    """The test's figures of a series' runs together (the envelope), each as OUT/<test>_<title>.png."""
    import rockcal.plots as plots  # matplotlib: only for a command that draws

    for figure in test.series_figures:
        if len(done) >= figure.min_runs:
            getattr(plots, figure.draw)(done, out / figure.file(test.name), figure.heading(test.title))


def _series(test: LabTest, options: dict) -> tuple[str | None, list]:
    """The test's list-valued setting and its values (each one run), parsed from its option."""
    for s in test.own_settings:
        if s.series:
            text, flag = options.pop(s.name), flag_of(test, s.name)
            entries = str(text).split(",")
            for k, entry in enumerate(entries, start=1):
                if not entry.strip():
                    raise InputError(flag, f"entry {k} of {text!r} is empty: give numbers separated by "
                                           "single commas")
            try:
                values = [float(v) for v in entries]
            except ValueError:
                raise InputError(flag, f"a comma-separated list of numbers, got {text!r}") from None
            with fields_named({s.name: flag}):
                s.check_series(values)
            options[s.name] = values[0]
            return s.name, values
    return None, []


def _on_packings(test, params, settings, packing, seeds, run, as_json, out, name) -> tuple[dict, np.ndarray]:
    """A test on `seeds` packings: one packing's summary, or their mean and spread; and the
    first packing's curve."""
    per_seed, curves = [], []
    for k, seed in enumerate(seed_list(settings["seed"], seeds)):
        label = f"{test.title} test" + (f", packing {k + 1}/{seeds}" if seeds > 1 else "")
        result, specimen = _run_one(test, params, settings | {"seed": seed}, packing, label, as_json)
        for problem in warnings_of(result.summary()):
            print(f"rockcal: warning: {label}: {problem}", file=sys.stderr)
        curves.append(result.curve)
        per_seed.append(result.summary() | specimen.description() | _clumps(specimen) | run
                        | {"specimen": specimen.label, "seed": seed})
        if out is not None:
            write_outputs(out, test, result, specimen, per_seed[-1],
                          name if seeds == 1 else f"{name}_seed{seed}")
    summary = per_seed[0] if seeds == 1 else _over_seeds(per_seed, settings["seed"], run)
    if out is not None and seeds > 1:
        _write_text(out / f"{name}_summary.json", json_text(summary, indent=2))
    return summary, curves[0]


def _clumps(specimen) -> dict:
    """A clumped specimen's grains (clumps) beside its particles (pebbles); nothing for balls."""
    if getattr(specimen, "clump_of", None) is None:
        return {}
    return {"n_grains": specimen.n_grains}


def _checked_settings(test: LabTest, options: dict) -> dict:
    """The test's specimen settings from the options (`labtests.settings.specimen_settings`), an
    error naming the flag."""
    rename = {setting: flag_of(test, setting) for setting in test.settings}
    with fields_named(lambda field: rename.get(field.removeprefix("specimen."), field)):
        return specimen_settings(test, options)


def _run_one(test: LabTest, params, settings: dict, packing: str, label: str, as_json: bool):
    """One packing's specimen and its result, with a spinner and the test's reading on stderr;
    a setting found wrong on the specimen made (before the run) is named by its flag."""
    flags = fields_named({setting: flag_of(test, setting) for setting in test.settings} | {"packing": "--packing"})
    with flags, nullcontext() if as_json else Console(stderr=True).status("making the specimen"):
        specimen = test.hexagonal(settings) if packing == "hexagonal" else test.make(settings)
    failed = None
    with flags, Progress(SpinnerColumn(), TextColumn(label), TextColumn("{task.description}"), TimeElapsedColumn(),
                  console=Console(stderr=True), disable=as_json, transient=True) as bar:
        task = bar.add_task("", total=None)
        try:
            result = test.run(params, specimen, settings,
                              lambda x, y: bar.update(task, description=test.reading(x, y)))
        except RunFailed as exc:  # the physics, not the input: one line, exit 1
            failed = exc
    if failed is not None:
        print(f"rockcal: run failed: {label}: {failed}", file=sys.stderr)
        raise typer.Exit(1)
    return result, specimen


def _over_seeds(per_seed: list[dict], seed: int, run: dict) -> dict:
    """The mean and sample spread over packings, each packing's summary under "per_seed"."""
    count = len(per_seed)
    specimen = per_seed[0]["specimen"].replace(f"seed {seed}", f"seeds {seed}-{seed + count - 1}")
    shared = {k: v for k, v in per_seed[0].items() if k not in run and k not in ("specimen", "seed")}
    return mean_over_seeds([{k: s[k] for k in shared} for s in per_seed]) | run | {
        "failed": all(s["failed"] for s in per_seed), "specimen": specimen, "seeds": seed_list(seed, count), "per_seed": per_seed}


def write_outputs(out: Path, test: LabTest, result, specimen, summary: dict, name: str) -> None:
    """A run's curve (CSV), summary (JSON), crack pattern (on three planes in 3D) and curve
    (PNG), named `name`, each written whole (`rockcal.output_files`: a link at its name is
    replaced, not followed)."""
    import rockcal.plots as plots
    from rockcal.labtests.rig import rig_for
    from rockcal.output_files import atomic_path

    try:
        out.mkdir(parents=True, exist_ok=True)
        with atomic_path(out / f"{name}_curve.csv") as tmp:
            np.savetxt(tmp, result.curve, delimiter=",", fmt="%.8g",
                       header=",".join(test.curve_columns), comments="")
    except OSError as exc:
        raise InputError("--out", f"cannot write to {out}: {exc.strerror}") from None
    _write_text(out / f"{name}_summary.json", json_text(summary, indent=2))
    strength = test.strength_response
    broken = material(summary.get("model", DEFAULT_MATERIAL)).breaks_word
    heading = f"{strength.label or strength.name} {getattr(result, strength.name):.4g} {strength.unit} — broken {broken}"
    plots.specimen_cracks(specimen, result.positions, result.cracks, out / f"{name}_cracks.png", heading)
    if test.plot:
        getattr(plots, test.plot)(result.curve, out / f"{name}_curve.png", f"{test.title} test", rig_for(specimen))


def _write_text(path: Path, text: str) -> None:
    """Write `text` to `path` whole (`write_atomic`)."""
    from rockcal.output_files import write_atomic

    try:
        write_atomic(path, text)
    except OSError as exc:
        raise InputError("--out", f"cannot write {path}: {exc.strerror}") from None


def _show(test: LabTest, summary: dict, as_json: bool) -> None:
    """The responses as a table (with their spread over packings), or one JSON object."""
    chosen = material(summary.get("model", DEFAULT_MATERIAL))
    rows = [(r.label or r.name, _value(summary, r.name, r.unit)) for r in test.responses]
    if "n_grains" in summary:  # clumps: their pebbles are the particles
        rows.append(("grains (clumps)", f"{summary['n_grains']:.0f}"))
    rows += [(f"particles / {chosen.pairs_word}", f"{summary['n_particles']:.0f} / {summary['n_bonds']:.0f}"),
             (f"broken {chosen.breaks_word} tension / shear",
              f"{summary['n_broken_tension']:.0f} / {summary['n_broken_shear']:.0f}"),
             ("steps, wall time", f"{summary['steps']:.0f}, {summary['wall_s']:.1f} s")]
    if not summary["failed"]:
        rows.append(("failed", "no: no bond broke, the peak is no strength"))
    _print(f"{test.title} test — {summary['specimen']}", rows, summary, as_json)


def _show_combined(test: LabTest, combined: dict, as_json: bool) -> None:
    """What a series of runs gives together (e.g. the strength envelope)."""
    rows = [(r.label or r.name, _value(combined, r.name, r.unit)) for r in test.combined_responses
            if r.name in combined]  # an envelope needs two runs or more
    _print(f"{test.title}: {len(combined['runs'])} runs together", rows, combined, as_json)


def _print(title: str, rows: list[tuple[str, str]], data: dict, as_json: bool) -> None:
    """A table of (name, value) rows, or `data` as one JSON object."""
    if as_json:
        typer.echo(json_text(data))
        return
    table = Table(title=title, show_header=False)
    for row in rows:
        table.add_row(*row)
    Console().print(table)


def _value(summary: dict, name: str, unit: str) -> str:
    """A response with its unit, and its spread over packings when there are several."""
    value = summary[name]
    if not isinstance(value, (int, float)):
        return str(value)
    text = f"{value:.4g}"
    if "per_seed" in summary:
        text += f" ± {summary[f'{name}_std']:.2g} (over {len(summary['per_seed'])} packings)"
    return f"{text} {unit}".strip()
