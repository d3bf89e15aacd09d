"""The explicit integrator: central differences (leapfrog) for solid disks of unit thickness,
PFC local damping, and the conservation laws of an undamped system.

A bonded pair moving along its line of centres is a linear oscillator: relative coordinate
with m_eff = m0 m1 / (m0 + m1) on the spring k = kbn A = Ebar_c / (R0 + R1) * 2 lambda min(R) t.
`advance` leaves the velocities at the half step after the forces it reports, so the force
history F_n and velocities v_(n+1/2) of successive single steps form the leapfrog sequence.
"""

import numpy as np
import pytest

from rockcal.dem.laws import INTACT, BondRow
from rockcal.dem.simulate import TIME_STEP_SAFETY, _wall_totals, advance, scale_density, stable_time_step
from rockcal.materials.parallel_bond import new_state
from rockcal.params import make_params

T = 1.0
GPA = 1e9
DENSITY = 2650.0
EBAR = 20.0


def mass(r):
    return DENSITY * np.pi * r**2 * T


def oscillator(r0, r1, speed, hold_0=False, **params):
    """Bonded pair along x, E_c = 0; disk 1 moves away at `speed` relative to disk 0 (zero total
    momentum unless disk 0 is held)."""
    pos = np.array([[0.0, 0.0], [r0 + r1, 0.0]])
    values = {"E_c": 0.0, "Ebar_c": EBAR, "density": DENSITY, "damping": 0.0,
              "sigma_c": 1e4, "tau_c": 1e4} | params
    state = new_state(pos, np.array([r0, r1]), [[0, 1]], make_params(values),
                      driven=np.array([0]) if hold_0 else None)
    m0, m1 = mass(r0), mass(r1)
    if hold_0:
        state.particles.vel[1, 0] = speed
    else:
        state.particles.vel[0, 0] = -speed * m1 / (m0 + m1)
        state.particles.vel[1, 0] = speed * m0 / (m0 + m1)
    lam = values.get("lambda", 1.0)
    k = EBAR * GPA / (r0 + r1) * 2 * lam * min(r0, r1) * T
    m_eff = m1 if hold_0 else m0 * m1 / (m0 + m1)
    return state, k, m_eff


def run(state, steps):
    """Single steps: (bond normal force F_n, velocities v_(n+1/2)) per step, with v_(-1/2)."""
    fn = np.empty(steps)
    vel = np.empty((steps + 1, state.particles.pos.shape[0], 2))
    vel[0] = state.particles.vel
    for s in range(steps):
        advance(state, 1)
        fn[s] = state.bonds.table[BondRow.FN, 0]
        vel[s + 1] = state.particles.vel
    return fn, vel


def test_particles_are_solid_disks_of_unit_thickness():
    """m = rho pi R^2 t and I = m R^2 / 2 (inverse values stored; 0 for driven disks)."""
    r = np.array([1e-3, 1.5e-3, 0.7e-3])
    pos = np.array([[0.0, 0.0], [5e-3, 0.0], [0.0, 5e-3]])
    state = new_state(pos, r, np.empty((0, 2), int), make_params({"density": DENSITY}),
                      driven=np.array([2]))
    np.testing.assert_allclose(1 / state.particles.inv_mass[:2], mass(r[:2]), rtol=1e-12)
    np.testing.assert_allclose(1 / state.particles.inv_inertia[:2], 0.5 * mass(r[:2]) * r[:2]**2,
                               rtol=1e-12)
    assert state.particles.inv_mass[2] == 0.0 and state.particles.inv_inertia[2] == 0.0


def test_leapfrog_invariant_of_the_oscillator_is_exact():
    """Central differences conserve, for a linear spring, the discrete energy
    1/2 sum m v_(n-1/2) . v_(n+1/2) + F_n^2 / (2k) exactly (to round-off), at the engine's own
    time step, over tens of periods; and that step is stable (omega dt < 2)."""
    r0, r1 = 1e-3, 1.4e-3
    state, k, m_eff = oscillator(r0, r1, speed=0.01)
    omega = np.sqrt(k / m_eff)
    assert omega * state.dt < 2.0
    steps = int(40 * 2 * np.pi / omega / state.dt)
    fn, vel = run(state, steps)
    m = np.array([mass(r0), mass(r1)])
    kinetic = 0.5 * np.einsum("k,skd,skd->s", m, vel[:-1], vel[1:])
    energy = kinetic + fn**2 / (2 * k)
    assert np.abs(fn).max() > 0
    np.testing.assert_allclose(energy, energy[0], rtol=1e-9)


def test_undamped_oscillator_conserves_energy_over_many_periods():
    """Kinetic (time-centred velocities) plus spring energy stays within (omega dt)^2 / 4 of
    its initial value over 50 periods, with no drift, at dt = T / 100."""
    r0, r1 = 1.2e-3, 1e-3
    state, k, m_eff = oscillator(r0, r1, speed=0.02)
    period = 2 * np.pi * np.sqrt(m_eff / k)
    state.dt = period / 100
    fn, vel = run(state, 5000)
    m = np.array([mass(r0), mass(r1)])
    v_mid = 0.5 * (vel[:-1] + vel[1:])
    energy = 0.5 * np.einsum("k,skd,skd->s", m, v_mid, v_mid) + fn**2 / (2 * k)
    e0 = 0.5 * m_eff * 0.02**2
    bound = (2 * np.pi / 100) ** 2 / 4
    assert np.abs(energy / e0 - 1).max() < 1.1 * bound
    assert abs(energy[:100].mean() - energy[-100:].mean()) < 1e-5 * e0


