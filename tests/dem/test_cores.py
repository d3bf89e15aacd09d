"""The engine runs on no more threads than there are free cores, unless told how many."""

from types import SimpleNamespace

import numba
import numpy as np
import pytest

from rockcal.dem import simulate
from rockcal.dem.cores import Sample, free_cores


def after(seconds: float, others_s: float, own_s: float, cores: int = 2) -> Sample:
    """A sample `seconds` after one at zero, in which the other processes and this one took
    these processor seconds (100 clock ticks a second)."""
    return Sample(seconds, own_s, round(100 * (others_s + own_s)), round(100 * cores * seconds), cores)


ZERO = Sample(0.0, 0.0, 0, 0, 2)


@pytest.mark.parametrize("others_s, own_s, free", [
    (0.0, 0.5, 2),  # idle but for this process on one core
    (0.0, 1.0, 2),  # this process on both
    (1.0, 1.0, 1),  # a CPU-bound process, this one on one thread beside it
    (0.67, 1.33, 1),  # the same, this one on two threads
    (1.33, 0.67, 1),  # two, this one on one thread beside them
    (0.2, 1.0, 2),  # a little background work
])
def test_free_cores_are_the_cores_less_the_other_processes_time(others_s, own_s, free):
    assert free_cores(ZERO, after(1.0, others_s, own_s)) == free


def test_no_clock_tick_no_estimate():
    assert free_cores(ZERO, ZERO) is None


@pytest.fixture
def two_threads():
    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("numba has one thread here")
    cap = numba.get_num_threads()
    numba.set_num_threads(2)
    yield
    simulate.use_threads(None)
    numba.set_num_threads(cap)


def threads_of_a_run(monkeypatch, free: int) -> int:
    """The threads `advance` runs a two-block specimen on, with `free` cores free."""
    seen = []
    monkeypatch.setattr(simulate._free_cores, "now", lambda: free)
    monkeypatch.setattr(simulate, "_advance_all", lambda state, n, threads: seen.append(numba.get_num_threads()))
    simulate.advance(SimpleNamespace(neighbours=SimpleNamespace(block_starts=np.array([0, 2000, 4000]))), 1)
    assert numba.get_num_threads() == 2  # numba's threads as they were
    return seen[0]


def test_by_default_one_thread_per_free_core(monkeypatch, two_threads):
    assert threads_of_a_run(monkeypatch, free=1) == 1
    assert threads_of_a_run(monkeypatch, free=2) == 2


def test_a_fixed_number_of_threads_whatever_the_load(monkeypatch, two_threads):
    simulate.use_threads(2)
    assert threads_of_a_run(monkeypatch, free=1) == 2
