"""PFC3D's linear parallel bond between two spheres, against its closed forms.

Bond of radius R̄ = λ̄ min(R_0, R_1): Ā = π R̄², Ī = π R̄⁴/4, J̄ = π R̄⁴/2, k̄n = Ē_c / (R_0 + R_1),
k̄s = k̄n / (k̄n/k̄s). Springs: k̄n Ā along the normal, k̄s Ā in shear, k̄s J̄ in twist, k̄n Ī in
bending; a touching contact adds kn = E_c π min(R)² / (R_0 + R_1) in compression. Strengths:
pulled apart F = σ̄c Ā; bent M = σ̄c Ī / (β̄ R̄); twisted M = c̄ J̄ / (β̄ R̄); sheared
F = (c̄ - σ tan φ̄) Ā with σ = F̄n / Ā (tension positive).

Both spheres are driven: sphere 1 moves with a prescribed velocity and spin, sphere 0 stays put
(spun only in bending);
the pair lies along an oblique normal so that every vector component takes part.
"""

import numpy as np
import pytest

from rockcal.dem3d.bonds import Bond
from rockcal.dem3d.laws import BROKEN_SHEAR, BROKEN_TENSION, INTACT, Laws
from rockcal.dem3d.simulate import advance, assemble_state

R0, R1 = 1.0e-3, 1.25e-3
LAM = 0.8
EBAR = 40e9
KBN_KBS = 1.6
SIGMA_C, COH = 20e6, 30e6
N = np.array([1.0, 2.0, 2.0]) / 3.0  # normal from sphere 0 to sphere 1
T = np.array([2.0, 1.0, -2.0]) / 3.0  # a direction in the contact plane
B = np.cross(N, T)  # the other one
RB = LAM * min(R0, R1)
AREA, INERTIA, POLAR = np.pi * RB**2, np.pi * RB**4 / 4, np.pi * RB**4 / 2
KBN = EBAR / (R0 + R1)
KBS = KBN / KBN_KBS


def bonded_pair(E_c=0.0, mcf=1.0, tan_phi=0.0, ten=SIGMA_C, coh=COH):
    """Two driven spheres bonded while touching; E_c = 0 leaves the bond alone."""
    p0 = np.array([0.3e-3, -0.2e-3, 0.1e-3])
    pos = np.array([p0, p0 + (R0 + R1) * N])
    laws = Laws(E_c=E_c, ks_per_kn=0.5, mu=1e3, Ebar_c=EBAR, ksbar_per_knbar=1 / KBN_KBS,
                lam=LAM, tan_phi=tan_phi, mcf=mcf)
    state = assemble_state(pos, [R0, R1], [[0, 1]], 2650.0, laws, damping=0.0, ten=ten,
                           coh=coh, driven=[0, 1])
    state.dt = 1e-7  # no free sphere sets one
    return state


def drive(state, vel=(0.0, 0.0, 0.0), spin=(0.0, 0.0, 0.0), steps=1, spin_0=(0.0, 0.0, 0.0)):
    """Sphere 1 at `vel` and `spin` (sphere 0 at `spin_0`) for `steps` steps; the bond's and
    sphere 0's loads after each: F̄n, F̄s, M̄b, M̄t, force and moment on sphere 0, bond state."""
    state.spheres.spin[1] = spin
    state.spheres.spin[0] = spin_0
    out = []
    for _ in range(steps):
        state.spheres.vel[1] = vel
        advance(state, 1)
        b = state.bonds
        out.append((b.table[Bond.FN, 0], b.shear_force()[0].copy(),
                    b.bending_moment()[0].copy(), b.table[Bond.MT, 0],
                    state.spheres.force[0].copy(), state.spheres.moment[0].copy(),
                    state.bonds.state[0]))
    return out


def slope(values, step_size):
    """d value / d (prescribed motion) between the 5th and the last step."""
    return (values[-1] - values[4]) / ((len(values) - 5) * step_size)


