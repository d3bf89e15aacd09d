"""How fast this machine runs the engine: a fraction of a second of stepping a small bonded
lattice on one thread, for the first screen's expected time before the store holds any run, and
how much of the machine other work takes meanwhile.

The probe counts processor time, so that it gives a core's speed whatever else runs; the share of
the cores the runs will get is the other part of the estimate: the tasks that other work has
ready to run, counted between the probe's rounds (`cores.others_runnable`), or, where more, what
the probe's own wall time says of them (a task beside L others on C cores runs (L + 1) / C times
slower than on a core of its own). Neither is capped at the cores: other work that asks for four
cores of two leaves a campaign's two workers a third of the machine, not half.

Machines of one kind differ about 2x in speed, so the plan scales its reference run time (measured
on one machine, beside this probe's time there) by the ratio of this machine's probe time to that
one's.
"""

from __future__ import annotations

import functools
import os
import time
from typing import NamedTuple

import numba
import numpy as np

from rockcal.dem import cores
from rockcal.dem.simulate import advance
from rockcal.specimens.specimen import hexagonal
from rockcal.materials.parallel_bond import make_params, new_state

# width, height and disk radius: 7 300 disks, whose arrays (2 MB) outgrow a core's L2 cache as
# a full-size specimen's do
LATTICE_MM = (40.0, 40.0, 0.25)
STEPS = 100
# the lattice is made anew LATTICES times, ROUNDS runs each: one lattice's arrays may land where
# every step of it runs a third slower (seen in about one process in five), as a run's seldom do
LATTICES = 3
# the engine's first step takes longer than this only where numba compiles it (about half a
# minute; loading it from numba's cache takes a second or two)
COMPILED_S = 8.0
ROUNDS = 4


class Probe(NamedTuple):
    """The probe's time per step and how busy the machine was meanwhile."""

    ms_per_step: float  # processor time: the engine's speed on a core of its own
    cores: int  # the cores this process may run on
    busy_cores: float  # the cores other processes ask for, more than `cores` on a crowded machine
    compiled_here: bool  # numba's cache did not hold the engine: this install's first run


@functools.cache
def probe() -> Probe:
    """The engine's processor time per step on the probe lattice at the granite's default
    parameters, its disks moving slightly, on one thread: the least of ROUNDS runs of STEPS
    steps on each of LATTICES lattices (ms); and the cores other work asks for meanwhile: the mean of its tasks ready to
    run, counted before each round (`dem.cores.others_runnable`), or what the rounds' wall
    time over their processor time says, if more (`others_from_wall`)."""
    spec = hexagonal(*LATTICE_MM, limited=False)  # the probe, not a user's specimen
    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        best, others = np.inf, []
        wall, processor = time.perf_counter(), time.process_time()
        for lattice in range(LATTICES):
            state = new_state(spec.pos, spec.radius, spec.bonds, make_params({}))
            state.particles.vel[:] = np.random.default_rng(0).normal(0, 1e-4, spec.pos.shape)
            advance(state, 1)  # the first compiles the engine, or loads it from numba's cache
            if lattice == 0:
                compiled_here = time.perf_counter() - wall > COMPILED_S
                wall, processor = time.perf_counter(), time.process_time()
            for _ in range(ROUNDS):
                others.append(cores.others_runnable())
                started = time.process_time()
                advance(state, STEPS)
                best = min(best, time.process_time() - started)
        slower = (time.perf_counter() - wall) / max(time.process_time() - processor, 1e-9)
    finally:
        numba.set_num_threads(threads)
    mine = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
    runnable = 0.0 if None in others else float(np.mean(others))
    return Probe(1e3 * best / STEPS, mine, max(runnable, others_from_wall(slower, mine)), compiled_here)


# a probe up to this much slower in wall time than in processor time may just have been
# interrupted now and then: it says nothing of other work
UNSHARED_SLOWDOWN = 1.1


def others_from_wall(slower: float, cores: int) -> float:
    """The cores other work asks for, from how much slower (wall time over processor time) a
    one-thread task ran beside it on `cores` cores: (L + 1) / C = slower; 0 where it ran about
    as fast as alone (then up to C - 1 others leave it a core: the runnable count tells)."""
    return max(0.0, slower * cores - 1) if slower > UNSHARED_SLOWDOWN else 0.0


def probe_ms_per_step() -> float:
    """`probe`'s time per step, ms."""
    return probe().ms_per_step


def busy_cores() -> tuple[int, float]:
    """This process's cores and, of them, those other work kept busy during the probe."""
    p = probe()
    return p.cores, p.busy_cores
