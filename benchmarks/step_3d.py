"""Time per sphere per step of the 3D engine (`rockcal.dem3d`) against the 2D engine's time per
disk per step, measured in the same run.

3D: a bonded, perturbed FCC packing of about 10⁴ spheres (radii 0.975-1.035 of half the lattice
spacing, centres jittered, bonds at the pairs that touch or overlap: a bonded coordination of
about 6.5, as a dense PFC3D rock). 2D: the full-size UCS specimen of `engine_profile.py`
(50 x 100 mm, R_min 0.25 mm, about 13 000 disks, coordination 5.4). Both with their particles
moving slightly so that every law is exercised, and the same number of threads.

A genesis packing has more bonds per sphere than the lattice: `--cylinder D H R_MIN` also
times a cylinder carved from one (the 3D granite campaign's is 25 50 0.8: bonded coordination
about 9.6), bonded as the campaign bonds it.

`--install-gaps 0 0.6` bonds it at each gap (0: touching pairs only, as Potyondy & Cundall's
PFC3D granite; the default is the 3D genesis's, 0.6 R_min): one packing, fewer bonds per sphere
at the narrower gap.

Run by hand: `python benchmarks/step_3d.py [--steps 300] [--rounds 3] [--threads 1 2]
[--cylinder 25 50 0.8] [--install-gaps 0 0.6]`.
"""

import argparse
import os
import time

import numba
import numpy as np

import rockcal
from rockcal.dem import simulate as simulate_2d
from rockcal.dem3d import simulate as simulate_3d
from rockcal.dem3d.laws import Laws
from rockcal.dem3d.neighbours import near_pairs, spatial_order
from rockcal.specimens3d.genesis import DEFAULT_GENESIS_3D
from rockcal.specimens3d.specimen import random_specimen
from rockcal.materials.parallel_bond import new_state
from rockcal.params import make_params

SOURCE_POINT = {"E_c": 21.65, "kn_ks": 1.9, "sigma_c": 36.55, "tau_c": 90, "mu": 0.5,
                "sigma_c_cv": 0.23, "tau_c_cv": 0.23}


def perturbed_fcc(cells: int, spacing: float, seed: int = 0):
    """Centres and radii of an FCC packing of 4 cells³ spheres, nearest neighbours `spacing`
    apart, jittered by 2 % of it, radii 0.975-1.035 of spacing / 2; the touching pairs (i < j)."""
    rng = np.random.default_rng(seed)
    side = spacing * np.sqrt(2)
    basis = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
    cell = np.array([(i, j, k) for k in range(cells) for j in range(cells) for i in range(cells)])
    pos = ((cell[:, None, :] + basis[None]) * side).reshape(-1, 3)
    pos += rng.uniform(-0.02, 0.02, pos.shape) * spacing
    pos = pos[spatial_order(pos, spacing)]
    radius = rng.uniform(0.975, 1.035, len(pos)) * spacing / 2
    pi, pj = near_pairs(pos, radius, 0.0)
    return pos, radius, np.column_stack([pi, pj])


LAWS_3D = Laws(E_c=21.65e9, ks_per_kn=1 / 1.9, mu=0.5, Ebar_c=21.65e9, ksbar_per_knbar=1 / 1.9,
               lam=1.0, tan_phi=0.0, mcf=1.0)


def moving_state_3d(pos, radius, pairs):
    """Spheres bonded at `pairs`, moving slightly."""
    state = simulate_3d.assemble_state(pos, radius, pairs, 2650.0, LAWS_3D, ten=36.55e6, coh=90e6)
    state.spheres.vel[:] = np.random.default_rng(0).normal(0, 1e-4, pos.shape)
    return state


def state_3d(cells: int):
    return moving_state_3d(*perturbed_fcc(cells, 1e-3))


def cylinder_state_3d(diameter_mm: float, height_mm: float, rmin_mm: float, install_gap: float):
    genesis = DEFAULT_GENESIS_3D.model_copy(update={"install_gap": install_gap})
    spec = random_specimen("cylinder", diameter_mm, height_mm, rmin_mm, genesis=genesis)
    return moving_state_3d(spec.pos, spec.radius, spec.bonds)


