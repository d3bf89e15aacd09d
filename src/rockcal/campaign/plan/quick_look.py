"""The quick look (`--quick`): a campaign at half resolution, a first look in minutes on its
own route."""

from __future__ import annotations

from rockcal.campaign.input.config import Campaign, check_specimens
from rockcal.campaign.plan.cost import specimen_size
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.plan.route import route_of

QUICK_RESOLUTION = 2  # `--quick`: R_min this many times the campaign's
QUICK_DRAWS = 50  # `--quick`: at most this many target draws for the parameters' intervals
# a specimen of fewer grains reads responses a few grains decide: a strength on its search
# bound, a disk whose peak breaks no bond; the quick look's note names each such specimen
FEW_GRAINS = 1000


def quick_look(campaign: Campaign) -> Campaign:
    """The campaign as a first look in minutes: R_min doubled (a quarter of the grains), one
    validation beam and at most QUICK_DRAWS searches for the intervals. Its numbers are not the
    full-resolution calibration; its route is chosen from its own costs (that of `campaign`, if
    it is on one, is left)."""
    route = route_of(campaign)
    if route is not None:
        return quick_look(route.other)
    s = campaign.specimen
    specimen = s.model_copy(update={"rmin_mm": QUICK_RESOLUTION * s.rmin_mm, "bending_seeds": 1})
    uncertainty = campaign.uncertainty.model_copy(update={"draws": min(campaign.uncertainty.draws, QUICK_DRAWS)})
    update = {"specimen": specimen, "uncertainty": uncertainty}
    if campaign.sensitivity and (campaign.sensitivity.rmin_mm or 0) <= specimen.rmin_mm:
        update["sensitivity"] = campaign.sensitivity.model_copy(update={"rmin_mm": None})
    quick = campaign.model_copy(update=update)
    check_specimens(quick, quick=True)
    return planned(quick)


def quick_look_note(quick: Campaign) -> str:
    """What a quick look is, in the words of the first screen, the report and the JSON."""
    rmin = quick.specimen.rmin_mm
    beam = " and one validation beam" if "bending" in quick.validation_tests() else ""
    sizes = [specimen_size(test, quick.specimen) for test in quick.tests()]
    few = [f"{text} specimen holds about {grains:,} grains" for text, grains, _ in sizes if grains < FEW_GRAINS]
    warning = f"; warning: the {', the '.join(few)}, fewer than {FEW_GRAINS:,}: too few for its numbers to " \
              "mean much (a strength on its bound, a peak that breaks no bond)" if few else ""
    return (f"quick look: half resolution (R_min {rmin:g} mm, the campaign's "
            f"{rmin / QUICK_RESOLUTION:g} mm doubled){beam}; its numbers are a first look, not the "
            f"full-resolution calibration{warning}")
