"""Full-size Brazilian test: a 50 mm disk, R_min 0.25 mm, the source's identified parameters.

Run by hand: `python benchmarks/brazilian_full_size.py [--rate-factor 1] [--seed 1] [--threads N]`.
Prints sigma_t, the peak load, the wall time (warm JIT) and the throughput.
"""

import argparse
import json
import time

import numba

from rockcal.labtests.brazilian import brazilian_disk, simulate_brazilian


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--threads", type=int, default=numba.config.NUMBA_NUM_THREADS)
    parser.add_argument("--rate-factor", type=float, default=1.0)
    parser.add_argument("--seed", type=int, default=1, help="packing seed")
    args = parser.parse_args()
    numba.set_num_threads(args.threads)

    started = time.perf_counter()
    spec = brazilian_disk(50.0, seed=args.seed)
    packing_s = time.perf_counter() - started
    simulate_brazilian({}, brazilian_disk(15.0))  # warm the JIT
    result = simulate_brazilian({}, spec, rate_factor=args.rate_factor)
    report = result.summary() | {
        "threads": args.threads, "rate_factor": args.rate_factor, "seed": args.seed,
        "packing_or_cache_s": round(packing_s, 2),
        "particle_steps_per_s": result.n_particles * result.steps / result.wall_s,
    }
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
