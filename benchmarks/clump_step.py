"""A clumped step against a ball step: the UCS test on a specimen of balls and on specimens of
clumps (each template of `rockcal.materials.clump_templates`) of the same size, R_min and seed, each
timed by its own clock on one thread; the time per step per pebble (a ball is one pebble) and
its ratio to the balls', measured in the same run; with `--fresh`, each specimen is made anew
(not from the cache) and its genesis timed too.

Run by hand: `python benchmarks/clump_step.py [--width-mm 20] [--rmin-mm 0.4] [--threads 1] [--fresh]`.
"""

import argparse
import json
import time

import numba

import rockcal
from rockcal.materials.clump_templates import GRAIN_SHAPES
from rockcal.params import MicroParams


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--width-mm", type=float, default=20.0)
    parser.add_argument("--rmin-mm", type=float, default=0.4)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--fresh", action="store_true", help="make every specimen anew and time its genesis")
    args = parser.parse_args()
    numba.set_num_threads(args.threads)
    params = MicroParams()
    rows = {}
    for shape in GRAIN_SHAPES:
        started = time.perf_counter()
        spec = rockcal.random_packing(args.width_mm, 2 * args.width_mm, args.rmin_mm, seed=1, grain_shape=shape,
                                      cache=not args.fresh)
        genesis_s = time.perf_counter() - started
        rockcal.simulate_ucs(params, rockcal.random_packing(10, 20, 0.5, seed=1, grain_shape=shape))  # compile
        result = rockcal.simulate_ucs(params, spec)
        rows[shape] = {"grains": int(spec.n_grains), "pebbles": int(spec.n_particles), "steps": result.steps,
                       "wall_s": round(result.wall_s, 2), **({"genesis_s": round(genesis_s, 1)} if args.fresh else {}),
                       "ns_per_pebble_step": 1e9 * result.wall_s / (spec.n_particles * result.steps)}
    ball = rows["ball"]["ns_per_pebble_step"]
    for row in rows.values():
        row["over_ball"] = round(row["ns_per_pebble_step"] / ball, 3)
        row["ns_per_pebble_step"] = round(row["ns_per_pebble_step"], 1)
    print(json.dumps({"threads": args.threads, "width_mm": args.width_mm, "rmin_mm": args.rmin_mm, **rows}, indent=2))


if __name__ == "__main__":
    main()
