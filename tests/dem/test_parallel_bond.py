"""The linear parallel bond (PFC2D, Potyondy & Cundall 2004): Rb = lambda min(R), A = 2 Rb t,
I = 2/3 Rb^3 t, kbn = Ebar_c / (Ri + Rj), kbs = kbn / (kbn/kbs); forces and moment
incremental from zero; tension failure when Fn/A + mcf |M| Rb / I > sigma_c, else shear
failure when |Fs|/A > tau_c - (Fn/A) tan(phi_b); a broken bond carries nothing.

E_c = 0 isolates the bond unless a test says otherwise. Both disks are held (driven) and
moved by prescribed velocities and spins; `advance(state, 1)` evaluates the laws with the
current velocities, then moves the disks.
"""

import numpy as np
import pytest

from rockcal.dem.laws import BROKEN_SHEAR, BROKEN_TENSION, INTACT, BondRow
from rockcal.dem.simulate import advance
from rockcal.materials.parallel_bond import new_state
from rockcal.params import make_params

T = 1.0
GPA, MPA = 1e9, 1e6
EBAR = 20.0  # GPa


def bonded_pair(r0, r1, angle=0.0, gap=0.0, **params):
    """Two disks bonded at centre distance r0 + r1 + gap, both held."""
    n = np.array([np.cos(angle), np.sin(angle)])
    p0 = np.array([-0.4e-3, 1.1e-3])
    pos = np.array([p0, p0 + (r0 + r1 + gap) * n])
    values = {"E_c": 0.0, "Ebar_c": EBAR, "knbar_ksbar": 1.6, "lambda": 0.8, "sigma_c": 50.0,
              "tau_c": 60.0, "damping": 0.0} | params
    state = new_state(pos, np.array([r0, r1]), [[0, 1]], make_params(values),
                      driven=np.array([0]))
    state.particles.inv_mass[:] = 0.0
    state.particles.inv_inertia[:] = 0.0
    return state, n


def geometry(r0, r1, lam=0.8, ebar=EBAR, ratio=1.6):
    """(kbn, kbs, A, I, Rb) of the bond between disks r0, r1."""
    rb = lam * min(r0, r1)
    kbn = ebar * GPA / (r0 + r1)
    return kbn, kbn / ratio, 2 * rb * T, 2 / 3 * rb**3 * T, rb


def bond_loads(state):
    """The bond's normal force, shear force and moment."""
    table = state.bonds.table
    return table[BondRow.FN, 0], table[BondRow.FS, 0], table[BondRow.M, 0]


def step(state, vel=((0.0, 0.0), (0.0, 0.0)), spin=(0.0, 0.0)):
    state.particles.vel[:] = vel
    state.particles.spin[:] = spin
    advance(state, 1)


def tangent(n):
    return np.array([-n[1], n[0]])


@pytest.mark.parametrize("direction", [+1.0, -1.0])
def test_normal_force_is_kbn_A_times_the_separation(direction):
    """Pulling the disks apart (or pushing them together) by dn gives Fn = kbn A dn along the
    line of centres, tension positive: the bond pulls disk 0 towards disk 1; no moment."""
    r0, r1 = 1e-3, 1.3e-3
    state, n = bonded_pair(r0, r1, angle=0.9)
    kbn, _, area, _, _ = geometry(r0, r1)
    d0 = np.linalg.norm(state.particles.pos[1] - state.particles.pos[0])
    speed = direction * 1e-8 / state.dt
    for _ in range(7):
        step(state, vel=((0, 0), tuple(speed * n)))
    step(state)  # evaluate at the final positions
    dn = np.linalg.norm(state.particles.pos[1] - state.particles.pos[0]) - d0
    assert dn == pytest.approx(direction * 7e-8, rel=1e-6)
    fn = kbn * area * dn
    assert bond_loads(state)[0] == pytest.approx(fn, rel=1e-9)
    np.testing.assert_allclose(state.particles.force[0], fn * n, rtol=1e-9, atol=1e-12 * abs(fn))
    np.testing.assert_allclose(state.particles.force[1], -fn * n, rtol=1e-9, atol=1e-12 * abs(fn))
    assert bond_loads(state)[1:] == (0.0, 0.0)
    np.testing.assert_allclose(state.particles.moment, 0.0, atol=1e-12 * abs(fn) * r0)


