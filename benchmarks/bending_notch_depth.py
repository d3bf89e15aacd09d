"""K_IC against notch depth, averaged over packings: the source's beam (220 x 50 mm, span 160 mm)
at a scale, notches 15 and 20 mm deep (at full scale), the source's identified parameters.

Run by hand: `python benchmarks/bending_notch_depth.py [--scale 0.5] [--seeds 3]
[--notch-width-mm 2] [--threads 1]` (notch width at full scale; 0 = a cut).
Prints each run and, per notch, the mean and spread of P_max and K_IC over the packings and the
relative change from the shallow to the deep notch.
"""

import argparse
import json

import numba

from rockcal.labtests.bending import Beam, notched_beam, simulate_bending
from rockcal.labtests.seeds import mean_over_seeds, seed_list

NOTCHES_MM = (15.0, 20.0)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--scale", type=float, default=0.5)
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--notch-width-mm", type=float, default=2.0)
    parser.add_argument("--threads", type=int, default=1)
    args = parser.parse_args()
    numba.set_num_threads(args.threads)

    s = args.scale
    means = {}
    for notch in NOTCHES_MM:
        beam = Beam(220 * s, 50 * s, notch * s, args.notch_width_mm * s, 160 * s)
        runs = []
        for seed in seed_list(1, args.seeds):
            result = simulate_bending({}, notched_beam(beam, 0.25, 1.65, seed), beam)
            runs.append(result.summary())
            print(json.dumps({"notch_mm": notch, "seed": seed} | {
                k: runs[-1][k] for k in ("P_max_kN_per_m", "K_IC_MPa_sqrt_m", "n_particles",
                                         "n_broken_tension", "steps", "wall_s")}), flush=True)
        means[notch] = mean_over_seeds(runs)
    shallow, deep = (means[n] for n in NOTCHES_MM)
    print(json.dumps({
        "scale": s, "notch_width_mm": args.notch_width_mm, "seeds": args.seeds,
        "mean": {n: {k: m[k] for k in ("P_max_kN_per_m", "P_max_kN_per_m_std", "K_IC_MPa_sqrt_m",
                                        "K_IC_MPa_sqrt_m_std")} for n, m in means.items()},
        "P_max_change": deep["P_max_kN_per_m"] / shallow["P_max_kN_per_m"] - 1,
        "K_IC_change": deep["K_IC_MPa_sqrt_m"] / shallow["K_IC_MPa_sqrt_m"] - 1}, indent=2))


if __name__ == "__main__":
    main()
