"""Stepping in time: the state of a bonded-particle model and the explicit integrator.

The state is named parts of plain arrays: particles, the bonded pairs' law state (a
material's: parallel bonds `laws.Bonds`, flat joints `flatjoint.FlatJoints`), walls and the
neighbour list (`neighbours.NeighbourList`), with the law constants, damping and time step.
A material builds it (`rockcal.materials`) with `assemble_state`.
`advance` runs many steps inside one compiled loop (force laws, walls, PFC local damping,
central-difference motion) and hands back to Python only to update the neighbour list, so the
per-step cost is the arithmetic alone.
Each step sums the pair forces block by block and the pairs across block borders in parallel,
then adds the border pairs' forces and moves the particles block by block
(`neighbours.block_layout`): the order of every sum is fixed by the specimen, so results do not
depend on the number of threads. The threads share out these tasks inside one parallel region
per call (`tasks`), not one region per phase.
Everything is SI; disks have unit thickness (PFC2D convention).
A state whose particles are pebbles of rigid clumps (`State.clumps`) runs the same steps in the
clumps' own kernel (`clump_motion`); without clumps nothing here changes.
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import numba
from numba import njit, prange

from rockcal.dem import border, cores, laws, neighbours, tasks
from rockcal.dem.bonded import add_bonded_forces
from rockcal.dem.laws import Disk, Load

THICKNESS_M = 1.0
TIME_STEP_SAFETY = 0.8
LEFT, RIGHT, BOTTOM, TOP = range(4)


class Particles(NamedTuple):
    """Per-particle arrays; the engine changes them in place. They are views into the two
    arrays the engine works on, one row per disk: `disks` (columns `laws.Disk`, 64 bytes: what
    a force loop gathers of a disk is one cache line) and `loads` (columns `laws.Load`)."""

    pos: np.ndarray  # (n, 2), m
    vel: np.ndarray  # (n, 2), m/s
    spin: np.ndarray  # rad/s
    radius: np.ndarray  # m
    inv_mass: np.ndarray  # 0 for driven particles, whose velocity is prescribed
    inv_inertia: np.ndarray
    force: np.ndarray  # (n, 2): force of the last step, N per m of thickness
    moment: np.ndarray
    disks: np.ndarray
    loads: np.ndarray


def new_particles(pos, radius, inv_mass, inv_inertia) -> Particles:
    """Particles at rest, their rows aligned on cache lines."""
    n = pos.shape[0]
    disks = _aligned_zeros(n, len(Disk))
    loads = _aligned_zeros(n, 4)
    disks[:, Disk.X:Disk.Y + 1] = pos
    disks[:, Disk.RADIUS] = radius
    disks[:, Disk.INV_MASS] = inv_mass
    disks[:, Disk.INV_INERTIA] = inv_inertia
    return Particles(pos=disks[:, Disk.X:Disk.Y + 1], vel=disks[:, Disk.VX:Disk.VY + 1],
                     spin=disks[:, Disk.SPIN], radius=disks[:, Disk.RADIUS],
                     inv_mass=disks[:, Disk.INV_MASS], inv_inertia=disks[:, Disk.INV_INERTIA],
                     force=loads[:, Load.FORCE_X:Load.FORCE_Y + 1], moment=loads[:, Load.MOMENT],
                     disks=disks, loads=loads)


def _aligned_zeros(n: int, width: int) -> np.ndarray:
    """Zeros of shape (n, width) float64 starting on a 64-byte boundary."""
    buffer = np.zeros(n * width + 8)
    skip = (-buffer.ctypes.data % 64) // 8
    return buffer[skip:skip + n * width].reshape(n, width)


class Walls(NamedTuple):
    """The four axis-aligned walls (LEFT, RIGHT, BOTTOM, TOP); only active ones push."""

    pos: np.ndarray  # x_left, x_right, y_bottom, y_top, m
    vel: np.ndarray  # m/s
    active: np.ndarray
    force: np.ndarray  # (n, 4): force of each particle on each wall
    stiffness: float  # normal stiffness of a wall contact, N/m

    def total_force(self) -> np.ndarray:
        """Force on each wall (left, right, bottom, top), compression positive, N per m."""
        return _wall_totals(self.force)


@dataclass
class State:
    """A bonded-particle model: its particles, its bonded pairs' law state `bonds` (the first
    pairs of the neighbour list, in its order; its material's type: parallel bonds
    `laws.Bonds`, flat joints `flatjoint.FlatJoints`, with `breaks`, `take_radii`, `springs`
    and a bond phase, `bonded`), walls and neighbour list, the law constants (of the linear
    contacts and parallel bonds), damping and time step."""

    particles: Particles
    bonds: tuple  # laws.Bonds, flatjoint.FlatJoints, ...: its material's
    walls: Walls
    neighbours: neighbours.NeighbourList
    laws: laws.Laws
    damping: float
    dt: float
    step: int = 0
    # rigid clumps of pebbles (`clump_motion.Clumps`: it moves them, and sets their time step
    # and density scaling); None: every particle is a ball
    clumps: object = None

    @property
    def n_particles(self) -> int:
        return self.particles.pos.shape[0]

    def breaks(self) -> tuple[np.ndarray, np.ndarray]:
        """The cracks so far: how each bond broke (laws.INTACT, BROKEN_TENSION, BROKEN_SHEAR) and
        where (m, NaN where intact). With flat joints each element is one: a broken element is a
        crack at its centroid."""
        return self.bonds.breaks()

    def n_broken(self, mode: int | None = None) -> int:
        """Bonds (flat-joint elements) broken so far, in `mode` or (None) either."""
        state = self.breaks()[0]
        return int(np.count_nonzero(state if mode is None else state == mode))

    def advance(self, n_steps: int) -> None:
        """Run `n_steps` time steps (`advance`)."""
        advance(self, n_steps)

    def scale_density(self) -> float:
        """Scale the masses for a quasi-static test (`scale_density`)."""
        return scale_density(self)


@njit(cache=True)
def _wall_totals(a):
    """The walls' (n, 4) forces summed over the particles, row after row as numpy's
    a.sum(axis=0) adds them; each wall's sum in a register of its own (kept in memory, the four
    would wait on each other's stores: a test reads them after every few steps)."""
    s0 = s1 = s2 = s3 = 0.0
    for k in range(a.shape[0]):
        s0 += a[k, 0]
        s1 += a[k, 1]
        s2 += a[k, 2]
        s3 += a[k, 3]
    return np.array([s0, s1, s2, s3])


