"""The 3D Brazilian test at PFC3D-like granite values (`ucs_3d.GRANITE_3D`): a disk D x D/2
carved from a cuboid packing, between flat platens and between bearing strips, on packings
1-3, and at half the loading speed on packing 1; sigma_t, whether it split through the centre,
its steps and seconds.

    python benchmarks/brazilian_3d.py [--diameter-mm 20] [--rmin-mm 0.75]   # about a minute on 2 cores
"""

import argparse

from rockcal.specimens3d.specimen import random_disk
from rockcal.labtests.brazilian import simulate_brazilian
from rockcal.materials.parallel_bond import make_params
from ucs_3d import GRANITE_3D


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--diameter-mm", type=float, default=20.0)
    parser.add_argument("--rmin-mm", type=float, default=0.75)
    parser.add_argument("--packings", type=int, default=3)
    args = parser.parse_args()
    params = make_params(GRANITE_3D)
    print(f"{'loading':18s} {'packing':>7s} {'spheres':>7s} {'sigma_t MPa':>11s} {'split':>5s} {'steps':>7s} {'s':>6s}")
    for loading in ("flat", "strips"):
        for seed in range(1, args.packings + 1):
            disk = random_disk(args.diameter_mm, rmin_mm=args.rmin_mm, seed=seed)
            rates = (1.0, 0.5) if seed == 1 and loading == "flat" else (1.0,)
            for rate in rates:
                r = simulate_brazilian(params, disk, loading=loading, rate_factor=rate)
                name = loading + (", half speed" if rate != 1.0 else "")
                print(f"{name:18s} {seed:7d} {disk.n_spheres:7d} {r.sigma_t_MPa:11.1f} {r.split:5.0f} "
                      f"{r.steps:7d} {r.wall_s:6.1f}")


if __name__ == "__main__":
    main()
