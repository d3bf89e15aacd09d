"""The atomic operations the engine's threads share tasks by (`rockcal.dem.atomics`): exact
counts from threads adding at once, and one winner of a claim."""

import numba
import numpy as np
import pytest
from numba import njit, prange

from rockcal.dem import atomics


@pytest.fixture(autouse=True)
def _two_threads():
    """Two threads at once, also in a test worker that otherwise runs one."""
    cap = numba.get_num_threads()
    numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))
    yield
    numba.set_num_threads(cap)


@njit(parallel=True)
def _add_from_threads(counters, threads, adds):
    for _ in prange(threads):
        for _k in range(adds):
            atomics.fetch_add(counters, 0, 1)


@njit(parallel=True)
def _claim_from_threads(slots, wins, threads):
    for w in prange(threads):
        for s in range(slots.shape[0]):
            if atomics.compare_exchange(slots, s, 0, w + 1):
                atomics.fetch_add(wins, 0, 1)


def test_threads_adding_at_once_lose_no_addition():
    threads = numba.get_num_threads()
    counters = np.zeros(8, np.int64)
    _add_from_threads(counters, threads, 200_000)
    assert counters[0] == threads * 200_000


def test_each_slot_is_claimed_by_one_thread_only():
    slots, wins = np.zeros(1000, np.int64), np.zeros(1, np.int64)
    _claim_from_threads(slots, wins, numba.get_num_threads())
    assert wins[0] == 1000 and (slots > 0).all()


@njit
def _sequence():
    a = np.zeros(2, np.int64)
    before = atomics.fetch_add(a, 1, 5)
    lost = atomics.compare_exchange(a, 1, 4, 9)
    won = atomics.compare_exchange(a, 1, 5, 7)
    return before, lost, won, atomics.load(a, 1), atomics.yield_core()


def test_one_thread_sees_what_it_did():
    assert _sequence() == (0, False, True, 7, 0)
