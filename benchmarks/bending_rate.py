"""The validation beams' rate check: the embedded granite campaign's full-size beams (its
specimen settings, its seed and the next N - 1) at a point, at the pin's speed and at half of it.

Run by hand: `python benchmarks/bending_rate.py [--seeds 3] [--first-seed 1] [--rates 1 0.5] [--intact-speed 2]
[--set E_c=21.42 --set kn_ks=1.970 --set sigma_c=36.28]` (one thread per beam, the beams one
after the other; about 5 min per beam on one core). Prints each beam's K_IC, P_max and steps,
then each rate's three-beam mean and its change against the first rate.
`--intact-speed` sets the pin's speed factor until the first bond breaks
(`bending.INTACT_PIN_SPEED`, for comparing loading rules).
"""

import argparse
import json

import numpy as np

from rockcal.campaign.input.config import load_campaign
from rockcal.campaign.runs.pool import specimen_of
from rockcal.campaign.runs.spec import run_spec
from rockcal.labtests import bending
from rockcal.labtests.seeds import seed_list
from rockcal.params import make_params, parse_assignments

CAMPAIGN_POINT = {"E_c": 21.42, "kn_ks": 1.970, "sigma_c": 36.28}  # an identified point of the granite campaign, rounded


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--first-seed", type=int, default=None, help="default: the campaign's seed")
    parser.add_argument("--rates", type=float, nargs="+", default=[1.0, 0.5])
    parser.add_argument("--intact-speed", type=float, default=bending.INTACT_PIN_SPEED)
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    args = parser.parse_args()
    point = CAMPAIGN_POINT | parse_assignments(args.set)
    bending.INTACT_PIN_SPEED = args.intact_speed
    campaign, _ = load_campaign(None)
    seeds = seed_list(args.first_seed or campaign.specimen.seed, args.seeds)
    k_ic = {}
    for rate in args.rates:
        for seed in seeds:
            settings = campaign.specimen.model_copy(update={"seed": seed})
            spec = run_spec("bending", settings, campaign.fixed_params() | point)
            s = dict(spec.specimen)
            result = bending.simulate_bending(
                make_params(dict(spec.params)), specimen_of("bending", spec.specimen),
                bending.beam_of(s), rate_factor=rate, stop_fraction=s["stop_fraction"],
                contact_stiffness=s["contact_stiffness"])
            k_ic[rate, seed] = result.K_IC_MPa_sqrt_m
            print(json.dumps({"rate_factor": rate, "seed": seed, "intact_speed": args.intact_speed,
                              "K_IC_MPa_sqrt_m": round(result.K_IC_MPa_sqrt_m, 4),
                              "P_max_kN_per_m": round(result.P_max_kN_per_m, 2),
                              "steps": result.steps, "wall_s": round(result.wall_s, 1)}), flush=True)
    mean = {rate: np.mean([k_ic[rate, s] for s in seeds]) for rate in args.rates}
    first = mean[args.rates[0]]
    for rate in args.rates:
        print(f"rate {rate:g}: mean K_IC {mean[rate]:.4f} MPa m^0.5 "
              f"({100 * (mean[rate] / first - 1):+.2f} %)")


if __name__ == "__main__":
    main()
