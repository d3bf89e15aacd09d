"""`rockcal simulate ...`: one virtual lab test with given micro-parameters."""

from __future__ import annotations

import json
import math
from contextlib import nullcontext
from enum import Enum
from pathlib import Path
from typing import Optional

import numpy as np
import typer
from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

from rockcal.dem.genesis import Genesis, make_genesis
from rockcal.dem.simulate import CONTACT_STIFFNESS, DEFAULT_CONTACT_STIFFNESS
from rockcal.errors import InputError, as_flags
from rockcal.labtests import bending as bending_test
from rockcal.labtests.loading import check_stop_fraction
from rockcal.labtests.ucs import DEFAULT_STRAIN, POST_PEAK_FRACTION
from rockcal.params import make_params, parse_assignments

app = typer.Typer(no_args_is_help=True, help="Run one virtual lab test.")


class Packing(str, Enum):
    random = "random"
    hexagonal = "hexagonal"


class Strain(str, Enum):
    gauge = "gauge"
    platen = "platen"


ContactStiffness = Enum("ContactStiffness", [(name, name) for name in CONTACT_STIFFNESS], type=str)


SET_HELP = ("Micro-parameter NAME=VALUE, repeatable: E_c, Ebar_c (GPa), kn_ks, knbar_ksbar, "
            "sigma_c, tau_c, sigma_c_sd, tau_c_sd (MPa) or sigma_c_cv, tau_c_cv (sd / mean), "
            "phi_b (degrees), mcf, mu, lambda, "
            "density (kg/m3), damping.")
GENESIS_DEFAULTS = Genesis()
INSTALL_GAP = typer.Option(GENESIS_DEFAULTS.install_gap,
                           help="Bond installation gap / R_min (PFC pbm_igap / R_min).")
CLOUD_POROSITY = typer.Option(GENESIS_DEFAULTS.cloud_porosity,
                              help="Cloud porosity: sets the grain count (PFC pk_nc).")
PRESSURE_MPA = typer.Option(GENESIS_DEFAULTS.pressure_mpa,
                            help="Material pressure of the packing, MPa (PFC pk_Pm).")
# The options every test shares (typer reads each command's signature: one Option serves many).
CONTACT_STIFFNESS = typer.Option(ContactStiffness(DEFAULT_CONTACT_STIFFNESS),
                                 help="A contact's kn from E_c as PFC 3.x/4.0 (t E_c) or PFC 5+ "
                                      "does (2 min(R) t E_c / (R_A + R_B)).")
SET = typer.Option([], "--set", help=SET_HELP)
RMIN_MM = typer.Option(0.25, help="Smallest radius, mm.")
RADIUS_RATIO = typer.Option(1.65, help="Largest / smallest radius.")
SEED = typer.Option(1, min=0, help="Packing seed.")
SEEDS = typer.Option(1, help="Average over this many packings (seed, seed + 1, ...): mean and spread.")
AS_JSON = typer.Option(False, "--json", help="Print one JSON object.")
OUT = typer.Option(None, help="Write curve CSV, summary JSON and PNGs here.")


def genesis_of(install_gap: float, cloud_porosity: float, pressure_mpa: float) -> Genesis:
    """The genesis settings of the specimen flags; a bad one is an error naming its flag."""
    values = dict(install_gap=install_gap, cloud_porosity=cloud_porosity, pressure_mpa=pressure_mpa)
    with as_flags():
        return make_genesis(values)


def finite(name: str, value: float, low: float = 0.0) -> float:
    """A CLI number must be finite and above `low`."""
    if not math.isfinite(value) or value <= low:
        raise InputError(name, f"must be a finite number > {low:g}, got {value}")
    return value


