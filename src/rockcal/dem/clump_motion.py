"""Rigid clumps in the engine: a state's particles as pebbles of rigid bodies (PFC's clumps).

`clump(state, clump_of, density)` makes the particles of a state (`simulate.assemble_state`)
pebbles of rigid clumps (`clumps.members`; -1: a ball, in no clump) and sets `State.clumps`,
after which `simulate.advance`, `stable_time_step` and `scale_density` run through `Clumps`.

A clump is a body (`Body`: centroid, velocity, spin, angle, inverse mass and inertia) of the
mass and polar inertia of its pebbles' union at the density (`clumps.union_properties`; a
one-pebble clump has exactly a ball's, so it moves as the ball, to the bit). Each step runs the
ball engine's pair and wall forces on the pebbles (`simulate._advance`'s, in its order), then,
clump by clump, sums its pebbles' forces and moments about its centroid (Σ F_k and
Σ M_k + r_k × F_k, r_k from the centroid to the pebble's centre as placed, pebbles in
increasing order, then its applied force and moment), applies
PFC local damping to that force and moment, and steps the body by leapfrog (velocity, then
position and angle), as `simulate._move` does a ball; its pebbles are then carried rigidly:
centre at centroid + R(angle) offset, velocity v + ω × r, spin ω. Balls move as in
`simulate._move`. Pebbles of one clump are never in contact nor bonded
(`neighbours.NeighbourList.clump_of`). A clump's motion is set on its body (`Clumps.vel`,
`spin`, then `Clumps.carry_pebbles`): its pebbles' rows are written from it every step.

Deterministic as the ball engine: forces are summed block by block as there, and each clump sums
its own pebbles in a fixed order, so no result depends on the number of threads.
"""

from __future__ import annotations

from dataclasses import replace
from enum import IntEnum
from typing import NamedTuple

import numba
import numpy as np
from numba import njit, prange

from rockcal.dem import clumps as clump_shapes
from rockcal.dem import border, laws, neighbours, simulate, tasks
from rockcal.dem.laws import Disk, Load


class Body(IntEnum):
    """Columns of a clump's row in `Clumps.bodies` (64 bytes)."""

    X = 0  # centroid, m
    Y = 1
    VX = 2  # m/s
    VY = 3
    SPIN = 4  # rad/s
    ANGLE = 5  # rotation since the clump was made, rad (counter-clockwise)
    INV_MASS = 6  # 0: a driven clump, whose velocity and spin are prescribed
    INV_INERTIA = 7


