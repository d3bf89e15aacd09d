"""PFC's 2D flat joint (`rockcal.dem.flatjoint`) against closed forms, on two grains.

An interface of half-length R̄ = λ min(R0, R1) with N_r elements of length L = 2R̄/N_r (unit
thickness), k_n = E*/(R0 + R1), k_s = k_n/κ*. Two ways in: the law itself, fed relative
displacements (`update_joint`), and two grains moved by prescribed velocities and spins
(`add_flatjoint_forces` evaluates the law with the current velocities, then the test moves the
grains by one step).
"""

import numpy as np
import pytest

from rockcal.dem import flatjoint as fj
from rockcal.dem.simulate import new_particles

GPA, MPA = 1e9, 1e6
EMOD = 20.0  # GPa
KRATIO = 1.6
R0, R1 = 1.0e-3, 1.3e-3
LAM = 0.8
DT = 1e-7


def kn_of(r0=R0, r1=R1, emod=EMOD):
    return emod * GPA / (r0 + r1)


def joint(nr, bonded=True, gap0=0.0, ten=50.0, coh=60.0, fa=0.0, fric=0.5, r0=R0, r1=R1):
    """One flat joint between grains of radii r0, r1 (strengths in MPa, angle in degrees)."""
    kn = kn_of(r0, r1)
    return fj.new_flatjoints(nr, kn=kn, ks=kn / KRATIO, rmul=LAM, fric=fric,
                             tan_fa=np.tan(np.radians(fa)), gap0=gap0, bonded=bonded,
                             ten=ten * MPA, coh=coh * MPA)


def rbar_of(r0=R0, r1=R1):
    return LAM * min(r0, r1)


def law(j, dn=0.0, ds=0.0, dtheta=0.0, rbar=None):
    """One step of the law with these relative displacements; how many elements broke."""
    return fj.update_joint(0, rbar_of() if rbar is None else rbar, dn, ds, dtheta, j.table,
                           j.state, j.elements)


class Pair:
    """Two grains joined by flat joint 0, moved by prescribed velocities and spins."""

    def __init__(self, j, r0=R0, r1=R1, angle=0.7, gap=0.0):
        self.n = np.array([np.cos(angle), np.sin(angle)])
        p0 = np.array([0.3e-3, -0.2e-3])
        self.radius = np.array([r0, r1])
        self.grains = new_particles(np.array([p0, p0 + (r0 + r1 + gap) * self.n]), self.radius,
                                    np.ones(2), np.ones(2))
        self.pos = self.grains.pos
        self.force = self.grains.force
        self.moment = self.grains.moment
        self.j = j
        self.pi = np.array([0], np.int64)
        self.pj = np.array([1], np.int64)

    @property
    def t(self):
        return np.array([-self.n[1], self.n[0]])

    def step(self, vel=((0.0, 0.0), (0.0, 0.0)), spin=(0.0, 0.0)):
        g = self.grains
        g.vel[:] = vel
        g.spin[:] = spin
        g.loads[:] = 0.0
        bonded = np.count_nonzero(self.j.state == fj.BONDED)
        fj.add_flatjoint_forces(0, 1, g.disks, self.pi, self.pj, None, self.j, None, DT, g.loads)
        self.pos += g.vel * DT
        return bonded - np.count_nonzero(self.j.state == fj.BONDED)  # elements broken


# --- stiffness of a bonded interface -----------------------------------------------------

@pytest.mark.parametrize("nr", [1, 2, 3, 7])
@pytest.mark.parametrize("direction", [+1.0, -1.0])
def test_normal_stiffness_of_a_bonded_interface_is_kn_A(nr, direction):
    """Pulling the grains apart (or pushing them together) by dn along the line of centres
    gives F_n = k_n A dn (tension positive: the joint pulls grain 0 towards grain 1), A = 2R̄,
    whatever N_r; no shear, no moment."""
    pair = Pair(joint(nr))
    d0 = np.linalg.norm(pair.pos[1] - pair.pos[0])
    v = direction * 1e-8 / DT * pair.n
    for _ in range(7):
        pair.step(vel=((0, 0), v))
    pair.step()
    dn = np.linalg.norm(pair.pos[1] - pair.pos[0]) - d0
    assert dn == pytest.approx(direction * 7e-8, rel=1e-9)
    fn = kn_of() * 2 * rbar_of() * dn
    assert pair.j.table[fj.FN, 0] == pytest.approx(fn, rel=1e-9)
    np.testing.assert_allclose(pair.j.elements[fj.E_FN, 0], fn / nr, rtol=1e-9)
    np.testing.assert_allclose(pair.force, [fn * pair.n, -fn * pair.n], rtol=1e-9,
                               atol=1e-12 * abs(fn))
    assert abs(pair.j.table[fj.FS, 0]) < 1e-12 * abs(fn)
    assert abs(pair.j.table[fj.M, 0]) < 1e-12 * abs(fn) * R0
    np.testing.assert_allclose(pair.moment, 0.0, atol=1e-12 * abs(fn) * R0)


