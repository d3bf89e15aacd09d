"""Forward runs on a Dask cluster: the same results and store as `Executor`, on many machines.

Run specs (a few hundred bytes) travel to the workers, and with each the packing its specimen
is cut from, made once on the cluster or read from the driver's cache (`cluster_packings`):
a worker without the driver's disk makes no packing again. The driver alone writes the store,
each run as soon as it finishes. A worker killed mid-run makes the scheduler
run its tasks elsewhere; a task that still errors is a failed run, never an exception.

Tasks and results are pickles: whoever reaches a scheduler can run code on its workers. A
tls:// scheduler is reached with mutual TLS (`distributed.Security`), its certificates from
--tls-ca-file/--tls-cert/--tls-key or from the Dask config (distributed.comm.tls); tcp:// is
for a network no one else is on.
"""

from __future__ import annotations

import importlib.util
import logging
import os
import re
import time
from concurrent.futures import CancelledError
from typing import Callable, Iterable

from rockcal.campaign.runs import MAX_WORKERS
from rockcal.campaign.runs.tls import CLEAR_TEXT, TLSFiles, security_of
from rockcal.campaign.runs.cluster_packings import ClusterPackings, Packing, install
from rockcal.campaign.runs.pool import Batch, execute
from rockcal.campaign.runs.spec import ENGINE
from rockcal.campaign.runs.store import RunStore
from rockcal.campaign.runs.spec import RunResult, RunSpec
from rockcal.errors import InputError

log = logging.getLogger(__name__)

OPTION = "--scheduler"
CONNECT_TIMEOUT_S = 10.0
FORMS = f"tls://HOST:PORT, tcp://HOST:PORT or local:N (1 <= N <= {MAX_WORKERS})"
def parse_scheduler(scheduler: str) -> tuple[str, int | str]:
    """("local", N), ("tls", "tls://HOST:PORT") or ("tcp", "tcp://HOST:PORT"); InputError naming
    --scheduler for anything else, or when Dask is not installed. Connects to nothing (the CLI
    checks before any store)."""
    if importlib.util.find_spec("distributed") is None:
        raise InputError(OPTION, "Dask is not installed; pip install 'rockcal[dask]'")
    text = scheduler.strip()
    local = re.fullmatch(r"local:([+-]?\d+)", text)
    if local:
        n = int(local.group(1))
        if not 1 <= n <= MAX_WORKERS:
            raise InputError(OPTION, f"local:N needs 1 to {MAX_WORKERS} workers, got {text!r}")
        return "local", n
    remote = re.fullmatch(r"(tcp|tls)://([\w.-]+|\[[0-9A-Fa-f:.]+\]):(\d+)", text)
    if remote and 1 <= int(remote.group(3)) <= 65535:
        return remote.group(1), text
    raise InputError(OPTION, f"expected {FORMS}, got {scheduler!r}")


def run_on_worker(spec: RunSpec, time_limit_s: float | None, packing: Packing | None = None) -> RunResult:
    """The task: its `packing` into the worker's specimen cache, then `execute` on one numba
    thread (set per thread; the cluster's processes are the parallelism)."""
    import numba

    numba.set_num_threads(1)
    install(packing)
    return execute(spec, time_limit_s)


def worker_engine() -> str:
    """The engine a worker runs (checked against the driver's on connecting)."""
    return ENGINE


