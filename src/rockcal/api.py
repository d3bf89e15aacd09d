"""rockcal from Python (a notebook, a script): `calibrate` runs a campaign as `rockcal
calibrate` does, without its screen, and returns a `Calibration` (its result, figures and
export); `simulate` runs one virtual lab test as `rockcal simulate <test>` does, and returns its
result. Bad input raises `rockcal.errors.InputError` naming the key, as the command's one-line
errors do."""

from __future__ import annotations

import html
import os
import re
import sys
import time
import warnings
from base64 import b64encode
from dataclasses import dataclass
from numbers import Integral, Real
from pathlib import Path

from rockcal.errors import InputError, fields_named

EXPORT_FILES = {"pfc-fish": "mpParams.p2dat", "pfc-python": "mpParams.py", "json": "mpParams.json"}


def _export_file(format: str, in_3d: bool) -> str:
    """The file `Calibration.export` writes in OUT by default: a 3D calibration's FISH file is
    PFC3D's (mpParams.p3dat)."""
    from rockcal.pfc.parameter_file import PARAMETER_FILE

    return PARAMETER_FILE if in_3d and format == "pfc-fish" else EXPORT_FILES[format]


@dataclass(frozen=True)
class Figure:
    """One of the report's figures, as its PNG file; a notebook shows it."""

    title: str
    path: Path

    def _repr_png_(self) -> bytes:
        return self.path.read_bytes()


@dataclass(frozen=True, repr=False)
class Calibration:
    """What `calibrate` returns: the campaign's `result` (a `CalibrationResult`, whose fields
    read through: `calibration.identified`, `verified`, `errors`, `accepted`...), its output
    folder `out`, the report's `figures`, and `export`. A notebook shows its summary and
    figures."""

    result: object  # rockcal.campaign.procedure.result.CalibrationResult
    out: Path

    def __getattr__(self, name: str):
        if name.startswith("_") or "result" not in self.__dict__:
            raise AttributeError(name)
        return getattr(self.result, name)

    def __dir__(self):
        return sorted({*super().__dir__(), *type(self.result).model_fields})

    @property
    def figures(self) -> dict[str, Figure]:
        """The report's figures written to OUT, by their file's name without .png
        ("stress_strain", "cracks_ucs", ...); those the campaign left out are not here."""
        from rockcal.campaign.outputs.figures import figures_of

        return {name.removesuffix(".png"): Figure(title, self.out / name)
                for title, name, _, _ in figures_of(self.result) if (self.out / name).is_file()}

    def export(self, format: str = "pfc-fish", to: str | Path | None = None, fishtank: int = 6) -> Path:
        """Write the identified parameters under PFC FISHTank's names, as `rockcal export OUT
        --format FORMAT --to TO --fishtank N` does: "pfc-fish" (a FISHTank mpParams data file),
        "pfc-python" (a PFC2D Python script, 2D only) or "json"; `to` by default
        OUT/mpParams.p2dat (a 3D calibration's: PFC3D's mpParams.p3dat; .py, .json); `fishtank` the PFC version whose
        FISHTank reads it (5, 6 or 7); a 3D calibration's FISH file has FISHTank's vessel,
        mvParams.p3dat, written beside it. Returns the path of the file asked for."""
        from rockcal.pfc.calibrated import for_fishtank, in_3d
        from rockcal.pfc.formats import WRITERS, write_export
        from rockcal.campaign.outputs.export import calibration_in

        if not isinstance(format, str) or format not in WRITERS:
            raise InputError("format", f"one of {', '.join(WRITERS)}, got {format!r}")
        path = None if to is None else path_argument("to", to)
        calibrated = calibration_in(self.out)
        if path is None:
            path = self.out / _export_file(format, in_3d(calibrated))
        return write_export(path, format, for_fishtank(calibrated, fishtank, "fishtank"), "to")[0]

    def __repr__(self) -> str:
        r = self.result
        found = ", ".join(f"{name} {value:.4g}" for name, value in r.identified.items())
        told = "".join(f"; {line}" for line in _warnings(r))
        return f"<Calibration of {r.rock}: {_verdict(r)}; identified {found}{told}; in {self.out}>"

    def _repr_html_(self) -> str:
        r = self.result
        e = html.escape
        rows = "".join(f"<tr><td>{e(name)}</td><td>{value:.4g}</td><td></td><td></td></tr>"
                       for name, value in r.identified.items())
        rows += "".join(f"<tr><td>{e(name)}</td><td>{_num(r.verified.get(name))}</td><td>{target:.4g}</td>"
                        f"<td>{_pct(r.errors.get(name))}</td></tr>" for name, target in r.targets.items())
        figures = "".join(f"<figure><img alt='{e(f.title)}' src='data:image/png;base64,"
                          f"{b64encode(f._repr_png_()).decode()}'><figcaption>{e(f.title)}</figcaption></figure>"
                          for f in self.figures.values())
        note = "".join(f"<p><b>{e(line)}</b></p>" for line in [r.quick_look, *_warnings(r)] if line)
        return (f"<h3>Calibration of {e(r.rock)}: {e(_verdict(r))}</h3>{note}<table><tr><th></th>"
                f"<th>value</th><th>target</th><th>error</th></tr>{rows}</table>"
                f"<p>report: {e(str(self.out / 'report.html'))}</p>{figures}")


