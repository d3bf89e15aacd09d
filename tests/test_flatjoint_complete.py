"""The complete flat joint: PFC 7+'s residual strength (`fj_cohres`, `fj_resmode`) against
closed forms on two grains, the searched parameters' whole numbers (fj_nr) rounded the one way
everywhere, and bad input refused in one line naming the key, exit 2, before any run."""

import sys

import numpy as np
import pytest

from rockcal import hexagonal
from rockcal.campaign.input.config import parse_campaign, whole_numbers
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.procedure.rounding import rounded
from rockcal.campaign.procedure.steps import planning_state, sample_points, search_space
from rockcal.cli.app import main
from rockcal.dem import flatjoint as fj
from rockcal.dem.simulate import advance
from rockcal.errors import InputError
from rockcal.materials import FLATJOINT, new_state, parameters
from rockcal.materials.flat_joint import NAMES, flatjointed, make_flatjoint_params

MPA = 1e6
KN = 20e9 / 2.3e-3  # Pa/m: E* 20 GPa over R_i + R_j = 2.3 mm
KRATIO = 1.6
RBAR = 0.8e-3  # m: the interface's half-length
COH, TEN, FRIC = 20.0, 100.0, 0.5  # MPa, MPa, 1


def joint(nr=2, cohres=0.0, fa=0.0):
    """One bonded flat joint (strengths in MPa, c_r in MPa, angle in degrees)."""
    return fj.new_flatjoints(nr, kn=KN, ks=KN / KRATIO, rmul=1.0, fric=FRIC, tan_fa=np.tan(np.radians(fa)),
                             gap0=0.0, bonded=True, ten=TEN * MPA, coh=COH * MPA, cohres=cohres * MPA)


def law(j, dn=0.0, ds=0.0, dtheta=0.0):
    return fj.update_joint(0, RBAR, dn, ds, dtheta, j.table, j.state, j.elements)


def sheared_past_its_strength(j, sigma_mpa, fa=0.0):
    """Pressed to the normal stress σ (tension positive), then sheared 1 % past c - σ tan φ."""
    area = 2 * RBAR
    law(j, dn=sigma_mpa * MPA / KN)
    strength = (COH - sigma_mpa * np.tan(np.radians(fa))) * MPA * area
    law(j, ds=1.01 * strength / (KN / KRATIO * area))


# --- the residual law ----------------------------------------------------------------------

@pytest.mark.parametrize("nr", [1, 3])
@pytest.mark.parametrize("sigma_mpa, fa", [(-10.0, 0.0), (-10.0, 30.0), (0.0, 0.0)])
def test_a_pair_sheared_past_its_strength_keeps_the_residual_cohesions_resistance(nr, sigma_mpa, fa):
    """A bonded pair under σ <= 0, sheared past c - σ tan φ, breaks in shear; with fj_resmode 1
    its shear force drops to the closed form μ |F_n| + c_r 2R̄ t (every element closed), where
    without residual cohesion it drops to μ |F_n|."""
    cohres = 5.0
    area = 2 * RBAR
    for c_r, expected in ((cohres, FRIC * abs(sigma_mpa) * MPA * area + cohres * MPA * area),
                          (0.0, FRIC * abs(sigma_mpa) * MPA * area)):
        j = joint(nr, c_r, fa)
        sheared_past_its_strength(j, sigma_mpa, fa)
        assert np.all(j.state[0] == fj.BROKEN_SHEAR)
        assert j.table[fj.FS, 0] == pytest.approx(expected, rel=1e-12)
        assert j.table[fj.FN, 0] == pytest.approx(sigma_mpa * MPA * area, rel=1e-12, abs=1e-9)


