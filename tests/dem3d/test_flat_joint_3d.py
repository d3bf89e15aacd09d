"""PFC3D's flat joint between two spheres against its closed forms.

Interface of radius R̄ = λ min(R_0, R_1): A = π R̄², I = π R̄⁴/4, J = π R̄⁴/2, k_n = E* / (R_0 + R_1),
k_s = k_n / κ*. A bonded interface: k_n A along the normal (tension and compression), k_s A in
shear, k_n I in bending and k_s J in twist, whatever N_r and N_α. An unbonded one: compression
only, so bent at zero gap half of it closes (moment k_n I θ / 2), and bent further than its
closure it opens over the segment the gap field leaves open. A bonded one pulled apart breaks
at σ_c A, sheared at c A, and an unbonded one slides at μ |F_n|.

Both spheres are driven (sphere 1 moved, sphere 0 still, or both spun in opposite senses to bend
and twist), of equal radii so that spinning them slides nothing; the pair lies along an oblique
normal so that every vector component takes part.
"""

import numba
import numpy as np
import pytest

from rockcal.dem3d import flat_joint as fj
from rockcal.dem3d.laws import Laws
from rockcal.dem3d.simulate import advance, assemble_state

R = 1.0e-3
LAM = 0.9
EMOD = 40e9
KRATIO = 1.6
N = np.array([1.0, 2.0, 2.0]) / 3.0  # normal from sphere 0 to sphere 1
T = np.array([2.0, 1.0, -2.0]) / 3.0  # a direction in the contact plane
RB = LAM * R
AREA, INERTIA, POLAR = np.pi * RB**2, np.pi * RB**4 / 4, np.pi * RB**4 / 2
KN = EMOD / (2 * R)
KS = KN / KRATIO
LINEAR = Laws(E_c=0.0, ks_per_kn=0.5, mu=0.5, Ebar_c=0.0, ksbar_per_knbar=1.0, lam=1.0,
              tan_phi=0.0, mcf=1.0)


def joined_pair(bonded=True, ten=np.inf, coh=np.inf, fric=0.5, nr=2, nal=4, gap0=0.0,
                cohres=0.0):
    """Two driven spheres touching along N, joined by one flat joint."""
    p0 = np.array([0.3e-3, -0.2e-3, 0.1e-3])
    pos = np.array([p0, p0 + 2 * R * N])

    def joints(pos, radius, pi, pj, order):
        d = pos[pj] - pos[pi]
        return fj.new_flatjoints_3d(nr, nal, d / np.linalg.norm(d, axis=1)[:, None], 0.0, KN, KS,
                                    LAM, fric, 0.0, gap0, bonded, ten, coh, cohres)

    state = assemble_state(pos, [R, R], [[0, 1]], 2650.0, LINEAR, damping=0.0, driven=[0, 1],
                           joints=joints)
    state.dt = 1e-7
    return state


def drive(state, vel=(0.0, 0.0, 0.0), spin=(0.0, 0.0, 0.0), steps=1):
    """Sphere 1 at `vel`, the spheres at spins +`spin` (1) and -`spin` (0), for `steps` steps;
    after each the force and moment on sphere 0 and the joint's FN."""
    state.spheres.spin[1] = spin
    state.spheres.spin[0] = -np.asarray(spin)
    out = []
    for _ in range(steps):
        state.spheres.vel[1] = vel
        advance(state, 1)
        out.append((state.spheres.force[0].copy(), state.spheres.moment[0].copy(),
                    state.bonds.table[fj.FN, 0]))
    return out


def slope(values, size):
    return (values[-1] - values[1]) / ((len(values) - 2) * size)