def _warnings(result) -> list[str]:
    """The summary's warnings: each parameter on its search bound; which parameters the sheet
    pins and the test that would pin the others."""
    found = result.identifiability
    return [f"warning: {line}" for line in result.at_bounds or []] + \
        ([f"identifiability: {found.text}"] if found else [])


def _verdict(result) -> str:
    return f"{'accepted' if result.accepted else 'not accepted'}, {result.dem_runs} DEM runs"


def _num(value) -> str:
    return "—" if value is None else f"{value:.4g}"


def _pct(value) -> str:
    return "—" if value is None else f"{100 * value:+.1f} %"


def calibrate(campaign: str | Path | dict | None = None, *, out: str | Path | None = None, quick: bool = False,
              resume: bool = False, wait: bool = False, workers: int = 0, scheduler: str | None = None,
              threads: int | None = None, quiet: bool = False) -> Calibration:
    """Calibrate a campaign file, a dict of its tables (`{"targets": {"ucs": {...}}, "specimen":
    {...}}`; a relative curve path taken from the current folder), or an embedded rock by name
    ("granite", "ldb"; None: the granite) in `out` (default runs/<rock name>,
    runs/<rock name>-quick with `quick`), going on with its stored runs if `resume`; returns the
    `Calibration`, also written to OUT/record.json with a report. `wait`, `workers`, `scheduler`
    and `threads` are `rockcal calibrate`'s options. Unless `quiet`, the first screen and a line
    as each stage begins and ends are printed on stderr (`StageLines`)."""
    from rockcal.campaign.input.config import parse_campaign
    from rockcal.campaign.job import as_run, campaign_of, run_in_folder

    check_calibrate_arguments(campaign, out=out, quick=quick, resume=resume, wait=wait, workers=workers,
                              scheduler=scheduler, threads=threads)
    yes_or_no("quiet", quiet)
    out = None if out is None else Path(out)
    with _as_arguments():
        if isinstance(campaign, dict):
            text = toml_text(campaign)
            chosen, text, note, out = as_run(parse_campaign(text, Path.cwd()), text, quick, out)
        else:
            chosen, text, note, out = campaign_of(campaign, quick, out)
        how = {"workers": workers, "scheduler": scheduler, "threads": threads}
        start = None if quiet else lambda store, executor: StageLines(chosen, note, store, executor)
        result = run_in_folder(chosen, text, out, note=note, resume=resume, wait=wait, how=how, start=start)[0]
    return Calibration(result, out)


class StageLines:
    """`calibrate`'s progress as plain lines on stderr, for a script or a notebook where the
    command's bars do not show: the first screen, then a line as each stage's runs begin and
    another as they end."""

    def __init__(self, campaign, note: str | None, store, executor):
        from rockcal.campaign.plan.screen import describe

        self.began: dict[str, float] = {}
        self.told: set[tuple[str, int, int]] = set()
        self._print(f"Calibrating {campaign.rock.name}" + (" (quick look)" if note else ""))
        for line in ([note] if note else []) + describe(campaign, store, getattr(executor, "workers", None)):
            self._print("  " + line)
        if hasattr(executor, "on_genesis"):  # the packings the cache lacks, made first
            executor.on_genesis = lambda made, total: self("genesis (packings)", made, total)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def __call__(self, stage: str, done: int, total: int) -> None:
        if stage not in self.began:
            self.began[stage] = time.perf_counter()
            self._print(f"{stage}: {total} to do")
        if done == total and (stage, done, total) not in self.told:
            self.told.add((stage, done, total))
            self._print(f"{stage}: {done}/{total} done, {time.perf_counter() - self.began[stage]:.0f} s")

    def note(self, text: str) -> None:
        """A step's warning (a parameter the targets barely see), as it comes."""
        self._print(f"warning: {text}")

    @staticmethod
    def _print(line: str) -> None:
        print(line, file=sys.stderr, flush=True)


