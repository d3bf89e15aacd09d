"""The first screen's expected time against the wall time of the campaigns a new user runs
first: the README's quick look (`rockcal calibrate --quick`), the tutorial's campaign and the 3D
granite, each a whole command in a new process with an empty specimen cache (so the 3D
genesis is included), idle and then beside as many CPU-bound processes as there are cores
(this script starts and stops them).

Each row gives the command's wall time, when its first screen was made and what it expected
(`--json`: `planned_at_s`, `expected_s`), and the ratio of the time after the screen to the
expected time. Run by hand from the repository's root, with nothing else running (about 20 min
on 2 cores):

    python benchmarks/first_hour.py [--busy-only | --idle-only]
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

CAMPAIGNS = {"quick look": ["--quick"], "tutorial": ["docs/campaigns/tutorial.toml"],
             "3D granite": ["docs/campaigns/granite-3d.toml"]}


def timed(name: str, args: list[str]) -> dict:
    """One campaign on an empty specimen cache, into a new folder: its timing from `--json`,
    and the wall time."""
    with tempfile.TemporaryDirectory() as folder:
        started = time.perf_counter()
        done = subprocess.run([sys.executable, "-m", "rockcal", "calibrate", *args, "--json",
                               "--out", str(Path(folder) / "out")],
                              env=os.environ | {"ROCKCAL_CACHE": str(Path(folder) / "cache")},
                              capture_output=True, text=True)
        wall = time.perf_counter() - started
    if done.returncode:
        raise SystemExit(f"{name}: {done.stderr.strip().splitlines()[-1]}")
    summary = json.loads(done.stdout)
    after = wall - summary["planned_at_s"]
    return {"campaign": name, "wall_s": round(wall, 1), "planned_at_s": summary["planned_at_s"],
            "expected_s": summary["expected_s"], "after_screen_over_expected": round(after / summary["expected_s"], 2)}


def busy():
    """As many CPU-bound processes as cores, started now; stop them with `.kill()`."""
    return [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(os.cpu_count() or 1)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--busy-only", action="store_true")
    parser.add_argument("--idle-only", action="store_true")
    a = parser.parse_args()
    conditions = [c for c in ("idle", "busy") if not (c == "idle" and a.busy_only or c == "busy" and a.idle_only)]
    for condition in conditions:
        others = busy() if condition == "busy" else []
        try:
            for name, args in CAMPAIGNS.items():
                row = timed(name, args) | {"condition": condition}
                print(json.dumps(row), flush=True)
        finally:
            for process in others:
                process.kill()


if __name__ == "__main__":
    main()
