"""The registry of lab tests: each kind declares its responses and specimen settings, a run of
any kind goes through the same forward path, and an unknown kind is a clear error."""

import math
from types import SimpleNamespace

import pytest

from rockcal.campaign.input.config import SpecimenSettings, UCSTargets
from rockcal.campaign.runs.pool import execute
from rockcal.campaign.runs.spec import ENGINE, SPECIMEN_KEYS, RunSpec, run_spec
from rockcal.errors import InputError
from rockcal.labtests.registry import LAB_TESTS, lab_test


# small specimens of every test, and a value of each test's series where it has one
SMALL = SpecimenSettings(rmin_mm=0.4, width_mm=8, height_mm=16, disk_diameter_mm=10, beam_length_mm=44,
                         beam_height_mm=10, notch_mm=3.6, notch_width_mm=0.8, span_mm=32, scb_radius_mm=10,
                         scb_notch_mm=5, scb_notch_width_mm=0.8)
PARAMS = {"E_c": 20.0, "kn_ks": 2.0, "sigma_c": 40.0, "tau_c": 60.0}


def test_every_test_is_registered_under_its_name():
    assert all(lab_test(name).name == name for name in LAB_TESTS)


@pytest.mark.parametrize("kind", list(LAB_TESTS))
def test_every_registered_test_runs_through_the_forward_path(kind):
    """A run of each kind on a small specimen gives every response it declares as a finite
    number, and its targets positive (a series' run at 5 of its unit)."""
    series = lab_test(kind).series
    result = execute(run_spec(kind, SMALL, PARAMS, own={series.name: 5.0} if series else None))
    assert result.status == "ok", result.message
    assert all(math.isfinite(result.responses[r.name]) for r in lab_test(kind).responses)
    assert all(result.responses[name] > 0 for name in lab_test(kind).targets)


def test_a_tests_strength_is_one_of_its_responses():
    """A crack figure is titled with the test's strength: the UCS test's is its UCS, not its
    first response (E)."""
    for test in LAB_TESTS.values():  # a misspelt strength would fall back to the first response
        assert not test.strength or test.strength_response.name == test.strength
    assert lab_test("ucs").strength_response.name == "ucs_MPa"


def test_an_unknown_test_is_an_error_naming_the_known_ones():
    with pytest.raises(InputError, match=f"no lab test named 'triaxial'; known: {', '.join(LAB_TESTS)}"):
        run_spec("triaxial", SpecimenSettings(), {})


@pytest.mark.parametrize("kind", list(LAB_TESTS))
def test_a_tests_revision_keys_only_its_own_runs(kind):
    """A changed procedure (a test's revision) makes new keys for its runs, not for the
    others': a run's engine names its test's revision past the first, and its key differs from
    the key of every earlier revision's run."""
    revision = lab_test(kind).revision
    spec = run_spec(kind, SpecimenSettings(), {})
    assert spec.engine == (ENGINE if revision == 1 else f"{ENGINE}, {kind} test revision {revision}")
    for earlier in (ENGINE, *(f"{ENGINE}, {kind} test revision {r}" for r in range(2, revision))):
        assert spec.key != RunSpec(spec.kind, spec.specimen, spec.params, earlier).key or revision == 1


@pytest.mark.parametrize("kind", ["ucs", "bending", "brazilian"])
def test_a_setting_added_later_keys_a_run_only_away_from_its_old_value(kind):
    """contact_stiffness came after runs were stored: at PFC 5's convention, the engine's before,
    a run keeps the key it had; PFC 4's (the default since) makes a new one, and the run gets
    it either way."""
    pfc5 = SpecimenSettings(contact_stiffness="pfc5")
    spec = run_spec(kind, pfc5, {})
    assert "contact_stiffness" not in dict(spec.specimen)
    assert lab_test(kind).settings_of(pfc5)["contact_stiffness"] == "pfc5"
    pfc4 = run_spec(kind, SpecimenSettings(), {})
    assert dict(pfc4.specimen)["contact_stiffness"] == "pfc4" and pfc4.key != spec.key


def test_the_ucs_targets_are_the_ucs_tests_measured_responses():
    assert set(lab_test("ucs").targets) <= set(UCSTargets.model_fields)


def test_run_keys_name_the_specimen_settings_in_their_order():
    """The order keys the store: it must not change."""
    assert [n for n, _ in run_spec("bending", SpecimenSettings(), {}).specimen] == [
        "beam_length_mm", "beam_height_mm", "notch_mm", "notch_width_mm", "span_mm", "rmin_mm",
        "radius_ratio", "seed", "install_gap", "cloud_porosity", "pressure_mpa", "stop_fraction",
        "contact_stiffness"]
    assert [n for n, _ in run_spec("ucs", SpecimenSettings(), {}).specimen] == [
        "width_mm", "height_mm", "rmin_mm", "radius_ratio", "seed", "install_gap", "cloud_porosity",
        "pressure_mpa", "strain", "stop_fraction", "contact_stiffness"]
    assert [n for n, _ in run_spec("brazilian", SpecimenSettings(), {}).specimen] == [
        "disk_diameter_mm", "rmin_mm", "radius_ratio", "seed", "install_gap", "cloud_porosity",
        "pressure_mpa", "contact_stiffness"]


def test_the_target_responses_of_the_tests_have_distinct_names():
    """A parameter set's responses over several tests make one dict."""
    names = [r for test in LAB_TESTS.values() for r in test.targets]
    assert len(names) == len(set(names))


def test_a_brazilian_run_goes_through_the_forward_path():
    settings = SimpleNamespace(disk_diameter_mm=10.0, rmin_mm=0.5, radius_ratio=1.65, seed=2,
                               **SpecimenSettings().model_dump(include={"install_gap", "cloud_porosity",
                                                                        "pressure_mpa", "contact_stiffness"}))
    result = execute(run_spec("brazilian", settings, {}))
    assert result.status == "ok", result.message
    assert list(result.responses)[:3] == ["sigma_t_MPa", "P_max_kN_per_m", "displacement_at_peak_mm"]
    assert set(SPECIMEN_KEYS) <= set(result.responses) and result.curve.shape[1] == 2


@pytest.mark.parametrize("name, settings, field", [
    ("ucs", {"width_mm": 1.0}, "width_mm"),
    ("bending", {"beam_length_mm": 2.0}, "beam_length_mm"),
    ("bending", {"notch_mm": 60.0}, "notch_mm"),
    ("brazilian", {"disk_diameter_mm": 2.0}, "disk_diameter_mm"),
])
def test_a_specimen_that_cannot_be_made_names_its_setting(name, settings, field):
    test = lab_test(name)
    values = test.settings_of(SpecimenSettings()) if name != "brazilian" else {
        "disk_diameter_mm": 50.0, "rmin_mm": 0.25, "radius_ratio": 1.65}
    with pytest.raises(InputError) as error:
        test.check(values | settings)
    assert error.value.field == field
