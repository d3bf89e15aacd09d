"""What the command line tells of its scope: its commands in the order a user meets them, the
defaults that differ in 3D, and a test with no 3D implementation refused in one line."""

import pytest

from test_cli import rockcal  # noqa: F401  (the command in this process)


def test_the_commands_are_listed_as_a_user_meets_them(rockcal):
    listed = rockcal("--help").stdout.split("Commands:")[1].split()
    named = [word for word in listed if word in ("calibrate", "simulate", "export", "sensitivity", "kic")]
    assert named == ["calibrate", "simulate", "export", "sensitivity", "kic"]


def test_a_setting_whose_default_differs_in_3d_shows_both(rockcal):
    text = " ".join(rockcal("simulate", "ucs", "--help").stdout.split())
    assert "[default: (0.09 in 2D, 0.35 with --dimensions 3)]" in text
    assert "[default: (pfc4 in 2D, pfc5 with --dimensions 3)]" in text


@pytest.mark.parametrize("test", ["bending"])
def test_a_test_without_3d_is_refused_in_one_line(rockcal, test, tmp_path):
    run = rockcal("simulate", test, "--dimensions", "3", "--out", str(tmp_path / "out"))
    assert run.returncode == 2
    assert run.stderr == (f"rockcal: error: {test}: no 3D implementation yet (3D has ucs, brazilian, "
                          "direct_tension, biaxial: confined (a triaxial cell, or a square prism in polyaxial "
                          "walls))\n")
    assert not (tmp_path / "out").exists()


def test_each_command_says_what_its_options_are_in_its_dimensions(rockcal):
    """--width-mm is the UCS and direct tension cylinders' diameter in 3D, and the confined
    cylinder's or prism's; kn is given in 2D and 3D; the Python export is 2D's."""
    def help_of(*command):
        return " ".join(rockcal(*command, "--help").stdout.split())

    ucs, biaxial, tension = (help_of("simulate", test) for test in ("ucs", "biaxial", "direct-tension"))
    assert "Specimen width, mm (in 3D the cylinder's diameter)." in ucs
    assert "Specimen width, mm (in 3D the cylinder's diameter, the square prism's side)." in biaxial
    assert "Prism width W, mm (in 3D the cylinder's diameter)." in tension
    assert "UCS specimen height" not in ucs + biaxial + tension
    assert ("pfc5: 2 min(R) t E_c / (R_A + R_B) in 2D, t = 1 m; pi min(R)^2 E_c / (R_A + R_B) in 3D" in ucs)
    assert "pfc-python: a PFC2D Python script (2D only)" in help_of("export")
