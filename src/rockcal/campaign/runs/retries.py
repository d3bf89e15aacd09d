"""Runs that failed or timed out stay in the store with why, and run again when a campaign
needs them: at most once per campaign call, and MAX_TRIES times in all, so a run that fails
every time (a specimen that cannot be made) stops costing anything."""

from __future__ import annotations

from dataclasses import replace

from rockcal.campaign.runs.store import RunStore

from rockcal.campaign.runs.spec import RunResult, RunSpec

MAX_TRIES = 3


def stored_result(store: RunStore, spec: RunSpec, tried: set[str] | frozenset = frozenset()) -> RunResult | None:
    """The stored result to reuse for `spec`: a run done, a failure already tried by this call
    (`tried`), or one at MAX_TRIES (its message says so); None when it must run."""
    found = store.get(spec)
    if found is None or found.status == "ok" or spec.key in tried:
        return found
    tries = store.tries(spec.key)
    if tries < MAX_TRIES:
        return None
    return replace(found, message=f"{found.message} (failed {tries} times; not run again)")


def holds(store: RunStore, spec: RunSpec) -> bool:
    """The store holds a result of `spec` that a campaign reuses."""
    return stored_result(store, spec) is not None


def retry_line(store: RunStore) -> str | None:
    """The first screen's word on the failed and timed-out runs in the store (None: none)."""
    failures = store.failures()
    if not failures:
        return None
    timed_out = sum(status == "timed out" for _, status, _ in failures)
    spent = sum(tries >= MAX_TRIES for _, _, tries in failures)
    kinds = f" ({timed_out} timed out)" if timed_out else ""
    left = f"; {spent} of them failed {MAX_TRIES} times and will not be" if spent else ""
    return (f"failed runs in the store: {len(failures)}{kinds}; each is run again if this campaign "
            f"needs it (at most {MAX_TRIES} tries){left}")