@pytest.mark.parametrize("nr", [1, 4])
def test_shear_stiffness_of_a_bonded_interface_is_ks_A(nr):
    """Both grains spinning at ω (centres fixed) slide the joint's faces by -ω (R0 + R1) dt per
    step without bending it: F_s = k_s A ds, the same share on every element, no interface
    moment, and the grains' moments are the shear force's about their centres (R0 F_s, R1 F_s)."""
    pair = Pair(joint(nr, ten=1e4, coh=1e4))
    omega = 2e-6 / DT
    for _ in range(9):
        pair.step(spin=(omega, omega))
    ds = -omega * (R0 + R1) * 9 * DT
    fs = kn_of() / KRATIO * 2 * rbar_of() * ds
    assert pair.j.table[fj.FS, 0] == pytest.approx(fs, rel=1e-9)
    np.testing.assert_allclose(pair.j.elements[fj.E_FS, 0], fs / nr, rtol=1e-9)
    assert pair.j.table[fj.THETA, 0] == 0.0
    assert abs(pair.j.table[fj.M, 0]) < 1e-12 * abs(fs) * R0
    assert abs(pair.j.table[fj.FN, 0]) < 1e-12 * abs(fs)
    np.testing.assert_allclose(pair.force, [fs * pair.t, -fs * pair.t], rtol=1e-9,
                               atol=1e-12 * abs(fs))
    np.testing.assert_allclose(pair.moment, [R0 * fs, R1 * fs], rtol=1e-9)


@pytest.mark.parametrize("nr", [1, 2, 3, 5, 8])
def test_moment_rotation_slope_is_kn_times_the_elements_second_moment(nr):
    """Bending by dθ gives M = k_n I dθ with I the exact discrete sum over the elements,
    I = Σ_e (A_e ξ_e² + L³/12) (centroid terms plus each element's own, its stress varying
    linearly across it) = (2/3) R̄³: the centroid sum alone is (2/3) R̄³ (1 - 1/N_r²)."""
    rbar = rbar_of()
    length = 2 * rbar / nr
    xi = -rbar + (np.arange(nr) + 0.5) * length
    centroid_sum = float(np.sum(length * xi**2))
    own_sum = nr * length**3 / 12
    assert centroid_sum == pytest.approx(2 / 3 * rbar**3 * (1 - 1 / nr**2), rel=1e-12)
    assert centroid_sum + own_sum == pytest.approx(2 / 3 * rbar**3, rel=1e-12)
    assert fj.second_moment(rbar, nr) == pytest.approx((centroid_sum, own_sum), rel=1e-12)
    j = joint(nr, ten=1e4, coh=1e4)
    dtheta = 3e-5
    law(j, dtheta=dtheta)
    m = kn_of() * (centroid_sum + own_sum) * dtheta
    assert j.table[fj.M, 0] == pytest.approx(m, rel=1e-12)
    # the elements: F_n^e = -k_n A ξ_e dθ (opening on the side ξ < 0), M^e = k_n L³/12 dθ
    np.testing.assert_allclose(j.elements[fj.E_FN, 0], -kn_of() * length * xi * dtheta,
                               rtol=1e-12, atol=1e-12 * abs(m) / rbar)
    np.testing.assert_allclose(j.elements[fj.E_M, 0], kn_of() * length**3 / 12 * dtheta,
                               rtol=1e-12)
    assert abs(j.table[fj.FN, 0]) < 1e-12 * abs(m) / rbar


def test_relative_rotation_of_the_grains_bends_the_joint():
    """Turning grain 1 by dθ relative to grain 0 without sliding the faces (ω0 R0 + ω1 R1 = 0)
    gives M = k_n (2/3) R̄³ dθ, restoring: +M on grain 0, -M on grain 1, and no force."""
    pair = Pair(joint(3, ten=1e4, coh=1e4), angle=2.2)
    omega1 = 1e-5 / DT
    omega0 = -omega1 * R1 / R0
    for _ in range(6):
        pair.step(spin=(omega0, omega1))
    m = kn_of() * 2 / 3 * rbar_of()**3 * (omega1 - omega0) * 6 * DT
    assert pair.j.table[fj.M, 0] == pytest.approx(m, rel=1e-9)
    np.testing.assert_allclose(pair.moment, [m, -m], rtol=1e-9)
    np.testing.assert_allclose(pair.force, 0.0, atol=1e-9 * m / R0)