@app.command()
def ucs(
    set_: list[str] = SET,
    packing: Packing = typer.Option(Packing.random, help="Specimen packing."),
    rmin_mm: float = typer.Option(0.25, help="Smallest radius (hexagonal: the radius), mm."),
    radius_ratio: float = RADIUS_RATIO,
    width_mm: float = typer.Option(50.0, help="Specimen width, mm."),
    height_mm: float = typer.Option(100.0, help="Specimen height, mm."),
    seed: int = SEED,
    install_gap: float = INSTALL_GAP,
    cloud_porosity: float = CLOUD_POROSITY,
    pressure_mpa: float = PRESSURE_MPA,
    contact_stiffness: ContactStiffness = CONTACT_STIFFNESS,
    strain: Strain = typer.Option(Strain(DEFAULT_STRAIN), help="Axial strain read from the specimen's "
                                  "own end particles (gauge) or from the platens (platen, PFC's)."),
    stop_fraction: float = typer.Option(POST_PEAK_FRACTION, help="Stop once past the peak the "
                                        "stress is below this fraction of it (PFC ct_loadFac)."),
    max_axial_strain: float = typer.Option(0.02, help="Stop at this axial strain at the latest."),
    as_json: bool = AS_JSON,
    out: Optional[Path] = OUT,
) -> None:
    """Uniaxial compression test: E and nu (secant at half peak), UCS, stress-strain curve."""
    from rockcal.dem.specimen import hexagonal, random_packing
    from rockcal.labtests.ucs import simulate_ucs

    params = make_params(parse_assignments(set_))
    _check_packing_options(rmin_mm, radius_ratio)
    finite("--width-mm", width_mm)
    finite("--height-mm", height_mm)
    finite("--max-axial-strain", max_axial_strain)
    with as_flags():
        check_stop_fraction(stop_fraction)
    genesis = genesis_of(install_gap, cloud_porosity, pressure_mpa)
    with _status(as_json):
        if packing is Packing.hexagonal:
            specimen = hexagonal(width_mm, height_mm, rmin_mm)
        else:
            specimen = random_packing(width_mm, height_mm, rmin_mm, radius_ratio, seed, genesis)
    result = _run_with_progress(
        "UCS test", max_axial_strain, as_json,
        lambda axial, stress: f"strain {100 * axial:.3f} %  stress {stress:.1f} MPa",
        lambda progress: simulate_ucs(params, specimen, max_axial_strain=max_axial_strain,
                                      strain=strain.value, stop_fraction=stop_fraction,
                                      contact_stiffness=contact_stiffness.value, progress=progress))
    summary = result.summary() | specimen.description() | {
        "params": params.key(), "contact_stiffness": contact_stiffness.value, "specimen": specimen.label}
    if out is not None:
        _write_outputs(out, result, summary)
    _report(f"UCS test — {specimen.label}", (
        ("E", f"{result.E_GPa:.2f} GPa"), ("Poisson's ratio", f"{result.nu:.3f}"),
        ("UCS", f"{result.ucs_MPa:.1f} MPa"),
        ("axial strain at peak", f"{100 * result.peak_axial_strain:.3f} % ({result.strain})"),
        ("porosity / contacts / bonds per grain", f"{specimen.porosity:.3f} / "
         f"{summary['coordination']:.2f} / {summary['bonds_per_particle']:.2f}"),
        *_common_rows(summary)), summary, as_json)


def _write_outputs(out: Path, result, summary: dict) -> None:
    from rockcal import plots

    out.mkdir(parents=True, exist_ok=True)
    np.savetxt(out / "ucs_curve.csv", result.curve, delimiter=",", fmt="%.8g",
               header="axial_strain,lateral_strain,axial_stress_MPa", comments="")
    (out / "ucs_summary.json").write_text(json.dumps(summary, indent=2))
    plots.crack_pattern(result.positions, result.radius, result.cracks, out / "ucs_cracks.png",
                        f"UCS {result.ucs_MPa:.1f} MPa — broken bonds")
    plots.stress_strain(result.curve, out / "ucs_curve.png", "UCS test")


def _check_packing_options(rmin_mm: float, radius_ratio: float) -> None:
    finite("--rmin-mm", rmin_mm)
    finite("--radius-ratio", radius_ratio)
    if radius_ratio < 1:
        raise InputError("--radius-ratio", f"must be >= 1, got {radius_ratio}")


def _status(as_json: bool):
    """A spinner on stderr while the specimen is made (nothing with --json)."""
    return nullcontext() if as_json else Console(stderr=True).status("making the specimen")


def _run_with_progress(label: str, total: float, as_json: bool, describe, run):
    """Run `run(progress)` under a rich progress bar on stderr (none with --json);
    progress(x, y) advances the bar to x and shows describe(x, y)."""
    with Progress(TextColumn(label), BarColumn(), TextColumn("{task.description}"),
                  TimeElapsedColumn(), console=Console(stderr=True), disable=as_json,
                  transient=True) as bar:
        task = bar.add_task("", total=total)
        return run(lambda x, y: bar.update(task, completed=x, description=describe(x, y)))


def _load_description(unit: str):
    return lambda mm, kN: f"{unit} {mm:.4f} mm  load {kN:.2f} kN/m"


