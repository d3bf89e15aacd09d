"""Running forward runs (`rockcal.campaign.runs.spec`): a virtual lab test
(`rockcal.labtests.registry`) for one parameter set, on many cores, through the run store (a run
in the store is never run again).

Workers are separate processes (spawned, so numba's threads are never forked); each loads the
specimen from the on-disk specimen cache once, not per run. A running test takes its share of
the cores, counted afresh as it runs: one each while both of two workers are busy, both for
the last run of a batch once the other worker is idle (the engine's numbers do not depend on
its thread count). A running test reports its reading (strain and stress, or displacement and
load) about once a second, so a long run shows that it moves.

Ctrl-C is the parent's alone: workers start with SIGINT blocked and then ignore it, and an
interrupted parent stops them at once, storing nothing of the runs they had in hand.
"""

from __future__ import annotations

import os
import signal
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from contextlib import contextmanager
from functools import lru_cache
from multiprocessing import get_context
from pathlib import Path
from typing import Callable, Iterable

import numba
import numpy as np

from rockcal.campaign.runs.packings import make_in_turn, new_packings
from rockcal.campaign.runs.retries import stored_result
from rockcal.campaign.runs.spec import RunResult, RunSpec, params_of
from rockcal.campaign.runs.store import RunStore
from rockcal.dem.laws import BROKEN_SHEAR, BROKEN_TENSION
from rockcal.dem.simulate import use_threads
from rockcal.labtests import snapshots
from rockcal.labtests.kind import all_settings
from rockcal.labtests.registry import lab_test

POOL_RESTARTS = 3
LIVE_INTERVAL_S = 1.0  # a running test reports its reading at most this often
_live = None  # where a running test reports to: a worker's queue, or the serial executor
_busy = None  # a pool's count of running tests (shared by its workers), or None
_cores = 1


@lru_cache(maxsize=4)
def specimen_of(kind: str, specimen: tuple):
    """The specimen of a run's specimen settings, made once per process (from the disk cache
    when it holds it)."""
    return lab_test(kind).make(dict(specimen))


def prepare(spec: RunSpec) -> None:
    """Make (and cache on disk) the specimen of a run before its runs need it, on this run's
    share of the cores; one that cannot be made is left to `execute`, which records the run as
    failed."""
    _count_running(+1)
    try:
        _take_share_of_cores()
        specimen_of(spec.kind, spec.specimen)
    except Exception:
        pass
    finally:
        _count_running(-1)


class RunTimedOut(Exception):
    """A forward run went past its wall-time limit."""


def execute(spec: RunSpec, time_limit_s: float | None = None, snapshots_in: Path | None = None) -> RunResult:
    """Run one forward test; a run that raises is a failed result, not an exception, and a run
    past `time_limit_s` is stopped and recorded as timed out. With `snapshots_in` (a store's
    folder) a long test keeps snapshots there and goes on from its last one
    (`rockcal.labtests.snapshots`); its time, and its limit, then count the time before."""
    started = last = time.perf_counter()
    earlier_s = 0.0  # the run's time before the snapshot it went on from
    _count_running(+1)
    _take_share_of_cores()  # from the start (the specimen's genesis too), not the first reading

    def run_s() -> float:
        """The run's time so far, its stopped parts' included."""
        return time.perf_counter() - started + earlier_s

    def watch(x: float, y: float):
        nonlocal last, earlier_s
        _take_share_of_cores()
        earlier_s = snapshots.earlier_s()
        now = time.perf_counter()
        if time_limit_s is not None and run_s() > time_limit_s:
            raise RunTimedOut(f"stopped after the run's wall-time limit of {time_limit_s:g} s")
        if _live is not None and now - last >= LIVE_INTERVAL_S:
            last = now
            _live.put((spec.key, spec.kind, dimensions, float(x), float(y), run_s()))

    settings = all_settings(dict(spec.specimen))
    dimensions = settings["dimensions"]
    try:
        test = lab_test(spec.kind).of_dimensions(dimensions)
        specimen = specimen_of(spec.kind, spec.specimen)
        with snapshots.kept_in(snapshots_in, spec.key):
            r = test.run(params_of(spec), specimen, settings, watch)
            earlier_s = snapshots.earlier_s()
        responses = test.responses_of(r) | {
            "n_broken_tension": r.n_broken_tension, "n_broken_shear": r.n_broken_shear,
            "steps": r.steps} | specimen.description()
        bad = [k for k, v in responses.items() if v != v]  # NaN: no usable reading
        if bad:
            raise ValueError(f"no reading of {bad[0]} (the specimen did not load up)")
        return RunResult("ok", responses, r.curve, run_s(), cracks=crack_rows(r.cracks))
    except RunTimedOut as exc:
        return RunResult("timed out", {}, None, run_s(), str(exc))
    except Exception as exc:  # a run that raises is recorded as failed, the campaign goes on
        if interrupted(exc):
            raise KeyboardInterrupt from None
        return RunResult("failed", {}, None, run_s(), f"{type(exc).__name__}: {exc}")
    finally:
        _count_running(-1)