def test_shear_force_from_equal_spins_without_bending():
    """Both disks spinning at omega (centres fixed) slide the bond's ends past each other by
    -omega (R0 + R1) dt per step with no relative rotation: Fs = kbs A ds, M = 0, and the
    moments are the shear force's about each centre (R0 Fs, R1 Fs)."""
    r0, r1 = 1.2e-3, 0.9e-3
    state, n = bonded_pair(r0, r1, angle=-0.4)
    t = tangent(n)
    _, kbs, area, _, _ = geometry(r0, r1)
    omega = 2e-6 / state.dt
    for _ in range(9):
        step(state, spin=(omega, omega))
    ds = -omega * (r0 + r1) * 9 * state.dt
    fs = kbs * area * ds
    assert bond_loads(state)[1] == pytest.approx(fs, rel=1e-9)
    assert bond_loads(state)[2] == 0.0
    assert abs(bond_loads(state)[0]) < 1e-12 * abs(fs)
    np.testing.assert_allclose(state.particles.force[0], fs * t, rtol=1e-9, atol=1e-12 * abs(fs))
    np.testing.assert_allclose(state.particles.force[1], -fs * t, rtol=1e-9, atol=1e-12 * abs(fs))
    np.testing.assert_allclose(state.particles.moment, [r0 * fs, r1 * fs], rtol=1e-9)


def test_moment_from_relative_rotation():
    """Rotating disk 1 by dtheta relative to disk 0 (spins chosen so the bond's ends do not
    slide: omega0 R0 + omega1 R1 = 0) bends the bond: M = kbn I dtheta, restoring: +M on disk 0,
    -M on disk 1, and no force."""
    r0, r1 = 1e-3, 1.4e-3
    state, n = bonded_pair(r0, r1, angle=2.2, **{"lambda": 0.6})
    kbn, _, _, inertia, _ = geometry(r0, r1, lam=0.6)
    omega1 = 1e-5 / state.dt
    omega0 = -omega1 * r1 / r0
    for _ in range(6):
        step(state, spin=(omega0, omega1))
    m = kbn * inertia * (omega1 - omega0) * 6 * state.dt
    assert bond_loads(state)[2] == pytest.approx(m, rel=1e-9)
    assert abs(bond_loads(state)[1]) < 1e-9 * m / r0 and bond_loads(state)[0] == 0.0
    np.testing.assert_allclose(state.particles.moment, [m, -m], rtol=1e-9)
    np.testing.assert_allclose(state.particles.force, 0.0, atol=1e-9 * m / r0)


def one_step_load(state, fn, moment, r0, r1, fs=0.0, lam=0.8):
    """Velocities and spins that add fn, fs and M to the bond's normal force, shear force and
    moment in one step: disk 1 translated along n and t, the disks turned by -w and +w (equal
    radii, so the bond's ends do not slide)."""
    assert r0 == r1
    kbn, kbs, area, inertia, _ = geometry(r0, r1, lam=lam)
    d = state.particles.pos[1] - state.particles.pos[0]
    n = d / np.linalg.norm(d)
    v = fn / (kbn * area * state.dt) * n + fs / (kbs * area * state.dt) * tangent(n)
    w = moment / (2 * kbn * inertia * state.dt)
    return ((0.0, 0.0), tuple(v)), (-w, w)