class Clumps(NamedTuple):
    """The rigid clumps of a state (`State.clumps`): which pebbles form each, the pebbles'
    offsets from the centroid in the clump's frame (angle 0), the balls (particles in no clump)
    and the bodies' state; the engine changes `bodies` in place and places the pebbles from it.
    `applied` is a force (N per m of thickness) and moment (N m per m) applied to each clump
    every step (zero unless set: a body force, PFC's applied force and moment)."""

    clump_of: np.ndarray  # per particle: its clump, -1 for a ball
    first: np.ndarray  # clump c's pebbles: pebbles[first[c]:first[c + 1]]
    pebbles: np.ndarray
    offsets: np.ndarray  # (len(pebbles), 2), in the order of `pebbles`, m
    balls: np.ndarray  # the particles in no clump
    bodies: np.ndarray  # (n_clumps, len(Body))
    applied: np.ndarray  # (n_clumps, 3): force x, y and moment

    @property
    def n_clumps(self) -> int:
        return self.bodies.shape[0]

    @property
    def pos(self) -> np.ndarray:
        return self.bodies[:, Body.X:Body.Y + 1]

    @property
    def vel(self) -> np.ndarray:
        return self.bodies[:, Body.VX:Body.VY + 1]

    @property
    def spin(self) -> np.ndarray:
        return self.bodies[:, Body.SPIN]

    @property
    def angle(self) -> np.ndarray:
        return self.bodies[:, Body.ANGLE]

    @property
    def inv_mass(self) -> np.ndarray:
        return self.bodies[:, Body.INV_MASS]

    @property
    def inv_inertia(self) -> np.ndarray:
        return self.bodies[:, Body.INV_INERTIA]

    def carry_pebbles(self, particles: simulate.Particles) -> None:
        """Place every clump's pebbles from its body: after its position, angle, velocity or
        spin were set."""
        _place_clumps(0, self.n_clumps, self.first, self.pebbles, self.offsets, self.bodies,
                      particles.disks, np.zeros((particles.disks.shape[0], 2)))

    def advance(self, state: simulate.State, n_steps: int, threads: int) -> None:
        """`simulate.advance`'s steps on `threads` threads (set there) for a state of clumps."""
        p, w = state.particles, state.walls
        chunks = len(state.neighbours.block_starts) - 1  # as many as blocks: as many threads
        clump_chunks = np.linspace(0, self.n_clumps, chunks + 1).astype(np.int64)
        ball_chunks = np.linspace(0, len(self.balls), chunks + 1).astype(np.int64)
        done = 0
        while done < n_steps:
            pairs = state.neighbours
            done_now, rebuild = _advance_clumps(
                n_steps - done, p.disks, p.loads, pairs.pi, pairs.pj, pairs.shear, state.bonds,
                pairs.block_starts, pairs.bond_offsets, pairs.contact_offsets, w.pos, w.active,
                w.vel, w.force, w.stiffness, pairs.pos_at_build, pairs.rebuild_distance_sq,
                state.laws, state.damping, state.dt, self.first, self.pebbles, self.offsets,
                self.bodies, self.applied, self.balls, clump_chunks, ball_chunks, threads)
            done += done_now
            state.step += done_now
            if rebuild:
                simulate.rebuild_neighbours(state)

    def stable_time_step(self, state: simulate.State) -> float:
        """`simulate.stable_time_step` over bodies: safety x the smallest sqrt(m / k_trans) and
        sqrt(I / k_rot) of any free clump or ball (`_body_stiffness_sums`)."""
        k_trans, k_rot = self._body_stiffness_sums(state)
        inv_mass, inv_inertia = self._body_inverses(state.particles)
        free = inv_mass > 0
        with np.errstate(divide="ignore"):
            dt_t = np.sqrt(1.0 / (inv_mass[free] * k_trans[free]))
            dt_r = np.sqrt(1.0 / (inv_inertia[free] * np.maximum(k_rot[free], 1e-300)))
        return simulate.TIME_STEP_SAFETY * float(min(dt_t.min(), dt_r.min()))

    def scale_density(self, state: simulate.State) -> float:
        """`simulate.scale_density` over bodies: each free clump's and ball's mass and inertia
        set so that its own critical time step is the specimen's smallest. Returns their scaled
        mass over their true mass."""
        k_trans, k_rot = self._body_stiffness_sums(state)
        critical_s = state.dt / simulate.TIME_STEP_SAFETY
        inv_mass, inv_inertia = self._body_inverses(state.particles)
        free = inv_mass > 0
        true_mass = np.sum(1.0 / inv_mass[free])
        inv_mass[free] = 1.0 / (k_trans[free] * critical_s**2)
        inv_inertia[free] = 1.0 / (np.maximum(k_rot[free], 1e-300) * critical_s**2)
        n = self.n_clumps
        self.bodies[:, Body.INV_MASS] = inv_mass[:n]
        self.bodies[:, Body.INV_INERTIA] = inv_inertia[:n]
        state.particles.inv_mass[self.balls] = inv_mass[n:]
        state.particles.inv_inertia[self.balls] = inv_inertia[n:]
        self._label_pebbles(state.particles)
        return float(np.sum(1.0 / inv_mass[free]) / true_mass)

    def unbalanced_forces(self, particles) -> np.ndarray:
        """Each free body's resultant force (N per m; the clumps', then the free balls'): the sum
        of its pebbles' forces, what its motion answers to (a pebble's own force is balanced
        within its rigid clump)."""
        force = np.zeros((self.n_clumps, 2))
        np.add.at(force, self.clump_of[self.pebbles], particles.force[self.pebbles])
        force = np.concatenate([force, particles.force[self.balls]])
        return force[self._body_inverses(particles)[0] > 0]

    def _body_inverses(self, particles) -> tuple[np.ndarray, np.ndarray]:
        """Inverse masses and inertias of the bodies: the clumps', then the balls'."""
        return (np.concatenate([self.bodies[:, Body.INV_MASS], particles.inv_mass[self.balls]]),
                np.concatenate([self.bodies[:, Body.INV_INERTIA],
                                particles.inv_inertia[self.balls]]))

    def _body_of(self) -> np.ndarray:
        """Per particle its body: its clump, or n_clumps + its rank among the balls."""
        body = self.clump_of.copy()
        body[self.balls] = self.n_clumps + np.arange(len(self.balls))
        return body

    def _body_stiffness_sums(self, state) -> tuple[np.ndarray, np.ndarray]:
        """Each body's translational and rotational stiffness, a bound summed over its pebbles'
        listed pairs (as if touching, `simulate.pair_springs`) and a wall per pebble, as
        `simulate._stiffness_sums` does a ball's. A pebble at distance d from its clump's
        centroid turns a pair's contact point (lever arm at most d + R) and its normal line
        (at most d) with the clump: (k_s + k̄s Ā)(d + R)² + (k_n + k̄n Ā) d² + k̄n Ī, and a
        wall's k d²; with d = 0 (a ball) the ball's (k_s + k̄s Ā) R² + k̄n Ī, to the bit."""
        p, pairs = state.particles, state.neighbours
        n = state.n_particles
        kn, ks, kbn, kbs, kbr = simulate.pair_springs(state)
        arm = np.zeros(n)
        arm[self.pebbles] = np.hypot(self.offsets[:, 0], self.offsets[:, 1])
        k_wall = state.walls.stiffness
        k_trans = np.full(n, k_wall)
        k_rot = k_wall * arm**2
        for idx, r in ((pairs.pi, p.radius[pairs.pi]), (pairs.pj, p.radius[pairs.pj])):
            d = arm[idx]
            np.add.at(k_trans, idx, np.maximum(kn, ks) + np.maximum(kbn, kbs))
            np.add.at(k_rot, idx, (ks + kbs) * (d + r)**2 + kbr + (kn + kbn) * d**2)
        body, bodies = self._body_of(), self.n_clumps + len(self.balls)
        body_trans, body_rot = np.zeros(bodies), np.zeros(bodies)
        np.add.at(body_trans, body, k_trans)
        np.add.at(body_rot, body, k_rot)
        return body_trans, body_rot

    def _label_pebbles(self, particles) -> None:
        """Give each pebble's row its clump's inverse mass and inertia (the engine reads the
        clump's; 0 tells a driven pebble, as for a ball)."""
        owner = self.clump_of[self.pebbles]
        particles.inv_mass[self.pebbles] = self.bodies[owner, Body.INV_MASS]
        particles.inv_inertia[self.pebbles] = self.bodies[owner, Body.INV_INERTIA]


