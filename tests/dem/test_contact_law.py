"""The linear contact (PFC2D): kn = 2 min(Ri, Rj) t E_c / (Ri + Rj), ks = kn / (kn/ks),
incremental shear capped by Coulomb's mu Fn, no tension; frictionless walls with kn = 2 t E_c.

Motion is prescribed: every disk is made driven (inverse mass 0) and given a velocity or spin,
so one call `advance(state, 1)` evaluates the law at the current positions and then moves the
disks by velocity * dt.
"""

import numpy as np
import pytest

from rockcal.dem.simulate import advance
from rockcal.materials.parallel_bond import new_state
from rockcal.params import make_params

T = 1.0  # disk thickness, m (PFC2D)
GPA = 1e9


def cross(a, b):
    """z-component of a x b for 2D vectors."""
    return a[0] * b[1] - a[1] * b[0]


def contact_pair(r0, r1, centre_distance, angle=0.0, contact_stiffness="pfc5", **params):
    """Two unbonded disks, centre 1 at `centre_distance` from centre 0 in direction `angle`;
    both held (driven), so only prescribed motion moves them."""
    n = np.array([np.cos(angle), np.sin(angle)])
    p0 = np.array([0.7e-3, -0.3e-3])
    pos = np.array([p0, p0 + centre_distance * n])
    values = {"E_c": 10.0, "kn_ks": 2.0, "mu": 0.5, "damping": 0.0} | params
    state = new_state(pos, np.array([r0, r1]), np.empty((0, 2), int), make_params(values),
                      driven=np.array([0]), contact_stiffness=contact_stiffness)
    state.particles.inv_mass[:] = 0.0
    state.particles.inv_inertia[:] = 0.0
    return state, n


def step(state, vel1=(0.0, 0.0), spin1=0.0):
    """One step with disk 0 at rest and disk 1 moving as prescribed."""
    state.particles.vel[0] = 0.0
    state.particles.spin[0] = 0.0
    state.particles.vel[1] = vel1
    state.particles.spin[1] = spin1
    advance(state, 1)


def kn_of(r0, r1, E_c_gpa):
    return 2.0 * min(r0, r1) * T * E_c_gpa * GPA / (r0 + r1)


@pytest.mark.parametrize("r0, r1, angle", [(1e-3, 1e-3, 0.0), (1e-3, 1.6e-3, 0.7),
                                            (2.2e-3, 0.8e-3, -2.5)])
def test_normal_force_is_kn_times_overlap(r0, r1, angle):
    """Overlapping disks repel with Fn = kn * overlap along the line of centres, equal and
    opposite, with no moment; kn = 2 min(R) t E_c / (R0 + R1)."""
    overlap = 2e-6
    state, n = contact_pair(r0, r1, r0 + r1 - overlap, angle, E_c=7.5)
    step(state)
    fn = kn_of(r0, r1, 7.5) * overlap
    np.testing.assert_allclose(state.particles.force[0], -fn * n, rtol=1e-9, atol=1e-12 * fn)
    np.testing.assert_allclose(state.particles.force[1], fn * n, rtol=1e-9, atol=1e-12 * fn)
    np.testing.assert_allclose(state.particles.moment, 0.0, atol=1e-12 * fn * r0)


def test_normal_force_is_linear_in_overlap():
    """Closing the gap at constant speed raises the force by kn * v * dt each step."""
    r = 1e-3
    state, n = contact_pair(r, r, 2 * r - 1e-7)
    kn = kn_of(r, r, 10.0)
    speed = 1e-7 / state.dt  # 0.1 um per step
    forces = []
    for _ in range(5):
        step(state, vel1=-speed * n)
        forces.append(-state.particles.force[0] @ n)
    expected = kn * (1e-7 + 1e-7 * np.arange(5))
    np.testing.assert_allclose(forces, expected, rtol=1e-9)


def test_no_tension_and_no_force_across_a_gap():
    """Disks apart (a gap of 0.1 R, well inside the neighbour list) exert nothing; a contact
    being pulled apart carries no tension: its force drops to exactly zero as soon as the overlap is gone."""
    r = 1e-3
    state, n = contact_pair(r, 1.2 * r, 2.2 * r + 0.1 * r)  # gap 0.1 R
    step(state)
    assert np.all(state.particles.force == 0.0) and np.all(state.particles.moment == 0.0)

    state, n = contact_pair(r, 1.2 * r, 2.2 * r - 1e-6)
    step(state, vel1=2e-6 / state.dt * n)  # force at overlap 1 um, then moved to a 1 um gap
    assert -state.particles.force[0] @ n > 0
    step(state)
    assert np.all(state.particles.force == 0.0) and np.all(state.particles.moment == 0.0)


