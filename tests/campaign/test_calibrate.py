"""`rockcal calibrate` end to end on a small specimen: a twin experiment (targets made by the
engine at known parameters are recovered), and a campaign killed mid-way that resumes."""

import json
import signal
import sqlite3
import subprocess
import sys
import time

import pytest

import rockcal
from rockcal.campaign.runs.store import RunStore

pytestmark = pytest.mark.slow  # DEM runs and specimens of minutes: deselect with -m "not slow"

TRUE = {"E_c": 20.0, "kn_ks": 2.0, "sigma_c": 40.0}
FIXED = {"tau_c": 200.0, "mu": 0.5}
# About 200 disks: too few for every packing to read nu. On seed 1 of generator v6 the lateral
# gauges read nu 0.77 at TRUE (seeds 2 and 3: 0.225, 0.213), so the twin uses seed 2.
# Nor is its UCS smooth: near TRUE it jumps by up to 9 % between parameter sets 2 % apart
# (sigma_c 40.9 and 41.6 MPa at E_c 20, kn/ks 2: -5.8 % and +3.5 % of the target), so the twin
# accepts at the source's 5 % (at 2 % acceptance was luck: it came, or not, with a last-bit
# change of the inertias) and asks sigma_c, which the UCS alone pins, within 10 %.
SPECIMEN = {"rmin_mm": 0.4, "width_mm": 10.0, "height_mm": 20.0, "seed": 2}


def campaign_text(targets: dict) -> str:
    return f"""
[targets.ucs]
E_GPa = {targets["E_GPa"]!r}
nu = {targets["nu"]!r}
ucs_MPa = {targets["ucs_MPa"]!r}
[specimen]
rmin_mm = {SPECIMEN["rmin_mm"]}
width_mm = {SPECIMEN["width_mm"]}
height_mm = {SPECIMEN["height_mm"]}
seed = {SPECIMEN["seed"]}
[search]
bounds = {{ E_c = [10, 30], kn_ks = [1, 3], sigma_c = [20, 60] }}
fixed = {{ tau_c = {FIXED["tau_c"]}, mu = {FIXED["mu"]} }}
[surrogate]
samples = 12
checks = 2
[optimizer]
iterations = 50
[acceptance]
tolerance = 0.05
max_dem_runs = 24
"""


