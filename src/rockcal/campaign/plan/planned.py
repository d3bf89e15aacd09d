"""A campaign as it is planned, shown and run: its file's values, with the defaults the file
leaves open set from its runs' cost (`route`). Parsing leaves those defaults as they are, so
that reading a file never depends on the runs' time model (`cost`)."""

from __future__ import annotations

from rockcal.campaign.input.config import Campaign, check_specimens
from rockcal.campaign.plan.route import with_route
from rockcal.errors import InputError


def planned(campaign: Campaign) -> Campaign:
    """The campaign on its route (`route.with_route`, `route.route_of`)."""
    return with_route(campaign, coarse_possible(campaign))


def coarse_possible(campaign: Campaign) -> bool:
    """The specimens of the campaign's tests can be made at [surrogate] coarse_factor x R_min."""
    coarse = campaign.surrogate.model_copy(update={"coarse_samples": 1})
    try:
        check_specimens(campaign.model_copy(update={"surrogate": coarse}))
    except InputError:
        return False
    return True
