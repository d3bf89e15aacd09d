"""The engine's threads on idle and on busy cores: `rockcal simulate ucs --rmin-mm 0.5` timed
on one thread (`--threads 1`), on two (`--threads 2`) and by default (one thread per free
core), first on idle cores, then beside as many CPU-bound processes as there are cores (this
script starts them and stops them). On idle cores, two one-thread runs started together also
show what the machine gives two processes at once (on a virtual machine it moves from round to
round, and two threads cannot gain more than it gives). Each is a whole command in a new
process, one run after the other, timed whole and by its own clock (the run, without Python's
start and the specimen's loading); the ratios are to the one-thread run of the same condition.

Run by hand, on a machine with nothing else running (about 1.5 min on 2 cores):

    python benchmarks/threads_under_load.py [--rmin-mm 0.5] [--env OMP_WAIT_POLICY=passive] [--all] [--rounds 1]

`--all` also times two fixed threads on the busy cores (several times one thread's time: a
task half done on a descheduled thread holds the step). `--rounds K` times the whole table K
times in turn (a virtual machine's timings move by 10-20 % from run to run).

`--env NAME=VALUE` (repeatable) sets a variable in every timed run, e.g. numba's threading
layer (NUMBA_THREADING_LAYER=workqueue) or OpenMP's wait policy. The specimen is made (or
loaded from the cache) and the engine compiled by an untimed run first.
"""

import argparse
import contextlib
import json
import os
import subprocess
import sys
import time

RUNS = {"1 thread": ["--threads", "1"], "2 threads": ["--threads", "2"], "default": []}
FIXED_UNDER_LOAD = "2 threads"


@contextlib.contextmanager
def cpu_load(processes: int):
    """`processes` CPU-bound processes running until the block ends."""
    hogs = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(processes)]
    try:
        time.sleep(0.5)  # running before the timed command starts
        yield
    finally:
        for hog in hogs:
            hog.kill()
            hog.wait()


def timed(command: list[str], env: dict) -> tuple[float, dict]:
    """The wall time of a command printing one JSON object, and that object."""
    return timed_together(command, env, 1)[0]


def timed_together(command: list[str], env: dict, count: int) -> list[tuple[float, dict]]:
    """`timed` for `count` copies of a command started together."""
    started = time.perf_counter()
    runs = [subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             env=os.environ | env) for _ in range(count)]
    results = []
    for run in runs:
        out, err = run.communicate()
        if run.returncode != 0:
            sys.exit(err)
        results.append((time.perf_counter() - started, json.loads(out)))
    return results


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--rmin-mm", default="0.5")
    parser.add_argument("--env", action="append", default=[], metavar="NAME=VALUE")
    parser.add_argument("--all", action="store_true", help="two fixed threads on busy cores too")
    parser.add_argument("--rounds", type=int, default=1, help="the whole table this many times")
    args = parser.parse_args()
    env = dict(item.split("=", 1) for item in args.env)
    ucs = [sys.executable, "-m", "rockcal", "simulate", "ucs", "--rmin-mm", args.rmin_mm, "--json"]
    cores = len(os.sched_getaffinity(0))
    first = timed(ucs, env)[1]
    print(f"UCS, R_min {args.rmin_mm} mm: {first['n_particles']:.0f} grains, {first['steps']:.0f} steps; "
          f"{cores} cores{'; ' + ' '.join(args.env) if args.env else ''}")
    print(f"{'condition':34s} {'threads':10s} {'command s':>9s} {'ratio':>6s} {'run s':>7s} {'ratio':>6s}")
    seen = set()
    for round_ in range(1, args.rounds + 1):
        if args.rounds > 1:
            print(f"round {round_}")
        for condition, load in (("idle", 0), (f"beside {cores} CPU-bound processes", cores)):
            runs = {name: extra for name, extra in RUNS.items()
                    if not load or args.all or name != FIXED_UNDER_LOAD}
            with cpu_load(load):
                times = {name: timed(ucs + extra, env) for name, extra in runs.items()}
            one_s, one = times["1 thread"]
            together = (timed_together(ucs + RUNS["1 thread"], env, cores)
                        if not load and cores > 1 else [])
            rows = [(condition, name, *timing) for name, timing in times.items()]
            rows += [(f"idle, {cores} one-thread runs at once", "1 thread", *timing)
                     for timing in together]
            for label, name, seconds, summary in rows:
                seen.add((summary["ucs_MPa"], summary["steps"]))
                print(f"{label:34s} {name:10s} {seconds:9.2f} {seconds / one_s:6.2f} "
                      f"{summary['wall_s']:7.2f} {summary['wall_s'] / one['wall_s']:6.2f}")
            if together:
                mean_s = sum(summary["wall_s"] for _, summary in together) / cores
                two_threads_s = times["2 threads"][1]["wall_s"]
                print(f"{'':34s} the machine gives {cores} processes "
                      f"{cores * one['wall_s'] / mean_s:.2f}x one; 2 threads gave one run "
                      f"{one['wall_s'] / two_threads_s:.2f}x")
    print("same numbers in every run:", len(seen) == 1)


if __name__ == "__main__":
    main()
