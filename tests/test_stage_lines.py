"""`rockcal.calibrate` in a script or a notebook prints the first screen and a line as each
stage begins and ends, on stderr; `quiet=True` prints nothing."""

import sys
from pathlib import Path

import pytest

import rockcal
from rockcal.api import StageLines
from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.screen import describe
from rockcal.campaign.runs.store import RunStore
from rockcal.errors import InputError

sys.path.insert(0, str(Path(__file__).parent / "campaign"))
from tiny import tiny_campaign  # noqa: E402


def test_the_first_screen_then_a_line_as_each_stage_begins_and_ends(tmp_path, capsys):
    campaign = parse_campaign(tiny_campaign(), tmp_path)
    store = RunStore(tmp_path / "out")
    try:
        lines = StageLines(campaign, None, store, executor=None)
        screen = describe(campaign, store, None)
        for done in (0, 1, 2, 2):  # the last count again: told once
            lines("samples and checks", done, 2)
        lines("verification", 1, 1)  # a batch the store held: begun and done at once
    finally:
        store.close()
    err = capsys.readouterr().err.splitlines()
    assert err[:1 + len(screen)] == [f"Calibrating {campaign.rock.name}", *("  " + line for line in screen)]
    told = [line.rsplit(",", 1)[0] for line in err[1 + len(screen):]]
    assert told == ["samples and checks: 2 to do", "samples and checks: 2/2 done",
                    "verification: 1 to do", "verification: 1/1 done"]


def test_quiet_must_be_true_or_false():
    with pytest.raises(InputError, match="^quiet: True or False, got 'no'"):
        rockcal.calibrate(quiet="no")