# How a contact's normal stiffness follows from E_c (`laws.Laws`): PFC 5's deformability
# method, or PFC 3.x/4.0's ball stiffnesses 2·t·E_c in series (Potyondy & Cundall 2004).
CONTACT_STIFFNESS = ("pfc5", "pfc4")
# PFC 3.x/4.0's by default: the PFC2D of Potyondy & Cundall (2004) and of the source study, whose
# parameters (E_c, kn/ks) rockcal calibrates; with it the source's own PFC2D table is met (the
# documentation's Validation pages).
DEFAULT_CONTACT_STIFFNESS = "pfc4"


def assemble_state(pos, radius, pairs, density: float, damping: float, laws_si: laws.Laws,
                   wall_modulus: float, bonded, *, walls=(0.0, 0.0, 0.0, 0.0),
                   wall_active=(False,) * 4, driven=None, skin=None) -> State:
    """A state at rest: grains of `density` (kg/m³; `driven` ones have their velocities
    prescribed), the bonded `pairs` (i < j) first in the neighbour list and
    `bonded(pos, radius, nlist, order)` -> their law state (its material's: `State.bonds`) in
    the list's order (its pair k is pairs[order[k]]), walls of normal stiffness
    2 t x `wall_modulus` (Pa), and the stable time step."""
    n = pos.shape[0]
    radius = np.array(radius, float)
    mass = density * np.pi * radius**2 * THICKNESS_M
    inv_mass = 1.0 / mass
    inv_inertia = 1.0 / (0.5 * mass * radius**2)
    if driven is not None:
        inv_mass[driven] = 0.0
        inv_inertia[driven] = 0.0
    pos = np.ascontiguousarray(pos, float)
    nlist, order = neighbours.allocate(pos, radius, pairs,
                                       skin if skin is not None else 0.5 * radius.min())
    bonds = bonded(pos, radius, nlist, order)
    state = State(
        particles=new_particles(pos, radius, inv_mass, inv_inertia),
        bonds=bonds,
        walls=Walls(pos=np.array(walls, float), vel=np.zeros(4),
                    active=np.array(wall_active, np.bool_), force=np.zeros((n, 4)),
                    stiffness=2.0 * THICKNESS_M * wall_modulus),
        neighbours=nlist, laws=laws_si, damping=damping, dt=0.0,
    )
    state.dt = stable_time_step(state)
    return state


