"""A 3D UCS run (`rockcal.labtests.ucs` on the 3D rig) on a cylinder carved from a genesis packing: spheres,
bonds, steps, genesis and test wall time, E, ν, UCS and cracks, and the machine's load.

Material: PFC3D-style granite values (E_c = Ē_c = 62 GPa, kn/ks 2.5, σ̄c = c̄ = 175 MPa with
23 % spread, μ 0.5, λ̄ 1, ρ 2630 kg/m³) under rockcal's 2D names; genesis: 3D defaults
(`specimens3d.genesis.DEFAULT_GENESIS_3D`). The packing is kept in rockcal's specimen cache, so a
second run times the test alone.

Run by hand: `python benchmarks/ucs_3d.py [--size 25 50 0.8] [--size 50 100 1.0] [--rates 1 0.5]
[--seed 1] [--set E_c=30.97 ...]` (`--set NAME=VALUE` replaces one of the values above).
"""

import argparse
import os
import resource
import time

import numba

from rockcal.specimens3d.specimen import random_specimen
from rockcal.labtests.ucs import simulate_ucs
from rockcal.materials.parallel_bond import make_params
from rockcal.params import parse_assignments

GRANITE_3D = {"E_c": 62, "kn_ks": 2.5, "sigma_c": 175, "tau_c": 175, "sigma_c_cv": 0.23,
              "tau_c_cv": 0.23, "mu": 0.5, "lambda": 1.0, "density": 2630}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--size", type=float, nargs=3, action="append",
                        metavar=("DIAMETER_MM", "HEIGHT_MM", "RMIN_MM"))
    parser.add_argument("--rates", type=float, nargs="+", default=[1.0])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    args = parser.parse_args()
    params = make_params(GRANITE_3D | parse_assignments(args.set))
    print(f"threads {numba.get_num_threads()}, load average {os.getloadavg()[0]:.2f} "
          f"on {os.cpu_count()} cores")
    for diameter, height, rmin in args.size or [(25.0, 50.0, 0.8)]:
        started = time.perf_counter()
        spec = random_specimen("cylinder", diameter, height, rmin, seed=args.seed)
        genesis_s = time.perf_counter() - started
        print(f"cylinder {diameter:g} x {height:g} mm, R_min {rmin:g} mm: {spec.n_spheres} "
              f"spheres, {len(spec.bonds)} bonds, P_m reached {spec.pressure_mpa:.4f} MPa, "
              f"floaters {spec.floaters}, porosity {spec.porosity:.3f}; genesis {genesis_s:.0f} s",
              flush=True)
        for rate in args.rates:
            r = simulate_ucs(params, spec, rate_factor=rate)
            peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
            print(f"  rate {rate:g}: {r.steps} steps, {r.wall_s:.0f} s, "
                  f"{1e6 * r.wall_s / (r.steps * spec.n_spheres):.3f} µs per sphere-step, peak memory "
                  f"{peak_mb:.0f} MB ({1e3 * peak_mb / spec.n_spheres:.1f} kB per sphere); E {r.E_GPa:.2f} GPa, "
                  f"nu {r.nu:.3f}, UCS {r.ucs_MPa:.1f} MPa at strain {r.peak_axial_strain:.4f}; "
                  f"cracks {r.n_broken_tension} tension + {r.n_broken_shear} shear; load average "
                  f"{os.getloadavg()[0]:.2f}", flush=True)


if __name__ == "__main__":
    main()
