"""A run that broke no bond did not fail: its peak is no strength. Its summary says
`failed: false` and the notebook call and the command warn of it; a run that broke bonds says
`failed: true` without a warning. On a 10 mm disk of 178 grains, seconds a run: between flat
platens it breaks no bond (its peak is the disk seating), between ISRM's jaws it splits."""

import json
import sys
import warnings

import pytest

from rockcal.api import simulate
from rockcal.cli.app import main

DISK = {"disk_diameter_mm": 10.0, "seed": 2}


def test_a_disk_that_broke_no_bond_is_not_failed_and_warned_of():
    with pytest.warns(UserWarning, match="^Brazilian test: no bond broke: the specimen did not fail"):
        unbroken = simulate("brazilian", {}, **DISK)
    assert unbroken.n_broken_tension + unbroken.n_broken_shear == 0
    assert unbroken.summary()["failed"] is False and unbroken.sigma_t_MPa > 0  # a peak, no strength
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        split = simulate("brazilian", {}, **DISK, brazilian_loading="isrm")
    assert split.n_broken_tension > 0 and split.summary()["failed"] is True


def test_the_command_says_failed_false_in_its_json_and_a_warning_line(monkeypatch, capsys):
    monkeypatch.setattr(sys, "argv", ["rockcal", "simulate", "brazilian", "--diameter-mm", "10",
                                      "--seed", "2", "--json"])
    with pytest.raises(SystemExit) as done:
        main()
    out = capsys.readouterr()
    assert done.value.code == 0
    assert json.loads(out.out)["failed"] is False
    assert out.err.startswith("rockcal: warning: Brazilian test: no bond broke: the specimen did not fail")
