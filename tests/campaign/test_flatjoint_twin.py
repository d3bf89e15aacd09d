"""Twins of the flat-jointed material: UCS targets made by the engine at known parameters, on
the campaign's own specimen and seed, and recovered by a campaign that searches them: the bond
friction angle fj_fa (within 3°), the gapped fraction fjm_G_frac (within 0.05) and the number
of elements fj_nr (exactly, a whole number the search varies as a real and every run rounds).

Each twin pairs the parameter with one that the other target pins (E pins fj_emod, the UCS
fj_ten), so that the search is two-dimensional. On this 12 x 24 mm prism (R_min 0.3 mm, about
500 grains) with fj_coh 15 MPa below fj_ten 20 MPa (elements break in shear, where φ acts),
the UCS rises with fj_fa by about 0.55 %/° between 10° and 32° (38.2 to 43.4 MPa, in steps:
equal at 22° and 24°) while E stays within 0.2 %; a gapped fraction of 0.05 more lowers E by
about 4 % while the UCS wanders within 7 %; N_r = 1 ... 5 gives UCS 104, 82, 74, 70 and 66 MPa
at an E within 0.1 %. Measured (targets within 1 %, 13-14 DEM runs and about 20 s a twin on one
core): fj_fa 19.97° (true 20°), fjm_G_frac 0.206 (0.2) with fj_ten 21.0 MPa (20), fj_nr 3 (3)."""

import pytest

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.procedure.steps import calibrate
from rockcal.campaign.runs.pool import Executor, execute
from rockcal.campaign.runs.spec import run_spec
from rockcal.campaign.runs.store import RunStore

pytestmark = pytest.mark.slow  # DEM campaigns of a minute or so: deselect with -m "not slow"

SPECIMEN = {"rmin_mm": 0.3, "width_mm": 12, "height_mm": 24, "seed": 2}
STRENGTH_SPREAD = {"fj_ten_cv": 0.2, "fj_coh_cv": 0.2}  # a spread smooths the UCS's steps
TWINS = {
    "fj_fa": dict(
        true={"fj_emod": 30.0, "fj_fa": 20.0},
        bounds={"fj_emod": (20, 40), "fj_fa": (10, 32)},
        fixed={"fj_kratio": 2.0, "fj_ten": 20.0, "fj_coh": 15.0, "fj_nr": 2, "fjm_B_frac": 0.8},
        within={"fj_emod": 0.6, "fj_fa": 3.0}),
    "fjm_G_frac": dict(
        true={"fjm_G_frac": 0.2, "fj_ten": 20.0},
        bounds={"fjm_G_frac": (0.0, 0.4), "fj_ten": (15, 25)},
        fixed={"fj_emod": 30.0, "fj_kratio": 2.0, "fj_coh": 40.0, "fj_fa": 30.0, "fj_nr": 2,
               "fjm_B_frac": 0.6, "fjm_G_m": 0.001, "fjm_G_sd": 0.0005},
        within={"fjm_G_frac": 0.05, "fj_ten": 1.5}),  # the UCS wanders with G: fj_ten within ~5 %
    "fj_nr": dict(
        true={"fj_emod": 30.0, "fj_nr": 3},
        bounds={"fj_emod": (20, 40), "fj_nr": (1, 5)},
        fixed={"fj_kratio": 2.0, "fj_ten": 20.0, "fj_coh": 40.0, "fj_fa": 30.0, "fjm_B_frac": 0.7},
        within={"fj_emod": 0.6, "fj_nr": 0.0}),
}
TARGETS = ("E_GPa", "ucs_MPa")


def campaign_text(twin: dict, targets: dict) -> str:
    specimen = "\n".join(f"{k} = {v!r}" for k, v in SPECIMEN.items())
    table = lambda values: ", ".join(f"{k} = {list(v) if isinstance(v, tuple) else v!r}"  # noqa: E731
                                     for k, v in values.items())
    return f"""
[material]
model = "flatjoint"
[targets.ucs]
{chr(10).join(f"{name} = {targets[name]!r}" for name in TARGETS)}
[specimen]
{specimen}
[search]
bounds = {{ {table(twin["bounds"])} }}
fixed = {{ {table(twin["fixed"] | STRENGTH_SPREAD)} }}
[surrogate]
samples = 10
checks = 2
[optimizer]
iterations = 60
[acceptance]
tolerance = 0.01
max_dem_runs = 30
[identifiability]
runs = false  # this twin is about its route; the stage has its own tests
"""


def lab_targets(twin: dict, folder) -> dict:
    """The UCS responses at the true parameters, run as the campaign runs them."""
    stand_in = {"E_GPa": 30.0, "ucs_MPa": 50.0}
    campaign = planned(parse_campaign(campaign_text(twin, stand_in), folder))
    run = execute(run_spec("ucs", campaign.specimen, campaign.fixed_params() | twin["true"], "flatjoint"))
    assert run.status == "ok", run.message
    return {name: float(run.responses[name]) for name in TARGETS}


@pytest.fixture(scope="module", params=list(TWINS))
def twin(request, tmp_path_factory):
    """(the twin, its campaign, what the campaign found)."""
    name = request.param
    folder = tmp_path_factory.mktemp(name)
    spec = TWINS[name]
    campaign = planned(parse_campaign(campaign_text(spec, lab_targets(spec, folder)), folder))
    return name, campaign, calibrate(campaign, Executor(RunStore(folder / "out"), workers=1))


def test_the_searched_parameters_are_recovered(twin):
    name, campaign, record = twin
    assert record.accepted, record.errors
    for parameter, truth in TWINS[name]["true"].items():
        assert abs(record.identified[parameter] - truth) <= TWINS[name]["within"][parameter], parameter


@pytest.mark.parametrize("twin", ["fj_nr"], indirect=True)
def test_every_point_run_has_a_whole_number_of_elements(twin):
    """fj_nr is searched as a real number and rounded to a whole one wherever a point is run:
    the samples, the checks and the verified points."""
    name, campaign, record = twin
    k = record.parameters.index("fj_nr")
    points = [*record.samples.x, *record.surrogate_check.x, *(it.x for it in record.iterations)]
    values = {row[k] for row in points}
    assert all(float(v).is_integer() for v in values)
    assert values == {1.0, 2.0, 3.0, 4.0, 5.0}  # the samples reach every count, the ends too
    assert record.identified_params["fj_nr"] == TWINS[name]["true"]["fj_nr"]