def test_normal_stiffness_is_the_contact_and_bond_springs_in_parallel():
    """Pushed together the force grows at kn + k̄n Ā per unit of approach; pulled apart at k̄n Ā
    (the contact takes no tension); the force on sphere 0 is along the normal."""
    state = bonded_pair(E_c=30e9)
    kn = 30e9 * np.pi * min(R0, R1) ** 2 / (R0 + R1)
    step = 1e-9
    push = drive(state, vel=-step / state.dt * N, steps=40)
    force = np.array([h[4] for h in push])
    assert slope(force @ N, step) == pytest.approx(-(kn + KBN * AREA), rel=1e-9)
    np.testing.assert_allclose(np.cross(force[-1], N), 0.0, atol=1e-12 * abs(force[-1] @ N))
    pull = drive(state, vel=step / state.dt * N, steps=120)
    fn = np.array([h[0] for h in pull])
    total = np.array([h[4] @ N for h in pull])
    assert slope(fn, step) == pytest.approx(KBN * AREA, rel=1e-9)
    assert slope(total[-30:], step) == pytest.approx(KBN * AREA, rel=1e-9)  # contact open


def test_shear_stiffness_and_the_moment_of_the_shear_force():
    """Slid along the contact plane (no spin), the bond's shear force grows at k̄s Ā against
    the motion of sphere 0 relative to 1, no bending or twist appears, and sphere 0 gets the
    moment of the shear force at its lever arm R_0 (the contact point is at the surface)."""
    state = bonded_pair()
    step = 1e-10
    history = drive(state, vel=step / state.dt * T, steps=50)
    fs = np.array([h[1] for h in history])
    assert slope(fs @ T, step) == pytest.approx(KBS * AREA, rel=1e-6)
    assert np.abs(fs @ B).max() < 1e-9 * np.abs(fs @ T).max()
    _, _, mb, mt, _, moment, _ = history[-1]
    assert np.linalg.norm(mb) == 0.0 and mt == 0.0
    np.testing.assert_allclose(moment, R0 * np.cross(N, fs[-1]), rtol=1e-6,
                               atol=1e-9 * R0 * np.linalg.norm(fs[-1]))


def test_twisting_stiffness_is_ks_bar_J():
    """Sphere 1 spun about the normal: the twisting moment grows at k̄s J̄ per radian, and it is
    the only load."""
    state = bonded_pair()
    step = 1e-7  # rad per step
    history = drive(state, spin=step / state.dt * N, steps=50)
    mt = np.array([h[3] for h in history])
    assert slope(mt, step) == pytest.approx(KBS * POLAR, rel=1e-9)
    fn, fs, mb, _, _, moment, _ = history[-1]
    assert fn == 0.0 and np.linalg.norm(fs) < 1e-12 * abs(mt[-1]) / RB
    assert np.linalg.norm(mb) < 1e-12 * abs(mt[-1])
    np.testing.assert_allclose(moment, mt[-1] * N, rtol=1e-12)


def bending(rate, axis):
    """Spins of spheres 0 and 1 that turn them relative to each other at `rate` about `axis`
    (across the normal) with their contact point at rest: -rate R1/L and rate R0/L (their
    lever arms are R0 and R1, L = R0 + R1). The centres stay: pure bending."""
    length = R0 + R1
    return {"spin_0": -rate * R1 / length * axis, "spin": rate * R0 / length * axis}


def test_bending_stiffness_is_kn_bar_I():
    """The spheres turned relative to each other about an axis across the normal, their
    contact point at rest: the bending moment grows at k̄n Ī per radian about that axis, and it
    is the only load."""
    state = bonded_pair()
    step = 1e-7
    history = drive(state, steps=50, **bending(step / state.dt, B))
    mb = np.array([h[2] for h in history])
    assert slope(mb @ B, step) == pytest.approx(KBN * INERTIA, rel=1e-9)
    fn, fs, _, mt, _, moment, _ = history[-1]
    assert fn == 0.0 and np.linalg.norm(fs) < 1e-12 * KBS * AREA * step * 50
    assert abs(mt) < 1e-12 * np.linalg.norm(mb[-1])
    np.testing.assert_allclose(moment, mb[-1], rtol=1e-12)


