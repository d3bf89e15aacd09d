"""The 3D confined test in the triaxial cell beside the polyaxial prism: one run per confinement
on each (a cylinder packed in its cell, `specimens3d.specimen.packed_cylinder`; the square prism,
the cached cuboid packing), and the envelope through each one's peaks (Mohr–Coulomb phi and c,
Hoek–Brown sigma_ci and m_i). Each run: peak sigma1, E, nu, the sigma3 held (mean, and 95 % of
the readings' distance from it), wall time and the machine's load.

Material: the granite's 3D point (docs/concepts/pfc3d.md, "The granite in 3D"); `--set NAME=VALUE`
replaces one value. Specimen: that campaign's, 25 x 50 mm at R_min 0.8 mm.

Run by hand: `python benchmarks/cell_3d.py [--size 25 50 0.8] [--confinements 0 5 10 20] [--seed 1]`.
"""

import argparse
import os
import time

import numba
import numpy as np

from rockcal.labtests.biaxial import simulate_biaxial
from rockcal.labtests.envelope import envelope_responses
from rockcal.materials.parallel_bond import make_params
from rockcal.params import parse_assignments
from rockcal.specimens3d.specimen import packed_cylinder, random_specimen

GRANITE_3D_POINT = {"E_c": 30.97, "kn_ks": 4.088, "sigma_c": 44.06, "tau_c": 90, "sigma_c_cv": 0.23,
                    "tau_c_cv": 0.23, "density": 2622}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--size", type=float, nargs=3, default=(25.0, 50.0, 0.8),
                        metavar=("WIDTH_MM", "HEIGHT_MM", "RMIN_MM"))
    parser.add_argument("--confinements", type=float, nargs="+", default=[0.0, 5.0, 10.0, 20.0])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    args = parser.parse_args()
    params = make_params(GRANITE_3D_POINT | parse_assignments(args.set))
    width, height, rmin = args.size
    print(f"threads {numba.get_num_threads()}, load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; "
          f"{params}")
    for vessel, make in (("cell", packed_cylinder), ("prism", lambda *a, **k: random_specimen("cuboid", *a, **k))):
        started = time.perf_counter()
        specimen = make(width, height, rmin, seed=args.seed)
        print(f"{vessel}: {specimen.label}, {specimen.n_spheres} spheres; genesis (or the cache) "
              f"{time.perf_counter() - started:.0f} s", flush=True)
        runs = []
        for sigma3 in args.confinements:
            r = simulate_biaxial(params, specimen, sigma3)
            runs.append(r)
            peak = int(np.argmax(r.curve[:, 2]))
            off = np.abs(r.curve[1:peak + 1, 4] - sigma3)
            print(f"  sigma3 {sigma3:g} MPa: sigma1 {r.sigma1_MPa:.1f} MPa, E {r.E_GPa:.2f} GPa, nu {r.nu:.3f}; "
                  f"sigma3 held {r.sigma3_MPa:.3f} MPa, 95 % of readings within "
                  f"{np.percentile(off, 95) if len(off) else 0:.3f} MPa; {r.wall_s:.1f} s; load average "
                  f"{os.getloadavg()[0]:.2f}", flush=True)
        fit = envelope_responses([r.confinement_MPa for r in runs], [r.sigma1_MPa for r in runs])
        print("  envelope: " + ", ".join(f"{k} {v:.4g}" for k, v in fit.items()), flush=True)


if __name__ == "__main__":
    main()
