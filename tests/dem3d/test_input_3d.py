"""`[specimen] dimensions` and `rockcal simulate ucs --dimensions`: a value other than 2 or 3, a
3D campaign with a setting the 3D engine does not have, a flat-jointed material's bad fj_nal,
and a cylinder or a Brazilian disk too small for its spheres are refused before any run, in
one line naming the key, exit 2. The
settings whose default differs in 3D take the 3D default unless given.

Every case fails while the input is checked (no genesis, no run): the file is quick."""

import pytest

from rockcal.campaign.plan.cost import specimen_size
from rockcal.labtests.specimen_settings import DEFAULTS_3D, SpecimenSettings
from rockcal.specimens.grain_limit import DEFAULT_MAX_GRAINS, ENV
from rockcal.specimens3d.genesis import DEFAULT_GENESIS_3D
from rockcal.specimens3d.specimen import MIN_SPHERES, expected_spheres
from rockcal.errors import InputError
from rockcal.labtests.registry import LAB_TESTS
from rockcal.labtests.settings import specimen_settings
from rockcal.labtests.ucs import TEST as UCS

CAMPAIGN = """
[targets.ucs]
E_GPa = 30.0
nu = 0.16
ucs_MPa = 110.0
{targets}
[specimen]
{specimen}
[search]
bounds = {{ E_c = [15, 25], sigma_c = [30, 50] }}
"""
SPECIMEN = {"dimensions": "3", "width_mm": "7", "height_mm": "14", "rmin_mm": "0.5"}


def campaign(targets: str = "", **specimen: str) -> str:
    """The tiny 3D campaign with more `targets` and its [specimen] keys set (TOML values)."""
    keys = SPECIMEN | specimen
    return CAMPAIGN.format(targets=targets, specimen="\n".join(f"{k} = {v}" for k, v in keys.items()))


BRAZILIAN = "[targets.brazilian]\nsigma_t_MPa = 10.0"
TINY = ["--width-mm", "7", "--height-mm", "14", "--rmin-mm", "0.5"]


def one_line(run, key: str, *words: str) -> None:
    """Exit 2 and one line on stderr naming `key` (and holding each of `words`)."""
    assert run.returncode == 2, run.stderr
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"rockcal: error: {key}: "), run.stderr
    for word in words:
        assert word in lines[0], lines[0]


def calibrate(cli, tmp_path, text: str):
    """`rockcal calibrate --dry-run` of the campaign `text`; nothing is written when it refuses."""
    path = tmp_path / "rock.toml"
    path.write_text(text)
    run = cli("calibrate", path, "--dry-run", "--out", tmp_path / "out", cwd=tmp_path)
    assert not (tmp_path / "out").exists()
    return run


def test_the_tiny_3d_campaign_is_accepted(cli, tmp_path):
    run = calibrate(cli, tmp_path, campaign())
    assert run.returncode == 0, run.stderr


@pytest.mark.parametrize("value", ["4", "1", "0", "-3", "2.5", '"3D"'])
def test_dimensions_other_than_2_or_3_are_refused(cli, tmp_path, value):
    one_line(calibrate(cli, tmp_path, campaign(dimensions=value)), "specimen.dimensions")
    one_line(cli("simulate", "ucs", *TINY, "--dimensions", value.strip('"')), "--dimensions")


