"""The last step's parts of a result, from the runs at the identified point: the parameters'
intervals (the packings' scatter and the lab's spread), the curve fit, the validation of K_IC
over packings and the other validation checks against the lab's values."""

from __future__ import annotations

import numpy as np

from rockcal.campaign.input.config import Campaign
from rockcal.campaign.procedure.points import grouped, optimise, point_responses, spec_of
from rockcal.campaign.procedure.result import Check, CurveFit, Uncertainty, BendingValidation
from rockcal.inverse import Objective, curve_fit
from rockcal.inverse.uncertainty import parameter_intervals
from rockcal.labtests.kic import pmax_kic_disagreement
from rockcal.labtests.registry import PRIMARY_TEST, lab_test
from rockcal.labtests.seeds import mean_over_seeds

KIC_TEST = "bending"  # the validation whose record is `BendingValidation`: K_IC over packings


def uncertainty_of(state, packings: list, specs: list, done: dict, surrogate, progress) -> Uncertainty:
    """The model's scatter over packings at the identified point (relative sd of each
    response), then the parameters' intervals for targets drawn from the lab's spread and
    that scatter (`rockcal.inverse.uncertainty`), each solved on the surrogate."""
    campaign, goals, u = state.campaign, state.goals, state.campaign.uncertainty
    per_point = grouped(state, packings, [done[spec.key] for spec in specs], means=True)
    found = [point_responses(state, runs)[0] for runs in per_point]
    ok = [responses for responses in found if responses is not None]
    scatter = {r: float(np.std([v[r] for v in ok], ddof=1) / abs(np.mean([v[r] for v in ok])))
               if len(ok) > 1 else 0.0 for r in goals.targets}
    count = [0]

    def solve(targets: dict) -> np.ndarray:
        count[0] += 1
        progress("uncertainty (draws)", count[0], u.draws)
        return optimise(campaign, Objective(surrogate.predict, targets, weights=goals.weights or None), state.box).x

    return Uncertainty(
        seeds=[settings.seed for settings, _ in packings], run_keys=[spec.key for spec in specs],
        packing_responses=ok, scatter=scatter, spread=goals.spread, draws=u.draws,
        **parameter_intervals(solve, goals.targets, goals.spread, scatter, state.box, state.names,
                              draws=u.draws, seed=u.seed))


def curve_fit_of(state, identified: dict) -> CurveFit | None:
    """The RE and CC of the primary test's stress-strain curve at the identified parameters
    against the measured one (the simulated strain may dither at the start: only the points
    that advance it are kept); None without a measured curve or a curve of that run."""
    key = spec_of(state, PRIMARY_TEST, state.campaign.specimen, identified).key
    curve = state.curves.get(key)
    if state.goals.curve is None or curve is None:
        return None
    strain, stress = curve[:, 0], curve[:, 2]
    ahead = strain > np.maximum.accumulate(np.concatenate([[-np.inf], strain[:-1]]))
    fit = curve_fit(strain[ahead], stress[ahead], state.goals.curve[:, 0], state.goals.curve[:, 1])
    return CurveFit(RE=fit.RE, CC=fit.CC)


def validation_of(campaign: Campaign, specs: list | None, done: dict) -> BendingValidation | None:
    """The K_IC validation over packings against the lab's K_IC (None unless the bending test
    is a validation check), with the lab's own P_max / K_IC cross-check."""
    if specs is None:
        return None
    lab = campaign.targets.given()[KIC_TEST]
    seeds = [dict(spec.specimen)["seed"] for spec in specs]
    results = [done[spec.key] for spec in specs]
    ok = [(seed, spec, r) for seed, spec, r in zip(seeds, specs, results) if r.status == "ok"]
    found = {"lab_K_IC_MPa_sqrt_m": lab.K_IC_MPa_sqrt_m, "seeds": seeds, "run_keys": [s.key for s in specs]}
    if ok:
        found |= {"status": "ok", "run_key": ok[0][1].key, "ok_seeds": [s for s, _, _ in ok],
                  "K_IC_per_seed": [r.responses["K_IC_MPa_sqrt_m"] for _, _, r in ok]}
        found |= mean_over_seeds([r.responses for _, _, r in ok])
        found["K_IC_error"] = found["K_IC_MPa_sqrt_m"] / lab.K_IC_MPa_sqrt_m - 1
    else:
        found |= {"status": results[0].status, "message": results[0].message, "run_key": specs[0].key}
    if lab.P_max_kN is not None:
        found["warning"] = pmax_kic_disagreement(
            1e3 * lab.P_max_kN, 1e6 * lab.K_IC_MPa_sqrt_m, 1e-3 * lab.diameter_mm,
            1e-3 * lab.notch_mm, 1e-3 * lab.span_mm)
    return BendingValidation(**found)


def checks_of(campaign: Campaign, validation: dict[str, list], done: dict) -> list[Check] | None:
    """Each other validation test: its run (or its series of runs) at the identified
    parameters, on the campaign's packing, against the lab's values (None when there is none)."""
    checks = []
    for test, specs in validation.items():
        if test == KIC_TEST:
            continue
        section = campaign.targets.given()[test]
        lab, values = section.scalars(), section.series()
        runs = [done[spec.key] for spec in specs[:max(1, len(values))]]
        failed = next((run for run in runs if run.status != "ok"), None)
        found = {"test": test, "lab": lab, "run_key": specs[0].key,
                 "status": "ok" if failed is None else failed.status}
        if failed is not None:
            found["message"] = failed.message
        else:
            try:
                responses = runs[0].responses if not values else \
                    lab_test(test).point_responses([run.responses for run in runs], values)
                found |= {"responses": responses, "errors": {r: responses[r] / v - 1 for r, v in lab.items()}}
            except Exception as exc:  # a series its test cannot combine (peaks that give no envelope)
                found |= {"status": "failed", "message": f"{type(exc).__name__}: {exc}"}
        checks.append(Check(**found))
    return checks or None