def state_2d():
    spec = rockcal.random_packing(50, 100, 0.25, 1.65, seed=1)
    pos, radius = spec.pos, spec.radius
    state = new_state(pos, radius, spec.bonds, make_params(SOURCE_POINT),
                      walls=(0, 0, (pos[:, 1] - radius).min(), (pos[:, 1] + radius).max()),
                      wall_active=(False, False, True, True), bond_draws=spec.bond_draws)
    state.particles.vel[:] = np.random.default_rng(0).normal(0, 1e-4, (len(pos), 2))
    return state


def seconds_per_step(advance, state, steps: int) -> float:
    advance(state, 10)
    started = time.perf_counter()
    advance(state, steps)
    return (time.perf_counter() - started) / steps


def describe(name: str, state) -> None:
    pairs = state.neighbours
    n, bonds = len(pairs.pos_at_build), pairs.n_bonds
    print(f"{name}: {n} particles, {bonds} bonds ({2 * bonds / n:.2f} bonded coordination), "
          f"{len(pairs.pi) - bonds} unbonded near pairs, {len(pairs.block_starts) - 1} blocks")


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--steps", type=int, default=300)
    parser.add_argument("--rounds", type=int, default=3,
                        help="the engines are timed in turn this many times; the fastest counts")
    parser.add_argument("--cells", type=int, default=14, help="FCC cells per side (4 cells³ spheres)")
    parser.add_argument("--cylinder", type=float, nargs=3, metavar=("D_MM", "H_MM", "RMIN_MM"),
                        help="also a genesis cylinder of this size")
    parser.add_argument("--install-gaps", type=float, nargs="+", default=[DEFAULT_GENESIS_3D.install_gap],
                        help="the cylinder bonded at each of these installation gaps (/ R_min; 0: "
                             "touching pairs only)")
    parser.add_argument("--threads", type=int, nargs="+", default=[1, numba.config.NUMBA_NUM_THREADS])
    args = parser.parse_args()
    states = {"3D lattice": state_3d(args.cells)}
    for gap in args.install_gaps if args.cylinder else ():
        name = "3D cylinder {:g} x {:g} mm, R_min {:g}, gap {:g} R_min".format(*args.cylinder, gap)
        states[name] = cylinder_state_3d(*args.cylinder, gap)
    s2 = state_2d()
    n2, nb2 = s2.n_particles, s2.neighbours.n_bonds
    for name, s3 in states.items():
        describe(name, s3)
    describe("2D", s2)
    simulate_2d.use_threads(None)
    cap = numba.get_num_threads()
    for threads in sorted(set(args.threads)):
        numba.set_num_threads(threads)
        t3 = dict.fromkeys(states, np.inf)
        t2 = np.inf
        for _ in range(args.rounds):
            for name, s3 in states.items():
                t3[name] = min(t3[name], seconds_per_step(simulate_3d.advance, s3, args.steps))
            simulate_2d.use_threads(threads)
            t2 = min(t2, seconds_per_step(simulate_2d.advance, s2, args.steps))
        print(f"{threads} thread(s): 2D {t2 / n2 * 1e9:.0f} ns per disk-step ({t2 / nb2 * 1e9:.0f} ns per bond-step)")
        for name, s3 in states.items():
            n3, nb3 = s3.n_spheres, s3.neighbours.n_bonds
            print(f"  {name}: {t3[name] / n3 * 1e9:.0f} ns per sphere-step ({t3[name] / nb3 * 1e9:.0f} ns "
                  f"per bond-step); ratio to 2D per particle {(t3[name] / n3) / (t2 / n2):.2f}, "
                  f"per bond {(t3[name] / nb3) / (t2 / nb2):.2f}")
    numba.set_num_threads(cap)
    print("load average:", " ".join(f"{x:.2f}" for x in os.getloadavg()))


if __name__ == "__main__":
    main()
