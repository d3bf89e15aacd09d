"""What a 3D run costs, for the plan's time model (`rockcal.campaign.plan.cost`): stored runs of
a campaign's store run again on one thread, each one's processor seconds for its specimen and
for its test, its steps (against the stored run's: the same run takes the same steps) and its
spheres, and its processor time per sphere-step; with `--parallel-bond`, each run again on the
same specimen at the 3D granite's parallel-bond point, the flat joint's sphere-step over the
parallel bond's.

For each test, resolution and confinement in the store, the run with the median steps is run
(`--tests` to choose the tests). The store is only read.

Run by hand, one thread: `NUMBA_NUM_THREADS=1 python benchmarks/plan_3d.py STORE [--rmin-mm 0.75]
[--tests ucs brazilian] [--parallel-bond]`.
"""

import argparse
import json
import os
import sqlite3
import statistics
import time

from cell_3d import GRANITE_3D_POINT
from rockcal.campaign.plan.engine_speed import probe
from rockcal.campaign.runs.spec import RunSpec, params_of
from rockcal.labtests.kind import all_settings
from rockcal.labtests.registry import lab_test
from rockcal.materials.parallel_bond import make_params


def median_runs(store: str, tests: list[str] | None, rmin_mm: float | None) -> list[tuple[RunSpec, dict]]:
    """(spec, stored responses) of the run with the median steps of each test, R_min and
    confinement in the store."""
    db = sqlite3.connect(f"file:{store}/runs.sqlite?mode=ro", uri=True)
    groups: dict[tuple, list] = {}
    for kind, specimen, params, engine, responses in db.execute(
            "SELECT kind, specimen, params, engine, responses FROM runs WHERE status = 'ok'"):
        s, r = json.loads(specimen), json.loads(responses)
        if (tests and kind not in tests) or (rmin_mm and abs(s["rmin_mm"] - rmin_mm) > 1e-6):
            continue
        spec = RunSpec(kind, tuple(s.items()), tuple(json.loads(params).items()), engine)
        key = (kind, s["rmin_mm"], s.get("confinement_mpa"), s.get("brazilian_loading"))
        groups.setdefault(key, []).append((spec, r))
    chosen = []
    for key in sorted(groups, key=str):
        runs = sorted(groups[key], key=lambda run: run[1]["steps"])
        chosen.append(runs[len(runs) // 2])
    return chosen


def timed(test, params, specimen, settings):
    """The run's result and its processor seconds on this thread."""
    started = time.thread_time()
    result = test.run(params, specimen, settings, None)
    return result, time.thread_time() - started


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("store", help="a campaign's --out folder (read only)")
    parser.add_argument("--tests", nargs="+", default=None)
    parser.add_argument("--rmin-mm", type=float, default=None)
    parser.add_argument("--parallel-bond", action="store_true",
                        help="run each specimen again at the 3D granite's parallel-bond point")
    args = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; probe {probe().ms_per_step:.3f} ms a step")
    print(f"{'test':>15s} {'R_min':>5s} {'conf':>4s} {'make s':>6s} {'run s':>6s} {'steps':>6s} {'stored':>6s} "
          f"{'spheres':>7s} {'ns/sph-step':>11s}")
    for spec, stored in median_runs(args.store, args.tests, args.rmin_mm):
        settings = all_settings(dict(spec.specimen))
        test = lab_test(spec.kind)
        started = time.thread_time()
        specimen = test.make(settings)
        make_s = time.thread_time() - started
        materials = [("", params_of(spec))]
        if args.parallel_bond:
            materials.append((" pb", make_params(GRANITE_3D_POINT)))
        for name, params in materials:
            result, run_s = timed(test, params, specimen, settings)
            spheres = stored["n_particles"]
            print(f"{spec.kind + name:>15s} {settings['rmin_mm']:5.3g} {settings.get('confinement_mpa') or 0:4g} "
                  f"{make_s:6.1f} {run_s:6.1f} {result.steps:6d} {stored['steps'] if not name else 0:6d} "
                  f"{spheres:7d} {1e9 * run_s / (result.steps * spheres):11.0f}", flush=True)
    print(f"load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
