"""Engine throughput: time per step by phase (and of the bond phase's parts, each alone),
particle-steps/s on 1 and 2 threads, and the ratio to the bare bond loop
(`benchmarks/bond_loop.py`) run in the same process.

Run by hand: `python benchmarks/engine_profile.py [--steps 1000] [--rounds 3] [--bond-loop PATH]`. The
specimen is the full-size UCS one (50 x 100 mm, R_min 0.25 mm, granite genesis) at the source
study's identified point, its particles moving slightly so that every law is exercised; the
bare loop gets the same number of disks (its own bonds: 4.1 per disk, ours about 5.4).
"""

import argparse
import contextlib
import importlib.util
import io
import sys
import time
from pathlib import Path

import numba
import numpy as np
from numba import njit

import rockcal
from rockcal.dem import laws, simulate
from rockcal.materials.parallel_bond import new_state
from rockcal.params import make_params

SOURCE_POINT = {"E_c": 21.65, "kn_ks": 1.9, "sigma_c": 36.55, "tau_c": 90, "mu": 0.5,
                "sigma_c_cv": 0.23, "tau_c_cv": 0.23}


def ucs_state():
    spec = rockcal.random_packing(50, 100, 0.25, 1.65, seed=1)
    pos, radius = spec.pos, spec.radius
    state = new_state(pos, radius, spec.bonds, make_params(SOURCE_POINT),
                      walls=(0, 0, (pos[:, 1] - radius).min(), (pos[:, 1] + radius).max()),
                      wall_active=(False, False, True, True), bond_draws=spec.bond_draws)
    state.particles.vel[:] = np.random.default_rng(0).normal(0, 1e-4, (len(pos), 2))
    return state


def per_step(fn, steps: int) -> float:
    fn()
    started = time.perf_counter()
    for _ in range(steps):
        fn()
    return (time.perf_counter() - started) / steps


def phases(state, steps: int) -> dict:
    """Seconds per step of each phase, run one by one on all pairs and particles (one thread)."""
    p, pairs, walls = state.particles, state.neighbours, state.walls
    n, nb = state.n_particles, pairs.n_bonds
    rebuild = per_step(lambda: simulate.rebuild_neighbours(state), 5)  # before the motion below
    return {
        "bond forces": per_step(lambda: laws.add_bond_forces(
            0, nb, p.disks, pairs.pi, pairs.pj, pairs.shear, state.bonds, state.laws, state.dt,
            p.loads), steps),
        "near unbonded pairs": per_step(lambda: laws.add_contact_forces(
            nb, len(pairs.pi), p.disks, pairs.pi, pairs.pj, pairs.shear, state.laws, state.dt,
            p.loads), steps),
        "walls": per_step(lambda: laws.add_wall_forces(
            0, n, p.disks, walls.pos, walls.active, walls.stiffness, p.loads, walls.force),
            steps),
        "damping and motion": per_step(lambda: simulate._move(
            0, n, p.disks, p.loads, state.damping, state.dt, pairs.pos_at_build), steps),
        "neighbour list (per rebuild)": rebuild,
    }


@njit(error_model="numpy")
def _bond_parts(parts, first, last, disks, pi, pj, contact_shear, bonds, law, dt, loads):
    """The bond phase's loop with only some of its parts: 1 the gather of the disks' data, 2 the
    vector law, 4 the store of the bonds' new data, 8 the scatter (their sum: the whole
    phase)."""
    tile = np.zeros((laws.TILE_ROWS, laws.TILE))
    for start in range(first, last, laws.TILE):
        count = min(laws.TILE, last - start)
        if parts & 1:
            laws._gather(start, count, disks, pi, pj, tile)
        if parts & 2:
            laws._bond_law(start, count, bonds.state, contact_shear, bonds.table, law, dt, tile)
        if parts & 4:
            laws._store(start, count, tile, contact_shear, bonds.table)
        if parts & 8:
            laws._scatter(start, count, disks, pi, pj, tile, bonds, loads)


