"""The FISHTank export of a clumped material (FISHTank's clumped materials, PFC's clump
templates) and of either material for the FISHTank of PFC 5, 6 or 7: every name FISHTank's
clump procedures read is set, the template the file creates is the engine's to the last bit,
and `cm_matType` is the targeted FISHTank's."""

import json
import re
import sys
from types import ModuleType, SimpleNamespace

import numpy as np
import pytest

from rockcal.campaign.input.config import SpecimenSettings
from rockcal.materials.clump_templates import DEFAULT_SHAPE, GRAIN_SHAPES, template
from rockcal.errors import InputError
from rockcal.materials.flat_joint import make_flatjoint_params
from rockcal.params import make_params
from rockcal.pfc.calibrated import Calibrated, for_fishtank
from rockcal.pfc.json_file import to_json
from rockcal.pfc.parameter_file import to_fish
from rockcal.pfc.python_script import to_python

# The names FISHTank reads to make a clumped material's grains, as found in siyuanxu/PFC-fishPKG,
# ExampleProjects/fistSrc/ft.fis (fistPkg25, PFC 5.0): `_mpMakeGrains` (cm_shape: 0 balls,
# 1 clumps), `_mpClumpDistribute` (cm_nSD, cm_ctName(i), cm_Dmult, cm_Dlo(i), cm_Dup(i),
# cm_typeSD(i), cm_Vfrac(i)) and `_mpCheckCommonParams` (the same, cm_ctName(i) a string when
# cm_shape = 1). itascaconsulting/2021_ARMA_frac, fistSrc/ft.fis (FISHTank 6.6, PFC 6.0) reads
# the same names in the same procedures.
CLUMP_NAMES = ("cm_shape", "cm_nSD", "cm_ctName", "cm_Dmult", "cm_Dlo", "cm_Dup", "cm_typeSD", "cm_Vfrac")
# The template cm_ctName(i) names is made by PFC's command before mpSetCommonParams, as in
# siyuanxu/PFC-fishPKG, ExampleProjects/MatGen-FlatJointed/mpParams-Clumped.p2dat:
# `clump template create pebcalculate name NAME pebbles N` and N times radius, x, y.
TEMPLATE_COMMAND = re.compile(r"^clump template create pebcalculate name (\w+) pebbles (\d+) \.\.\.$")
# cm_matType of the two materials in each FISHTank: siyuanxu/PFC-fishPKG fistSrc/ft.fis
# (fistPkg25, PFC 5.0: `_mpCheckAllParams` cases 2 parallel-bonded, 3 flat-jointed; the
# clumped examples' mpParams-Clumped.p2dat set 2 and 3) and itascaconsulting/2021_ARMA_frac
# fistSrc/ft.fis (FISHTank 6.6, PFC 6.0: 2 parallel-bonded, 3 soft-bonded, 4 flat-jointed).
# No PFC 7 FISHTank source was at hand: 7 is numbered as 6.
MATERIAL_TYPES = {5: {"parallel_bond": 2, "flatjoint": 3}, 6: {"parallel_bond": 2, "flatjoint": 4},
                  7: {"parallel_bond": 2, "flatjoint": 4}}

MATERIALS = {"parallel_bond": make_params({"E_c": 20.0, "sigma_c_cv": 0.2}),
             "flatjoint": make_flatjoint_params({"fjm_B_frac": 0.8})}
CLUMPED = [shape for shape in GRAIN_SHAPES if shape != DEFAULT_SHAPE]
ORIGIN = {"rock": "granite", "accepted": True, "dem_runs": 1, "campaign": "c", "engine": "e",
          "targets": {"E_GPa": 70.0}, "verified": {}, "identified": {}}


def calibrated(model: str, shape: str, version: int = 6) -> Calibrated:
    specimen = SpecimenSettings(rmin_mm=0.4, radius_ratio=1.5, grain_shape=shape)
    return for_fishtank(Calibrated(MATERIALS[model], specimen, ORIGIN), version)


def fish_values(text: str) -> dict:
    """The assignments of a FISH parameter file (an array's first entry under its name)."""
    values = {}
    for name, value in re.findall(r"^  (\w+)(?:\(1\))? = (.+?)(?:  ;.*)?$", text, re.M):
        values[name] = value.strip("'") if value.startswith("'") else value
    return values


def fish_templates(text: str) -> dict[str, np.ndarray]:
    """The clump templates a FISH file creates: name -> pebbles (radius, x, y) as written."""
    lines = text.splitlines()
    made = {}
    for k, line in enumerate(lines):
        found = TEMPLATE_COMMAND.match(line)
        if found:
            n = int(found[2])
            rows = [lines[k + 1 + i].removesuffix(" ...").split() for i in range(n)]
            made[found[1]] = np.array(rows, float)
    return made


def python_run(text: str) -> SimpleNamespace:
    """The export's Python script run as in PFC: the commands and FISH variables it sets."""
    commands, fish = [], {}
    itasca = ModuleType("itasca")
    itasca.command = commands.append
    itasca.fish = SimpleNamespace(set=fish.__setitem__)
    saved = sys.modules.get("itasca")
    sys.modules["itasca"] = itasca
    try:
        scope = {}
        exec(text, scope)
    finally:
        if saved is None:
            del sys.modules["itasca"]
        else:
            sys.modules["itasca"] = saved
    return SimpleNamespace(commands=commands, fish=fish, scope=scope)


def engine_pebbles(shape: str) -> np.ndarray:
    t = template(shape)
    return np.column_stack([t.radii, t.offsets])


