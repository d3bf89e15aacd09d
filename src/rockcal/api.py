"""rockcal from Python (a notebook, a script): `calibrate` runs a campaign as `rockcal
calibrate` does, without its screen, and returns a `Calibration` (its result, figures and
export); `simulate` runs one virtual lab test as `rockcal simulate <test>` does, and returns its
result. Bad input raises `rockcal.errors.InputError` naming the key, as the command's one-line
errors do."""

from __future__ import annotations

import html
import os
import re
from base64 import b64encode
from dataclasses import dataclass
from numbers import Integral, Real
from pathlib import Path

from rockcal.errors import InputError, fields_named

EXPORT_FILES = {"pfc-fish": "mpParams.p2dat", "pfc-python": "mpParams.py", "json": "mpParams.json"}


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
        "pfc-python" (a PFC Python script) or "json"; `to` by default OUT/mpParams.p2dat (.py,
        .json); `fishtank` the PFC version whose FISHTank reads it (5, 6 or 7).
        Returns the path written."""
        from rockcal.pfc.calibrated import for_fishtank
        from rockcal.pfc.formats import WRITERS
        from rockcal.campaign.outputs.export import calibration_in
        from rockcal.output_files import write_atomic

        if format not in WRITERS:
            raise InputError("format", f"one of {', '.join(WRITERS)}, got {format!r}")
        path = self.out / EXPORT_FILES[format] if to is None else Path(to)
        text = WRITERS[format](for_fishtank(calibration_in(self.out), fishtank, "fishtank"))
        try:
            return write_atomic(path, text)
        except OSError as exc:
            raise InputError("to", f"cannot write {path}: {exc.strerror}") from None

    def __repr__(self) -> str:
        r = self.result
        found = ", ".join(f"{name} {value:.4g}" for name, value in r.identified.items())
        return f"<Calibration of {r.rock}: {_verdict(r)}; identified {found}; in {self.out}>"

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
        note = f"<p><b>{e(r.quick_look)}</b></p>" if r.quick_look else ""
        return (f"<h3>Calibration of {e(r.rock)}: {e(_verdict(r))}</h3>{note}<table><tr><th></th>"
                f"<th>value</th><th>target</th><th>error</th></tr>{rows}</table>"
                f"<p>report: {e(str(self.out / 'report.html'))}</p>{figures}")


def _verdict(result) -> str:
    return f"{'accepted' if result.accepted else 'not accepted'}, {result.dem_runs} DEM runs"


def _num(value) -> str:
    return "—" if value is None else f"{value:.4g}"


def _pct(value) -> str:
    return "—" if value is None else f"{100 * value:+.1f} %"


def calibrate(campaign: str | Path | dict | None = None, *, out: str | Path | None = None, quick: bool = False,
              resume: bool = False, wait: bool = False, workers: int = 0, scheduler: str | None = None,
              threads: int | None = None) -> Calibration:
    """Calibrate a campaign file, a dict of its tables (`{"targets": {"ucs": {...}}, "specimen":
    {...}}`; a relative curve path taken from the current folder), or an embedded rock by name
    ("granite", "ldb"; None: the granite) in `out` (default runs/<rock name>,
    runs/<rock name>-quick with `quick`), going on with its stored runs if `resume`; returns the
    `Calibration`, also written to OUT/record.json with a report. `wait`, `workers`, `scheduler`
    and `threads` are `rockcal calibrate`'s options."""
    from rockcal.campaign.input.config import parse_campaign
    from rockcal.campaign.job import as_run, campaign_of, run_in_folder
    from rockcal.campaign.runs import MAX_WORKERS

    if not (campaign is None or isinstance(campaign, (str, os.PathLike, dict))):
        raise InputError("campaign", "a campaign file's path, an embedded rock's name or a dict of the "
                                     f"file's tables, got {type(campaign).__name__}")
    if not 0 <= workers <= MAX_WORKERS:
        raise InputError("workers", f"must be in [0, {MAX_WORKERS}], got {workers}")
    out = None if out is None else Path(out)
    with _as_arguments():
        if isinstance(campaign, dict):
            text = toml_text(campaign)
            chosen, text, note, out = as_run(parse_campaign(text, Path.cwd()), text, quick, out)
        else:
            chosen, text, note, out = campaign_of(campaign, quick, out)
        how = {"workers": workers, "scheduler": scheduler, "threads": threads}
        result = run_in_folder(chosen, text, out, note=note, resume=resume, wait=wait, how=how)[0]
    return Calibration(result, out)


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


def _plain(value, path: list[str]):
    """`value` as the Python TOML writes (numpy numbers and paths as numbers and text); the
    numbers TOML cannot check (inf, nan, beyond 64 bits) are refused with the file's own
    messages, when the text is read."""
    if isinstance(value, dict):
        for name in value:
            if not isinstance(name, str):
                raise InputError(".".join([*path, str(name)]), f"keys are text, got {type(name).__name__}")
        return {name: _plain(v, [*path, name]) for name, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v, [*path[:-1], f"{path[-1]}[{i}]"]) for i, v in enumerate(value)]
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
    """One run of the lab test `test` ("ucs", "brazilian", "bending", "biaxial",
    "direct_tension", or as the command line spells it, "direct-tension") with the
    micro-parameters `params` of `model` (default: the parallel bond; the others at their
    defaults) on a specimen of `settings` (the campaign file's [specimen] keys and the test's
    own, e.g. `rmin_mm=0.5`, `confinement_mpa=5`); `packing` "hexagonal" for a lattice where
    the test has one. Returns the test's result: `summary()` gives its responses, `curve` its
    curve."""
    from rockcal.labtests.registry import lab_test
    from rockcal.labtests.settings import specimen_settings
    from rockcal.materials import DEFAULT_MATERIAL, material, parameters

    kind = lab_test(test.replace("-", "_"))
    micro = parameters(material(model or DEFAULT_MATERIAL), params or {})
    chosen = specimen_settings(kind, settings)
    if packing not in ("random", "hexagonal") or (packing == "hexagonal" and kind.hexagonal is None):
        known = "'random' or 'hexagonal'" if kind.hexagonal else "'random'"
        raise ValueError(f"packing: {known}, got {packing!r}")
    specimen = kind.hexagonal(chosen) if packing == "hexagonal" else kind.make(chosen)
    return kind.run(micro, specimen, chosen, lambda x, y: None)
