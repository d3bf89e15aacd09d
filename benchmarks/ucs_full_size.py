"""Full-size UCS benchmark: 50 x 100 mm, R_min 0.25 mm (the paper's specimen), granite defaults.

Run by hand: `python benchmarks/ucs_full_size.py [--seed 1] [--threads N] [--rate-factor 0.5]
[--model flatjoint --set fj_emod=30 ...] [--grain-shape two-pebble] [--width-mm 50 --rmin-mm 0.25]`. Prints the packing time, the wall time of the whole
test (warm JIT) and the throughput in particle-steps and bond-steps/s.
"""

import argparse
import json
import time

import numba

import rockcal
from rockcal.materials import DEFAULT_MATERIAL, material
from rockcal.params import parse_assignments


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--threads", type=int, default=numba.config.NUMBA_NUM_THREADS)
    parser.add_argument("--rate-factor", type=float, default=1.0)
    parser.add_argument("--seed", type=int, default=1, help="packing seed")
    parser.add_argument("--model", default=DEFAULT_MATERIAL, help="the material (rockcal.materials)")
    parser.add_argument("--set", action="append", default=[], help="micro-parameter NAME=VALUE")
    parser.add_argument("--width-mm", type=float, default=50.0, help="the specimen's width (height: twice it)")
    parser.add_argument("--rmin-mm", type=float, default=0.25)
    parser.add_argument("--grain-shape", default="ball", help="ball or a clump template (rockcal.materials.clump_templates)")
    args = parser.parse_args()
    params = material(args.model).make(parse_assignments(args.set))
    numba.set_num_threads(args.threads)

    started = time.perf_counter()
    spec = rockcal.random_packing(args.width_mm, 2 * args.width_mm, args.rmin_mm, 1.65, seed=args.seed,
                                  grain_shape=args.grain_shape)
    packing_s = time.perf_counter() - started
    rockcal.simulate_ucs(params, rockcal.random_packing(10, 20, 0.25, 1.65, seed=1, grain_shape=args.grain_shape))  # warm the JIT
    result = rockcal.simulate_ucs(params, spec, rate_factor=args.rate_factor)
    report = result.summary() | {
        "threads": args.threads, "rate_factor": args.rate_factor, "seed": args.seed,
        "model": args.model, "grain_shape": args.grain_shape, "params": params.key(),
        "packing_or_cache_s": round(packing_s, 2), "porosity": round(spec.porosity, 4),
        "coordination": round(spec.coordination(), 3),
        "particle_steps_per_s": result.n_particles * result.steps / result.wall_s,
        "bond_steps_per_s": result.n_bonds * result.steps / result.wall_s,
    }
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
