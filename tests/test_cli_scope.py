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


@pytest.mark.parametrize("test", ["bending", "direct-tension"])
def test_a_test_without_3d_is_refused_in_one_line(rockcal, test, tmp_path):
    run = rockcal("simulate", test, "--dimensions", "3", "--out", str(tmp_path / "out"))
    assert run.returncode == 2
    assert run.stderr == (f"rockcal: error: {test}: no 3D implementation yet (3D has ucs, brazilian, "
                          "biaxial: confined (square prism, polyaxial walls))\n")
    assert not (tmp_path / "out").exists()
