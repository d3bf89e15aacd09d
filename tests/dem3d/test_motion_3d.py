"""Conservation and frame indifference of the 3D engine.

Without damping or external loads, central differences with pair forces that are equal and
opposite and moments taken about the contact point (lever arms adding up to the centre
distance) conserve the total momentum Σ m v and the angular momentum Σ m x × v + I ω exactly
(to round-off; x at the end of a step, v and ω of the half step that led there). A bonded pair
turning as a rigid body keeps the loads it carries, turned with it: the shear force and
moments are rotated with the contact plane, never created.
"""

import numpy as np
import pytest

from rockcal.dem3d.bonds import Bond
from rockcal.dem3d.laws import INTACT, Laws
from rockcal.dem3d.simulate import advance, assemble_state
from rockcal.dem3d.state import solid_sphere

DENSITY = 2650.0
LAWS = Laws(E_c=10e9, ks_per_kn=0.5, mu=0.4, Ebar_c=10e9, ksbar_per_knbar=0.5, lam=0.9,
            tan_phi=0.2, mcf=1.0)


def test_a_free_sphere_keeps_its_velocity_and_spin():
    state = assemble_state(np.zeros((1, 3)), [1e-3], np.empty((0, 2)), DENSITY, LAWS,
                           damping=0.7)
    state.dt = 1e-6
    state.spheres.vel[0] = (0.3, -0.2, 0.1)
    state.spheres.spin[0] = (40.0, 10.0, -25.0)
    advance(state, 1000)
    assert np.all(state.spheres.vel[0] == (0.3, -0.2, 0.1))
    assert np.all(state.spheres.spin[0] == (40.0, 10.0, -25.0))
    np.testing.assert_allclose(state.spheres.pos[0], 1000 * 1e-6 * np.array([0.3, -0.2, 0.1]),
                               rtol=1e-12)


def cluster(seed):
    """A free cluster of 27 spheres on a jittered 3 x 3 x 3 grid, most neighbours bonded
    (weakly: some break), the others in contact, set flying and spinning at random."""
    rng = np.random.default_rng(seed)
    r = rng.uniform(0.9e-3, 1.2e-3, 27)
    grid = np.array([(i, j, k) for k in range(3) for j in range(3) for i in range(3)], float)
    pos = grid * 2.15e-3 + rng.uniform(-0.1e-3, 0.1e-3, grid.shape)
    dist = np.linalg.norm(pos[:, None] - pos[None], axis=2)
    i, j = np.nonzero(np.triu(dist < r[:, None] + r[None] + 0.3e-3, 1))
    pairs = np.column_stack([i, j])[rng.random(len(i)) < 0.7]
    state = assemble_state(pos, r, pairs, DENSITY, LAWS, damping=0.0, ten=3e6, coh=3e6)
    state.spheres.vel[:] = rng.normal(0, 0.5, (27, 3))
    state.spheres.spin[:] = rng.normal(0, 300.0, (27, 3))
    return state


def momenta(state):
    s = state.spheres
    m, inertia = solid_sphere(s.radius, DENSITY)
    linear = (m[:, None] * s.vel).sum(axis=0)
    angular = (m[:, None] * np.cross(s.pos, s.vel)).sum(axis=0) + (inertia[:, None] * s.spin).sum(axis=0)
    return linear, angular


def test_momentum_and_angular_momentum_of_a_free_cluster_are_conserved():
    """While bonds stretch, bend, twist and break and spheres collide and slide."""
    state = cluster(3)
    p0, l0 = momenta(state)
    s = state.spheres
    m, inertia = solid_sphere(s.radius, DENSITY)
    p_scale = (m[:, None] * np.abs(s.vel)).sum()
    l_scale = (m * np.linalg.norm(s.pos, axis=1) * np.linalg.norm(s.vel, axis=1)).sum() \
        + (inertia[:, None] * np.abs(s.spin)).sum()
    com0 = (m[:, None] * s.pos).sum(axis=0) / m.sum()
    steps = 3000
    advance(state, steps)
    assert np.count_nonzero(state.bonds.state != INTACT) > 0  # something happened
    p, l_ = momenta(state)
    np.testing.assert_allclose(p, p0, atol=1e-12 * p_scale)
    np.testing.assert_allclose(l_, l0, atol=1e-12 * l_scale)
    com = (m[:, None] * s.pos).sum(axis=0) / m.sum()
    np.testing.assert_allclose(com, com0 + p0 / m.sum() * steps * state.dt,
                               atol=1e-10 * np.abs(s.pos).max())


