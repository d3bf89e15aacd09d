"""The bonded hexagonal lattice against its exact plane moduli (the physics check)."""

import numpy as np
import pytest

from rockcal import hexagonal, make_params, simulate_ucs
from rockcal.dem.simulate import BOTTOM, TOP, advance
from rockcal.materials.flat_joint import make_flatjoint_params
from rockcal.materials.parallel_bond import new_state


def exact_moduli(kn: float, ks: float) -> tuple[float, float]:
    """E (per unit thickness) and nu of a triangular lattice of normal and shear springs."""
    return 2 * np.sqrt(3) * kn * (kn + ks) / (3 * kn + ks), (kn - ks) / (3 * kn + ks)


def bonds_only(ratio: float):
    return make_params({"E_c": 0, "Ebar_c": 20, "kn_ks": ratio, "sigma_c": 1e4, "tau_c": 1e4})


@pytest.mark.parametrize("ratio", [1.0, 2.0, 4.0])
def test_hexagonal_lattice_moduli(ratio):
    params = bonds_only(ratio)
    result = simulate_ucs(params, hexagonal(20, 20, 0.25), max_axial_strain=0.002)
    kn = params.Ebar_c * 1e9 * params.lambda_  # kbn * area = Ebar / 2R * 2R * t
    E_exact, nu_exact = exact_moduli(kn, kn / ratio)
    assert result.E_GPa * 1e9 == pytest.approx(E_exact, rel=0.03)
    assert result.nu == pytest.approx(nu_exact, abs=0.015)
    assert result.n_broken_tension == result.n_broken_shear == 0


@pytest.mark.parametrize("ratio", [1.0, 4.0])
def test_hexagonal_lattice_of_bonded_flat_joints_has_the_exact_moduli(ratio):
    """As the parallel-bond lattice (above): each bonded interface is a normal spring
    k_n A = E*/(2R) 2λR = λE* and a shear spring k_s A; the disks do not rotate, so the
    elements' bending stiffness drops out."""
    params = make_flatjoint_params({"fj_emod": 20, "fj_kratio": ratio, "fj_ten": 1e4, "fj_coh": 1e4})
    result = simulate_ucs(params, hexagonal(20, 20, 0.25), max_axial_strain=0.002)
    kn = params.fj_emod * 1e9 * params.fj_rmul
    E_exact, nu_exact = exact_moduli(kn, kn / ratio)
    assert result.E_GPa * 1e9 == pytest.approx(E_exact, rel=0.03)
    assert result.nu == pytest.approx(nu_exact, abs=0.015)
    assert result.n_broken_tension == result.n_broken_shear == 0


def test_lattice_in_equilibrium_without_rotation():
    """Platens carry equal and opposite loads; under uniform strain the disks do not spin."""
    spec = hexagonal(12, 12, 0.25)
    state = new_state(spec.pos, spec.radius, spec.bonds, bonds_only(2.0),
                      walls=(0, 0, (spec.pos[:, 1] - spec.radius).min(),
                             (spec.pos[:, 1] + spec.radius).max()),
                      wall_active=(False, False, True, True))
    state.walls.pos[TOP] -= 2e-6  # 0.02 % strain, then let it settle
    advance(state, 20000)
    f = state.walls.total_force()
    assert f[TOP] > 0
    assert f[BOTTOM] == pytest.approx(f[TOP], rel=1e-3)
    assert np.abs(state.particles.force).max() < 1e-4 * f[TOP]
    assert np.abs(state.particles.spin).max() * state.dt < 1e-12
