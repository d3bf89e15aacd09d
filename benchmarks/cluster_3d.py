"""A 3D campaign on a Dask cluster against the same campaign on this machine's process pool.

Run by hand: `python benchmarks/cluster_3d.py [CAMPAIGN] [--workers 4] [--kill-after-s 60]`
(default campaign: docs/campaigns/granite-3d.toml). The cluster is a LocalCluster of one-thread
worker processes that speaks only mutual TLS (temporary certificates), each worker with a
specimen cache of its own, as on machines that share no disk; one busy worker is killed (SIGKILL)
`--kill-after-s` into the campaign, and its nanny starts a new one. Every specimen cache starts
empty. Prints each route's wall time and identified point, whether the two answers are the
same (exactly and to round-off), the packings made on the cluster and received by each worker,
and how often each run was executed.
"""

from __future__ import annotations

import argparse
import os
import signal
import tempfile
import threading
import time
from pathlib import Path

from distributed import WorkerPlugin

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.procedure.steps import calibrate
from rockcal.campaign.runs.dask import DaskExecutor
from rockcal.campaign.runs.pool import Executor
from rockcal.campaign.runs.store import RunStore
from rockcal.campaign.runs.tls import TLSFiles

ROOT = Path(__file__).resolve().parents[1]


class OwnCache(WorkerPlugin):
    """A worker plugin: each worker (a restarted one too) keeps its specimens in a folder of
    its own under `root`."""

    name = "rockcal-own-cache"

    def __init__(self, root: str):
        self.root = root

    def setup(self, worker) -> None:
        os.environ["ROCKCAL_CACHE"] = os.path.join(self.root, str(worker.name))


def tls_cluster(workers: int, folder: Path):
    """A LocalCluster speaking mutual TLS, and this client's certificate files for it."""
    from distributed import LocalCluster, Security

    security = Security.temporary()
    files = {"ca": security.tls_ca_file, "cert": security.tls_client_cert, "key": security.tls_client_key}
    for name, pem in files.items():
        (folder / f"{name}.pem").write_text(pem)
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, protocol="tls",
                           host="127.0.0.1", dashboard_address=None, security=security)
    return cluster, TLSFiles(folder / "ca.pem", folder / "cert.pem", folder / "key.pem")


def kill_a_busy_worker_after(client, after_s: float) -> dict:
    """In the background, after `after_s`, SIGKILL a worker running a forward run."""
    killed: dict = {}

    def watch():
        time.sleep(after_s)
        while not killed:
            busy = [w for w, keys in client.processing().items()
                    if any(str(k).startswith("rockcal-run-") for k in keys)]
            if busy:
                pid = client.run(os.getpid, workers=[busy[0]])[busy[0]]
                os.kill(pid, signal.SIGKILL)
                killed.update(pid=pid, at_s=time.perf_counter() - started)
            time.sleep(0.05)

    started = time.perf_counter()
    threading.Thread(target=watch, daemon=True).start()
    return killed


def run(campaign: Path, folder: Path, make_executor) -> tuple:
    store = RunStore(folder)
    executor = make_executor(store)
    started = time.perf_counter()
    try:
        record = calibrate(planned(parse_campaign(campaign.read_text(), campaign.parent)), executor)
    finally:
        executor.close()
    wall_s = time.perf_counter() - started
    executions = store.executions()
    store.close()
    return record, wall_s, executions, executor


def cache_files(root: Path) -> dict:
    """Per worker cache folder: packings made there (a genesis leaves its lock file) and received."""
    found = {}
    for folder in sorted(p for p in root.iterdir() if p.is_dir()):
        packings = list(folder.glob("*.npz"))
        made = sum(p.with_suffix(".lock").exists() for p in packings)
        found[folder.name] = (made, len(packings) - made)
    return found


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("campaign", nargs="?", type=Path, default=ROOT / "docs/campaigns/granite-3d.toml")
    parser.add_argument("--workers", type=int, default=4)
    parser.add_argument("--kill-after-s", type=float, default=60.0)
    args = parser.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="cluster_3d_"))
    print(f"load before: {os.getloadavg()[0]:.1f}; folder {folder}")

    os.environ["ROCKCAL_CACHE"] = str(folder / "pool-cache")
    pool, pool_s, pool_runs, _ = run(args.campaign, folder / "pool", lambda s: Executor(s, workers=2))
    print(f"process pool, 2 workers: {pool_s:.0f} s, {pool.dem_runs} runs, identified {pool.identified}")

    os.environ["ROCKCAL_CACHE"] = str(folder / "driver-cache")
    cluster, tls = tls_cluster(args.workers, folder)
    try:
        from distributed import Client

        with Client(cluster) as admin:
            admin.register_plugin(OwnCache(str(folder / "worker-caches")))
            killed = kill_a_busy_worker_after(admin, args.kill_after_s)
            dask, dask_s, dask_runs, executor = run(
                args.campaign, folder / "dask",
                lambda s: DaskExecutor(s, cluster.scheduler_address, tls=tls))
    finally:
        cluster.close()
    print(f"Dask over TLS, {args.workers} workers: {dask_s:.0f} s, {dask.dem_runs} runs, identified {dask.identified}")
    print(f"worker killed: {killed or 'none (the campaign ended first)'}")
    same = dask.identified == pool.identified and dask.verified == pool.verified
    close = all(abs(dask.identified[k] - v) <= 1e-12 * abs(v) for k, v in pool.identified.items())
    print(f"same answer: exactly {same}, to 1e-12 {close}; same runs {dask.dem_run_keys == pool.dem_run_keys}")
    print(f"packings made on the cluster: {executor.packings.made}; per worker cache (made, received): "
          f"{cache_files(folder / 'worker-caches')}")
    print(f"runs executed more than once: pool {sum(n > 1 for n in pool_runs.values())}, "
          f"Dask {sum(n > 1 for n in dask_runs.values())} of {len(dask_runs)}")
    print(f"load after: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