def clump(state: simulate.State, clump_of, density: float) -> Clumps:
    """Make the particles of `state` pebbles of rigid clumps (`clump_of`: per particle its clump
    0..n_clumps-1, or -1: a ball) of `density` (kg/m³), at rest where the pebbles lie: each
    clump of its pebbles' union's mass and inertia (`clumps.clump_properties`), driven if one
    of its pebbles is (inverse mass 0). Sets `state.clumps`, drops the pairs within a clump from
    the neighbour list and sets the time step; ValueError if a bond joins two pebbles of one
    clump. Returns the clumps."""
    p, nlist = state.particles, state.neighbours
    clump_of = np.asarray(clump_of, np.int64)
    if clump_of.shape != (state.n_particles,):
        raise ValueError("clump_of: one entry per particle")
    first, pebbles = clump_shapes.members(clump_of)
    bi, bj = nlist.pi[:nlist.n_bonds], nlist.pj[:nlist.n_bonds]
    if ((clump_of[bi] == clump_of[bj]) & (clump_of[bi] >= 0)).any():
        raise ValueError("a bond joins two pebbles of one clump")
    area, centroid, polar = clump_shapes.clump_properties(p.pos, p.radius, first, pebbles)
    lone = np.diff(first) == 1
    pebble = pebbles[first[:-1]]  # each clump's first pebble
    r = p.radius[pebble]
    # a one-pebble clump is a ball: its mass and inertia as simulate.assemble_state's, exactly
    ball_mass = density * np.pi * r**2 * simulate.THICKNESS_M
    mass = np.where(lone, ball_mass, density * area * simulate.THICKNESS_M)
    inertia = np.where(lone, 0.5 * ball_mass * r**2, density * polar * simulate.THICKNESS_M)
    centroid[lone] = p.pos[pebble[lone]]
    driven = np.zeros(len(r), np.bool_)
    np.logical_or.at(driven, clump_of[pebbles], p.inv_mass[pebbles] == 0.0)
    bodies = simulate._aligned_zeros(len(r), len(Body))
    bodies[:, Body.X:Body.Y + 1] = centroid
    bodies[:, Body.INV_MASS] = np.where(driven, 0.0, 1.0 / mass)
    bodies[:, Body.INV_INERTIA] = np.where(driven, 0.0, 1.0 / inertia)
    clumps = Clumps(clump_of=clump_of, first=first, pebbles=pebbles,
                    offsets=p.pos[pebbles] - centroid[clump_of[pebbles]],
                    balls=np.flatnonzero(clump_of < 0), bodies=bodies,
                    applied=np.zeros((len(r), 3)))
    p.vel[pebbles] = 0.0
    p.spin[pebbles] = 0.0
    clumps._label_pebbles(p)
    state.neighbours = neighbours.update(replace(nlist, clump_of=clump_of), p.pos, p.radius)
    state.clumps = clumps
    state.dt = simulate.stable_time_step(state)
    return clumps