@pytest.mark.parametrize("hold_0", [False, True])
@pytest.mark.parametrize("steps_per_period", [400, None])
def test_oscillation_period(hold_0, steps_per_period):
    """The period of the bonded pair is 2 pi sqrt(m_eff / k) (m_eff = m1 when disk 0 is held);
    at a finite step, leapfrog's own period pi dt / arcsin(omega dt / 2)."""
    state, k, m_eff = oscillator(1e-3, 1.3e-3, speed=0.01, hold_0=hold_0, **{"lambda": 0.7})
    omega = np.sqrt(k / m_eff)
    period = 2 * np.pi / omega
    if steps_per_period:
        state.dt = period / steps_per_period
    dt = state.dt
    fn, _ = run(state, int(30 * period / dt))
    up = np.flatnonzero((fn[:-1] < 0) & (fn[1:] >= 0))
    crossings = up + (-fn[up]) / (fn[up + 1] - fn[up])  # linear interpolation, in steps
    measured = np.diff(crossings).mean() * dt
    discrete = np.pi * dt / np.arcsin(omega * dt / 2)
    assert measured == pytest.approx(discrete, rel=1e-3)
    if steps_per_period:
        assert measured == pytest.approx(period, rel=1e-3)


@pytest.mark.parametrize("alpha", [0.1, 0.3])
def test_local_damping_removes_a_fixed_fraction_per_half_cycle(alpha):
    """PFC local damping (force reduced by alpha |F| against the velocity) makes the spring
    stiffer by (1 + alpha) moving out and softer by (1 - alpha) coming back, so successive
    amplitudes of a held-free oscillator shrink by sqrt((1 - alpha) / (1 + alpha))."""
    state, k, m_eff = oscillator(1e-3, 1e-3, speed=0.01, hold_0=True, damping=alpha)
    state.dt = 2 * np.pi * np.sqrt(m_eff / k) / 2000
    fn, _ = run(state, 4 * 2000)
    a = np.abs(fn)
    peaks = a[1:-1][(a[1:-1] >= a[:-2]) & (a[1:-1] > a[2:])]
    assert len(peaks) >= 6
    ratios = peaks[1:7] / peaks[:6]
    np.testing.assert_allclose(ratios, np.sqrt((1 - alpha) / (1 + alpha)), rtol=5e-3)


def cluster(seed, damping=0.0):
    """A free cluster of 16 disks: 4 x 4 jittered grid, neighbours bonded (some weakly) or in
    contact, random velocities and spins."""
    rng = np.random.default_rng(seed)
    r = rng.uniform(0.9e-3, 1.2e-3, 16)
    grid = np.array([[x, y] for y in range(4) for x in range(4)], float) * 2.2e-3
    pos = grid + rng.uniform(-0.1e-3, 0.1e-3, grid.shape)
    dist = np.hypot(*(pos[:, None] - pos[None]).transpose(2, 0, 1))
    i, j = np.nonzero(np.triu(dist < 2.5e-3, 1))
    bonds = np.column_stack([i, j])[rng.random(len(i)) < 0.7]
    params = make_params({"E_c": 10.0, "Ebar_c": 10.0, "mu": 0.4, "sigma_c": 3.0, "tau_c": 3.0,
                          "damping": damping, "density": DENSITY})
    state = new_state(pos, r, bonds, params)
    state.particles.vel[:] = rng.normal(0, 0.5, (16, 2))
    state.particles.spin[:] = rng.normal(0, 300.0, 16)
    return state


def test_momentum_of_a_free_system_is_conserved():
    """No external force: total momentum sum m v is constant to round-off while bonds stretch,
    break and disks collide and slide; the centre of mass moves uniformly."""
    state = cluster(3)
    m = mass(state.particles.radius)
    p0 = (m[:, None] * state.particles.vel).sum(axis=0)
    com0 = (m[:, None] * state.particles.pos).sum(axis=0) / m.sum()
    scale = (m[:, None] * np.abs(state.particles.vel)).sum()
    steps = 4000
    advance(state, steps)
    assert np.count_nonzero(state.bonds.state != INTACT) > 0  # something happened
    p = (m[:, None] * state.particles.vel).sum(axis=0)
    np.testing.assert_allclose(p, p0, atol=1e-11 * scale)
    com = (m[:, None] * state.particles.pos).sum(axis=0) / m.sum()
    np.testing.assert_allclose(com, com0 + p0 / m.sum() * steps * state.dt,
                               atol=1e-9 * np.abs(state.particles.pos).max())


