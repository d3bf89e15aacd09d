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

from rockcal.errors import InputError
from rockcal.params import make_params, parse_assignments

app = typer.Typer(no_args_is_help=True, help="Run one virtual lab test.")


class Packing(str, Enum):
    random = "random"
    hexagonal = "hexagonal"


SET_HELP = ("Micro-parameter NAME=VALUE, repeatable: E_c, Ebar_c (GPa), kn_ks, knbar_ksbar, "
            "sigma_c, tau_c (MPa), mu, lambda, density (kg/m3), damping.")


def finite(name: str, value: float, low: float = 0.0) -> float:
    """A CLI number must be finite and above `low`."""
    if not math.isfinite(value) or value <= low:
        raise InputError(name, f"must be a finite number > {low:g}, got {value}")
    return value


@app.command()
def ucs(
    set_: list[str] = typer.Option([], "--set", help=SET_HELP),
    packing: Packing = typer.Option(Packing.random, help="Specimen packing."),
    rmin_mm: float = typer.Option(0.25, help="Smallest radius (hexagonal: the radius), mm."),
    radius_ratio: float = typer.Option(1.65, help="Largest / smallest radius."),
    width_mm: float = typer.Option(50.0, help="Specimen width, mm."),
    height_mm: float = typer.Option(100.0, help="Specimen height, mm."),
    seed: int = typer.Option(1, help="Packing seed."),
    max_axial_strain: float = typer.Option(0.02, help="Stop at this axial strain at the latest."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    out: Optional[Path] = typer.Option(None, help="Write curve CSV, summary JSON and PNGs here."),
) -> None:
    """Uniaxial compression test: E and nu (secant at half peak), UCS, stress-strain curve."""
    from rockcal.dem.specimen import hexagonal, random_packing
    from rockcal.labtests.ucs import simulate_ucs

    params = make_params(parse_assignments(set_))
    for name, value in (("--rmin-mm", rmin_mm), ("--width-mm", width_mm), ("--height-mm", height_mm)):
        finite(name, value)
    finite("--radius-ratio", radius_ratio, 0.0)
    if radius_ratio < 1:
        raise InputError("--radius-ratio", f"must be >= 1, got {radius_ratio}")
    finite("--max-axial-strain", max_axial_strain)
    console = Console(stderr=True)
    with console.status("making the specimen", spinner="dots") if not as_json else nullcontext():
        if packing is Packing.hexagonal:
            specimen = hexagonal(width_mm, height_mm, rmin_mm)
        else:
            specimen = random_packing(width_mm, height_mm, rmin_mm, radius_ratio, seed)

    with Progress(TextColumn("UCS test"), BarColumn(), TextColumn("{task.description}"),
                  TimeElapsedColumn(), console=console, disable=as_json, transient=True) as bar:
        task = bar.add_task("", total=max_axial_strain)

        def progress(axial_strain: float, stress_MPa: float) -> None:
            bar.update(task, completed=axial_strain,
                       description=f"strain {100 * axial_strain:.3f} %  stress {stress_MPa:.1f} MPa")

        result = simulate_ucs(params, specimen, max_axial_strain=max_axial_strain, progress=progress)

    summary = result.summary() | {"params": params.key(), "specimen": specimen.label,
                                  "porosity": specimen.porosity}
    if out is not None:
        _write_outputs(out, result, summary)
    if as_json:
        typer.echo(json.dumps(summary))
        return
    table = Table(title=f"UCS test — {specimen.label}", show_header=False)
    for label, value in (("E", f"{result.E_GPa:.2f} GPa"), ("Poisson's ratio", f"{result.nu:.3f}"),
                         ("UCS", f"{result.ucs_MPa:.1f} MPa"),
                         ("axial strain at peak", f"{100 * result.peak_axial_strain:.3f} %"),
                         ("particles / bonds", f"{result.n_particles} / {result.n_bonds}"),
                         ("broken bonds tension / shear",
                          f"{result.n_broken_tension} / {result.n_broken_shear}"),
                         ("steps, wall time", f"{result.steps}, {result.wall_s:.1f} s")):
        table.add_row(label, value)
    Console().print(table)


def _write_outputs(out: Path, result, summary: dict) -> None:
    from rockcal import plots

    out.mkdir(parents=True, exist_ok=True)
    np.savetxt(out / "ucs_curve.csv", result.curve, delimiter=",", fmt="%.8g",
               header="axial_strain,lateral_strain,axial_stress_MPa", comments="")
    (out / "ucs_summary.json").write_text(json.dumps(summary, indent=2))
    plots.crack_pattern(result.positions, result.radius, result.cracks, out / "ucs_cracks.png",
                        f"UCS {result.ucs_MPa:.1f} MPa — broken bonds")
    plots.stress_strain(result.curve, out / "ucs_curve.png", "UCS test")
