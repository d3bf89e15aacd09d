"""`rockcal calibrate --quick`: the campaign at half resolution with one validation beam, labelled
as a quick look wherever its numbers are shown, in a folder of its own."""

import html
import subprocess
import sys

import pytest

from rockcal.campaign.input.config import load_campaign, parse_campaign
from rockcal.campaign.plan.cost import specimen_size
from rockcal.campaign.plan.quick_look import FEW_GRAINS, quick_look, quick_look_note
from rockcal.campaign.procedure.steps import calibrate
from rockcal.campaign.outputs.report import write_report
from rockcal.campaign.procedure.result import CalibrationResult
from rockcal.campaign.runs.store import STORE_NAME, RunStore
from rockcal.campaign.job import QUICK_LOOK
from rockcal.cli.calibrate import summary
from test_procedure import Workers  # a deterministic stand-in for the DEM

TINY = """
[rock]
name = "tiny"
[targets.ucs]
E_GPa = 20.0
[surrogate]
samples = 4
checks = 1
[search]
bounds = { E_c = [10, 30] }
[specimen]
width_mm = 8
height_mm = 16
rmin_mm = 0.2
"""


def test_a_quick_look_doubles_rmin_and_keeps_one_beam_of_the_granite():
    granite, _ = load_campaign(None)
    quick = quick_look(granite)
    assert quick.specimen.rmin_mm == 2 * granite.specimen.rmin_mm == 0.5
    assert (granite.specimen.bending_seeds, quick.specimen.bending_seeds) == (3, 1)
    unchanged = {"rmin_mm", "bending_seeds"}
    assert quick.specimen.model_dump(exclude=unchanged) == granite.specimen.model_dump(exclude=unchanged)
    assert (granite.uncertainty.draws, quick.uncertainty.draws) == (200, 50)
    assert quick.model_dump(exclude={"specimen", "uncertainty", "sensitivity"}) == \
        granite.model_dump(exclude={"specimen", "uncertainty", "sensitivity"})
    assert granite.sensitivity_specimen().rmin_mm == 0.5 and quick.sensitivity_specimen() == quick.specimen
    note = quick_look_note(quick)
    assert "R_min 0.5 mm" in note and "one validation beam" in note
    assert "not the full-resolution calibration" in note
    assert "warning" not in note  # its specimens keep thousands of grains


def test_a_quick_look_of_specimens_with_few_grains_warns_naming_the_count(tmp_path):
    quick = quick_look(parse_campaign(TINY, tmp_path))
    _, grains, _ = specimen_size("ucs", quick.specimen)
    assert grains < FEW_GRAINS
    assert quick_look_note(quick).endswith(f"; warning: the UCS 8 x 16 mm specimen holds about {grains:,} grains, "
                                           f"fewer than {FEW_GRAINS:,}: too few for its numbers to mean much (a "
                                           "strength on its bound, a peak that breaks no bond)")


def test_a_quick_look_without_a_beam_does_not_promise_one(tmp_path):
    assert "beam" not in quick_look_note(quick_look(parse_campaign(TINY, tmp_path)))


@pytest.mark.slow
def test_the_first_screen_says_quick_look_and_its_folder_is_its_own(tmp_path):
    (tmp_path / "tiny.toml").write_text(TINY)

    def calibrate(*args):  # every run stops at once: only the first screen and the store matter
        return subprocess.run([sys.executable, "-m", "rockcal", "calibrate", "tiny.toml", "--workers", "1",
                               "--time-limit-s", "1e-6", *args], cwd=tmp_path, capture_output=True,
                              text=True, timeout=300)

    run = calibrate("--quick")
    assert "Calibrating tiny (quick look)" in run.stderr
    assert "R_min 0.4 mm, the campaign's 0.2 mm doubled" in " ".join(run.stderr.split())
    out = tmp_path / "runs" / "tiny-quick"
    assert (out / STORE_NAME).exists() and not (tmp_path / "runs" / "tiny").exists()
    store = RunStore(out)
    assert "quick look" in store.document(QUICK_LOOK)
    store.close()
    again = calibrate("--out", out, "--resume")  # the full calibration never resumes a quick look
    assert again.returncode == 2 and again.stderr.startswith("rockcal: error: --quick: ")


@pytest.mark.slow
def test_the_report_and_json_of_a_quick_look_say_so(tmp_path):
    quick = quick_look(parse_campaign(TINY, tmp_path))
    note = quick_look_note(quick)
    result = calibrate(quick, Workers(1, lambda p: {"E_GPa": p["E_c"]})).model_copy(update={"quick_look": note})
    assert summary(result)["quick_look"] == note
    assert CalibrationResult.from_json(result.to_json()).quick_look == note
    store = RunStore(tmp_path / "out")
    page = write_report(result, store, tmp_path / "out").read_text()
    store.close()
    assert "<h1>Quick look at tiny (2D)</h1>" in page and html.escape(note) in page
    full = result.model_copy(update={"quick_look": None})
    assert summary(full)["quick_look"] is None and "quick_look" not in full.to_json()
