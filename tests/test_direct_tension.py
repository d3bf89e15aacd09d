"""Direct tension of a small gripped prism: quasi-static, elastic-brittle (sigma_t in proportion
to the bond tensile strength), failing between the grips; of balls or of clumps, which the grips
hold whole and carry without turning."""

import warnings
from dataclasses import replace

import matplotlib.pyplot as plt
import numpy as np
import pytest

from rockcal import make_params, plots, random_packing
from rockcal.campaign.input.config import SpecimenSettings
from rockcal.campaign.runs.spec import RunSpec, run_spec
from rockcal.specimens.carving import grains
from rockcal.dem.simulate import advance, scale_density
from rockcal.errors import InputError
from rockcal.labtests.direct_tension import simulate_direct_tension
from rockcal.labtests.registry import lab_test
from rockcal.labtests.rig.grips import Grips, grip_grains

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


def test_the_curve_figure_marks_the_peak_at_sigma_t(pulled, tmp_path):
    """The figure's one labelled mark is the peak, at the result's sigma_t (and plotting it
    warns of nothing, as an empty legend would)."""
    shown = {}
    with warnings.catch_warnings(), pytest.MonkeyPatch.context() as patch:
        warnings.simplefilter("error")
        patch.setattr(plots, "_save", lambda fig, path: shown.update(ax=fig.axes[0]))
        plots.tension_curve(pulled.curve, tmp_path / "curve.png", "direct tension test")
    (peak,), (label,) = shown["ax"].get_legend_handles_labels()
    assert peak.get_ydata()[0] == pytest.approx(pulled.sigma_t_direct_MPa, rel=1e-12)
    assert label == f"direct tensile strength {pulled.sigma_t_direct_MPa:.2f} MPa"
    plt.close("all")


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


@pytest.fixture(scope="module")
def clumped():
    return random_packing(10, 20, 0.25, 1.65, seed=3, grain_shape="two-pebble")


@pytest.fixture(scope="module")
def clumped_pulled(clumped):
    return simulate_direct_tension(make_params({}), clumped)


def test_one_pebble_clumps_pull_as_balls_to_the_bit(prism, pulled):
    """Each ball made a clump of one pebble: gripped by its centre, driven on its body, the same
    curve and cracks as the balls' to the last bit."""
    one_pebble = replace(prism, clump_of=np.arange(prism.n_particles))
    result = simulate_direct_tension(make_params({}), one_pebble)
    np.testing.assert_array_equal(result.curve, pulled.curve)
    np.testing.assert_array_equal(result.cracks["tension"], pulled.cracks["tension"])


def test_a_clump_is_gripped_whole_by_its_centroid(clumped):
    centre = grains(clumped)[0]
    bottom, top = grip_grains(clumped, 0.1)
    grip = 0.1 * clumped.height_m
    assert set(bottom) == set(np.flatnonzero(centre[:, 1] < centre[:, 1].min() + grip))
    assert set(top) == set(np.flatnonzero(centre[:, 1] > centre[:, 1].max() - grip))
    grips = Grips(clumped, make_params({}), 0.1, 1.0)
    np.testing.assert_array_equal(grips.bottom_particles, np.flatnonzero(np.isin(clumped.clump_of, bottom)))
    np.testing.assert_array_equal(grips.top_particles, np.flatnonzero(np.isin(clumped.clump_of, top)))


def test_gripped_clumps_move_rigidly_with_their_grip(clumped):
    """Pulled for a while (the prism loaded, its free clumps turning), a gripped clump has not
    turned and has moved by its grip's travel along y alone, every pebble with it."""
    grips = Grips(clumped, make_params({}), 0.1, 1.0)
    state = grips.state
    scale_density(state)
    clumps, steps = state.clumps, 400
    centroid0, pebbles0 = clumps.pos.copy(), state.particles.pos.copy()
    grips.move(1.0)
    advance(state, steps)
    travel = grips.speed * state.dt * steps
    assert grips.load() > 0
    for grip, particles, sign in ((grips.bottom, grips.bottom_particles, -1),
                                  (grips.top, grips.top_particles, 1)):
        assert np.all(clumps.angle[grip] == 0) and np.all(clumps.spin[grip] == 0)
        moved = clumps.pos[grip] - centroid0[grip]
        np.testing.assert_array_equal(moved[:, 0], 0.0)
        np.testing.assert_allclose(moved[:, 1], sign * travel, rtol=1e-9)
        pebble_moved = state.particles.pos[particles] - pebbles0[particles]
        np.testing.assert_allclose(pebble_moved, moved[np.searchsorted(grip, clumps.clump_of[particles])],
                                   rtol=0, atol=1e-12 * clumped.height_m)
    free = np.setdiff1d(np.arange(clumps.n_clumps), np.concatenate([grips.bottom, grips.top]))
    assert np.any(clumps.angle[free] != 0)


def test_a_clumped_prism_breaks_in_tension_between_the_grips(clumped, clumped_pulled):
    bottom, top = grip_grains(clumped, 0.1)
    pebble_y = clumped.pos[:, 1]
    below = pebble_y[np.isin(clumped.clump_of, bottom)].max()
    above = pebble_y[np.isin(clumped.clump_of, top)].min()
    y = clumped_pulled.cracks["tension"][:, 1]
    assert clumped_pulled.sigma_t_direct_MPa > 0
    assert clumped_pulled.n_broken_tension > 0 and clumped_pulled.n_broken_shear == 0
    assert np.all(y > below - clumped.radius.max()) and np.all(y < above + clumped.radius.max())


def test_halving_the_pulling_rate_changes_a_clumped_prisms_sigma_t_little(clumped, clumped_pulled):
    slow = simulate_direct_tension(make_params({}), clumped, rate_factor=0.5)
    assert slow.sigma_t_direct_MPa == pytest.approx(clumped_pulled.sigma_t_direct_MPa, rel=0.02)


def test_a_ball_run_keeps_its_key_and_a_clumped_run_has_its_own():
    """grain_shape and dimensions are the test's last settings: at "ball" and 2 out of a run's
    key, which is the one of the settings before them (a clumped campaign's direct tension runs
    were on balls)."""
    before = ("width_mm", "height_mm", "rmin_mm", "radius_ratio", "seed", "install_gap", "cloud_porosity",
              "pressure_mpa", "grip_fraction", "contact_stiffness")
    test = lab_test("direct_tension")
    assert test.settings == (*before, "grain_shape", "dimensions")
    values = test.settings_of(SpecimenSettings())
    ball = run_spec("direct_tension", SpecimenSettings(), {})
    old = RunSpec("direct_tension", tuple((name, values[name]) for name in before), ball.params, ball.engine)
    assert ball.specimen == old.specimen and ball.key == old.key
    two_pebble = SpecimenSettings(grain_shape="two-pebble")
    clumped = run_spec("direct_tension", two_pebble, {})
    assert dict(clumped.specimen)["grain_shape"] == "two-pebble" and clumped.key != ball.key
    assert test.packing(two_pebble)["grain_shape"] == "two-pebble"