@pytest.mark.parametrize("name", list(LAB_TESTS))
def test_a_test_runs_in_3d_where_it_says_so(name):
    """A test accepts 3D exactly where it has the setting `dimensions`, and there its specimen
    is one of spheres, as many as the first screen counts (within 15 %: carved by the spheres'
    centres); elsewhere 3D is refused naming the test."""
    test = LAB_TESTS[name]
    if "dimensions" not in test.settings:
        with pytest.raises(InputError, match=f"{name}: .*no 3D implementation"):
            test.check_dimensions(3, "parallel_bond")
        return
    test.check_dimensions(3, "parallel_bond")
    given = {"dimensions": 3, "width_mm": 7.0, "height_mm": 14.0, "rmin_mm": 0.5, "disk_diameter_mm": 16.0,
             "beam_length_mm": 16.0, "beam_height_mm": 7.0, "beam_thickness_mm": 7.0, "notch_mm": 2.1,
             "notch_width_mm": 1.0, "span_mm": 12.0,
             "scb_radius_mm": 8.5, "scb_notch_mm": 4.25, "scb_notch_width_mm": 1.0}
    s = specimen_settings(test, {k: v for k, v in given.items() if k in test.settings})
    test.check(s)
    made = test.make(s)
    assert made.dimensions == 3
    assert specimen_size(name, SpecimenSettings(**given))[1] == pytest.approx(made.n_particles, rel=0.15)


@pytest.mark.parametrize("key, value, flag, words", [
    ("disk_diameter_mm", "13", "--diameter-mm", ("D / 2 thick", "13.2 mm")),  # t 6.5 < 8 R_max
])
def test_a_3d_brazilian_test_it_cannot_run_is_refused(cli, tmp_path, key, value, flag, words):
    one_line(calibrate(cli, tmp_path, campaign(BRAZILIAN, **{key: value})), f"specimen.{key}", *words)
    one_line(cli("simulate", "brazilian", "--rmin-mm", "0.5", "--dimensions", "3", flag, value.strip('"')),
             flag, *words)
    assert calibrate(cli, tmp_path, campaign(BRAZILIAN, dimensions="2", **{key: value})).returncode == 0


BENDING = "[targets.bending]\nK_IC_MPa_sqrt_m = 1.0"


def test_a_beams_thickness_is_a_3d_beams_alone_and_defaults_to_eight_of_its_largest_spheres(cli, tmp_path):
    """A 2D beam is a slab of unit thickness: a thickness is refused there, naming the key; in 3D
    one thinner than 4 of the largest spheres (6.6 mm at R_min 0.5 mm) is refused, none given is
    16 R_min x radius_ratio."""
    for text, flag, words in (("10", "--thickness-mm", ["dimensions = 3"]), ("5", "--thickness-mm", ["4 diameters"])):
        dimensions = "2" if words == ["dimensions = 3"] else "3"
        one_line(calibrate(cli, tmp_path, campaign(BENDING, dimensions=dimensions, beam_thickness_mm=text)),
                 "specimen.beam_thickness_mm", *words)
        one_line(cli("simulate", "bending", "--rmin-mm", "0.5", "--dimensions", dimensions, flag, text), flag, *words)
    bending = LAB_TESTS["bending"]
    s = specimen_settings(bending, {"dimensions": 3, "rmin_mm": 0.5})
    assert s["beam_thickness_mm"] is None and bending.outline(s).vessel_mm == (220.0, 16 * 0.5 * 1.65, 50.0)


def test_the_flat_jointed_material_is_accepted_in_3d_and_its_bad_values_refused(cli, tmp_path):
    flat = '[material]\nmodel = "flatjoint"'
    box = ("E_c = [15, 25], sigma_c = [30, 50]", "fj_emod = [15, 25], fj_ten = [5, 15]")
    run = calibrate(cli, tmp_path, campaign(flat).replace(*box))
    assert run.returncode == 0, run.stderr
    for value in ("2", "65", "3.5"):
        bad = campaign(flat).replace(*box).replace(
            "fj_ten = [5, 15] }", f"fj_ten = [5, 15] }}\nfixed = {{ fj_nal = {value} }}")
        one_line(calibrate(cli, tmp_path, bad), "search.fixed.fj_nal")
        one_line(cli("simulate", "ucs", *TINY, "--dimensions", "3", "--model", "flatjoint",
                     f"--set=fj_nal={value}"), "fj_nal")


