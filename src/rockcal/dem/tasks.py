"""How the engines' threads share out a run of time steps inside one parallel region.

A step is phases of tasks (the ball engine's two: each block's pair forces and the pairs across
block borders in halves, then each block's border forces, walls and motion); a phase starts
once the one before is done. Starting a parallel region for each phase and waiting for it at
its end cost a sizeable part of a step of a few thousand grains (some 100 µs), so an engine's
compiled loop starts one region per call and its threads pass the phases among themselves
through counters in a shared int64 array (the atomic operations of `atomics`):

- a task is claimed before it runs (`claim`), so each runs once, and counted when done;
- each thread does the tasks it owns (task k of a phase: thread k mod threads), so a thread
  keeps working on the same grains, in its own cache, step after step;
- a thread waits for its phase to be done; kept waiting long, it does the tasks no thread has
  claimed yet: those of a thread that the system keeps from running. So the steps go on
  whichever threads run, also when the threading layer runs the threads' parts one after the
  other on one thread.

The tasks of a phase write separate particles, and each sums in a fixed order whichever thread
does it, so the numbers do not depend on the threads. An engine's
`task(r, s, shared, model, moved, half_skin_sq)` does task r of step s (its steps run by
`make_step(task)`): `model` is a tuple of its arrays, `moved` each moving part's largest
squared displacement since the neighbour list was built; a task of the first phase stops the
run (`stop_if_moved`) once one has moved half the skin.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from rockcal.dem import atomics

# Where the shared counters sit, each on a cache line of its own: the tasks done, whether (and
# at which step) the run stopped, then each task's claim (the steps its task was claimed for).
DONE, STOPPED, STOP_STEP, CLAIMS = 0, 8, 16, 24
# Polls of the tasks-done count before a waiting thread does the tasks of its phase that no
# thread has claimed yet.
HELP_AFTER_SPINS = 20_000


@njit(cache=True)
def scratch(moving_parts, tasks_per_step):
    """Each moving part's largest squared displacement and the shared counters, zeroed: made
    here, as in a parallel function numpy's constructors would each be a parallel region."""
    return np.zeros(moving_parts), np.zeros(CLAIMS + 8 * tasks_per_step, np.int64)


def make_step(task):
    """An engine's step function for its `task`: `step(phases, s, w, workers, shared, model,
    moved, half_skin_sq)` does thread w's part of step s, phase by phase (`phases`: the first
    task of each, then the step's count of tasks), and says False when the run stops. (Made per
    engine, not given the task as an argument: numba cannot cache a function that takes one.)"""

    @njit(cache=True, error_model="numpy")
    def phase(first, last, tasks_per_step, s, w, workers, shared, model, moved, half_skin_sq):
        for r in range(first + w, last, workers):
            if claim(shared, r, s) and not _done(task(r, s, shared, model, moved, half_skin_sq),
                                                 shared):
                return False
        spins = 0
        while atomics.load(shared, DONE) < s * tasks_per_step + last:
            if atomics.load(shared, STOPPED):
                return False
            spins += 1
            if spins == HELP_AFTER_SPINS:
                for r in range(first, last):
                    if claim(shared, r, s) and not _done(
                            task(r, s, shared, model, moved, half_skin_sq), shared):
                        return False
            elif spins > HELP_AFTER_SPINS:
                atomics.yield_core()
        return not atomics.load(shared, STOPPED)

    @njit(cache=True, error_model="numpy")
    def step(phases, s, w, workers, shared, model, moved, half_skin_sq):
        for p in range(len(phases) - 1):
            if not phase(phases[p], phases[p + 1], phases[-1], s, w, workers, shared, model,
                         moved, half_skin_sq):
                return False
        return True

    return step


@njit(cache=True)
def claim(shared, r, s):
    """Whether this thread is the one to do task r of step s."""
    return atomics.compare_exchange(shared, CLAIMS + 8 * r, s, s + 1)


@njit(cache=True)
def _done(went_on, shared):
    """Count a task done; whether the run goes on."""
    if went_on:
        atomics.fetch_add(shared, DONE, 1)
    return went_on


@njit(cache=True)
def stop_if_moved(s, shared, moved, half_skin_sq):
    """At the start of step s: whether a part moved half the skin in the steps before, and if
    so the run marked stopped after s steps."""
    if s == 0 or not must_rebuild(moved, half_skin_sq):
        return False
    shared[STOP_STEP] = s
    atomics.fetch_add(shared, STOPPED, 1)
    return True


@njit(cache=True)
def steps_done(shared, n_steps):
    """The steps the run did: n_steps, or those before it stopped."""
    return shared[STOP_STEP] if shared[STOPPED] else n_steps


@njit(cache=True)
def must_rebuild(moved, half_skin_sq):
    """Whether a part moved more than half the skin since the list was built."""
    for b in range(moved.shape[0]):
        if moved[b] > half_skin_sq:
            return True
    return False