def rebuild_neighbours(state: State) -> None:
    """Rebuild the neighbour list at the particles' positions, and give the bonds their
    particles' radii (needed after changing radii)."""
    p, nb = state.particles, state.neighbours.n_bonds
    state.neighbours = neighbours.update(state.neighbours, p.pos, p.radius)
    state.bonds.take_radii(p.radius, state.neighbours.pi[:nb], state.neighbours.pj[:nb])


def stable_time_step(state: State) -> float:
    """Safety x the smallest sqrt(m / k_translational) and sqrt(I / k_rotational) of any particle.

    Stiffness sums count every listed pair (as if touching) and the walls, as PFC does.
    With clumps, of every clump and ball (`clump_motion.Clumps.stable_time_step`).
    """
    if state.clumps is not None:
        return state.clumps.stable_time_step(state)
    p = state.particles
    k_trans, k_rot = _stiffness_sums(state)
    free = p.inv_mass > 0
    with np.errstate(divide="ignore"):
        dt_t = np.sqrt(1.0 / (p.inv_mass[free] * k_trans[free]))
        dt_r = np.sqrt(1.0 / (p.inv_inertia[free] * np.maximum(k_rot[free], 1e-300)))
    return TIME_STEP_SAFETY * float(min(dt_t.min(), dt_r.min()))


def unbalanced_forces(state: State) -> np.ndarray:
    """Each free body's resultant force (n, 2), N per m: a ball's, or with clumps each clump's
    and ball's (`clump_motion.Clumps.unbalanced_forces`)."""
    if state.clumps is not None:
        return state.clumps.unbalanced_forces(state.particles)
    return state.particles.force[state.particles.inv_mass > 0]


def scale_density(state: State) -> float:
    """Density scaling for quasi-static tests, as PFC's timestep scaling (`model mechanical
    timestep scale`) scales the inertial masses: each free particle's mass and moment of
    inertia are lowered so that its own critical time step equals the specimen's smallest, the
    time step unchanged (set once, on the listed pairs). The heavy particles no longer lag
    behind the light one that sets the time step: stress waves cross the specimen in fewer
    steps, and a test may load it faster for the same equilibrium (each test's loading rate is
    its own, checked by halving it). Returns the free particles' scaled mass over their true
    mass. With clumps, every clump's and ball's (`clump_motion.Clumps.scale_density`)."""
    if state.clumps is not None:
        return state.clumps.scale_density(state)
    p = state.particles
    k_trans, k_rot = _stiffness_sums(state)
    critical_s = state.dt / TIME_STEP_SAFETY
    free = p.inv_mass > 0
    true_mass = np.sum(1.0 / p.inv_mass[free])
    p.inv_mass[free] = 1.0 / (k_trans[free] * critical_s**2)
    p.inv_inertia[free] = 1.0 / (np.maximum(k_rot[free], 1e-300) * critical_s**2)
    return float(np.sum(1.0 / p.inv_mass[free]) / true_mass)


def _stiffness_sums(state: State) -> tuple[np.ndarray, np.ndarray]:
    """Each particle's translational and rotational stiffness, summed over every listed pair (as
    if touching: the larger of normal and shear, contact plus bond) and the walls. A bonded
    pair adds its bond's springs (`State.bonds.springs`: a flat joint's as a bonded interface,
    k_n A, k_s A; k_n (2/3) R̄³ t in rotation), and a flat joint is its pair's only spring."""
    p, pairs = state.particles, state.neighbours
    ri, rj = p.radius[pairs.pi], p.radius[pairs.pj]
    kn, ks, kbn, kbs, kbr = pair_springs(state)
    n = state.n_particles
    k_trans = np.full(n, state.walls.stiffness)
    k_rot = np.zeros(n)
    for idx, r in ((pairs.pi, ri), (pairs.pj, rj)):
        np.add.at(k_trans, idx, np.maximum(kn, ks) + np.maximum(kbn, kbs))
        np.add.at(k_rot, idx, (ks + kbs) * r**2 + kbr)
    return k_trans, k_rot


def pair_springs(state: State):
    """Each listed pair's springs: contact k_n, k_s (N/m) and its bond's k̄n Ā, k̄s Ā (N/m) and
    k̄n Ī (N m/rad), zero for unbonded pairs (`_stiffness_sums`)."""
    E_c, ks_per_kn = state.laws[:2]
    p, pairs, nb = state.particles, state.neighbours, state.neighbours.n_bonds
    ri, rj = p.radius[pairs.pi], p.radius[pairs.pj]
    length = ri + rj
    rmin = np.minimum(ri, rj)
    kn = np.full_like(length, E_c * THICKNESS_M) if state.laws.pfc4_contacts else \
        2 * rmin * THICKNESS_M * E_c / length
    if state.bonds.REPLACES_CONTACT:
        kn[:nb] = 0.0
    kbn, kbs, kbr = (np.concatenate([k, np.zeros(len(ri) - nb)]) for k in state.bonds.springs(
        rmin[:nb], length[:nb], state.laws, THICKNESS_M))
    return kn, kn * ks_per_kn, kbn, kbs, kbr