def test_the_residual_acts_where_the_sheared_surface_touches():
    """The pair, broken in shear and slipping, then pulled apart carries nothing; closed again it
    slips at the residual once more; bent half open, its residual is c_r over the closed half."""
    cohres = 5.0
    j = joint(2, cohres)
    sheared_past_its_strength(j, 0.0)
    law(j, dn=1e-7)  # open: no contact, no residual
    assert j.table[fj.FN, 0] == j.table[fj.FS, 0] == 0.0
    law(j, dn=-1e-7)  # back to touching: the shear builds up to the residual again
    ks_area = KN / KRATIO * 2 * RBAR
    law(j, ds=2 * cohres * MPA * 2 * RBAR / ks_area)
    assert j.table[fj.FS, 0] == pytest.approx(cohres * MPA * 2 * RBAR, rel=1e-12)
    law(j, dtheta=1e-5)  # g = -θ ξ: the side ξ > 0 closes, ξ < 0 opens and lets go
    assert j.table[fj.FS, 0] == pytest.approx(cohres * MPA * RBAR, rel=1e-12)
    law(j, ds=1e-5)  # slipping again: μ |F_n| + c_r R̄ t, the closed half's
    fn_closed = KN * 1e-5 * RBAR**2 / 2  # the compression k_n θ ξ integrated over 0 < ξ < R̄
    assert j.table[fj.FS, 0] == pytest.approx(FRIC * fn_closed + cohres * MPA * RBAR, rel=1e-12)


@pytest.mark.parametrize("gc, theta", [(-1e-8, 0.0), (1e-8, 0.0), (0.0, 2e-5), (3e-9, -2e-5), (-4e-9, 1e-5),
                                       (9e-9, 1e-5), (-9e-9, 1e-5)])
def test_the_closed_length_of_an_element(gc, theta):
    """The length where g(ξ) = g_c - θ (ξ - ξ_e) <= 0 over an element, against counting."""
    xc, length = 0.3e-3, 0.4e-3
    u = np.linspace(-length / 2, length / 2, 400_001)
    counted = np.mean(gc - theta * u <= 0.0) * length
    assert fj.closed_length(gc + theta * xc, theta, xc, length) == pytest.approx(counted, abs=length * 1e-5)


def test_a_tension_break_keeps_no_residual():
    """The residual cohesion is the sheared surface's: an element broken in tension, closed
    again, has friction only."""
    j = joint(2, cohres=5.0)
    law(j, dn=1.01 * TEN * MPA / KN)
    assert np.all(j.state[0] == fj.BROKEN_TENSION)
    law(j, dn=-1.01 * TEN * MPA / KN - 1e-8)
    law(j, ds=1e-6)
    assert j.table[fj.FS, 0] == pytest.approx(FRIC * abs(j.table[fj.FN, 0]), rel=1e-12)


def test_the_residual_changes_nothing_until_an_element_breaks_in_shear():
    """Joints with and without residual cohesion, under one random loading that opens, closes,
    bends and breaks elements in tension but never in shear, carry the same numbers to the last
    bit."""
    rng = np.random.default_rng(7)
    steps = rng.normal([5e-7, 0.0, 0.0], [3e-6, 1e-6, 2e-3], (400, 3))
    with_residual, without = joint(3, cohres=5.0), joint(3, cohres=0.0)
    for j in (with_residual, without):
        j.elements[fj.E_COH] = 1e4 * MPA  # no shear break
        for dn, ds, dtheta in steps:
            law(j, dn, ds, dtheta)
    assert np.all(without.state == fj.BROKEN_TENSION)
    assert np.array_equal(with_residual.elements, without.elements)
    assert np.array_equal(np.delete(with_residual.table, fj.COHRES, axis=0), np.delete(without.table, fj.COHRES, axis=0))


# --- the material ----------------------------------------------------------------------------

