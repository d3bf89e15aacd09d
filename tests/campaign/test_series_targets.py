"""Targets of a test run as a series (confined compression at several confinements) on a
synthetic forward model (no DEM): each parameter set runs one confined test per confinement,
each its own run, folded into the envelope the goals compare; the campaign recovers the
parameters that made the targets; the first screen counts a run per confinement."""

import math

import pytest

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.runs.spec import run_spec
from rockcal.campaign.plan.screen import describe, stages
from rockcal.campaign.procedure.steps import calibrate
from rockcal.campaign.runs.store import RunStore
from rockcal.campaign.runs.spec import RunResult
from rockcal.errors import InputError
from rockcal.labtests.envelope import fit_mohr_coulomb
from tiny import StandInExecutor

CONFINEMENTS = [0.0, 5.0, 10.0]
TRUE = {"E_c": 22.0, "kn_ks": 1.8, "sigma_c": 40.0, "tau_c": 80.0}


def ucs(p: dict) -> dict:
    return {"E_GPa": 2.0 * p["E_c"], "nu": 0.1 * p["kn_ks"], "ucs_MPa": 3.0 * p["sigma_c"] + 0.2 * p["tau_c"]}


def sigma1(p: dict, sigma3: float) -> float:
    """A Mohr-Coulomb stand-in: the UCS, rising with confinement by k = 1 + tau_c / 20."""
    return ucs(p)["ucs_MPa"] + (1 + p["tau_c"] / 20) * sigma3


def envelope(p: dict) -> dict:
    """phi and c of the stand-in's peaks at CONFINEMENTS (a line: exact)."""
    mc = fit_mohr_coulomb(CONFINEMENTS, [sigma1(p, s3) for s3 in CONFINEMENTS])
    return {"phi_deg": mc.phi_deg, "c_MPa": mc.c_MPa}


class Executor(StandInExecutor):
    """The stand-in for every run; it keeps the (test, confinement) of each run asked for."""

    def __init__(self):
        self.runs = []

    def result(self, spec):
        p = dict(spec.params)
        if spec.kind == "ucs":
            self.runs.append(("ucs", None, spec.params))
            return RunResult("ok", ucs(p) | {"n_particles": 100}, None, 0.0)
        s3 = dict(spec.specimen)["confinement_mpa"]
        self.runs.append(("biaxial", s3, spec.params))
        return RunResult("ok", {"confinement_MPa": s3, "sigma1_MPa": sigma1(p, s3)}, None, 0.0)


def campaign_text(targets: dict) -> str:
    return f"""
[targets.ucs]
E_GPa = {ucs(TRUE)["E_GPa"]!r}
nu = {ucs(TRUE)["nu"]!r}
[targets.biaxial]
confinement_mpa = {CONFINEMENTS}
{chr(10).join(f"{k} = {v!r}" for k, v in targets.items())}
[sensitivity]
array = "L9(3^4)"
levels = {{ E_c = [15, 22, 30], kn_ks = [1, 2, 3], sigma_c = [30, 40, 50], tau_c = [60, 80, 100] }}
threshold = 0.1
[surrogate]
samples = 16
checks = 2
[optimizer]
iterations = 80
[acceptance]
tolerance = 0.01
max_dem_runs = 40
[uncertainty]
enabled = true
draws = 10
packings = 2
"""


def test_an_envelope_target_recovers_the_parameters_and_runs_each_confinement(tmp_path):
    campaign = planned(parse_campaign(campaign_text(envelope(TRUE)), tmp_path))
    executor = Executor()
    record = calibrate(campaign, executor)
    assert record.target_tests == {"ucs": ["E_GPa", "nu"], "biaxial": ["phi_deg", "c_MPa"]}
    assert record.accepted and set(record.sensitivity.chosen) == set(TRUE)
    for name, truth in TRUE.items():
        assert record.identified[name] == pytest.approx(truth, rel=0.03), name
    # every parameter set ran the confined test at every confinement, but the verified points
    # whose UCS test missed its targets (the confined series is dear: [acceptance] ucs_first)
    sets = {s3: {p for test, at, p in executor.runs if at == s3} for s3 in [None, *CONFINEMENTS]}
    assert sets[0.0] == sets[5.0] == sets[10.0] and sets[0.0] <= sets[None]
    assert len(sets[None] - sets[0.0]) == sum(len(it.errors) == 2 for it in record.iterations)
    assert record.verified["phi_deg"] == pytest.approx(envelope(record.identified_params)["phi_deg"])
    assert set(record.uncertainty.scatter) == {"E_GPa", "nu", "phi_deg", "c_MPa"}
    keys = record.series_runs["biaxial"]
    assert len(set(keys)) == 3 and record.final_ucs_run_key not in keys


