"""Forward runs per minute on one UCS specimen: serial, process pool, and Dask local clusters.

Run by hand: `python benchmarks/dask_scaling.py [--width-mm 16 --height-mm 32 --rmin-mm 0.3]
[--runs 12]`. Every executor runs the same parameter sets into a fresh store; the specimen is
packed once beforehand (not timed). Prints a markdown table: start-up time (pool processes
start inside the first batch, so theirs is in the run time), run time, runs per minute, and
whether every executor gave bit-identical responses.
"""

import argparse
import os
import tempfile
import time
from pathlib import Path

from rockcal.campaign.input.config import SpecimenSettings
from rockcal.campaign.runs.dask import DaskExecutor
from rockcal.campaign.runs.pool import Executor, prepare
from rockcal.campaign.runs.spec import run_spec
from rockcal.campaign.runs.store import RunStore

EXECUTORS = [
    ("serial Executor", "1 process", lambda store: Executor(store, workers=1)),
    ("process-pool Executor", "2 processes", lambda store: Executor(store, workers=2)),
    ("DaskExecutor local:1", "1 worker", lambda store: DaskExecutor(store, "local:1")),
    ("DaskExecutor local:2", "2 workers", lambda store: DaskExecutor(store, "local:2")),
]


def parameter_sets(n: int) -> list[dict]:
    """n distinct (E_c, sigma_c) pairs on a 4-column grid."""
    return [{"E_c": 15.0 + 5.0 * (i % 4), "sigma_c": 30.0 + 10.0 * (i // 4), "tau_c": 200.0}
            for i in range(n)]


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--width-mm", type=float, default=16.0)
    parser.add_argument("--height-mm", type=float, default=32.0)
    parser.add_argument("--rmin-mm", type=float, default=0.3)
    parser.add_argument("--runs", type=int, default=12)
    args = parser.parse_args()
    settings = SpecimenSettings(width_mm=args.width_mm, height_mm=args.height_mm, rmin_mm=args.rmin_mm)
    specs = [run_spec("ucs", settings, p) for p in parameter_sets(args.runs)]
    started = time.perf_counter()
    prepare(specs[0])
    packing_s = time.perf_counter() - started
    rows, responses = [], {}
    with tempfile.TemporaryDirectory() as folder:
        for name, workers, make in EXECUTORS:
            store = RunStore(Path(folder) / name.replace(" ", "_").replace(":", ""))
            started = time.perf_counter()
            executor = make(store)
            start_s = time.perf_counter() - started
            started = time.perf_counter()
            results = executor.run(specs)
            run_s = time.perf_counter() - started
            executor.close()
            store.close()
            assert all(r.status == "ok" for r in results), [r.message for r in results]
            responses[name] = [r.responses for r in results]
            rows.append((name, workers, start_s, run_s, 60.0 * len(specs) / run_s))
    identical = all(r == responses[EXECUTORS[0][0]] for r in responses.values())
    print(f"UCS {args.width_mm:g} x {args.height_mm:g} mm, R_min {args.rmin_mm:g} mm, "
          f"{len(specs)} parameter sets; packing {packing_s:.1f} s (not timed below); "
          f"{os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f} at the end\n")
    print("| executor | parallelism | start-up s | runs s | runs / min | speed-up |")
    print("|---|---|---|---|---|---|")
    for name, workers, start_s, run_s, per_min in rows:
        print(f"| {name} | {workers} | {start_s:.1f} | {run_s:.1f} | {per_min:.1f} | "
              f"{per_min / rows[0][4]:.2f} |")
    print(f"\nbit-identical responses across executors: {'yes' if identical else 'NO'}")


if __name__ == "__main__":
    main()