@pytest.mark.parametrize("gap_fraction", [0.0, 0.3])
def test_rigid_rotation_of_a_joined_pair_loads_nothing(gap_fraction):
    """Turning the pair as a rigid body (centres on a circle about their midpoint, both grains
    spinning at the same rate) deforms nothing, joints across a gap included."""
    pair = Pair(joint(4), gap=gap_fraction * R0)
    centre = pair.pos.mean(axis=0)
    omega = 1e-5 / DT
    steps = 1000  # 0.01 rad
    for _ in range(steps):
        rel = pair.pos - centre
        pair.step(vel=omega * np.column_stack([-rel[:, 1], rel[:, 0]]), spin=(omega, omega))
    theta = omega * steps * DT
    area = 2 * rbar_of()
    assert abs(pair.j.table[fj.FS, 0]) < 1e-4 * kn_of() / KRATIO * area * R0 * theta
    assert abs(pair.j.table[fj.FN, 0]) < 1e-4 * kn_of() * area * R0 * theta
    assert pair.j.table[fj.THETA, 0] == 0.0
    assert abs(pair.j.table[fj.M, 0]) < 1e-4 * kn_of() * area * R0**2 * theta


# --- progressive damage ------------------------------------------------------------------

def test_growing_bend_breaks_elements_one_by_one_from_the_tension_side():
    """Bending (θ_b > 0 opens the side ξ < 0) in small steps at zero surface gap: element e of
    the tension side breaks, in tension, when k_n |ξ_e| θ reaches σ_c, so elements 0, 1, 2 of
    six break one at a time in that order and the compressed side never does. After the first
    break the interface still resists rotation: the broken element, open, carries nothing, and
    M = k_n θ (I - A ξ_0² - L³/12)."""
    nr, sigma_c = 6, 30.0
    j = joint(nr, ten=sigma_c, coh=1e4)
    rbar = rbar_of()
    length = 2 * rbar / nr
    xi = -rbar + (np.arange(nr) + 0.5) * length
    kn = kn_of()
    step = 1e-3 * sigma_c * MPA / (kn * rbar)
    order, at_theta, moments = [], [], []
    while len(order) < nr // 2 and j.table[fj.THETA, 0] < 1.5 * sigma_c * MPA / (kn * abs(xi[2])):
        before = j.state[0].copy()
        broke = law(j, dtheta=step)
        assert broke <= 1
        if broke:
            e = int(np.flatnonzero(before != j.state[0])[0])
            assert j.state[0, e] == fj.BROKEN_TENSION
            order.append(e)
            at_theta.append(j.table[fj.THETA, 0])
            moments.append(j.table[fj.M, 0])
    assert order == [0, 1, 2]
    theta_c = sigma_c * MPA / (kn * np.abs(xi[:3]))
    assert np.all(np.asarray(at_theta) >= theta_c * (1 - 1e-12)) and np.all(np.asarray(at_theta) < theta_c + step)
    assert np.all(j.state[0, 3:] == fj.BONDED)
    theta1 = at_theta[0]
    rest = 2 / 3 * rbar**3 - (length * xi[0]**2 + length**3 / 12)
    assert moments[0] == pytest.approx(kn * theta1 * rest, rel=1e-9)
    assert moments[0] > 0 and moments[-1] > 0
    # it still resists further rotation after all its tension side has gone
    m = j.table[fj.M, 0]
    law(j, dtheta=step)
    assert j.table[fj.M, 0] > m


# --- failure of a bonded element ---------------------------------------------------------

@pytest.mark.parametrize("factor, broken", [(1 - 1e-6, False), (1 + 1e-6, True)])
def test_tension_failure_at_the_tensile_strength(factor, broken):
    """Pulled uniformly to σ = factor σ_c, every element breaks in tension just above the
    strength; broken and open, they carry nothing."""
    sigma_c = 25.0
    j = joint(3, ten=sigma_c, coh=1e4)
    law(j, dn=factor * sigma_c * MPA / kn_of())
    if not broken:
        assert np.all(j.state[0] == fj.BONDED)
        assert j.table[fj.FN, 0] == pytest.approx(factor * sigma_c * MPA * 2 * rbar_of(), rel=1e-9)
    else:
        assert np.all(j.state[0] == fj.BROKEN_TENSION)
        assert j.table[fj.FN, 0] == j.table[fj.FS, 0] == j.table[fj.M, 0] == 0.0
        law(j, dn=-0.5 * factor * sigma_c * MPA / kn_of())  # still open: nothing
        assert j.table[fj.FN, 0] == 0.0


