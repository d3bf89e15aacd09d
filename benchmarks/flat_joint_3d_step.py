"""Time per sphere per step of the 3D engine with PFC3D's flat joints (`rockcal.dem3d.flat_joint`)
against the same engine with parallel bonds, on the same packing, in the same run.

The packing is `step_3d.py`'s perturbed FCC lattice (about 10⁴ spheres at the default 14 cells,
bonded coordination about 6.5); every bonded pair is a parallel bond in one state and a flat
joint of N_r x N_α elements in the other (the flat-jointed material's default 2 x 4 unless
given), at the source point's moduli and strengths, all joints bonded, or a fraction of them
slit (unbonded at zero gap: the elements the law integrates over their closed part). The
spheres move slightly so that every law is exercised. The states are timed in turn, each
`--rounds` times; the fastest of each counts.

Run by hand: `python benchmarks/flat_joint_3d_step.py [--cells 14] [--steps 200] [--rounds 3]
[--threads 1 2] [--elements 2 4] [--slit 0 0.2]`. With `--first-step`, the processor seconds
of a tiny flat-jointed state's first step alone: the stepping loop's compile, from scratch
when run with an empty numba cache (`NUMBA_CACHE_DIR=$(mktemp -d)`).
"""

import argparse
import os
import time

import numba
import numpy as np

from rockcal.dem3d import flat_joint
from rockcal.dem3d import simulate as simulate_3d
from rockcal.dem3d.laws import Laws
from step_3d import LAWS_3D, moving_state_3d, perturbed_fcc, seconds_per_step

EMOD, KRATIO, TEN, COH = 21.65e9, 1.9, 36.55e6, 90e6
LINEAR = Laws(E_c=EMOD, ks_per_kn=1 / KRATIO, mu=0.5, Ebar_c=0.0, ksbar_per_knbar=1.0, lam=1.0,
              tan_phi=0.0, mcf=1.0)


def flat_jointed_state(pos, radius, pairs, nr: int, nal: int, slit: float):
    """Flat joints of nr x nal elements at `pairs`, a fraction `slit` of them unbonded, moving
    as `step_3d.moving_state_3d`'s spheres."""
    slit_joint = np.random.default_rng(1).random(len(pairs)) < slit

    def joints(pos, radius, pi, pj, order):
        d = pos[pj] - pos[pi]
        dist = np.sqrt(np.sum(d * d, axis=1))
        kn = EMOD / (radius[pi] + radius[pj])
        return flat_joint.new_flatjoints_3d(nr, nal, d / dist[:, None], radius[pi] + radius[pj] - dist,
                                            kn, kn / KRATIO, 1.0, 0.5, 0.0, 0.0, ~slit_joint[order],
                                            TEN, COH)

    state = simulate_3d.assemble_state(pos, radius, pairs, 2650.0, LINEAR, joints=joints)
    state.spheres.vel[:] = np.random.default_rng(0).normal(0, 1e-4, pos.shape)
    return state


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--cells", type=int, default=14, help="FCC cells per side (4 cells³ spheres)")
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--elements", type=int, nargs=2, default=[2, 4], metavar=("N_R", "N_ALPHA"))
    parser.add_argument("--slit", type=float, nargs="+", default=[0.0, 0.2],
                        help="fractions of the joints slit (unbonded)")
    parser.add_argument("--threads", type=int, nargs="+", default=[1, numba.config.NUMBA_NUM_THREADS])
    parser.add_argument("--first-step", action="store_true",
                        help="time a tiny state's first step (the compile) and nothing else")
    args = parser.parse_args()
    if args.first_step:
        state = flat_jointed_state(*perturbed_fcc(2, 1e-3), *args.elements, max(args.slit))
        started = time.process_time()
        simulate_3d.advance(state, 1)
        print(f"first step: {time.process_time() - started:.1f} processor seconds")
        return
    pos, radius, pairs = perturbed_fcc(args.cells, 1e-3)
    states = {"parallel bonds": moving_state_3d(pos, radius, pairs)}
    for slit in args.slit:
        states[f"flat joints {args.elements[0]} x {args.elements[1]}, {slit:g} slit"] = \
            flat_jointed_state(pos, radius, pairs, *args.elements, slit)
    n, bonds = len(pos), len(pairs)
    print(f"{n} spheres, {bonds} bonded pairs ({2 * bonds / n:.2f} per sphere); laws {LAWS_3D}")
    cap = numba.get_num_threads()
    for threads in sorted(set(args.threads)):
        numba.set_num_threads(threads)
        best = dict.fromkeys(states, np.inf)
        for _ in range(args.rounds):
            for name, state in states.items():
                best[name] = min(best[name], seconds_per_step(simulate_3d.advance, state, args.steps))
        base = best["parallel bonds"]
        print(f"{threads} thread(s):")
        for name, seconds in best.items():
            print(f"  {name}: {seconds / n * 1e9:.0f} ns per sphere-step, {seconds / base:.2f} x the "
                  "parallel bonds'")
    numba.set_num_threads(cap)
    print("load average:", " ".join(f"{x:.2f}" for x in os.getloadavg()))


if __name__ == "__main__":
    main()
