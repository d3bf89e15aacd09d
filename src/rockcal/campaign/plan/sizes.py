"""The grains of every specimen a campaign will make, estimated before any genesis and refused
past the limit (`rockcal.specimens.grain_limit`), naming the campaign file's section."""

from __future__ import annotations

from rockcal.campaign.plan.screen import specimens
from rockcal.specimens.grain_limit import check_grains, expected_grains
from rockcal.errors import fields_named
from rockcal.labtests.registry import lab_test


def check_campaign_sizes(campaign) -> None:
    """InputError when a specimen of the campaign (its sensitivity runs' too) would hold more
    grains than the limit."""
    for test, settings in specimens(campaign):
        kind, p = lab_test(test), lab_test(test).packing(settings)
        coarse = campaign.sensitivity is not None and settings.rmin_mm != campaign.specimen.rmin_mm
        field = "sensitivity.rmin_mm" if coarse else "specimen"
        if settings.dimensions == 3:  # the test's own check counts the spheres of its vessel
            with fields_named(lambda key: field if key == "rmin_mm" else f"specimen.{key}"):
                kind.check(kind.settings_of(settings))
            continue
        grains = expected_grains(p["width_mm"], p["height_mm"], p["rmin_mm"], p["radius_ratio"],
                                 p["genesis"].cloud_porosity)
        check_grains(field, f"the {lab_test(test).title} specimen's packing ({p['width_mm']:g} x "
                            f"{p['height_mm']:g} mm, R_min {p['rmin_mm']:g} mm)", grains)
