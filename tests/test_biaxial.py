"""Confined (biaxial) compression on a small specimen: the servo holds sigma3 through the
loading, zero confinement is the UCS test, confinement strengthens the rock."""

import numpy as np
import pytest

from rockcal import make_params, random_packing, simulate_ucs
from rockcal.errors import InputError
from rockcal.labtests import biaxial
from rockcal.labtests.biaxial import simulate_biaxial
from rockcal.labtests.registry import lab_test
from rockcal.labtests.rig import Platens
from rockcal.labtests.rig.sides import SEATING_TOLERANCE
from rockcal.labtests.ucs import DENSITY_SCALED_SPEED

SIGMA3 = 10.0


@pytest.fixture(scope="module")
def specimen():
    return random_packing(10, 20, 0.25, 1.65, seed=3)


@pytest.fixture(scope="module")
def confined(specimen):
    return simulate_biaxial(make_params({}), specimen, SIGMA3)


def test_seating_brings_the_specimen_to_sigma3(confined):
    """The seating ends with the side walls at sigma3 (within its tolerance) and the axial
    loading starts from there: q and the strains at zero."""
    assert confined.seating_steps > 0
    assert confined.curve[0, 4] == pytest.approx(SIGMA3, rel=SEATING_TOLERANCE)
    assert np.all(confined.curve[0, :4] == 0)


def test_the_servo_holds_sigma3_through_the_loading(confined, specimen):
    """Up to the peak: the side walls' mean stress over the loading within 0.1 % of sigma3,
    its mean over each ramp of the loading (the time the specimen takes to settle after a
    change of speed) within 1 %, and 95 % of the readings within 1 %."""
    curve = confined.curve
    peak = int(np.argmax(curve[:, 2]))
    error = curve[1:peak + 1, 4] / SIGMA3 - 1
    platens = Platens(specimen, make_params({}), DENSITY_SCALED_SPEED)
    ramp = int(round(10 * platens.rows / DENSITY_SCALED_SPEED / platens.chunk))  # readings
    per_ramp = np.convolve(error, np.ones(ramp) / ramp, mode="valid")
    assert abs(error.mean()) < 1e-3
    assert np.abs(per_ramp).max() < 0.01
    assert np.quantile(np.abs(error), 0.95) < 0.01
    assert confined.sigma3_MPa == pytest.approx(SIGMA3, rel=1e-3)


def test_zero_confinement_is_the_ucs_test_to_the_last_bit(specimen):
    params = make_params({})
    unconfined = simulate_biaxial(params, specimen, 0.0)
    uniaxial = simulate_ucs(params, specimen)
    np.testing.assert_array_equal(unconfined.curve[:, :4], uniaxial.curve)
    assert np.all(unconfined.curve[:, 4] == 0) and unconfined.seating_steps == 0
    assert unconfined.sigma1_MPa == uniaxial.ucs_MPa
    assert (unconfined.E_GPa, unconfined.nu, unconfined.steps) == (
        uniaxial.E_GPa, uniaxial.nu, uniaxial.steps)
    assert unconfined.ci_MPa == uniaxial.ci_MPa and unconfined.cd_MPa == uniaxial.cd_MPa


def test_confinement_raises_the_peak_and_the_envelope_fits_it(specimen, confined):
    """sigma1 at 0 < 10 < 20 MPa; the deviator's peak too; the envelope through the three has
    a positive friction angle and Hoek-Brown's m_i."""
    params = make_params({})
    peaks = [simulate_biaxial(params, specimen, 0.0), confined,
             simulate_biaxial(params, specimen, 20.0)]
    sigma1 = [r.sigma1_MPa for r in peaks]
    assert sigma1[0] < sigma1[1] < sigma1[2]
    assert peaks[0].q_MPa < peaks[1].q_MPa
    for r in peaks:
        assert r.sigma1_MPa == pytest.approx(r.q_MPa + r.curve[np.argmax(r.curve[:, 2]), 4])
        assert 0 < r.ci_ratio <= 1 and 0 < r.cd_ratio <= 1
    fitted = biaxial.envelope([{"confinement_MPa": r.confinement_MPa, "sigma1_MPa": r.sigma1_MPa}
                               for r in peaks])
    assert fitted["sigma1_MPa"] == sigma1 and fitted["confinement_MPa"] == [0.0, 10.0, 20.0]
    assert 20 < fitted["phi_deg"] < 75 and fitted["c_MPa"] > 0 and fitted["m_i"] > 0