@njit(cache=True, error_model="numpy")
def _move(first, last, disks, loads, damping, dt, pos_at_build):
    """PFC local damping (force reduced by damping*|F| against the velocity), then leapfrog, of
    particles first..last-1. Returns their largest squared displacement since the neighbour
    list was built."""
    moved = 0.0
    for k in range(numba.uint64(first), numba.uint64(last)):
        inv_mass = disks[k, Disk.INV_MASS]
        if inv_mass > 0.0:
            for a in range(2):
                f = loads[k, Load.FORCE_X + a]
                f -= damping * abs(f) * np.sign(disks[k, Disk.VX + a])
                disks[k, Disk.VX + a] += f * inv_mass * dt
            moment = loads[k, Load.MOMENT]
            m = moment - damping * abs(moment) * np.sign(disks[k, Disk.SPIN])
            disks[k, Disk.SPIN] += m * disks[k, Disk.INV_INERTIA] * dt
        disks[k, Disk.X] += disks[k, Disk.VX] * dt
        disks[k, Disk.Y] += disks[k, Disk.VY] * dt
        dx = disks[k, Disk.X] - pos_at_build[k, 0]
        dy = disks[k, Disk.Y] - pos_at_build[k, 1]
        moved = max(moved, dx * dx + dy * dy)
    return moved


# numba caches this kernel with the law kernels compiled into it, keyed by this file alone:
# after editing laws.py or flatjoint.py in a checkout, clear the caches (__pycache__/*.nbi, *.nbc).
@njit(parallel=True, cache=True, error_model="numpy")
def _advance(n_steps, disks, loads, pi, pj, contact_shear, bonds, starts, bond_offsets,
             contact_offsets, walls, wall_active, wall_vel, wall_force, k_wall, pos_at_build,
             half_skin_sq, law, damping, dt, threads):
    """Run up to n_steps on up to `threads` threads (at most one per block); stop early when
    the list must be rebuilt. Returns the steps done and whether the list must be rebuilt. The
    bonded pairs' phase is the one of `bonds`' type (`bonded`): compiled, and cached, once per
    material. A step's tasks (`_task`) run in one parallel region per call (`tasks`)."""
    blocks = starts.shape[0] - 1
    phases = (0, blocks + border.TASKS, 2 * blocks + border.TASKS)
    moved, shared = tasks.scratch(blocks, phases[-1])
    rows = border.rows(bond_offsets, contact_offsets, laws.LOAD_COMPONENTS)
    workers = max(1, min(threads, blocks))
    for w in prange(workers):
        model = (disks, loads, pi, pj, contact_shear, bonds, starts, bond_offsets,
                 contact_offsets, walls, wall_active, wall_vel, wall_force, k_wall, pos_at_build,
                 law, damping, dt, rows)
        for s in range(n_steps):
            if not _step(phases, s, w, workers, shared, model, moved, half_skin_sq):
                break
    done = tasks.steps_done(shared, n_steps)
    if done > 0:
        _move_walls(walls, wall_vel, dt)  # the last step's
    return done, tasks.must_rebuild(moved, half_skin_sq)


@njit(cache=True, error_model="numpy")
def _task(r, s, shared, model, moved, half_skin_sq):
    """Task r of step s: each block's pair forces, the walls' move of the step before and the
    pairs across block borders in halves (`pair_task`), each block's border forces, walls and
    motion. False if the run stops."""
    blocks = moved.shape[0]
    if r < blocks + border.TASKS:
        return pair_task(r, s, shared, model, moved, half_skin_sq)
    (disks, loads, pi, pj, contact_shear, bonds, starts, bond_offsets, contact_offsets, walls,
     wall_active, wall_vel, wall_force, k_wall, pos_at_build, law, damping, dt, rows) = model
    b = r - blocks - border.TASKS
    border.add_forces(starts[b], starts[b + 1], pi, pj, bond_offsets, contact_offsets, rows,
                      loads)
    laws.add_wall_forces(starts[b], starts[b + 1], disks, walls, wall_active, k_wall, loads,
                         wall_force)
    moved[b] = _move(starts[b], starts[b + 1], disks, loads, damping, dt, pos_at_build)
    return True