def test_zero_contact_modulus_means_no_contact_force():
    """E_c = 0 (bonds only): overlapping, unbonded disks do not interact."""
    state, _ = contact_pair(1e-3, 1e-3, 2e-3 - 5e-6, E_c=0.0, Ebar_c=10.0)
    step(state)
    assert np.all(state.particles.force == 0.0) and np.all(state.particles.moment == 0.0)


@pytest.mark.parametrize("r0, r1, angle", [(1e-3, 1e-3, 0.3), (1.5e-3, 0.9e-3, 2.0)])
def test_shear_force_increments_by_ks_vs_dt(r0, r1, angle):
    """Sliding disk 1 along t = (-n_y, n_x) at speed vs drags disk 0 along: the shear force on
    disk 0 grows by ks * vs * dt per step, ks = kn / (kn/ks), while the normal force stays
    kn * overlap; the moments are those of the shear force about each centre, its point of
    action lying in the overlap (between R - overlap and R from the centre)."""
    overlap = 2e-6
    state, _ = contact_pair(r0, r1, r0 + r1 - overlap, angle, kn_ks=1.7, mu=0.8)
    kn = kn_of(r0, r1, 10.0)
    ks = kn / 1.7
    fn = kn * overlap
    vs = 1e-3 * fn / (ks * state.dt)  # 0.1 % of Fn per step: far below mu Fn
    arm_tol = overlap / min(r0, r1)
    for k in range(1, 21):
        d = state.particles.pos[1] - state.particles.pos[0]
        n = d / np.linalg.norm(d)  # at the positions where the step evaluates the law
        t = np.array([-n[1], n[0]])
        step(state, vel1=vs * t)
        f0 = -fn * n + ks * vs * state.dt * k * t
        np.testing.assert_allclose(state.particles.force[0], f0, rtol=1e-6, atol=1e-6 * fn)
        np.testing.assert_allclose(state.particles.force[1], -f0, rtol=1e-6, atol=1e-6 * fn)
        assert state.particles.moment[0] == pytest.approx(cross(r0 * n, f0), rel=arm_tol)
        assert state.particles.moment[1] == pytest.approx(cross(-r1 * n, -f0), rel=arm_tol)


def test_spinning_disk_drags_its_neighbour_along_its_surface():
    """Spinning disk 1 at omega (centres fixed) moves its surface at the contact by
    -omega R1 along t: the shear force on disk 0 grows by ks * (-omega R1) * dt per step (to
    within the overlap's share of the lever arm)."""
    r0, r1, overlap = 1.5e-3, 0.9e-3, 2e-6
    state, n = contact_pair(r0, r1, r0 + r1 - overlap, 2.0, kn_ks=1.7, mu=0.8)
    t = np.array([-n[1], n[0]])
    kn = kn_of(r0, r1, 10.0)
    ks = kn / 1.7
    omega = 1e-3 * kn * overlap / (ks * r1 * state.dt)
    for k in range(1, 11):
        step(state, spin1=omega)
        assert state.particles.force[0] @ t == pytest.approx(ks * (-omega * r1) * state.dt * k,
                                                             rel=overlap / r1)
        assert -state.particles.force[0] @ n == pytest.approx(kn * overlap, rel=1e-12)


def test_shear_force_is_capped_by_coulomb_friction_and_unloads_elastically():
    """Sliding on: |Fs| stops at mu * Fn exactly (Coulomb); reversing the slip then unloads the
    shear spring elastically, by ks * |vs| * dt per step, from that cap. (Slip by spinning
    disk 1, so the overlap stays exact; vs = -omega R1 to within the overlap's share of the
    lever arm.)"""
    r, overlap, mu = 1e-3, 3e-6, 0.4
    state, n = contact_pair(r, r, 2 * r - overlap, 0.2, mu=mu, kn_ks=2.5)
    t = np.array([-n[1], n[0]])
    kn = kn_of(r, r, 10.0)
    ks = kn / 2.5
    cap = mu * kn * overlap
    increment = 0.03 * cap
    omega = increment / (ks * r * state.dt)  # vs = -omega r: the shear force on 0 goes negative
    history = []
    for _ in range(60):
        step(state, spin1=omega)
        history.append(state.particles.force[0] @ t)
    history = np.array(history)
    elastic = -increment * np.arange(1, 61)
    sliding = elastic < -cap
    arm_tol = overlap / r
    np.testing.assert_allclose(history[~sliding], elastic[~sliding], rtol=arm_tol)
    np.testing.assert_allclose(history[sliding], -cap, rtol=1e-12)
    assert np.count_nonzero(sliding) > 20
    assert -state.particles.force[0] @ n == pytest.approx(kn * overlap, rel=1e-12)
    for k in range(1, 11):
        step(state, spin1=-omega)
        assert state.particles.force[0] @ t == pytest.approx(-cap + k * increment,
                                                             abs=arm_tol * cap)


