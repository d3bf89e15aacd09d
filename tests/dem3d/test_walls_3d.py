"""Planar walls (`rockcal.dem3d.walls`): PFC3D's ball-facet linear contact, kn = π E R
(deformability method with L = R, A = π R²), frictionless.

A free sphere that hits a wall head-on without damping is a linear oscillator on kn for half
a period: it leaves with its speed reversed after π sqrt(m / kn) (central differences keep a
linear spring's energy to O(dt²)); hit by a wall moving at v, it leaves at 2 v. A wall moves
at its velocity whatever touches it. The walls' reactions are summed block by block in an
order fixed by the specimen, so they are the same on any number of threads.
"""

import numba
import numpy as np
import pytest

from rockcal.dem3d.laws import Laws
from rockcal.dem3d.neighbours import near_pairs, spatial_order
from rockcal.dem3d.simulate import advance, assemble_state
from rockcal.dem3d.state import solid_sphere
from rockcal.dem3d.walls import box_walls, new_walls

R = 1e-3
E_WALL = 40e9
DENSITY = 2650.0
LAWS = Laws(E_c=20e9, ks_per_kn=0.5, mu=0.5, Ebar_c=20e9, ksbar_per_knbar=0.5, lam=1.0,
            tan_phi=0.0, mcf=1.0)
NORMAL = np.array([1.0, -2.0, 2.0]) / 3.0


def sphere_by_wall(gap, driven=False, damping=0.0):
    """One sphere at `gap` (negative: overlap) from a wall through the origin, normal NORMAL."""
    walls = new_walls([(0.0, 0.0, 0.0)], [NORMAL], E_WALL)
    state = assemble_state([(R + gap) * NORMAL + np.array([0.0, 2e-3, 1e-3]) @ _plane()],
                           [R], np.empty((0, 2)), DENSITY, LAWS, damping=damping,
                           driven=[0] if driven else None, walls=walls)
    return state


def _plane():
    """Projector onto the wall's plane (an offset along it changes nothing)."""
    return np.eye(3) - np.outer(NORMAL, NORMAL)


def test_a_sphere_pressed_into_a_wall_is_pushed_by_pi_E_R_times_the_overlap():
    overlap = 2e-6
    state = sphere_by_wall(-overlap, driven=True)
    advance(state, 1)
    push = np.pi * E_WALL * R * overlap
    assert state.walls.normal_force()[0] == pytest.approx(push, rel=1e-12)
    assert np.allclose(state.spheres.force[0], push * NORMAL, rtol=1e-12, atol=0)
    assert np.allclose(state.walls.force[0], -push * NORMAL, rtol=1e-12, atol=0)
    assert not state.spheres.moment.any()


def test_a_sphere_bounces_off_a_wall_with_its_speed_reversed_after_half_a_period():
    speed = 0.05
    state = sphere_by_wall(1e-9)
    state.spheres.vel[0] = -speed * NORMAL
    mass = solid_sphere(R, DENSITY)[0]
    contact_s = np.pi * np.sqrt(mass / (np.pi * E_WALL * R))
    state.dt = contact_s / 200
    touching = 0
    while state.step * state.dt < 3 * contact_s:
        advance(state, 1)
        touching += state.walls.normal_force()[0] > 0
    assert touching * state.dt == pytest.approx(contact_s, abs=1.5 * state.dt)
    assert np.allclose(state.spheres.vel[0], speed * NORMAL, rtol=1e-4, atol=0)


def test_the_time_step_and_density_scaling_count_a_touching_wall():
    free = sphere_by_wall(1e-3)
    touching = sphere_by_wall(0.0)
    mass = solid_sphere(R, DENSITY)[0]
    assert free.dt == np.inf
    assert touching.dt == pytest.approx(0.8 * np.sqrt(mass / (np.pi * E_WALL * R)), rel=1e-12)


def test_a_moving_wall_keeps_its_velocity_and_throws_a_sphere_off_at_twice_its_normal_speed():
    """An elastic hit by an infinitely heavy wall; frictionless, so its slide along its plane
    does not drag the sphere."""
    state = sphere_by_wall(0.0)
    mass = solid_sphere(R, DENSITY)[0]
    state.dt = np.pi * np.sqrt(mass / (np.pi * E_WALL * R)) / 200
    velocity = 0.02 * NORMAL + np.array([0.0, 0.01, 0.01]) @ _plane()
    state.walls.vel[0] = velocity
    start = state.walls.point[0].copy()
    advance(state, 600)
    assert np.allclose(state.walls.point[0], start + 600 * state.dt * velocity, rtol=1e-12)
    assert state.walls.normal_force()[0] == 0.0
    assert np.allclose(state.spheres.vel[0], 2 * 0.02 * NORMAL, rtol=1e-4, atol=0)


def squeezed_block(threads, walls_of=None):
    """A bonded, jittered simple-cubic block of 16³ spheres (two blocks of the engine) in a
    box of six walls closing in on it (or the walls `walls_of(pos, radius)`), on `threads`
    threads."""
    cap = numba.get_num_threads()
    numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    try:
        rng = np.random.default_rng(3)
        grid = np.array([(i, j, k) for k in range(16) for j in range(16) for i in range(16)], float)
        pos = grid * 2 * R + rng.uniform(-0.03, 0.03, grid.shape) * R
        pos = pos[spatial_order(pos, 2 * R)]
        radius = rng.uniform(0.98, 1.02, len(pos)) * R
        pi, pj = near_pairs(pos, radius, 0.0)
        if walls_of is None:
            walls = box_walls(pos.min(axis=0) - R, pos.max(axis=0) + R, E_WALL)
            walls.vel[:] = walls.normal * 0.5
        else:
            walls = walls_of(pos, radius)
        state = assemble_state(pos, radius, np.column_stack([pi, pj]), DENSITY, LAWS,
                               damping=0.2, ten=20e6, coh=30e6, walls=walls)
        state.spheres.vel[:] = rng.normal(0, 0.5, pos.shape)
        advance(state, 200)
    finally:
        numba.set_num_threads(cap)
    return state


def test_wall_forces_are_bit_reproducible_on_one_thread_or_two():
    one, two = squeezed_block(1), squeezed_block(2)
    assert len(one.neighbours.block_starts) == 3
    assert (one.walls.normal_force() > 0).all()
    assert np.array_equal(one.spheres.bodies, two.spheres.bodies)
    assert np.array_equal(one.walls.force, two.walls.force)