@pytest.mark.parametrize("mcf, moment_share", [(1.0, 0.0), (1.0, 0.6), (0.5, 0.6), (0.0, 0.0)])
@pytest.mark.parametrize("factor, broken", [(1 - 1e-6, False), (1 + 1e-6, True)])
def test_tension_failure_at_sigma_c(mcf, moment_share, factor, broken):
    """The bond breaks in tension exactly when Fn/A + mcf |M| Rb / I exceeds sigma_c: the load
    is split between pull and bending (moment_share of sigma_c from the moment term), and set
    just below or just above the strength. Broken, its force and moment are zero."""
    r = 1e-3
    sigma_c = 30.0
    state, n = bonded_pair(r, r, angle=0.5, sigma_c=sigma_c, tau_c=1e4, mcf=mcf)
    _, _, area, inertia, rb = geometry(r, r)
    target = factor * sigma_c * MPA
    m = moment_share * target * inertia / (rb * mcf) if moment_share else 0.0
    fn = (target - (mcf * abs(m) * rb / inertia if m else 0.0)) * area
    vel, spin = one_step_load(state, fn, m, r, r)
    step(state, vel, spin)
    if not broken:
        assert state.bonds.state[0] == INTACT
        assert bond_loads(state)[0] == pytest.approx(fn, rel=1e-9)
        assert bond_loads(state)[2] == pytest.approx(m, rel=1e-9, abs=1e-20)
        bond_fn, _, bond_m = bond_loads(state)
        assert bond_fn / area + mcf * abs(bond_m) * rb / inertia < sigma_c * MPA
    else:
        assert state.bonds.state[0] == BROKEN_TENSION
        assert bond_loads(state) == (0.0, 0.0, 0.0)
        assert np.all(state.particles.force == 0.0) and np.all(state.particles.moment == 0.0)
        step(state, vel, spin)  # stays broken and carries nothing
        assert state.bonds.state[0] == BROKEN_TENSION
        assert np.all(state.particles.force == 0.0) and np.all(state.particles.moment == 0.0)


def test_bending_alone_breaks_a_bond_in_tension_whatever_the_sign():
    """Pure bending either way: failure at |M| = sigma_c I / (mcf Rb), in tension."""
    r = 1e-3
    _, _, _, inertia, rb = geometry(r, r)
    for sign in (+1, -1):
        for factor, mode in ((1 - 1e-6, INTACT), (1 + 1e-6, BROKEN_TENSION)):
            state, _ = bonded_pair(r, r, sigma_c=25.0, tau_c=1e4, mcf=0.8)
            m = sign * factor * 25.0 * MPA * inertia / (0.8 * rb)
            vel, spin = one_step_load(state, 0.0, m, r, r)
            step(state, vel, spin)
            assert state.bonds.state[0] == mode, (sign, factor)


@pytest.mark.parametrize("phi_b", [0.0, 35.0])
@pytest.mark.parametrize("sigma_mpa", [-12.0, 0.0, 8.0])
@pytest.mark.parametrize("factor, broken", [(1 - 1e-6, False), (1 + 1e-6, True)])
def test_shear_failure_at_cohesion_minus_normal_stress_tan_phi(phi_b, sigma_mpa, factor,
                                                               broken):
    """Loaded first to a normal stress sigma (tension positive), then sheared in one step (disk
    1 slid along the tangent): the
    bond breaks in shear exactly when |Fs|/A exceeds tau_c - sigma tan(phi_b) (compression
    strengthens, tension weakens); broken, it carries nothing."""
    r, tau_c = 1e-3, 20.0
    state, n = bonded_pair(r, r, angle=-1.3, sigma_c=100.0, tau_c=tau_c, phi_b=phi_b)
    _, _, area, _, _ = geometry(r, r)
    vel, spin = one_step_load(state, sigma_mpa * MPA * area, 0.0, r, r)
    step(state, vel, spin)
    assert bond_loads(state)[0] / area == pytest.approx(sigma_mpa * MPA, rel=1e-9, abs=1e-3)
    strength = (tau_c - sigma_mpa * np.tan(np.radians(phi_b))) * MPA
    fs = factor * strength * area
    step(state, *one_step_load(state, 0.0, 0.0, r, r, fs=fs))
    if not broken:
        assert state.bonds.state[0] == INTACT
        assert abs(bond_loads(state)[1]) == pytest.approx(fs, rel=1e-9)
    else:
        assert state.bonds.state[0] == BROKEN_SHEAR
        assert bond_loads(state) == (0.0, 0.0, 0.0)
        assert np.all(state.particles.force == 0.0) and np.all(state.particles.moment == 0.0)


