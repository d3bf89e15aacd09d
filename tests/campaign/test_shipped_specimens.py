"""The packings shipped with rockcal: every one the embedded campaigns run on, each exactly what
genesis makes, and the first screen says which specimens must still be made."""

import numpy as np
import pytest

from rockcal.campaign.input.config import load_campaign, parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.plan.quick_look import quick_look
from rockcal.campaign.plan.screen import describe, specimens, specimens_to_make
from rockcal.campaign.runs.store import RunStore
from rockcal.specimens.specimen import SHIPPED_DIR, packing_name, random_packing
from rockcal.labtests.registry import lab_test


def packings(campaign) -> list[dict]:
    return [lab_test(test).packing(settings) for test, settings in specimens(campaign)]


def test_the_embedded_campaigns_run_on_shipped_packings_only():
    granite = planned(load_campaign(None)[0])
    full, quick = packings(granite), packings(quick_look(granite))
    # sensitivity (R_min 0.5 mm), 3 UCS packings, 3 beams; the quick look's 3 UCS packings, 1 beam
    assert sorted((p["width_mm"], p["rmin_mm"], p["seed"]) for p in full) == [
        (50, 0.25, 1), (50, 0.25, 2), (50, 0.25, 3), (50, 0.5, 1), (220, 0.25, 1), (220, 0.25, 2), (220, 0.25, 3)]
    assert len(quick) == 4
    missing = [p for p in full + quick if not (SHIPPED_DIR / packing_name(**p)).exists()]
    assert not missing, f"run benchmarks/shipped_specimens.py: {missing}"
    assert specimens_to_make(granite) == [] and specimens_to_make(quick_look(granite)) == []


@pytest.mark.slow
def test_a_shipped_packing_is_what_genesis_makes():
    """The smallest: the sensitivity runs' half-resolution UCS packing, made anew without any
    cache (`benchmarks/shipped_specimens.py --check` checks them all)."""
    granite, _ = load_campaign(None)
    args = lab_test("ucs").packing(granite.sensitivity_specimen())
    shipped = np.load(SHIPPED_DIR / packing_name(**args))
    made = random_packing(**args, cache=False)
    assert np.array_equal(made.pos, shipped["pos"]) and np.array_equal(made.radius, shipped["radius"])


def test_the_first_screen_names_the_specimens_to_make_first(tmp_path):
    loaded, text = load_campaign(None)
    granite = planned(loaded)
    ready = describe(granite, RunStore(tmp_path / "a"), workers=2)[-1]
    assert "every specimen is ready (cached, or shipped with rockcal); the " in ready
    other = planned(parse_campaign(text.replace("seed = 1", "seed = 7"), tmp_path))
    made = specimens_to_make(other)
    assert made == specimens(other)  # another packing seed: none is shipped
    lines = describe(other, RunStore(tmp_path / "b"), workers=2)
    assert f"first the genesis of {len(made)} specimens (UCS 50 x 100 mm, beam 220 x 50 mm), about" in lines[-1]
