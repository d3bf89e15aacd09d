"""Does the notched beam's P_max depend on the radius of its loading pin and supports?

Run by hand: `python benchmarks/bending_pin_radius.py [--rmin-mm 0.5] [--seeds 3] [--workers 2]
[--radii 2.5,5,10]`. The granite campaign's beam (220 x 50 mm, 2 mm carved notch 18 mm deep,
span 160 mm, granite genesis) at the source's identified point with the granite strength spread,
one run per (pin radius, packing seed); prints P_max and K_IC per radius (mean and sd over the
seeds) and the change from the default radius (5 mm). Pin and supports share the radius.
"""

from __future__ import annotations

import argparse
import json
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

SOURCE_POINT = {"sigma_c_cv": 0.23, "tau_c_cv": 0.23}  # on the MicroParams defaults: the source's point


def one_beam(job: tuple[float, float, int]) -> tuple[float, int, float, float, float]:
    """(pin radius, seed, P_max kN/m, K_IC, wall s) of one beam."""
    import numba

    from rockcal.labtests.bending import Beam, notched_beam, simulate_bending

    numba.set_num_threads(1)
    rmin_mm, pin_radius_mm, seed = job
    started = time.perf_counter()
    beam = Beam(pin_radius_mm=pin_radius_mm)
    result = simulate_bending(SOURCE_POINT, notched_beam(beam, rmin_mm, 1.65, seed), beam)
    return pin_radius_mm, seed, result.P_max_kN_per_m, result.K_IC_MPa_sqrt_m, time.perf_counter() - started


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--rmin-mm", type=float, default=0.5)
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--radii", default="2.5,5,10", help="pin and support radii, mm")
    args = parser.parse_args()
    radii = [float(r) for r in args.radii.split(",")]
    jobs = [(args.rmin_mm, r, seed) for r in radii for seed in range(1, args.seeds + 1)]
    with ProcessPoolExecutor(args.workers) as pool:
        runs = list(pool.map(one_beam, jobs))
    rows = []
    for r in radii:
        p = [run[2] for run in runs if run[0] == r]
        k = [run[3] for run in runs if run[0] == r]
        rows.append({"pin_radius_mm": r, "P_max_kN_per_m": p, "K_IC": k,
                     "K_IC_mean": float(np.mean(k)), "K_IC_sd": float(np.std(k, ddof=1)) if len(k) > 1 else 0.0,
                     "wall_s": [round(run[4]) for run in runs if run[0] == r]})
    default = next((row["K_IC_mean"] for row in rows if row["pin_radius_mm"] == 5.0), None)
    for row in rows:
        if default:
            row["change_from_5mm"] = row["K_IC_mean"] / default - 1
    print(json.dumps({"rmin_mm": args.rmin_mm, "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
