"""A multi-fidelity campaign: coarse samples (R_min x 2) train the surrogate that a few
full-resolution samples correct. A twin recovers the micro-parameters that made its UCS targets
with fewer full-resolution runs than the single-fidelity search, and the first screen counts
each kind of run."""

import pytest

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.runs.pool import Executor
from rockcal.campaign.plan.screen import describe
from rockcal.campaign.procedure.steps import calibrate
from rockcal.campaign.runs.store import RunStore
from rockcal.specimens.specimen import random_packing
from rockcal.labtests.ucs import simulate_ucs

TRUE = {"E_c": 20.0, "kn_ks": 2.0, "sigma_c": 40.0}
CAMPAIGN = """
[targets.ucs]
E_GPa = {E_GPa!r}
nu = {nu!r}
ucs_MPa = {ucs_MPa!r}
[specimen]
width_mm = 10
height_mm = 20
rmin_mm = 0.2
[search]
bounds = {{ E_c = [15, 25], kn_ks = [1.5, 2.5], sigma_c = [30, 50] }}
[surrogate]
samples = 5
checks = 3
coarse_samples = 20
[acceptance]
tolerance = 0.03
max_dem_runs = 40
[identifiability]
runs = false  # this twin is about its route; the stage has its own tests
"""
SINGLE_FIDELITY_RUNS = 19  # the same twin with 15 full-resolution samples: 15 + 3 checks + 1 verification


@pytest.mark.slow  # a campaign of 40 DEM runs
def test_a_multi_fidelity_twin_recovers_its_parameters_with_fewer_fine_runs(tmp_path):
    lab = simulate_ucs(TRUE, random_packing(10, 20, 0.2))
    campaign = planned(parse_campaign(CAMPAIGN.format(E_GPa=lab.E_GPa, nu=lab.nu, ucs_MPa=lab.ucs_MPa), tmp_path))
    store = RunStore(tmp_path / "out")
    screen = " ".join(describe(campaign, store, None))
    assert "coarse samples 20 (R_min 0.4 mm), samples and checks 8" in screen
    record = calibrate(campaign, Executor(store, workers=1))
    assert record.accepted
    for name, value in TRUE.items():
        assert record.identified[name] == pytest.approx(value, rel=0.03), name
    fine = record.dem_runs - len(record.coarse_samples.x)
    assert fine < SINGLE_FIDELITY_RUNS / 1.5
