"""How fast this machine runs the engine: a fraction of a second of stepping a small bonded
lattice on one thread, for the first screen's expected time before the store holds any run.

Machines of one kind differ about 2x in speed, so the plan scales its reference run time (measured
on one machine, beside this probe's time there) by the ratio of this machine's probe time to that
one's.
"""

from __future__ import annotations

import functools
import time

import numba
import numpy as np

from rockcal.dem.simulate import advance
from rockcal.dem.specimen import hexagonal
from rockcal.materials.parallel_bond import make_params, new_state

# width, height and disk radius: 7 300 disks, whose arrays (2 MB) outgrow a core's L2 cache as
# a full-size specimen's do
LATTICE_MM = (40.0, 40.0, 0.25)
STEPS = 300
ROUNDS = 3


@functools.cache
def probe_ms_per_step() -> float:
    """The engine's time per step on the probe lattice at the granite's default parameters, its
    disks moving slightly, on one thread: the fastest of ROUNDS runs of STEPS steps (ms)."""
    spec = hexagonal(*LATTICE_MM)
    state = new_state(spec.pos, spec.radius, spec.bonds, make_params({}))
    state.particles.vel[:] = np.random.default_rng(0).normal(0, 1e-4, spec.pos.shape)
    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        advance(state, 1)  # compiles the engine, or loads it from numba's cache
        best = np.inf
        for _ in range(ROUNDS):
            started = time.perf_counter()
            advance(state, STEPS)
            best = min(best, time.perf_counter() - started)
    finally:
        numba.set_num_threads(threads)
    return 1e3 * best / STEPS
