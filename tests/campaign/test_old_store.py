"""A store written by rockcal 0.2.1 before the procedure became a declared list of steps
resumes without running anything again and gives the same record."""

import json
import shutil
import subprocess
import sys
from pathlib import Path

DATA = Path(__file__).parent / "data" / "store-0.2.1"


def test_a_store_of_the_earlier_procedure_resumes_with_nothing_run_again(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    shutil.copy(DATA / "runs.sqlite", out / "runs.sqlite")
    run = subprocess.run([sys.executable, "-m", "rockcal", "calibrate", str(DATA / "campaign.toml"), "--out",
                          str(out), "--resume", "--workers", "1", "--json"], capture_output=True, text=True,
                         timeout=600)
    assert run.returncode == 0, run.stderr
    now = json.loads((out / "record.json").read_text())
    before = json.loads((DATA / "record.json").read_text())
    assert now.pop("executed_runs") == 0
    before.pop("executed_runs")
    assert now == before