@pytest.mark.parametrize("nr, nal", [(1, 3), (3, 5)])
def test_bonded_interface_is_a_parallel_bond_of_its_disk(nr, nal):
    """Each motion alone: k_n A pulled and pushed, k_s A sheared, k_n I bent, k_s J twisted,
    whatever the elements."""
    step = 1e-9
    angle = 1e-7
    dt = 1e-7
    pull = drive(joined_pair(nr=nr, nal=nal), vel=step / dt * N, steps=6)
    assert slope(np.array([h[0] for h in pull]) @ N, step) == pytest.approx(KN * AREA, rel=1e-9)
    push = drive(joined_pair(nr=nr, nal=nal), vel=-step / dt * N, steps=6)
    assert slope(np.array([h[0] for h in push]) @ N, step) == pytest.approx(-KN * AREA, rel=1e-9)
    shear = drive(joined_pair(nr=nr, nal=nal), vel=step / dt * T, steps=6)
    force = np.array([h[0] for h in shear])
    assert slope(force @ T, step) == pytest.approx(KS * AREA, rel=1e-6)
    # the moment on sphere 0 of the shear force (lever arm R) and of the bend it takes with it
    bend = drive(joined_pair(nr=nr, nal=nal), spin=0.5 * angle / dt * T, steps=6)
    moment = np.array([h[1] for h in bend])
    assert slope(moment @ T, angle) == pytest.approx(KN * INERTIA, rel=1e-6)
    twist = drive(joined_pair(nr=nr, nal=nal), spin=0.5 * angle / dt * N, steps=6)
    moment = np.array([h[1] for h in twist])
    assert slope(moment @ N, angle) == pytest.approx(KS * POLAR, rel=1e-6)
    np.testing.assert_allclose(np.cross(moment[-1], N), 0.0, atol=1e-9 * abs(moment[-1] @ N))


def test_unbonded_interface_takes_no_tension():
    """Pulled apart an unbonded (slit) interface carries nothing; pushed, k_n A."""
    step = 1e-9
    pull = drive(joined_pair(bonded=False), vel=step / 1e-7 * N, steps=4)
    assert all(np.all(h[0] == 0.0) for h in pull)
    push = drive(joined_pair(bonded=False), vel=-step / 1e-7 * N, steps=12)
    assert slope(np.array([h[0] for h in push]) @ N, step) == pytest.approx(-KN * AREA, rel=1e-9)


def segment(x0):
    """∫ dA, ∫ x dA and ∫ x² dA over the part x < x0 of the disk of radius R̄ (x0 <= R̄)."""
    root = np.sqrt(RB * RB - x0 * x0)
    turn = np.arcsin(x0 / RB) + np.pi / 2
    return (x0 * root + RB**2 * turn, -2 / 3 * root**3,
            x0 * (2 * x0 * x0 - RB * RB) * root / 4 + RB**4 * turn / 4)


@pytest.mark.parametrize("nr, nal", [(2, 4), (3, 7)])
def test_half_open_disk_moment_rotation(nr, nal):
    """An unbonded interface bent at zero gap closes over half its disk: M = k_n I θ / 2. Pushed
    to a closure δ first, then bent by θ, it stays closed until θ R̄ = δ, then opens where
    g = -δ + θ x > 0: F = k_n ∫(θ x - δ) dA and M = k_n ∫ x (θ x - δ) dA over x < δ / θ."""
    dt = 1e-7
    angle = 2e-7
    half = drive(joined_pair(bonded=False, nr=nr, nal=nal), spin=0.5 * angle / dt * T, steps=5)
    assert half[-1][1] @ T == pytest.approx(KN * INERTIA / 2 * 5 * angle, rel=1e-7)
    closure = 3e-10
    state = joined_pair(bonded=False, nr=nr, nal=nal)
    drive(state, vel=-closure / dt * N)
    theta = 0.0
    for out in drive(state, spin=0.5 * angle / dt * T, steps=12):
        theta += angle
        # the gap g = -δ + θ x along x = the direction n × T points (`flat_joint`'s gradient)
        area, first, second = segment(min(closure / theta, RB))
        fn = KN * (theta * first - closure * area)
        moment = KN * (theta * second - closure * first)
        assert out[2] == pytest.approx(fn, rel=1e-6)
        assert out[1] @ T == pytest.approx(moment, rel=1e-6)
    assert theta * RB > 2 * closure  # well open at the end


def test_tension_break_then_compression_only():
    """Pulled apart, every element breaks at σ_c A (each carries σ = k_n gap); it then takes
    no tension and, pushed back, compression at k_n A."""
    ten = 5e6
    state = joined_pair(ten=ten, coh=1e9)
    step = 2e-8
    out = drive(state, vel=step / 1e-7 * N, steps=20)
    fn = np.array([h[2] for h in out])
    assert ten * AREA - KN * AREA * step < fn.max() <= ten * AREA
    assert np.all(state.bonds.state == fj.BROKEN_TENSION)
    assert fn[-1] == 0.0
    assert state.n_broken() == state.bonds.state.size
    back = drive(state, vel=-step / 1e-7 * N, steps=30)
    force = np.array([h[0] for h in back]) @ N
    assert force[-1] < 0.0 and slope(force[-5:], step) == pytest.approx(-KN * AREA, rel=1e-9)


