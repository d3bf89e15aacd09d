"""The registry of lab tests: each kind declares its responses and specimen settings, a run of
any kind goes through the same forward path, and an unknown kind is a clear error."""

from types import SimpleNamespace

import pytest

from rockcal.campaign.config import RESPONSES, SpecimenSettings, UCSTargets
from rockcal.campaign.forward import ENGINE, SPECIMEN_KEYS, execute, run_spec
from rockcal.campaign.store import RunSpec
from rockcal.errors import InputError
from rockcal.labtests.registry import LAB_TESTS, lab_test


def test_every_test_is_registered_under_its_name():
    assert list(LAB_TESTS) == ["ucs", "bending", "brazilian", "biaxial", "direct_tension"]
    assert all(lab_test(name).name == name for name in LAB_TESTS)


def test_an_unknown_test_is_an_error_naming_the_known_ones():
    with pytest.raises(InputError, match="no lab test named 'triaxial'; known: ucs, bending, brazilian, biaxial, direct_tension"):
        run_spec("triaxial", SpecimenSettings(), {})


def test_a_tests_revision_keys_only_its_own_runs():
    """A changed procedure (UCS revision 4, bending revision 8) makes new keys for its runs, not
    for the others'."""
    settings = SpecimenSettings()
    assert run_spec("brazilian", settings, {}).engine == ENGINE
    for kind, revision in (("ucs", 4), ("bending", 8)):
        spec = run_spec(kind, settings, {})
        assert lab_test(kind).revision == revision
        assert spec.engine == f"{ENGINE}, {kind} test revision {revision}"
        for earlier in (ENGINE, *(f"{ENGINE}, {kind} test revision {r}" for r in range(2, revision))):
            assert spec.key != RunSpec(spec.kind, spec.specimen, spec.params, earlier).key


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
    assert RESPONSES == ("E_GPa", "nu", "ucs_MPa", "ci_MPa", "ci_ratio", "cd_MPa", "cd_ratio")
    assert set(RESPONSES) <= set(UCSTargets.model_fields)


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