def test_driven_disks_move_exactly_as_prescribed():
    """A driven disk ignores the forces on it: it keeps its prescribed velocity and spin and
    moves by velocity * dt each step, while the free disk it pushes is accelerated."""
    r = 1e-3
    pos = np.array([[0.0, 0.0], [2 * r - 1e-6, 0.0]])
    state = new_state(pos, np.array([r, r]), np.empty((0, 2), int),
                      make_params({"damping": 0.0}), driven=np.array([0]))
    state.particles.vel[0] = (3.0, -1.0)
    state.particles.spin[0] = 50.0
    advance(state, 10)
    np.testing.assert_allclose(state.particles.vel[0], (3.0, -1.0))
    assert state.particles.spin[0] == 50.0
    np.testing.assert_allclose(state.particles.pos[0], 10 * state.dt * np.array([3.0, -1.0]),
                               rtol=1e-12)
    assert state.particles.vel[1, 0] > 0


@pytest.mark.parametrize("gap_fraction", [
    0.0,
    0.3,
])
def test_angular_momentum_of_a_free_spinning_pair_is_conserved(gap_fraction):
    """A free bonded pair set turning as a rigid body (orbit and spins at the same rate) keeps
    its angular momentum sum m (x - c) x v + I omega about the centre of mass, with no
    damping, over 1.2 rad of turn; pairs bonded across a gap (genesis' install_gap)
    included."""
    r0, r1 = 1e-3, 1.2e-3
    pos = np.array([[0.0, 0.0], [r0 + r1 + gap_fraction * r0, 0.0]])
    state = new_state(pos, np.array([r0, r1]), [[0, 1]],
                      make_params({"E_c": 0.0, "Ebar_c": EBAR, "damping": 0.0,
                                   "density": DENSITY, "sigma_c": 1e4, "tau_c": 1e4}))
    m = mass(np.array([r0, r1]))
    inertia = 0.5 * m * np.array([r0, r1]) ** 2
    omega = 200.0

    def momentum():
        pos, vel = state.particles.pos, state.particles.vel
        rel = pos - (m[:, None] * pos).sum(axis=0) / m.sum()
        return (m * (rel[:, 0] * vel[:, 1] - rel[:, 1] * vel[:, 0])).sum() \
            + (inertia * state.particles.spin).sum()

    rel = pos - (m[:, None] * pos).sum(axis=0) / m.sum()
    state.particles.vel[:] = omega * np.column_stack([-rel[:, 1], rel[:, 0]])
    state.particles.spin[:] = omega
    l0 = momentum()
    chunk = int(np.ceil(1.2 / (omega * state.dt) / 20))  # 1.2 rad in all
    history = []
    for _ in range(20):
        advance(state, chunk)
        history.append(momentum())
    np.testing.assert_allclose(history, l0, rtol=1e-6)


def test_density_scaling_gives_each_disk_the_mass_its_stiffness_allows():
    """A bonded pair of unequal disks (E_c = 0): each disk's stiffness is the bond's normal spring
    k plus a wall's 2 Ebar_c t (counted for every disk, as the time step counts it), so density scaling gives
    both the mass (k + k_wall) (dt / safety)^2 and the moment of inertia (ks_bar r^2 + k_bend)
    (dt / safety)^2 of their own radius; the time step stays; a held disk stays held. It returns
    the pair's scaled mass over its true mass."""
    r0, r1 = 1.0e-3, 1.6e-3
    state, k, _ = oscillator(r0, r1, 0.0)
    dt, heavy = state.dt, 1.0 / state.particles.inv_mass[1]
    true_mass = np.sum(1.0 / state.particles.inv_mass)
    mass_scale = scale_density(state)
    assert mass_scale == pytest.approx(np.sum(1.0 / state.particles.inv_mass) / true_mass, rel=1e-12)
    assert stable_time_step(state) == pytest.approx(dt, rel=1e-12)
    critical_sq = (dt / TIME_STEP_SAFETY) ** 2
    k_wall = 2 * EBAR * GPA * T
    np.testing.assert_allclose(1.0 / state.particles.inv_mass, (k + k_wall) * critical_sq, rtol=1e-12)
    ks_bar = k / make_params({}).knbar_ksbar
    k_bend = EBAR * GPA / (r0 + r1) * 2 / 3 * r0**3 * T
    np.testing.assert_allclose(1.0 / state.particles.inv_inertia,
                               (ks_bar * np.array([r0, r1]) ** 2 + k_bend) * critical_sq, rtol=1e-12)
    assert 1.0 / state.particles.inv_mass[1] < heavy
    held, _, _ = oscillator(r0, r1, 0.0, hold_0=True)
    scale_density(held)
    assert held.particles.inv_mass[0] == 0.0 and held.particles.inv_inertia[0] == 0.0


def test_the_walls_total_force_is_numpys_sum_to_the_bit():
    """The compiled total adds row after row, as numpy's sum over the first axis does."""
    force = np.random.default_rng(3).lognormal(0.0, 3.0, (1001, 4))
    force[::3] = 0.0
    assert _wall_totals(force).tobytes() == force.sum(axis=0).tobytes()