def test_shear_break_then_slip_at_friction():
    """Pushed to F_n, then sheared: each element breaks at |F_s| = c A_e (tan φ = 0), then the
    interface slides at μ |F_n|."""
    coh, fric = 4e6, 0.4
    state = joined_pair(ten=1e9, coh=coh, fric=fric)
    dt = 1e-7
    closure = 2e-8
    drive(state, vel=-closure / dt * N)
    step = 1e-8
    out = drive(state, vel=step / dt * T, steps=40)
    shear = np.array([h[0] for h in out]) @ T
    assert coh * AREA - KS * AREA * step < shear.max() <= coh * AREA * (1 + 1e-6)
    assert np.all(state.bonds.state == fj.BROKEN_SHEAR)
    table = state.bonds.table[:, 0]
    assert table[fj.FN] == pytest.approx(-KN * AREA * closure, rel=1e-2)
    assert np.linalg.norm(table[fj.FSX:fj.FSZ + 1]) == pytest.approx(fric * -table[fj.FN], rel=1e-9)


def test_same_bits_on_one_thread_or_two():
    """A block of jittered spheres joined by flat joints, shaken until elements break: the same
    arrays on one thread and two."""
    def run(threads):
        cap = numba.get_num_threads()
        numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
        try:
            state = shaken_block()
            advance(state, 120)
        finally:
            numba.set_num_threads(cap)
        return state

    runs = [run(1), run(2)]
    assert runs[0].n_broken() > 0
    assert len(runs[0].neighbours.block_starts) == 3
    assert np.array_equal(runs[0].spheres.bodies, runs[1].spheres.bodies)
    for a, b in zip(runs[0].bonds, runs[1].bonds):
        assert np.array_equal(a, b, equal_nan=True)


def shaken_block():
    """`test_reproducible_3d`'s block of 13³ spheres joined by flat joints of 2 x 3 elements,
    a fifth of them slit, set moving fast enough at random that elements break."""
    from test_reproducible_3d import jittered_block

    rng = np.random.default_rng(7)
    pos, radius, pi, pj = jittered_block(rng)
    n = len(pi)

    def joints(pos, radius, bi, bj, order):
        d = pos[bj] - pos[bi]
        dist = np.linalg.norm(d, axis=1)
        overlap = radius[bi] + radius[bj] - dist
        kn = EMOD / (radius[bi] + radius[bj])
        return fj.new_flatjoints_3d(2, 3, d / dist[:, None], overlap, kn, kn / KRATIO, 1.0, 0.5,
                                    0.3, 0.0, rng.uniform(size=n)[order] < 0.8,
                                    rng.normal(20e6, 4e6, n)[order], rng.normal(30e6, 6e6, n)[order])

    state = assemble_state(pos, radius, np.column_stack([pi, pj]), 2650.0, LINEAR, damping=0.1,
                           joints=joints)
    state.spheres.vel[:] = rng.normal(0, 6.0, pos.shape)
    state.spheres.spin[:] = rng.normal(0, 2000.0, pos.shape)
    return state


def test_a_simple_cubic_prism_reads_the_joints_modulus_and_no_poisson_effect():
    """The UCS test on a flat-jointed simple-cubic prism: independent columns of joints
    (k_n A = π E* R / 2 each, the contact replaced), E = π E* / 4 and ν = 0."""
    from test_ucs_3d import cubic_prism

    from rockcal.labtests.ucs import simulate_ucs
    from rockcal.materials.flat_joint import make_flatjoint_params

    params = make_flatjoint_params({"fj_emod": 30, "lnm_emod": 10, "fj_kratio": 2.5,
                                    "fj_ten": 1e5, "fj_coh": 1e5})
    result = simulate_ucs(params, cubic_prism(4, 1e-3), max_axial_strain=5e-3)
    assert result.n_broken_tension + result.n_broken_shear == 0
    assert result.E_GPa == pytest.approx(np.pi * 30 / 4, rel=2e-3)
    assert abs(result.nu) < 1e-5