def rotation(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def loaded_pair(load=True):
    """Two driven spheres bonded across a small gap, then loaded in every mode at once: shear,
    bending, twist and stretch (unless not `load`), to strains of about 1e-3, as near failure."""
    r0, r1 = 1.0e-3, 1.3e-3
    n = np.array([2.0, -1.0, 2.0]) / 3.0
    pos = np.array([[0.1e-3, 0.2e-3, -0.3e-3], [0.0, 0.0, 0.0]])
    pos[1] = pos[0] + (r0 + r1 + 0.05e-3) * n
    state = assemble_state(pos, [r0, r1], [[0, 1]], DENSITY, LAWS._replace(E_c=0.0),
                           damping=0.0, driven=[0, 1])
    state.dt = 1e-7
    state.spheres.vel[1] = 0.4 * np.array([1.0, 2.0, 0.5]) * load
    state.spheres.spin[1] = np.array([300.0, -400.0, 200.0]) * load
    advance(state, 50)
    state.spheres.vel[:] = 0.0
    state.spheres.spin[:] = 0.0
    advance(state, 1)  # the loads of the final positions
    return state


def bond_loads(state):
    b = state.bonds
    return b.table[Bond.FN, 0], b.shear_force()[0].copy(), b.bending_moment()[0].copy(), \
        b.table[Bond.MT, 0]


def turn_rigidly(state, axis, total, steps):
    """Turn both (driven) spheres by `total` rad about `axis` through their midpoint in `steps`
    steps, as central differences see a rigid body turn: each step starts from the exact turned
    positions, with the velocities of the chords that led there and the spin of the turn."""
    s = state.spheres
    centre = s.pos.mean(axis=0)
    start = s.pos - centre
    spin = np.asarray(axis) / np.linalg.norm(axis) * total / steps / state.dt
    for step in range(1, steps + 1):
        now = start @ rotation(axis, step * total / steps).T
        s.vel[:] = (now - start @ rotation(axis, (step - 1) * total / steps).T) / state.dt
        s.pos[:] = centre + now
        s.spin[:] = spin
        advance(state, 1)


@pytest.mark.parametrize("axis", [(0.0, 0.0, 1.0), (1.0, 2.0, -0.5)])
def test_a_bonded_pair_turned_as_a_rigid_body_carries_its_loads_along(axis):
    """Turned by 1 rad about `axis` in 10⁴ steps, the bond's shear force and bending moment
    turn with the pair, their sizes and the normal force and twisting moment unchanged (the
    shear force to the O(θ³) slip per step of central differences)."""
    state = loaded_pair()
    fn0, fs0, mb0, mt0 = bond_loads(state)
    assert min(abs(fn0), np.linalg.norm(fs0), np.linalg.norm(mb0), abs(mt0)) > 0
    turn_rigidly(state, axis, 1.0, 10_000)
    whole = rotation(axis, 1.0)
    fn, fs, mb, mt = bond_loads(state)
    assert fn == pytest.approx(fn0, rel=1e-5)  # a stretch of 1e-10 m, to round-off
    assert mt == pytest.approx(mt0, rel=1e-9)
    assert np.linalg.norm(fs) == pytest.approx(np.linalg.norm(fs0), rel=1e-7)
    assert np.linalg.norm(mb) == pytest.approx(np.linalg.norm(mb0), rel=1e-9)
    np.testing.assert_allclose(fs, whole @ fs0, atol=1e-6 * np.linalg.norm(fs0))
    np.testing.assert_allclose(mb, whole @ mb0, atol=1e-6 * np.linalg.norm(mb0))


def test_turning_an_unloaded_pair_creates_no_load():
    """Turned by Θ = 1 rad in 10⁴ steps (θ = 1e-4 each), an unloaded bond stays unloaded: less
    than the load of a slip of 1e-8 of the pair's size (central differences slip a rigid turn
    by θ³/24 of it per step, Θ θ² / 24 = 4e-10 in all)."""
    state = loaded_pair(load=False)
    turn_rigidly(state, (1.0, -1.0, 2.0), 1.0, 10_000)
    fn, fs, mb, mt = bond_loads(state)
    kbn_a = LAWS.Ebar_c / 2.3e-3 * np.pi * 0.9e-3**2
    tiny = kbn_a * 2.3e-3 * 1e-8
    assert abs(fn) < tiny and np.linalg.norm(fs) < tiny
    assert np.linalg.norm(mb) < tiny * 1e-3 and abs(mt) < tiny * 1e-3
