"""Neighbour search: the cell-grid list of near pairs equals the brute-force one (disks and, in
the 3D engine, spheres), and the Verlet list kept by `advance` (rebuilt when a disk has moved
half the skin) never misses a contact and keeps the shear force of lasting contacts across
rebuilds."""

import numpy as np
import pytest

from rockcal.dem import neighbours, simulate
from rockcal.dem.neighbours import near_pairs
from rockcal.dem.simulate import advance
from rockcal.dem3d.neighbours import near_pairs as near_pairs_3d
from rockcal.materials.parallel_bond import new_state
from rockcal.params import make_params

T = 1.0
GPA = 1e9


def brute_force_pairs(pos, radius, skin):
    """All pairs i < j whose gap is below the skin, sorted by (i, j)."""
    d2 = ((pos[:, None, :] - pos[None, :, :]) ** 2).sum(axis=2)
    reach = radius[:, None] + radius[None, :] + skin
    i, j = np.nonzero(np.triu(d2 < reach**2, 1))
    return i, j  # np.nonzero is row-major: sorted by i, then j


def random_disks(rng, n, box, rmin=0.5e-3, ratio=1.65):
    return rng.uniform(0, box, (n, 2)), rng.uniform(rmin, ratio * rmin, n)


# (near-pair search, particles, side of the box they lie in, m)
SEARCHES = {"disks": (near_pairs, 300, 0.02), "spheres": (near_pairs_3d, 600, 0.012)}


@pytest.mark.parametrize("particles", SEARCHES)
@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("skin_factor", [0.0, 0.25, 1.0, 3.0])
def test_near_pairs_equal_brute_force(particles, seed, skin_factor):
    """For random polydisperse disks (spheres) the grid search returns exactly the pairs with
    gap < skin, each once as i < j, in (i, j) order; also after random moves of up to a radius."""
    search, n, box = SEARCHES[particles]
    rng = np.random.default_rng(seed)
    pos, radius = random_disks(rng, n, box)
    if particles == "spheres":
        pos = np.column_stack([pos, rng.uniform(0, box, n)])
    skin = skin_factor * radius.min()
    for _ in range(3):
        pi, pj = search(pos, radius, skin)
        bi, bj = brute_force_pairs(pos, radius, skin)
        np.testing.assert_array_equal(pi, bi)
        np.testing.assert_array_equal(pj, bj)
        assert len(bi) > 0
        pos = pos + rng.uniform(-1, 1, pos.shape) * radius.max()


@pytest.mark.parametrize("particles", SEARCHES)
def test_near_pairs_in_a_dense_pile_and_a_line(particles):
    """Degenerate layouts: 80 disks (spheres) piled in one spot (every pair near: more pairs
    than the search's first buffer), and on one horizontal line (a grid one cell high)."""
    search = SEARCHES[particles][0]
    dims = 2 if particles == "disks" else 3
    rng = np.random.default_rng(7)
    pos = rng.uniform(0, 0.2e-3, (80, dims))
    radius = rng.uniform(0.5e-3, 0.8e-3, 80)
    pi, pj = search(pos, radius, 0.1e-3)
    assert len(pi) == 80 * 79 // 2
    np.testing.assert_array_equal(np.column_stack([pi, pj]),
                                  np.column_stack(brute_force_pairs(pos, radius, 0.1e-3)))
    line = np.zeros((50, dims))
    line[:, 0] = np.arange(50) * 2.05e-3
    r = np.full(50, 1e-3)
    pi, pj = search(line, r, 0.1e-3)
    np.testing.assert_array_equal(pi, np.arange(49))
    np.testing.assert_array_equal(pj, np.arange(1, 50))
    pi, pj = search(line[:1], r[:1], 0.1e-3)
    assert len(pi) == 0


