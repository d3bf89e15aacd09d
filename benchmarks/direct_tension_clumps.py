"""Direct tension of balls and of clumps: sigma_t of a small prism (20 x 40 mm, R_min 0.4 mm
by default) of balls, two-pebble and three-pebble clumps on three packings (seeds 1-3) at the
default parameters, and with `--half-speed` at half the loading speed too, one thread.

Run by hand: `python benchmarks/direct_tension_clumps.py [--width-mm 20] [--rmin-mm 0.4] [--half-speed]`.
"""

import argparse
import json

import numba

import rockcal
from rockcal.labtests.direct_tension import simulate_direct_tension
from rockcal.params import MicroParams

SHAPES = ("ball", "two-pebble", "three-pebble")
SEEDS = (1, 2, 3)


def run(params, spec, rate_factor: float = 1.0) -> dict:
    """One run's sigma_t (MPa), steps and bonds broken."""
    r = simulate_direct_tension(params, spec, rate_factor=rate_factor)
    return {"sigma_t_MPa": round(r.sigma_t_direct_MPa, 2), "steps": r.steps,
            "broken": r.n_broken_tension + r.n_broken_shear}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--width-mm", type=float, default=20.0)
    parser.add_argument("--rmin-mm", type=float, default=0.4)
    parser.add_argument("--half-speed", action="store_true", help="each run at half the speed too")
    args = parser.parse_args()
    numba.set_num_threads(1)
    params = MicroParams()
    rows = []
    for shape in SHAPES:
        for seed in SEEDS:
            spec = rockcal.random_packing(args.width_mm, 2 * args.width_mm, args.rmin_mm, seed=seed,
                                          grain_shape=shape)
            row = {"shape": shape, "seed": seed, "grains": int(spec.n_grains), **run(params, spec)}
            if args.half_speed:
                half = run(params, spec, 0.5)
                row["half_speed_change_pct"] = round(100 * (half["sigma_t_MPa"] / row["sigma_t_MPa"] - 1), 2)
            rows.append(row)
            print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
