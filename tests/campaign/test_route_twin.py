"""A twin with a dear target: UCS (E, nu, UCS) and notched-beam bending (K_IC) targets made by
the engine at known E_c, kn/ks and sigma_c, on the campaign's own specimens and seed. The plain
file (no [surrogate] section) takes the multi-fidelity route (`plan.route`): coarse runs train
the surrogate, a few full-resolution runs correct it; the same file with [surrogate] samples
set keeps the single-fidelity route. Both recover every parameter within 5 %, the
multi-fidelity route with fewer full-resolution runs."""

import pytest

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.plan.route import COARSE_PER_PARAMETER, FULL_AFTER_PARAMETERS, route_of
from rockcal.campaign.plan.screen import describe
from rockcal.campaign.procedure.steps import calibrate
from rockcal.campaign.runs.pool import Executor, execute
from rockcal.campaign.runs.spec import run_spec
from rockcal.campaign.runs.store import RunStore

pytestmark = pytest.mark.slow  # DEM campaigns of a minute or so: deselect with -m "not slow"

TRUE = {"E_c": 20.0, "kn_ks": 2.0, "sigma_c": 40.0}
# tau_c 1.5 x sigma_c: at the default 90 MPa this prism's UCS jumps by 10 % between points 0.5 %
# apart (151 to 173 MPa), too rough a surface for targets met within 3 %; at 60 MPa it moves
# smoothly (119 to 122 MPa), and K_IC follows sigma_c (the beam breaks in tension)
FIXED = {"tau_c": 60.0, "mu": 0.5}
RECOVERED_WITHIN = 0.05  # the requirement
# a 10 x 20 mm UCS prism and a notched beam at 2/3 of tests/test_bending.py's small one
# (S/W = 3.2, a/W = 0.36 as at full size), both of R_min 0.25 mm: about 520 and 1 100 grains,
# a second or so a run; coarse (R_min 0.5 mm) the beam keeps about 280 grains and breaks too
SPECIMEN = {"width_mm": 10, "height_mm": 20, "rmin_mm": 0.25, "seed": 1, "beam_length_mm": 44,
            "beam_height_mm": 10, "notch_mm": 3.6, "notch_width_mm": 0.8, "span_mm": 32}
SINGLE_FIDELITY_SAMPLES = 12


def campaign_text(targets: dict, surrogate: str = "") -> str:
    specimen = "\n".join(f"{k} = {v!r}" for k, v in SPECIMEN.items())
    return f"""
[targets.ucs]
E_GPa = {targets["E_GPa"]!r}
nu = {targets["nu"]!r}
ucs_MPa = {targets["ucs_MPa"]!r}
[targets.bending]
K_IC_MPa_sqrt_m = {targets["K_IC_MPa_sqrt_m"]!r}
[validation]
tests = []
[specimen]
{specimen}
[search]
bounds = {{ E_c = [15, 25], kn_ks = [1.5, 2.5], sigma_c = [30, 50] }}
fixed = {{ tau_c = {FIXED["tau_c"]!r}, mu = {FIXED["mu"]!r} }}
{surrogate}
[acceptance]
tolerance = 0.03
max_dem_runs = 40
[identifiability]
runs = false  # this twin is about its route; the stage has its own tests
"""


@pytest.fixture(scope="module")
def lab(tmp_path_factory):
    """The lab targets: one UCS run and one bending run at TRUE, as the campaign runs them
    (its specimen settings, seed and fixed parameters: the same run specs)."""
    stand_in = {"E_GPa": 30.0, "nu": 0.2, "ucs_MPa": 100.0, "K_IC_MPa_sqrt_m": 1.0}
    campaign = planned(parse_campaign(campaign_text(stand_in), tmp_path_factory.mktemp("lab")))
    params = campaign.fixed_params() | TRUE
    targets = {}
    for test, names in (("ucs", ("E_GPa", "nu", "ucs_MPa")), ("bending", ("K_IC_MPa_sqrt_m",))):
        run = execute(run_spec(test, campaign.specimen, params, campaign.material.model))
        assert run.status == "ok", run.message
        targets |= {name: float(run.responses[name]) for name in names}
        if test == "bending":  # the beam breaks at its notch: the crack starts above the notch's tip
            cracks = 1e3 * run.cracks[:, :2]
            assert len(cracks) and abs(cracks[:, 0] - SPECIMEN["beam_length_mm"] / 2).max() < 2.0
            assert cracks[:, 1].min() < SPECIMEN["notch_mm"] + 1.5
    assert targets["K_IC_MPa_sqrt_m"] > 0
    return targets


@pytest.fixture(scope="module")
def multi(lab, tmp_path_factory):
    folder = tmp_path_factory.mktemp("multi")
    campaign = planned(parse_campaign(campaign_text(lab), folder))
    return campaign, calibrate(campaign, Executor(RunStore(folder / "out"), workers=1))


@pytest.fixture(scope="module")
def single(lab, tmp_path_factory):
    folder = tmp_path_factory.mktemp("single")
    campaign = planned(parse_campaign(campaign_text(lab, f"[surrogate]\nsamples = {SINGLE_FIDELITY_SAMPLES}"), folder))
    return campaign, calibrate(campaign, Executor(RunStore(folder / "out"), workers=1))


def full_resolution_runs(record) -> int:
    """The parameter sets run at the campaign's R_min (a coarse one is no full-resolution run)."""
    return record.dem_runs - (len(record.coarse_samples.x) if record.coarse_samples else 0)


def test_the_plain_file_takes_the_multi_fidelity_route_and_says_so(lab, tmp_path):
    campaign = planned(parse_campaign(campaign_text(lab), tmp_path))
    assert route_of(campaign).name == "multi-fidelity"
    n = len(TRUE)
    s = campaign.surrogate
    assert (s.coarse_samples, s.samples) == (COARSE_PER_PARAMETER * n, n + FULL_AFTER_PARAMETERS)
    screen = "\n".join(describe(campaign, RunStore(tmp_path / "out"), None))
    assert f"coarse samples {2 * COARSE_PER_PARAMETER * n} (R_min 0.5 mm)" in screen  # a UCS and a beam each
    assert "route: multi-fidelity" in screen
    other = planned(parse_campaign(campaign_text(lab, f"[surrogate]\nsamples = {SINGLE_FIDELITY_SAMPLES}"), tmp_path))
    assert other.surrogate.coarse_samples == 0
    assert route_of(other).name == "one candidate a round"


@pytest.mark.parametrize("route", ["multi", "single"])
def test_each_route_recovers_the_true_parameters(route, request):
    campaign, record = request.getfixturevalue(route)
    assert record.accepted
    assert all(abs(e) <= campaign.acceptance.tolerance for e in record.errors.values())
    for name, truth in TRUE.items():
        assert record.identified[name] == pytest.approx(truth, rel=RECOVERED_WITHIN), name


def test_the_multi_fidelity_route_uses_fewer_full_resolution_runs(multi, single):
    (_, mf), (_, sf) = multi, single
    assert mf.coarse_samples is not None and len(mf.coarse_samples.x) == COARSE_PER_PARAMETER * len(TRUE)
    assert sf.coarse_samples is None
    assert full_resolution_runs(mf) < full_resolution_runs(sf)