def test_residual_strength_is_off_by_default_and_keeps_the_store_keys():
    """At their defaults fj_cohres and fj_resmode (and the 3D joint's fj_nal) are left out of a
    parameter set's key, so the runs stored before them keep their keys; set, they are in it
    and reach the joints (Pa)."""
    default = make_flatjoint_params({})
    assert set(default.key()) == set(NAMES) - {"fj_cohres", "fj_resmode", "fj_nal"}
    assert make_flatjoint_params({"fj_nal": 5}).key()["fj_nal"] == 5
    on = make_flatjoint_params({"fj_resmode": 1.0, "fj_cohres": 4.0})
    assert on.key()["fj_resmode"] == 1 and on.key()["fj_cohres"] == 4.0
    pos = np.array([[0.0, 0.0], [2e-3, 0.0]])
    radius = np.array([1e-3, 1e-3])
    pairs = np.array([[0, 1]])
    assert flatjointed(pos, radius, pairs, default).joints().table[fj.COHRES, 0] == 0.0
    assert flatjointed(pos, radius, pairs, on).joints().table[fj.COHRES, 0] == 4.0 * MPA


@pytest.mark.parametrize("values, field", [
    ({"fj_fa": 90.0}, "fj_fa"),
    ({"fj_fa": -1.0}, "fj_fa"),
    ({"fj_cohres": 5.0}, "fj_cohres"),  # mode 0 keeps no residual: a value there would be ignored
    ({"fj_resmode": 2.0}, "fj_resmode"),
    ({"fj_cohres": -1.0, "fj_resmode": 1.0}, "fj_cohres"),
    ({"fjm_B_frac": 0.7, "fjm_G_frac": 0.2}, "fjm_G_frac"),  # gapped joints with no gap
])
def test_bad_material_values_name_their_field(values, field):
    with pytest.raises(InputError) as err:
        parameters(FLATJOINT, values)
    assert err.value.field == field


def test_gapped_joints_need_a_gap_distribution():
    assert parameters(FLATJOINT, {"fjm_B_frac": 0.7, "fjm_G_frac": 0.2, "fjm_G_m": 0.001}).fjm_G_frac == 0.2
    assert parameters(FLATJOINT, {"fjm_B_frac": 0.7, "fjm_G_frac": 0.2, "fjm_G_sd": 0.001}).fjm_G_sd == 0.001


# --- the campaign: searching them -------------------------------------------------------------

CAMPAIGN = """
[material]
model = "flatjoint"
[targets.ucs]
E_GPa = 20.0
ucs_MPa = 60.0
[specimen]
rmin_mm = 0.4
width_mm = 8
height_mm = 16
[search]
bounds = {{ {bounds} }}
fixed = {{ {fixed} }}
[surrogate]
samples = 14
checks = 2
[acceptance]
max_dem_runs = 20
"""


def campaign(bounds: str, fixed: str = "", extra: str = ""):
    return planned(parse_campaign(CAMPAIGN.format(bounds=bounds, fixed=fixed) + extra, None))


def test_the_complete_flat_joint_can_be_searched():
    c = campaign("fj_fa = [0, 40], fjm_B_frac = [0.5, 0.7], fjm_G_frac = [0.1, 0.3], fjm_G_m = [0.001, 0.01], "
                 "fjm_G_sd = [0, 0.001], fj_nr = [1, 4], fj_cohres = [0, 10]", "fj_resmode = 1")
    assert set(c.search.bounds) == {"fj_fa", "fjm_B_frac", "fjm_G_frac", "fjm_G_m", "fjm_G_sd", "fj_nr", "fj_cohres"}
    assert whole_numbers("flatjoint") == {"fj_nr", "fj_nal"}  # fjm_rmulCode and fj_resmode pick rules


def test_fixed_values_are_checked_with_the_searched_ones_not_their_defaults():
    """A gapped fraction fixed with its gap searched, or varied by the sensitivity levels: valid,
    though the gap's default 0 would not be."""
    assert campaign("fjm_G_m = [0.001, 0.01]", "fjm_B_frac = 0.7, fjm_G_frac = 0.2").search.fixed["fjm_G_frac"] == 0.2
    levels = "[sensitivity]\narray = 'L4(2^3)'\nlevels = { fjm_G_m = [0.001, 0.01], install_gap = [0.5, 0.8] }\n"
    assert campaign("fj_emod = [10, 30]", "fjm_B_frac = 0.7, fjm_G_frac = 0.2", levels).sensitivity is not None