def calibrate(*args, **kwargs):
    return subprocess.Popen([sys.executable, "-m", "rockcal", "calibrate", *map(str, args)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kwargs)


@pytest.fixture(scope="module")
def twin(tmp_path_factory):
    """Targets made by the engine at TRUE, and the uninterrupted campaign's --json output."""
    folder = tmp_path_factory.mktemp("twin")
    specimen = rockcal.random_packing(SPECIMEN["width_mm"], SPECIMEN["height_mm"], SPECIMEN["rmin_mm"],
                                      seed=SPECIMEN["seed"])
    made = rockcal.simulate_ucs(TRUE | FIXED, specimen)
    targets = {"E_GPa": made.E_GPa, "nu": made.nu, "ucs_MPa": made.ucs_MPa}
    config = folder / "twin.toml"
    config.write_text(campaign_text(targets))
    run = calibrate(config, "--out", folder / "out", "--workers", "1", "--json")
    stdout, stderr = run.communicate(timeout=600)
    assert run.returncode == 0, stderr
    return config, json.loads(stdout)


def test_twin_experiment_recovers_the_parameters(twin):
    _, result = twin
    found = result["identified"]
    assert result["accepted"]
    assert found["E_c"] == pytest.approx(TRUE["E_c"], rel=0.05)
    assert found["sigma_c"] == pytest.approx(TRUE["sigma_c"], rel=0.10)
    assert found["kn_ks"] == pytest.approx(TRUE["kn_ks"], rel=0.10)
    assert all(abs(e) <= result["tolerance"] for e in result["relative_errors"].values())
    assert result["dem_runs"] <= 24


def test_json_says_when_each_stage_began(twin):
    """In the order the procedure runs them, within the command's elapsed time."""
    began = twin[1]["stage_began_s"]
    assert list(began)[:2] == ["samples and checks", "verification"]  # no sensitivity section
    assert list(began.values()) == sorted(began.values())
    assert 0 < began["samples and checks"] < began["verification"] < twin[1]["elapsed_s"]


def test_killed_campaign_resumes_to_the_same_result_running_nothing_twice(twin, tmp_path):
    config, uninterrupted = twin
    out = tmp_path / "out"
    store = out / "runs.sqlite"
    run = calibrate(config, "--out", out, "--workers", "1")
    deadline = time.time() + 300
    while time.time() < deadline and run.poll() is None:
        if _stored_runs(store) >= 6:
            break
        time.sleep(0.05)
    assert run.poll() is None, "the campaign ended before it could be killed"
    run.send_signal(signal.SIGKILL)
    run.wait()
    done_before = _count(store, "SELECT COUNT(*) FROM runs")

    again = calibrate(config, "--out", out, "--workers", "1")
    assert again.wait(timeout=600) == 2  # an OUT that holds runs needs --resume
    resumed = calibrate(config, "--out", out, "--workers", "2", "--resume", "--json")
    stdout, stderr = resumed.communicate(timeout=600)
    assert resumed.returncode == 0, stderr
    result = json.loads(stdout)
    assert result["identified"] == uninterrupted["identified"]
    assert result["verified"] == uninterrupted["verified"]
    assert result["executed_runs"] == result["dem_runs"] + result["identifiability"]["runs"] - done_before
    assert set(RunStore(out).executions().values()) == {1}
    assert (out / "report.html").exists()


def test_twin_intervals_hold_the_truth_and_shrink_with_the_lab_spread(twin):
    """The twin campaign again, with a lab spread (sd a fraction of each target): at 3 % each
    interval holds the true parameter, and a third of the spread narrows E_c's, which E pins
    (narrower intervals may miss the truth by the surrogate's own error, which they leave out).
    UCS, noisy on 202 disks (sigma_c 40 gives 162 to 197 MPa), lets the surrogate see a second
    valley at kn/ks 2.9, sigma_c 58: draws land in both at either spread, so kn/ks's and
    sigma_c's intervals span both and their width is the valleys' distance, not the spread's.
    Every DEM run comes from the store. One packing: on this 202-disk specimen the model's own
    scatter between packings (nu: 85 % between two) would swamp any lab spread; that path, and
    intervals that shrink with the spread, are tested on a known model in
    tests/inverse/test_uncertainty.py."""
    from rockcal.campaign.input.config import parse_campaign
    from rockcal.campaign.plan.planned import planned
    from rockcal.campaign.runs.pool import Executor
    from rockcal.campaign.procedure.steps import calibrate

    config, result = twin
    targets = result["targets"]
    widths = []
    for fraction in (0.03, 0.01):
        spread = ", ".join(f"{r} = {fraction * v!r}" for r, v in targets.items())
        # no identifiability runs: the lab spread moves the ends of the ranges it reads
        text = config.read_text() + "[uncertainty]\ndraws = 60\npackings = 1\n[identifiability]\nruns = false\n"
        text = text.replace("[specimen]", f"spread = {{ {spread} }}\n[specimen]")
        store = RunStore(config.parent / "out")
        executor = Executor(store, workers=1)
        try:
            record = calibrate(planned(parse_campaign(text, config.parent)), executor)
        finally:
            store.close()
        assert executor.executed == 0
        intervals = record.uncertainty.intervals
        for name, truth in TRUE.items():
            assert fraction < 0.03 or intervals[name].p5 <= truth <= intervals[name].p95, name
        widths.append({n: i.p95 - i.p5 for n, i in intervals.items()})
    wide, narrow = widths
    assert narrow["E_c"] < wide["E_c"]
    assert 0.9 * TRUE["E_c"] < intervals["E_c"].p5 < intervals["E_c"].p95 < 1.1 * TRUE["E_c"]  # 1 %


def _stored_runs(store) -> int:
    """Runs in the store so far; 0 before the campaign has made its file and tables."""
    try:
        return _count(store, "SELECT COUNT(*) FROM runs") if store.exists() else 0
    except sqlite3.OperationalError:  # the file exists, its tables not yet
        return 0


def _count(store, query: str) -> int:
    db = sqlite3.connect(store, timeout=30)
    try:
        return db.execute(query).fetchone()[0]
    finally:
        db.close()
