"""A bonded simple-cubic lattice of equal spheres (spacing d = 2R, bonds between nearest
neighbours) has the elastic constants of a cubic spring lattice:

- uniaxial strain ε_xx: each x-bond stretches by ε d and carries k_n ε d over an area d², so
  C11 = k_n / d, and no lateral stress, C12 = 0;
- symmetric shear u_x = γ y / 2, u_y = γ x / 2: the spheres do not turn (their moments cancel),
  x- and y-bonds slide by γ d / 2 and carry k_s γ d / 2 over d², so C44 = σ_xy / γ = k_s / (2d)
  (strain energy k_s γ² / (4d) per volume).

k_n and k_s are the bond's and the contact's springs in parallel where the contact is closed:
k̄n Ā + kn in compression, k̄n Ā in tension; k̄s Ā in shear, plus ks once the lattice is
precompressed (with μ large enough that the contacts stick). Precompressed to a stress σ0, the
bonds' normal forces turn with them as the lattice shears and add σ0 γ / 2 to σ_xy (the
initial-stress term), and the spacing is the compressed one, d' = d (1 + ε0).

The outer layer of spheres is driven along the affine field; the 4 x 4 x 4 inner spheres are
free and find their equilibrium under local damping. Strain is fitted to the inner spheres'
displacements; stress is the force across the mid-plane carried by the bonds between inner
spheres, over their share d² of the plane.
"""

import numpy as np
import pytest

from rockcal.dem3d.bonds import Bond
from rockcal.dem3d.laws import Laws, bond_springs, contact_springs
from rockcal.dem3d.simulate import advance, assemble_state, scale_density

SIDE = 6
R = 1e-3
D = 2 * R
LAWS = Laws(E_c=30e9, ks_per_kn=0.4, mu=5.0, Ebar_c=50e9, ksbar_per_knbar=0.5, lam=1.0,
            tan_phi=0.0, mcf=1.0)
STRAIN = 1e-4


def lattice():
    """The bonded lattice, its outer spheres driven, with density scaling."""
    index = np.array([(i, j, k) for k in range(SIDE) for j in range(SIDE) for i in range(SIDE)])
    pos = index * D
    flat = lambda ijk: (ijk[..., 2] * SIDE + ijk[..., 1]) * SIDE + ijk[..., 0]
    pairs = np.concatenate([np.column_stack([flat(index[index[:, a] < SIDE - 1]),
                                             flat(index[index[:, a] < SIDE - 1] + np.eye(3, dtype=int)[a])])
                            for a in range(3)])
    outer = np.flatnonzero(((index == 0) | (index == SIDE - 1)).any(axis=1))
    state = assemble_state(pos, np.full(len(pos), R), pairs, 2650.0, LAWS, damping=0.7,
                           driven=outer)
    scale_density(state)
    return state, index, outer


def deform(state, outer, gradient, steps=400, relax=1500):
    """Move the outer spheres along u = gradient x over `steps` steps, then hold and relax."""
    s = state.spheres
    s.vel[outer] = (s.pos[outer] - s.pos[outer].mean(axis=0)) @ gradient.T / (steps * state.dt)
    advance(state, steps)
    s.vel[outer] = 0.0
    advance(state, relax)


def inner_strain(state, index, start):
    """The displacement gradient fitted to the inner spheres' displacements."""
    inner = np.flatnonzero(((index > 0) & (index < SIDE - 1)).all(axis=1))
    x = np.column_stack([start[inner], np.ones(len(inner))])
    fit, *_ = np.linalg.lstsq(x, state.spheres.pos[inner] - start[inner], rcond=None)
    return fit[:3].T


