"""Campaigns on a Dask cluster (local processes on loopback): the same answer as on one core,
bit for bit, and no run lost or run twice when workers die, runs fail or overrun their time."""

import os
import signal
import sys
import threading
import time

import pytest

pytest.importorskip("distributed")

from distributed import LocalCluster  # noqa: E402

from rockcal.campaign.runs import dask as dask_executor  # noqa: E402
from rockcal.campaign.input.config import SpecimenSettings, parse_campaign  # noqa: E402
from rockcal.campaign.plan.planned import planned  # noqa: E402
from rockcal.campaign.runs.dask import DaskExecutor, parse_scheduler  # noqa: E402
from rockcal.campaign.runs.pool import Executor  # noqa: E402
from rockcal.campaign.runs.packings import packing_file  # noqa: E402
from rockcal.campaign.runs.spec import run_spec  # noqa: E402
from rockcal.specimens.specimen import stored_packing  # noqa: E402
from rockcal.campaign.procedure.steps import calibrate  # noqa: E402
from rockcal.campaign.runs.store import RunStore  # noqa: E402
from rockcal.errors import InputError  # noqa: E402
from tiny import tiny_campaign

CAMPAIGN = tiny_campaign()
TINY = SpecimenSettings(rmin_mm=0.4, width_mm=8, height_mm=16)
SLOWER = SpecimenSettings(rmin_mm=0.3, width_mm=20, height_mm=40)  # ~1 s a run: time to kill one
WORKERS_BACK_S = 240  # a nanny's new worker imports the engine anew: slow on cores the suite keeps busy


@pytest.fixture(scope="module")
def worker_cache(tmp_path_factory):
    return tmp_path_factory.mktemp("worker_cache")


@pytest.fixture(scope="module")
def cluster(worker_cache):
    """Two one-thread worker processes on loopback, reached over tcp:// like a real cluster,
    with a specimen cache of their own (as on other machines)."""
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None, env={"ROCKCAL_CACHE": str(worker_cache)}) as cluster:
        yield cluster


def specs(settings, n, **fixed):
    return [run_spec("ucs", settings, {"E_c": 15.0 + i, "sigma_c": 40.0} | fixed) for i in range(n)]


@pytest.mark.slow
def test_campaign_on_dask_gives_the_serial_answer_bit_for_bit(tmp_path):
    records = {}
    for name, make in (("serial", lambda s: Executor(s, workers=1)),
                       ("dask", lambda s: DaskExecutor(s, "local:2"))):
        store = RunStore(tmp_path / name)
        executor = make(store)
        try:
            records[name] = calibrate(planned(parse_campaign(CAMPAIGN, tmp_path)), executor)
            if name == "dask":  # the workers read the driver's specimen cache
                assert set(executor.client.run(os.getenv, "ROCKCAL_CACHE").values()) == {os.environ["ROCKCAL_CACHE"]}
        finally:
            executor.close()
        assert executor.executed == records[name].dem_runs == store.count()
        assert set(store.executions().values()) == {1}
        store.close()
    serial, dask = records["serial"], records["dask"]
    assert dask.identified == serial.identified
    assert dask.verified == serial.verified  # floats compared exactly
    assert [it.verified for it in dask.iterations] == [it.verified for it in serial.iterations]
    assert dask.dem_run_keys == serial.dem_run_keys


@pytest.mark.slow
def test_workers_without_the_drivers_cache_get_its_packing_and_make_none(cluster, worker_cache, tmp_path):
    spec = specs(TINY.model_copy(update={"seed": 11}), 1, mu=0.35)
    serial = Executor(RunStore(tmp_path / "serial"), workers=1).run(spec)[0]  # packs in the driver's cache
    name = packing_file(spec[0])
    executor = DaskExecutor(RunStore(tmp_path / "dask"), cluster.scheduler_address)
    try:
        on_cluster = executor.run(spec)[0]
    finally:
        executor.close()
    assert on_cluster.status == serial.status == "ok"
    assert on_cluster.responses == serial.responses
    assert executor.packings.made == 0
    # the workers' cache holds the driver's packing, written there, not made (a genesis locks its file)
    assert (worker_cache / name).read_bytes() == stored_packing(name).read_bytes()
    assert not (worker_cache / name).with_suffix(".lock").exists()


@pytest.mark.slow
def test_a_packing_no_cache_holds_is_made_once_on_the_cluster(cluster, worker_cache, tmp_path):
    batch = specs(TINY.model_copy(update={"seed": 12}), 3)  # three runs of one packing
    name = packing_file(batch[0])
    assert stored_packing(name) is None
    executor = DaskExecutor(RunStore(tmp_path / "dask"), cluster.scheduler_address)
    shown = []
    executor.on_genesis = lambda made, total: shown.append((made, total))
    try:
        results = executor.run(batch)
    finally:
        executor.close()
    assert [r.status for r in results] == ["ok"] * 3 and executor.packings.made == 1
    assert shown == [(0, 1), (1, 1)]
    assert stored_packing(name).read_bytes() == (worker_cache / name).read_bytes()  # the driver keeps it


def running_runs(keys) -> bool:
    return any(str(key).startswith("rockcal-run-") for key in keys)


def kill_a_busy_worker(client, after_s: float = 0.3) -> dict:
    """In the background, SIGKILL a worker process that is running a run (not making a
    packing); returns (filled in when done) its pid and the tasks it held."""
    killed = {}

    def watch():
        deadline = time.time() + 60
        while time.time() < deadline:
            if any(map(running_runs, client.processing().values())):
                time.sleep(after_s)  # let the run get going
                busy = {w: keys for w, keys in client.processing().items() if running_runs(keys)}
                if busy:
                    worker, keys = next(iter(busy.items()))
                    pid = client.run(os.getpid, workers=[worker])[worker]
                    os.kill(pid, signal.SIGKILL)
                    killed.update(pid=pid, keys=set(keys))
                    return
            time.sleep(0.01)

    killed["thread"] = threading.Thread(target=watch, daemon=True)
    killed["thread"].start()
    return killed


