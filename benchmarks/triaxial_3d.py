"""3D confined runs (`rockcal.labtests.biaxial` on the 3D rig) on a square prism from a genesis packing, one per
confinement, and the envelope through their peaks; the UCS test on the cylinder carved from
the same packing, for the two shapes' strengths side by side; the loading speed halved at one
confinement. Each run: peak sigma1, E, nu, the sigma3 the side walls held, the seating's and
the loading's steps, wall time, and the machine's load.

Material: the PFC3D-style granite values of `ucs_3d.py` (E_c = Ē_c = 62 GPa, kn/ks 2.5,
σ̄c = c̄ = 175 MPa with 23 % spread); genesis: the 3D defaults. The packing is kept in
rockcal's specimen cache, so a second run times the tests alone.

Run by hand: `NUMBA_NUM_THREADS=1 python benchmarks/triaxial_3d.py [--size 12 24 0.5]
[--confinements 0 5 10 20] [--halve-at 10] [--seed 1]`.
"""

import argparse
import os
import time

import numba
import numpy as np
from ucs_3d import GRANITE_3D

from rockcal.specimens3d.specimen import carve_cylinder, random_specimen
from rockcal.labtests.biaxial import simulate_biaxial
from rockcal.labtests.ucs import simulate_ucs
from rockcal.labtests.envelope import envelope_responses
from rockcal.materials.parallel_bond import make_params


def show(label: str, r) -> None:
    peak = int(np.argmax(r.curve[:, 2]))
    off = np.abs(r.curve[1:peak + 1, 4] - r.confinement_MPa)
    print(f"  {label}: sigma1 {r.sigma1_MPa:.1f} MPa (q {r.q_MPa:.1f}), E {r.E_GPa:.2f} GPa, "
          f"nu {r.nu:.3f}; sigma3 held {r.sigma3_MPa:.3f} MPa, 95 % of readings within "
          f"{np.percentile(off, 95) if len(off) else 0:.3f} MPa; seating {r.seating_steps} steps, "
          f"{r.steps} steps in all, {r.wall_s:.1f} s; cracks {r.n_broken_tension} + {r.n_broken_shear}; "
          f"load average {os.getloadavg()[0]:.2f}", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--size", type=float, nargs=3, default=(12.0, 24.0, 0.5),
                        metavar=("WIDTH_MM", "HEIGHT_MM", "RMIN_MM"))
    parser.add_argument("--confinements", type=float, nargs="+", default=[0.0, 5.0, 10.0, 20.0])
    parser.add_argument("--halve-at", type=float, default=10.0, help="the confinement run again at half speed")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    params = make_params(GRANITE_3D)
    width, height, rmin = args.size
    print(f"threads {numba.get_num_threads()}, load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    started = time.perf_counter()
    prism = random_specimen("cuboid", width, height, rmin, seed=args.seed)
    print(f"prism {width:g} x {width:g} x {height:g} mm, R_min {rmin:g} mm: {prism.n_spheres} spheres, "
          f"{len(prism.bonds)} bonds; genesis (or the cache) {time.perf_counter() - started:.0f} s", flush=True)
    runs = []
    for sigma3 in args.confinements:
        runs.append(simulate_biaxial(params, prism, sigma3))
        show(f"sigma3 {sigma3:g} MPa", runs[-1])
    fit = envelope_responses([r.confinement_MPa for r in runs], [r.sigma1_MPa for r in runs])
    print("  envelope: " + ", ".join(f"{k} {v:.4g}" for k, v in fit.items()), flush=True)
    if args.halve_at in args.confinements:
        full = runs[args.confinements.index(args.halve_at)]
        half = simulate_biaxial(params, prism, args.halve_at, rate_factor=0.5)
        show(f"sigma3 {args.halve_at:g} MPa, half speed", half)
        print(f"  half speed moves sigma1 by {100 * (half.sigma1_MPa / full.sigma1_MPa - 1):+.2f} %", flush=True)
    cylinder = carve_cylinder(prism)
    r = simulate_ucs(params, cylinder)
    print(f"  UCS cylinder from the same packing ({cylinder.n_spheres} spheres): UCS {r.ucs_MPa:.1f} MPa, "
          f"E {r.E_GPa:.2f} GPa, nu {r.nu:.3f}, {r.wall_s:.1f} s", flush=True)


if __name__ == "__main__":
    main()