@njit(cache=True, error_model="numpy")
def pair_task(r, s, shared, model, moved, half_skin_sq):
    """Task r < blocks + border.TASKS of step s of an engine of disks (`model` begins with
    `_advance`'s arrays): block r's pair forces, or a half of the pairs across block borders
    into their rows (`border`; the first half also moves the walls by the step before). False
    if the run stops."""
    (disks, loads, pi, pj, contact_shear, bonds, starts, bond_offsets, contact_offsets, walls,
     wall_active, wall_vel, wall_force, k_wall, pos_at_build, law, damping, dt, rows) = model[:19]
    blocks = starts.shape[0] - 1
    if tasks.stop_if_moved(s, shared, moved, half_skin_sq):
        return False
    if r < blocks:
        for k in range(numba.uint64(starts[r]), numba.uint64(starts[r + 1])):
            loads[k, Load.FORCE_X] = 0.0
            loads[k, Load.FORCE_Y] = 0.0
            loads[k, Load.MOMENT] = 0.0
        add_bonded_forces(bond_offsets[r], bond_offsets[r + 1], disks, pi, pj, contact_shear,
                          bonds, law, dt, loads)
        laws.add_contact_forces(contact_offsets[r], contact_offsets[r + 1], disks, pi, pj,
                                contact_shear, law, dt, loads)
        return True
    task = r - blocks
    if task == 0 and s > 0:
        _move_walls(walls, wall_vel, dt)
    (b0, b1, bond_rows), (c0, c1, contact_rows) = border.task_pairs(task, bond_offsets,
                                                                    contact_offsets, rows)
    add_bonded_forces(b0, b1, disks, pi, pj, contact_shear, bonds, law, dt, rows, bond_rows)
    laws.add_contact_forces(c0, c1, disks, pi, pj, contact_shear, law, dt, rows, contact_rows)
    return True


_step = tasks.make_step(_task)


@njit(cache=True)
def _move_walls(walls, wall_vel, dt):
    for w in range(4):
        walls[w] += wall_vel[w] * dt


def use_threads(count: int | None) -> None:
    """Run the engine on `count` of numba's threads, or (None, the default) on as many as
    there are free cores (`cores.FreeCores`)."""
    global _follow_load
    if count is not None:
        numba.set_num_threads(count)
    _follow_load = count is None


_follow_load = True
_free_cores = cores.FreeCores()


def advance(state: State, n_steps: int) -> None:
    """Run n_steps time steps, rebuilding the neighbour list whenever particles moved enough,
    on `engine_threads`."""
    with engine_threads(len(state.neighbours.block_starts) - 1) as threads:
        _advance_all(state, n_steps, threads)


@contextlib.contextmanager
def engine_threads(blocks: int):
    """The threads a run of steps takes, numba's set to them while it runs: at most one per
    block (a small specimen is one block, and a parallel loop over it would cost more in
    waiting than it saves) and, unless `use_threads` fixed their number, one per free core."""
    cap = numba.get_num_threads()
    threads = min(cap, blocks)
    if threads > 1 and _follow_load:
        threads = min(threads, _free_cores.now() or threads)
    threads = max(1, threads)
    if threads == cap:  # setting the count costs as much as a few steps of a small specimen
        yield threads
        return
    numba.set_num_threads(threads)
    try:
        yield threads
    finally:
        numba.set_num_threads(cap)


def _advance_all(state: State, n_steps: int, threads: int) -> None:
    if state.clumps is not None:  # pebbles of rigid clumps: the clumps' kernel
        state.clumps.advance(state, n_steps, threads)
        return
    p, w = state.particles, state.walls
    done = 0
    while done < n_steps:
        pairs = state.neighbours
        done_now, rebuild = _advance(
            n_steps - done, p.disks, p.loads, pairs.pi, pairs.pj, pairs.shear, state.bonds,
            pairs.block_starts, pairs.bond_offsets, pairs.contact_offsets, w.pos, w.active,
            w.vel, w.force, w.stiffness, pairs.pos_at_build, pairs.rebuild_distance_sq,
            state.laws, state.damping, state.dt, threads)
        done += done_now
        state.step += done_now
        if rebuild and not neighbours.release_lone_movers(p.pos, p.radius, pairs.pos_at_build,
                                                          pairs.skin):
            rebuild_neighbours(state)
