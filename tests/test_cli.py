"""The command line: JSON output, files, and one-line errors with exit code 2."""

import json
import sys
from types import SimpleNamespace

import pytest

from rockcal.cli.app import main

SMALL = ["--width-mm", "10", "--height-mm", "20"]


@pytest.fixture
def rockcal(monkeypatch, capsys):
    """`rockcal ARGS` in this process: its exit code, stdout and stderr."""
    def run(*args):
        monkeypatch.setattr(sys, "argv", ["rockcal", *args])
        capsys.readouterr()
        with pytest.raises(SystemExit) as done:
            main()
        out = capsys.readouterr()
        return SimpleNamespace(returncode=done.value.code, stdout=out.out, stderr=out.err)
    return run


@pytest.mark.slow
def test_simulate_ucs_json_and_outputs(tmp_path, rockcal):
    run = rockcal("simulate", "ucs", *SMALL, "--set", "sigma_c=30", "--json", "--out", str(tmp_path))
    assert run.returncode == 0, run.stderr
    summary = json.loads(run.stdout)
    for key in ("E_GPa", "nu", "ucs_MPa", "peak_axial_strain", "n_particles", "n_bonds",
                "n_broken_tension", "n_broken_shear", "steps", "wall_s", "porosity",
                "coordination", "bonds_per_particle"):
        assert key in summary
    assert summary["strain"] == "gauge" and summary["contact_stiffness"] == "pfc4"
    assert summary["params"]["sigma_c"] == 30
    assert {p.name for p in tmp_path.iterdir()} >= {"ucs_curve.csv", "ucs_summary.json", "ucs_cracks.png"}


@pytest.mark.parametrize("args, field", [
    (["--set", "E_c=-5"], "E_c"),
    (["--set", "kn_ks=0"], "kn_ks"),
    (["--set", "colour=3"], "colour"),
    (["--set", "sigma_c=abc"], "sigma_c"),
    (["--set", "E_c"], "--set"),
    (["--rmin-mm", "0"], "--rmin-mm"),
    (["--rmin-mm", "-1"], "--rmin-mm"),
    (["--radius-ratio", "0.8"], "--radius-ratio"),
    (["--width-mm", "1"], "--width-mm"),
    (["--max-axial-strain", "nan"], "--max-axial-strain"),
    (["--packing", "cubic"], "--packing"),
    (["--set", "sigma_c_sd=-1"], "sigma_c_sd"),
    (["--set", "tau_c_sd=-0.5"], "tau_c_sd"),
    (["--set", "sigma_c_cv=-0.1"], "sigma_c_cv"),
    (["--set", "sigma_c_cv=0.2", "--set", "sigma_c_sd=5"], "sigma_c_cv"),
    (["--set", "phi_b=90"], "phi_b"),
    (["--set", "phi_b=-1"], "phi_b"),
    (["--set", "mcf=1.5"], "mcf"),
    (["--install-gap", "-0.1"], "--install-gap"),
    (["--cloud-porosity", "0"], "--cloud-porosity"),
    (["--cloud-porosity", "1"], "--cloud-porosity"),
    (["--pressure-mpa", "0"], "--pressure-mpa"),
    (["--strain", "laser"], "--strain"),
    (["--contact-stiffness", "pfc3"], "--contact-stiffness"),
    (["--stop-fraction", "1"], "--stop-fraction"),
    (["--threads", "0"], "--threads"),
])
def test_bad_input_is_one_line_and_exit_2(args, field, rockcal):
    assert_one_line_error(rockcal("simulate", "ucs", *SMALL, *args), field)


@pytest.mark.parametrize("args, field", [
    (["--model", "parallel_bond", "--set", "fj_emod=1"], "fj_emod"),  # a flat-joint name
    (["--model", "flatjoint", "--set", "E_c=20"], "E_c"),  # a parallel-bond name
    (["--model", "flatjoint", "--set", "fjm_B_frac=0.8", "--set", "fjm_G_frac=0.3"], "fjm_G_frac"),
    (["--model", "flatjoint", "--set", "fjm_B_frac=-0.1"], "fjm_B_frac"),
    (["--model", "flatjoint", "--set", "fj_nr=0"], "fj_nr"),
    (["--model", "flatjoint", "--set", "fj_fa=90"], "fj_fa"),
    (["--model", "flatjoint", "--set", "lnm_emod=-1"], "lnm_emod"),
    (["--model", "flatjoint_x"], "--model"),
])
def test_bad_flatjoint_input_is_one_line_and_exit_2(args, field, rockcal):
    assert_one_line_error(rockcal("simulate", "ucs", *SMALL, *args), field)


@pytest.mark.slow
def test_simulate_ucs_with_the_flat_jointed_material(rockcal):
    run = rockcal("simulate", "ucs", "--width-mm", "8", "--height-mm", "16", "--rmin-mm", "0.4",
                  "--model", "flatjoint", "--set", "fj_emod=30", "--set", "fjm_B_frac=0.9", "--json")
    assert run.returncode == 0, run.stderr
    summary = json.loads(run.stdout)
    assert summary["model"] == "flatjoint" and summary["params"]["fj_emod"] == 30
    assert summary["params"]["lnm_emod"] == 30  # the linear contacts default to the joints'
    assert summary["ucs_MPa"] > 0 and summary["n_broken_tension"] > 0


@pytest.mark.parametrize("test, args, flag", [
    ("bending", ["--length-mm", "2"], "--length-mm"),  # too short for its particles
    ("bending", ["--span-mm", "300"], "--span-mm"),
    ("brazilian", ["--diameter-mm", "1"], "--diameter-mm"),  # too small for its particles
])
def test_a_specimen_that_cannot_be_made_names_its_flag(test, args, flag, rockcal):
    assert_one_line_error(rockcal("simulate", test, *args), flag)


def assert_one_line_error(run, field: str) -> None:
    assert run.returncode == 2
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and field in lines[0], run.stderr
    assert "Traceback" not in run.stderr


def test_version(rockcal):
    import rockcal as package

    run = rockcal("--version")
    assert run.returncode == 0 and run.stdout.strip() == f"rockcal {package.__version__}"
