"""A store written by rockcal 0.2.1 (UCS test revision 3) before the procedure became a
declared list of steps resumes with the same answer: the runs of a later test revision run
again (the UCS runs, whose curve gained a column of broken bonds in revision 4; the Brazilian
check, whose split is read crack by crack in revision 2) and give the same engine numbers to the
last bit, the same parameter sets
and the same acceptance; the surrogate's and the search's numbers agree to round-off (the store
was written on another processor: `same_record`). The record's surrogate check is the one of
shapes chosen as now: where the leave-one-out errors tie (its 4 samples), the smallest."""

import json
import shutil
import sqlite3
from pathlib import Path

import pytest

from same_record import differences

DATA = Path(__file__).parent / "data" / "store-0.2.1"
SAME = ("identified", "identified_params", "accepted", "dem_runs", "errors", "best_iteration", "bounds",
        "fixed", "objective", "iterations", "uncertainty", "checks", "surrogate_check")


@pytest.mark.slow  # a campaign's UCS runs, run again
def test_a_store_of_the_earlier_procedure_resumes_with_the_same_answer(tmp_path, cli):
    out = tmp_path / "out"
    out.mkdir()
    shutil.copy(DATA / "runs.sqlite", out / "runs.sqlite")
    with sqlite3.connect(DATA / "runs.sqlite") as db:
        stored_runs = db.execute("SELECT COUNT(*) FROM runs WHERE kind IN ('ucs', 'brazilian')").fetchone()[0]
    campaign = tmp_path / "campaign.toml"  # its identifiability stage, later than the store, off: no run of its own
    campaign.write_text((DATA / "campaign.toml").read_text() + "\n[identifiability]\nruns = false\n")
    run = cli("calibrate", campaign, "--out", out, "--resume", "--workers", "1", "--json")
    assert run.returncode == 0, run.stderr
    now = json.loads((out / "record.json").read_text())
    before = json.loads((DATA / "record.json").read_text())
    assert now["executed_runs"] == stored_runs
    found = [d for key in SAME for d in differences(_without_new(now[key], before[key]), before[key], key)]
    assert not found, found


def _without_new(now, before):
    """`now` with the responses `before` lacks (CI, CD) left out, at any depth, and the keys of
    the runs (new revisions, new keys) taken from `before`."""
    if isinstance(now, dict) and isinstance(before, dict):
        return {k: before[k] if k.startswith("run_key") else _without_new(v, before[k])
                for k, v in now.items() if k in before}
    if isinstance(now, list) and isinstance(before, list) and len(now) == len(before):
        return [_without_new(a, b) for a, b in zip(now, before)]
    return now
