"""Rigid clumps of pebbles (PFC's clumps): the union's mass properties against closed forms and
quadrature, a one-pebble clump against a ball to the bit, the conservation laws and rigidity of
free clumps, a clump settling on a wall, two bonded clumps pulled apart, and the time step.

Disks have unit thickness; a clump's mass and inertia are those of its pebbles' union at the
density (`clumps.union_properties`), and `clump_motion.clump` turns a state's particles into
pebbles of clumps (-1: a ball).
"""

import math

import numba
import numpy as np
import pytest
from scipy import integrate

from rockcal import hexagonal, make_params
from rockcal.dem import clumps
from rockcal.dem.clump_motion import clump
from rockcal.dem.laws import BROKEN_TENSION, INTACT, BondRow
from rockcal.dem.neighbours import block_starts, near_pairs
from rockcal.dem.simulate import (
    TIME_STEP_SAFETY,
    advance,
    scale_density,
    stable_time_step,
    unbalanced_forces,
    use_threads,
)
from rockcal.materials import new_state as material_state
from rockcal.materials.flat_joint import make_flatjoint_params
from rockcal.materials.parallel_bond import new_state

T = 1.0
GPA, MPA = 1e9, 1e6
DENSITY = 2650.0
R = 1e-3


def lens_area(r, d):
    """Area of the intersection of two disks of radius r at centre distance d < 2r."""
    return 2 * r * r * math.acos(d / (2 * r)) - 0.5 * d * math.sqrt(4 * r * r - d * d)


def two_disk_polar_moment(r, d):
    """Polar moment of the union of two disks of radius r at (±d/2, 0) about the origin, by
    quadrature over vertical strips: for x >= 0 the right disk bounds the union (half-height
    h), and a strip adds x² 2h + (2/3) h³."""
    def strip(x):
        h = math.sqrt(max(0.0, r * r - (x - d / 2) ** 2))
        return 2 * x * x * h + 2 / 3 * h**3
    half, _ = integrate.quad(strip, 0.0, d / 2 + r, epsabs=0, epsrel=1e-13, limit=200)
    return 2 * half


def grid_union(centres, radii, n=1500):
    """Area, centroid and polar moment of a union of disks by counting the midpoints of an
    n x n grid over its bounding box (an independent estimate, to about 1e-4 here)."""
    lo = (centres - radii[:, None]).min(0)
    hi = (centres + radii[:, None]).max(0)
    xs = lo[0] + (np.arange(n) + 0.5) * (hi[0] - lo[0]) / n
    ys = lo[1] + (np.arange(n) + 0.5) * (hi[1] - lo[1]) / n
    x, y = np.meshgrid(xs, ys)
    inside = np.zeros(x.shape, bool)
    for (a, b), r in zip(centres, radii):
        inside |= (x - a) ** 2 + (y - b) ** 2 <= r * r
    cell = (hi[0] - lo[0]) * (hi[1] - lo[1]) / n**2
    area = inside.sum() * cell
    cx, cy = x[inside].mean(), y[inside].mean()
    return area, np.array([cx, cy]), ((x[inside] - cx) ** 2 + (y[inside] - cy) ** 2).sum() * cell


@pytest.mark.parametrize("d_over_r", [0.0, 0.3, 1.0, 1.7, 1.999, 2.0, 2.5])
def test_union_of_two_equal_disks(d_over_r):
    """Two disks of radius R at distance d: the union's area is 2πR² less the lens (πR² when
    they coincide, 2πR² apart), its centroid the midpoint, its polar moment about it the
    strip quadrature's (2(πR⁴/2 + πR² d²/4) once apart)."""
    d = d_over_r * R
    area, centroid, polar = clumps.union_properties([[0.3 * R, -R], [0.3 * R + d, -R]], [R, R])
    if d == 0:
        expected_area, expected_polar = math.pi * R**2, math.pi * R**4 / 2
    elif d >= 2 * R:
        expected_area = 2 * math.pi * R**2
        expected_polar = 2 * (math.pi * R**4 / 2 + math.pi * R**2 * d**2 / 4)
    else:
        expected_area = 2 * math.pi * R**2 - lens_area(R, d)
        expected_polar = two_disk_polar_moment(R, d)
    assert area == pytest.approx(expected_area, rel=1e-13)
    assert polar == pytest.approx(expected_polar, rel=1e-11)
    np.testing.assert_allclose(centroid, [0.3 * R + d / 2, -R], rtol=0, atol=1e-14 * R)


