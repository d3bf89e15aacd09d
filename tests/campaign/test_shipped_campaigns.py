"""The campaign files shipped in docs/ and shown in the README load; the tough granite differs
from the embedded one only in what its header says; the tutorial's campaign runs as the
tutorial says."""

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from rockcal.campaign.input.config import load_campaign, parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.plan.screen import specimens_to_make

DOCS = Path(__file__).parents[2] / "docs" / "campaigns"


def test_the_tough_granite_differs_from_the_embedded_one_only_in_its_settings_and_box():
    """Its three settings, and PFC 5's contacts on which it was measured."""
    granite, _ = load_campaign(None)
    tough, _ = load_campaign(str(DOCS / "granite-tough.toml"))
    changed_specimen = {k for k, v in tough.specimen.model_dump().items()
                        if granite.specimen.model_dump()[k] != v}
    assert changed_specimen == {"install_gap", "notch_width_mm", "contact_stiffness"}
    assert tough.specimen.contact_stiffness == "pfc5"
    assert (tough.specimen.install_gap, tough.specimen.notch_width_mm) == (1.1, 0.0)
    assert tough.search.fixed == {"tau_c": 90.0, "mu": 0.5}  # constant strengths
    assert tough.sensitivity is None and tough.search.bounds["sigma_c"] == (10.0, 28.0)
    assert tough.targets == granite.targets and tough.rock == granite.rock


ROOT = Path(__file__).parents[2]


def readme_campaign() -> str:
    """The campaign file the README shows (its one TOML block)."""
    text = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```toml\n(.*?)```", text, flags=re.S)
    assert len(blocks) == 1
    return blocks[0]


def test_the_readme_campaign_is_a_valid_campaign_of_about_twenty_lines():
    campaign = planned(parse_campaign(readme_campaign(), ROOT))
    assert set(campaign.target_sections()) == {"ucs"} and campaign.validation_tests() == ["bending"]
    assert campaign.wants_uncertainty() and set(campaign.search.bounds) == {"E_c", "kn_ks", "sigma_c"}
    assert len(readme_campaign().strip().splitlines()) <= 25


def test_the_tutorial_campaign_runs_on_the_shipped_half_resolution_specimens():
    """So the tutorial starts at once: every specimen it needs ships with rockcal."""
    tutorial = planned(load_campaign(str(DOCS / "tutorial.toml"))[0])
    granite, _ = load_campaign(None)
    assert tutorial.targets == granite.targets
    assert tutorial.specimen.rmin_mm == 0.5 and tutorial.specimen.bending_seeds == 1
    assert not specimens_to_make(tutorial)


@pytest.mark.slow
def test_the_tutorial_campaign_runs_end_to_end(tmp_path):
    """The tutorial's commands: calibrate (as its quick look, at R_min 1 mm: seconds rather
    than minutes), report, export, export-specimen."""
    out = tmp_path / "tutorial"

    def rockcal(*args):
        run = subprocess.run([sys.executable, "-m", "rockcal", *map(str, args)], capture_output=True,
                             text=True, timeout=1800)
        assert run.returncode == 0, run.stderr
        return run.stdout

    result = json.loads(rockcal("calibrate", DOCS / "tutorial.toml", "--quick", "--out", out, "--json"))
    assert result["accepted"] and result["rock"] == "tutorial-granite"
    assert all(abs(e) <= 0.05 for e in result["relative_errors"].values())
    assert set(result["intervals"]) == {"E_c", "kn_ks", "sigma_c"} and result["K_IC_MPa_sqrt_m"] > 0
    assert (out / "report.html").exists() and (out / "parameter_draws.png").exists()
    fish = rockcal("export", out, "--format", "pfc-fish")
    assert "pbm_emod" in fish and "mpSetPBParams" in fish
    rockcal("export-specimen", out, "--to", tmp_path / "specimen")
    assert (tmp_path / "specimen" / "balls.csv").exists() and (tmp_path / "specimen" / "bonds.csv").exists()


def test_an_embedded_rock_is_taken_by_name_and_an_unknown_name_is_refused(tmp_path, monkeypatch):
    from rockcal.campaign.input.config import embedded_rocks
    from rockcal.errors import InputError

    monkeypatch.chdir(tmp_path)
    assert "granite" in embedded_rocks()
    for rock in embedded_rocks():
        campaign, _ = load_campaign(rock)
        assert campaign.rock.name.lower().startswith(rock[:3])
    assert load_campaign("granite") == load_campaign(None)
    with pytest.raises(InputError, match="no embedded rock of that name") as error:
        load_campaign("granit")
    assert error.value.field == "CONFIG"


def test_the_multi_fidelity_granite_differs_from_the_embedded_one_only_in_its_surrogate():
    granite, _ = load_campaign(None)
    multi, _ = load_campaign(str(DOCS / "granite-multifidelity.toml"))
    assert multi.model_dump(exclude={"surrogate"}) == granite.model_dump(exclude={"surrogate"})
    assert (multi.surrogate.coarse_samples, multi.surrogate.samples, multi.surrogate.checks) == (20, 4, 2)


def test_the_all_targets_granite_fits_k_ic_and_searches_the_installation_gap():
    granite, _ = load_campaign(None)
    every, _ = load_campaign(str(DOCS / "granite-all-targets.toml"))
    assert every.validation_tests() == [] and set(every.target_sections()) == {"ucs", "bending"}
    assert "install_gap" in every.search.bounds and every.surrogate.coarse_samples > 0
    assert every.targets.ucs.packings == 3  # the UCS of constant bond strengths, over packings
    assert every.targets.ucs.model_copy(update={"packings": 1}) == granite.targets.ucs
    assert every.targets.bending == granite.targets.bending


