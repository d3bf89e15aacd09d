"""rockcal from Python (a notebook, a script): `calibrate` runs a campaign as `rockcal
calibrate` does, without its screen; `simulate` runs one virtual lab test as `rockcal simulate
<test>` does, and returns its result. Bad input raises `rockcal.errors.InputError` naming the
key, as the command's one-line errors do."""

from __future__ import annotations

from pathlib import Path


def calibrate(campaign: str | Path | None = None, *, out: str | Path | None = None, quick: bool = False,
              resume: bool = False, workers: int = 0, scheduler: str | None = None, threads: int | None = None):
    """Calibrate a campaign file (or an embedded rock by name: "granite", "ldb"; None: the
    granite) in `out` (default runs/<rock name>, runs/<rock name>-quick with `quick`), going on
    with its stored runs if `resume`; returns the `CalibrationResult` (its `identified`
    parameters, `verified` responses, `errors`...), also written to OUT/record.json with a
    report. `workers`, `scheduler` and `threads` are `rockcal calibrate`'s options."""
    from rockcal.campaign.job import campaign_of, run_in_folder
    from rockcal.campaign.runs import MAX_WORKERS
    from rockcal.errors import InputError

    if not 0 <= workers <= MAX_WORKERS:
        raise InputError("workers", f"must be in [0, {MAX_WORKERS}], got {workers}")
    chosen, text, note, out = campaign_of(campaign, quick, None if out is None else Path(out))
    how = {"workers": workers, "scheduler": scheduler, "threads": threads}
    return run_in_folder(chosen, text, out, note=note, resume=resume, how=how)[0]


def simulate(test: str, params: dict | None = None, *, model: str | None = None, packing: str = "random",
             **settings):
    """One run of the lab test `test` ("ucs", "brazilian", "bending", "biaxial",
    "direct_tension") with the micro-parameters `params` of `model` (default: the parallel
    bond; the others at their defaults) on a specimen of `settings` (the campaign file's
    [specimen] keys and the test's own, e.g. `rmin_mm=0.5`, `confinement_mpa=5`); `packing`
    "hexagonal" for a lattice where the test has one. Returns the test's result: `summary()`
    gives its responses, `curve` its curve."""
    from rockcal.labtests.registry import lab_test
    from rockcal.labtests.settings import specimen_settings
    from rockcal.materials import DEFAULT_MATERIAL, material, parameters

    kind = lab_test(test)
    micro = parameters(material(model or DEFAULT_MATERIAL), params or {})
    chosen = specimen_settings(kind, settings)
    if packing not in ("random", "hexagonal") or (packing == "hexagonal" and kind.hexagonal is None):
        raise ValueError(f"packing: 'random'{' or hexagonal' if kind.hexagonal else ''}, got {packing!r}")
    specimen = kind.hexagonal(chosen) if packing == "hexagonal" else kind.make(chosen)
    return kind.run(micro, specimen, chosen, lambda x, y: None)