@pytest.mark.parametrize("centres, radii", [
    ([[0, 0], [1.2, 0.3], [0.4, 1.1]], [1.0, 0.7, 0.8]),  # three overlapping, unequal
    ([[math.cos(t), math.sin(t)] for t in np.arange(6) * math.pi / 3], [0.6] * 6),  # a ring: a hole
    ([[0, 0], [0.5, 0], [0.2, 0.1], [0.2, 0.1]], [1.0, 0.4, 0.3, 0.3]),  # inside others, twins
    ([[0, 0], [2.5, 0.5], [1.2, 0]], [1.0, 1.0, 0.5]),  # a chain
])
def test_union_of_many_disks_against_a_grid(centres, radii):
    """Any union (holes, disks inside others, identical disks, chains) against a fine grid,
    and the same whatever the order of its disks and after a rigid motion."""
    centres, radii = np.array(centres, float) * R, np.array(radii, float) * R
    area, centroid, polar = clumps.union_properties(centres, radii)
    grid_area, grid_centroid, grid_polar = grid_union(centres, radii)
    assert area == pytest.approx(grid_area, rel=2e-4)
    np.testing.assert_allclose(centroid, grid_centroid, rtol=0, atol=1e-4 * R)
    assert polar == pytest.approx(grid_polar, rel=3e-4)
    turn = np.array([[math.cos(0.7), -math.sin(0.7)], [math.sin(0.7), math.cos(0.7)]])
    moved = centres[::-1] @ turn.T + [3 * R, -2 * R]
    area2, centroid2, polar2 = clumps.union_properties(moved, radii[::-1])
    assert area2 == pytest.approx(area, rel=1e-12) and polar2 == pytest.approx(polar, rel=1e-12)
    np.testing.assert_allclose(centroid2, turn @ centroid + [3 * R, -2 * R], rtol=0, atol=1e-14)


def test_members_of_each_clump():
    first, pebbles = clumps.members([1, 0, -1, 1, 0, 2])
    assert first.tolist() == [0, 2, 4, 5] and pebbles.tolist() == [1, 4, 0, 3, 5]
    with pytest.raises(ValueError, match="clump 1 has no pebble"):
        clumps.members([0, 2, -1])


def bonded_state(pos, radius, bonds, clump_of, *, driven=None, walls=None, **params):
    """A parallel-bonded state of these pebbles made clumps (`clump_of`)."""
    values = {"E_c": 20.0, "Ebar_c": 20.0, "density": DENSITY, "damping": 0.0} | params
    options = {} if walls is None else dict(walls=walls, wall_active=(False, False, True, False))
    state = new_state(np.array(pos, float), np.array(radius, float),
                      np.array(bonds, int).reshape(-1, 2), make_params(values), driven=driven,
                      **options)
    return state, clump(state, clump_of, DENSITY)