def test_a_whole_number_is_rounded_one_way_wherever_a_point_is_run():
    """Samples, checks and the planning stand-in: fj_nr a whole number inside its bounds, the
    others to 4 significant digits as before; the same value gives the same point."""
    c = campaign("fj_emod = [10, 30], fj_nr = [1, 4]")
    state = planning_state(c)
    assert list(state.whole) == [False, True]
    x, checks = sample_points(state.box, c.surrogate, state.whole)
    for row in [*x, *checks, list(state.identified().values())]:
        assert float(row[1]).is_integer() and 1 <= row[1] <= 4
        assert row[0] == float(f"{row[0]:.4g}")
    assert set(x[:, 1]) == {1.0, 2.0, 3.0, 4.0}
    assert list(rounded(np.array([2.5, 2.5]), np.array([False, True]))) == [2.5, 3.0]  # halves up
    assert list(rounded(np.array([2.71828, 1.23456]))) == [2.718, 1.235]  # as before: 4 digits


def test_a_dry_run_plans_whole_numbers_of_elements(tmp_path, monkeypatch, capsys):
    """The first screen of a campaign searching fj_nr: planned from the same rounded points,
    exit 0, nothing run or made."""
    config = tmp_path / "campaign.toml"
    config.write_text(CAMPAIGN.format(bounds="fj_emod = [10, 30], fj_nr = [1, 4]", fixed="fj_fa = 20"))
    monkeypatch.setattr(sys, "argv", ["rockcal", "calibrate", str(config), "--out", str(tmp_path / "out"),
                                      "--dry-run"])
    with pytest.raises(SystemExit) as exit:
        main()
    assert exit.value.code == 0, capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_a_middle_level_of_a_whole_number_is_whole():
    text = CAMPAIGN.format(bounds="", fixed="").replace("[search]\nbounds = {  }\nfixed = {  }\n", "") + \
        "[sensitivity]\narray = 'L4(2^3)'\nlevels = { fj_emod = [10, 30], fj_nr = [2, 3] }\n"
    bounds, fixed = search_space(planned(parse_campaign(text, None)), ["fj_emod"])
    assert bounds == {"fj_emod": (10.0, 30.0)} and fixed["fj_nr"] == 3.0


def test_fractions_are_checked_on_the_pairs_corners_of_a_large_box():
    """A box of more than 10 parameters is checked on each pair's corners, the others at their
    lower bounds: B in [0.5, 0.7] with G in [0.1, 0.3] is valid however many others are searched,
    and G up to 0.35 is not."""
    many = ("fj_emod = [20, 40], fj_kratio = [1, 3], fj_ten = [10, 30], fj_coh = [20, 60], fj_fa = [0, 40], "
            "fj_fric = [0.3, 0.7], fj_rmul = [0.8, 1], fjm_G_m = [0.001, 0.01], fjm_G_sd = [0, 0.001], "
            "fj_nr = [1, 4], fjm_B_frac = [0.5, 0.7], fjm_G_frac = [0.1, {g}]")
    assert len(campaign(many.format(g=0.3)).search.bounds) == 12
    with pytest.raises(InputError) as err:
        campaign(many.format(g=0.35))
    assert err.value.field == "search.bounds.fjm_G_frac" and "fjm_B_frac 0.7, fjm_G_frac 0.35" in err.value.problem


# --- bad input: one line naming the key, exit 2, nothing made ----------------------------------

