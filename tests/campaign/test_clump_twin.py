"""A twin with clumped grains: UCS targets (E, nu, UCS) made by the engine at known E_c, kn/ks
and sigma_c on a specimen of two-pebble clumps, then a campaign on the same specimen
settings and seed that searches all three; it recovers E_c and sigma_c within 5 %. The shear
strength is fixed well above sigma_c (tau_c 2.5 sigma_c), so that the UCS follows sigma_c: with
tau_c 1.5 sigma_c a point with sigma_c 5 % low met the UCS within 0.6 %, and the recovered sigma_c
was a matter of the search's path."""

import pytest

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.procedure.steps import calibrate
from rockcal.campaign.runs.pool import Executor, execute
from rockcal.campaign.runs.spec import run_spec
from rockcal.campaign.runs.store import RunStore

pytestmark = pytest.mark.slow  # a campaign of about 20 small DEM runs

TRUE = {"E_c": 20.0, "kn_ks": 2.0, "sigma_c": 40.0}
RECOVERED_WITHIN = 0.05
CAMPAIGN = """
[targets.ucs]
E_GPa = {E_GPa!r}
nu = {nu!r}
ucs_MPa = {ucs_MPa!r}
[specimen]
width_mm = 10
height_mm = 20
rmin_mm = 0.25
grain_shape = "two-pebble"
[search]
bounds = {{ E_c = [15, 25], kn_ks = [1.5, 2.5], sigma_c = [30, 50] }}
fixed = {{ tau_c = 100, mu = 0.5 }}
[surrogate]
samples = 12
checks = 2
[acceptance]
tolerance = 0.03
max_dem_runs = 30
[identifiability]
runs = false  # this twin is about its route; the stage has its own tests
"""


def test_a_clumped_twin_recovers_its_bond_modulus_and_strength(tmp_path):
    stand_in = planned(parse_campaign(CAMPAIGN.format(E_GPa=30.0, nu=0.2, ucs_MPa=100.0), tmp_path))
    lab = execute(run_spec("ucs", stand_in.specimen, stand_in.fixed_params() | TRUE, stand_in.material.model))
    assert lab.status == "ok", lab.message
    targets = {name: float(lab.responses[name]) for name in ("E_GPa", "nu", "ucs_MPa")}
    campaign = planned(parse_campaign(CAMPAIGN.format(**targets), tmp_path))
    record = calibrate(campaign, Executor(RunStore(tmp_path / "out"), workers=1))
    assert record.accepted
    for name in ("E_c", "sigma_c"):
        assert record.identified[name] == pytest.approx(TRUE[name], rel=RECOVERED_WITHIN), name
