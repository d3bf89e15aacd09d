"""The genesis of a batch's packings comes first, as a stage of its own: each packing the
batch needs and the cache lacks is made once, the progress counts them, and the plan knows in
2D and 3D which packings the cache already holds."""

import pytest

from rockcal.campaign.input.config import SpecimenSettings
from rockcal.campaign.plan.cost import genesis_s, genesis_work
from rockcal.campaign.plan.engine_speed import others_from_wall
from rockcal.campaign.runs.packings import new_packings, packing_file
from rockcal.campaign.runs.pool import Executor
from rockcal.campaign.runs.spec import run_spec
from rockcal.campaign.runs.store import RunStore
from rockcal.labtests.registry import lab_test
from rockcal.specimens.specimen import cache_dir

SMALL_2D = SpecimenSettings(rmin_mm=0.4, width_mm=8, height_mm=16)
SMALL_3D = SpecimenSettings(dimensions=3, rmin_mm=0.8, width_mm=11, height_mm=22, disk_diameter_mm=22)


@pytest.mark.parametrize("test, settings", [("ucs", SMALL_2D), ("ucs", SMALL_3D), ("brazilian", SMALL_3D),
                                            ("biaxial", SMALL_3D.model_copy(update={"confinement_mpa": 5.0}))])
def test_the_plan_names_the_file_the_genesis_writes(test, settings, monkeypatch, tmp_path):
    """Making a test's specimen writes exactly the packing file the plan looks for."""
    monkeypatch.setenv("ROCKCAL_CACHE", str(tmp_path))
    kind = lab_test(test)
    name = kind.packing_file(settings)
    assert not (cache_dir() / name).exists()
    kind.make(kind.settings_of(settings))
    assert (cache_dir() / name).exists()


@pytest.mark.slow  # a process pool's start and four DEM runs
def test_a_batch_makes_each_missing_packing_once_before_its_runs(monkeypatch, tmp_path):
    """Four runs on two packings (two seeds): two geneses, counted up from 0 to 2 of 2 on the
    pool, then the runs; a second batch on the same packings makes none."""
    monkeypatch.setenv("ROCKCAL_CACHE", str(tmp_path / "cache"))
    specs = [run_spec("ucs", SMALL_2D.model_copy(update={"seed": seed}), {"E_c": e_c, "sigma_c": 40.0})
             for seed in (1, 2) for e_c in (15.0, 20.0)]
    assert len(new_packings(specs)) == 2
    executor = Executor(RunStore(tmp_path / "out"), workers=2)
    shown = []
    executor.on_genesis = lambda made, total: shown.append((made, total))
    try:
        results = executor.run(specs)
    finally:
        executor.close()
    assert [r.status for r in results] == ["ok"] * 4
    made = [m for m, _ in shown]
    assert shown[0] == (0, 2) and shown[-1] == (2, 2) and made == sorted(set(made))  # counted up, once each
    assert all((cache_dir() / packing_file(spec)).exists() for spec in specs)
    assert new_packings(specs) == []


@pytest.mark.parametrize("settings", [SMALL_2D, SMALL_3D])
def test_genesis_time_grows_with_grains_times_rows(settings):
    """A vessel twice as tall holds twice the grains in twice the rows: four times the work and
    the time; a machine twice as fast (half the probe's step) takes half the time."""
    tall = settings.model_copy(update={"height_mm": 2 * settings.height_mm})
    assert genesis_work("ucs", tall) == pytest.approx(4 * genesis_work("ucs", settings), rel=0.01)  # whole grains
    assert genesis_s("ucs", tall, 1.0) == pytest.approx(4 * genesis_s("ucs", settings, 1.0), rel=0.01)
    assert genesis_s("ucs", settings, 0.5) == pytest.approx(genesis_s("ucs", settings, 1.0) / 2)


@pytest.mark.parametrize("others, cores", [(2, 2), (4, 2), (4, 4), (9, 8)])
def test_a_probe_slowed_by_other_work_counts_it(others, cores):
    """A one-thread task beside L others on C cores (L >= C) runs (L + 1) / C slower: that
    reading gives L back; one that ran about as fast as alone says nothing."""
    assert others_from_wall((others + 1) / cores, cores) == pytest.approx(others)
    assert others_from_wall(1.0, cores) == 0.0