def test_a_clump_has_the_mass_and_inertia_of_its_pebbles_union():
    """m = ρ A t and I = ρ J t of the union (overlap counted once), about its centroid; a
    one-pebble clump a ball's; the pebbles' rows carry their clump's inverses."""
    d = 1.1 * R
    state, cl = bonded_state([[0, 0], [d, 0], [5 * R, 0]], [R, R, 0.7 * R], [], [0, 0, 1])
    area = 2 * math.pi * R**2 - lens_area(R, d)
    assert 1 / cl.inv_mass[0] == pytest.approx(DENSITY * area * T, rel=1e-13)
    assert 1 / cl.inv_inertia[0] == pytest.approx(DENSITY * two_disk_polar_moment(R, d) * T,
                                                  rel=1e-11)
    np.testing.assert_allclose(cl.pos[0], [d / 2, 0], atol=1e-15)
    ball = DENSITY * np.pi * (0.7 * R) ** 2 * T
    assert 1 / cl.inv_mass[1] == ball and 1 / cl.inv_inertia[1] == 0.5 * ball * (0.7 * R) ** 2
    np.testing.assert_array_equal(state.particles.inv_mass, cl.inv_mass[[0, 0, 1]])


def test_a_clumps_unbalanced_force_is_the_sum_over_its_pebbles():
    """Equal and opposite forces on a clump's two pebbles leave its body balanced; a ball's
    is its own; a driven ball has none to balance."""
    d = 1.1 * R
    state, cl = bonded_state([[0, 0], [d, 0], [5 * R, 0], [9 * R, 0]], [R] * 4, [], [0, 0, -1, -1],
                             driven=np.array([False, False, False, True]))
    state.particles.force[:] = [[3.0, -1.0], [-3.0, 1.0], [0.5, 2.0], [7.0, 7.0]]
    np.testing.assert_array_equal(unbalanced_forces(state), [[0.0, 0.0], [0.5, 2.0]])


def test_pebbles_of_a_clump_are_never_paired_nor_bonded():
    """The neighbour list drops pairs within a clump, at every rebuild; a bond inside a clump
    is refused."""
    state, cl = bonded_state([[0, 0], [1.5 * R, 0], [3.6 * R, 0], [5.1 * R, 0]], [R] * 4,
                             [[1, 2]], [0, 0, 1, 1])
    cl.vel[:] = [[-0.5, 0.0], [0.5, 0.0]]
    cl.spin[:] = [300.0, -200.0]
    cl.carry_pebbles(state.particles)
    for _ in range(5):
        advance(state, 400)
        same = cl.clump_of[state.neighbours.pi] == cl.clump_of[state.neighbours.pj]
        assert not same.any()
    with pytest.raises(ValueError, match="one clump"):
        bonded_state([[0, 0], [1.5 * R, 0]], [R, R], [[0, 1]], [0, 0])


MATERIALS = {"parallel_bond": make_params({"E_c": 20, "sigma_c": 3, "tau_c": 3, "damping": 0.7}),
             "flatjoint": make_flatjoint_params({"fj_emod": 20, "fj_kratio": 2.0, "fj_ten": 3,
                                                 "fj_coh": 3, "damping": 0.7})}


def stirred_specimen(params, clump_of=None):
    """A small bonded hexagonal specimen between bottom and top walls, stirred so that some
    bonds break; its grains made clumps by `clump_of` if given."""
    spec = hexagonal(5, 5, 0.25)
    walls = dict(walls=(0, 0, (spec.pos[:, 1] - spec.radius).min(),
                        (spec.pos[:, 1] + spec.radius).max()), wall_active=(False, False, True, True))
    state = material_state(params, spec, **walls)
    rng = np.random.default_rng(1)
    vel, spin = rng.normal(0, 0.5, state.particles.vel.shape), rng.normal(0, 300.0, len(spec.pos))
    if clump_of is None:
        state.particles.vel[:] = vel
        state.particles.spin[:] = spin
        return state
    cl = clump(state, clump_of, params.density)
    cl.vel[:] = vel[cl.pebbles]
    cl.spin[:] = spin[cl.pebbles]
    cl.carry_pebbles(state.particles)
    balls = cl.balls
    state.particles.vel[balls] = vel[balls]
    state.particles.spin[balls] = spin[balls]
    return state