@pytest.mark.parametrize("fa", [0.0, 35.0])
@pytest.mark.parametrize("sigma_mpa", [-12.0, 0.0, 8.0])
@pytest.mark.parametrize("factor, broken", [(1 - 1e-6, False), (1 + 1e-6, True)])
def test_shear_failure_at_cohesion_minus_normal_stress_tan_phi(fa, sigma_mpa, factor, broken):
    """Loaded to a normal stress σ (tension positive), then sheared in one step: the elements
    break in shear exactly when |F_s^e|/A_e exceeds c - σ tan φ (compression strengthens,
    tension weakens). Broken, they keep only friction: μ |F_n| in compression, nothing in
    tension."""
    coh, fric = 20.0, 0.5
    j = joint(2, ten=100.0, coh=coh, fa=fa, fric=fric)
    area = 2 * rbar_of()
    law(j, dn=sigma_mpa * MPA / kn_of())
    assert j.table[fj.FN, 0] / area == pytest.approx(sigma_mpa * MPA, rel=1e-9, abs=1e-3)
    strength = (coh - sigma_mpa * np.tan(np.radians(fa))) * MPA
    fs = factor * strength * area
    law(j, ds=fs / (kn_of() / KRATIO * area))
    if not broken:
        assert np.all(j.state[0] == fj.BONDED)
        assert j.table[fj.FS, 0] == pytest.approx(fs, rel=1e-9)
    else:
        assert np.all(j.state[0] == fj.BROKEN_SHEAR)
        assert j.table[fj.FS, 0] == pytest.approx(fric * max(0.0, -sigma_mpa * MPA) * area,
                                                  rel=1e-9, abs=1e-9)
        assert j.table[fj.FN, 0] == pytest.approx(min(0.0, sigma_mpa) * MPA * area, rel=1e-9)


def test_tension_is_checked_before_shear():
    """A load past both strengths breaks the elements in tension (tension is checked first)."""
    j = joint(2, ten=10.0, coh=10.0)
    law(j, dn=12.0 * MPA / kn_of(), ds=12.0 * MPA / (kn_of() / KRATIO))
    assert np.all(j.state[0] == fj.BROKEN_TENSION)


# --- unbonded elements: slit and gapped ----------------------------------------------------

def test_a_slit_interface_carries_compression_and_friction_but_no_tension():
    """A slit joint (g_0 = 0, elements unbonded): compression k_n A dn, nothing in tension; its
    shear force grows as k_s A ds until it slips at μ |F_n|, and unloads elastically."""
    nr, fric = 3, 0.4
    j = joint(nr, bonded=False, fric=fric)
    kn, area = kn_of(), 2 * rbar_of()
    ks = kn / KRATIO
    law(j, dn=2e-8)  # opening from touching: nothing
    assert j.table[fj.FN, 0] == j.table[fj.FS, 0] == j.table[fj.M, 0] == 0.0
    law(j, dn=-5e-8)  # now closed by 3e-8
    fn = -kn * area * 3e-8
    assert j.table[fj.FN, 0] == pytest.approx(fn, rel=1e-9)
    assert np.all(j.state[0] == fj.UNBONDED)
    ds = 0.1 * fric * abs(fn) / (ks * area)
    shear = []
    for _ in range(15):
        law(j, ds=ds)
        shear.append(j.table[fj.FS, 0])
    expected = np.minimum(ks * area * ds * np.arange(1, 16), fric * abs(fn))
    np.testing.assert_allclose(shear, expected, rtol=1e-9)
    law(j, ds=-ds)  # unloading from the slip limit is elastic
    assert j.table[fj.FS, 0] == pytest.approx(fric * abs(fn) - ks * area * ds, rel=1e-9)
    law(j, dn=1e-7)  # pulled apart: nothing, friction included
    assert j.table[fj.FN, 0] == j.table[fj.FS, 0] == j.table[fj.M, 0] == 0.0


