"""A user's text in the files rockcal writes: a rock name or a folder made to break out of a
comment stays data in every export format, the report and the record; the campaign file refuses
a rock name that is not one line of text."""

import ast
import json
import runpy

import pytest

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.outputs.export import read_calibration
from rockcal.pfc.formats import WRITERS
from rockcal.campaign.outputs.report import write_report
from rockcal.campaign.procedure.result import CalibrationResult, save_result
from rockcal.campaign.runs.store import RunStore
from rockcal.errors import InputError
from rockcal.params import make_params

CAMPAIGN = """
[targets.ucs]
E_GPa = 41.5
[specimen]
rmin_mm = 0.4
width_mm = 8
height_mm = 16
[search]
bounds = { E_c = [10, 30] }
"""
HOSTILE = {
    "newline": 'x\nimport os; os.system("touch PWNED")\n# ',
    "carriage return": "x\rimport os; os.system('touch PWNED')\r# ",
    "utf-7 coding cookie": "coding=utf_7 +AAo-import os+ADs- os.system(+ACI-touch PWNED+ACI-)+AAo-+ACM-",
    "line separator": "x\u2028import os; os.system('touch PWNED')",
    "fish command": 'x\nsystem.command("touch PWNED")\n; ',
    "nul and escape": "x\x00\x1b[2J",
    "right-to-left override": "x\u202e# )'DENWP hcuot'(metsys.so",
    "html": "</title><script>alert(1)</script>",
}


def finished(folder, rock: str):
    """A store holding a finished campaign's record (what `calibrate` writes at its end)."""
    nothing = {"samples": {"x": [], "responses": []}, "iterations": [], "dem_run_keys": [],
               "surrogate_check": {"x": [], "dem": [], "predicted": [], "max_relative_error": None,
                                   "trusted": None, "tolerance": 0.05, "epsilon": {}},
               "failed_runs": [{"stage": "samples", "message": rock}], "ucs_specimen": {}, "fixed": {}}
    result = CalibrationResult.model_validate(nothing | {
        "rock": rock, "accepted": True, "dem_runs": 1, "targets": {"E_GPa": 41.5},
        "specimen": parse_campaign(CAMPAIGN, folder).specimen, "parameters": ["E_c"],
        "bounds": {"E_c": [10, 30]}, "verified": {"E_GPa": 41.3}, "errors": {"E_GPa": -0.005},
        "identified": {"E_c": 21.65}, "identified_params": make_params({"E_c": 21.65}).key(),
        "tolerance": 0.05, "objective": "F", "best_iteration": 0, "final_ucs_run_key": "none"})
    store = RunStore(folder)
    save_result(store, result)
    return store, result


def exports(tmp_path, rock: str, folder_name: str = "out") -> dict[str, str]:
    folder = tmp_path / folder_name
    store, _ = finished(folder, rock)
    try:
        calibrated = read_calibration(store, folder)
    finally:
        store.close()
    return {name: write(calibrated) for name, write in WRITERS.items()}


@pytest.fixture(scope="module")
def benign(tmp_path_factory):
    return exports(tmp_path_factory.mktemp("benign"), "granite")


def code_of_python(text: str) -> str:
    return ast.dump(ast.parse(text))


def code_of_fish(text: str) -> list[str]:
    """The lines a FISH interpreter reads as commands (all but comments and blank lines)."""
    return [line for line in text.splitlines() if line.strip() and not line.lstrip().startswith(";")]


@pytest.mark.parametrize("rock", HOSTILE.values(), ids=HOSTILE.keys())
def test_a_hostile_rock_name_stays_a_comment_in_every_export(rock, benign, tmp_path, monkeypatch):
    made = exports(tmp_path, rock)
    python, fish = made["pfc-python"], made["pfc-fish"]
    assert code_of_python(python) == code_of_python(benign["pfc-python"])
    assert code_of_fish(fish) == code_of_fish(benign["pfc-fish"])
    for text in (python, fish):
        assert text.isascii() and all(" " <= c <= "~" for line in text.splitlines() for c in line)
    assert python.splitlines()[0] == "# -*- coding: utf-8 -*-"
    (tmp_path / "params.py").write_bytes(python.encode())
    monkeypatch.chdir(tmp_path)
    runpy.run_path(str(tmp_path / "params.py"))
    assert not (tmp_path / "PWNED").exists()
    assert json.loads(made["json"])["origin"]["rock"] == rock


def test_a_hostile_folder_name_stays_a_comment(benign, tmp_path):
    made = exports(tmp_path, "granite", folder_name=HOSTILE["newline"])
    assert code_of_python(made["pfc-python"]) == code_of_python(benign["pfc-python"])
    assert code_of_fish(made["pfc-fish"]) == code_of_fish(benign["pfc-fish"])


@pytest.mark.parametrize("rock", HOSTILE.values(), ids=HOSTILE.keys())
def test_a_hostile_rock_name_is_text_in_the_report_and_the_record(rock, tmp_path):
    store, result = finished(tmp_path, rock)
    try:
        page = write_report(result, store, tmp_path).read_text()
    finally:
        store.close()
    assert "<script>" not in page and "touch PWNED\")" not in page.replace("&quot;", "'")
    assert CalibrationResult.from_json(result.to_json()).rock == rock
    assert json.loads(result.to_json())["rock"] == rock


@pytest.mark.parametrize("rock", ["x\ny", "x\r", "a\x00b", "x\u2028y", "x\u202ey", "\x1b[2J"])
def test_the_campaign_file_refuses_a_rock_name_that_is_not_one_line(rock, tmp_path):
    text = f"[rock]\nname = {json.dumps(rock)}\n" + CAMPAIGN
    with pytest.raises(InputError, match="^rock.name: a rock name is one line of text"):
        parse_campaign(text, tmp_path)


@pytest.mark.parametrize("rock", ["[/]", "[bold]x[/bold", "[link=file:///etc/passwd]x"])
def test_rich_markup_in_a_rock_name_is_printed_as_text(rock, tmp_path, capsys):
    from types import SimpleNamespace

    from rockcal.cli.calibrate import _print_plan, _print_summary

    campaign = planned(parse_campaign(f"[rock]\nname = {json.dumps(rock)}\n" + CAMPAIGN, tmp_path))
    store, result = finished(tmp_path, rock)
    try:
        _print_plan(campaign, store, SimpleNamespace(workers=None), None)
        _print_summary(result, tmp_path / "report.html", as_json=False, timing={})
    finally:
        store.close()
    captured = capsys.readouterr()
    assert f"Calibrating {rock}" in captured.err and rock in captured.out
