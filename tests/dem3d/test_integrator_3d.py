"""The explicit integrator of the 3D engine: the time-step rule and density scaling (the 2D
engine's, with a sphere's stiffness sums), the period of a bonded pair and PFC local damping.

A pair bonded along n and moving along it is a linear oscillator: m_eff = m0 m1 / (m0 + m1)
(m1 when sphere 0 is held) on the spring k̄n Ā = Ē_c / (R0 + R1) π (λ̄ min R)², E_c = 0.
"""

import numpy as np
import pytest

from rockcal.dem3d.bonds import Bond
from rockcal.dem3d.laws import Laws
from rockcal.dem3d.simulate import (
    TIME_STEP_SAFETY,
    advance,
    assemble_state,
    scale_density,
)
from rockcal.dem3d.state import solid_sphere

DENSITY = 2650.0
EBAR = 30e9
LAM = 0.7
N = np.array([2.0, 3.0, -6.0]) / 7.0
LAWS = Laws(E_c=0.0, ks_per_kn=0.5, mu=0.5, Ebar_c=EBAR, ksbar_per_knbar=0.4, lam=LAM,
            tan_phi=0.0, mcf=1.0)


def pair(r0, r1, speed=0.0, hold_0=False, damping=0.0):
    """A bonded pair along N; sphere 1 moves away from 0 at `speed` relative to it (no total
    momentum unless 0 is held)."""
    pos = np.array([[1e-3, -2e-3, 0.5e-3], [0.0, 0.0, 0.0]])
    pos[1] = pos[0] + (r0 + r1) * N
    state = assemble_state(pos, [r0, r1], [[0, 1]], DENSITY, LAWS, damping=damping,
                           driven=[0] if hold_0 else None)
    m0, m1 = solid_sphere([r0, r1], DENSITY)[0]
    if hold_0:
        state.spheres.vel[1] = speed * N
    else:
        state.spheres.vel[0] = -speed * m1 / (m0 + m1) * N
        state.spheres.vel[1] = speed * m0 / (m0 + m1) * N
    rb = LAM * min(r0, r1)
    k = EBAR / (r0 + r1) * np.pi * rb**2
    return state, k, (m1 if hold_0 else m0 * m1 / (m0 + m1))


def normal_force_history(state, steps):
    fn = np.empty(steps)
    for s in range(steps):
        advance(state, 1)
        fn[s] = state.bonds.table[Bond.FN, 0]
    return fn


def test_time_step_and_density_scaling_follow_each_spheres_stiffness():
    """dt = safety × min over spheres of sqrt(m / k_t) and sqrt(I / k_r), with k_t = max(k̄n Ā,
    k̄s Ā) and k_r = k̄s Ā R² + max(k̄s J̄, k̄n Ī) (R the sphere's own radius); density scaling
    then gives each sphere m = k_t (dt / safety)² and I = k_r (dt / safety)², dt unchanged."""
    r = np.array([1.0e-3, 1.5e-3])
    state, kbn_a, _ = pair(*r)
    rb = LAM * r.min()
    kbn = EBAR / r.sum()
    kbs = kbn * LAWS.ksbar_per_knbar
    k_t = max(kbn_a, kbs * np.pi * rb**2)
    k_r = kbs * np.pi * rb**2 * r**2 + max(kbs * np.pi * rb**4 / 2, kbn * np.pi * rb**4 / 4)
    m, inertia = solid_sphere(r, DENSITY)
    expected = TIME_STEP_SAFETY * min(np.sqrt(m / k_t).min(), np.sqrt(inertia / k_r).min())
    assert state.dt == pytest.approx(expected, rel=1e-12)
    scale_density(state)
    critical_sq = (state.dt / TIME_STEP_SAFETY) ** 2
    np.testing.assert_allclose(1 / state.spheres.inv_mass, k_t * critical_sq, rtol=1e-12)
    np.testing.assert_allclose(1 / state.spheres.inv_inertia, k_r * critical_sq, rtol=1e-12)
    assert state.dt == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("hold_0", [False, True])
def test_oscillation_period_of_a_bonded_pair(hold_0):
    """2π sqrt(m_eff / k̄n Ā) at 400 steps a period, and central differences' own
    π dt / arcsin(ω dt / 2) at the engine's time step."""
    for steps_per_period in (400, None):
        state, k, m_eff = pair(1e-3, 1.3e-3, speed=0.01, hold_0=hold_0)
        omega = np.sqrt(k / m_eff)
        if steps_per_period:
            state.dt = 2 * np.pi / omega / steps_per_period
        fn = normal_force_history(state, int(20 * 2 * np.pi / omega / state.dt))
        up = np.flatnonzero((fn[:-1] < 0) & (fn[1:] >= 0))
        crossings = up + (-fn[up]) / (fn[up + 1] - fn[up])
        measured = np.diff(crossings).mean() * state.dt
        assert measured == pytest.approx(np.pi * state.dt / np.arcsin(omega * state.dt / 2),
                                         rel=1e-3)
        if steps_per_period:
            assert measured == pytest.approx(2 * np.pi / omega, rel=1e-3)


@pytest.mark.parametrize("alpha", [0.1, 0.3])
def test_local_damping_removes_a_fixed_fraction_per_half_cycle(alpha):
    """PFC local damping (each component reduced by α |F| against its velocity) makes the
    spring (1 + α) stiffer moving out and (1 - α) softer coming back, so successive amplitudes
    shrink by sqrt((1 - α) / (1 + α)), also along an oblique line."""
    state, k, m_eff = pair(1e-3, 1e-3, speed=0.01, hold_0=True, damping=alpha)
    state.dt = 2 * np.pi * np.sqrt(m_eff / k) / 2000
    a = np.abs(normal_force_history(state, 4 * 2000))
    peaks = a[1:-1][(a[1:-1] >= a[:-2]) & (a[1:-1] > a[2:])]
    assert len(peaks) >= 6
    np.testing.assert_allclose(peaks[1:7] / peaks[:6], np.sqrt((1 - alpha) / (1 + alpha)),
                               rtol=5e-3)
