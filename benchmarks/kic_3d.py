"""Is the 3D notched beam's K_IC a property of the rock, not of the loading or the beam's
thickness? At the granite's 3D point: one packing at the pin's speed and at half of it (the
rate), then each of two thicknesses on packings 1..N (the thickness), each run's K_IC, peak
load, spheres, bonds broken, steps and seconds; each thickness' mean and sd, and the changes
(the thickness' with the standard error of the difference of the means); the machine's load.

The beam is the source's 220 x 50 mm beam (notch 18 x 2 mm, span 160 mm) times `--scale`; the
thicknesses default to the 3D beam's default (`bending.thickness_3d_mm`, eight of its
largest spheres across) and twice it.

Run by hand: `python benchmarks/kic_3d.py [--scale 0.3] [--rmin-mm 0.75] [--packings 3]`;
`--set NAME=VALUE` replaces a micro-parameter of the granite's 3D point.
"""

import argparse
import os
from dataclasses import replace

import numba
import numpy as np

from cell_3d import GRANITE_3D_POINT
from rockcal.labtests.bending import Beam, thickness_3d_mm, notched_beam_3d, simulate_bending
from rockcal.materials.parallel_bond import make_params
from rockcal.params import parse_assignments

RADIUS_RATIO = 1.65


def run(params, beam: Beam, rmin_mm: float, seed: int, rate: float) -> float:
    """One beam's run, printed; its K_IC."""
    spec = notched_beam_3d(beam, rmin_mm, RADIUS_RATIO, seed)
    r = simulate_bending(params, spec, beam, rate_factor=rate)
    print(f"{beam.thickness_mm:9g} {rate:4g} {seed:7d} {spec.n_spheres:7d} {r.K_IC_MPa_sqrt_m:7.3f} "
          f"{r.P_max_kN:8.3f} {r.n_broken_tension + r.n_broken_shear:6d} {r.steps:7d} {r.wall_s:6.0f}", flush=True)
    return r.K_IC_MPa_sqrt_m


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--scale", type=float, default=0.3)
    parser.add_argument("--rmin-mm", type=float, default=0.75)
    parser.add_argument("--thicknesses-mm", type=float, nargs=2, default=None,
                        help="default: the 3D beam's default thickness and twice it")
    parser.add_argument("--packings", type=int, default=3)
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    args = parser.parse_args()
    params = make_params(GRANITE_3D_POINT | parse_assignments(args.set))
    s = args.scale
    beam = Beam(220.0 * s, 50.0 * s, 18.0 * s, 2.0 * s, 160.0 * s)
    thin = thickness_3d_mm(beam, args.rmin_mm, RADIUS_RATIO)
    thicknesses = args.thicknesses_mm or (thin, 2 * thin)
    print(f"3D beam {beam.length_mm:g} x {beam.height_mm:g} mm, R_min {args.rmin_mm:g} mm; threads "
          f"{numba.get_num_threads()}, load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    print(f"{'thickness':>9s} {'rate':>4s} {'packing':>7s} {'spheres':>7s} {'K_IC':>7s} {'P_max kN':>8s} "
          f"{'broken':>6s} {'steps':>7s} {'s':>6s}")
    first = replace(beam, thickness_mm=thicknesses[0])
    full, half = (run(params, first, args.rmin_mm, 1, rate) for rate in (1.0, 0.5))
    print(f"rate: half the pin's speed moves packing 1's K_IC by {100 * (half / full - 1):+.1f} %")
    means, standard_errors = [], []
    for thickness in thicknesses:
        k_ic = [full] if thickness == thicknesses[0] else []
        k_ic += [run(params, replace(beam, thickness_mm=thickness), args.rmin_mm, seed, 1.0)
                 for seed in range(len(k_ic) + 1, args.packings + 1)]
        means.append(float(np.mean(k_ic)))
        sd = float(np.std(k_ic, ddof=1)) if len(k_ic) > 1 else 0.0
        standard_errors.append(sd / len(k_ic) ** 0.5)
        print(f"thickness {thickness:g} mm: K_IC {means[-1]:.3f} ± {sd:.3f} MPa·m^0.5 over {len(k_ic)} packings")
    difference = means[1] - means[0]
    standard_error = float(np.hypot(*standard_errors))  # of the difference of two independent means
    print(f"thickness: {thicknesses[1]:g} mm against {thicknesses[0]:g} mm moves the mean K_IC by "
          f"{difference:+.3f} ({100 * difference / means[0]:+.1f} %), its standard error {standard_error:.3f}")
    print(f"load average {os.getloadavg()[0]:.2f} at the end")


if __name__ == "__main__":
    main()