def test_neighbour_list_value_against_brute_force():
    """`allocate` lists the bonds (in block layout) and then the unbonded near pairs; `update`
    after random moves lists the same bonds and the new near pairs, carries the shear force of
    pairs that stay listed, and `needs_update` turns true only past half the skin."""
    rng = np.random.default_rng(4)
    pos, radius = random_disks(rng, 400, 0.025)
    skin = 0.5 * radius.min()
    bi, bj = brute_force_pairs(pos, radius, 0.0)
    bonds = np.column_stack([bi, bj])[rng.permutation(len(bi))[:len(bi) // 2]]
    nlist, order = neighbours.allocate(pos, radius, bonds, skin)
    nb = nlist.n_bonds
    assert nb == len(bonds)
    np.testing.assert_array_equal(np.column_stack([nlist.pi[:nb], nlist.pj[:nb]]), bonds[order])
    bond_keys = set(map(tuple, bonds))
    for _ in range(3):
        near = set(zip(*brute_force_pairs(pos, radius, skin)))
        listed = list(zip(nlist.pi[nb:], nlist.pj[nb:]))
        assert len(listed) == len(set(listed))
        assert set(listed) == near - bond_keys
        assert nlist.contact_offsets[0] == nb and nlist.contact_offsets[-1] == len(nlist.pi)
        assert not neighbours.needs_update(nlist, pos)
        nlist.shear[:] = rng.normal(size=len(nlist.shear))
        moved = pos.copy()
        moved[0] += (0.51 * skin, 0.0)
        assert neighbours.needs_update(nlist, moved)
        new = neighbours.update(nlist, moved, radius)
        np.testing.assert_array_equal(new.pi[:nb], nlist.pi[:nb])
        np.testing.assert_array_equal(new.shear[:nb], nlist.shear[:nb])
        old = dict(zip(listed, nlist.shear[nb:]))
        for pair, shear in zip(zip(new.pi[nb:], new.pj[nb:]), new.shear[nb:]):
            assert shear == old.get(pair, 0.0)
        pos = pos + rng.uniform(-1, 1, pos.shape) * radius.min()
        nlist = neighbours.update(nlist, pos, radius)


def gas(seed, n=36, mu=0.0):
    """Disks in a walled box, fast enough to cross the neighbour skin every few tens of steps;
    frictionless (history-free forces) unless `mu`."""
    rng = np.random.default_rng(seed)
    box = 14e-3
    pos, radius = [], []
    while len(pos) < n:
        r = rng.uniform(0.6e-3, 1.0e-3)
        p = rng.uniform(r, box - r, 2)
        if all(np.hypot(*(p - q)) > r + s for q, s in zip(pos, radius)):
            pos.append(p)
            radius.append(r)
    params = make_params({"E_c": 5.0, "mu": mu, "damping": 0.0})
    state = new_state(np.array(pos), np.array(radius), np.empty((0, 2), int), params,
                      walls=(0.0, box, 0.0, box), wall_active=(True,) * 4, contact_stiffness="pfc5")
    state.particles.vel[:] = rng.normal(0.0, 1.0, (n, 2)) * 0.03e-3 / state.dt  # ~0.03 mm per step
    return state


def brute_force_forces(pos, radius, walls, E_c):
    """Forces of frictionless linear contacts between all pairs and with the four walls."""
    d = pos[None, :, :] - pos[:, None, :]  # d[i, j] = pos[j] - pos[i]
    dist = np.hypot(d[..., 0], d[..., 1])
    np.fill_diagonal(dist, np.inf)
    ri, rj = radius[:, None], radius[None, :]
    overlap = np.maximum(0.0, ri + rj - dist)
    kn = 2 * np.minimum(ri, rj) * T * E_c / (ri + rj)
    force = -(kn * overlap / dist)[..., None] * d  # pushes i away from every j it overlaps
    force = force.sum(axis=1)
    k_wall = 2 * T * E_c
    force[:, 0] += k_wall * np.maximum(0, walls[0] - (pos[:, 0] - radius))
    force[:, 0] -= k_wall * np.maximum(0, pos[:, 0] + radius - walls[1])
    force[:, 1] += k_wall * np.maximum(0, walls[2] - (pos[:, 1] - radius))
    force[:, 1] -= k_wall * np.maximum(0, pos[:, 1] + radius - walls[3])
    return force


def test_no_contact_is_missed_during_a_long_run():
    """Runs of random length (rebuilds inside and between `advance` calls), each followed by a
    step whose forces are checked against the all-pairs forces at that step's positions: every
    contact is found while the disks travel many skins (5 R_min) and collide many times."""
    state = gas(5)
    rng = np.random.default_rng(11)
    start = state.particles.pos.copy()
    travelled = np.zeros(len(state.particles.pos))
    contacts = 0
    scale = 2 * T * 5 * GPA * 1e-6  # the force of a 1 um overlap
    for _ in range(150):
        before = state.particles.pos.copy()
        advance(state, int(rng.integers(1, 40)))
        at = state.particles.pos.copy()
        travelled += np.hypot(*(at - before).T)
        advance(state, 1)
        expected = brute_force_forces(at, state.particles.radius, state.walls.pos, 5 * GPA)
        np.testing.assert_allclose(state.particles.force, expected, rtol=1e-9, atol=1e-9 * scale)
        contacts += np.count_nonzero(np.any(expected != 0, axis=1))
    assert contacts > 100
    rmin = state.particles.radius.min()  # the default skin is rmin / 2
    assert np.median(travelled) > 5 * rmin
    assert np.abs(state.particles.pos - start).max() > 2 * rmin


def test_shear_force_survives_neighbour_list_rebuilds(monkeypatch):
    """A lasting frictional contact keeps its shear force while two distant disks' travel
    (side by side, so not flying free: `release_lone_movers`) forces the neighbour list to be
    rebuilt many times."""
    rebuilds = count_rebuilds(monkeypatch)
    r, overlap = 1e-3, 2e-6
    pos = np.array([[0.0, 0.0], [2 * r - overlap, 0.0], [20e-3, 0.0], [20e-3 + 2.1 * r, 0.0]])
    params = make_params({"E_c": 10.0, "kn_ks": 2.0, "mu": 0.5, "damping": 0.0})
    state = new_state(pos, np.full(4, r), np.empty((0, 2), int), params, driven=np.array([0]))
    state.particles.inv_mass[:] = 0.0
    state.particles.inv_inertia[:] = 0.0
    kn = 2 * r * T * 10 * GPA / (2 * r)
    ks = kn / 2.0
    omega = 0.01 * kn * overlap / (ks * r * state.dt)
    state.particles.spin[1] = omega
    advance(state, 20)  # shear force on disk 0: 20 ks (-omega r) dt along y
    state.particles.spin[1] = 0.0
    advance(state, 1)
    before = state.particles.force[0].copy()
    assert before[1] == pytest.approx(20 * ks * (-omega * r) * state.dt, rel=overlap / r)
    state.particles.vel[2:] = (0.0, 0.05 * r / state.dt)  # 10 R in all: many skins
    advance(state, 200)
    state.particles.vel[2:] = 0.0
    advance(state, 1)
    assert state.particles.pos[2, 1] > 9 * r
    assert len(rebuilds) > 10
    np.testing.assert_allclose(state.particles.force[0], before, rtol=1e-12)


def count_rebuilds(monkeypatch) -> list:
    """The steps at which `advance` rebuilds the neighbour list, from now on."""
    steps = []
    rebuild = simulate.rebuild_neighbours

    def counted(state):
        steps.append(state.step)
        rebuild(state)
    monkeypatch.setattr(simulate, "rebuild_neighbours", counted)
    return steps


def test_a_grain_flying_free_does_not_rebuild_the_list(monkeypatch):
    """A disk flying away from the others (a grain spalled off a specimen) travels many skins
    without a rebuild: its build position moves with it (`release_lone_movers`); once it
    nears another disk, the list is rebuilt as before."""
    rebuilds = count_rebuilds(monkeypatch)
    r = 1e-3
    pos = np.array([[0.0, 0.0], [2 * r, 0.0], [0.0, 3 * r], [30e-3, 0.0]])
    params = make_params({"E_c": 10.0, "mu": 0.5, "damping": 0.0})
    state = new_state(pos, np.full(4, r), np.empty((0, 2), int), params)
    state.particles.vel[2] = (0.0, 0.05 * r / state.dt)  # away from the pair: 10 R
    advance(state, 200)
    assert state.particles.pos[2, 1] > 12 * r and rebuilds == []
    state.particles.vel[2] = 0.0
    state.particles.vel[3] = (-0.05 * r / state.dt, 0.0)  # towards the pair: 10 R
    advance(state, 200)
    assert state.particles.pos[3, 0] < 21e-3 and rebuilds == []
    advance(state, 320)  # to touch disk 1
    assert len(rebuilds) > 0


def test_releasing_lone_movers_changes_no_number(monkeypatch):
    """A frictional gas (disks colliding, many flying free between collisions) runs to the
    same positions, velocities and forces, to the bit, with lone movers released and with
    every half skin's travel rebuilding the list."""
    states = []
    for release in (True, False):
        if not release:
            monkeypatch.setattr(neighbours, "release_lone_movers", lambda *args: False)
        rebuilds = count_rebuilds(monkeypatch)
        state = gas(5, mu=0.5)
        for steps in (300, 1, 700, 250, 750):
            advance(state, steps)
        states.append((state, len(rebuilds)))
    (released, released_rebuilds), (rebuilt, all_rebuilds) = states
    assert released_rebuilds < all_rebuilds
    for name in ("pos", "vel", "spin", "force", "moment"):
        np.testing.assert_array_equal(getattr(released.particles, name), getattr(rebuilt.particles, name))
