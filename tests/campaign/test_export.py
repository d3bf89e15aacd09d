"""`rockcal export` and `export-specimen`: every unit conversion checked by reading the file
back, and bad input as one line with exit code 2."""

import csv
import json
import re
import runpy
import subprocess
import sys

import numpy as np
import pytest

from rockcal.campaign.runs.store import RunStore
from rockcal.specimens.genesis import Genesis
from rockcal.specimens.specimen import random_packing
from rockcal.materials.parallel_bond import bond_strengths
from rockcal.params import make_params

pytestmark = pytest.mark.slow  # a small calibration campaign, then the rockcal command in a new process

IDENTIFIED = {"E_c": 21.65, "kn_ks": 1.9, "sigma_c": 36.55, "sigma_c_cv": 0.2, "tau_c": 90.0,
              "tau_c_sd": 15.0, "phi_b": 12.0, "mcf": 0.8, "mu": 0.5, "density": 2622.0}
CAMPAIGN = """
[rock]
name = "twin"
density_kg_m3 = 2622
[targets.ucs]
E_GPa = 41.5
[specimen]
rmin_mm = 0.4
radius_ratio = 1.5
width_mm = 8
height_mm = 16
install_gap = 0.5
cloud_porosity = 0.1
pressure_mpa = 0.2
[search]
bounds = { E_c = [10, 30] }
"""
# The same material in PFC's SI units, written out by hand.
EXPECTED = {"pbm_emod": 21.65e9, "pbm_krat": 1.9, "pbm_fric": 0.5, "pbm_bemod": 21.65e9,
            "pbm_bkrat": 1.9, "pbm_rmul": 1.0, "pbm_mcf": 0.8, "pbm_ten_m": 36.55e6,
            "pbm_ten_sd": 7.31e6, "pbm_coh_m": 90e6, "pbm_coh_sd": 15e6, "pbm_fa": 12.0,
            "pbm_igap": 0.2e-3, "cm_Dlo": 0.8e-3, "cm_Dup": 1.2e-3, "cm_densityVal": 2622.0,
            "cm_localDampFac": 0.7, "pk_seed": 10001, "pk_Pm": 0.2e6, "pk_nc": 0.1, "cm_matType": 2,
            "cm_densityCode": 0, "cm_shape": 0, "cm_Dmult": 1.0, "cm_nSD": 1, "cm_typeSD": 0, "cm_Vfrac": 1.0, "pk_procCode": 1,
            "lnm_emod": 21.65e9, "lnm_krat": 1.9, "lnm_fric": 0.5}


def rockcal(*args):
    return subprocess.run([sys.executable, "-m", "rockcal", *map(str, args)], capture_output=True,
                          text=True)


@pytest.fixture(scope="module")
def finished(tmp_path_factory, save_finished):
    """A store holding a finished campaign's documents (what `calibrate` writes at its end)."""
    return save_finished(tmp_path_factory.mktemp("campaign"), CAMPAIGN, make_params(IDENTIFIED), {"E_c": 21.65},
                         uncertainty={"seeds": [1], "run_keys": [], "packing_responses": [], "scatter": {},
                                      "spread": {}, "draws": 10, "samples": [], "drawn_targets": {},
                                      "intervals": {"E_c": {"p5": 20.9, "p50": 21.6, "p95": 22.4,
                                                            "at_bound": 0.0, "pinned": True}}})

def check(values: dict) -> None:
    assert values.pop("cm_matName", "rockcal_parallel_bond") == "rockcal_parallel_bond"
    assert set(values) == set(EXPECTED)
    for name, value in EXPECTED.items():
        assert values[name] == pytest.approx(value, rel=1e-12), name


def test_fish_file_reads_back_in_si(finished, tmp_path):
    path = tmp_path / "mpParams.p2dat"
    run = rockcal("export", finished, "--format", "pfc-fish", "--to", path)
    assert run.returncode == 0, run.stderr
    text = path.read_text()
    assert re.search(r"^def mpSetPBParams$", text, re.M) and "; rockcal calibration of twin" in text
    assert ";   E_c: 5-95 % interval 20.9 to 22.4" in text
    values = {m[0]: float(m[1]) for m in re.findall(r"^\s+(\w+)(?:\(1\))? = ([-+0-9.e]+)", text, re.M)}
    assert re.search(r"^  cm_matName = 'rockcal_parallel_bond'$", text, re.M) and text.endswith("@_mpCheckAllParams\n")
    check(values)


def test_python_script_reads_back_in_si(finished, tmp_path):
    path = tmp_path / "params.py"
    assert rockcal("export", finished, "--format", "pfc-python", "--to", path).returncode == 0
    check(runpy.run_path(str(path))["PARAMETERS"])


def test_json_to_stdout_reads_back_in_si(finished):
    run = rockcal("export", finished, "--format", "json")
    assert run.returncode == 0, run.stderr
    data = json.loads(run.stdout)
    check(data["parameters"])
    assert data["units"]["pbm_emod"] == "Pa" and data["origin"]["accepted"] is True


def test_specimen_lists_read_back(finished, tmp_path):
    run = rockcal("export-specimen", finished, "--to", tmp_path / "spec")
    assert run.returncode == 0, run.stderr
    with open(tmp_path / "spec" / "balls.csv") as f:
        balls = np.array([[float(v) for v in row] for row in list(csv.reader(f))[1:]])
    with open(tmp_path / "spec" / "bonds.csv") as f:
        bonds = np.array([[float(v) for v in row] for row in list(csv.reader(f))[1:]])
    specimen = random_packing(8, 16, 0.4, 1.5, 1, Genesis(install_gap=0.5, cloud_porosity=0.1,
                                                           pressure_mpa=0.2))
    np.testing.assert_array_equal(balls[:, 0], np.arange(1, specimen.n_particles + 1))
    np.testing.assert_array_equal(balls[:, 1:3], specimen.pos)
    np.testing.assert_array_equal(balls[:, 3], specimen.radius)
    np.testing.assert_array_equal(bonds[:, :2] - 1, specimen.bonds)
    ten, coh = bond_strengths(make_params(IDENTIFIED), specimen.bond_draws, len(specimen.bonds))
    np.testing.assert_array_equal(bonds[:, 2], ten)
    np.testing.assert_array_equal(bonds[:, 3], coh)


@pytest.mark.parametrize("args, field", [
    (["export", "{empty}"], "OUT"),
    (["export", "{unfinished}"], "OUT"),
    (["export-specimen", "{unfinished}"], "OUT"),
    (["export", "{finished}", "--format", "pfc-cpp"], "--format"),
    (["export", "{finished}", "--to", "{finished}/no/such/dir/x.dat"], "--to"),
    (["export-specimen", "{finished}", "--to", "{finished}/runs.sqlite"], "--to"),
])
def test_bad_input_is_one_line_exit_2(finished, tmp_path, args, field):
    unfinished = tmp_path / "unfinished"
    RunStore(unfinished).close()
    (tmp_path / "empty").mkdir()
    names = {"finished": finished, "unfinished": unfinished, "empty": tmp_path / "empty"}
    run = rockcal(*[a.format(**names) for a in args])
    assert run.returncode == 2
    assert len(run.stderr.strip().splitlines()) == 1 and field in run.stderr
    assert RunStore(finished, create=False).document("record.json")  # nothing lost