@njit(cache=True, error_model="numpy")
def _place_clumps(first_clump, last_clump, first, pebbles, offsets, bodies, disks, pos_at_build):
    """Carry the pebbles of clumps first_clump..last_clump-1 with their bodies
    (`_place_clump`). Returns their largest squared displacement from `pos_at_build`."""
    moved = 0.0
    for c in range(numba.uint64(first_clump), numba.uint64(last_clump)):
        moved = max(moved, _place_clump(c, first, pebbles, offsets, bodies, disks, pos_at_build))
    return moved


@njit(cache=True, error_model="numpy", inline="always")
def _place_clump(c, first, pebbles, offsets, bodies, disks, pos_at_build):
    """Carry clump c's pebbles with its body: centre at centroid + R(angle) offset, velocity
    v + ω × r, spin ω. Returns their largest squared displacement from `pos_at_build`."""
    moved = 0.0
    cos_a = 1.0  # a lone pebble sits at the centroid whatever the angle: no sine to take
    sin_a = 0.0
    if first[c + 1] - first[c] > 1:
        cos_a = np.cos(bodies[c, Body.ANGLE])
        sin_a = np.sin(bodies[c, Body.ANGLE])
    x = bodies[c, Body.X]
    y = bodies[c, Body.Y]
    vx = bodies[c, Body.VX]
    vy = bodies[c, Body.VY]
    spin = bodies[c, Body.SPIN]
    for q in range(numba.uint64(first[c]), numba.uint64(first[c + 1])):
        k = numba.uint64(pebbles[q])
        rx = cos_a * offsets[q, 0] - sin_a * offsets[q, 1]
        ry = sin_a * offsets[q, 0] + cos_a * offsets[q, 1]
        disks[k, Disk.X] = x + rx
        disks[k, Disk.Y] = y + ry
        disks[k, Disk.VX] = vx - spin * ry
        disks[k, Disk.VY] = vy + spin * rx
        disks[k, Disk.SPIN] = spin
        dx = disks[k, Disk.X] - pos_at_build[k, 0]
        dy = disks[k, Disk.Y] - pos_at_build[k, 1]
        moved = max(moved, dx * dx + dy * dy)
    return moved


@njit(cache=True, error_model="numpy")
def _move_clumps(first_clump, last_clump, first, pebbles, offsets, bodies, applied, disks, loads,
                 damping, dt, pos_at_build):
    """Sum each clump's pebble forces and moments about its centroid (pebbles in order, then
    the applied load; lever arms from the centroid to the pebbles' centres as placed), PFC
    local damping and leapfrog on the body (as `simulate._move` on a ball, the same
    operations), then carry its pebbles (`_place_clump`). Returns their largest squared
    displacement since the neighbour list was built."""
    moved = 0.0
    for c in range(numba.uint64(first_clump), numba.uint64(last_clump)):
        q0 = numba.uint64(first[c])
        fx = 0.0
        fy = 0.0
        moment = 0.0
        for q in range(q0, numba.uint64(first[c + 1])):
            k = numba.uint64(pebbles[q])
            rx = disks[k, Disk.X] - bodies[c, Body.X]  # centroid to pebble centre
            ry = disks[k, Disk.Y] - bodies[c, Body.Y]
            f_x = loads[k, Load.FORCE_X]
            f_y = loads[k, Load.FORCE_Y]
            m = loads[k, Load.MOMENT] + (rx * f_y - ry * f_x)
            if q == q0:  # the first pebble's load itself: a one-pebble clump's is the ball's
                fx = f_x
                fy = f_y
                moment = m
            else:
                fx += f_x
                fy += f_y
                moment += m
        fx += applied[c, 0]
        fy += applied[c, 1]
        moment += applied[c, 2]
        inv_mass = bodies[c, Body.INV_MASS]
        if inv_mass > 0.0:
            fx -= damping * abs(fx) * np.sign(bodies[c, Body.VX])
            bodies[c, Body.VX] += fx * inv_mass * dt
            fy -= damping * abs(fy) * np.sign(bodies[c, Body.VY])
            bodies[c, Body.VY] += fy * inv_mass * dt
            m = moment - damping * abs(moment) * np.sign(bodies[c, Body.SPIN])
            bodies[c, Body.SPIN] += m * bodies[c, Body.INV_INERTIA] * dt
        bodies[c, Body.X] += bodies[c, Body.VX] * dt
        bodies[c, Body.Y] += bodies[c, Body.VY] * dt
        bodies[c, Body.ANGLE] += bodies[c, Body.SPIN] * dt
        moved = max(moved, _place_clump(c, first, pebbles, offsets, bodies, disks, pos_at_build))
    return moved