def mid_plane_traction(state, index, axis, start):
    """Force per area on the lower half across the mid-plane normal to `axis`, from the bonded
    pairs (bond plus contact) joining inner spheres across it, each over its share of the
    plane at the current spacing (the fitted strain since the lattice's `start` positions)."""
    s, nl = state.spheres, state.neighbours
    pi, pj = nl.pi[:nl.n_bonds], nl.pj[:nl.n_bonds]
    inner = ((index > 0) & (index < SIDE - 1)).all(axis=1)
    crossing = inner[pi] & inner[pj] & (index[pi, axis] == SIDE // 2 - 1) \
        & (index[pj, axis] == SIDE // 2)
    d = s.pos[pj] - s.pos[pi]
    dist = np.linalg.norm(d, axis=1)
    n = d / dist[:, None]
    overlap = 2 * R - dist - state.bonds.table[Bond.REF_OVERLAP]
    kn, _ = contact_springs(R, 2 * R, state.laws)
    fn = state.bonds.table[Bond.FN] - np.where(overlap > 0, kn * overlap, 0.0)
    force = fn[:, None] * n + state.bonds.shear_force() + state.bonds.contact_shear()
    stretch = 1.0 + np.diag(inner_strain(state, index, start))
    share = D * D * np.prod(np.delete(stretch, axis))
    return force[crossing].sum(axis=0) / (np.count_nonzero(crossing) * share)


def test_uniaxial_strain_gives_c11_of_bond_and_contact_in_parallel_and_no_lateral_stress():
    kbn_a, _, _, _ = bond_springs(R, 2 * R, LAWS)
    kn, _ = contact_springs(R, 2 * R, LAWS)
    for sign, k_normal in ((-1, kn + kbn_a), (1, kbn_a)):
        state, index, outer = lattice()
        start = state.spheres.pos.copy()
        deform(state, outer, np.diag([sign * STRAIN, 0.0, 0.0]))
        grad = inner_strain(state, index, start)
        assert grad[0, 0] == pytest.approx(sign * STRAIN, rel=1e-3)
        assert np.abs(grad - np.diag(np.diag(grad))).max() < 1e-6 * STRAIN
        sxx = mid_plane_traction(state, index, 0, start)[0]
        assert sxx / grad[0, 0] == pytest.approx(k_normal / D, rel=1e-4)
        syy = mid_plane_traction(state, index, 1, start)[1]
        assert abs(syy) < 1e-6 * abs(sxx)


@pytest.mark.parametrize("precompressed", [False, True])
def test_symmetric_shear_gives_c44_of_the_shear_springs(precompressed):
    """Unloaded, only the bonds' shear springs act (the contacts open as the lattice shears);
    precompressed, the closed contacts' ks adds in parallel."""
    _, kbs_a, _, _ = bond_springs(R, 2 * R, LAWS)
    _, ks = contact_springs(R, 2 * R, LAWS)
    state, index, outer = lattice()
    built = state.spheres.pos.copy()
    if precompressed:
        deform(state, outer, -STRAIN * np.eye(3))
    sigma_0 = mid_plane_traction(state, index, 0, built)[0]
    spacing = D * (1.0 + inner_strain(state, index, built)[0, 0])
    assert (sigma_0 < 0) == precompressed
    start = state.spheres.pos.copy()
    gamma = 0.2 * STRAIN
    deform(state, outer, np.array([[0, gamma / 2, 0], [gamma / 2, 0, 0], [0, 0, 0]]))
    grad = inner_strain(state, index, start)
    measured_gamma = grad[0, 1] + grad[1, 0]
    assert measured_gamma == pytest.approx(gamma, rel=1e-3)
    sxy = mid_plane_traction(state, index, 0, built)[1]
    syx = mid_plane_traction(state, index, 1, built)[0]
    k_shear = kbs_a + (ks if precompressed else 0.0)
    c44 = k_shear / (2 * spacing) + sigma_0 / 2
    assert sxy / measured_gamma == pytest.approx(c44, rel=1e-4)
    assert syx == pytest.approx(sxy, rel=1e-6)
    assert np.abs(state.spheres.spin).max() * state.dt < 1e-9 * gamma
