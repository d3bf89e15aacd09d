"""`rockcal kic`: the lab's K_IC of a straight-notched round bar from its peak load."""

from __future__ import annotations

import typer

from rockcal.output_files import json_text


def kic(
    pmax_kn: float = typer.Option(..., "--pmax-kn", help="Peak load P_max, kN."),
    diameter_mm: float = typer.Option(..., help="Bar diameter D, mm."),
    notch_mm: float = typer.Option(..., help="Notch depth a, mm."),
    span_mm: float = typer.Option(..., help="Support span S, mm."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
) -> None:
    """K_IC = 0.25 (S/D) Y P_max / D^1.5 (Ouchterlony's straight-notched round bar)."""
    from rockcal.labtests.kic import check_round_bar, ouchterlony_Y, round_bar_kic

    from rockcal.errors import as_flags
    from rockcal.labtests.plausible import check_plausible

    given = {"pmax_kn": pmax_kn, "diameter_mm": diameter_mm, "notch_mm": notch_mm, "span_mm": span_mm}
    for name, value in given.items():
        check_plausible("--" + name.replace("_", "-"), name, value)
    args = (1e3 * pmax_kn, 1e-3 * diameter_mm, 1e-3 * notch_mm, 1e-3 * span_mm)
    with as_flags():
        check_round_bar(*args)
    summary = {"K_IC_MPa_sqrt_m": round_bar_kic(*args) / 1e6,
               "Y": ouchterlony_Y(notch_mm / diameter_mm), "a_over_D": notch_mm / diameter_mm,
               "formula": "Ouchterlony straight-notched round bar, 0.25 (S/D) Y P / D^1.5"}
    if as_json:
        typer.echo(json_text(summary))
        return
    typer.echo(f"K_IC = {summary['K_IC_MPa_sqrt_m']:.3f} MPa·m^0.5  (Y = {summary['Y']:.3f}, "
               f"a/D = {summary['a_over_D']:.3f}; Ouchterlony's straight-notched round bar)")
