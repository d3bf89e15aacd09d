"""A twin experiment on joint targets: UCS (E, nu, UCS) and Brazilian (sigma_t) targets made by
the engine at known E_c, kn/ks, sigma_c and tau_c, all four recovered by `rockcal calibrate`.

With tau_c 1.5 x sigma_c the two tests see the two bond strengths differently, though on this
202-disk specimen sigma_c only faintly (UCS revision 3): a 10 % change of sigma_c moves the UCS
by -1.7 % / +3.8 % and sigma_t by -1.6 % / +0.8 %, one of tau_c moves the UCS by -3.8 % / +7.7 %
(and sigma_t by -6 % / +8 %: the disk crushes under the platens). The 290-disk
sigma_t is rough near the truth: verified points within 4 % of it in every parameter gave
sigma_t 0.5-0.7 % off, so a tolerance below 1 % is met by luck, after a number of rounds that
depends on the search's path (which follows the BLAS kernel's round-off:
docs/concepts/reproducibility.md). By the sensitivities above, targets met within 1 % pin E_c,
kn/ks and tau_c down within 5 %, sigma_c only within about 15 % (a point with sigma_c 8 % low
and tau_c 2 % high matches all four within 0.5 %). Nearer tau_c = sigma_c both tests follow
tau_c alike and sigma_c is barely seen at all.
"""

import json
import sqlite3
import subprocess
import sys

import pytest

import rockcal
from rockcal.labtests.brazilian import brazilian_disk, simulate_brazilian

pytestmark = pytest.mark.slow  # DEM runs and specimens of minutes: deselect with -m "not slow"

TRUE = {"E_c": 20.0, "kn_ks": 2.0, "sigma_c": 30.0, "tau_c": 45.0}
RECOVERED_WITHIN = {"E_c": 0.05, "kn_ks": 0.05, "sigma_c": 0.15, "tau_c": 0.05}  # see above
FIXED = {"mu": 0.5}
# the UCS specimen of tests/campaign/test_calibrate.py (202 disks) and a 20 mm disk (290 disks)
SPECIMEN = {"rmin_mm": 0.4, "width_mm": 10.0, "height_mm": 20.0, "seed": 2, "disk_diameter_mm": 20.0}


def campaign_text(ucs, sigma_t_MPa: float) -> str:
    specimen = "\n".join(f"{k} = {v}" for k, v in SPECIMEN.items())
    return f"""
[targets.ucs]
E_GPa = {ucs.E_GPa!r}
nu = {ucs.nu!r}
ucs_MPa = {ucs.ucs_MPa!r}
[targets.brazilian]
sigma_t_MPa = {sigma_t_MPa!r}
[specimen]
{specimen}
[search]
bounds = {{ E_c = [10, 30], kn_ks = [1, 3], sigma_c = [20, 40], tau_c = [35, 55] }}
fixed = {{ mu = {FIXED["mu"]} }}
[surrogate]
samples = 16
checks = 2
[optimizer]
iterations = 60
[acceptance]
tolerance = 0.01
max_dem_runs = 40
[identifiability]
runs = false
"""


@pytest.fixture(scope="module")
def twin(tmp_path_factory):
    """The campaign's --json output and its folder."""
    folder = tmp_path_factory.mktemp("joint")
    s = SPECIMEN
    ucs = rockcal.simulate_ucs(TRUE | FIXED, rockcal.random_packing(s["width_mm"], s["height_mm"],
                                                                    s["rmin_mm"], seed=s["seed"]))
    disk = brazilian_disk(s["disk_diameter_mm"], s["rmin_mm"], seed=s["seed"])
    sigma_t = float(simulate_brazilian(TRUE | FIXED, disk).sigma_t_MPa)
    config = folder / "joint.toml"
    config.write_text(campaign_text(ucs, sigma_t))
    run = subprocess.run([sys.executable, "-m", "rockcal", "calibrate", str(config), "--out",
                          str(folder / "out"), "--workers", "1", "--json"],
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout), folder / "out"


def test_ucs_and_brazilian_targets_recover_all_four_parameters(twin):
    result, _ = twin
    assert result["accepted"]
    for name, truth in TRUE.items():
        assert result["identified"][name] == pytest.approx(truth, rel=RECOVERED_WITHIN[name]), name
    assert result["target_tests"] == {"ucs": ["E_GPa", "nu", "ucs_MPa"], "brazilian": ["sigma_t_MPa"]}
    assert set(result["relative_errors"]) == {"E_GPa", "nu", "ucs_MPa", "sigma_t_MPa"}
    assert all(abs(e) <= result["tolerance"] for e in result["relative_errors"].values())


def test_every_parameter_set_ran_both_tests_and_the_report_shows_each(twin):
    result, out = twin
    db = sqlite3.connect(out / "runs.sqlite")
    try:
        kinds = dict(db.execute("SELECT kind, COUNT(*) FROM runs GROUP BY kind").fetchall())
    finally:
        db.close()
    # every parameter set ran the disk but the verified points that missed on UCS: the disk
    # costs more than this UCS prism, so a round runs the UCS test first ([acceptance] ucs_first)
    record = json.loads((out / "record.json").read_text(encoding="utf-8"))
    missed = sum("sigma_t_MPa" not in (it["errors"] or {}) for it in record["iterations"])
    assert kinds == {"ucs": result["dem_runs"], "brazilian": result["dem_runs"] - missed}
    page = (out / "report.html").read_text(encoding="utf-8")
    error = result["relative_errors"]["sigma_t_MPa"]
    assert f"<td>Brazilian</td><td>sigma_t_MPa</td><td>{result['targets']['sigma_t_MPa']:.4g}</td>" in page
    assert f"{100 * error:+.1f} %" in page and "disk D 20 mm" in page
