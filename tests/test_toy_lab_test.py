"""A lab test registered from outside rockcal (its own module: this one) runs through
`rockcal simulate` and a campaign with no other edit: the registry is the one place a test is
known. The toy test reads twice the contact modulus off a hexagonal lattice, so a campaign
that fits it and the UCS test's E recovers the E_c that made both targets."""

from dataclasses import dataclass

import numpy as np
import pytest
from typer.testing import CliRunner

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.runs.pool import Executor
from rockcal.campaign.procedure.steps import calibrate
from rockcal.campaign.runs.store import RunStore
from rockcal.specimens.specimen import hexagonal
from rockcal.labtests import registry
from rockcal.errors import InputError
from rockcal.labtests.kind import LabTest, Outline, Response
from rockcal.labtests.result import LabResult
from rockcal.labtests.ucs import simulate_ucs
from rockcal.specimens.specimen import random_packing


@dataclass
class ToyResult(LabResult):
    twice_E_c_GPa: float


def _run(params, specimen, settings, progress) -> ToyResult:
    progress(0.0, 2 * params.E_c)
    n = specimen.n_particles
    return ToyResult(twice_E_c_GPa=2 * params.E_c, n_particles=n, n_bonds=len(specimen.bonds),
                     n_broken_tension=0, n_broken_shear=0, steps=0, wall_s=0.0,
                     curve=np.array([[0.0, 0.0], [1.0, 2 * params.E_c]]), positions=specimen.pos,
                     radius=specimen.radius, cracks={"tension": np.zeros((0, 2)), "shear": np.zeros((0, 2))})


TOY = LabTest(
    name="toy", title="toy", help="Twice the contact modulus, read off a lattice.",
    responses=(Response("twice_E_c_GPa", "GPa"),), settings=("width_mm", "height_mm", "rmin_mm", "seed"),
    check=lambda s: None, make=lambda s: hexagonal(s["width_mm"], s["height_mm"], s["rmin_mm"]),
    run=_run, reading=lambda x, y: f"{y:.1f} GPa",
    outline=lambda s: Outline("toy lattice", s["width_mm"], s["height_mm"]),
    curve_columns=("x", "twice_E_c_GPa"))
SPECIMEN = {"rmin_mm": 0.4, "width_mm": 10.0, "height_mm": 20.0, "seed": 2}


@pytest.fixture
def toy():
    registry.register(TOY)
    yield TOY
    del registry.LAB_TESTS["toy"]


def test_the_toy_test_runs_through_rockcal_simulate(toy, tmp_path):
    from rockcal.cli.app import app, _register

    _register()
    run = CliRunner().invoke(app, ["simulate", "toy", "--width-mm", "4", "--height-mm", "4", "--rmin-mm", "0.5",
                                   "--set", "E_c=12", "--seeds", "2", "--json", "--out", str(tmp_path)])
    assert run.exit_code == 0, run.output
    assert '"twice_E_c_GPa": 24.0' in run.output and '"seeds": [1, 2]' in run.output
    assert (tmp_path / "toy_seed2_curve.csv").read_text().startswith("x,twice_E_c_GPa")


def _calibrate(E_GPa: float, twice_E_c_GPa: float, folder, **acceptance):
    """A campaign fitting the UCS test's E and the toy test, E_c searched in [10, 30] GPa."""
    text = f"""
[targets.ucs]
E_GPa = {E_GPa!r}
[targets.toy]
twice_E_c_GPa = {twice_E_c_GPa!r}
[specimen]
{chr(10).join(f"{k} = {v}" for k, v in SPECIMEN.items())}
[search]
bounds = {{ E_c = [10, 30] }}
[surrogate]
samples = 4
checks = 1
[acceptance]
{chr(10).join(f"{k} = {v}" for k, v in acceptance.items())}
"""
    return calibrate(planned(parse_campaign(text, folder)), Executor(RunStore(folder / "out"), workers=1))


def test_a_campaign_calibrates_against_the_toy_test(toy, tmp_path):
    true_E_c = 18.0
    specimen = random_packing(SPECIMEN["width_mm"], SPECIMEN["height_mm"], SPECIMEN["rmin_mm"], seed=SPECIMEN["seed"])
    E_GPa = simulate_ucs({"E_c": true_E_c}, specimen).E_GPa
    record = _calibrate(E_GPa, 2 * true_E_c, tmp_path, tolerance=0.02, max_dem_runs=10)
    assert record.target_tests == {"ucs": ["E_GPa"], "toy": ["twice_E_c_GPa"]}
    assert record.accepted and record.identified["E_c"] == pytest.approx(true_E_c, rel=0.02)
    assert record.verified["twice_E_c_GPa"] == pytest.approx(2 * record.identified["E_c"])


def test_a_campaign_whose_targets_conflict_ends_with_a_verdict_naming_them(toy, tmp_path):
    # the UCS test's E wants E_c = 18, the toy test wants E_c = 25: at best both within about 16 %
    specimen = random_packing(SPECIMEN["width_mm"], SPECIMEN["height_mm"], SPECIMEN["rmin_mm"], seed=SPECIMEN["seed"])
    E_GPa = simulate_ucs({"E_c": 18.0}, specimen).E_GPa
    record = _calibrate(E_GPa, 50.0, tmp_path, tolerance=0.02, max_dem_runs=8)
    assert not record.accepted
    conflict, = record.verdict.conflicts
    assert sorted(conflict.targets) == ["E_GPa", "twice_E_c_GPa"]
    assert conflict.least_error == pytest.approx(2 / (1 / 18 + 1 / 25) / 18 - 1, abs=0.02)  # at E_c = 20.9
    assert record.verdict.unreachable == {}
    assert len(record.verdict.trade_off.errors) >= 5  # the samples, checks and verifications seen


def test_a_test_without_the_dimensions_setting_is_refused_in_3d_naming_it():
    """A plug-in test whose settings lack `dimensions` has no 3D implementation: 3D is refused
    naming the test (the built-in tests all run in 3D)."""
    TOY.check_dimensions(2, "parallel_bond")
    with pytest.raises(InputError, match="toy: no 3D implementation yet"):
        TOY.check_dimensions(3, "parallel_bond")