def check_calibrate_arguments(campaign, *, out, quick, resume, wait, workers, scheduler, threads) -> None:
    """`calibrate`'s arguments, each of its type and in its range (as `rockcal calibrate`'s
    options are checked before anything runs); InputError naming the first bad one."""
    import numba

    from rockcal.campaign.runs import MAX_WORKERS

    if not (campaign is None or isinstance(campaign, (str, os.PathLike, dict))):
        raise InputError("campaign", "a campaign file's path, an embedded rock's name or a dict of the "
                                     f"file's tables, got {type(campaign).__name__}")
    if out is not None:
        path_argument("out", out)
    for name, value in {"quick": quick, "resume": resume, "wait": wait}.items():
        yes_or_no(name, value)
    whole_number("workers", workers, 0, MAX_WORKERS)
    if threads is not None:
        whole_number("threads", threads, 1, numba.config.NUMBA_NUM_THREADS, "(NUMBA_NUM_THREADS)")
    if scheduler is not None:
        if not isinstance(scheduler, str):
            raise InputError("scheduler", f"text (tls://HOST:PORT, tcp://HOST:PORT or local:N), got "
                                          f"{type(scheduler).__name__}")
        from rockcal.campaign.runs.dask import parse_scheduler

        with _as_arguments():
            parse_scheduler(scheduler)


def path_argument(name: str, value) -> Path:
    """`value` as a path: text or a path, not empty, without a NUL; InputError naming `name`."""
    if not isinstance(value, (str, os.PathLike)) or not isinstance(os.fspath(value), str):
        raise InputError(name, f"a path (text or a Path), got {type(value).__name__}")
    text = os.fspath(value)
    if not text.strip() or "\0" in text:
        raise InputError(name, f"a path, got {text!r}")
    return Path(text)


def yes_or_no(name: str, value) -> None:
    """InputError naming `name` unless `value` is True or False (numpy's too)."""
    if not (isinstance(value, bool) or type(value).__name__ == "bool_"):
        raise InputError(name, f"True or False, got {value!r}")


def whole_number(name: str, value, low: int, high: int, why: str = "") -> None:
    """InputError naming `name` unless `value` is a whole number (not a bool) in [low, high]."""
    if isinstance(value, bool) or type(value).__name__ == "bool_" or not isinstance(value, Integral):
        raise InputError(name, f"a whole number in [{low}, {high}], got {value!r}")
    if not low <= value <= high:
        raise InputError(name, f"must be in [{low}, {high}]{' ' + why if why else ''}, got {value}")


# `rockcal calibrate`'s options that `calibrate` takes as arguments, as a call writes them
_ARGUMENTS = {"--out": "out", "--resume": "resume=True", "--quick": "quick=True", "--wait": "wait=True",
              "--workers": "workers", "--scheduler": "scheduler", "--threads": "threads"}
_FLAGS = re.compile("(" + "|".join(_ARGUMENTS) + r")(?![\w-])")


def _as_arguments() -> fields_named:
    """Within it, an InputError naming `rockcal calibrate`'s argument or options names
    `calibrate`'s arguments instead (`campaign`, `out`, and in its advice `resume=True`, not
    CONFIG, `--out` and `--resume`)."""
    return fields_named(
        lambda field: {"CONFIG": "campaign", **_ARGUMENTS}.get(field, field).removesuffix("=True"),
        lambda problem: _FLAGS.sub(lambda flag: _ARGUMENTS[flag[0]], problem))


def toml_text(tables: dict) -> str:
    """A campaign's tables as the TOML text of its file (kept in the run store as the file's
    is); InputError naming a key whose value a campaign file cannot hold."""
    import tomli_w

    if not isinstance(tables, dict):
        raise InputError("campaign", f"a dict of the campaign file's tables, got {type(tables).__name__}")
    return tomli_w.dumps(_plain(tables, []))


