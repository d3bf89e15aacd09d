"""Full-size notched-beam bending: 220 x 50 mm, notch 18 x 2 mm, span 160 mm, R_min 0.25 mm,
the source's identified parameters (the MicroParams defaults) beside the lab K_IC 1.057 MPa m^0.5.

Run by hand: `python benchmarks/bending_full_size.py [--notch-mm 18] [--rate-factor 1] [--threads N]`.
Prints K_IC, P_max, the wall time (warm JIT) and the throughput.
"""

import argparse
import json
import time

import numba

from rockcal.labtests.bending import Beam, notched_beam, simulate_bending

LAB_KIC_MPA_SQRT_M = 1.057


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--threads", type=int, default=numba.config.NUMBA_NUM_THREADS)
    parser.add_argument("--notch-mm", type=float, default=18.0)
    parser.add_argument("--rate-factor", type=float, default=1.0)
    args = parser.parse_args()
    numba.set_num_threads(args.threads)

    beam = Beam(notch_mm=args.notch_mm)
    started = time.perf_counter()
    spec = notched_beam(beam)
    packing_s = time.perf_counter() - started
    small = Beam(44, 10, 3.6, 1.0, 32)
    simulate_bending({}, notched_beam(small), small)  # warm the JIT
    result = simulate_bending({}, spec, beam, rate_factor=args.rate_factor)
    report = result.summary() | {
        "lab_K_IC_MPa_sqrt_m": LAB_KIC_MPA_SQRT_M,
        "K_IC_error": result.K_IC_MPa_sqrt_m / LAB_KIC_MPA_SQRT_M - 1,
        "threads": args.threads, "rate_factor": args.rate_factor,
        "packing_or_cache_s": round(packing_s, 2),
        "particle_steps_per_s": result.n_particles * result.steps / result.wall_s,
    }
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
