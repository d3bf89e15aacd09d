"""The plan's time model in 3D (`rockcal.campaign.plan.cost`): its reference is the 3D granite
cylinder's run, a 3D beam's and disk's steps are their travel to the peak rather than their
rows, and the shipped flat-jointed 3D campaign's runs cost what its stored runs took."""

from pathlib import Path

import pytest

from rockcal.campaign.input.config import load_campaign
from rockcal.campaign.plan import screen
from rockcal.campaign.plan.cost import WORK_EXPONENT, relative_time, specimen_size
from rockcal.campaign.plan.route import point_cost, sample_cost
from rockcal.campaign.runs.store import RunStore
from rockcal.materials import material

DOCS = Path(__file__).parents[2] / "docs" / "campaigns"


def campaign(name: str, **specimen):
    """A shipped campaign, its [specimen] changed by `specimen`."""
    c, _ = load_campaign(str(DOCS / name))
    return c.model_copy(update={"specimen": c.specimen.model_copy(update=specimen)})


def test_the_3d_reference_run_is_the_3d_granite_cylinders(tmp_path, monkeypatch):
    """The 3D granite's cylinder (25 x 50 mm at R_min 0.8 mm) does the reference run's work, so
    on the reference machine its UCS run is planned at the reference run's time, and a flat
    jointed one at the flat joint's 3D factor times that."""
    granite = campaign("granite-3d-all-targets.toml")
    work = specimen_size("ucs", granite.specimen)[2]
    assert work == pytest.approx(screen.REFERENCE_WORK[3], rel=0.01)
    monkeypatch.setattr(screen, "probe_ms_per_step", lambda: screen.REFERENCE_PROBE_MS)
    sizes, empty = {"ucs": specimen_size("ucs", granite.specimen)}, RunStore(tmp_path)
    assert screen.run_times(granite, empty, sizes)[0]["ucs"] == pytest.approx(screen.REFERENCE_RUN_S[3], rel=0.02)
    jointed = granite.model_copy(update={"material": granite.material.model_copy(update={"model": "flatjoint"})})
    assert screen.run_times(jointed, empty, sizes)[0]["ucs"] == pytest.approx(
        material("flatjoint").slower_in(3) * screen.REFERENCE_RUN_S[3], rel=0.02)


@pytest.mark.parametrize("test", ["bending", "brazilian"])
def test_a_3d_beam_or_disk_costs_more_ucs_runs_on_coarser_grains(test):
    """On grains 1.4 x coarser a 3D beam's or disk's work falls with its grains alone (its steps
    are its travel to the peak), a UCS cylinder's with its rows too: a run of it costs at least
    1.4^WORK_EXPONENT more UCS runs. In 2D, where both follow their rows, it costs as many."""
    for dimensions in (3, 2):
        fine = campaign("granite-3d-all-targets.toml", dimensions=dimensions, rmin_mm=0.8)
        coarse = campaign("granite-3d-all-targets.toml", dimensions=dimensions, rmin_mm=1.12)
        (_, grains_fine, work_fine), (_, grains, work) = (specimen_size(test, c.specimen) for c in (fine, coarse))
        rows = 1.0 if dimensions == 3 else 1.4
        assert work / work_fine == pytest.approx(grains / grains_fine / rows, rel=0.01)
        grows = relative_time(coarse, test) / relative_time(fine, test)
        if dimensions == 3:
            assert grows > 0.99 * 1.4 ** WORK_EXPONENT[3]
        else:
            assert grows == pytest.approx(1.0, rel=0.05)


def test_the_flat_jointed_3d_sheet_costs_what_its_runs_took():
    """docs/campaigns/ldb-3d.toml: a parameter set with every test took about 17 UCS runs' time
    and a verified one, with its three disks, 33 (its store's runs at R_min 0.5 mm); the plan's
    were 10.9 and 15.2 while it took a 3D disk's steps to follow its rows."""
    ldb = campaign("ldb-3d.toml")
    assert sample_cost(ldb) == pytest.approx(17, rel=0.15)
    assert point_cost(ldb) == pytest.approx(33, rel=0.15)
