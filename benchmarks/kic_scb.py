"""K_IC of the semi-circular bend (SCB, ISRM 2014) beside the notched beam's at one material
point, in 2D or 3D: each specimen on packings 1..N at the pin's speed (and, with `--rates 1
0.5`, at half of it), its K_IC, peak load, steps and seconds, then each rate's mean and spread
and its change against the first rate; the machine's load.

The beam is the source's 220 x 50 mm beam (notch 18 x 2 mm, span 160 mm) times `--scale`, as
thick as it is deep in 3D; the half disk has the beam's depth as its radius (D 100 mm at full
size), a notch of 0.5 R, S/R 0.8 and the beam's notch width, 0.8 R thick in 3D.

Run by hand, one run after the other:
    python benchmarks/kic_scb.py                                   # 2D, full size, R_min 0.25 mm
    python benchmarks/kic_scb.py --dimensions 3 --scale 0.3 --rmin-mm 0.75 --rates 1 0.5
`--set NAME=VALUE` replaces a micro-parameter of the embedded granite's point.
"""

import argparse
import os

import numba
import numpy as np

from rockcal.labtests.bending import Beam, notched_beam, notched_beam_3d, simulate_bending
from rockcal.labtests.scb import HalfDisk, half_disk, half_disk_3d, simulate_scb
from rockcal.params import make_params, parse_assignments


def specimens(scale: float) -> tuple[Beam, HalfDisk]:
    """The beam (in 3D as thick as it is deep) and the half disk at `scale` x the full size."""
    depth = 50.0 * scale
    beam = Beam(220.0 * scale, depth, 18.0 * scale, 2.0 * scale, 160.0 * scale, thickness_mm=depth)
    return beam, HalfDisk(depth, 0.5 * depth, 0.8, 2.0 * scale)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--dimensions", type=int, choices=(2, 3), default=2)
    parser.add_argument("--scale", type=float, default=1.0)
    parser.add_argument("--rmin-mm", type=float, default=0.25)
    parser.add_argument("--packings", type=int, default=3)
    parser.add_argument("--rates", type=float, nargs="+", default=[1.0])
    parser.add_argument("--only", choices=("bending", "scb"), default=None)
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    args = parser.parse_args()
    params = make_params(parse_assignments(args.set))
    beam, hd = specimens(args.scale)
    in_3d = args.dimensions == 3
    unit = "kN" if in_3d else "kN/m"
    print(f"{args.dimensions}D, scale {args.scale:g}, R_min {args.rmin_mm:g} mm; threads {numba.get_num_threads()}, "
          f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    tests = {
        "bending": (lambda seed: (notched_beam_3d(beam, args.rmin_mm, seed=seed) if in_3d
                                  else notched_beam(beam, args.rmin_mm, seed=seed)),
                    lambda spec, rate: simulate_bending(params, spec, beam, rate_factor=rate),
                    "K_IC_MPa_sqrt_m"),
        "scb": (lambda seed: (half_disk_3d(hd, args.rmin_mm, seed=seed) if in_3d
                              else half_disk(hd, args.rmin_mm, seed=seed)),
                lambda spec, rate: simulate_scb(params, spec, hd, rate_factor=rate),
                "K_IC_scb_MPa_sqrt_m"),
    }
    print(f"{'test':8s} {'rate':>4s} {'packing':>7s} {'grains':>7s} {'K_IC':>7s} {'P_max ' + unit:>12s} "
          f"{'broken':>6s} {'steps':>7s} {'s':>6s}")
    for name, (make, run, response) in tests.items():
        if args.only not in (None, name):
            continue
        k_ic = {}
        for seed in range(1, args.packings + 1):
            spec = make(seed)
            for rate in args.rates:
                r = run(spec, rate)
                k_ic[rate, seed] = getattr(r, response)
                peak = r.P_max_kN if in_3d else r.P_max_kN_per_m
                print(f"{name:8s} {rate:4g} {seed:7d} {spec.n_particles:7d} {k_ic[rate, seed]:7.3f} {peak:12.3f} "
                      f"{r.n_broken_tension + r.n_broken_shear:6d} {r.steps:7d} {r.wall_s:6.0f}", flush=True)
        first = None
        for rate in args.rates:
            values = [k_ic[rate, seed] for seed in range(1, args.packings + 1)]
            mean = float(np.mean(values))
            first = first or mean
            sd = float(np.std(values, ddof=1)) if len(values) > 1 else 0.0
            print(f"{name}: rate {rate:g}: K_IC {mean:.3f} ± {sd:.3f} MPa·m^0.5 over {len(values)} packings "
                  f"({100 * (mean / first - 1):+.1f} % against rate {args.rates[0]:g})")
    print(f"load average {os.getloadavg()[0]:.2f} at the end")


if __name__ == "__main__":
    main()