@pytest.mark.parametrize("model", MATERIALS)
@pytest.mark.parametrize("shape", CLUMPED)
def test_the_fish_file_sets_every_clump_name_and_creates_the_engines_template(model, shape):
    text = to_fish(calibrated(model, shape))
    values = fish_values(text)
    missing = [name for name in CLUMP_NAMES if name not in values]
    assert not missing
    assert values["cm_shape"] == "1" and values["cm_nSD"] == "1" and values["cm_typeSD"] == "0"
    assert "  cm_ctName = array.create(cm_nSD)" in text
    made = fish_templates(text)
    assert list(made) == [values["cm_ctName"]]
    np.testing.assert_array_equal(made[values["cm_ctName"]], engine_pebbles(shape))  # to the bit
    # made before FISHTank's groups, as its clumped examples do, and not inside a FISH function
    assert text.index("clump template create") < text.index("def mpSetCommonParams")
    # the sizes are the grains' equivalent diameters: 2 R_min to 2 R_min x ratio
    assert float(values["cm_Dlo"]) == pytest.approx(0.8e-3) and float(values["cm_Dup"]) == pytest.approx(1.2e-3)


@pytest.mark.parametrize("shape", CLUMPED)
def test_the_python_script_and_json_carry_the_same_template(shape):
    c = calibrated("flatjoint", shape)
    run = python_run(to_python(c))
    name = run.fish["cm_ctName"]
    assert run.fish["cm_shape"] == 1 and name == ["rockcal_" + shape.replace("-", "_")]
    assert not [n for n in CLUMP_NAMES if n not in run.fish]
    (command,) = run.commands
    words = command.split()
    assert words[:7] == ["clump", "template", "create", "pebcalculate", "name", name[0], "pebbles"]
    assert int(words[7]) == template(shape).n_pebbles
    np.testing.assert_array_equal(np.array(words[8:], float).reshape(-1, 3), engine_pebbles(shape))
    data = json.loads(to_json(c))
    assert data["parameters"]["cm_ctName"] == name[0] and data["fishtank"]["pfc"] == 6
    pebbles = data["clump_templates"][name[0]]["pebbles"]
    np.testing.assert_array_equal([[p["radius"], p["x"], p["y"]] for p in pebbles], engine_pebbles(shape))


@pytest.mark.parametrize("model", MATERIALS)
def test_balls_are_disks_without_a_template(model):
    c = calibrated(model, DEFAULT_SHAPE)
    text = to_fish(c)
    values = fish_values(text)
    assert values["cm_shape"] == "0" and "cm_ctName" not in values
    assert "clump template" not in text
    run = python_run(to_python(c))
    assert run.commands == [] and "cm_ctName" not in run.fish
    data = json.loads(to_json(c))
    assert data["clump_templates"] == {} and "cm_ctName" not in data["parameters"]


@pytest.mark.parametrize("version", MATERIAL_TYPES)
@pytest.mark.parametrize("model", MATERIALS)
@pytest.mark.parametrize("shape", [DEFAULT_SHAPE, "two-pebble"])
def test_cm_mattype_is_the_targeted_fishtanks(version, model, shape):
    c = calibrated(model, shape, version)
    expected = MATERIAL_TYPES[version][model]
    text = to_fish(c)
    assert fish_values(text)["cm_matType"] == str(expected)
    assert python_run(to_python(c)).fish["cm_matType"] == expected
    assert json.loads(to_json(c))["parameters"]["cm_matType"] == expected
    (said,) = [line for line in text.splitlines() if line.startswith("; for PFC")]  # the file says which
    kind = {"parallel_bond": "parallel-bonded", "flatjoint": "flat-jointed"}[model]
    assert said.startswith(f"; for PFC {version}.0") and f"{expected} {kind}" in said


@pytest.mark.parametrize("bad", ["4", "8", "6.6", "pfc6", "", "True"])
def test_an_unknown_fishtank_is_refused_naming_the_option(bad):
    with pytest.raises(InputError, match="^--fishtank: no FISHTank for PFC"):
        calibrated("parallel_bond", DEFAULT_SHAPE, bad)


CAMPAIGN = """
[rock]
name = "twin"
[targets.ucs]
E_GPa = 41.5
[specimen]
rmin_mm = 0.4
radius_ratio = 1.5
width_mm = 8
height_mm = 16
grain_shape = "three-pebble"
[search]
bounds = { E_c = [10, 30] }
"""


@pytest.fixture(scope="module")
def finished(tmp_path_factory, save_finished):
    """A store holding a finished clumped campaign's record (what `calibrate` writes at its end)."""
    return save_finished(tmp_path_factory.mktemp("clumped"), CAMPAIGN, make_params({"E_c": 21.65}), {"E_c": 21.65})

def test_rockcal_export_of_a_clumped_campaign_for_pfc5(cli, finished, tmp_path):
    path = tmp_path / "mpParams-Clumped.p2dat"
    run = cli("export", finished, "--fishtank", "5", "--to", path)
    assert run.returncode == 0, run.stderr
    text = path.read_text()
    values = fish_values(text)
    assert values["cm_matType"] == "2" and values["cm_shape"] == "1"
    assert values["cm_ctName"] == "rockcal_three_pebble"
    np.testing.assert_array_equal(fish_templates(text)["rockcal_three_pebble"], engine_pebbles("three-pebble"))
    assert "; for PFC 5.0's FISHTank (fistPkg25)" in text
    default = cli("export", finished, "--format", "json")
    assert default.returncode == 0 and json.loads(default.stdout)["fishtank"]["pfc"] == 6


@pytest.mark.parametrize("bad", ["8", "6.6", "x"])
def test_rockcal_export_refuses_a_bad_fishtank_in_one_line_before_reading_the_campaign(cli, tmp_path, bad):
    run = cli("export", tmp_path / "no-such-campaign", "--fishtank", bad)
    assert run.returncode == 2
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and "--fishtank" in lines[0] and "Traceback" not in run.stderr
