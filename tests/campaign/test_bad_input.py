"""Bad input through the real CLI: a broken campaign file, option or store file gets one line
on stderr naming what is wrong, exit code 2, no traceback, and leaves the store as it was.

Every case must fail while the input is validated, before any forward run: the sweep is fast.
"""

import hashlib
import shutil
import sqlite3
import sys

import pytest

from rockcal.campaign.input.config import SpecimenSettings
from rockcal.campaign.runs.pool import Executor
from rockcal.campaign.runs.spec import run_spec
from rockcal.campaign.runs.store import SCHEMA_VERSION, STORE_NAME, RunStore
from rockcal.cli.app import main
from one_line import ERROR, assert_one_line

pytestmark = pytest.mark.slow  # each case runs the rockcal command in a new process

CAMPAIGN = """
[targets.ucs]
E_GPa = 20.0
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
CURVES = {
    "text.csv": "strain,stress_MPa\n0,0\n0.001,abc\n0.002,20\n0.003,30\n",
    "nan.csv": "0,0\n0.001,nan\n0.002,20\n0.003,30\n",
    "decreasing.csv": "0,0\n0.002,10\n0.001,20\n0.003,30\n",
}


def edit(old: str, new: str) -> str:
    assert old in CAMPAIGN
    return CAMPAIGN.replace(old, new)


def with_curve(name: str) -> str:
    return edit("ucs_MPa = 40.0", f"ucs_MPa = 40.0\ncurve = {name!r}")


CAMPAIGNS = [  # (case, campaign text, the key the error must name)
    ("no UCS targets", edit("[targets.ucs]\nE_GPa = 20.0\nucs_MPa = 40.0",
                            "[targets.bending]\nK_IC_MPa_sqrt_m = 1.0"), "targets.ucs"),
    ("UCS target with no response", edit("E_GPa = 20.0\nucs_MPa = 40.0", ""), "targets.ucs"),
    ("inverted bounds", edit("E_c = [10, 30]", "E_c = [30, 10]"), "search.bounds.E_c"),
    ("unknown top-level key", "colour = 'grey'\n" + CAMPAIGN, "colour"),
    ("unknown nested key", edit("samples = 6", "sampels = 6"), "surrogate.sampels"),
    ("acceptance tolerance 0", CAMPAIGN + "tolerance = 0\n", "acceptance.tolerance"),
    ("negative surrogate tolerance", edit("checks = 1", "checks = 1\ntolerance = -0.05"),
     "surrogate.tolerance"),
    ("samples 0", edit("samples = 6", "samples = 0"), "surrogate.samples"),
    ("curve with text", with_curve("text.csv"), "targets.ucs.curve"),
    ("curve with NaN", with_curve("nan.csv"), "targets.ucs.curve"),
    ("curve with decreasing strain", with_curve("decreasing.csv"), "targets.ucs.curve"),
    ("curve file missing", with_curve("missing.csv"), "targets.ucs.curve"),
    ("bound not a number", edit("E_c = [10, 30]", 'E_c = ["ten", 30]'), "search.bounds.E_c"),
    ("negative bound", edit("E_c = [10, 30]", "E_c = [-10, 30]"), "search.bounds.E_c"),
    ("unknown parameter", edit("E_c = [10, 30]", "E_cc = [10, 30]"), "search.bounds.E_cc"),
    ("fixed value out of range", edit("mu = 0.5", "mu = -1"), "search.fixed.mu"),
    ("a flat-joint parameter with the parallel bond", edit("mu = 0.5", "mu = 0.5, fj_emod = 30"),
     "search.fixed.fj_emod"),
    ("flat joints bonded and gapped over 1", "[material]\nmodel = 'flatjoint'\n" + edit(
        "bounds = { E_c = [10, 30], sigma_c = [20, 60] }\nfixed = { mu = 0.5 }",
        "bounds = { fj_emod = [10, 30], fj_ten = [20, 60] }\n"
        "fixed = { fjm_B_frac = 0.8, fjm_G_frac = 0.3 }"), "search.fixed.fjm_G_frac"),
    ("a parallel-bond bound with the flat joint", "[material]\nmodel = 'flatjoint'\n" + CAMPAIGN,
     "search.bounds.E_c"),
    ("beam too short for its particles", edit("[specimen]", "[targets.bending]\nK_IC_MPa_sqrt_m = 1.0\n"
                                               "[specimen]\nbeam_length_mm = 4"), "specimen.beam_length_mm"),
    ("span longer than the beam", edit("[specimen]", "[targets.bending]\nK_IC_MPa_sqrt_m = 1.0\n"
                                       "[specimen]\nspan_mm = 300"), "specimen.span_mm"),
    ("specimen narrower than its particles", edit("width_mm = 8", "width_mm = 2"),
     "specimen.width_mm"),
    ("not TOML", CAMPAIGN + "[[[", "CONFIG"),
    ("negative installation gap", edit("height_mm = 16", "height_mm = 16\ninstall_gap = -0.5"),
     "specimen.install_gap"),
    ("cloud porosity 1", edit("height_mm = 16", "height_mm = 16\ncloud_porosity = 1.0"),
     "specimen.cloud_porosity"),
    ("pressure 0", edit("height_mm = 16", "height_mm = 16\npressure_mpa = 0"),
     "specimen.pressure_mpa"),
    ("unknown strain reading", edit("height_mm = 16", "height_mm = 16\nstrain = 'laser'"),
     "specimen.strain"),
    ("unknown contact stiffness", edit("height_mm = 16", "height_mm = 16\ncontact_stiffness = 'pfc3'"),
     "specimen.contact_stiffness"),
    ("negative strength sd", edit("mu = 0.5", "mu = 0.5, sigma_c_sd = -3"),
     "search.fixed.sigma_c_sd"),
    ("bond friction angle 90", edit("mu = 0.5", "mu = 0.5, phi_b = 90"), "search.fixed.phi_b"),
    ("sd and cv of one strength", edit("mu = 0.5", "mu = 0.5, sigma_c_sd = 3, sigma_c_cv = 0.2"),
     "search.fixed.sigma_c_cv"),
    ("spread of a response not targeted", edit("ucs_MPa = 40.0", "ucs_MPa = 40.0\nspread = { nu = 0.01 }"),
     "targets.ucs.spread.nu"),
    ("spread range without the target", edit("ucs_MPa = 40.0", "ucs_MPa = 40.0\nspread = { ucs_MPa = [41, 45] }"),
     "targets.ucs.spread.ucs_MPa"),
    ("spread sd 0", edit("ucs_MPa = 40.0", "ucs_MPa = 40.0\nspread = { E_GPa = 0 }"),
     "targets.ucs.spread.E_GPa"),
    ("Brazilian target 0", edit("[specimen]", "[targets.brazilian]\nsigma_t_MPa = 0\n[specimen]"),
     "targets.brazilian.sigma_t_MPa"),
    ("Brazilian section without its target", edit("[specimen]", "[targets.brazilian]\n[specimen]"),
     "targets.brazilian.sigma_t_MPa"),
    ("misspelt Brazilian key", edit("[specimen]", "[targets.brazilian]\nsigma_t_MPa = 9.0\nweight = 2\n"
                                    "[specimen]"), "targets.brazilian.weight:"),
    ("weight 0", edit("ucs_MPa = 40.0", "ucs_MPa = 40.0\nweights = { E_GPa = 0 }"),
     "targets.ucs.weights.E_GPa"),
    ("weight of a response not targeted", edit("ucs_MPa = 40.0", "ucs_MPa = 40.0\nweights = { nu = 2 }"),
     "targets.ucs.weights.nu"),
    ("Brazilian spread of a UCS response", edit("[specimen]", "[targets.brazilian]\nsigma_t_MPa = 9.0\n"
                                                "spread = { E_GPa = 1.0 }\n[specimen]"),
     "targets.brazilian.spread.E_GPa"),
    *[(f"confinements {case}", edit("[specimen]", f"[targets.biaxial]\nconfinement_mpa = {values}\n"
                                     f"phi_deg = 40\n[specimen]"), "targets.biaxial.confinement_mpa")
      for case, values in (("unsorted", "[10, 5]"), ("negative", "[-5, 5]"), ("empty", "[]"),
                           ("repeated", "[5, 5]"), ("one, for an envelope", "[5]"))],
    ("peaks not one per confinement", edit("[specimen]", "[targets.biaxial]\nconfinement_mpa = [0, 5]\n"
                                           "sigma1_MPa = [100]\n[specimen]"), "targets.biaxial.sigma1_MPa"),
    ("confined section without a target", edit("[specimen]", "[targets.biaxial]\nconfinement_mpa = [0, 5]\n"
                                               "[specimen]"), "targets.biaxial"),
    ("CI target of a test without curves", edit("[specimen]", "[targets.direct_tension]\n"
                                                "sigma_t_direct_MPa = 9\nci_MPa = 50\n[specimen]"),
     "targets.direct_tension.ci_MPa"),
    ("validation by an unknown test", CAMPAIGN + "[validation]\ntests = ['triaxial']\n", "validation.tests"),
    ("UCS as a validation check", CAMPAIGN + "[validation]\ntests = ['ucs']\n", "validation.tests"),
    ("validation without its targets", CAMPAIGN + "[validation]\ntests = ['brazilian']\n",
     "validation.tests"),
    ("weights of a validation check", edit("[specimen]", "[targets.bending]\nK_IC_MPa_sqrt_m = 1.0\n"
                                           "weights = { K_IC_MPa_sqrt_m = 2 }\n[specimen]"),
     "targets.bending.weights"),
    ("disk narrower than its particles", edit("[specimen]", "[targets.brazilian]\nsigma_t_MPa = 9.0\n"
                                              "[specimen]\ndisk_diameter_mm = 2"), "specimen.disk_diameter_mm"),
    ("disk diameter 0", edit("height_mm = 16", "height_mm = 16\ndisk_diameter_mm = 0"),
     "specimen.disk_diameter_mm"),
    ("too few draws", CAMPAIGN + "[uncertainty]\ndraws = 2\n", "uncertainty.draws"),
    ("no packings", CAMPAIGN + "[uncertainty]\npackings = 0\n", "uncertainty.packings"),
    ("pinned within 0", CAMPAIGN + "[identifiability]\npinned_within = 0\n", "identifiability.pinned_within"),
    ("pinned within inf", CAMPAIGN + "[identifiability]\npinned_within = inf\n", "identifiability.pinned_within"),
    ("pinned share 0", CAMPAIGN + "[identifiability]\npinned_share = 0\n", "identifiability.pinned_share"),
    ("pinned share over 1", CAMPAIGN + "[identifiability]\npinned_share = 1.5\n", "identifiability.pinned_share"),
    ("runs not a bool", CAMPAIGN + "[identifiability]\nruns = 3\n", "identifiability.runs"),
    ("unknown test to rank", CAMPAIGN + '[identifiability]\ntests = ["tilt"]\n', "identifiability.tests"),
    ("unknown identifiability key", CAMPAIGN + "[identifiability]\nshare = 0.2\n", "identifiability.share"),
]
OPTIONS = [  # (case, extra arguments, the option the error must name first)
    ("negative workers", ["--workers", "-1"], "--workers"),
    ("workers not a number", ["--workers", "many"], "--workers"),
    ("time limit 0", ["--time-limit-s", "0"], "--time-limit-s"),
    ("bogus scheduler", ["--scheduler", "bogus"], "--scheduler"),
    ("no local workers", ["--scheduler", "local:0"], "--scheduler"),
    ("no threads", ["--threads", "0"], "--threads"),
    ("more threads than numba has", ["--threads", "100000"], "--threads"),
]


def not_sqlite(path):
    path.write_bytes(bytes(range(256)) * 16)


def sqlite_not_a_store(path):
    db = sqlite3.connect(path)
    db.execute("CREATE TABLE samples (id INTEGER, granite TEXT)")
    db.execute("INSERT INTO samples VALUES (1, 'Beishan')")
    db.commit()
    db.close()


def newer_store(path):
    """A rockcal store of a later schema, which need not use WAL either."""
    db = sqlite3.connect(path)
    db.execute("UPDATE meta SET value=? WHERE key='schema_version'", (str(SCHEMA_VERSION + 1),))
    db.commit()
    db.execute("PRAGMA journal_mode=DELETE")
    db.close()


STORES = [("store of random bytes", not_sqlite), ("SQLite file, not a store", sqlite_not_a_store),
          ("store of a newer rockcal", newer_store)]


@pytest.fixture(scope="module")
def valid_store(tmp_path_factory):
    """A run store from a tiny earlier run."""
    folder = tmp_path_factory.mktemp("earlier")
    store = RunStore(folder)
    spec = run_spec("ucs", SpecimenSettings(rmin_mm=0.4, width_mm=8, height_mm=16), {"E_c": 20.0})
    assert Executor(store, workers=1).run([spec])[0].status == "ok"
    store.save_document("campaign.toml", CAMPAIGN)
    store.close()
    return folder / STORE_NAME


@pytest.fixture
def out(tmp_path, valid_store):
    """OUT holding a copy of the earlier store; the campaign's files next to it."""
    for name, text in CURVES.items():
        (tmp_path / name).write_text(text)
    folder = tmp_path / "out"
    folder.mkdir()
    shutil.copy(valid_store, folder / STORE_NAME)
    return folder


