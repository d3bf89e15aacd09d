"""Where a campaign's forward runs go: a local process pool, or a Dask cluster."""

from __future__ import annotations

from rockcal.campaign.runs.pool import Executor
from rockcal.campaign.runs.store import RunStore


def make_executor(store: RunStore, *, workers: int = 0, scheduler: str | None = None,
                  time_limit_s: float | None = None, tls=None, threads: int | None = None):
    """The executor of a campaign: a local process pool (each run on `threads` at most), or a
    Dask cluster with `scheduler` (reached with the `TLSFiles` `tls`, for tls://; each run on
    one thread)."""
    if scheduler is None:
        return Executor(store, workers, time_limit_s, threads)
    from rockcal.campaign.runs.dask import DaskExecutor

    return DaskExecutor(store, scheduler, time_limit_s, tls)
