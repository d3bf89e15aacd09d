"""The UCS test on 3D specimens (`rockcal.labtests.ucs` on the 3D rig) against what must hold:

- a bonded simple-cubic prism between the platens is a bundle of independent columns: each
  bond (contact and parallel bond in parallel, k = π (E_c + Ē_c) R / 2) is squeezed by ε d,
  so σ = k ε / d² × d, E = π (E_c + Ē_c) / 4, and nothing pushes sideways, ν = 0;
- a bonded genesis specimen between touching platens is at rest and stays at rest (bonds take
  the overlaps as their reference: no locked-in force);
- a small cylinder shows a linear elastic stage, a peak and a fall past it, with cracks;
- the same specimen and seed give the same curve bit for bit;
- halving the loading speed moves E, ν and UCS by less than 2 %.
"""

import numpy as np
import pytest

from rockcal.labtests.rig.platens_3d import Platens3D
from rockcal.specimens3d.specimen import Specimen3D, random_specimen
from rockcal.labtests.ucs import simulate_ucs
from rockcal.labtests.ucs import POST_PEAK_FRACTION
from rockcal.materials.parallel_bond import make_params

GRANITE = make_params({"E_c": 62, "kn_ks": 2.5, "sigma_c": 175, "tau_c": 175,
                       "sigma_c_cv": 0.23, "tau_c_cv": 0.23, "mu": 0.5, "density": 2630})


@pytest.fixture
def cylinder(small_cylinder):
    """`conftest.small_cylinder`: 10 x 20 mm at R_min 0.6 mm, about 300 spheres."""
    return small_cylinder


def cubic_prism(side: int, r: float) -> Specimen3D:
    """side x side x 2 side equal spheres on a simple-cubic lattice, neighbours bonded."""
    index = np.array([(i, j, k) for k in range(2 * side) for j in range(side) for i in range(side)])
    flat = {tuple(v): n for n, v in enumerate(index)}
    bonds = [(flat[tuple(v)], flat[tuple(v + step)]) for v in index for step in np.eye(3, dtype=int)
             if tuple(v + step) in flat]
    d = 2 * r
    return Specimen3D(index * d + r, np.full(len(index), r), np.array(bonds), "cuboid",
                      (side * d, side * d, 2 * side * d), "simple cubic",
                      np.full((len(bonds), 2), 0.5))


def test_a_simple_cubic_prism_reads_the_columns_modulus_and_no_poisson_effect():
    params = make_params({"E_c": 10, "Ebar_c": 30, "kn_ks": 2.5, "sigma_c": 1e5, "tau_c": 1e5})
    result = simulate_ucs(params, cubic_prism(5, 1e-3), max_axial_strain=5e-3)
    assert result.n_broken_tension + result.n_broken_shear == 0
    assert result.E_GPa == pytest.approx(np.pi * (10 + 30) / 4, rel=2e-3)
    assert abs(result.nu) < 1e-5


def test_a_bonded_specimen_between_touching_platens_stays_at_rest(cylinder):
    platens = Platens3D(cylinder, GRANITE, 1.0)
    state = platens.state
    state.scale_density()
    state.advance(2000)
    # a sphere may touch a platen by a rounding error: forces of 1e-11 N against 1e4 N at the peak
    assert np.abs(state.spheres.vel).max() < 1e-9 * platens.speed
    assert np.abs(state.spheres.force).max() < 1e-9
    assert abs(platens.load()) < 1e-9


def test_a_small_cylinder_loads_linearly_peaks_and_fails(cylinder):
    result = simulate_ucs(GRANITE, cylinder)
    strain, _, stress, broken = result.curve.T
    peak = int(np.argmax(stress))
    assert 0 < peak < len(stress) - 1
    assert stress[-1] < POST_PEAK_FRACTION * stress[peak]
    assert 0 < result.nu < 0.5 and 0 < result.E_GPa < np.inf
    rising = (stress > 0.1 * stress[peak]) & (stress < 0.5 * stress[peak]) \
        & (np.arange(len(stress)) < peak)
    tangent = np.polyfit(strain[rising], stress[rising], 1)[0] / 1e3
    assert tangent == pytest.approx(result.E_GPa, rel=0.05)
    assert np.all(np.diff(broken) >= 0) and broken[peak] < broken[-1]
    assert result.n_broken_tension + result.n_broken_shear == broken[-1]


def test_the_same_specimen_gives_the_same_curve_bit_for_bit(cylinder):
    runs = [simulate_ucs(GRANITE, cylinder, max_axial_strain=2e-3) for _ in range(2)]
    assert np.array_equal(runs[0].curve, runs[1].curve)


@pytest.mark.slow
def test_halving_the_loading_speed_moves_E_nu_and_ucs_by_less_than_2_percent():
    """On a 12 x 24 mm cylinder at R_min 0.6 mm (about 575 spheres)."""
    cylinder = random_specimen("cylinder", 12.0, 24.0, 0.6, seed=1, cache=False)
    full, half = (simulate_ucs(GRANITE, cylinder, rate_factor=rate) for rate in (1.0, 0.5))
    for name in ("E_GPa", "nu", "ucs_MPa"):
        assert getattr(half, name) == pytest.approx(getattr(full, name), rel=0.02), name


def test_a_model_that_breaks_mid_run_ends_the_test_as_a_failed_run(cylinder, monkeypatch):
    """Spheres scattered beyond any packing at a neighbour-list rebuild (`dem3d.neighbours
    .check_grid`) end the test as RunFailed, which the command line prints in one line."""
    from rockcal.dem3d import neighbours
    from rockcal.labtests.result import RunFailed

    checks = []
    real = neighbours.check_grid

    def scattered_after_setup(pos, radius, skin):
        checks.append(1)
        if len(checks) > 1:  # the state's first list is built before the loading starts
            raise neighbours.SpheresScattered("the spheres are scattered over 1e9 cells of the neighbour grid")
        real(pos, radius, skin)

    monkeypatch.setattr(neighbours, "check_grid", scattered_after_setup)
    with pytest.raises(RunFailed, match="the model broke while the test ran"):
        simulate_ucs(GRANITE, cylinder)