class DaskExecutor:
    """Runs specs through the store on a Dask cluster: tcp://HOST:PORT, or local:N processes."""

    def __init__(self, store: RunStore, scheduler: str, time_limit_s: float | None = None,
                 tls: TLSFiles | None = None):
        self.store = store
        self.time_limit_s = time_limit_s
        self.executed = 0  # runs done by this executor (not found in the store)
        self.tried: set[str] = set()  # keys run by this executor: a failure among them is not rerun
        self.on_genesis = None  # shows the packings made of those to make
        self.cluster = None
        kind, where = parse_scheduler(scheduler)
        from distributed import Client, LocalCluster

        security, self.security_source = security_of(kind, tls)  # where the certificates come from
        if kind == "local":
            self.cluster = _local_cluster(LocalCluster, where)
            self.client = Client(self.cluster)
        else:
            if kind == "tcp":
                log.warning(CLEAR_TEXT, where)
            self.client = _connect(Client, where, security)
        self.packings = ClusterPackings(self.client)

    def close(self) -> None:
        self.client.close()
        if self.cluster is not None:
            self.cluster.close()

    def run(self, specs: Iterable[RunSpec],
            progress: Callable[[int, int], None] | None = None) -> list[RunResult]:
        """Results in the order of `specs`; each new one is stored as soon as it is done."""
        from distributed import as_completed

        batch = Batch(self.store, specs, None, self.tried)
        self.packings.ready(batch.todo, self.on_genesis)
        batch.show(progress)
        submitted = time.perf_counter()
        futures = {self.client.submit(run_on_worker, spec, self.time_limit_s, self.packings.of(spec),
                                      key=f"rockcal-run-{spec.key}"): spec for spec in batch.todo}
        try:
            for future in as_completed(futures):
                spec = futures.pop(future)
                result, finished = _result(future, submitted)
                future.release()
                batch.finish(spec, result, store=finished)
        finally:
            if futures:  # interrupted: do not leave the cluster working for no one
                self.client.cancel(list(futures))
            self.executed += batch.executed
        return batch.in_order()


def _result(future, submitted: float) -> tuple[RunResult, bool]:
    """The run's result and whether it finished (a task that errored finished as failed; one
    cancelled with the scheduler did not, and runs again on resume)."""
    try:
        return future.result(), True
    except CancelledError as exc:
        message = f"cancelled by the Dask scheduler ({_one_line(exc)}); not stored, runs again on resume"
        return RunResult("failed", {}, None, time.perf_counter() - submitted, message), False
    except Exception as exc:  # KilledWorker after too many worker deaths, or the task raised
        message = f"{type(exc).__name__}: {_one_line(exc)}"
        log.warning("forward run %s failed on the cluster: %s", future.key, message)
        return RunResult("failed", {}, None, time.perf_counter() - submitted, message), True


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split())


def _local_cluster(LocalCluster, n: int):
    """N one-thread worker processes on loopback, no dashboard; workers see ROCKCAL_CACHE."""
    env = {name: os.environ[name] for name in ("ROCKCAL_CACHE", "ROCKCAL_MAX_GRAINS") if name in os.environ}
    if n > (os.cpu_count() or 1):
        log.warning("local:%d starts more worker processes than this machine's %d cores", n,
                    os.cpu_count() or 1)
    try:
        return LocalCluster(n_workers=n, threads_per_worker=1, processes=True, host="127.0.0.1",
                            dashboard_address=None, env=env)
    except Exception as exc:
        raise InputError(OPTION, f"cannot start local:{n}: {_one_line(exc)}") from None


def _connect(Client, address: str, security=None):
    """A client of the scheduler at `address` (with `security` for tls://) whose workers run
    this engine."""
    try:
        client = Client(address, timeout=CONNECT_TIMEOUT_S, security=security)
    except (OSError, TimeoutError) as exc:
        why = f" ({_one_line(exc)})" if security is not None and str(exc) else ""
        raise InputError(OPTION, f"cannot reach the Dask scheduler at {address} "
                                 f"within {CONNECT_TIMEOUT_S:g} s{why}") from None
    try:
        engines = client.run(worker_engine)
    except Exception as exc:
        client.close()
        raise InputError(OPTION, f"workers of {address} cannot run rockcal: {_one_line(exc)}") from None
    wrong = {w: e for w, e in engines.items() if e != ENGINE}
    if wrong:
        client.close()
        worker, engine = next(iter(wrong.items()))
        raise InputError(OPTION, f"worker {worker} runs {engine}, this driver {ENGINE}; "
                                 "install the same rockcal on every worker")
    if not engines:
        log.warning("the Dask scheduler at %s has no workers yet; runs wait for them", address)
    threads = {w: n for w, n in client.nthreads().items() if n > 1}
    if threads:
        log.warning("workers of %s have several threads, which take turns (the engine holds "
                    "the GIL); start one single-thread worker per core (--nthreads 1)", address)
    return client