MAX_NESTING = 32  # tables and lists within one another: a campaign file's go 4 deep


def _plain(value, path: list[str], depth: int = 0):
    """`value` as the Python TOML writes (numpy numbers and paths as numbers and text); the
    numbers TOML cannot check (inf, nan, beyond 64 bits) are refused with the file's own
    messages, when the text is read; tables and lists nested more than MAX_NESTING deep (a dict
    that holds itself) are refused."""
    if depth > MAX_NESTING:
        raise InputError(".".join(map(str, path))[:40] + "...", f"tables or lists nested more than "
                                                                f"{MAX_NESTING} deep (does a dict hold itself?)")
    if isinstance(value, dict):
        for name in value:
            if not isinstance(name, str):
                raise InputError(".".join([*path, str(name)]), f"keys are text, got {type(name).__name__}")
        return {name: _plain(v, [*path, name], depth + 1) for name, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v, [*path[:-1], f"{path[-1]}[{i}]"], depth + 1) for i, v in enumerate(value)]
    if isinstance(value, bool):
        return value
    if isinstance(value, Integral):
        return int(value)
    if isinstance(value, Real):
        return float(value)
    if isinstance(value, (str, os.PathLike)):
        return os.fspath(value)
    got = "None: leave the key out" if value is None else type(value).__name__
    raise InputError(".".join(map(str, path)), f"a number, text, true/false, list or table, got {got}")


def simulate(test: str, params: dict | None = None, *, model: str | None = None, packing: str = "random",
             **settings):
    """One run of the lab test `test` ("ucs", "brazilian", "bending", "biaxial", "scb",
    "direct_tension", or as the command line spells it, "direct-tension") with the
    micro-parameters `params` of `model` (default: the parallel bond; the others at their
    defaults) on a specimen of `settings` (the campaign file's [specimen] keys and the test's
    own, e.g. `rmin_mm=0.5`, `confinement_mpa=5`); `packing` "hexagonal" for a lattice where
    the test has one. Returns the test's result: `summary()` gives its responses and whether the
    specimen failed (`failed`: a bond broke; a run that broke none is warned of), `curve` its
    curve."""
    from rockcal.labtests.registry import lab_test
    from rockcal.labtests.result import warnings_of
    from rockcal.labtests.settings import specimen_settings
    from rockcal.materials import DEFAULT_MATERIAL, material, parameters

    check_simulate_arguments(test, params, model, packing)
    kind = lab_test(test.replace("-", "_"))
    micro = parameters(material(model or DEFAULT_MATERIAL), dict(params or {}))
    chosen = specimen_settings(kind, _no_flags_as_numbers(settings))
    if packing == "hexagonal" and kind.hexagonal is None:
        raise InputError("packing", f"'random' (the {kind.title} test has no lattice), got {packing!r}")
    specimen = kind.hexagonal(chosen) if packing == "hexagonal" else kind.make(chosen)
    result = kind.run(micro, specimen, chosen, lambda x, y: None)
    for problem in warnings_of(result.summary()):
        warnings.warn(f"{kind.title} test: {problem}", stacklevel=2)
    return result


def check_simulate_arguments(test, params, model, packing) -> None:
    """`simulate`'s arguments but the specimen's settings, each of its type; InputError naming
    the first bad one."""
    from collections.abc import Mapping

    if not isinstance(test, str):
        raise InputError("test", f"a lab test's name (\"ucs\", \"brazilian\", ...), got {type(test).__name__}")
    if not (params is None or isinstance(params, Mapping)):
        raise InputError("params", f"a dict of micro-parameters (NAME: value), got {type(params).__name__}")
    if not (model is None or isinstance(model, str)):
        raise InputError("model", f"a material's name (\"parallel_bond\", \"flatjoint\"), got {type(model).__name__}")
    if packing not in ("random", "hexagonal"):
        raise InputError("packing", f"'random' or 'hexagonal', got {packing!r}")


def _no_flags_as_numbers(settings: dict) -> dict:
    """The specimen's settings, a True or False given for a number refused naming its key."""
    from rockcal.labtests.specimen_settings import SpecimenSettings

    for name, value in settings.items():
        field = SpecimenSettings.model_fields.get(name)
        if isinstance(value, bool) and (field is None or field.annotation is not bool):
            raise InputError(name, f"a number, got {value}")
    return settings