def bond_parts(state, steps: int) -> dict:
    """Seconds per step of each part of the bond phase run alone (one thread), on a copy of the
    state (the parts alone do not keep it consistent)."""
    p, pairs = state.particles, state.neighbours
    args = (0, pairs.n_bonds, p.disks.copy(), pairs.pi, pairs.pj, pairs.shear.copy(),
            laws.Bonds(*(a.copy() for a in state.bonds)), state.laws, state.dt, p.loads.copy())
    names = {1: "gather of the disks' data", 2: "vector law", 4: "store of the bonds' data",
             8: "scatter"}
    return {name: per_step(lambda: _bond_parts(part, *args), steps) for part, name in names.items()}


def load_bond_loop(path: Path):
    spec = importlib.util.spec_from_file_location("bond_loop", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def bare_loop_seconds_per_step(module, n: int, steps: int) -> tuple[float, int]:
    """The bare loop's seconds per step on its own lattice of n disks (one thread), and its
    bond count."""
    argv, sys.argv = sys.argv, ["bond_loop.py", str(n), str(steps)]
    buffer = io.StringIO()
    try:
        with contextlib.redirect_stdout(buffer):
            module.main()
    finally:
        sys.argv = argv
    lines = buffer.getvalue().split()
    ms = float(lines[lines.index("ms/step,") - 1])
    bonds = int(lines[lines.index("bonds:") - 1].rstrip(","))
    return ms / 1e3, bonds


@njit
def _bare_step_with_bond_state(pos, vel, rot, spin, force, moment, bi, bj, kn, ks, kb, rest, inv_m,
                               inv_i, rad, dt, nsteps, rows, shear):
    """The bare loop's step (`bond_loop.py`) carrying what a PFC bond must keep
    from step to step: it reads and writes each bond's normal and shear forces, moment and contact
    shear force, and reads its reference overlap and two strengths; its arithmetic stays the
    bare loop's. The engine's floor, less the PFC law's own arithmetic."""
    n = pos.shape[0]
    for _ in range(nsteps):
        for k in range(n):
            force[k, 0] = 0.0
            force[k, 1] = 0.0
            moment[k] = 0.0
        for b in range(bi.shape[0]):
            i = bi[b]
            j = bj[b]
            dx = pos[j, 0] - pos[i, 0]
            dy = pos[j, 1] - pos[i, 1]
            d = np.sqrt(dx * dx + dy * dy)
            nx = dx / d
            ny = dy / d
            fn = kn * (d - rest[b]) + 1e-30 * (rows[b, 3] + rows[b, 4] + rows[b, 5])
            vs = ((vel[j, 1] - vel[i, 1]) * nx - (vel[j, 0] - vel[i, 0]) * ny
                  - spin[i] * rad[i] - spin[j] * rad[j])
            fs = rows[b, 1] + ks * vs * dt
            m = rows[b, 2] + kb * (rot[j] - rot[i])
            shear[b] = 0.5 * shear[b] + fs
            rows[b, 0] = fn
            rows[b, 1] = fs
            rows[b, 2] = m
            fx = fn * nx - fs * ny
            fy = fn * ny + fs * nx
            force[i, 0] += fx
            force[i, 1] += fy
            force[j, 0] -= fx
            force[j, 1] -= fy
            moment[i] += m + rad[i] * fs
            moment[j] += -m + rad[j] * fs
        for k in range(n):
            vel[k, 0] += force[k, 0] * inv_m[k] * dt
            vel[k, 1] += force[k, 1] * inv_m[k] * dt
            spin[k] += moment[k] * inv_i[k] * dt
            pos[k, 0] += vel[k, 0] * dt
            pos[k, 1] += vel[k, 1] * dt
            rot[k] += spin[k] * dt


def bare_loop_on_specimen(module, state, steps: int, bond_state: bool = False) -> float:
    """Seconds per step of the bare loop's `step` over this specimen's own disks and bonds (with
    `bond_state`: of `_bare_step_with_bond_state`)."""
    p, nb = state.particles, state.neighbours.n_bonds
    bi, bj = state.neighbours.pi[:nb].copy(), state.neighbours.pj[:nb].copy()
    pos, radius = p.pos.copy(), p.radius.copy()
    rest = np.hypot(*(pos[bj] - pos[bi]).T)
    n = len(pos)
    kn, dt = 2e10, 1e-8
    args = (pos, np.random.default_rng(0).normal(0, 1e-4, (n, 2)), np.zeros(n), np.zeros(n),
            np.zeros((n, 2)), np.zeros(n), bi, bj, kn, kn / 2, kn * radius.mean()**2 / 3, rest,
            p.inv_mass.copy(), p.inv_inertia.copy(), radius, dt)
    if bond_state:
        nb = len(bi)
        step = lambda k: _bare_step_with_bond_state(*args, k, np.zeros((nb, 8)), np.zeros(nb))
    else:
        step = lambda k: module.step(*args, k)
    step(10)
    started = time.perf_counter()
    step(steps)
    return (time.perf_counter() - started) / steps


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--rounds", type=int, default=3,
                        help="the engine and the bare loop timed in turn this many times; the "
                             "fastest of each counts (timings on a shared machine move 10-20 %%)")
    parser.add_argument("--bond-loop", type=Path,
                        default=Path(__file__).resolve().parent / "bond_loop.py")
    args = parser.parse_args()
    cap = numba.config.NUMBA_NUM_THREADS
    state = ucs_state()
    n, nb = state.n_particles, state.neighbours.n_bonds
    print(f"full-size UCS specimen: {n} disks, {nb} bonds, {len(simulate.neighbours.block_starts(n)) - 1} blocks")

    numba.set_num_threads(1)
    for name, seconds in phases(state, args.steps).items():
        print(f"  {name:30s} {1e3 * seconds:7.3f} ms")
    print("the bond phase's parts, each alone:")
    for name, seconds in bond_parts(ucs_state(), args.steps).items():
        print(f"  {name:30s} {1e3 * seconds:7.3f} ms")
    module = load_bond_loop(args.bond_loop)
    threads = sorted({1, min(2, cap)})
    best = {key: np.inf for key in [*threads, "bare", "same", "state"]}
    for _ in range(args.rounds):
        for t in threads:
            simulate.use_threads(t)
            state = ucs_state()
            best[t] = min(best[t], per_step(lambda: simulate.advance(state, 50), args.steps // 50) / 50)
        numba.set_num_threads(1)
        bare, bare_bonds = bare_loop_seconds_per_step(module, n, 2 * args.steps)
        best["bare"] = min(best["bare"], bare)
        best["same"] = min(best["same"], bare_loop_on_specimen(module, ucs_state(), 2 * args.steps))
        best["state"] = min(best["state"], bare_loop_on_specimen(module, ucs_state(), 2 * args.steps,
                                                                 bond_state=True))
    print(f"fastest of {args.rounds} rounds, each timing the engine and the bare loop in turn:")
    for t in threads:
        print(f"engine, {t} thread(s): {1e3 * best[t]:.3f} ms/step, "
              f"{n / best[t] / 1e6:.1f} M particle-steps/s, {nb / best[t] / 1e6:.1f} M bond-steps/s")
    bare, one = best["bare"], best[1]
    print(f"bare bond loop, 1 thread: {1e3 * bare:.3f} ms/step, {n / bare / 1e6:.1f} M "
          f"particle-steps/s, {bare_bonds / bare / 1e6:.1f} M bond-steps/s ({bare_bonds} bonds)")
    print(f"ratio to the bare loop on 1 thread: {bare / one:.2f} per particle-step, "
          f"{(nb / one) / (bare_bonds / bare):.2f} per bond-step")
    print(f"bare loop's step on this specimen's {nb} bonds, 1 thread: {1e3 * best['same']:.3f} "
          f"ms/step; ratio {best['same'] / one:.2f}")
    print(f"the same carrying a PFC bond's state (forces, moment, contact shear, strengths): "
          f"{1e3 * best['state']:.3f} ms/step")
    if 2 in best:
        print(f"2 threads / 1 thread: {one / best[2]:.2f}x")


if __name__ == "__main__":
    main()
