"""A run's numbers are a function of its input alone: the same specimen run twice gives the same
arrays bit for bit, on one thread or two (pairs are summed block by block, then across block
borders, in an order fixed by the specimen), through bond breaks and neighbour-list rebuilds."""

import numba
import numpy as np

from rockcal.dem3d.laws import INTACT, Laws
from rockcal.dem3d.neighbours import near_pairs, spatial_order
from rockcal.dem3d.simulate import advance, assemble_state


def jittered_block(rng):
    """A jittered simple-cubic block of 13³ spheres (two blocks of particles: the engine splits a
    specimen from 2 000 spheres on), its radii and touching pairs."""
    r = 1e-3
    grid = np.array([(i, j, k) for k in range(13) for j in range(13) for i in range(13)], float)
    pos = grid * 2 * r + rng.uniform(-0.03, 0.03, grid.shape) * r
    pos = pos[spatial_order(pos, 2 * r)]
    radius = rng.uniform(0.98, 1.04, len(pos)) * r
    pi, pj = near_pairs(pos, radius, 0.0)
    return pos, radius, pi, pj


def shaken_block():
    """`jittered_block` bonded, set moving fast enough at random that bonds break and the
    neighbour list is rebuilt."""
    rng = np.random.default_rng(7)
    pos, radius, pi, pj = jittered_block(rng)
    laws = Laws(E_c=20e9, ks_per_kn=0.5, mu=0.5, Ebar_c=20e9, ksbar_per_knbar=0.5, lam=1.0,
                tan_phi=0.3, mcf=1.0)
    state = assemble_state(pos, radius, np.column_stack([pi, pj]), 2650.0, laws, damping=0.1,
                           ten=rng.normal(20e6, 4e6, len(pi)), coh=rng.normal(30e6, 6e6, len(pi)))
    state.spheres.vel[:] = rng.normal(0, 6.0, pos.shape)
    state.spheres.spin[:] = rng.normal(0, 2000.0, pos.shape)
    return state


def run(threads):
    cap = numba.get_num_threads()
    numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    try:
        state = shaken_block()
        first = state.neighbours
        advance(state, 250)
    finally:
        numba.set_num_threads(cap)
    assert state.neighbours is not first  # rebuilt on the way
    assert np.count_nonzero(state.bonds.state != INTACT) > 0
    return state


def test_runs_are_bit_reproducible_on_one_thread_or_two():
    runs = [run(1), run(1), run(2)]
    assert len(runs[0].neighbours.block_starts) == 3
    for other in runs[1:]:
        for name in ("bodies", "loads"):
            assert np.array_equal(getattr(runs[0].spheres, name), getattr(other.spheres, name))
        for a, b in zip(runs[0].bonds, other.bonds):
            assert np.array_equal(a, b, equal_nan=True)
        assert np.array_equal(runs[0].neighbours.pi, other.neighbours.pi)
        assert np.array_equal(runs[0].neighbours.shear, other.neighbours.shear)