def test_the_3d_all_targets_granite_fits_the_2d_ones_lab_values_on_spheres_and_plans_its_first_screen(cli, tmp_path):
    """The 2D all-targets granite's four lab values (their spread left out, as the 3D granite's:
    no uncertainty stage) on the 3D granite's cylinder and a 3D beam
    at its default thickness, the gap searched; the beam dear, so multi-fidelity with the beam
    on only some of the full-resolution samples. Its dry run plans without a run."""
    every, _ = load_campaign(str(DOCS / "granite-3d-all-targets.toml"))
    two_d, _ = load_campaign(str(DOCS / "granite-all-targets.toml"))
    three_d, _ = load_campaign(str(DOCS / "granite-3d.toml"))
    assert every.targets.bending == two_d.targets.bending and every.validation_tests() == []
    assert every.targets.ucs == two_d.targets.ucs.model_copy(update={"spread": three_d.targets.ucs.spread})
    assert every.specimen.dimensions == 3 and every.specimen.beam_thickness_mm is None
    assert {k: getattr(every.specimen, k) for k in ("width_mm", "height_mm", "rmin_mm")} == \
        {k: getattr(three_d.specimen, k) for k in ("width_mm", "height_mm", "rmin_mm")}
    assert "install_gap" in every.search.bounds and every.surrogate.coarse_samples > 0
    assert 0 < every.surrogate.samples_every_test < every.surrogate.samples
    run = cli("calibrate", DOCS / "granite-3d-all-targets.toml", "--dry-run", "--out", tmp_path / "out")
    assert run.returncode == 0, run.stderr
    assert "21.12 mm thick" in run.stdout and not (tmp_path / "out").exists()


def test_the_3d_lac_du_bonnet_fits_the_embedded_ones_sheet_and_search_on_spheres_and_plans_its_first_screen(cli, tmp_path):
    """The embedded ldb campaign's targets, material, search and optimizer on 3D cylinders and
    a disk small enough for about an hour on 2 cores (coarse runs at 1.5 R_min, the coarsest the
    disk allows), no DEM runs after the search; its dry run plans without a run."""
    ldb, _ = load_campaign("ldb")
    three_d, _ = load_campaign(str(DOCS / "ldb-3d.toml"))
    same = {"targets", "material", "search", "optimizer", "validation"}
    assert three_d.model_dump(include=same) == ldb.model_dump(include=same)
    assert three_d.specimen.dimensions == 3 and three_d.surrogate.coarse_factor == 1.5
    assert three_d.uncertainty.packings == 1 and not three_d.identifiability.runs
    assert (three_d.specimen.width_mm, three_d.specimen.height_mm, three_d.specimen.rmin_mm) == (10, 20, 0.5)
    run = cli("calibrate", DOCS / "ldb-3d.toml", "--dry-run", "--out", tmp_path / "out")
    assert run.returncode == 0, run.stderr
    assert "disk D 20 x t 10 mm" in run.stdout and not (tmp_path / "out").exists()


def test_the_flat_jointed_granite_has_the_embedded_granites_rock_targets_and_specimen():
    """So the rock lab can set the two materials side by side at calibrated points."""
    granite, _ = load_campaign(None)
    flat, _ = load_campaign(str(DOCS / "granite-flatjoint.toml"))
    assert flat.material.model == "flatjoint"
    assert flat.targets.ucs == granite.targets.ucs and flat.rock == granite.rock
    same = {"rmin_mm", "radius_ratio", "seed", "width_mm", "height_mm", "install_gap", "cloud_porosity",
            "pressure_mpa", "strain", "stop_fraction", "disk_diameter_mm"}
    assert {k: getattr(flat.specimen, k) for k in same} == {k: getattr(granite.specimen, k) for k in same}


def test_the_narrow_gap_3d_granite_differs_from_the_3d_granite_only_in_its_gap_and_box():
    """Bonded at 0.125 R_min (the 3D examples' gap in Itasca's FISHTank files) in place of the
    default 0.6: fewer bonds per sphere, so the box reaches to stiffer, stronger bonds."""
    default, _ = load_campaign(str(DOCS / "granite-3d.toml"))
    narrow, _ = load_campaign(str(DOCS / "granite-3d-narrow-gap.toml"))
    assert default.specimen.install_gap == 0.6 and narrow.specimen.install_gap == 0.125
    assert narrow.specimen.model_copy(update={"install_gap": 0.6}) == default.specimen
    assert narrow.model_dump(exclude={"specimen", "search", "rock"}) == \
        default.model_dump(exclude={"specimen", "search", "rock"})
    assert narrow.search.fixed == default.search.fixed
    assert narrow.rock.model_copy(update={"name": default.rock.name}) == default.rock
    assert all(narrow.search.bounds[k][1] >= default.search.bounds[k][1] for k in default.search.bounds)


@pytest.mark.parametrize("page, heading, shown", [
    ("docs/tutorial.md", "## 2. The campaign file", "docs/campaigns/tutorial.toml"),
    ("docs/reference/campaign-file.md", "## An example", "src/rockcal/campaign/input/granite.toml")])
def test_a_page_shows_its_campaign_file_as_the_file_is(page, heading, shown):
    """The tutorial's campaign and the campaign file's example are written out on their pages
    (so GitHub shows them too): each is its file, word for word."""
    after = (ROOT / page).read_text().split(heading, 1)[1]
    assert re.search(r"```toml\n(.*?)```", after, flags=re.S).group(1) == (ROOT / shown).read_text()
