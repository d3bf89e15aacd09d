"""The campaign bar's ETA against the truth: a finished campaign's runs, replayed through the
bar of `rockcal calibrate` at the times they finished.

Run by hand on the store of a campaign run from a fresh store, e.g. the one
`calibrate_granite.py` leaves: `python benchmarks/eta_replay.py runs/granite-bench`. The first
screen's plan (`rockcal.campaign.plan.screen.stage_times`, for an empty store and the workers given)
sets the bar's weights; at the end of each stage it prints the ETA the bar showed and the time
the campaign really took from there.
"""

import argparse
import json
import tempfile
from pathlib import Path

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.plan.screen import stage_runs, stage_times
from rockcal.campaign.runs.store import RunStore
from rockcal.cli.calibrate import _stage_progress


def finished_runs(store: RunStore) -> list[tuple[float, float]]:
    """(start, end) of each stored run, seconds from the first start, in the order they ended."""
    rows = store.db.execute("SELECT wall_s, finished_at FROM runs ORDER BY finished_at").fetchall()
    t0 = min(end - wall for wall, end in rows)
    return [(end - wall - t0, end - t0) for wall, end in rows]


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("out", type=Path, help="a finished campaign's folder")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    store = RunStore(args.out, create=False)
    campaign = planned(parse_campaign(store.document("campaign.toml"), args.out))
    with tempfile.TemporaryDirectory() as empty:
        times = stage_times(campaign, RunStore(Path(empty) / "plan"), args.workers)
    runs = finished_runs(store)
    clock = [0.0]
    progress = _stage_progress(True, stage_runs(campaign), times)
    progress.bar.get_time = lambda: clock[0]
    for task in progress.bar.tasks:  # made before the clock was set
        task._get_time = progress.bar.get_time
        task.start_time = 0.0
    end = runs[-1][1]
    expected = sum(s for _, s in times.values())
    print(f"{len(runs)} runs in {end:.0f} s; the first screen expected {expected:.0f} s")
    print(f"{'after':<26} {'at s':>6} {'ETA s':>6} {'truth s':>8} {'error':>7}")
    k = 0
    for stage, n in stage_runs(campaign).items():
        progress(stage, 0, n)
        for done in range(1, n + 1):
            clock[0] = runs[k][1]
            progress(stage, done, n)
            k += 1
        eta = progress.bar.tasks[progress.campaign].time_remaining
        left = end - clock[0]
        if left > 0 and eta is not None:
            print(f"{stage:<26} {clock[0]:6.0f} {eta:6.0f} {left:8.0f} {100 * (eta / left - 1):+6.0f} %")
    print(json.dumps({"wall_s": end, "expected_s": expected}))


if __name__ == "__main__":
    main()
