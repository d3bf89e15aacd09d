"""The campaign files shipped in docs/ load, and differ from the embedded granite only in what
their header says."""

from pathlib import Path

from rockcal.campaign.config import load_campaign

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