def test_peaks_as_targets_name_each_confinement(tmp_path):
    peaks = [sigma1(TRUE, s3) for s3 in CONFINEMENTS]
    record = calibrate(planned(parse_campaign(campaign_text({"sigma1_MPa": peaks}), tmp_path)), Executor())
    assert record.target_tests["biaxial"] == ["sigma1_MPa@0MPa", "sigma1_MPa@5MPa", "sigma1_MPa@10MPa"]
    assert record.accepted
    assert record.verified["sigma1_MPa@10MPa"] == pytest.approx(peaks[2], rel=0.01)
    assert math.isfinite(record.verified["m_i"])  # the envelope comes with the peaks


def test_a_confined_validation_check_folds_its_series(tmp_path):
    text = campaign_text(envelope(TRUE)) + '[validation]\ntests = ["biaxial"]\n'
    text = text.replace("[uncertainty]\nenabled = true", "[uncertainty]\nenabled = false")
    record = calibrate(planned(parse_campaign(text, tmp_path)), Executor())
    [check] = record.checks
    assert check.test == "biaxial" and check.status == "ok"
    assert check.responses["phi_deg"] == pytest.approx(envelope(record.identified_params)["phi_deg"])
    assert set(check.errors) == {"phi_deg", "c_MPa"}


def test_the_first_screen_counts_a_run_per_confinement(tmp_path):
    """A confined series is dear: one point is verified a round (`plan.route`)."""
    campaign = planned(parse_campaign(campaign_text(envelope(TRUE)), tmp_path))
    assert stages(campaign) == [("sensitivity", "ucs", 9), ("sensitivity", "biaxial", 27),
                                ("samples and checks", "ucs", 18), ("samples and checks", "biaxial", 54),
                                ("verification", "ucs", 1), ("verification", "biaxial", 3),
                                ("packings and validation", "ucs", 1),
                                ("packings and validation", "biaxial", 3),
                                ("identifiability", "ucs", 6), ("identifiability", "biaxial", 18)]
    lines = describe(campaign, RunStore(tmp_path / "out"), workers=None)
    assert lines[1].endswith("each parameter set runs UCS and confined compression at 3 values of "
                             "confinement_mpa (0, 5, 10 MPa)")


def test_a_confinement_keys_its_own_run():
    campaign = planned(parse_campaign(campaign_text(envelope(TRUE)), None))
    specimen = campaign.specimen
    runs = {s3: run_spec("biaxial", specimen, TRUE, own={"confinement_mpa": s3}).key for s3 in CONFINEMENTS}
    assert len(set(runs.values())) == 3
    assert runs[0.0] == run_spec("biaxial", specimen, TRUE).key  # the setting's default, 0


def test_a_peak_is_named_by_its_confinement_in_spread_and_weights(tmp_path):
    peaks = {"sigma1_MPa": [sigma1(TRUE, s3) for s3 in CONFINEMENTS]}
    named = campaign_text(peaks | {"spread": {}}).replace(
        "spread = {}", 'spread = { "sigma1_MPa@5MPa" = 3.0 }\nweights = { "sigma1_MPa@10MPa" = 2.0 }')
    campaign = planned(parse_campaign(named, tmp_path))
    assert campaign.targets.biaxial.spread == {"sigma1_MPa@5MPa": 3.0}
    with pytest.raises(InputError) as error:
        parse_campaign(named.replace('"sigma1_MPa@5MPa"', "sigma1_MPa"), tmp_path)
    assert error.value.field == "targets.biaxial.spread.sigma1_MPa"
