"""The local process pool: the same numbers as a serial run, and a worker process killed mid-run
costs only that run, which is run again on a new pool."""

import os
import signal
import threading
import time

import pytest

from rockcal.campaign.input.config import SpecimenSettings
from rockcal.campaign.runs.pool import Executor
from rockcal.campaign.runs.spec import run_spec
from rockcal.campaign.runs.store import RunStore

pytestmark = pytest.mark.slow  # DEM runs and specimens of minutes: deselect with -m "not slow"

SETTINGS = SpecimenSettings(rmin_mm=0.3, width_mm=12, height_mm=24)  # ~1 s a run


def batch(n: int):
    return [run_spec("ucs", SETTINGS, {"E_c": 15.0 + i, "sigma_c": 40.0}) for i in range(n)]


def test_a_killed_pool_worker_loses_nothing_and_the_numbers_match_a_serial_run(tmp_path):
    specs = batch(6)
    pool_store, serial_store = RunStore(tmp_path / "pool"), RunStore(tmp_path / "serial")
    executor = Executor(pool_store, workers=2)
    killed = []

    def kill_one_worker():
        watched = RunStore(tmp_path / "pool")  # a connection of this thread's own
        deadline = time.time() + 120
        while time.time() < deadline and not killed:
            pool = executor._pool
            if pool is not None and pool._processes and watched.count() >= 1:
                pid = next(iter(pool._processes))
                os.kill(pid, signal.SIGKILL)
                killed.append(pid)
            time.sleep(0.01)

    watcher = threading.Thread(target=kill_one_worker, daemon=True)
    watcher.start()
    try:
        results = executor.run(specs)
    finally:
        executor.close()
    watcher.join()
    assert killed, "no worker was killed"
    assert [r.status for r in results] == ["ok"] * len(specs)
    assert pool_store.executions() == {s.key: 1 for s in specs}
    serial = Executor(serial_store, workers=1).run(specs)
    assert [r.responses for r in serial] == [r.responses for r in results]


def test_running_tests_report_their_readings_as_they_go(tmp_path, monkeypatch):
    """Each running test shows its strain and stress about once a second (here every step
    chunk), on the pool and serially; nothing is shown once the runs are done."""
    import rockcal.campaign.runs.pool as forward

    monkeypatch.setattr(forward, "LIVE_INTERVAL_S", 0.0)
    for workers in (2, 1):
        shown = []
        executor = Executor(RunStore(tmp_path / str(workers)), workers=workers)
        executor.on_live = shown.append
        try:
            executor.run(batch(2))
        finally:
            executor.close()
        readings = [line for lines in shown for line in lines]
        assert readings and all(line.startswith("UCS ") for line in readings)
        assert any(" MPa" in line and "strain" in line for line in readings)
        assert max(map(len, shown)) <= workers  # a line per run in flight
        assert shown[-1] == []
