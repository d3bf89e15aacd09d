"""A twin experiment with a strength envelope target: UCS targets (E, UCS) and the Mohr-Coulomb
c and phi of confined tests at 0, 5 and 10 MPa, all made by the engine at known E_c and tau_c
on a 10 x 20 mm specimen (202 disks), recovered by a campaign that runs one confined test per
confinement at every parameter set; its report draws the envelope and the confined curves.

On this specimen the cohesion follows tau_c (+/- 10 % of tau_c moves c by -8 % / +7 %) and E
follows E_c; phi barely moves with either (within 0.3 degrees), so c and E pin the two down.
"""

import pytest

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.runs.pool import Executor
from rockcal.campaign.procedure.steps import calibrate
from rockcal.campaign.outputs.report import write_report
from rockcal.campaign.runs.store import RunStore
from rockcal.specimens.specimen import random_packing
from rockcal.labtests.biaxial import envelope, simulate_biaxial
from rockcal.labtests.ucs import simulate_ucs

pytestmark = pytest.mark.slow  # about 25 parameter sets of 4 small DEM runs each

TRUE = {"E_c": 20.0, "tau_c": 45.0}
FIXED = {"kn_ks": 2.0, "sigma_c": 30.0, "mu": 0.5}
RECOVERED_WITHIN = 0.03  # relative, each parameter
CONFINEMENTS = [0.0, 5.0, 10.0]
SPECIMEN = {"rmin_mm": 0.4, "width_mm": 10.0, "height_mm": 20.0, "seed": 2}


def lab_values() -> tuple[dict, dict]:
    """The UCS test's and the envelope's responses at TRUE, as a lab would report them."""
    s = SPECIMEN
    specimen = random_packing(s["width_mm"], s["height_mm"], s["rmin_mm"], seed=s["seed"])
    ucs = simulate_ucs(TRUE | FIXED, specimen)
    peaks = [simulate_biaxial(TRUE | FIXED, specimen, s3) for s3 in CONFINEMENTS]
    fit = envelope([{"confinement_MPa": p.confinement_MPa, "sigma1_MPa": p.sigma1_MPa} for p in peaks])
    return {"E_GPa": ucs.E_GPa, "ucs_MPa": ucs.ucs_MPa}, fit


def campaign_text(ucs: dict, fit: dict) -> str:
    fixed = ", ".join(f"{k} = {v}" for k, v in FIXED.items())
    return f"""
[targets.ucs]
E_GPa = {ucs["E_GPa"]!r}
ucs_MPa = {ucs["ucs_MPa"]!r}
[targets.biaxial]
confinement_mpa = {CONFINEMENTS}
phi_deg = {fit["phi_deg"]!r}
c_MPa = {fit["c_MPa"]!r}
[specimen]
{chr(10).join(f"{k} = {v}" for k, v in SPECIMEN.items())}
[search]
bounds = {{ E_c = [15, 25], tau_c = [35, 55] }}
fixed = {{ {fixed} }}
[surrogate]
samples = 10
checks = 2
[optimizer]
iterations = 60
[acceptance]
tolerance = 0.02
max_dem_runs = 24
[identifiability]
runs = false  # this twin is about its route; the stage has its own tests
"""


@pytest.fixture(scope="module")
def twin(tmp_path_factory):
    """The campaign's result, its store and its folder."""
    folder = tmp_path_factory.mktemp("envelope-twin")
    store = RunStore(folder)
    record = calibrate(planned(parse_campaign(campaign_text(*lab_values()), folder)), Executor(store, workers=1))
    yield record, store, folder
    store.close()


def test_ucs_and_envelope_targets_recover_the_parameters(twin):
    record, _, _ = twin
    assert record.target_tests == {"ucs": ["E_GPa", "ucs_MPa"], "biaxial": ["phi_deg", "c_MPa"]}
    assert record.accepted
    for name, truth in TRUE.items():
        assert record.identified[name] == pytest.approx(truth, rel=RECOVERED_WITHIN), name


def test_each_confinement_is_its_own_stored_run(twin):
    record, store, _ = twin
    runs = [store.run(key) for key in record.series_runs["biaxial"]]
    assert [run.specimen["confinement_mpa"] for run in runs] == CONFINEMENTS
    assert [run.responses["confinement_MPa"] for run in runs] == CONFINEMENTS
    peaks = [run.responses["sigma1_MPa"] for run in runs]
    assert peaks == sorted(peaks)  # the peak rises with the confinement
    assert envelope([run.responses for run in runs])["c_MPa"] == pytest.approx(record.verified["c_MPa"])


def test_the_report_draws_the_envelope_and_the_confined_curves(twin):
    record, store, folder = twin
    page = write_report(record, store, folder / "report").read_text(encoding="utf-8")
    for name in ("biaxial_strength_envelope.png", "biaxial_confined_compression_curves.png",
                 "crack_stresses_ucs.png"):
        assert (folder / "report" / name).stat().st_size > 10_000, name
    assert "Confined compression: strength envelope" in page
    assert f"<td>confined compression</td><td>c_MPa</td><td>{record.targets['c_MPa']:.4g}</td>" in page
