"""The cost of a flat-joint step against a parallel-bond step on the same specimen, in one run.

Both materials on the same packing (the flat joints at the parallel bonds' pairs, N_r = 2 by
default), the grains stirred alike so that the contacts work, one thread; each round times STEPS
steps of each material in turn (the fastest round counts), so both see the same machine.

Run by hand: `python benchmarks/fjm_ratio.py [--width-mm 50 --height-mm 100] [--nr 2]
[--slit 0.0]`. Prints ms per step of each and their ratio (the goal: <= 2).

`--table`: UCS, Brazilian sigma_t and UCS / sigma_t of the flat-jointed material over slit
fractions and N_r, beside the parallel bond's on the same grains, both at the parallel bond's
granite defaults (E_c = E* = 21.65 GPa, kn/ks 1.9, sigma_c = fj_ten 36.55 MPa, tau_c = fj_coh
90 MPa, mu 0.5); `--rmin-mm` sets the size (full size: 0.25, the UCS prism 50 x 100 mm and the
disk 50 mm; `--rmin-mm 0.5 --scale 0.5` is a quarter of the grains, half the size).
"""

import argparse
import json
import time

import numba
import numpy as np

import rockcal
from rockcal.dem.flatjoint_material import make_flatjoint_params
from rockcal.dem.simulate import advance
from rockcal.materials import new_state
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


def table(rmin_mm: float, scale: float, seed: int) -> list[dict]:
    """One row per material: UCS (MPa), Brazilian sigma_t (MPa) and their ratio."""
    from rockcal.labtests.brazilian import brazilian_disk, simulate_brazilian

    prism = rockcal.random_packing(50 * scale, 100 * scale, rmin_mm, 1.65, seed)
    disk = brazilian_disk(50 * scale, rmin_mm, 1.65, seed)
    granite = {"fj_emod": 21.65, "fj_kratio": 1.9, "fj_ten": 36.55, "fj_coh": 90.0, "fj_fric": 0.5}
    materials = [("parallel_bond", make_params({}))] + [
        (f"flatjoint slit {slit:g} N_r {nr}",
         make_flatjoint_params(granite | {"fj_nr": nr, "fjm_B_frac": 1.0 - slit}))
        for slit in (0.0, 0.3, 0.6) for nr in (1, 2, 3)]
    rows = []
    for name, params in materials:
        started = time.perf_counter()
        ucs = rockcal.simulate_ucs(params, prism)
        bts = simulate_brazilian(params, disk)
        rows.append({"material": name, "E_GPa": ucs.E_GPa, "ucs_MPa": ucs.ucs_MPa,
                     "sigma_t_MPa": bts.sigma_t_MPa, "ucs_over_bts": ucs.ucs_MPa / bts.sigma_t_MPa,
                     "wall_s": time.perf_counter() - started})
        print(json.dumps(rows[-1]), flush=True)
    return rows


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--width-mm", type=float, default=50.0)
    parser.add_argument("--height-mm", type=float, default=100.0)
    parser.add_argument("--rmin-mm", type=float, default=0.25)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--nr", type=int, default=2, help="elements per flat joint")
    parser.add_argument("--slit", type=float, default=0.0, help="slit fraction of the flat joints")
    parser.add_argument("--table", action="store_true", help="UCS and Brazilian over slit and N_r")
    parser.add_argument("--scale", type=float, default=1.0, help="--table: specimen size / full size")
    args = parser.parse_args()
    numba.set_num_threads(1)
    if args.table:
        table(args.rmin_mm, args.scale, args.seed)
        return
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
