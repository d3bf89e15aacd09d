"""A table of broken campaign files through `rockcal calibrate` (in this process: it must stop
while checking its input): each is one line on stderr naming what is wrong, exit code 2, and
no store, folder or run made."""

import os
import sys

import pytest

from rockcal.cli.app import main
from one_line import ERROR, assert_one_line

BASE = """[rock]
name = "granite"
[targets.ucs]
E_GPa = 20.0
nu = 0.25
ucs_MPa = 40.0
[specimen]
rmin_mm = 0.4
width_mm = 8
height_mm = 16
[search]
bounds = { E_c = [10, 30], sigma_c = [20, 60] }
fixed = { mu = 0.5 }
[surrogate]
samples = 6
checks = 1
[optimizer]
iterations = 20
[acceptance]
max_dem_runs = 9
"""
SENSITIVITY = "[sensitivity]\narray = 'L16(4^5)'\nlevels = { E_c = [15, 20, 25, 30], sigma_c = [20, 30, 40, 50] }\n"
FLAT_JOINT = BASE.replace("bounds = { E_c = [10, 30], sigma_c = [20, 60] }\nfixed = { mu = 0.5 }",
                          "bounds = { fj_emod = [10, 30], fj_ten = [20, 60], fjm_B_frac = [0.5, 0.7], "
                          "fjm_G_frac = [0.1, 0.3] }\nfixed = { fjm_G_m = 0.005 }").replace("[search]", '[material]\nmodel = "flatjoint"\n[search]')
BENDING = "[targets.bending]\nK_IC_MPa_sqrt_m = 1.0\n"
BRAZILIAN = "[targets.brazilian]\nsigma_t_MPa = 9.0\n"


def edit(old: str, new: str) -> str:
    assert old in BASE, old
    return BASE.replace(old, new, 1)


def add(line: str, after: str) -> str:
    return edit(after, f"{after}\n{line}")


