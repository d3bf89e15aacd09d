"""A failed or timed-out run is kept with why, and runs again when a later call needs it: once
per call, at most MAX_TRIES times; the first screen says how many will be retried."""

import numpy as np

from rockcal.campaign.input.config import SpecimenSettings, parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.runs.pool import Executor
from rockcal.campaign.runs.spec import run_spec
from rockcal.campaign.plan.screen import describe
from rockcal.campaign.procedure.steps import CalibrationFailed, calibrate
from rockcal.campaign.runs.retries import MAX_TRIES
from rockcal.campaign.runs.store import RunStore
from rockcal.specimens.specimen import cache_dir, packing_name, stored_packing
from rockcal.labtests.registry import lab_test
from tiny import tiny_campaign

TINY = SpecimenSettings(rmin_mm=0.4, width_mm=8, height_mm=16, seed=3)
CAMPAIGN = tiny_campaign(samples=4, iterations=10, max_dem_runs=6, seed=4)


def specs(n: int, settings=TINY, **fixed):
    return [run_spec("ucs", settings, {"E_c": 15.0 + i, "sigma_c": 40.0} | fixed) for i in range(n)]


def test_timed_out_runs_run_again_on_a_later_call_and_replace_their_record(tmp_path):
    batch = specs(2, mu=0.41)
    store = RunStore(tmp_path)
    first = Executor(store, workers=1, time_limit_s=1e-4).run(batch)
    assert [r.status for r in first] == ["timed out"] * 2
    again = Executor(store, workers=1)
    second = again.run(batch)
    assert [r.status for r in second] == ["ok"] * 2 and again.executed == 2
    assert [store.get(s).status for s in batch] == ["ok", "ok"]
    assert store.executions() == {s.key: 2 for s in batch}
    assert Executor(store, workers=1).run(batch)[0].responses == second[0].responses  # a run done stays


def test_a_failure_runs_once_per_call_and_at_most_max_tries_in_all(tmp_path):
    narrow = SpecimenSettings(rmin_mm=0.4, width_mm=2, height_mm=16)  # narrower than 4 grains
    batch = specs(1, narrow)
    store = RunStore(tmp_path)
    for call in range(MAX_TRIES + 2):
        executor = Executor(store, workers=1)
        results = executor.run(batch) + executor.run(batch)  # the second: from the store
        assert [r.status for r in results] == ["failed", "failed"]
        assert executor.executed == (1 if call < MAX_TRIES else 0)
    assert store.tries(batch[0].key) == MAX_TRIES
    assert results[0].message.endswith(f"(failed {MAX_TRIES} times; not run again)")


def test_a_repaired_specimen_cache_heals_the_runs_that_failed_on_it(tmp_path):
    batch = specs(2, mu=0.43)
    name = packing_name(**lab_test("ucs").packing(TINY))
    Executor(RunStore(tmp_path / "maker"), workers=1).run(specs(1, mu=0.2))  # the packing, cached
    path = stored_packing(name)
    assert path is not None and path.parent == cache_dir()
    good = path.read_bytes()
    path.write_bytes(good[:len(good) // 3])  # truncated
    from rockcal.campaign.runs.pool import specimen_of

    specimen_of.cache_clear()
    store = RunStore(tmp_path / "campaign")
    assert [r.status for r in Executor(store, workers=1).run(batch)] == ["failed", "failed"]
    path.write_bytes(good)  # repaired
    specimen_of.cache_clear()
    healed = Executor(store, workers=1).run(batch)
    assert [r.status for r in healed] == ["ok", "ok"]
    assert np.isfinite(healed[0].responses["E_GPa"])


def test_a_campaign_of_timed_out_runs_resumes_and_the_first_screen_says_so(tmp_path):
    campaign = planned(parse_campaign(CAMPAIGN, tmp_path))
    store = RunStore(tmp_path)
    try:
        calibrate(campaign, Executor(store, workers=1, time_limit_s=1e-4))
        raise AssertionError("every run timed out: the calibration cannot go on")
    except CalibrationFailed:
        pass
    timed_out = store.count()
    lines = describe(campaign, store, None)
    assert "runs of this campaign already in the store: 0 " in lines[2]
    assert lines[3].startswith(f"failed runs in the store: {timed_out} ({timed_out} timed out); each "
                               f"is run again if this campaign needs it (at most {MAX_TRIES} tries)")
    executor = Executor(store, workers=1)
    result = calibrate(campaign, executor)
    assert result.dem_runs >= 1 and executor.executed >= timed_out
    assert not result.failed_runs
