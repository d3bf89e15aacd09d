"""Stepping in time: the state of a 3D bonded-particle model and the explicit integrator.

`advance` runs many steps inside one compiled loop (pair laws, PFC local damping, central
differences) and returns to Python only to rebuild the neighbour list. Each step sums the
pairs' forces block by block in parallel, then the pairs across block borders, then adds the
walls' pushes and moves the spheres block by block, then moves the walls: the order of every
sum is fixed by the specimen, so a run's numbers do not depend on the number of threads. SI
units. A state whose spheres are pebbles of rigid clumps (`State.clumps`) runs the same steps
in the clumps' own kernel (`clump_motion`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numba
import numpy as np
from numba import njit, prange

from rockcal.dem import border, tasks
from rockcal.dem.simulate import engine_threads
from rockcal.dem3d import flat_joint, forces, neighbours
from rockcal.dem3d import walls as planes
from rockcal.dem3d.bonds import Bonds, new_bonds, no_bonds
from rockcal.dem3d.laws import INTACT, Laws, contact_springs
from rockcal.dem3d.state import LOAD_COMPONENTS, Load, Sphere, Spheres, new_spheres
from rockcal.dem3d.vectors import norms

TIME_STEP_SAFETY = 0.8
# what the stepping loop is given for the material a state has not
_NO_BONDS = no_bonds()
_NO_JOINTS = flat_joint.no_flatjoints_3d()


@dataclass
class State:
    """A bonded sphere model: spheres, bonds (the first pairs of the neighbour list: parallel
    bonds, `bonds.Bonds`, or flat joints, `flat_joint.FlatJoints3D`), the neighbour list, the
    law constants, local damping, time step and walls (planes, a cylinder; none unless given:
    `walls`)."""

    spheres: Spheres
    bonds: Bonds | flat_joint.FlatJoints3D
    neighbours: neighbours.NeighbourList
    laws: Laws
    damping: float
    dt: float
    step: int = 0
    walls: planes.Walls = field(default_factory=planes.no_walls)
    clumps: object = None  # rigid clumps of pebbles (`clump_motion.Clumps3D`), which move them

    @property
    def n_spheres(self) -> int:
        return self.spheres.pos.shape[0]

    @property
    def particles(self) -> Spheres:  # the engine protocol's name (`rockcal.engine`)
        return self.spheres

    @property
    def n_particles(self) -> int:
        return self.n_spheres

    def breaks(self) -> tuple[np.ndarray, np.ndarray]:
        """How each bond (each flat-joint element) broke (laws.INTACT, BROKEN_TENSION,
        BROKEN_SHEAR) and where (m)."""
        return self.bonds.breaks()

    def n_broken(self, mode: int | None = None) -> int:
        """Bonds broken so far, in `mode` (laws.BROKEN_TENSION, BROKEN_SHEAR) or (None) either."""
        state = self.bonds.breaks()[0]
        return int(np.count_nonzero(state != INTACT if mode is None else state == mode))

    def advance(self, n_steps: int) -> None:
        """Run `n_steps` time steps (`advance`)."""
        advance(self, n_steps)

    def scale_density(self) -> float:
        """Scale the masses for a quasi-static test (`scale_density`)."""
        return scale_density(self)


def assemble_state(pos, radius, pairs, density: float, laws: Laws, *, damping=0.7,
                   ten=np.inf, coh=np.inf, driven=None, skin=None, walls=None,
                   joints=None) -> State:
    """A state at rest: spheres of `density` (kg/m³; `driven` ones keep their prescribed
    velocity and spin), parallel bonds at the `pairs` (i < j) with tensile strength `ten` and
    cohesion `coh` (Pa; one value or one per pair, in the order of `pairs`), each taking its
    pair's overlap at installation as its reference; or, with `joints`, the bonded pairs'
    state it makes, `joints(pos, radius, pi, pj, order)` (pi, pj: the bonded pairs in the
    list's order, `order` the pairs' rows in `pairs`); `walls` (`walls.Walls`, default none);
    and the stable time step."""
    pos = np.ascontiguousarray(pos, float)
    radius = np.asarray(radius, float)
    pairs = np.asarray(pairs, np.int64).reshape(-1, 2)
    nlist, order = neighbours.allocate(pos, radius, pairs,
                                       skin if skin is not None else 0.5 * radius.min())
    pi, pj = nlist.pi[:nlist.n_bonds], nlist.pj[:nlist.n_bonds]
    overlap = radius[pi] + radius[pj] - norms(pos[pj] - pos[pi])
    if joints is None:
        ten, coh = (np.broadcast_to(np.asarray(v, float), len(pairs))[order] for v in (ten, coh))
        bonded = new_bonds(overlap, ten, coh, radius[pi], radius[pj])
    else:
        bonded = joints(pos, radius, pi, pj, order)
    state = State(spheres=new_spheres(pos, radius, density, driven),
                  bonds=bonded,
                  neighbours=nlist,
                  laws=laws, damping=damping, dt=0.0,
                  walls=walls if walls is not None else planes.no_walls())
    state.dt = stable_time_step(state)
    return state


def rebuild_neighbours(state: State) -> None:
    """Rebuild the neighbour list at the spheres' positions and give the bonds their spheres'
    radii (needed after changing radii)."""
    s, nb = state.spheres, state.neighbours.n_bonds
    state.neighbours = neighbours.update(state.neighbours, s.pos, s.radius)
    state.bonds.take_radii(s.radius[state.neighbours.pi[:nb]], s.radius[state.neighbours.pj[:nb]])


def stiffness_sums(state: State) -> tuple[np.ndarray, np.ndarray]:
    """Each sphere's translational and rotational stiffness, summed over every listed pair as
    if touching (the 2D engine's rule): max(kn, ks) + max(k̄n Ā, k̄s Ā) in translation,
    (ks + k̄s Ā) R² + max(k̄n Ī, k̄s J̄) in rotation (R the sphere's own radius); and π E R
    in translation for each wall within the list's skin (`walls.wall_springs`). A flat joint
    counts as an intact bond of its own springs and replaces its pair's contact."""
    s, pairs, nb = state.spheres, state.neighbours, state.neighbours.n_bonds
    ri, rj = s.radius[pairs.pi], s.radius[pairs.pj]
    rmin, length = np.minimum(ri, rj), ri + rj
    kn, ks = contact_springs(rmin, length, state.laws)
    if state.bonds.REPLACES_CONTACT:
        kn[:nb] = ks[:nb] = 0.0
    kbn, kbs, kbt, kbb = (np.concatenate([k, np.zeros(len(ri) - nb)])
                          for k in state.bonds.springs(rmin[:nb], length[:nb], state.laws))
    n = state.n_spheres
    k_trans, k_rot = np.zeros(n), np.zeros(n)
    for idx, r in ((pairs.pi, ri), (pairs.pj, rj)):
        np.add.at(k_trans, idx, np.maximum(kn, ks) + np.maximum(kbn, kbs))
        np.add.at(k_rot, idx, (ks + kbs) * r**2 + np.maximum(kbt, kbb))
    if len(state.walls.table):
        k_trans += planes.wall_springs(state.walls, s.pos, s.radius, state.neighbours.skin)
    return k_trans, k_rot


def stable_time_step(state: State) -> float:
    """Safety × the smallest sqrt(m / k_translational) and sqrt(I / k_rotational) of any free
    sphere (`stiffness_sums`); inf if no free sphere has a spring. With clumps, of every clump
    and ball (`clump_motion.Clumps3D.stable_time_step`)."""
    if state.clumps is not None:
        return state.clumps.stable_time_step(state)
    s = state.spheres
    k_trans, k_rot = stiffness_sums(state)
    free = (s.inv_mass > 0) & (k_trans > 0)
    if not free.any():
        return np.inf
    dt_t = np.sqrt(1.0 / (s.inv_mass[free] * k_trans[free]))
    dt_r = np.sqrt(1.0 / (s.inv_inertia[free] * np.maximum(k_rot[free], 1e-300)))
    return TIME_STEP_SAFETY * float(min(dt_t.min(), dt_r.min()))


def scale_density(state: State) -> float:
    """Density scaling for quasi-static runs, as the 2D engine (PFC's `timestep scale`): each
    free sphere's mass and inertia set so that its own critical step equals the specimen's,
    the time step unchanged. Returns the scaled over the true mass of the free spheres. With
    clumps, of every clump and ball (`clump_motion.Clumps3D.scale_density`)."""
    if state.clumps is not None:
        return state.clumps.scale_density(state)
    s = state.spheres
    k_trans, k_rot = stiffness_sums(state)
    critical_s = state.dt / TIME_STEP_SAFETY
    free = (s.inv_mass > 0) & (k_trans > 0)
    true_mass = np.sum(1.0 / s.inv_mass[free])
    s.inv_mass[free] = 1.0 / (k_trans[free] * critical_s**2)
    s.inv_inertia[free] = 1.0 / (np.maximum(k_rot[free], 1e-300) * critical_s**2)
    return float(np.sum(1.0 / s.inv_mass[free]) / true_mass)


@njit(cache=True, error_model="numpy")
def _move(first, last, bodies, loads, damping, dt, pos_at_build):
    """PFC local damping (each force and moment component reduced by damping × its size against
    its velocity), then central differences, of spheres first..last-1; driven spheres keep
    their velocity and spin. Returns their largest squared displacement since the list was
    built."""
    moved = 0.0
    for k in range(numba.uint64(first), numba.uint64(last)):
        inv_mass = bodies[k, Sphere.INV_MASS]
        if inv_mass > 0.0:
            inv_inertia = bodies[k, Sphere.INV_INERTIA]
            for a in range(3):
                f = loads[k, Load.FX + a]
                f -= damping * abs(f) * np.sign(bodies[k, Sphere.VX + a])
                bodies[k, Sphere.VX + a] += f * inv_mass * dt
                m = loads[k, Load.MX + a]
                m -= damping * abs(m) * np.sign(bodies[k, Sphere.WX + a])
                bodies[k, Sphere.WX + a] += m * inv_inertia * dt
        dist_sq = 0.0
        for a in range(3):
            bodies[k, Sphere.X + a] += bodies[k, Sphere.VX + a] * dt
            step = bodies[k, Sphere.X + a] - pos_at_build[k, a]
            dist_sq += step * step
        moved = max(moved, dist_sq)
    return moved


# numba caches this kernel with the law kernels compiled into it, keyed by this file alone:
# after editing laws.py, forces.py or flat_joint.py in a checkout, clear the caches
# (__pycache__/*.nbi, *.nbc).
@njit(parallel=True, cache=True, error_model="numpy")
def _advance(n_steps, bodies, loads, pi, pj, shear, bonds, joints, starts,
             bond_offsets, contact_offsets, pos_at_build, half_skin_sq, laws, damping, dt,
             walls, wall_force, threads):
    """Run up to n_steps on up to `threads` threads (at most one per block); stop early when
    the list must be rebuilt. Returns the steps done and whether the list must be rebuilt. The
    walls push the spheres of each block, their reactions summed block by block into
    `wall_force`, and move after the spheres. A step's tasks (`_task`) run in one parallel
    region per call (`rockcal.dem.tasks`)."""
    blocks = starts.shape[0] - 1
    phases = (0, blocks + border.TASKS, 2 * blocks + border.TASKS)
    moved, shared = tasks.scratch(blocks, phases[-1])
    wall_parts = _wall_parts(blocks, walls.shape[0])
    rows = border.rows(bond_offsets, contact_offsets, LOAD_COMPONENTS)
    workers = max(1, min(threads, blocks))
    for w in prange(workers):
        model = (bodies, loads, pi, pj, shear, bonds, joints, starts,
                 bond_offsets, contact_offsets, pos_at_build, laws, damping, dt, walls,
                 wall_force, wall_parts, rows)
        for s in range(n_steps):
            if not _step(phases, s, w, workers, shared, model, moved, half_skin_sq):
                break
    done = tasks.steps_done(shared, n_steps)
    if done > 0:
        _walls_after_step(walls, wall_force, wall_parts, dt)  # the last step's
    return done, tasks.must_rebuild(moved, half_skin_sq)


@njit(cache=True, error_model="numpy")
def _task(r, s, shared, model, moved, half_skin_sq):
    """Task r of step s: each block's pair forces, beside them the walls of the step before
    (their forces summed, their move) and the pairs across block borders in halves, into their
    rows (`rockcal.dem.border`); then each block's border and wall forces and motion. False if
    the run stops."""
    (bodies, loads, pi, pj, shear, bonds, joints, starts, bond_offsets,
     contact_offsets, pos_at_build, laws, damping, dt, walls, wall_force, wall_parts,
     rows) = model
    blocks = moved.shape[0]
    if r < blocks + border.TASKS and tasks.stop_if_moved(s, shared, moved, half_skin_sq):
        return False
    if r < blocks:
        for k in range(numba.uint64(starts[r]), numba.uint64(starts[r + 1])):
            for c in range(6):
                loads[k, c] = 0.0
        _bonded_forces(bond_offsets[r], bond_offsets[r + 1], bodies, loads, pi, pj, bonds, joints,
                       laws, dt)
        forces.add_contact_forces(contact_offsets[r], contact_offsets[r + 1], bodies, loads, pi,
                                  pj, shear, laws, dt)
    elif r < blocks + border.TASKS:
        task = r - blocks
        if task == 0 and s > 0:
            _walls_after_step(walls, wall_force, wall_parts, dt)
        (b0, b1, bond_rows), (c0, c1, contact_rows) = border.task_pairs(task, bond_offsets,
                                                                        contact_offsets, rows)
        _bonded_forces(b0, b1, bodies, rows, pi, pj, bonds, joints, laws, dt, bond_rows)
        forces.add_contact_forces(c0, c1, bodies, rows, pi, pj, shear, laws, dt, contact_rows)
    else:
        b = r - blocks - border.TASKS
        border.add_forces(starts[b], starts[b + 1], pi, pj, bond_offsets, contact_offsets, rows,
                          loads)
        part = wall_parts[b]
        part[:] = 0.0
        planes.add_wall_forces(starts[b], starts[b + 1], bodies, loads, walls, part)
        moved[b] = _move(starts[b], starts[b + 1], bodies, loads, damping, dt, pos_at_build)
    return True


_step = tasks.make_step(_task)


@njit(cache=True, error_model="numpy", inline="always")
def _bonded_forces(first, last, bodies, loads, pi, pj, bonds, joints, laws, dt, into_rows=-1):
    """The bonded pairs first..last-1: flat joints if the state has them, else parallel bonds.
    One kernel for both materials: numba compiles the stepping loop once."""
    if joints.table.shape[1] > 0:
        flat_joint.add_flatjoint_forces(first, last, bodies, loads, pi, pj, joints, dt, into_rows)
    else:
        forces.add_bond_forces(first, last, bodies, loads, pi, pj, bonds.table, bonds.state,
                               bonds.break_xyz, laws, dt, into_rows)


@njit(cache=True)
def _wall_parts(blocks, n_walls):
    """Each block's share of each wall's force, zeroed (`tasks.scratch` says why here)."""
    return np.zeros((blocks, n_walls, 3))


@njit(cache=True)
def _walls_after_step(walls, wall_force, wall_parts, dt):
    """The walls' forces summed over the blocks, block by block; then the walls moved."""
    for w in range(walls.shape[0]):
        for a in range(3):
            total = 0.0
            for b in range(wall_parts.shape[0]):
                total += wall_parts[b, w, a]
            wall_force[w, a] = total
    planes.move_walls(walls, dt)


def advance(state: State, n_steps: int) -> None:
    """Run n_steps time steps, rebuilding the neighbour list whenever spheres moved enough; on
    numba's threads as the 2D engine (`rockcal.dem.simulate.advance`): at most one per block and,
    by default, one per free core. With clumps, the clumps' kernel (`clump_motion`)."""
    if state.clumps is not None:
        return state.clumps.advance(state, n_steps)
    with engine_threads(len(state.neighbours.block_starts) - 1) as threads:
        done = 0
        s = state.spheres
        flat = isinstance(state.bonds, flat_joint.FlatJoints3D)
        bonds, joints = (_NO_BONDS, state.bonds) if flat else (state.bonds, _NO_JOINTS)
        while done < n_steps:
            pairs = state.neighbours
            done_now, rebuild = _advance(
                n_steps - done, s.bodies, s.loads, pairs.pi, pairs.pj, pairs.shear, bonds,
                joints, pairs.block_starts, pairs.bond_offsets,
                pairs.contact_offsets, pairs.pos_at_build, pairs.rebuild_distance_sq,
                state.laws, state.damping, state.dt, state.walls.table, state.walls.force,
                threads)
            done += done_now
            state.step += done_now
            if rebuild:
                state.neighbours = neighbours.update(pairs, s.pos, s.radius)
