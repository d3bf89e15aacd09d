"""`rockcal sensitivity analyze`: range analysis of the runs of an orthogonal design."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from rockcal.output_files import json_text
from rich.console import Console
from rich.table import Table

from rockcal.errors import InputError

app = typer.Typer(no_args_is_help=True, rich_markup_mode=None, help="Sensitivity analysis: which micro-parameter drives which response.")


@app.callback()
def _group() -> None:
    """Sensitivity analysis of forward runs (orthogonal design, range analysis)."""


def _names(option: str, text: str) -> list[str]:
    names = [n.strip() for n in text.split(",") if n.strip()]
    if not names:
        raise InputError(option, "give comma-separated column names, e.g. E_c,kn_ks")
    if len(set(names)) != len(names):
        raise InputError(option, f"a column is named twice in {text!r}")
    return names


def _table(analysis, response: str) -> Table:
    """The source's table: K1..Kn, k1..kn and R of every factor for one response."""
    n = max(len(e.levels) for e in analysis.effects[response].values())
    table = Table(title=f"Range analysis of {response}")
    table.add_column("factor", no_wrap=True)
    for prefix in ("K", "k"):
        for i in range(1, n + 1):
            table.add_column(f"{prefix}{i}", justify="right")
    table.add_column("R", justify="right")
    table.add_column("rank", justify="right")
    ranking = analysis.ranking(response)
    for factor in analysis.factors:
        e = analysis.effects[response][factor]
        pad = [""] * (n - len(e.levels))
        table.add_row(factor, *[f"{v:.4g}" for v in e.K], *pad, *[f"{v:.4g}" for v in e.k], *pad,
                      f"{e.R:.4g}", str(ranking.index(factor) + 1))
    return table


def _bar_chart(analysis, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rockcal.output_files import save_figure

    m = len(analysis.responses)
    fig, axes = plt.subplots(1, m, figsize=(3.2 * m + 1, 3.6), squeeze=False)
    for ax, response in zip(axes[0], analysis.responses):
        R = [analysis.effects[response][f].R for f in analysis.factors]
        top = analysis.ranking(response)[0]
        colours = ["tab:red" if f == top else "tab:blue" for f in analysis.factors]
        ax.bar(analysis.factors, R, color=colours)
        ax.set_title(f"R of {response}")
        ax.tick_params(axis="x", rotation=45)
    fig.tight_layout()
    save_figure(fig, path, dpi=150)
    plt.close(fig)


def _write(out: Path, analysis, summary: dict) -> None:
    """OUT/range_analysis.png and .json, each written whole (a link there is replaced, not followed)."""
    from rockcal.output_files import write_atomic

    try:
        out.mkdir(parents=True, exist_ok=True)
        _bar_chart(analysis, out / "range_analysis.png")
        write_atomic(out / "range_analysis.json", json_text(summary, indent=2))
    except OSError as exc:
        raise InputError("--out", f"cannot write to {out}: {exc.strerror or exc}") from None


@app.command()
def analyze(
    results: Path = typer.Argument(..., help="CSV: one column per factor and response, one row per run."),
    factors: str = typer.Option(..., help="Factor columns, comma-separated (e.g. E_c,kn_ks,sigma_c)."),
    responses: str = typer.Option(..., help="Response columns, comma-separated (e.g. E,nu,UCS)."),
    threshold: Optional[float] = typer.Option(
        None, help="Also choose every factor with R >= THRESHOLD x the largest R of a response (0-1]."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    out: Optional[Path] = typer.Option(None, help="Write range_analysis.png (bars of R) and range_analysis.json here."),
) -> None:
    """K_i, k_i = K_i / runs per level and R = max k - min k of every factor for every response.

    Levels of a factor are the sorted unique values of its column. The factors to invert
    are the most influential one of each response (and, with --threshold, any close to it).
    JSON: {response: {factor: {"levels", "K", "k", "R"}}, ..., "ranking": {response:
    [factors by decreasing R]}, "chosen": [factors]}.
    """
    from rockcal.inverse.range_analysis import range_analysis, read_results

    response_names = _names("--responses", responses)
    if {"ranking", "chosen"} & set(response_names):
        raise InputError("--responses", "'ranking' and 'chosen' are reserved names; rename the column")
    factor_cols, response_cols = read_results(results, _names("--factors", factors), response_names)
    if threshold is not None and not (0 < threshold <= 1):
        raise InputError("--threshold", f"must be in (0, 1], got {threshold}")
    analysis = range_analysis(factor_cols, response_cols)
    summary = analysis.to_dict(threshold)
    summary = summary.pop("responses") | summary
    if out is not None:
        _write(out, analysis, summary)
    if as_json:
        typer.echo(json_text(summary))
        return
    console = Console()
    for response in analysis.responses:
        console.print(_table(analysis, response))
    console.print("Most influential: " + "; ".join(
        f"{r}: {' > '.join(summary['ranking'][r])}" for r in analysis.responses))
    console.print(f"Parameters to invert: {', '.join(summary['chosen'])}")
