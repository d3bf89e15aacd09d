"""The route a campaign takes where its file leaves the defaults open (`plan.route`): a dear
parameter set (a beam beside the UCS test) trains on coarse runs and verifies one point a round;
a UCS-only campaign keeps the defaults; what the file sets stays."""

import json

import pytest

from rockcal.campaign.input.config import Surrogate, load_campaign, parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.plan.quick_look import quick_look
from rockcal.campaign.plan.route import COARSE_PER_PARAMETER, route_of
from rockcal.cli.app import main

UCS_ONLY = """
[targets.ucs]
E_GPa = 20.0
ucs_MPa = 40.0
[specimen]
rmin_mm = 0.4
width_mm = 12
height_mm = 24
beam_length_mm = 48
beam_height_mm = 12
span_mm = 40
notch_mm = 4
disk_diameter_mm = 12
[search]
bounds = { E_c = [10, 30], sigma_c = [20, 60], kn_ks = [1, 3] }
"""
BEAM = "[targets.bending]\nK_IC_MPa_sqrt_m = 1.0\n[validation]\ntests = []\n"


def test_a_ucs_only_campaign_keeps_the_defaults(tmp_path):
    campaign = planned(parse_campaign(UCS_ONLY, tmp_path))
    assert route_of(campaign) is None
    assert campaign.surrogate == Surrogate()
    assert campaign.acceptance.candidates == 2


def test_the_embedded_granite_keeps_its_own_settings():
    granite = planned(load_campaign(None)[0])
    assert route_of(granite) is None
    assert (granite.surrogate.samples, granite.surrogate.coarse_samples, granite.acceptance.candidates) == (15, 0, 2)


def test_a_beam_as_a_target_takes_the_multi_fidelity_route(tmp_path):
    campaign = planned(parse_campaign(UCS_ONLY + BEAM, tmp_path))
    route = route_of(campaign)
    assert route.name == "multi-fidelity"
    s = campaign.surrogate
    assert (s.coarse_samples, s.samples, s.checks) == (3 * COARSE_PER_PARAMETER, 4, 1)
    assert campaign.acceptance.candidates == 1 and campaign.acceptance.ucs_first
    assert route.other.surrogate == Surrogate() and route.other.acceptance.candidates == 2


def test_a_specimen_too_small_for_coarse_runs_stays_on_one_fidelity(tmp_path):
    campaign = planned(parse_campaign(UCS_ONLY.replace("width_mm = 12", "width_mm = 8") + BEAM, tmp_path))
    assert route_of(campaign).name == "one candidate a round"
    assert campaign.surrogate == Surrogate()


def test_a_beam_as_a_check_only_is_no_dearer_than_ucs(tmp_path):
    assert route_of(planned(parse_campaign(UCS_ONLY + "[targets.bending]\nK_IC_MPa_sqrt_m = 1.0\n", tmp_path))) is None


@pytest.mark.parametrize("setting, multi, candidates", [
    ("[surrogate]\nsamples = 12\n", False, 1),
    ("[surrogate]\ncoarse_samples = 0\n", False, 1),
    ("[acceptance]\ncandidates = 3\n", True, 3),
], ids=["samples", "no coarse samples", "candidates"])
def test_what_the_file_sets_stays(setting, multi, candidates, tmp_path):
    campaign = planned(parse_campaign(UCS_ONLY + BEAM + setting, tmp_path))
    assert (campaign.surrogate.coarse_samples > 0) == multi
    assert campaign.acceptance.candidates == candidates


def test_several_packings_verify_one_point_a_round_on_one_fidelity(tmp_path):
    campaign = planned(parse_campaign(UCS_ONLY.replace("ucs_MPa = 40.0", "ucs_MPa = 40.0\npackings = 3"), tmp_path))
    assert route_of(campaign).name == "one candidate a round"
    assert (campaign.surrogate.coarse_samples, campaign.acceptance.candidates) == (0, 1)


def test_the_cost_of_two_candidates_a_round_counts_the_second_optimum(tmp_path):
    """The plan verifies the search's optimum a round on either route: the other route's cost
    says what a second optimum's runs add."""
    from rockcal.campaign.plan.screen import describe
    from rockcal.campaign.runs.store import RunStore

    campaign = planned(parse_campaign(UCS_ONLY.replace("ucs_MPa = 40.0", "ucs_MPa = 40.0\npackings = 3"), tmp_path))
    [cost] = [line for line in describe(campaign, RunStore(tmp_path / "out"), workers=2) if line.startswith("cost: ")]
    ours, other = cost.split("; ")
    assert " when a round verifies" not in ours
    verified, most = (int(n) for n in other.split("about ")[1].split(" when")[0].split(", "))
    assert other.startswith("2 candidates a round: ") and most == verified + 3  # a point on 3 packings


def test_a_quick_look_compares_with_the_other_route_at_its_own_resolution(tmp_path):
    quick = quick_look(planned(parse_campaign(UCS_ONLY.replace("rmin_mm = 0.4", "rmin_mm = 0.2") + BEAM, tmp_path)))
    assert route_of(quick).other.specimen.rmin_mm == quick.specimen.rmin_mm == 0.4


def test_the_dry_run_shows_the_route_and_the_other_routes_cost(tmp_path, monkeypatch, capsys):
    config = tmp_path / "campaign.toml"
    config.write_text(UCS_ONLY + BEAM)
    monkeypatch.setattr("sys.argv", ["rockcal", "calibrate", str(config), "--dry-run", "--json", "--workers", "2"])
    with pytest.raises(SystemExit) as exit:
        main()
    assert exit.value.code == 0
    plan = json.loads(capsys.readouterr().out)
    route = plan["route"]
    assert route["name"] == "multi-fidelity" and route["other"]["name"] == "single fidelity"
    assert route["other"]["ucs_runs_time"] > 2 * plan["ucs_runs_time"]
