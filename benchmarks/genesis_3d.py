"""The 3D genesis' time and the packings it makes.

`--stats`: the cuboid packing of a cylinder's vessel (diameter x diameter x height) for each
seed, uncached, timed on the engine's threads: spheres, wall stress reached, floaters left,
porosity, sphere-sphere contacts per sphere, the radii's mean, spread and largest over R_min
(enlarged floaters show there) and the contact normals' fabric tensor's eigenvalues (1/3 each
for an isotropic packing); then each quantity's mean and spread over the seeds.

`--ucs`: each size's cylinder made uncached (`specimens3d.specimen.random_specimen`), then a UCS
run on it, both timed in the same process: the genesis over its own UCS test.

`--coefficient`: each size's cuboid packing on one thread, in processor time, over the engine
probe's step (ms) and the packing's grains x rows: the plan's `cost.GENESIS_S_PER_WORK[3]`.

Run by hand: `python benchmarks/genesis_3d.py --stats [--size 25 50 0.8] [--seeds 1 2 3]`;
`python benchmarks/genesis_3d.py --ucs [--size 25 50 0.8] [--size 50 100 0.8]`;
`python benchmarks/genesis_3d.py --coefficient [--size 25 50 0.8]`.
"""

import argparse
import os
import time

import numba
import numpy as np

from rockcal.campaign.plan.engine_speed import probe_ms_per_step
from rockcal.dem.neighbours import CONTACT_GAP
from rockcal.dem3d.vectors import norms
from rockcal.labtests.ucs import simulate_ucs
from rockcal.materials.parallel_bond import make_params
from rockcal.specimens3d.genesis import DEFAULT_GENESIS_3D, pair_gaps
from rockcal.specimens3d.packing import pack_vessel
from rockcal.specimens3d.specimen import expected_spheres, random_specimen

GRANITE_3D = {"E_c": 62, "kn_ks": 2.5, "sigma_c": 175, "tau_c": 175, "sigma_c_cv": 0.23,
              "tau_c_cv": 0.23, "mu": 0.5, "lambda": 1.0, "density": 2630}


def load() -> str:
    return f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores"


def packing_stats(pos, radius, size, rmin) -> dict:
    """Porosity, contacts per sphere, the radii over R_min and the fabric tensor's eigenvalues."""
    pi, pj, _ = pair_gaps(pos, radius, CONTACT_GAP * radius.min())
    branch = pos[pj] - pos[pi]
    normal = branch / norms(branch)[:, None]
    fabric = np.einsum("pa,pb->ab", normal, normal) / len(normal)
    eig = np.sort(np.linalg.eigvalsh(fabric))
    return {"porosity": 1 - 4 / 3 * np.pi * np.sum(radius**3) / np.prod(size),
            "coordination": 2 * len(pi) / len(radius),
            "R_mean/R_min": radius.mean() / rmin, "R_cv": radius.std() / radius.mean(),
            "R_max/R_min": radius.max() / rmin, "fabric_min": eig[0], "fabric_max": eig[-1]}


def stats(sizes, seeds) -> None:
    g = DEFAULT_GENESIS_3D
    for diameter, height, rmin in sizes:
        size = np.array([diameter, diameter, height]) * 1e-3
        rows = []
        for seed in seeds:
            started = time.perf_counter()
            pos, radius, pressure, left = pack_vessel(size, rmin * 1e-3, 1.65, seed, g.cloud_porosity,
                                                      g.pressure_mpa)
            seconds = time.perf_counter() - started
            row = packing_stats(pos, radius, size, rmin * 1e-3)
            rows.append(row)
            print(f"{diameter:g} x {diameter:g} x {height:g} mm, R_min {rmin:g}, seed {seed}: "
                  f"{len(radius)} spheres, genesis {seconds:.1f} s, P {pressure:.4f} MPa, floaters "
                  f"{left}; " + ", ".join(f"{k} {v:.4f}" for k, v in row.items()) + f"; {load()}",
                  flush=True)
        for key in rows[0]:
            values = np.array([r[key] for r in rows])
            print(f"  {key}: mean {values.mean():.4f}, sd {values.std(ddof=1):.4f}")


def ucs(sizes, seed) -> None:
    params = make_params(GRANITE_3D)
    for diameter, height, rmin in sizes:
        started = time.perf_counter()
        spec = random_specimen("cylinder", diameter, height, rmin, seed=seed, cache=False)
        genesis_s = time.perf_counter() - started
        print(f"cylinder {diameter:g} x {height:g} mm, R_min {rmin:g}: {spec.n_spheres} spheres, "
              f"genesis {genesis_s:.0f} s; {load()}", flush=True)
        r = simulate_ucs(params, spec)
        print(f"  UCS run {r.wall_s:.0f} s (UCS {r.ucs_MPa:.1f} MPa); genesis / UCS run "
              f"{genesis_s / r.wall_s:.2f}; {load()}", flush=True)


def coefficient(sizes, seed) -> None:
    g = DEFAULT_GENESIS_3D
    probe_ms = probe_ms_per_step()
    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        for diameter, height, rmin in sizes:
            size = np.array([diameter, diameter, height]) * 1e-3
            started = time.process_time()
            pack_vessel(size, rmin * 1e-3, 1.65, seed, g.cloud_porosity, g.pressure_mpa)
            seconds = time.process_time() - started
            work = expected_spheres(diameter, height, rmin, 1.65, g.cloud_porosity) * height / (rmin * 2.65)
            print(f"{diameter:g} x {diameter:g} x {height:g} mm, R_min {rmin:g}: genesis {seconds:.1f} s "
                  f"of processor time on one thread, probe {probe_ms:.4f} ms, work {work:.4g} "
                  f"grain-rows: {seconds / (probe_ms * work):.3g} s per grain-row per probe-ms; {load()}",
                  flush=True)
    finally:
        numba.set_num_threads(threads)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--stats", action="store_true")
    parser.add_argument("--ucs", action="store_true")
    parser.add_argument("--coefficient", action="store_true")
    parser.add_argument("--size", type=float, nargs=3, action="append",
                        metavar=("DIAMETER_MM", "HEIGHT_MM", "RMIN_MM"))
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    args = parser.parse_args()
    sizes = args.size or [(25.0, 50.0, 0.8)]
    print(f"threads {numba.get_num_threads()}, {load()}", flush=True)
    if args.stats:
        stats(sizes, args.seeds)
    if args.ucs:
        ucs(sizes, args.seeds[0])
    if args.coefficient:
        coefficient(sizes, args.seeds[0])


if __name__ == "__main__":
    main()