@pytest.mark.parametrize("material", MATERIALS)
def test_one_pebble_clumps_move_as_balls_to_the_bit(material):
    """A specimen whose grains are one-pebble clumps (and some plain balls beside them) has the
    balls' time step and runs their trajectory to the bit: forces, motion, bonds (parallel
    bonds or flat joints), walls, and the breaks, over steps with neighbour-list rebuilds."""
    balls = stirred_specimen(MATERIALS[material])
    n = balls.n_particles
    clump_of = np.where(np.arange(n) % 3 == 0, -1, np.cumsum(np.arange(n) % 3 != 0) - 1)
    clumped = stirred_specimen(MATERIALS[material], clump_of)
    assert clumped.clumps.n_clumps == n - len(clumped.clumps.balls) > 0
    assert clumped.dt == balls.dt
    for _ in range(4):
        advance(balls, 150)
        advance(clumped, 150)
        for a, b in ((balls.particles.disks, clumped.particles.disks),
                     (balls.particles.loads, clumped.particles.loads),
                     (balls.walls.force, clumped.walls.force),
                     (balls.neighbours.pi, clumped.neighbours.pi), *zip(balls.bonds, clumped.bonds)):
            assert np.array_equal(a, b, equal_nan=True)
    assert 0 < balls.n_broken() < balls.breaks()[0].size
    assert scale_density(balls) == pytest.approx(scale_density(clumped), rel=1e-14)
    assert np.array_equal(balls.particles.inv_mass, clumped.particles.inv_mass)
    assert np.array_equal(balls.particles.inv_inertia, clumped.particles.inv_inertia)


def pebble_gaps(state, cl):
    """Distances between every two pebbles of each clump."""
    pos = state.particles.pos
    return np.concatenate([
        np.hypot(*(pos[own][:, None] - pos[own][None]).reshape(-1, 2).T)
        for own in (cl.pebbles[cl.first[c]:cl.first[c + 1]] for c in range(cl.n_clumps))])


def test_a_free_spinning_clump_is_rigid():
    """A lone three-pebble clump, no damping, thrown spinning: its velocity and spin stay
    exactly, its centroid moves uniformly, its pebbles keep their distances (to round-off)
    and move at v + ω × r."""
    state, cl = bonded_state([[0, 0], [1.3 * R, 0.2 * R], [0.5 * R, 1.1 * R]], [R, 0.8 * R, 0.6 * R],
                             [], [0, 0, 0])
    cl.vel[0] = (0.3, -0.2)
    cl.spin[0] = 2000.0
    cl.carry_pebbles(state.particles)
    gaps0, c0 = pebble_gaps(state, cl), cl.pos[0].copy()
    steps = int(3 * 2 * np.pi / (2000.0 * state.dt))  # three turns
    advance(state, steps)
    assert cl.spin[0] == 2000.0 and tuple(cl.vel[0]) == (0.3, -0.2)
    np.testing.assert_allclose(cl.pos[0], c0 + steps * state.dt * np.array([0.3, -0.2]),
                               rtol=0, atol=1e-12)
    np.testing.assert_allclose(pebble_gaps(state, cl), gaps0, rtol=0, atol=1e-14)
    r = state.particles.pos - cl.pos[0]
    np.testing.assert_allclose(state.particles.vel, [0.3, -0.2] + 2000.0 * np.column_stack(
        [-r[:, 1], r[:, 0]]), rtol=1e-12)
    assert (state.particles.spin == 2000.0).all()


def momentum(cl):
    """Linear and angular momentum (about the origin) of the clumps."""
    m, inertia = 1 / cl.inv_mass, 1 / cl.inv_inertia
    linear = (m[:, None] * cl.vel).sum(axis=0)
    angular = (m * (cl.pos[:, 0] * cl.vel[:, 1] - cl.pos[:, 1] * cl.vel[:, 0])).sum() \
        + (inertia * cl.spin).sum()
    return linear, angular