def _common_rows(summary: dict):
    """Size, damage and cost of a test (means over packings when there are several)."""
    return (("particles / bonds", f"{summary['n_particles']:.0f} / {summary['n_bonds']:.0f}"),
            ("broken bonds tension / shear",
             f"{summary['n_broken_tension']:.0f} / {summary['n_broken_shear']:.0f}"),
            ("steps, wall time", f"{summary['steps']:.0f}, {summary['wall_s']:.1f} s"))


def _report(title: str, rows, summary: dict, as_json: bool) -> None:
    if as_json:
        typer.echo(json.dumps(summary))
        return
    table = Table(title=title, show_header=False)
    for label, value in rows:
        table.add_row(label, value)
    Console().print(table)


def _write_load_curve(out: Path, name: str, result, summary: dict, crack_title: str) -> None:
    from rockcal import plots

    out.mkdir(parents=True, exist_ok=True)
    np.savetxt(out / f"{name}_curve.csv", result.curve, delimiter=",", fmt="%.8g",
               header="displacement_mm,load_kN_per_m", comments="")
    (out / f"{name}_summary.json").write_text(json.dumps(summary, indent=2))
    plots.crack_pattern(result.positions, result.radius, result.cracks, out / f"{name}_cracks.png",
                        crack_title)
    plots.load_displacement(result.curve, out / f"{name}_curve.png", f"{name} test")


@app.command()
def bending(
    set_: list[str] = SET,
    rmin_mm: float = RMIN_MM,
    radius_ratio: float = RADIUS_RATIO,
    length_mm: float = typer.Option(220.0, help="Beam length, mm."),
    height_mm: float = typer.Option(50.0, help="Beam depth W, mm."),
    notch_mm: float = typer.Option(18.0, help="Notch depth a, mm (bottom edge, mid-span)."),
    notch_width_mm: float = typer.Option(2.0, help="Notch width, mm; 0 cuts the bonds (sharp crack)."),
    span_mm: float = typer.Option(160.0, help="Distance S between the supports, mm."),
    seed: int = SEED,
    seeds: int = SEEDS,
    install_gap: float = INSTALL_GAP,
    cloud_porosity: float = CLOUD_POROSITY,
    pressure_mpa: float = PRESSURE_MPA,
    contact_stiffness: ContactStiffness = CONTACT_STIFFNESS,
    stop_fraction: float = typer.Option(
        bending_test.POST_PEAK_FRACTION,
        help="Stop once the load has stayed below this fraction of the peak (0.9: as soon as "
             "P_max is certain; lower ones run the crack path)."),
    as_json: bool = AS_JSON,
    out: Optional[Path] = OUT,
) -> None:
    """Three-point bending of a notched beam: peak load, load-displacement curve, K_IC."""
    from rockcal.labtests.bending import (DEFAULT_MAX_DISPLACEMENT_MM, Beam, check_beam, notched_beam,
                                          simulate_bending)

    params = make_params(parse_assignments(set_))
    _check_packing_options(rmin_mm, radius_ratio)
    beam = Beam(length_mm, height_mm, notch_mm, notch_width_mm, span_mm)
    with as_flags():
        check_beam(beam, rmin_mm, radius_ratio)
        check_stop_fraction(stop_fraction)
    genesis = genesis_of(install_gap, cloud_porosity, pressure_mpa)

    def one(packing_seed: int, label: str):
        with _status(as_json):
            specimen = notched_beam(beam, rmin_mm, radius_ratio, packing_seed, genesis)
        result = _run_with_progress(
            label, DEFAULT_MAX_DISPLACEMENT_MM, as_json, _load_description("pin"),
            lambda progress: simulate_bending(params, specimen, beam, progress=progress,
                                              stop_fraction=stop_fraction,
                                              contact_stiffness=contact_stiffness.value))
        return result, specimen, f"K_IC {result.K_IC_MPa_sqrt_m:.3f} MPa·m^0.5 — broken bonds"

    summary = _over_seeds("bending", one, seed, seeds, params, out, contact_stiffness)
    _report(f"Three-point bending — {summary['specimen']}", (
        ("K_IC (notched beam, S/W = %.2f)" % (span_mm / height_mm),
         _mean_text(summary, "K_IC_MPa_sqrt_m", "%.3f", "MPa·m^0.5")),
        ("peak load", _mean_text(summary, "P_max_kN_per_m", "%.2f", "kN per m of thickness")),
        ("pin displacement at peak", _mean_text(summary, "displacement_at_peak_mm", "%.4f", "mm")),
        *_common_rows(summary)), summary, as_json)