def test_tension_is_checked_before_shear():
    """A load exceeding both strengths breaks the bond in tension (PFC 5's order)."""
    r = 1e-3
    state, n = bonded_pair(r, r, sigma_c=10.0, tau_c=10.0)
    _, _, area, _, _ = geometry(r, r)
    step(state, *one_step_load(state, 12.0 * MPA * area, 0.0, r, r, fs=12.0 * MPA * area))
    assert state.bonds.state[0] == BROKEN_TENSION


def test_bond_installed_at_an_overlap_locks_in_no_force_and_acts_in_parallel_with_contact():
    """A bond installed at an overlapping pair starts force-free (the overlap is the contact's
    reference gap); compressing further by dn loads contact and bond in parallel,
    F = (kn + kbn A) dn; once the bond has broken, only the linear contact (with the same
    reference) remains: no tension, kn dn in compression."""
    r, overlap0 = 1e-3, 4e-6
    e_c = 15.0
    state, n = bonded_pair(r, r, angle=0.3, gap=-overlap0, E_c=e_c, sigma_c=5.0, tau_c=1e4)
    kn = 2 * r * T * e_c * GPA / (2 * r)
    kbn, _, area, _, _ = geometry(r, r)
    step(state)
    assert np.all(state.particles.force == 0.0) and np.all(state.particles.moment == 0.0)
    dn = 1e-7
    speed = dn / state.dt
    step(state, vel=((0, 0), tuple(-speed * n)))
    step(state)
    np.testing.assert_allclose(state.particles.force[0], -(kn + kbn * area) * dn * n, rtol=1e-6)
    # pull apart until the bond breaks in tension
    while state.bonds.state[0] == INTACT:
        step(state, vel=((0, 0), tuple(speed * n)))
    assert state.bonds.state[0] == BROKEN_TENSION
    step(state)
    assert np.all(state.particles.force == 0.0)  # beyond the reference: no tension
    d = np.linalg.norm(state.particles.pos[1] - state.particles.pos[0])
    back = d - (2 * r - overlap0 - dn)  # to dn past the reference
    step(state, vel=((0, 0), tuple(-back / state.dt * n)))
    step(state)
    np.testing.assert_allclose(state.particles.force[0], -kn * dn * n, rtol=1e-5)


@pytest.mark.parametrize("gap_fraction", [
    0.0,
    0.3,
])
def test_rigid_rotation_of_a_bonded_pair_loads_nothing(gap_fraction):
    """Turning a bonded pair as a rigid body (centres on a circle about the midpoint, both
    disks spinning at the same rate) deforms nothing, so the bond stays free of force and
    moment; pairs bonded across a gap (genesis' install_gap) included."""
    r = 1e-3
    state, n = bonded_pair(r, 1.2 * r, angle=0.2, gap=gap_fraction * r)
    kbn, kbs, area, _, _ = geometry(r, 1.2 * r)
    centre = state.particles.pos.mean(axis=0)
    omega = 1e-5 / state.dt
    steps = 1000  # theta = 0.01 rad
    for _ in range(steps):
        rel = state.particles.pos - centre
        step(state, vel=omega * np.column_stack([-rel[:, 1], rel[:, 0]]), spin=(omega, omega))
    theta = omega * steps * state.dt
    scale = kbs * area * r * theta  # the shear force of a slip r theta
    assert abs(bond_loads(state)[1]) < 1e-4 * scale
    assert abs(bond_loads(state)[0]) < 1e-4 * kbn * area * r * theta
    assert bond_loads(state)[2] == 0.0