@pytest.fixture
def rockcal(monkeypatch, capsys):
    """`rockcal ARGS` from the folder `cwd`, in this process: its exit code and stderr."""
    def run(*args, cwd):
        monkeypatch.chdir(cwd)
        monkeypatch.setattr(sys, "argv", ["rockcal", *map(str, args)])
        capsys.readouterr()
        with pytest.raises(SystemExit) as done:
            main()
        return done.value.code, capsys.readouterr().err
    return run


def sha256(path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.mark.parametrize("text, key", [c[1:] for c in CAMPAIGNS], ids=[c[0] for c in CAMPAIGNS])
def test_a_bad_campaign_file(text, key, out, rockcal):
    config = out.parent / "campaign.toml"
    config.write_text(text)
    before = sha256(out / STORE_NAME)
    code, stderr = rockcal("calibrate", config, "--out", out, "--resume", cwd=out.parent)
    assert_one_line(code, stderr, ERROR + key)
    assert sha256(out / STORE_NAME) == before


@pytest.mark.parametrize("args, option", [c[1:] for c in OPTIONS], ids=[c[0] for c in OPTIONS])
def test_a_bad_option(args, option, out, rockcal):
    config = out.parent / "campaign.toml"
    config.write_text(CAMPAIGN)
    before = sha256(out / STORE_NAME)
    code, stderr = rockcal("calibrate", config, "--out", out, "--resume", *args, cwd=out.parent)
    assert_one_line(code, stderr, ERROR + option + ": ")
    assert sha256(out / STORE_NAME) == before


@pytest.mark.parametrize("spoil", [c[1] for c in STORES], ids=[c[0] for c in STORES])
@pytest.mark.parametrize("command", ["calibrate", "report"])
def test_a_bad_store_file(command, spoil, out, rockcal):
    store = out / STORE_NAME
    if spoil is not newer_store:
        store.unlink()
    spoil(store)
    before = sha256(store)
    config = out.parent / "campaign.toml"
    config.write_text(CAMPAIGN)
    args = [config, "--out", out, "--resume"] if command == "calibrate" else [out]
    code, stderr = rockcal(command, *args, cwd=out.parent)
    assert_one_line(code, stderr, ERROR + f"OUT: {store}")
    assert sha256(store) == before


@pytest.mark.parametrize("record, names", [
    ("{not json", "record.json: not valid JSON"),
    ('{"rock": "granite"}', "targets: Field required (in record.json)"),  # an older record
    ('{"rock": 3}', "rock: Input should be a valid string (in record.json)"),
])
def test_a_record_that_does_not_fit(record, names, out, rockcal):
    store = RunStore(out)
    store.save_document("record.json", record)
    store.close()
    assert_one_line(*rockcal("report", out, cwd=out.parent), ERROR + names)


def test_report_on_a_folder_without_a_store(tmp_path, rockcal):
    code, stderr = rockcal("report", tmp_path, cwd=tmp_path)
    assert_one_line(code, stderr, ERROR + f"OUT: {tmp_path} holds no run store")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("config, args", [
    pytest.param(with_curve("text.csv"), [], id="broken curve"),
    pytest.param(CAMPAIGN, ["--scheduler", "bogus"], id="bogus scheduler"),
    pytest.param(CAMPAIGN, ["--scheduler", "tcp://127.0.0.1:9"], id="unreachable scheduler"),
])
def test_a_bad_input_leaves_no_store_in_a_new_out(config, args, tmp_path, rockcal):
    for name, text in CURVES.items():
        (tmp_path / name).write_text(text)
    (tmp_path / "campaign.toml").write_text(config)
    code, stderr = rockcal("calibrate", tmp_path / "campaign.toml", "--out", tmp_path / "out", *args,
                           cwd=tmp_path)
    assert code == 2, stderr
    assert not (tmp_path / "out" / STORE_NAME).exists()