def peak_before_break(history, load):
    """The largest `load` of the intact bond, and the mode it broke in."""
    modes = np.array([h[6] for h in history])
    broke = np.flatnonzero(modes != INTACT)
    assert len(broke), "the bond did not break"
    return max(load(h) for h in history[:broke[0]]), modes[broke[0]]


STEPS_TO_BREAK = 1000  # the load grows by 1/1000 of the strength per step


def test_pulled_apart_it_breaks_in_tension_at_sigma_c_A():
    state = bonded_pair()
    strength = SIGMA_C * AREA
    step = strength / (KBN * AREA) / STEPS_TO_BREAK
    history = drive(state, vel=step / state.dt * N, steps=int(1.05 * STEPS_TO_BREAK))
    peak, mode = peak_before_break(history, lambda h: h[0])
    assert mode == BROKEN_TENSION
    assert peak == pytest.approx(strength, rel=2 / STEPS_TO_BREAK)
    assert peak <= strength
    assert history[-1][0] == 0.0 and np.all(history[-1][4] == 0.0)  # a broken bond carries nothing


@pytest.mark.parametrize("mcf", [1.0, 0.5])
def test_bent_it_breaks_in_tension_at_sigma_c_I_over_mcf_R(mcf):
    state = bonded_pair(mcf=mcf)
    strength = SIGMA_C * INERTIA / (mcf * RB)
    step = strength / (KBN * INERTIA) / STEPS_TO_BREAK
    history = drive(state, steps=int(1.05 * STEPS_TO_BREAK), **bending(step / state.dt, B))
    peak, mode = peak_before_break(history, lambda h: np.linalg.norm(h[2]))
    assert mode == BROKEN_TENSION
    assert peak == pytest.approx(strength, rel=2 / STEPS_TO_BREAK)


@pytest.mark.parametrize("mcf", [1.0, 0.5])
def test_twisted_it_breaks_in_shear_at_c_J_over_mcf_R(mcf):
    state = bonded_pair(mcf=mcf)
    strength = COH * POLAR / (mcf * RB)
    step = strength / (KBS * POLAR) / STEPS_TO_BREAK
    history = drive(state, spin=step / state.dt * N, steps=int(1.05 * STEPS_TO_BREAK))
    peak, mode = peak_before_break(history, lambda h: abs(h[3]))
    assert mode == BROKEN_SHEAR
    assert peak == pytest.approx(strength, rel=2 / STEPS_TO_BREAK)


@pytest.mark.parametrize("precompression", [0.0, 0.5])
def test_sheared_it_breaks_at_c_minus_sigma_tan_phi_times_A(precompression):
    """With φ̄ = 30°: unloaded it breaks at |F̄s| = c̄ Ā; pressed first to a normal stress σ =
    -precompression × c̄ (compression negative) it holds (c̄ - σ tan φ̄) Ā, PFC's sign."""
    tan_phi = np.tan(np.radians(30.0))
    state = bonded_pair(tan_phi=tan_phi, ten=1e12)
    sigma = -precompression * COH
    if precompression:
        approach = -sigma / KBN
        drive(state, vel=-approach / 100 / state.dt * N, steps=100)
    fn = drive(state)[-1][0]
    assert fn / AREA == pytest.approx(sigma, rel=1e-9, abs=1e-6 * COH)
    strength = (COH - fn / AREA * tan_phi) * AREA
    step = strength / (KBS * AREA) / STEPS_TO_BREAK
    history = drive(state, vel=step / state.dt * T, steps=int(1.3 * STEPS_TO_BREAK))
    peak, mode = peak_before_break(history, lambda h: np.linalg.norm(h[1]))
    assert mode == BROKEN_SHEAR
    assert peak == pytest.approx(strength, rel=2 / STEPS_TO_BREAK)