def run_killing_a_worker(executor, batch):
    """Run `batch`, both workers up, while a busy worker is killed; returns (results, what was
    killed). The nanny's new worker is waited for by the next call, not here: the runs' fate is
    known without it."""
    client = executor.client
    client.wait_for_workers(2, timeout=WORKERS_BACK_S)
    executor.packings.ready(batch)  # the packing first: the watch below waits for runs alone
    killed = kill_a_busy_worker(client)
    results = executor.run(batch)
    killed["thread"].join()
    return results, killed


@pytest.mark.slow
def test_a_worker_killed_mid_run_loses_nothing_and_duplicates_nothing(cluster, tmp_path):
    store = RunStore(tmp_path)
    executor = DaskExecutor(store, cluster.scheduler_address)
    batch = specs(SLOWER, 6)
    try:
        results, killed = run_killing_a_worker(executor, batch)
        pids_after = set(executor.client.run(os.getpid).values())
    finally:
        executor.close()
    assert "pid" in killed, "no worker was busy to be killed"
    assert killed["pid"] not in pids_after  # the nanny replaced the killed worker
    assert killed["keys"] <= {f"rockcal-run-{s.key}" for s in batch}
    assert [r.status for r in results] == ["ok"] * len(batch)
    assert store.executions() == {s.key: 1 for s in batch}  # each run stored exactly once
    assert [store.get(s).responses for s in batch] == [r.responses for r in results]


@pytest.mark.slow
def test_a_task_that_keeps_killing_workers_is_a_failed_run(cluster, tmp_path):
    store = RunStore(tmp_path)
    executor = DaskExecutor(store, cluster.scheduler_address)
    batch = specs(SLOWER, 2, mu=0.4)
    cluster.scheduler.allowed_failures = 0  # the first worker death is fatal to its tasks
    try:
        results, killed = run_killing_a_worker(executor, batch)
    finally:
        cluster.scheduler.allowed_failures = 3
        executor.close()
    failed = [r for r in results if r.status == "failed"]
    assert failed and all(r.message.startswith("KilledWorker: ") for r in failed)
    assert store.executions() == {s.key: 1 for s in batch}
    assert [store.get(s).status for s in batch] == [r.status for r in results]


@pytest.mark.slow
def test_a_run_that_raises_is_stored_as_failed_and_the_batch_completes(cluster, tmp_path):
    narrow = SpecimenSettings(rmin_mm=0.4, width_mm=2, height_mm=16)  # narrower than 4 particles
    batch = specs(TINY, 3, mu=0.45) + specs(narrow, 1)
    store = RunStore(tmp_path)
    executor = DaskExecutor(store, cluster.scheduler_address)
    try:
        results = executor.run(batch)
        again = executor.run(batch)
    finally:
        executor.close()
    assert [r.status for r in results] == ["ok", "ok", "ok", "failed"]
    assert "width_mm" in results[-1].message and "too small" in results[-1].message
    assert store.get(batch[-1]).message == results[-1].message
    assert executor.executed == 4  # the second call found everything in the store
    assert [r.responses for r in again] == [r.responses for r in results]
    assert store.executions() == {s.key: 1 for s in batch}


@pytest.mark.slow
def test_a_run_past_its_time_limit_is_recorded_as_timed_out(cluster, tmp_path):
    store = RunStore(tmp_path)
    executor = DaskExecutor(store, cluster.scheduler_address, time_limit_s=0.01)
    batch = specs(TINY, 2, mu=0.55)
    try:
        results = executor.run(batch)
    finally:
        executor.close()
    assert [r.status for r in results] == ["timed out"] * 2
    assert all("0.01 s" in r.message for r in results)
    assert [store.get(s).status for s in batch] == ["timed out"] * 2


@pytest.mark.parametrize("text, expected", [
    ("local:3", ("local", 3)), (" local:1 ", ("local", 1)),
    ("tcp://10.0.0.5:8786", ("tcp", "tcp://10.0.0.5:8786")),
    ("tcp://head-node.cluster:8786", ("tcp", "tcp://head-node.cluster:8786"))])
def test_scheduler_forms(text, expected):
    assert parse_scheduler(text) == expected


@pytest.mark.parametrize("text", ["bogus", "local:0", "local:-2", "local:x", "local", "tcp://host",
                                  "tcp://host:0", "tcp://host:99999", "http://host:8786", ""])
def test_bad_scheduler_strings_name_the_option(text):
    with pytest.raises(InputError, match="^--scheduler: "):
        parse_scheduler(text)


def test_an_unreachable_scheduler_is_an_input_error(tmp_path, monkeypatch):
    monkeypatch.setattr(dask_executor, "CONNECT_TIMEOUT_S", 1.0)
    started = time.time()
    with pytest.raises(InputError, match="^--scheduler: cannot reach the Dask scheduler at tcp://127.0.0.1:9 "):
        DaskExecutor(RunStore(tmp_path), "tcp://127.0.0.1:9")
    assert time.time() - started < 20


def test_without_dask_installed_the_option_is_an_input_error(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import fails as if not installed
    with pytest.raises(InputError, match=r"^--scheduler: Dask is not installed; pip install 'rockcal\[dask\]'"):
        DaskExecutor(RunStore(tmp_path), "local:1")
