"""Direct tension of a small gripped prism: quasi-static, elastic-brittle (sigma_t in proportion
to the bond tensile strength), failing between the grips."""

import numpy as np
import pytest

from rockcal import make_params, random_packing
from rockcal.errors import InputError
from rockcal.labtests.direct_tension import simulate_direct_tension
from rockcal.labtests.registry import lab_test
from rockcal.labtests.rig.grips import grip_grains

SIGMA_C = 36.55  # the granite's bond tensile strength, MPa


@pytest.fixture(scope="module")
def prism():
    return random_packing(10, 20, 0.25, 1.65, seed=3)


@pytest.fixture(scope="module")
def pulled(prism):
    return simulate_direct_tension(make_params({}), prism)


def test_sigma_t_is_the_peak_force_over_the_width(pulled, prism):
    peak = int(np.argmax(pulled.curve[:, 1]))
    assert pulled.sigma_t_direct_MPa == pulled.curve[peak, 1] > 0
    assert pulled.P_max_kN_per_m == pytest.approx(pulled.sigma_t_direct_MPa * prism.width_m * 1e3)
    assert pulled.curve.shape[1] == 3
    assert pulled.curve[-1, 2] == pulled.n_broken_tension + pulled.n_broken_shear


def test_the_prism_breaks_in_tension_between_the_grips(pulled, prism):
    """Every bond breaks in tension, none inside a grip (its grains move as one body)."""
    bottom, top = grip_grains(prism, 0.1)
    y = pulled.cracks["tension"][:, 1]
    assert pulled.n_broken_tension > 0 and pulled.n_broken_shear == 0
    assert np.all(y > prism.pos[bottom, 1].max() - prism.radius.max())
    assert np.all(y < prism.pos[top, 1].min() + prism.radius.max())


def test_halving_the_pulling_rate_changes_sigma_t_little(pulled, prism):
    slow = simulate_direct_tension(make_params({}), prism, rate_factor=0.5)
    assert slow.sigma_t_direct_MPa == pytest.approx(pulled.sigma_t_direct_MPa, rel=0.02)


@pytest.mark.parametrize("factor", [0.5, 2.0])
def test_sigma_t_scales_with_the_bond_tensile_strength(pulled, prism, factor):
    """Elastic-brittle: before the first break the prism does not know the bond strengths (the
    same curve to the last bit); the contacts and bonds are linear and bonds break in tension
    only, so scaling sigma_c scales every force at every break: sigma_t in proportion."""
    scaled = simulate_direct_tension(make_params({"sigma_c": factor * SIGMA_C}), prism)
    first = min(np.argmax(pulled.curve[:, 2] > 0), np.argmax(scaled.curve[:, 2] > 0))
    np.testing.assert_array_equal(scaled.curve[:first], pulled.curve[:first])
    assert scaled.n_broken_shear == 0
    assert scaled.sigma_t_direct_MPa / pulled.sigma_t_direct_MPa == pytest.approx(factor, rel=0.03)


def test_the_lab_test_declares_its_grip_and_runs_from_its_settings(prism, pulled):
    test = lab_test("direct_tension")
    settings = {"grip_fraction": 0.1, "contact_stiffness": "pfc4"}
    result = test.run(make_params({}), prism, settings, None)
    np.testing.assert_array_equal(result.curve, pulled.curve)
    (grip,) = test.own_settings
    assert grip.name == "grip_fraction" and grip.default == 0.1 and not grip.series
    assert test.targets == ("sigma_t_direct_MPa",)
    for bad in (0.0, 0.5, -0.1):
        with pytest.raises(InputError) as error:
            grip.check(bad)
        assert error.value.field == "grip_fraction"
