"""The documentation's figure of rockcal against PFC2D on the source study's L16 table
(`docs/images/l16_parity.png`), drawn with the report's parity plot.

Run by hand: `python benchmarks/docs_figures.py [--l16-json l16-seed1.json l16-seed2.json
l16-seed3.json] [--out docs/images]`. Without `--l16-json` it draws the measured three-packing
means in `benchmarks/data/source_l16_rockcal.csv`; with it, the means of the runs you made with
`python benchmarks/source_l16.py --set sigma_c_cv=0.23 --set tau_c_cv=0.23 --seed N --json
l16-seedN.json`. Takes a few seconds.
"""

from __future__ import annotations

import argparse
import csv
import json
from pathlib import Path

import numpy as np

from rockcal import plots

HERE = Path(__file__).resolve().parent
PFC2D = HERE / "data" / "source_table3_l16.csv"
ROCKCAL = HERE / "data" / "source_l16_rockcal.csv"
RESPONSES = ("E_GPa", "nu", "ucs_MPa")


def read_csv(path: Path) -> list[dict]:
    with open(path) as f:
        rows = [line for line in f if not line.startswith("#")]
    return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(rows)]


def rockcal_means(paths: list[Path] | None) -> dict[int, dict[str, float]]:
    """rockcal's E, nu and UCS per run: the mean over the packings of `source_l16.py --json`
    files, or the measured means shipped in benchmarks/data."""
    if not paths:
        return {int(r["run"]): {k: r[k] for k in RESPONSES} for r in read_csv(ROCKCAL)}
    names = {"E_GPa": "E", "nu": "nu", "ucs_MPa": "ucs"}
    per_seed = [{row["run"]: row for row in json.loads(p.read_text())["rows"]} for p in paths]
    return {run: {k: float(np.mean([seed[run][names[k]] for seed in per_seed])) for k in RESPONSES}
            for run in per_seed[0]}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--l16-json", type=Path, nargs="*", default=None)
    parser.add_argument("--out", type=Path, default=HERE.parent / "docs" / "images")
    args = parser.parse_args()
    pfc = {int(r["run"]): r for r in read_csv(PFC2D)}
    ours = rockcal_means(args.l16_json)
    runs = sorted(ours)
    points = {k: {"16 points of the L16 table": ([pfc[r][k] for r in runs], [ours[r][k] for r in runs])}
              for k in RESPONSES}
    args.out.mkdir(parents=True, exist_ok=True)
    path = args.out / "l16_parity.png"
    plots.parity(points, 0.10, path, x="PFC2D", y="rockcal",
                 title="rockcal against the source study's PFC2D (mean of 3 packings)")
    print(path)


if __name__ == "__main__":
    main()