BAD = [
    ("fj_fa 90", "fj_fa = [0, 90]", "", "search.bounds.fj_fa: Input should be less than 90"),
    ("fj_fa negative", "fj_fa = [-5, 30]", "", "search.bounds.fj_fa: Input should be greater than or equal to 0"),
    ("fixed fj_fa 95", "fj_emod = [10, 30]", "fj_fa = 95", "search.fixed.fj_fa: Input should be less than 90"),
    ("fj_nr not whole", "fj_nr = [1.5, 4]", "", "search.bounds.fj_nr: a whole number"),
    ("fj_nr upper not whole", "fj_nr = [1, 3.2]", "", "search.bounds.fj_nr: a whole number"),
    ("a mode searched", "fj_resmode = [0, 1]", "", "search.bounds.fj_resmode: a whole number that picks a rule"),
    ("gapped with no gap", "fjm_G_frac = [0, 0.3]", "fjm_B_frac = 0.7",
     "search.bounds.fjm_G_frac: fjm_G_frac = 0.3 asks for gapped joints but their initial gap is 0"),
    ("gap searched down to 0", "fjm_G_m = [0, 0.01]", "fjm_B_frac = 0.7, fjm_G_frac = 0.2",
     "search.bounds: fjm_G_frac = 0.2 asks for gapped joints"),
    ("B + G past 1 at a corner", "fjm_B_frac = [0.5, 0.8], fjm_G_frac = [0.1, 0.3]", "fjm_G_m = 0.002",
     "search.bounds.fjm_G_frac: fjm_B_frac + fjm_G_frac = 1.1 exceeds 1"),
    ("G with the default B = 1", "fjm_G_frac = [0.1, 0.3]", "fjm_G_m = 0.002",
     "search.bounds.fjm_G_frac: fjm_B_frac + fjm_G_frac = 1.1 exceeds 1"),
    ("residual without its mode", "fj_cohres = [0, 10]", "", "search.bounds.fj_cohres: 10 MPa acts only with "
     "fj_resmode = 1"),
]


@pytest.mark.parametrize("bounds, fixed, message", [c[1:] for c in BAD], ids=[c[0] for c in BAD])
def test_bad_flat_joint_input_is_one_line_and_exit_2(bounds, fixed, message, tmp_path, monkeypatch, capsys):
    config = tmp_path / "campaign.toml"
    config.write_text(CAMPAIGN.format(bounds=bounds, fixed=fixed))
    monkeypatch.setattr(sys, "argv", ["rockcal", "calibrate", str(config), "--out", str(tmp_path / "out"),
                                      "--workers", "1"])
    with pytest.raises(SystemExit) as exit:
        main()
    lines = capsys.readouterr().err.splitlines()
    assert exit.value.code == 2 and len(lines) == 1, lines
    assert lines[0].startswith("rockcal: error: " + message), lines[0]
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("cohres", [0.0, 1.0])
def test_in_the_engine_a_sheared_element_holds_friction_and_the_residual(cohres):
    """A stirred lattice (fj_coh 2 MPa) breaks its elements in shear in the engine's compiled
    step; then every one holds at most μ |F_n| + c_r L t (L its length), and with c_r > 0 some
    hold more than friction alone: the residual acts there too."""
    spec = hexagonal(5, 5, 0.25)
    assert np.ptp(spec.radius) == 0
    params = make_flatjoint_params({"fj_emod": 30, "fj_kratio": 2.5, "fj_nr": 2, "fj_ten": 1e4, "fj_coh": 2.0,
                                    "fj_resmode": 1, "fj_cohres": cohres})
    state = new_state(params, spec)
    rng = np.random.default_rng(3)
    state.particles.vel[:] = rng.normal(0, 2.0, state.particles.vel.shape)
    state.particles.spin[:] = rng.normal(0, 5000.0, len(spec.radius))
    state.damping = 0.0
    advance(state, 200)
    joints = state.bonds
    sheared = joints.state == fj.BROKEN_SHEAR
    assert sheared.mean() > 0.5
    friction = params.fj_fric * np.maximum(-joints.elements[fj.E_FN][sheared], 0.0)
    shear = np.abs(joints.elements[fj.E_FS][sheared])
    length = 2 * params.fj_rmul * spec.radius[0] / params.fj_nr
    assert np.all(shear <= (friction + cohres * MPA * length) * (1 + 1e-9))
    beyond = np.count_nonzero(shear > friction * (1 + 1e-9) + 1e-9)
    assert (beyond > 0) == (cohres > 0)
