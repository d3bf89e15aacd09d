"""The command line: JSON output, files, and one-line errors with exit code 2."""

import json
import sys
from types import SimpleNamespace

import pytest

from rockcal.cli.app import main
from one_line import assert_one_line

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


def test_simulate_direct_tension_with_two_pebble_grains(rockcal):
    run = rockcal("simulate", "direct-tension", "--grain-shape", "two-pebble", "--width-mm", "10",
                  "--height-mm", "20", "--rmin-mm", "0.5", "--radius-ratio", "1.25", "--json")
    assert run.returncode == 0, run.stderr
    summary = json.loads(run.stdout)
    assert summary["n_particles"] == 2 * summary["n_grains"]
    assert "two-pebble clumps" in summary["specimen"] and summary["sigma_t_direct_MPa"] > 0


@pytest.mark.parametrize("test, args, flag", [
    ("bending", ["--length-mm", "2"], "--length-mm"),  # too short for its particles
    ("bending", ["--span-mm", "300"], "--span-mm"),
    ("brazilian", ["--diameter-mm", "1"], "--diameter-mm"),  # too small for its particles
])
def test_a_specimen_that_cannot_be_made_names_its_flag(test, args, flag, rockcal):
    assert_one_line_error(rockcal("simulate", test, *args), flag)


def assert_one_line_error(run, field: str) -> None:
    assert_one_line(run.returncode, run.stderr, "", field)


def test_version(rockcal):
    import rockcal as package

    run = rockcal("--version")
    assert run.returncode == 0 and run.stdout.strip() == f"rockcal {package.__version__}"


def test_commands_are_added_once_however_often_main_runs(rockcal):
    """A process may run `main` many times (a notebook, the tests): each command is added once."""
    from rockcal.cli.app import app

    for _ in range(3):
        assert rockcal("--version").returncode == 0
    names = [c.name for c in app.registered_commands] + [g.name for g in app.registered_groups]
    assert len(names) == len(set(names)) == 7



# `rockcal simulate` checks every input before the run: bad input is one line naming the option
# and exit 2 (a confinement the servo cannot hold, an empty or repeated entry in a list, a grip
# that holds no grain rows, a grain finer than any rock's or a cloud of a few grains, a
# specimen with no bonded element, too many packings); a run whose physics fails is one line
# and exit 1; a reading no elastic solid gives is a warning line on stderr.

PRISM = ["--width-mm", "8", "--height-mm", "16", "--rmin-mm", "0.4"]
HUGE = "99999999999999999999999999"


def one_line(run, code: int, start: str, *words: str) -> None:
    assert_one_line(run.returncode, run.stderr, start, *words, exit_code=code)


@pytest.mark.parametrize("test, args, flag, words", [
    ("biaxial", ["--confinement-mpa", "1e-12"], "--confinement-mpa", ("at least 0.1 MPa", "1e-12")),
    ("biaxial", ["--confinement-mpa", "0,0.05"], "--confinement-mpa", ("at least 0.1 MPa", "0.05")),
    ("biaxial", ["--confinement-mpa", "0,,5"], "--confinement-mpa", ("entry 2", "'0,,5'")),
    ("biaxial", ["--confinement-mpa", "0,5,"], "--confinement-mpa", ("entry 3",)),
    ("biaxial", ["--confinement-mpa", ""], "--confinement-mpa", ("entry 1",)),
    ("biaxial", ["--confinement-mpa", "0,5,5.0"], "--confinement-mpa", ("5 MPa is given 2 times",)),
    ("biaxial", ["--confinement-mpa", "nan"], "--confinement-mpa", ()),
    ("biaxial", ["--confinement-mpa", "1e300"], "--confinement-mpa", ()),
    ("direct-tension", ["--grip-fraction", "1e-9"], "--grip-fraction", ("one mean grain diameter", "0.0663")),
    ("direct-tension", ["--grip-fraction", "0.05"], "--grip-fraction", ("two rows of grains",)),
    ("ucs", ["--rmin-mm", "1e-300"], "--rmin-mm", ("at least 0.001 mm",)),
    ("ucs", ["--packing", "hexagonal", "--rmin-mm", "1e-300"], "--rmin-mm", ()),
    ("ucs", ["--seeds", HUGE], "--seeds", ("[1, 100]",)),
    ("ucs", ["--seeds", "101"], "--seeds", ()),
    ("ucs", ["--threads", HUGE], "--threads", ()),
    ("ucs", ["--width-mm", "1e300"], "specimen", ("grains",)),
    ("ucs", ["--set", "Ebar_c=0"], "Ebar_c", ("no bonded element",)),
    ("ucs", ["--model", "flatjoint", "--set", "fjm_B_frac=0"], "fjm_B_frac", ("every flat joint slit",)),
    ("ucs", ["--model", "flatjoint", "--set", "fjm_B_frac=0", "--set", "fjm_G_frac=0.5"], "fjm_B_frac",
     ("slit or gapped",)),
    ("ucs", ["--model", "flatjoint", "--set", "fj_ten=0", "--set", "fj_coh=0"], "fj_coh", ()),
])
def test_bad_input_is_refused_before_the_run(test, args, flag, words, rockcal):
    base = [a for pair in zip(PRISM[::2], PRISM[1::2]) if pair[0] not in args for a in pair]
    one_line(rockcal("simulate", test, *base, *args), 2, f"rockcal: error: {flag}", *words)