def test_a_closed_slit_interface_resists_bending_until_it_opens():
    """Under compression a slit joint bends as a bonded one (k_n I) while closed everywhere;
    past the rotation that opens its edge (θ R̄ = |g_s|) it is softer, but never pulls."""
    nr = 4
    j = joint(nr, bonded=False)
    kn, rbar = kn_of(), rbar_of()
    closing = 1e-7
    law(j, dn=-closing)
    theta = 0.5 * closing / rbar
    law(j, dtheta=theta)
    assert j.table[fj.M, 0] == pytest.approx(kn * 2 / 3 * rbar**3 * theta, rel=1e-9)
    law(j, dtheta=2 * theta)  # now open over a sixth of its length, at its edge ξ = -R̄
    assert 0 < j.table[fj.M, 0] < kn * 2 / 3 * rbar**3 * 3 * theta
    assert np.all(j.elements[fj.E_FN, 0] <= 0.0)


def test_a_gapped_element_carries_nothing_until_its_gap_closes():
    """A gapped joint (g_0 > 0, unbonded): closing it by less than g_0, and sliding it, loads
    nothing; closed by more, it carries k_n A (dn + g_0) in compression, and friction from
    then on."""
    g0, fric = 2e-7, 0.5
    j = joint(2, bonded=False, gap0=g0, fric=fric)
    kn, area = kn_of(), 2 * rbar_of()
    ks = kn / KRATIO
    for _ in range(3):
        law(j, dn=-0.5e-7, ds=1e-8, dtheta=1e-6)
        assert j.table[fj.FN, 0] == j.table[fj.FS, 0] == j.table[fj.M, 0] == 0.0
    law(j, dtheta=-3e-6)  # back to no rotation
    law(j, dn=-1e-7)  # closed by 0.5e-7
    fn = -kn * area * 0.5e-7
    assert j.table[fj.FN, 0] == pytest.approx(fn, rel=1e-9)
    assert j.table[fj.FS, 0] == 0.0
    law(j, ds=1e-9)
    assert j.table[fj.FS, 0] == pytest.approx(min(ks * area * 1e-9, fric * abs(fn)), rel=1e-9)


@pytest.mark.parametrize("bonded", [True, False])
@pytest.mark.parametrize("gc, theta", [(1e-7, 0.0), (-1e-7, 0.0), (1e-8, 1e-4), (1e-8, -1e-4),
                                       (-1e-8, 2e-4), (-1e-8, -2e-4), (5e-7, 1e-4)])
def test_element_force_and_moment_are_the_stress_integrated_over_the_element(bonded, gc, theta):
    """The closed forms of an element's normal force and moment (also over the closed part of
    a partly open unbonded element) against a fine midpoint quadrature of k_n g(ξ)
    (bonded) or k_n min(g, 0) (unbonded) over it."""
    kn, xc, length = 1e13, 0.3e-3, 0.4e-3
    fn, me = fj.element_normal_force(kn, gc + theta * xc, theta, xc, length, bonded)
    u = (np.arange(200000) + 0.5) / 200000 * length - 0.5 * length
    g = gc - theta * u
    stress = kn * (g if bonded else np.minimum(g, 0.0))
    du = length / len(u)
    scale = kn * length * (abs(gc) + abs(theta) * length)
    assert fn == pytest.approx(stress.sum() * du, rel=1e-6, abs=1e-9 * scale)
    assert me == pytest.approx(-(stress * u).sum() * du, rel=1e-6, abs=1e-9 * scale * length)


# --- strengths ---------------------------------------------------------------------------

def test_element_strengths_are_drawn_reproducibly_by_seed():
    """Each element's tensile strength and cohesion (the law's per-element arrays) come from the
    material's seeded draws: the same seed gives the same arrays, bit for bit, another seed
    others; as in PFC, the elements of one joint share its draw (fj_ten, fj_coh are contact
    properties)."""
    from rockcal.specimens.specimen import hexagonal
    from rockcal.materials import flat_joint as fjm

    spec = hexagonal(4.0, 4.0, 0.25)
    params = fjm.make_flatjoint_params({"fj_nr": 3, "fj_ten_sd": 10.0, "fj_coh_cv": 0.3})
    first, again, other = (fjm.assign_flatjointed(spec.pos, spec.radius, params, 0.0, seed=s).joints()
                           for s in (11, 11, 12))
    for row in (fj.E_TEN, fj.E_COH):
        np.testing.assert_array_equal(first.elements[row], again.elements[row])
        assert not np.array_equal(first.elements[row], other.elements[row])
        assert np.all(first.elements[row] == first.elements[row][:, :1])
        assert first.elements[row].min() >= 0.0 and len(np.unique(first.elements[row])) > 10