@pytest.mark.parametrize("key, value, flag", [
    ("grain_shape", '"cloud"', "--grain-shape"),  # no 3D template
    ("contact_stiffness", '"pfc4"', "--contact-stiffness"),
])
def test_a_2d_only_setting_is_refused_in_3d(cli, tmp_path, key, value, flag):
    one_line(calibrate(cli, tmp_path, campaign(**{key: value})), f"specimen.{key}", "dimensions = 3")
    one_line(cli("simulate", "ucs", *TINY, "--dimensions", "3", flag, value.strip('"')), flag)
    assert calibrate(cli, tmp_path, campaign(dimensions="2", **{key: value})).returncode == 0


def test_the_hexagonal_lattice_is_refused_in_3d(cli):
    one_line(cli("simulate", "ucs", *TINY, "--dimensions", "3", "--packing", "hexagonal"), "--packing")


@pytest.mark.parametrize("key, value", [
    ("width_mm", "6.5"),  # 8 R_max = 6.6 mm: fewer than 4 of the largest spheres across
    ("height_mm", "6.5"),
    ("cloud_porosity", "0.9"),  # a cloud of about 53 spheres
])
def test_a_cylinder_too_small_for_its_spheres_is_refused(cli, tmp_path, key, value):
    one_line(calibrate(cli, tmp_path, campaign(**{key: value})), f"specimen.{key}")
    flag = "--" + key.replace("_", "-")
    one_line(cli("simulate", "ucs", *TINY, "--dimensions", "3", flag, value), flag)


def test_the_grain_limit_counts_spheres(cli, monkeypatch):
    """7 x 7 x 14 mm at R_min 0.5 mm is a cloud of about 345 spheres (a 2D packing of the same
    sides: about 63 disks): a limit of 200 grains refuses it, naming R_min."""
    monkeypatch.setenv(ENV, str(DEFAULT_MAX_GRAINS))  # put back after the test: --max-grains sets it
    spheres = expected_spheres(7, 14, 0.5, 1.65, DEFAULT_GENESIS_3D.cloud_porosity)
    assert 300 < spheres < 450
    one_line(cli("--max-grains", "200", "simulate", "ucs", *TINY, "--dimensions", "3"), "--rmin-mm",
             f"{spheres:,.0f} grains")
    assert expected_spheres(7, 14, 0.5, 1.65, 0.9) < MIN_SPHERES


def test_3d_defaults_apply_where_a_setting_is_not_given():
    assert {k: getattr(SpecimenSettings(), k) for k in DEFAULTS_3D} == {"cloud_porosity": 0.09,
                                                                       "contact_stiffness": "pfc4",
                                                                       "confined_vessel": "prism"}
    in_3d = SpecimenSettings(dimensions=3)
    assert in_3d.cloud_porosity == DEFAULT_GENESIS_3D.cloud_porosity == 0.35
    assert in_3d.contact_stiffness == "pfc5" and in_3d.confined_vessel == "cylinder"
    assert SpecimenSettings(dimensions=3, cloud_porosity=0.3).cloud_porosity == 0.3
    settings = specimen_settings(UCS, {"dimensions": 3, "width_mm": 7, "height_mm": 14, "rmin_mm": 0.5})
    assert settings["dimensions"] == 3 and settings["cloud_porosity"] == 0.35
    with pytest.raises(InputError, match="^contact_stiffness: "):
        specimen_settings(UCS, {"dimensions": 3, "contact_stiffness": "pfc4", "width_mm": 7,
                                "height_mm": 14, "rmin_mm": 0.5})


def test_clumps_are_taken_by_the_3d_ucs_and_brazilian_tests_and_refused_by_the_confined_one():
    given = {"dimensions": 3, "width_mm": 10.0, "height_mm": 20.0, "rmin_mm": 0.6, "disk_diameter_mm": 16.0,
             "grain_shape": "two-pebble"}
    for name in ("ucs", "brazilian"):
        test = LAB_TESTS[name]
        test.check(specimen_settings(test, {k: v for k, v in given.items() if k in test.settings}))
    confined = LAB_TESTS["biaxial"]
    with pytest.raises(InputError, match="grain_shape"):
        confined.check(specimen_settings(confined, {k: v for k, v in given.items() if k in confined.settings}))
