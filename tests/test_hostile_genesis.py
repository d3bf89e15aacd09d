"""Hostile genesis settings of 3D and clumped specimens: each is refused in one line naming its
key (`rockcal: error: <key>: ...`, exit 2) before any DEM run and before any file is written;
none crashes, runs out of memory or shows a traceback."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rockcal.errors import InputError
from rockcal.labtests.registry import lab_test
from rockcal.labtests.settings import specimen_settings
from rockcal.specimens.packing import MAX_PACKING_PRESSURE_MPA
from rockcal.specimens3d.specimen import MAX_CLOUD_POROSITY_3D

ONE_LINE = re.compile(r"rockcal: error: (\S+): [^\n]+\n")
GRANITE_3D = Path(__file__).parents[1] / "docs" / "campaigns" / "granite-3d.toml"


def refused(cli, tmp_path, *args) -> str:
    """The key of the one-line refusal of `rockcal ARGS` run in `tmp_path`, which it leaves empty."""
    done = cli(*args, cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    match = ONE_LINE.fullmatch(done.stderr)
    assert match, done.stderr
    assert list(tmp_path.iterdir()) == [], "a refused command wrote a file"
    return match.group(1)


SIMULATE_3D = ["simulate", "brazilian", "--dimensions", "3", "--out", "out"]


@pytest.mark.parametrize("args, key", [
    # a sparse cloud: no sphere had a spring, a time step of inf made every centre NaN and the
    # neighbour grid was indexed out of bounds (exit 139)
    ([*SIMULATE_3D, "--cloud-porosity", "0.99"], "--cloud-porosity"),
    (["simulate", "ucs", "--dimensions", "3", "--cloud-porosity", "0.9", "--out", "out"], "--cloud-porosity"),
    ([*SIMULATE_3D, "--diameter-mm", "300"], "--rmin-mm"),  # 54 million spheres, counted as 2D disks
    ([*SIMULATE_3D, "--rmin-mm", "1e-300"], "--rmin-mm"),  # ZeroDivisionError
    ([*SIMULATE_3D, "--pressure-mpa", "1000"], "--pressure-mpa"),  # ValueError in the grid
    (["simulate", "biaxial", "--dimensions", "3", "--confinement-mpa", "5", "--pressure-mpa", "500",
      "--out", "out"], "--pressure-mpa"),
    (["simulate", "ucs", "--grain-shape", "two-pebble", "--pressure-mpa", "1000", "--out", "out"], "--pressure-mpa"),
    (["simulate", "ucs", "--grain-shape", "two-pebble", "--packing", "hexagonal", "--width-mm", "10",
      "--height-mm", "20", "--out", "out"], "--packing"),  # ran balls
    ([*SIMULATE_3D, "--loading", "strips", "--strip-modulus-gpa", "1e-300"], "--strip-modulus-gpa"),
    (["simulate", "brazilian", "--loading", "strips", "--strip-modulus-gpa", "1e-300", "--out", "out"],
     "--strip-modulus-gpa"),
])
def test_a_hostile_genesis_setting_is_refused_in_one_line(cli, tmp_path, args, key):
    assert refused(cli, tmp_path, *args) == key


def test_a_clumped_genesis_that_gives_up_is_refused(cli, tmp_path):
    """70 of 70 clumps still floating: the run went on with them before."""
    key = refused(cli, tmp_path, "simulate", "ucs", "--grain-shape", "two-pebble", "--cloud-porosity", "0.5",
                  "--width-mm", "10", "--height-mm", "20", "--rmin-mm", "0.5", "--out", "out")
    assert key == "--cloud-porosity"


@pytest.mark.parametrize("change, key", [
    (("dimensions = 3", 'dimensions = "3"'), "specimen.dimensions"),  # was named contact_stiffness
    (("rmin_mm = 0.8", "rmin_mm = 0.8\ncloud_porosity = 0.9"), "specimen.cloud_porosity"),
    (("rmin_mm = 0.8", "rmin_mm = 0.8\npressure_mpa = 1000"), "specimen.pressure_mpa"),
    (("rmin_mm = 0.8", "rmin_mm = 0.8\ndisk_diameter_mm = 300\n[targets.brazilian]\nsigma_t_MPa = 10"),
     "specimen.rmin_mm"),  # a 3D disk of 1.7 million spheres, counted as 41,592 disks
])
def test_a_hostile_3d_campaign_is_refused_in_one_line(cli, tmp_path, change, key):
    text = GRANITE_3D.read_text().replace(*change)
    path = tmp_path / "campaign.toml"
    path.write_text(text)
    done = cli("calibrate", path, "--dry-run", cwd=tmp_path)
    assert done.returncode == 2 and ONE_LINE.fullmatch(done.stderr).group(1) == key, done.stderr
    assert [p.name for p in tmp_path.iterdir()] == ["campaign.toml"]


# ---------------------------------------------------------------------------------------------
# any 3D or clumped specimen setting is accepted or refused naming a key, before any genesis

NUMBERS = st.one_of(st.sampled_from([0.0, -1.0, 5e-324, 1e-300, 1e-3, 0.45, 0.4500001, 0.9, 0.99, 1.0,
                                     100.0, 100.1, 1000.0, 1e300]),
                    st.floats(1e-4, 1e4, allow_nan=False))
SETTINGS = {"rmin_mm": NUMBERS, "radius_ratio": NUMBERS, "cloud_porosity": NUMBERS, "pressure_mpa": NUMBERS,
            "install_gap": NUMBERS, "width_mm": NUMBERS, "height_mm": NUMBERS, "disk_diameter_mm": NUMBERS}
TESTS = {"ucs": ("width_mm", "height_mm"), "biaxial": ("width_mm", "height_mm"),
         "brazilian": ("disk_diameter_mm",)}


@st.composite
def specimen_cases(draw):
    """A test, 3D or of a clump shape, with one to three of its settings at hostile values."""
    test = draw(st.sampled_from(sorted(TESTS)))
    values = {"dimensions": 3} if draw(st.booleans()) else {
        "grain_shape": draw(st.sampled_from(["two-pebble", "three-pebble", "cloud"]))}
    names = [n for n in SETTINGS if not n.endswith("_mm") or n == "rmin_mm" or n in TESTS[test]]
    for name in draw(st.lists(st.sampled_from(names), min_size=1, max_size=3, unique=True)):
        values[name] = draw(SETTINGS[name])
    return test, values


@settings(max_examples=60, deadline=None, derandomize=True, database=None)
@given(specimen_cases())
def test_any_3d_or_clump_setting_is_accepted_or_refused_by_name(case):
    test, values = case
    try:
        s = specimen_settings(lab_test(test), values)
    except InputError as exc:
        assert exc.field in lab_test(test).settings, (exc.field, values)  # a key, maybe one left at its default
        assert "\n" not in str(exc)
        return
    # accepted: within the bounds where the genesis finishes
    assert s["pressure_mpa"] <= MAX_PACKING_PRESSURE_MPA and s["rmin_mm"] >= 1e-3
    if s["dimensions"] == 3:
        assert s["cloud_porosity"] <= MAX_CLOUD_POROSITY_3D