CASES = [  # (case, campaign file as text or bytes, the start of the message after "rockcal: error: ")
    # numbers that are not finite, named by the key as the file writes it
    ("E_GPa inf", edit("E_GPa = 20.0", "E_GPa = inf"), "targets.ucs.E_GPa: must be a finite number"),
    ("E_GPa nan", edit("E_GPa = 20.0", "E_GPa = nan"), "targets.ucs.E_GPa: must be a finite number"),
    ("ucs_MPa -inf", edit("ucs_MPa = 40.0", "ucs_MPa = -inf"), "targets.ucs.ucs_MPa: must be a finite"),
    ("nu nan", edit("nu = 0.25", "nu = nan"), "targets.ucs.nu: must be a finite number"),
    ("spread sd inf", add("spread = { E_GPa = inf }", "ucs_MPa = 40.0"), "targets.ucs.spread.E_GPa: must be a finite"),
    ("spread range to inf", add("spread = { E_GPa = [19, inf] }", "ucs_MPa = 40.0"),
     "targets.ucs.spread.E_GPa[1]: must be a finite"),
    ("weight nan", add("weights = { nu = nan }", "ucs_MPa = 40.0"), "targets.ucs.weights.nu: must be a finite"),
    ("rmin nan", edit("rmin_mm = 0.4", "rmin_mm = nan"), "specimen.rmin_mm: must be a finite"),
    ("radius ratio nan", add("radius_ratio = nan", "height_mm = 16"), "specimen.radius_ratio: must be a finite"),
    ("width inf", edit("width_mm = 8", "width_mm = inf"), "specimen.width_mm: must be a finite"),
    ("height nan", edit("height_mm = 16", "height_mm = nan"), "specimen.height_mm: must be a finite"),
    ("install gap nan", add("install_gap = nan", "height_mm = 16"), "specimen.install_gap: must be a finite"),
    ("cloud porosity nan", add("cloud_porosity = nan", "height_mm = 16"), "specimen.cloud_porosity: must be"),
    ("pressure inf", add("pressure_mpa = inf", "height_mm = 16"), "specimen.pressure_mpa: must be a finite"),
    ("stop fraction nan", add("stop_fraction = nan", "height_mm = 16"), "specimen.stop_fraction: must be"),
    ("float past double", add("install_gap = 1e400", "height_mm = 16"), "specimen.install_gap: must be a finite"),
    ("bound inf", edit("E_c = [10, 30]", "E_c = [10, inf]"), "search.bounds.E_c[1]: must be a finite"),
    ("bound nan", edit("E_c = [10, 30]", "E_c = [nan, 30]"), "search.bounds.E_c[0]: must be a finite"),
    ("fixed nan", edit("mu = 0.5", "mu = nan"), "search.fixed.mu: must be a finite"),
    ("density inf", add("density_kg_m3 = inf", 'name = "granite"'), "rock.density_kg_m3: must be a finite"),
    ("surrogate tolerance nan", add("tolerance = nan", "checks = 1"), "surrogate.tolerance: must be a finite"),
    ("acceptance tolerance nan", add("tolerance = nan", "max_dem_runs = 9"), "acceptance.tolerance: must be"),
    ("alpha inf", add("alpha = inf", "iterations = 20"), "optimizer.alpha: must be a finite"),
    ("rho nan", add("rho = nan", "iterations = 20"), "optimizer.rho: must be a finite"),
    ("sensitivity level nan", BASE + SENSITIVITY.replace("25, 30]", "25, nan]"),
     "sensitivity.levels.E_c[3]: must be a finite"),
    ("sensitivity threshold nan", BASE + SENSITIVITY + "threshold = nan\n", "sensitivity.threshold: must be"),
    ("sensitivity rmin inf", BASE + SENSITIVITY + "rmin_mm = inf\n", "sensitivity.rmin_mm: must be a finite"),
    ("Brazilian target inf", BASE + BRAZILIAN.replace("9.0", "inf"), "targets.brazilian.sigma_t_MPa: must be"),
    ("K_IC nan", BASE + BENDING.replace("1.0", "nan"), "targets.bending.K_IC_MPa_sqrt_m: must be"),
    ("lab bar diameter inf", BASE + BENDING + "diameter_mm = inf\n", "targets.bending.diameter_mm: must be"),
    # seeds and integers
    ("specimen seed -1", add("seed = -1", "height_mm = 16"), "specimen.seed: Input should be greater than"),
    ("surrogate seed -1", add("seed = -1", "checks = 1"), "surrogate.seed: Input should be greater than"),
    ("optimizer seed -5", add("seed = -5", "iterations = 20"), "optimizer.seed: Input should be greater than"),
    ("uncertainty seed -1", BASE + "[uncertainty]\nseed = -1\n", "uncertainty.seed: Input should be greater"),
    ("seed not whole", add("seed = 1.5", "height_mm = 16"), "specimen.seed: Input should be a valid integer"),
    ("seed past 64 bits", add("seed = 99999999999999999999999", "height_mm = 16"),
     "specimen.seed: 99999999999999999999999 is beyond TOML's 64-bit integers"),
    ("samples -3", edit("samples = 6", "samples = -3"), "surrogate.samples: Input should be greater"),
    ("max runs 0", edit("max_dem_runs = 9", "max_dem_runs = 0"), "acceptance.max_dem_runs: Input should be"),
    ("bending seeds 0", add("bending_seeds = 0", "height_mm = 16"), "specimen.bending_seeds: Input should be"),
    # values out of range
    ("nu 0.5", edit("nu = 0.25", "nu = 0.5"), "targets.ucs.nu: Input should be less than 0.5"),
    ("E_GPa negative", edit("E_GPa = 20.0", "E_GPa = -20.0"), "targets.ucs.E_GPa: Input should be greater"),
    ("radius ratio 20", add("radius_ratio = 20", "height_mm = 16"), "specimen.radius_ratio: Input should be"),
    ("acceptance tolerance 1.5", add("tolerance = 1.5", "max_dem_runs = 9"), "acceptance.tolerance: Input"),
    ("rmin 0", edit("rmin_mm = 0.4", "rmin_mm = 0"), "specimen.rmin_mm: Input should be greater than 0"),
    # the file itself
    ("binary bytes", bytes(range(256)), "CONFIG: "),
    ("UTF-16", BASE.encode("utf-16"), "CONFIG: "),
    ("Latin-1 rock name", BASE.replace("granite", "Granit S\xfcd").encode("latin-1"), "CONFIG: "),
    ("NUL byte", BASE.replace("[surrogate]", "\x00[surrogate]"), "CONFIG: not valid TOML"),
    ("not TOML", BASE + "[[[", "CONFIG: not valid TOML"),
    ("duplicate key", add("E_GPa = 21.0", "E_GPa = 20.0"), "CONFIG: not valid TOML"),
    ("empty file", "", "targets: Field required"),
    ("number as words", edit("E_GPa = 20.0", 'E_GPa = "twenty"'), "targets.ucs.E_GPa: Input should be a valid number"),
    ("number as a date", edit("E_GPa = 20.0", "E_GPa = 2024-01-01"), "targets.ucs.E_GPa: Input should be a valid number"),
    ("table as array", edit("fixed = { mu = 0.5 }", "fixed = [0.5]"), "search.fixed: Input should be a valid"),
    ("unknown section", BASE + "[triaxial]\nsigma3 = 10\n", "triaxial: Extra inputs are not permitted"),
    ("misspelt key", edit("rmin_mm = 0.4", "rmin_m = 0.4"),
     "specimen.rmin_m: Extra inputs are not permitted; did you mean rmin_mm?"),
    ("misspelt target", edit("ucs_MPa = 40.0", "ucs_Mpa = 40.0"),
     "targets.ucs.ucs_Mpa: Extra inputs are not permitted; did you mean ucs_MPa?"),
    ("curve is a device", add('curve = "/dev/zero"', "ucs_MPa = 40.0"), "targets.ucs.curve: /dev/zero is not a regular"),
    ("curve is a folder", add('curve = "/"', "ucs_MPa = 40.0"), "targets.ucs.curve: / is a folder"),
    # the rock's name
    ("rock name with a newline", edit('name = "granite"', 'name = "a\\nb"'), "rock.name: a rock name is one line"),
    ("rock name with an escape", edit('name = "granite"', 'name = "a\\u001b[2J"'), "rock.name: a rock name is"),
    ("rock name empty", edit('name = "granite"', 'name = ""'), "rock.name: String should have at least 1"),
    ("rock name 300 long", edit('name = "granite"', f'name = "{"x" * 300}"'), "rock.name: String should have"),
    # sizes past the grain limit, refused before any genesis
    ("rmin 0.002", edit("rmin_mm = 0.4", "rmin_mm = 0.002"), "specimen: the UCS specimen's packing"),
    ("width 1e300", edit("width_mm = 8", "width_mm = 1e300"), "specimen: the UCS specimen's packing"),
    ("beam of fine grains", BASE.replace("rmin_mm = 0.4", "rmin_mm = 0.004") + BENDING,
     "specimen: the UCS specimen's packing"),
    ("sensitivity on fine grains", BASE + SENSITIVITY + "rmin_mm = 0.001\n",
     "sensitivity.rmin_mm: the UCS specimen's packing"),
    # every specimen the plan makes, checked before the first run
    ("coarse specimen too small", add("coarse_samples = 4\ncoarse_factor = 4", "checks = 1"),
     "surrogate.coarse_factor: at R_min 1.6 mm the UCS specimen cannot be made: specimen.width_mm"),
    ("sensitivity specimen too small", BASE + SENSITIVITY + "rmin_mm = 1.5\n",
     "sensitivity.rmin_mm: at R_min 1.5 mm the UCS specimen cannot be made"),
    # work and memory bounded, in the run budget's terms
    ("a million samples", edit("samples = 6", "samples = 1000000"), "surrogate.samples: Input should be less"),
    ("samples past the budget", edit("samples = 6", "samples = 9"),
     "surrogate.samples: 9 samples and 1 checks are more DEM runs than the budget of 9"),
    ("a billion ants", add("ants = 1000000000", "iterations = 20"), "optimizer.ants: Input should be less"),
    ("ants x iterations", add("ants = 10000", "iterations = 20").replace("iterations = 20", "iterations = 101"),
     "optimizer.iterations: ants x iterations = 1,010,000 surrogate evaluations per search"),
    ("huge budget", edit("max_dem_runs = 9", "max_dem_runs = 9223372036854775807"), "acceptance.max_dem_runs"),
    ("huge draws", BASE + "[uncertainty]\ndraws = 10000000\n", "uncertainty.draws: Input should be less"),
    ("huge packings", BASE + "[uncertainty]\npackings = 1000\n", "uncertainty.packings: Input should be less"),
    ("huge target packings", add("packings = 1000", "ucs_MPa = 40.0"), "targets.ucs.packings: Input should be"),
    ("5000 samples", edit("samples = 6", "samples = 5000").replace("max_dem_runs = 9", "max_dem_runs = 5000"),
     "surrogate.samples: Input should be less than or equal to 1000"),
    ("draws x ants x iterations", add("ants = 1000", "iterations = 20").replace("iterations = 20", "iterations = 1000")
     + "[uncertainty]\nenabled = true\ndraws = 10000\n", "uncertainty.draws: 10,000 draws x 1,000,000 evaluations"),
    ("candidates x ants x iterations", add("ants = 1000", "iterations = 20").replace("iterations = 20", "iterations = 1000")
     .replace("max_dem_runs = 9", "max_dem_runs = 90\ncandidates = 80"), "acceptance.candidates: 80 candidates x 2"),
    ("candidates past any budget", edit("max_dem_runs = 9", "max_dem_runs = 9\ncandidates = 9223372036854775807"),
     "acceptance.candidates: Input should be less"),
    ("a long series of confinements", edit("[specimen]", "[targets.biaxial]\nconfinement_mpa = ["
                                           + ", ".join(str(k) for k in range(21)) + "]\nphi_deg = 40.0\n[specimen]"),
     "targets.biaxial.confinement_mpa: at most 20 confinements"),
    ("budget x a long series x packings", edit("[specimen]", "[targets.biaxial]\nconfinement_mpa = [0, 5, 10, 20]\n"
                                               "phi_deg = 40.0\npackings = 100\n[specimen]")
     .replace("max_dem_runs = 9", "max_dem_runs = 50"), "acceptance.max_dem_runs: 50 parameter sets x 401 DEM runs each"),
    ("uncertainty packings x target packings", add("packings = 100", "ucs_MPa = 40.0")
     .replace("max_dem_runs = 9", "max_dem_runs = 150") + "[uncertainty]\nenabled = true\npackings = 100\n",
     "uncertainty.packings: 150 parameter sets and 100 packings x 100 DEM runs each"),
    # checks that would fail after DEM runs, made before them
    ("samples too few for the searched", edit("samples = 6", "samples = 4").replace(
        "sigma_c = [20, 60] }", "sigma_c = [20, 60], kn_ks = [1, 3] }"),
     "surrogate.samples: 4 samples are too few for a surrogate of 3 searched parameters (search.bounds); at least 5"),
    ("coarse samples too few", add("coarse_samples = 3", "checks = 1"),
     "surrogate.coarse_samples: 3 coarse samples are too few for a surrogate of 2 searched parameters"),
    ("the other material's parameter searched", edit("E_c = [10, 30]", "fj_emod = [10, 30]"),
     "search.bounds.fj_emod: a parameter of the flatjoint material, not of parallel_bond: choose material.model"),
    ("the other material's parameter fixed", edit("mu = 0.5", "fj_nr = 3"),
     "search.fixed.fj_nr: a parameter of the flatjoint material"),
    ("the other material's parameter levelled", FLAT_JOINT + "[sensitivity]\narray = 'L4(2^3)'\n"
     "levels = { E_c = [10, 30], fj_kratio = [1, 2] }\n", "sensitivity.levels.E_c: a parameter of the parallel_bond"),
    ("middle level invalid", BASE.replace("bounds = { E_c = [10, 30], sigma_c = [20, 60] }\n", "")
     + "[sensitivity]\narray = 'L4(2^3)'\nlevels = { E_c = [-10, 5], kn_ks = [1, 2] }\n",
     "sensitivity.levels.E_c: Input should be greater than or equal to 0, at the middle levels"),
    ("flat-joint middle level invalid", FLAT_JOINT.replace(
        "bounds = { fj_emod = [10, 30], fj_ten = [20, 60], fjm_B_frac = [0.5, 0.7], fjm_G_frac = [0.1, 0.3] }\n", "")
     + "[sensitivity]\narray = 'L4(2^3)'\nlevels = { fj_emod = [-10, 5], fj_kratio = [1, 2] }\n",
     "sensitivity.levels.fj_emod: Input should be greater than 0, at the middle levels"),
    # targets and the search box
    ("empty target section", BASE + "[targets.direct_tension]\n",
     "targets.direct_tension: no lab value given; give at least one of sigma_t_direct_MPa"),
    ("a whole number's bounds not whole", FLAT_JOINT.replace("fj_ten = [20, 60]", "fj_nr = [1.5, 4]"),
     "search.bounds.fj_nr: a whole number"),
    ("a code searched", FLAT_JOINT.replace("fj_ten = [20, 60]", "fjm_rmulCode = [0, 2]"),
     "search.bounds.fjm_rmulCode: a whole number"),
    ("fractions past 1 at a corner", FLAT_JOINT.replace("0.3] }", "0.35] }"),
     "search.bounds.fjm_G_frac: fjm_B_frac + fjm_G_frac = 1.05 exceeds 1"),
    ("levels unlike the array", BASE + "[sensitivity]\narray = 'L4(2^3)'\nlevels = { E_c = [15, 20, 25] }\n",
     "sensitivity.levels.E_c: L4(2^3) has no free column with 3 levels"),
]
DEFAULT_FOLDER = [  # (case, rock name): no --out, so the name would pick the folder
    ("parent", "../../x"), ("absolute", "/tmp/x"), ("dot", "."), ("two dots", ".."), ("slash", "a/b"),
    ("backslash", "a\\\\b"), ("hidden", ".x"), ("rich markup", "[/]"),
]