@app.command()
def brazilian(
    set_: list[str] = SET,
    rmin_mm: float = RMIN_MM,
    radius_ratio: float = RADIUS_RATIO,
    diameter_mm: float = typer.Option(50.0, help="Disk diameter D, mm."),
    seed: int = SEED,
    seeds: int = SEEDS,
    install_gap: float = INSTALL_GAP,
    cloud_porosity: float = CLOUD_POROSITY,
    pressure_mpa: float = PRESSURE_MPA,
    contact_stiffness: ContactStiffness = CONTACT_STIFFNESS,
    as_json: bool = AS_JSON,
    out: Optional[Path] = OUT,
) -> None:
    """Brazilian test of a disk between platens: sigma_t = 2P/(pi D t), load-closure curve."""
    from rockcal.labtests.brazilian import DEFAULT_MAX_STRAIN, brazilian_disk, check_disk, simulate_brazilian

    params = make_params(parse_assignments(set_))
    _check_packing_options(rmin_mm, radius_ratio)
    with as_flags():
        check_disk(diameter_mm, rmin_mm, radius_ratio)
    genesis = genesis_of(install_gap, cloud_porosity, pressure_mpa)

    def one(packing_seed: int, label: str):
        with _status(as_json):
            specimen = brazilian_disk(diameter_mm, rmin_mm, radius_ratio, packing_seed, genesis)
        result = _run_with_progress(
            label, DEFAULT_MAX_STRAIN * diameter_mm, as_json, _load_description("closure"),
            lambda progress: simulate_brazilian(params, specimen, progress=progress,
                                                contact_stiffness=contact_stiffness.value))
        return result, specimen, f"sigma_t {result.sigma_t_MPa:.2f} MPa — broken bonds"

    summary = _over_seeds("brazilian", one, seed, seeds, params, out, contact_stiffness)
    _report(f"Brazilian test — {summary['specimen']}", (
        ("tensile strength sigma_t", _mean_text(summary, "sigma_t_MPa", "%.2f", "MPa")),
        ("peak load", _mean_text(summary, "P_max_kN_per_m", "%.2f", "kN per m of thickness")),
        ("platen closure at peak", _mean_text(summary, "displacement_at_peak_mm", "%.4f", "mm")),
        *_common_rows(summary)), summary, as_json)


def _over_seeds(name: str, one, seed: int, count: int, params, out: Path | None,
                contact_stiffness: ContactStiffness):
    """Run `one(seed, label)` -> (result, specimen, crack title) on `count` packings and
    write each one's outputs; the summary of one packing, or the mean and spread over several
    (with each packing's summary under "per_seed")."""
    from rockcal.labtests.seeds import mean_over_seeds, seed_list

    run = {"params": params.key(), "contact_stiffness": contact_stiffness.value}
    if count < 1:
        raise InputError("--seeds", f"must be >= 1, got {count}")
    responses, per_seed = [], []
    for k, packing_seed in enumerate(seed_list(seed, count)):
        label = f"{name} test" + (f", packing {k + 1}/{count}" if count > 1 else "")
        result, specimen, crack_title = one(packing_seed, label)
        responses.append(result.summary() | specimen.description())
        per_seed.append(responses[-1] | run | {"specimen": specimen.label, "seed": packing_seed})
        if out is not None:
            _write_load_curve(out, name if count == 1 else f"{name}_seed{packing_seed}", result,
                              per_seed[-1], crack_title)
    if count == 1:
        return per_seed[0]
    specimen = per_seed[0]["specimen"].replace(f"seed {seed}", f"seeds {seed}-{seed + count - 1}")
    summary = mean_over_seeds(responses) | run | {"specimen": specimen, "seeds": seed_list(seed, count),
                                                  "per_seed": per_seed}
    if out is not None:
        (out / f"{name}_summary.json").write_text(json.dumps(summary, indent=2))
    return summary


def _mean_text(summary: dict, key: str, fmt: str, unit: str) -> str:
    """A response, with its spread over packings when there are several."""
    text = fmt % summary[key]
    if "per_seed" in summary:
        text += " ± " + fmt % summary[f"{key}_std"] + f" (over {len(summary['per_seed'])} packings)"
    return f"{text} {unit}"
