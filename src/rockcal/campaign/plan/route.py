"""The campaign's route, chosen from what its runs cost where the file leaves it open.

A parameter set whose runs cost at least DEAR UCS runs (a notched beam, a confined series, a
direct-tension prism beside the UCS test) takes the multi-fidelity route unless [surrogate]
sets samples or coarse_samples: coarse runs (R_min x coarse_factor, about a tenth of the work)
train the surrogate and a few full-resolution runs correct it, the tests beside UCS at half of
them (unless [surrogate] sets samples_every_test). A verified point that costs at
least DEAR UCS runs (those tests, or several packings) is verified one at a time unless
[acceptance] sets candidates: a second candidate would double each round's cost for a
smaller chance of a second round. Where that point's other tests cost more than its UCS runs,
the UCS runs go first and the others only where the UCS responses met the tolerance, unless
[acceptance] sets ucs_first: a round whose point misses on UCS then costs one UCS run. A
UCS-only campaign keeps the defaults.
"""

from __future__ import annotations

from dataclasses import dataclass

from rockcal.campaign.plan.cost import relative_time
from rockcal.labtests.registry import PRIMARY_TEST

DEAR = 2.0  # UCS runs' time: a parameter set or a verified point this dear changes the defaults
COARSE_PER_PARAMETER = 5  # multi-fidelity: coarse samples per searched parameter
FULL_AFTER_PARAMETERS = 1  # multi-fidelity: full-resolution samples, the searched parameters + this
CHECKS = 1  # multi-fidelity: full-resolution check runs


@dataclass(frozen=True)
class Route:
    """What the defaults became and why, and the campaign the other route would run."""

    name: str  # "multi-fidelity" or "single fidelity, one candidate a round"
    why: str
    other: object  # the Campaign with the defaults as they were
    other_name: str


def sample_cost(campaign) -> float:
    """A parameter set's runs in UCS runs' time: every test calibrated against, once per value
    of its series, on one packing (as the surrogate's samples run)."""
    return sum(len(campaign.target_sections()[t].series() or [None]) * relative_time(campaign, t)
               for t in campaign.target_sections())


def point_cost(campaign, tests: list[str] | None = None) -> float:
    """A verified point's runs (of `tests`, default all) in UCS runs' time: `sample_cost` on
    each test's packings."""
    return sum(s.packings * len(s.series() or [None]) * relative_time(campaign, t)
               for t, s in campaign.target_sections().items() if tests is None or t in tests)


def with_route(campaign, coarse_possible: bool = True):
    """The campaign with the defaults its file leaves open set from its runs' cost, and its
    `route` (None for a campaign whose defaults stay); `coarse_possible`: its specimens can be
    made at the coarse resolution."""
    surrogate, acceptance = campaign.surrogate, campaign.acceptance
    sample, point = sample_cost(campaign), point_cost(campaign)
    multi = (sample >= DEAR and coarse_possible
             and not ({"samples", "coarse_samples"} & surrogate.model_fields_set))
    one = point >= DEAR and "candidates" not in acceptance.model_fields_set
    if not (multi or one):
        return campaign
    update = {}
    # the tests beside UCS are the dearer part of a verified point: verify UCS first
    others = [t for t in campaign.target_sections() if t != PRIMARY_TEST]
    first = (one and point_cost(campaign, others) > point_cost(campaign, [PRIMARY_TEST])
             and "ucs_first" not in acceptance.model_fields_set)
    if one:
        update["acceptance"] = acceptance.model_copy(update={"candidates": 1, **({"ucs_first": True} if first else {})})
    if multi:
        n = len(campaign.search.bounds) or len(campaign.sensitivity.levels)
        samples = n + FULL_AFTER_PARAMETERS
        # the dear tests' corrections (a ratio and a smooth rest) need fewer full-size runs
        every = max(2, samples // 2) if others else None
        update["surrogate"] = surrogate.model_copy(update={
            "coarse_samples": COARSE_PER_PARAMETER * n, "samples": samples,
            **({} if "checks" in surrogate.model_fields_set else {"checks": CHECKS}),
            **({} if "samples_every_test" in surrogate.model_fields_set else {"samples_every_test": every})})
    chosen = campaign.model_copy(update=update)
    reasons = []
    if multi:
        u = update["surrogate"]
        others = "" if u.samples_every_test is None else f" (the other tests at {u.samples_every_test} of them)"
        reasons.append(f"a parameter set's runs take {sample:.2g} UCS runs' time: {u.coarse_samples} coarse runs "
                       f"(R_min x {u.coarse_factor:g}) train the surrogate, {u.samples} full-resolution ones{others} "
                       f"and {u.checks} check{'s' if u.checks != 1 else ''} correct it")
    if one:
        reasons.append(("" if multi and point == sample else f"a verified point's runs take {point:.2g} UCS runs' "
                        "time: ") + "one point is verified a round"
                       + (", its UCS test first and the others only where UCS meets the tolerance" if first else ""))
    why = "; ".join(reasons) + (" ([surrogate] samples, coarse_samples or samples_every_test, [acceptance] candidates"
                                + (" and ucs_first" if first else "") + " choose otherwise)")
    chosen._route = (Route("multi-fidelity", why, campaign, "single fidelity") if multi else
                     Route("one candidate a round", why, campaign, f"{acceptance.candidates} candidates a round"))
    return chosen


def route_of(campaign) -> Route | None:
    """The route `with_route` chose (None: the defaults stayed)."""
    return getattr(campaign, "_route", None)