def run_cli(args, monkeypatch, capsys) -> tuple[int, str]:
    monkeypatch.setattr(sys, "argv", ["rockcal", *map(str, args)])
    with pytest.raises(SystemExit) as exit:
        main()
    return exit.value.code, capsys.readouterr().err


def test_the_table_is_large():
    assert len(CASES) + len(DEFAULT_FOLDER) >= 60


@pytest.mark.parametrize("text, message", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_a_broken_campaign_file(text, message, tmp_path, monkeypatch, capsys):
    config = tmp_path / "campaign.toml"
    config.write_bytes(text if isinstance(text, bytes) else text.encode())
    code, stderr = run_cli(["calibrate", config, "--out", tmp_path / "out", "--workers", "1"], monkeypatch, capsys)
    assert_one_line(code, stderr, ERROR + message)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("rock", [c[1] for c in DEFAULT_FOLDER], ids=[c[0] for c in DEFAULT_FOLDER])
def test_a_rock_name_that_is_not_a_folder_name_needs_out(rock, tmp_path, monkeypatch, capsys):
    (tmp_path / "campaign.toml").write_text(edit('name = "granite"', f'name = "{rock}"'))
    monkeypatch.chdir(tmp_path)
    code, stderr = run_cli(["calibrate", "campaign.toml", "--workers", "1"], monkeypatch, capsys)
    assert_one_line(code, stderr, ERROR + "rock.name: ")
    assert "give --out" in stderr
    assert list(tmp_path.iterdir()) == [tmp_path / "campaign.toml"]


def test_fractions_searched_together_are_checked_on_the_box_not_against_defaults(tmp_path, monkeypatch, capsys):
    """B in [0.5, 0.7] and G in [0.1, 0.3] never sum past 1, though G's 0.3 does with the default B 1."""
    config = tmp_path / "campaign.toml"
    config.write_text(FLAT_JOINT)
    code, stderr = run_cli(["calibrate", config, "--out", tmp_path / "out", "--dry-run", "--json"], monkeypatch, capsys)
    assert code == 0, stderr
    assert not (tmp_path / "out").exists()


def test_a_quick_look_too_coarse_for_the_specimen_is_refused_before_any_run(tmp_path, monkeypatch, capsys):
    config = tmp_path / "campaign.toml"
    config.write_text(BASE)
    code, stderr = run_cli(["calibrate", config, "--quick", "--out", tmp_path / "out"], monkeypatch, capsys)
    assert_one_line(code, stderr, ERROR + "--quick: at R_min 0.8 mm the UCS specimen cannot be made: specimen.width_mm")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("args, message", [
    (["--workers", "9223372036854775807"], "--workers: Input should be less than or equal to 256"),
    (["--scheduler", "local:99999999999999999999"], "--scheduler: local:N needs 1 to 256 workers"),
], ids=["workers", "local workers"])
def test_worker_counts_are_bounded(args, message, tmp_path, monkeypatch, capsys):
    config = tmp_path / "campaign.toml"
    config.write_text(BASE)
    code, stderr = run_cli(["calibrate", config, "--out", tmp_path / "out", *args], monkeypatch, capsys)
    assert_one_line(code, stderr, ERROR + message)
    assert not (tmp_path / "out").exists()


def test_a_pipe_as_the_campaign_file_is_refused_not_waited_on(tmp_path, monkeypatch, capsys):
    fifo = tmp_path / "campaign.toml"
    os.mkfifo(fifo)
    code, stderr = run_cli(["calibrate", fifo, "--dry-run"], monkeypatch, capsys)
    assert_one_line(code, stderr, ERROR + f"CONFIG: {fifo} is not a regular file")