def interrupted(exc: BaseException) -> bool:
    """An exception that a Ctrl-C caused: numba's compiled code, interrupted, raises a
    SystemError whose cause is the KeyboardInterrupt."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return False


@contextmanager
def sigint_blocked():
    """Within it SIGINT waits (it is not lost): a worker process started here inherits the
    blocked signal, so a Ctrl-C never reaches it before `_init_worker` ignores it."""
    if not hasattr(signal, "pthread_sigmask"):
        yield
        return
    before = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, before)


def _count_running(change: int) -> None:
    if _busy is not None:
        with _busy.get_lock():
            _busy.value += change


def _take_share_of_cores() -> None:
    """On a pool worker, run on this test's share of the cores as of now."""
    if _busy is not None:
        threads = max(1, _cores // max(1, _busy.value))
        if threads != numba.get_num_threads():
            numba.set_num_threads(threads)


def crack_rows(cracks: dict[str, np.ndarray]) -> np.ndarray:
    """Broken bonds as rows (x m, y m, mode) in 2D, (x m, y m, z m, mode) in 3D: 1 tension, 2 shear."""
    return np.vstack([np.column_stack([cracks[mode], np.full(len(cracks[mode]), code)])
                      for code, mode in ((BROKEN_TENSION, "tension"), (BROKEN_SHEAR, "shear"))])


def _init_worker(cores: int, busy, live, live_interval_s: float, threads: int | None) -> None:
    """A pool worker's settings: its runs share `cores` (or, `threads` given, that many each at
    most, free or not) and report to `live`."""
    global _live, _busy, _cores, LIVE_INTERVAL_S
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's: it stops the workers
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    _live, _busy = live, busy
    LIVE_INTERVAL_S = live_interval_s  # the parent's: a spawned worker imports the module anew
    _cores = min(threads or cores, numba.config.NUMBA_NUM_THREADS)
    use_threads(None if threads is None else 1)


def live_lines(readings: dict[str, tuple]) -> list[str]:
    """A line per running test: its title, short key, latest reading and time so far."""
    return [f"{lab_test(kind).title} {key[:6]}: {lab_test(kind).of_dimensions(dimensions).reading(x, y)}, "
            f"{elapsed:.0f} s" for key, (kind, dimensions, x, y, elapsed) in readings.items()]


class _Shown:
    """The serial executor's `_live`: readings go straight to the display."""

    def __init__(self, executor: "Executor"):
        self.executor = executor

    def put(self, item) -> None:
        self.executor._reading(item)


def split_stored(store: RunStore, specs: list[RunSpec],
                 tried: set[str] | frozenset = frozenset()) -> tuple[dict[str, RunResult], list[RunSpec]]:
    """The results already in the store (by key) and the distinct specs still to run (a stored
    failure runs again: `retries`)."""
    results: dict[str, RunResult] = {}
    todo: dict[str, RunSpec] = {}
    for spec in specs:
        if spec.key in results or spec.key in todo:
            continue
        found = stored_result(store, spec, tried)
        if found is not None:
            results[spec.key] = found
        else:
            todo[spec.key] = spec
    return results, list(todo.values())


class Executor:
    """Runs specs through the store: serially (workers=1) or on a process pool."""

    def __init__(self, store: RunStore, workers: int = 0, time_limit_s: float | None = None,
                 threads: int | None = None):
        self.store = store
        self.workers = workers if workers > 0 else (os.cpu_count() or 1)
        self.time_limit_s = time_limit_s
        self.threads = threads  # a run's threads at most, free cores or not (None: its share of the free ones)
        self._pool = None
        self._queue = None
        self.executed = 0  # runs done by this executor (not found in the store)
        self.tried: set[str] = set()  # keys run by this executor: a failure among them is not rerun
        self.on_live: Callable[[list[str]], None] | None = None  # shows `live_lines` of running tests
        self.on_genesis: Callable[[int, int], None] | None = None  # shows the packings made of those to make
        self._readings: dict[str, tuple] = {}

    def _reading(self, item) -> None:
        key, *reading = item
        self._readings[key] = tuple(reading)
        self._show()

    def _done(self, key: str) -> None:
        if self._readings.pop(key, None) is not None:
            self._show()

    def _show(self) -> None:
        if self.on_live is not None:
            self.on_live(live_lines(self._readings))

    def _drain(self) -> None:
        while self._queue is not None and not self._queue.empty():
            try:
                self._reading(self._queue.get_nowait())
            except Exception:  # queue.Empty, or a reading cut short by a dying worker
                break

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(cancel_futures=True)

    def _stop_now(self) -> None:
        """Stop the pool's workers at once (a Ctrl-C): the runs they had in hand are not stored."""
        pool, self._pool = self._pool, None
        if pool is None:
            return
        # the queue of tasks' feeder thread may be blocked on a pipe that no stopped worker
        # reads: not waited for, or the pool's shutdown, and Python's exit, wait for ever
        pool._call_queue.cancel_join_thread()
        for process in list((pool._processes or {}).values()):
            process.terminate()
        pool.shutdown(wait=False, cancel_futures=True)

    def _get_pool(self) -> ProcessPoolExecutor:
        if self._pool is None:
            context = get_context("spawn")
            self._queue = context.Queue()
            self._pool = ProcessPoolExecutor(
                self.workers, mp_context=context, initializer=_init_worker,
                initargs=(os.cpu_count() or 1, context.Value("i", 0), self._queue,
                          LIVE_INTERVAL_S, self.threads))
        return self._pool

    def run(self, specs: Iterable[RunSpec],
            progress: Callable[[int, int], None] | None = None) -> list[RunResult]:
        """Results in the order of `specs`; each new one is stored as soon as it is done."""
        global _live
        batch = Batch(self.store, specs, None, self.tried)
        self._make_packings(new_packings(batch.todo))
        batch.show(progress)
        try:
            if self.workers == 1 or len(batch.todo) <= 1:
                if self.threads is not None:
                    use_threads(self.threads)
                _live = _Shown(self)
                for spec in batch.todo:
                    batch.finish(spec, execute(spec, self.time_limit_s, self.store.path.parent))
                    self._done(spec.key)
            else:
                self._run_on_pool(batch)
        finally:
            _live = None
            self.executed += batch.executed
        return batch.in_order()

    def _make_packings(self, specs: list[RunSpec]) -> None:
        """Make the packings of `specs` (`packings.new_packings`) into the specimen cache: one
        per worker at a time, or here where there is one worker or one packing."""
        if self.workers == 1 or len(specs) <= 1:
            make_in_turn(specs, prepare, self.on_genesis)
            return
        show = self.on_genesis or (lambda done, total: None)
        try:
            with sigint_blocked():
                futures = [self._get_pool().submit(prepare, spec) for spec in specs]
            show(0, len(specs))
            pending = set(futures)
            while pending:  # in short waits, as the runs': a Ctrl-C is taken between them
                finished, pending = wait(pending, timeout=LIVE_INTERVAL_S, return_when=FIRST_COMPLETED)
                if finished:
                    show(len(specs) - len(pending), len(specs))
        except BaseException:  # a Ctrl-C
            self._stop_now()
            raise
        if any(f.exception() is not None for f in futures):  # a worker died: the runs get a new pool
            self._pool.shutdown(cancel_futures=True)
            self._pool = None

    def _run_on_pool(self, batch: Batch) -> None:
        """Run on the process pool; a worker process that dies breaks the pool, which is made
        anew for the runs not yet done (after POOL_RESTARTS new pools they are recorded failed)."""
        try:
            self._run_on_workers(batch)
        except BaseException:  # a Ctrl-C: nothing more is stored, the workers stop now
            self._stop_now()
            raise

    def _run_on_workers(self, batch: Batch) -> None:
        todo = batch.todo
        for attempt in range(POOL_RESTARTS + 1):
            with sigint_blocked():  # the workers it starts ignore Ctrl-C from their first instruction
                futures = {self._get_pool().submit(execute, spec, self.time_limit_s, self.store.path.parent): spec
                           for spec in todo}
            pending = set(futures)
            while pending:
                finished, pending = wait(pending, timeout=LIVE_INTERVAL_S, return_when=FIRST_COMPLETED)
                self._drain()
                for future in finished:
                    self._done(futures[future].key)
                    try:
                        result = future.result()
                    except BrokenProcessPool:
                        continue
                    batch.finish(futures[future], result)
            todo = [spec for spec in todo if spec.key not in batch.results]
            if not todo:
                return
            self._pool.shutdown(cancel_futures=True)
            self._pool = None
        for spec in todo:
            batch.finish(spec, RunResult("failed", {}, None, 0.0, "a worker process died during "
                                         "the run, on every try"))


class Batch:
    """One call of an executor's `run`: the results the store already holds, the runs still to
    do, and the progress over both; each run done is stored as it finishes."""

    def __init__(self, store: RunStore, specs: Iterable[RunSpec],
                 progress: Callable[[int, int], None] | None, tried: set[str] | None = None):
        self.store, self.specs, self.progress = store, list(specs), progress
        self.tried = set() if tried is None else tried  # keys run by the executor so far
        self.results, self.todo = split_stored(store, self.specs, self.tried)
        self.total = len(self.results) + len(self.todo)
        self.executed = 0  # runs of this batch stored as done
        self._report()

    def show(self, progress: Callable[[int, int], None] | None) -> None:
        """Report the progress from now on to `progress` (after the genesis of the batch's
        packings, so that their bar comes first)."""
        self.progress = progress
        self._report()

    def finish(self, spec: RunSpec, result: RunResult, store: bool = True) -> None:
        """Record a run's result; `store=False` keeps it out of the store (it runs again later)."""
        if store:
            self.store.put(spec, result)
            self.tried.add(spec.key)
            self.executed += 1
        self.results[spec.key] = result
        self._report()

    def in_order(self) -> list[RunResult]:
        return [self.results[s.key] for s in self.specs]

    def _report(self) -> None:
        if self.progress:
            self.progress(len(self.results), self.total)
