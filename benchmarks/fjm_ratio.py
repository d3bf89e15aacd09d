"""The cost of a flat-joint step against a parallel-bond step on the same specimen, in one run.

Both materials on the same packing (the flat joints at the parallel bonds' pairs, N_r = 2 by
default), the grains stirred alike so that the contacts work, one thread; each round times STEPS
steps of each material in turn (the fastest round counts), so both see the same machine.

Run by hand: `python benchmarks/fjm_ratio.py [--width-mm 50 --height-mm 100] [--nr 2]
[--slit 0.0]`. Prints ms per step of each and their ratio (the goal: <= 2).
The flat-jointed material's strengths over slit fraction and N_r: `benchmarks/fjm_table.py`.
"""

import argparse
import json
import time

import numba
import numpy as np

import rockcal
from rockcal.dem.simulate import advance
from rockcal.materials import new_state
from rockcal.materials.flat_joint import make_flatjoint_params
from rockcal.params import make_params

STEPS = 300
ROUNDS = 5


def stirred(params, specimen):
    """The specimen's state in the material of `params`, its grains moving slightly."""
    state = new_state(params, specimen)
    rng = np.random.default_rng(0)
    state.particles.vel[:] = rng.normal(0, 1e-4, specimen.pos.shape)
    state.particles.spin[:] = rng.normal(0, 1e-4 / specimen.radius.mean(), specimen.n_particles)
    return state


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--width-mm", type=float, default=50.0)
    parser.add_argument("--height-mm", type=float, default=100.0)
    parser.add_argument("--rmin-mm", type=float, default=0.25)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--nr", type=int, default=2, help="elements per flat joint")
    parser.add_argument("--slit", type=float, default=0.0, help="slit fraction of the flat joints")
    args = parser.parse_args()
    numba.set_num_threads(1)
    specimen = rockcal.random_packing(args.width_mm, args.height_mm, args.rmin_mm, 1.65, args.seed)
    states = {"parallel_bond": stirred(make_params({}), specimen),
              "flatjoint": stirred(make_flatjoint_params({"fj_nr": args.nr,
                                                          "fjm_B_frac": 1.0 - args.slit}), specimen)}
    for state in states.values():
        advance(state, 1)  # compiles the engine, or loads it from numba's cache
    best = dict.fromkeys(states, np.inf)
    for _ in range(ROUNDS):
        for name, state in states.items():
            started = time.perf_counter()
            advance(state, STEPS)
            best[name] = min(best[name], (time.perf_counter() - started) / STEPS)
    print(json.dumps({"specimen": specimen.label, "particles": specimen.n_particles,
                      "bonded_pairs": len(specimen.bonds), "nr": args.nr, "slit": args.slit,
                      "steps": STEPS, "rounds": ROUNDS,
                      "ms_per_step": {name: 1e3 * s for name, s in best.items()},
                      "ratio": best["flatjoint"] / best["parallel_bond"]}, indent=1))


if __name__ == "__main__":
    main()
