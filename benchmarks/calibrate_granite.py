"""The embedded granite campaign at full resolution, timed, beside the source study's figures.

Run by hand: `python benchmarks/calibrate_granite.py [--out runs/granite-bench] [--workers N]
[--campaign FILE]`. Runs `rockcal calibrate --json` on the embedded granite, or on a campaign
file of the same rock (resuming the folder's store if it holds one), and prints the wall
time, the DEM runs used, the identified parameters, the verified errors and K_IC. The wall time
is also given in "UCS units": divided by one full-size UCS run at the source's identified point
(granite specimen and strength spread, all threads) timed in the same benchmark, so that
machines of different speed compare: the fastest of `--reference-runs` (2) timings before the
campaign and one after it, the unit their mean (a shared machine's speed can drift by a fifth
over half an hour); that run's E, nu
and UCS are printed too. The campaign's work, which no other work on the machine moves, is
given in the same unit (`work_ucs_units`): the grains times the steps of every run it made,
over the reference run's (12 933 grains, 63 137 steps). The identification's wall time (`identification_s`, and in units) is
the campaign's up to the stage of the runs at the identified point (its packings and
validation), as the command's `stage_began_s` gives it.
"""

import argparse
import json
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

from rockcal.campaign.procedure.steps import PACKINGS_AND_VALIDATION

SOURCE = {"E_c": 21.65, "kn_ks": 1.9, "sigma_c": 36.55, "dem_runs": 49, "K_IC_error": 0.10}


def reference_ucs(times: int) -> tuple[list[float], dict]:
    """Wall times of `times` full-size UCS runs at the source's point, as the campaign runs it
    (the same run: its time moves 10-20 % with where its arrays lie in memory), and its
    responses."""
    from rockcal.campaign.input.config import load_campaign
    from rockcal.campaign.runs.pool import execute
    from rockcal.campaign.runs.spec import run_spec

    granite, _ = load_campaign(None)
    params = granite.fixed_params() | {k: SOURCE[k] for k in ("E_c", "kn_ks", "sigma_c")}
    execute(run_spec("ucs", granite.specimen.model_copy(update={"height_mm": 20, "width_mm": 10}),
                     params))  # compiles the engine and warms the caches
    walls = []
    for _ in range(times):
        started = time.perf_counter()
        run = execute(run_spec("ucs", granite.specimen, params))
        walls.append(time.perf_counter() - started)
    return walls, {k: run.responses[k] for k in ("E_GPa", "nu", "ucs_MPa", "steps")}


REFERENCE_WORK = 12_933 * 63_137  # grains x steps of the reference UCS run


def campaign_work(store: Path) -> float:
    """Grains x steps of the store's runs done, over the reference UCS run's."""
    with sqlite3.connect(f"file:{store}?mode=ro", uri=True) as db:
        rows = db.execute("SELECT responses FROM runs WHERE status = 'ok'").fetchall()
    return sum(r["n_particles"] * r["steps"] for r in (json.loads(row[0]) for row in rows)) / REFERENCE_WORK


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", type=Path, default=Path("runs/granite-bench"))
    parser.add_argument("--workers", type=int, default=0)
    parser.add_argument("--campaign", type=Path, help="a campaign file (default: the embedded granite)")
    parser.add_argument("--reference-runs", type=int, default=2,
                        help="times the reference UCS run is timed before the campaign (once more "
                             "after it; the unit: the mean of the fastest before and the one after; "
                             "0: no UCS units)")
    args = parser.parse_args()
    walls, at_source = reference_ucs(args.reference_runs) if args.reference_runs > 0 else ([], None)
    reference_s = min(walls, default=None)
    started = time.perf_counter()
    command = [sys.executable, "-m", "rockcal", "calibrate", *([str(args.campaign)] if args.campaign else []),
               "--out", str(args.out),
               "--workers", str(args.workers), "--json"]
    if (args.out / "runs.sqlite").exists():
        command.append("--resume")
    run = subprocess.run(command, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(run.stderr)
    result = json.loads(run.stdout)
    result["wall_s"] = time.perf_counter() - started
    final_stage_s = result["stage_began_s"].get(PACKINGS_AND_VALIDATION)
    result["identification_s"] = result["wall_s"] - (0.0 if final_stage_s is None else
                                                      result["elapsed_s"] - final_stage_s)
    if reference_s:
        after_s = reference_ucs(1)[0][0]
        result["reference_ucs_s"] = 0.5 * (reference_s + after_s)
        result["reference_ucs_runs_s"] = {"before": walls, "after": after_s}
        result["reference_ucs_at_source_point"] = at_source
        result["wall_ucs_units"] = result["wall_s"] / result["reference_ucs_s"]
        result["identification_ucs_units"] = result["identification_s"] / result["reference_ucs_s"]
    result["work_ucs_units"] = campaign_work(args.out / "runs.sqlite")
    result["source"] = SOURCE
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