@njit(cache=True, error_model="numpy")
def _move_balls(first_ball, last_ball, balls, disks, loads, damping, dt, pos_at_build):
    """`simulate._move` on balls first_ball..last_ball-1 of the list `balls`."""
    moved = 0.0
    for b in range(numba.uint64(first_ball), numba.uint64(last_ball)):
        k = balls[b]
        moved = max(moved, simulate._move(k, k + 1, disks, loads, damping, dt, pos_at_build))
    return moved


# numba caches this kernel with the law kernels compiled into it, keyed by this file alone:
# after editing laws.py, flatjoint.py or simulate.py in a checkout, clear the caches
# (__pycache__/*.nbi, *.nbc).
@njit(parallel=True, cache=True, error_model="numpy")
def _advance_clumps(n_steps, disks, loads, pi, pj, contact_shear, bonds, starts, bond_offsets,
                    contact_offsets, walls, wall_active, wall_vel, wall_force, k_wall,
                    pos_at_build, half_skin_sq, law, damping, dt, first, pebbles, offsets,
                    bodies, applied, balls, clump_chunks, ball_chunks, threads):
    """`simulate._advance` for a state of clumps: the same pair and wall forces on the pebbles,
    then the clumps (`_move_clumps`) and balls (`_move_balls`) moved chunk by chunk. Returns
    the steps done and whether the list must be rebuilt.

    Three phases a step (`tasks`), one more than the ball engine's: a clump's pebbles may lie in
    several blocks, so the bodies move once every pebble's load is complete; the walls' forces
    stay a phase of their own (called pebble by pebble from the bodies' loop they cost more
    than a phase's wait)."""
    blocks = starts.shape[0] - 1
    chunks = clump_chunks.shape[0] - 1
    phases = (0, blocks + border.TASKS, 2 * blocks + border.TASKS,
              2 * blocks + border.TASKS + chunks)
    moved, shared = tasks.scratch(chunks, phases[-1])
    rows = border.rows(bond_offsets, contact_offsets, laws.LOAD_COMPONENTS)
    workers = max(1, min(threads, blocks))
    for w in prange(workers):
        model = (disks, loads, pi, pj, contact_shear, bonds, starts, bond_offsets,
                 contact_offsets, walls, wall_active, wall_vel, wall_force, k_wall, pos_at_build,
                 law, damping, dt, rows, first, pebbles, offsets, bodies, applied, balls,
                 clump_chunks, ball_chunks)
        for s in range(n_steps):
            if not _step(phases, s, w, workers, shared, model, moved, half_skin_sq):
                break
    done = tasks.steps_done(shared, n_steps)
    if done > 0:
        simulate._move_walls(walls, wall_vel, dt)  # the last step's
    return done, tasks.must_rebuild(moved, half_skin_sq)


@njit(cache=True, error_model="numpy")
def _task(r, s, shared, model, moved, half_skin_sq):
    """Task r of step s: each block's pair forces, the walls' move of the step before and the
    pairs across block borders in halves, each block's border and wall forces, each chunk's
    bodies moved. False if the run stops."""
    (disks, loads, pi, pj, contact_shear, bonds, starts, bond_offsets, contact_offsets, walls,
     wall_active, wall_vel, wall_force, k_wall, pos_at_build, law, damping, dt, rows, first,
     pebbles, offsets, bodies, applied, balls, clump_chunks, ball_chunks) = model
    blocks = starts.shape[0] - 1
    if r < blocks + border.TASKS:
        return simulate.pair_task(r, s, shared, model, moved, half_skin_sq)
    if r < 2 * blocks + border.TASKS:
        b = r - blocks - border.TASKS
        border.add_forces(starts[b], starts[b + 1], pi, pj, bond_offsets, contact_offsets, rows,
                          loads)
        laws.add_wall_forces(starts[b], starts[b + 1], disks, walls, wall_active, k_wall, loads,
                             wall_force)
    else:  # every pebble's load is complete: move the bodies
        c = r - 2 * blocks - border.TASKS
        moved[c] = max(
            _move_clumps(clump_chunks[c], clump_chunks[c + 1], first, pebbles, offsets, bodies,
                         applied, disks, loads, damping, dt, pos_at_build),
            _move_balls(ball_chunks[c], ball_chunks[c + 1], balls, disks, loads, damping, dt,
                        pos_at_build))
    return True


_step = tasks.make_step(_task)