def test_contact_that_opens_forgets_its_shear_force():
    """A contact that separates loses its shear force; touching again, it starts from zero."""
    r, overlap = 1e-3, 2e-6
    state, n = contact_pair(r, r, 2 * r - overlap, 1.0)
    t = np.array([-n[1], n[0]])
    kn = kn_of(r, r, 10.0)
    for _ in range(10):
        step(state, spin1=1e-3 * kn * overlap / (kn / 2 * r * state.dt))
    assert abs(state.particles.force[0] @ t) > 0
    away = 2 * overlap / state.dt * n
    for _ in range(2):
        step(state, vel1=away)
    for _ in range(2):
        step(state, vel1=-away)
    step(state)
    assert -state.particles.force[0] @ n == pytest.approx(kn * overlap, rel=1e-6)
    assert abs(state.particles.force[0] @ t) < 1e-9 * kn * overlap


@pytest.mark.parametrize("E_c, Ebar_c", [(8.0, None), (0.0, 12.0)])
def test_walls_are_frictionless_springs_of_stiffness_2_t_E(E_c, Ebar_c):
    """A disk pressing into the left and top walls gets k_wall * overlap from each along the
    wall normals, k_wall = 2 t E_c (Ebar_c when E_c = 0), and the walls report those forces
    (compression positive); a moving wall moves by its velocity * dt per step."""
    r = 1e-3
    values = {"E_c": E_c, "damping": 0.0} | ({"Ebar_c": Ebar_c} if Ebar_c else {})
    k_wall = 2 * T * (E_c or Ebar_c) * GPA
    d_left, d_top = 1e-6, 3e-6
    pos = np.array([[r - d_left, 5e-3 - r + d_top], [4e-3, 2e-3]])
    state = new_state(pos, np.array([r, r]), np.empty((0, 2), int), make_params(values),
                      walls=(0.0, 10e-3, 0.0, 5e-3), wall_active=(True, True, False, True),
                      driven=np.array([0]))
    state.particles.inv_mass[:] = 0.0
    state.particles.inv_inertia[:] = 0.0
    advance(state, 1)
    np.testing.assert_allclose(state.particles.force[0], [k_wall * d_left, -k_wall * d_top],
                               rtol=1e-9)
    np.testing.assert_allclose(state.walls.force[0], [k_wall * d_left, 0, 0, k_wall * d_top],
                               rtol=1e-9)
    np.testing.assert_allclose(state.particles.force[1], 0.0)
    assert state.particles.moment[0] == 0.0  # frictionless
    np.testing.assert_allclose(state.walls.force.sum(axis=0),
                               [k_wall * d_left, 0, 0, k_wall * d_top], rtol=1e-9)
    # the top wall pushes down 0.1 um per step
    dv = 1e-7 / state.dt
    state.walls.vel[3] = -dv
    top = state.walls.pos[3]
    for k in range(1, 6):
        advance(state, 1)
        assert state.walls.force[0, 3] == pytest.approx(k_wall * (d_top + (k - 1) * 1e-7), rel=1e-9)
    assert state.walls.pos[3] == pytest.approx(top - 5 * 1e-7, rel=1e-12)


@pytest.mark.parametrize("r0, r1", [(1e-3, 1e-3), (1e-3, 1.65e-3), (2.2e-3, 0.8e-3)])
def test_pfc4_contacts_are_ball_stiffnesses_in_series(r0, r1):
    """PFC 3.x/4.0: each ball has kn = 2 t E_c, and a contact the two in series, t E_c whatever
    the radii; ks = kn / (kn/ks) as before. Equal radii: the same as PFC 5's."""
    overlap, vs_dt = 2e-6, 1e-9
    state, n = contact_pair(r0, r1, r0 + r1 - overlap, 0.4, "pfc4", E_c=7.5, kn_ks=1.7, mu=0.8)
    t = np.array([-n[1], n[0]])
    step(state, vel1=vs_dt / state.dt * t)
    kn = 2 * T * 7.5 * GPA / 2  # (2 t E_c)(2 t E_c) / (2 t E_c + 2 t E_c)
    np.testing.assert_allclose(-state.particles.force[0] @ n, kn * overlap, rtol=1e-9)
    np.testing.assert_allclose(state.particles.force[0] @ t, kn / 1.7 * vs_dt, rtol=1e-6)
    if r0 == r1:
        assert kn == pytest.approx(kn_of(r0, r1, 7.5))