@pytest.mark.parametrize("test, args", [
    ("brazilian", ["--diameter-mm", "10", "--rmin-mm", "1e-300"]),
    ("bending", ["--length-mm", "44", "--height-mm", "10", "--notch-mm", "3.6", "--notch-width-mm", "0.8",
                 "--span-mm", "32", "--rmin-mm", "1e-300"]),
])
def test_a_grain_finer_than_a_rocks_is_refused_by_every_test(test, args, rockcal):
    one_line(rockcal("simulate", test, *args), 2, "rockcal: error: --rmin-mm", "1 µm")


def test_a_specimen_that_is_no_solid_is_warned_of(rockcal):
    """A flat-jointed prism with one bonded joint in a thousand: nu 9.48 at half its peak."""
    run = rockcal("simulate", "ucs", *PRISM, "--model", "flatjoint", "--set", "fjm_B_frac=0.001", "--json")
    assert run.returncode == 0, run.stderr
    warnings = [line for line in run.stderr.splitlines() if line.startswith("rockcal: warning: ")]
    assert len(warnings) == 2 and "nu = 9.479 is outside (-1, 1)" in warnings[0], run.stderr
    assert "no bond broke" in warnings[1] and json.loads(run.stdout)["failed"] is False


def test_a_seating_that_does_not_settle_is_a_failed_run(rockcal, monkeypatch):
    monkeypatch.setattr("rockcal.labtests.rig.sides.SEATING_ROUNDS", 1)
    one_line(rockcal("simulate", "biaxial", *PRISM, "--confinement-mpa", "5"), 1,
             "rockcal: run failed: confined compression test: the specimen did not settle at the "
             "confinement of 5 MPa", "try another confinement")


def test_a_curve_too_short_to_read_is_a_failed_run(rockcal):
    one_line(rockcal("simulate", "ucs", *PRISM, "--max-axial-strain", "1e-300"), 1,
             "rockcal: run failed: UCS test: the compression curve has fewer than two readings",
             "try a larger maximum axial strain")


@pytest.mark.parametrize("test, args", [
    ("ucs", ["--width-mm", "5", "--height-mm", "10"]),
    ("direct-tension", ["--width-mm", "5", "--height-mm", "10"]),
    ("brazilian", ["--diameter-mm", "10"]),
    ("bending", ["--length-mm", "22", "--height-mm", "5", "--notch-mm", "1.8", "--notch-width-mm", "0.2",
                 "--span-mm", "16"]),
])
def test_a_grain_cloud_of_a_few_grains_is_refused_before_the_genesis(test, args, rockcal):
    """A cloud porosity of 0.99 leaves one or two grains (no gauge, platen or pin has a grain
    to read or load); 0.9999999 none."""
    for porosity in ("0.99", "0.9999999"):
        one_line(rockcal("simulate", test, *args, "--cloud-porosity", porosity), 2,
                 f"rockcal: error: --cloud-porosity: a cloud porosity of {porosity} leaves about",
                 "fewer than 16 (4 grains across)")
