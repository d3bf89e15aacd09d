"""The flat-jointed material in the engine (`simulate._advance`'s flat-joint phase): bonded flat
joints against parallel bonds of the same R̄ and moduli, the time step, and cracks counted per
broken element (the bonded lattice's exact moduli: `tests/test_lattice.py`)."""

import numpy as np
import pytest

from rockcal import hexagonal, make_params
from rockcal.dem import flatjoint as fj
from rockcal.dem.simulate import advance
from rockcal.materials import new_state
from rockcal.materials.flat_joint import make_flatjoint_params

STRONG = {"fj_ten": 1e4, "fj_coh": 1e4}


def twin_states(nr: int, rmul: float = 0.8):
    """A small lattice as bonded flat joints with N_r elements and as parallel bonds of the same
    λ, moduli and stiffness ratios (bonds only: E_c = 0, lnm_emod = 0), both stirred alike."""
    spec = hexagonal(5, 5, 0.25)
    walls = dict(walls=(0, 0, (spec.pos[:, 1] - spec.radius).min(),
                        (spec.pos[:, 1] + spec.radius).max()), wall_active=(False, False, True, True))
    joints = new_state(make_flatjoint_params({"fj_emod": 30, "fj_kratio": 2.5, "fj_nr": nr,
                                              "fj_rmul": rmul, "lnm_emod": 0, **STRONG}),
                       spec, **walls)
    bonds = new_state(make_params({"E_c": 0, "Ebar_c": 30, "kn_ks": 2.5, "lambda": rmul,
                                   "sigma_c": 1e4, "tau_c": 1e4}), spec, **walls)
    rng = np.random.default_rng(3)
    vel, spin = rng.normal(0, 0.02, bonds.particles.vel.shape), rng.normal(0, 50.0, len(spec.radius))
    for state in (joints, bonds):
        state.particles.vel[:] = vel
        state.particles.spin[:] = spin
    return joints, bonds


@pytest.mark.parametrize("nr", [1, 2, 5])
def test_bonded_flat_joints_move_grains_as_parallel_bonds_do(nr):
    """With every element bonded the interface is a parallel bond: the same time step (its
    stiffness sums count k_n A, k_s A and k_n (2/3) R̄³), and the same forces, moments and
    motion over a run of a stirred lattice, to rounding. Undamped: local damping turns with the
    sign of each velocity, which amplifies last-bit differences (the incremental bond against
    the joint's total gap) by orders of magnitude within a few hundred steps."""
    joints, bonds = twin_states(nr)
    assert joints.dt == pytest.approx(bonds.dt, rel=1e-12)
    joints.dt = bonds.dt
    joints.damping = bonds.damping = 0.0
    for _ in range(4):
        advance(joints, 50)
        advance(bonds, 50)
        for a, b in ((joints.particles.force, bonds.particles.force),
                     (joints.particles.moment, bonds.particles.moment),
                     (joints.bonds.table[fj.FN:fj.M + 1], bonds.bonds.table[:3])):
            np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * np.abs(b).max())
            assert np.abs(b).max() > 0
        np.testing.assert_allclose(joints.particles.pos, bonds.particles.pos, rtol=1e-14)
    assert joints.walls.stiffness == bonds.walls.stiffness


def test_a_broken_element_is_a_crack_at_its_centroid():
    """Pulled apart, a lattice breaks elements: each counts once (State.n_broken, by mode), at
    its centroid on the interface (between its two grains' centres)."""
    spec = hexagonal(5, 5, 0.25)
    params = make_flatjoint_params({"fj_emod": 30, "fj_nr": 3, "fj_ten": 1.0, "fj_coh": 50.0})
    state = new_state(params, spec)
    rate = 1e-3 / (200 * state.dt)  # a strain of 1e-3 in 200 steps: E* 1e-3 = 30 MPa > fj_ten
    state.particles.vel[:, 0] = rate * (state.particles.pos[:, 0] - spec.pos[:, 0].mean())
    advance(state, 200)
    mode, where = state.breaks()
    assert mode.shape == (len(spec.bonds) * 3,)
    broken = mode > 0
    assert 0 < state.n_broken() == np.count_nonzero(broken) <= len(mode)
    assert state.n_broken(fj.BROKEN_TENSION) + state.n_broken(fj.BROKEN_SHEAR) == state.n_broken()
    assert np.isfinite(where[broken]).all() and np.isnan(where[~broken]).all()
    pairs = state.neighbours
    nb = pairs.n_bonds
    joint = np.repeat(np.arange(nb), 3)[broken]
    pos = state.particles.pos
    i, j = pairs.pi[:nb][joint], pairs.pj[:nb][joint]
    # the centroid lies within R̄ of the contact point, off the line of centres by |ξ_e| <= R̄
    mid = 0.5 * (pos[i] + pos[j])
    assert np.all(np.hypot(*(where[broken] - mid).T) < 1.01 * params.fj_rmul * 0.25e-3 + 1e-6)