def test_free_clumps_keep_their_momentum():
    """Four free clumps, no damping, bonded in a chain and flung together: bonds stretch and
    break, pebbles collide and slide; the total momentum stays to round-off, each clump's
    pebbles at their distances. Bonded clumps turning as one rigid body keep their angular
    momentum Σ m c × v + I ω (its moments about each centroid are r × F plus the pebbles')."""
    pos = [[0, 0], [1.3 * R, 0.4 * R], [3.3 * R, 0.3 * R], [4.5 * R, 0.0], [4.7 * R, 1.2 * R],
           [6.6 * R, 0.2 * R], [6.8 * R, 2.0 * R], [8.4 * R, 0.8 * R]]
    radius = [R, R, R, 0.8 * R, 0.8 * R, R, R, 0.9 * R]
    clump_of = [0, 0, 1, 1, 1, 2, 2, 3]
    bonds = [[1, 2], [3, 5], [4, 6], [6, 7]]
    state, cl = bonded_state(pos, radius, bonds, clump_of, sigma_c=20.0, tau_c=20.0, mu=0.4)
    rng = np.random.default_rng(7)
    cl.vel[:] = rng.normal(0, 1.0, (4, 2))
    cl.spin[:] = rng.normal(0, 1000.0, 4)
    cl.carry_pebbles(state.particles)
    p0, gaps0 = momentum(cl)[0], pebble_gaps(state, cl)
    scale = (np.abs(cl.vel) / cl.inv_mass[:, None]).sum()
    advance(state, 3000)
    assert np.count_nonzero(state.bonds.state != INTACT) > 0  # something happened
    np.testing.assert_allclose(momentum(cl)[0], p0, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(pebble_gaps(state, cl), gaps0, rtol=0, atol=1e-13)

    state, cl = bonded_state(pos, radius, bonds, clump_of, Ebar_c=20.0, E_c=0.0, sigma_c=1e4,
                             tau_c=1e4)
    centre = (cl.pos / cl.inv_mass[:, None]).sum(axis=0) / (1 / cl.inv_mass).sum()
    omega = 300.0
    rel = cl.pos - centre
    cl.vel[:] = omega * np.column_stack([-rel[:, 1], rel[:, 0]])
    cl.spin[:] = omega
    cl.carry_pebbles(state.particles)
    l0 = momentum(cl)[1]
    chunk = int(np.ceil(1.2 / (omega * state.dt) / 20))  # 1.2 rad in all
    history = []
    for _ in range(20):
        advance(state, chunk)
        history.append(momentum(cl)[1])
    assert np.abs(state.bonds.table[BondRow.FN]).max() > 0
    np.testing.assert_allclose(history, l0, rtol=1e-6)


def test_a_clump_settles_on_a_wall_without_creeping():
    """A two-pebble clump of unequal pebbles pushed onto the bottom wall by a constant force at
    its centroid (a body force) with PFC local damping: it lands on its large pebble, turns
    until the small one touches, and comes to rest: its velocity and spin decay to nothing,
    the wall pushes back the applied force, split so that the moments about the centroid
    balance, and it then stays put."""
    r0, r1 = R, 0.6 * R
    state, cl = bonded_state([[0, r0 + 2e-6], [1.2 * R, r1 + 0.2 * R]], [r0, r1], [], [0, 0],
                             walls=(0.0, 0.0, 0.0, 0.0), damping=0.7)
    load = state.walls.stiffness * 1e-6  # about a micrometre of overlap
    cl.applied[0] = (0.0, -load, 0.0)
    x0 = cl.pos[0, 0]
    advance(state, 5000)
    settled, angle = cl.pos[0].copy(), cl.angle[0]
    assert angle < -0.1  # it turned onto its small pebble (clockwise)
    speed = np.hypot(*cl.vel[0])
    assert speed < 1e-9 and abs(cl.spin[0]) * R < 1e-9
    on_wall = state.walls.force[:, 2]
    assert (on_wall > 0).all()  # both pebbles touch
    assert on_wall.sum() == pytest.approx(load, rel=1e-9)
    arm = state.particles.pos[:, 0] - cl.pos[0, 0]
    assert abs((arm * on_wall).sum()) < 1e-9 * load * R
    advance(state, 5000)
    np.testing.assert_allclose(cl.pos[0], settled, rtol=0, atol=1e-15)
    assert abs(cl.angle[0] - angle) < 1e-12
    assert cl.pos[0, 0] == x0  # a frictionless wall: no force along it, no drift


@pytest.mark.parametrize("pulled", ["driven", "by a force"])
def test_two_bonded_clumps_break_at_the_bond_strength(pulled):
    """Two two-pebble clumps bonded end to end (E_c = 0: the bond alone) pulled apart along the
    bond: it breaks in tension when its normal force reaches σ̄c Ā, Ā = 2 λ R t. Driven (the
    bond's force then rises by k̄n Ā v dt per step) or free and pulled by opposite applied
    forces rising slowly (quasi-static: the bond carries the applied force)."""
    lam, sigma_c = 0.8, 10.0
    pos = [[0, 0], [1.2 * R, 0], [3.2 * R, 0], [4.4 * R, 0], [2 * R, 9 * R]]  # and a free ball
    driven = np.arange(4) if pulled == "driven" else None
    state, cl = bonded_state(pos, [R] * 5, [[1, 2]], [0, 0, 1, 1, -1], driven=driven, E_c=0.0,
                             sigma_c=sigma_c, tau_c=1e4, damping=0.7, **{"lambda": lam})
    strength = sigma_c * MPA * 2 * lam * R * T
    k = 20.0 * GPA / (2 * R) * 2 * lam * R * T  # k̄n Ā
    gaps0 = pebble_gaps(state, cl)
    if pulled == "driven":
        cl.vel[1] = (1e-3 * strength / (k * state.dt), 0.0)  # a thousandth of it per step
        cl.carry_pebbles(state.particles)
        forces = []
        while state.bonds.state[0] == INTACT:
            advance(state, 1)
            forces.append(state.bonds.table[BondRow.FN, 0])
        assert strength - 1e-3 * strength < forces[-2] <= strength
        assert len(forces) == pytest.approx(1000, abs=2)
    else:
        steps, chunk = 6000, 10
        for s in range(0, steps, chunk):
            pull = 1.25 * strength * s / steps
            cl.applied[:, 0] = (-pull, pull)
            bond_force = state.bonds.table[BondRow.FN, 0]
            advance(state, chunk)
            if state.bonds.state[0] != INTACT:
                break
            if s > steps // 3:  # once settled, the bond carries the pull
                assert bond_force == pytest.approx(pull, rel=1e-2)
        assert pull == pytest.approx(strength, rel=1e-2)
    assert state.bonds.state[0] == BROKEN_TENSION
    np.testing.assert_allclose(pebble_gaps(state, cl), gaps0, rtol=0, atol=1e-15)


def test_time_step_and_density_scaling_count_the_clump():
    """A two-pebble clump bonded to a ball (E_c = 0: the bond's springs alone, and a wall per
    pebble): the time step is safety x the smaller of each body's sqrt(m / k) and sqrt(I / k_rot),
    the clump's mass and inertia its union's and its stiffness the sum over its pebbles, in
    rotation at lever arms about its centroid ((k̄s Ā)(d + R)² + k̄n Ā d² + k̄n Ī per pair, k_wall
    d² per pebble); density scaling gives each body the mass and inertia its stiffness allows,
    the time step unchanged."""
    r0, r1, rb = R, 0.7 * R, 0.8 * R
    pos = [[0, 0], [1.1 * R, 0.3 * R], [1.1 * R + 0.3 * R, 0.3 * R + r1 + rb]]
    state, cl = bonded_state(pos, [r0, r1, rb], [[1, 2]], [0, 0, -1], E_c=0.0, Ebar_c=20.0,
                             knbar_ksbar=1.5, **{"lambda": 0.9})
    ebar, length, rmin = 20.0 * GPA, r1 + rb, min(r1, rb)
    kbn = ebar / length * 2 * 0.9 * rmin * T
    kbs, kbr = kbn / 1.5, ebar / length * 2 / 3 * (0.9 * rmin) ** 3 * T
    k_wall = 2 * ebar * T
    area, centroid, polar = clumps.union_properties(pos[:2], [r0, r1])
    d = np.hypot(*(np.array(pos[:2]) - centroid).T)
    clump_k = (2 * k_wall + kbn, k_wall * (d**2).sum() + kbs * (d[1] + r1) ** 2 + kbn * d[1] ** 2 + kbr)
    ball_k = (k_wall + kbn, kbs * rb**2 + kbr)
    clump_mass = (DENSITY * area * T, DENSITY * polar * T)
    ball_m = DENSITY * np.pi * rb**2 * T
    ball_mass = (ball_m, 0.5 * ball_m * rb**2)
    expected = TIME_STEP_SAFETY * min(np.sqrt(m / k) for m, k in
                                      zip(clump_mass + ball_mass, clump_k + ball_k))
    assert state.dt == pytest.approx(expected, rel=1e-12)
    dt = state.dt
    true = clump_mass[0] + ball_mass[0]
    ratio = scale_density(state)
    critical_sq = (dt / TIME_STEP_SAFETY) ** 2
    np.testing.assert_allclose([1 / cl.inv_mass[0], 1 / cl.inv_inertia[0]],
                               np.array(clump_k) * critical_sq, rtol=1e-12)
    np.testing.assert_allclose([1 / state.particles.inv_mass[2], 1 / state.particles.inv_inertia[2]],
                               np.array(ball_k) * critical_sq, rtol=1e-12)
    assert ratio == pytest.approx((sum(clump_k[:1]) + ball_k[0]) * critical_sq / true, rel=1e-12)
    assert stable_time_step(state) == pytest.approx(dt, rel=1e-12)
    assert (state.particles.inv_mass[:2] == cl.inv_mass[0]).all()


def test_clumps_run_the_same_whatever_the_number_of_threads():
    """1000 two-pebble clumps (two blocks of pebbles, so two threads share the work), bonded
    into a lattice and stirred: one thread and two give the same numbers."""
    nx, ny = 40, 25
    centres = np.array([[3.2 * R * i, 2.0 * R * j] for j in range(ny) for i in range(nx)])
    pos = np.repeat(centres, 2, axis=0) + np.tile([[-0.6 * R, 0.0], [0.6 * R, 0.0]], (nx * ny, 1))
    clump_of = np.repeat(np.arange(nx * ny), 2)
    radius = np.full(len(pos), R)
    pi, pj = near_pairs(pos, radius, 1e-3 * R)
    bonds = np.column_stack([pi, pj])[clump_of[pi] != clump_of[pj]]
    assert len(block_starts(len(pos))) - 1 == 2
    rng = np.random.default_rng(5)
    vel, spin = rng.normal(0, 0.5, (nx * ny, 2)), rng.normal(0, 300.0, nx * ny)
    runs = []
    cap = numba.get_num_threads()
    try:
        for threads in (1, 2):
            use_threads(threads)
            state, cl = bonded_state(pos, radius, bonds, clump_of, sigma_c=3.0, tau_c=3.0,
                                     damping=0.7)
            cl.vel[:] = vel
            cl.spin[:] = spin
            cl.carry_pebbles(state.particles)
            advance(state, 100)
            runs.append((state.particles.disks.copy(), cl.bodies.copy(), state.bonds.table.copy()))
    finally:
        use_threads(None)
        numba.set_num_threads(cap)
    assert 0 < np.count_nonzero(state.bonds.state) < len(bonds)
    for one, two in zip(*runs):
        assert np.array_equal(one, two)