def test_the_lab_test_runs_from_its_settings(specimen, confined):
    """As a campaign runs it: the registry's test, its settings as a dict."""
    test = lab_test("biaxial")
    settings = {"confinement_mpa": SIGMA3, "strain": "gauge", "stop_fraction": 0.7,
                "contact_stiffness": "pfc4"}
    result = test.run(make_params({}), specimen, settings, None)
    np.testing.assert_array_equal(result.curve, confined.curve)
    assert list(test.responses_of(result))[:2] == ["sigma1_MPa", "confinement_MPa"]
    assert test.curve_columns[4] == "confinement_MPa" and result.curve.shape[1] == 5


@pytest.mark.parametrize("values", [[], [-5.0], [0.0, 10.0, 5.0], [5.0, 5.0], [float("nan")]])
def test_a_bad_confinement_list_names_the_setting(values):
    (setting,) = lab_test("biaxial").own_settings
    assert setting.name == "confinement_mpa" and setting.series and setting.default == 0.0
    with pytest.raises(InputError) as error:
        setting.check_series(values)
    assert error.value.field == "confinement_mpa"


def test_a_negative_confinement_is_rejected_before_any_run():
    with pytest.raises(InputError, match="confinement_mpa"):
        simulate_biaxial(make_params({}), None, -1.0)


def test_halving_the_loading_rate_moves_the_confined_peak_little(specimen, confined):
    """At sigma3 = 10 MPa: -0.1 % on this packing (seeds 1 and 2: -1.1 %, +1.5 %)."""
    slow = simulate_biaxial(make_params({}), specimen, SIGMA3, rate_factor=0.5)
    for key in ("sigma1_MPa", "E_GPa", "nu"):
        assert getattr(slow, key) == pytest.approx(getattr(confined, key), rel=0.02), key


def test_a_series_on_the_command_line_writes_the_envelope_and_the_curves(tmp_path):
    """`rockcal simulate biaxial` over two confinements: each run's peak, the envelope through
    them, its figure and the curves together; over one confinement, no envelope."""
    import json

    from typer.testing import CliRunner

    from rockcal.cli.app import _register, app

    _register()
    small = ["simulate", "biaxial", "--width-mm", "10", "--height-mm", "20", "--rmin-mm", "0.4", "--seed", "2"]
    run = CliRunner().invoke(app, [*small, "--confinement-mpa", "0,5", "--json", "--out", str(tmp_path)])
    assert run.exit_code == 0, run.output
    found = json.loads(run.output.splitlines()[-1])
    assert found["confinement_MPa"] == [0.0, 5.0] and found["sigma1_MPa"][1] > found["sigma1_MPa"][0]
    assert found["phi_deg"] > 0 and found["c_MPa"] > 0
    for name in ("biaxial_strength_envelope.png", "biaxial_confined_compression_curves.png",
                 "biaxial_confinement_mpa_5_curve.png"):
        assert (tmp_path / name).stat().st_size > 10_000, name
    one = CliRunner().invoke(app, [*small, "--confinement-mpa", "5", "--out", str(tmp_path / "one")])
    assert one.exit_code == 0, one.output
    assert not (tmp_path / "one" / "biaxial_strength_envelope.png").exists()
    assert (tmp_path / "one" / "biaxial_confined_compression_curves.png").exists()


def test_a_clumped_specimen_seats_and_confinement_raises_its_peak():
    """Seating reads equilibrium on the bodies (a clump's pebbles bear forces its rigid body
    balances): a specimen of two-pebble clumps settles at sigma3 and peaks above its UCS."""
    clumped = random_packing(8, 16, 0.4, 1.65, seed=1, grain_shape="two-pebble")
    params = make_params({})
    confined = simulate_biaxial(params, clumped, 5.0)
    assert confined.curve[0, 4] == pytest.approx(5.0, rel=SEATING_TOLERANCE)
    assert confined.sigma1_MPa > simulate_ucs(params, clumped).ucs_MPa


def test_a_series_of_ten_thousand_confinements_is_refused_before_any_run(tmp_path, monkeypatch, capsys):
    import sys

    from rockcal.cli.app import main

    series = ",".join(str(1 + k) for k in range(10_000))
    monkeypatch.setattr(sys, "argv", ["rockcal", "simulate", "biaxial", "--confinement-mpa", series,
                                      "--out", str(tmp_path / "out")])
    with pytest.raises(SystemExit) as exit:
        main()
    lines = capsys.readouterr().err.splitlines()
    assert exit.value.code == 2 and len(lines) == 1
    assert lines[0].startswith("rockcal: error: --confinement-mpa: at most 20 confinements")
    assert not (tmp_path / "out").exists()
