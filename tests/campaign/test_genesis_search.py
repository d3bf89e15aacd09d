"""The installation gap searched beside the micro-parameters: a twin campaign recovers the gap
and E_c that made its targets, each run keyed by its own gap, every run on the one packing."""

import pytest

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.runs.pool import Executor
from rockcal.campaign.procedure.steps import calibrate
from rockcal.campaign.runs.store import RunStore
from rockcal.specimens.genesis import Genesis
from rockcal.specimens.specimen import random_packing
from rockcal.errors import InputError
from rockcal.labtests.ucs import simulate_ucs

TRUE = {"E_c": 20.0, "install_gap": 0.6}
CAMPAIGN = """
[targets.ucs]
E_GPa = {E_GPa!r}
ucs_MPa = {ucs_MPa!r}
[specimen]
width_mm = 8
height_mm = 16
rmin_mm = 0.2
[search]
bounds = {{ E_c = [15, 25], install_gap = [0.3, 0.9] }}
fixed = {{ sigma_c = 35 }}
[surrogate]
samples = 8
checks = 1
[acceptance]
tolerance = 0.02
max_dem_runs = 16
[identifiability]
runs = false  # this twin is about its route; the stage has its own tests
"""


@pytest.mark.slow  # a campaign
def test_a_twin_recovers_the_installation_gap_and_e_c(tmp_path, monkeypatch):
    monkeypatch.setenv("ROCKCAL_CACHE", str(tmp_path / "cache"))
    specimen = random_packing(8, 16, 0.2, genesis=Genesis(install_gap=TRUE["install_gap"]))
    lab = simulate_ucs({"E_c": TRUE["E_c"], "sigma_c": 35.0}, specimen)
    store = RunStore(tmp_path / "out")
    record = calibrate(planned(parse_campaign(CAMPAIGN.format(E_GPa=lab.E_GPa, ucs_MPa=lab.ucs_MPa), tmp_path)),
                       Executor(store, workers=1))
    assert record.accepted
    assert record.identified["install_gap"] == pytest.approx(TRUE["install_gap"], abs=0.05)
    assert record.identified["E_c"] == pytest.approx(TRUE["E_c"], rel=0.03)
    assert record.specimen.install_gap == record.identified["install_gap"]  # what the export writes
    assert "install_gap" not in record.identified_params  # a genesis setting, not the material's
    gaps = {store.run(key).specimen["install_gap"] for key in record.dem_run_keys}
    assert len(gaps) == record.dem_runs  # each run keyed by its own gap
    assert len(list((tmp_path / "cache").glob("*.npz"))) == 1  # one packing, bonded anew per gap


@pytest.mark.parametrize("section, key", [
    ("fixed = { install_gap = 0.5 }", "search.fixed"),
    ("bounds = { install_gap = [-1, 1] }", "search.bounds.install_gap"),
    ("bounds = { rmin_mm = [0.2, 0.3] }", "search.bounds"),  # a setting no campaign searches
    ("bounds = { fjm_B_frac = [0.5, 1.2] }", "search.bounds.fjm_B_frac"),  # a fraction above 1
])
def test_a_bad_search_bound_or_fixed_value_is_named(tmp_path, section, key):
    material = '[material]\nmodel = "flatjoint"\n' if "fjm_" in section else ""
    text = f"{material}[targets.ucs]\nE_GPa = 40\n[search]\n{section}\n" + \
        ("bounds = { E_c = [10, 30] }\n" if "fixed" in section else "")
    with pytest.raises(InputError) as error:
        parse_campaign(text, tmp_path)
    assert error.value.field.startswith(key)
