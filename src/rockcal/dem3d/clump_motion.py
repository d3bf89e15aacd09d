"""Rigid clumps in the 3D engine: a state's spheres as pebbles of rigid bodies (PFC3D's clumps).

`clump(state, clump_of, density)` makes the spheres of a state (`simulate.assemble_state`)
pebbles of rigid clumps (`dem.clumps.members`; -1: a ball, in no clump) and sets
`State.clumps`, after which `simulate.advance`, `stable_time_step` and `scale_density` run
through `Clumps3D`.

A clump is a body (`Body`): centroid, velocity, angular momentum L and angular velocity ω (both
in the world frame), orientation as a unit quaternion q (from the clump's frame, the world's
when it was made, to the world), inverse mass, and its inverse inertia tensor in its own frame
(`inv_inertia`), of its pebbles' union at the density (`clumps.union_properties`). Each step
runs the ball engine's pair and wall forces on the pebbles (`forces`, `walls`), then, clump by
clump, sums its pebbles' forces and moments about its centroid (Σ F_k and
Σ M_k + r_k × F_k, pebbles in increasing order, then its `applied` force and moment), applies
PFC's local damping to each component of that force and moment (against the velocity and the
angular velocity), and steps the body by central differences as the ball engine does a sphere:
v and L at the half step, x and q at the whole. The angular velocity ω = R I⁻¹ Rᵀ L (I the
inertia tensor in the clump's frame, R the rotation of q) turns q by the midpoint rule: ω at
the orientation half a step on, then q turned by ω dt. A torque-free clump so keeps L to the
bit, and its kinetic energy ½ ω · L to second order in the time step. Its pebbles are then
carried rigidly: centre at centroid + R offset, velocity v + ω × r, spin ω. Pebbles of one
clump never touch (`neighbours.NeighbourList.clump_of`) nor are bonded.

The clumps' steps run on one thread (`_advance_clumps`): the pairs in the list's order, each
clump its own pebbles in a fixed order, the bodies moved once every pebble's load is complete;
so no result depends on the number of threads. (The ball engine's parallel tasks would compile
for minutes more in a kernel of their own; a clumped specimen of a few thousand grains steps at
one core's speed.)
"""

from __future__ import annotations

import math
from dataclasses import replace
from enum import IntEnum
from typing import NamedTuple

import numba
import numpy as np
from numba import njit

from rockcal.dem.clumps import members
from rockcal.dem3d import forces, neighbours, simulate
from rockcal.dem3d import walls as planes
from rockcal.dem3d.clumps import union_properties
from rockcal.dem3d.state import LOAD_COMPONENTS, Load, Sphere


class Body(IntEnum):
    """Columns of a clump's row in `Clumps3D.bodies`."""

    X = 0  # centroid, m
    Y = 1
    Z = 2
    VX = 3  # m/s
    VY = 4
    VZ = 5
    LX = 6  # angular momentum, world frame, kg m²/s
    LY = 7
    LZ = 8
    WX = 9  # angular velocity, world frame, rad/s
    WY = 10
    WZ = 11
    QW = 12  # orientation: the unit quaternion from the clump's frame to the world's
    QX = 13
    QY = 14
    QZ = 15
    INV_MASS = 16  # 0: a driven clump, whose velocity and angular velocity are prescribed


BODY_WIDTH = 24


class Clumps3D(NamedTuple):
    """The rigid clumps of a 3D state (`State.clumps`): which pebbles form each, the pebbles'
    offsets from the centroid in the clump's frame, the balls (spheres in no clump), the
    bodies' state, each clump's inertia tensor and its inverse in its own frame (kg m², 1/(kg
    m²)), and a force and moment applied to each clump every step (N, N m; zero unless set)."""

    clump_of: np.ndarray  # per sphere: its clump, -1 for a ball
    first: np.ndarray  # clump c's pebbles: pebbles[first[c]:first[c + 1]]
    pebbles: np.ndarray
    offsets: np.ndarray  # (len(pebbles), 3), in the clump's frame, m
    balls: np.ndarray
    bodies: np.ndarray  # (n_clumps, BODY_WIDTH)
    inertia: np.ndarray  # (n_clumps, 3, 3)
    inv_inertia: np.ndarray  # (n_clumps, 3, 3)
    applied: np.ndarray  # (n_clumps, 6): force, then moment

    @property
    def n_clumps(self) -> int:
        return self.bodies.shape[0]

    @property
    def pos(self) -> np.ndarray:
        return self.bodies[:, Body.X:Body.Z + 1]

    @property
    def vel(self) -> np.ndarray:
        return self.bodies[:, Body.VX:Body.VZ + 1]

    @property
    def momentum(self) -> np.ndarray:
        """Each clump's angular momentum about its centroid, world frame."""
        return self.bodies[:, Body.LX:Body.LZ + 1]

    @property
    def spin(self) -> np.ndarray:
        return self.bodies[:, Body.WX:Body.WZ + 1]

    @property
    def inv_mass(self) -> np.ndarray:
        return self.bodies[:, Body.INV_MASS]

    def rotation(self, c: int) -> np.ndarray:
        """Clump c's rotation matrix, from its frame to the world's."""
        return _rotation(self.bodies, c)

    def set_spin(self, c: int, spin) -> None:
        """Give clump c the angular velocity `spin` (world frame, rad/s), its angular momentum
        with it; then `carry_pebbles`."""
        r = self.rotation(c)
        self.spin[c] = spin
        self.momentum[c] = r @ self.inertia[c] @ r.T @ np.asarray(spin, float)

    def carry_pebbles(self, spheres) -> None:
        """Place every clump's pebbles from its body, after its motion was set."""
        _place_clumps(0, self.n_clumps, self.first, self.pebbles, self.offsets, self.bodies,
                      spheres.bodies, np.zeros((spheres.bodies.shape[0], 3)))

    def kinetic_energy(self) -> float:
        """The clumps' kinetic energy ½ m v² + ½ ω · L, J (free clumps)."""
        free = self.inv_mass > 0
        v, w, L = self.vel[free], self.spin[free], self.momentum[free]
        return float(0.5 * ((v * v).sum(axis=1) / self.inv_mass[free]).sum() + 0.5 * (w * L).sum())

    def advance(self, state, n_steps: int) -> None:
        """`simulate.advance`'s steps for a state of clumps (`_advance_clumps`)."""
        s, b, w = state.spheres, state.bonds, state.walls
        done = 0
        while done < n_steps:
            pairs = state.neighbours
            done_now, rebuild = _advance_clumps(
                n_steps - done, s.bodies, s.loads, pairs.pi, pairs.pj, pairs.shear, b.table, b.state,
                b.break_xyz, pairs.n_bonds, pairs.pos_at_build, pairs.rebuild_distance_sq, state.laws,
                state.damping, state.dt, w.table, w.force, self.first, self.pebbles, self.offsets,
                self.bodies, self.inv_inertia, self.applied, self.balls)
            done += done_now
            state.step += done_now
            if rebuild:
                state.neighbours = neighbours.update(pairs, s.pos, s.radius)

    def stable_time_step(self, state) -> float:
        """`simulate.stable_time_step` over bodies: safety x the smallest sqrt(m / k_trans)
        and sqrt(I_min / k_rot) of any free clump or ball (`_body_stiffness_sums`; I_min a
        clump's smallest principal moment)."""
        k_trans, k_rot = self._body_stiffness_sums(state)
        mass, smallest = self._body_inertias(state.spheres)
        free = np.isfinite(mass) & (k_trans > 0)
        if not free.any():
            return np.inf
        dt_t = np.sqrt(mass[free] / k_trans[free])
        dt_r = np.sqrt(smallest[free] / np.maximum(k_rot[free], 1e-300))
        return simulate.TIME_STEP_SAFETY * float(min(dt_t.min(), dt_r.min()))

    def scale_density(self, state) -> float:
        """`simulate.scale_density` over bodies: each free clump's and ball's mass, and its
        inertia (a clump's tensor scaled whole, its smallest principal moment set), so that its
        own critical time step is the specimen's. Returns the scaled over the true mass."""
        k_trans, k_rot = self._body_stiffness_sums(state)
        critical_s = state.dt / simulate.TIME_STEP_SAFETY
        mass, smallest = self._body_inertias(state.spheres)
        free = np.isfinite(mass) & (k_trans > 0)
        true_mass = mass[free].sum()
        new_mass = k_trans * critical_s**2
        factor = np.maximum(k_rot, 1e-300) * critical_s**2 / smallest
        n = self.n_clumps
        clumps, balls = free[:n], free[n:]
        self.bodies[clumps, Body.INV_MASS] = 1.0 / new_mass[:n][clumps]
        self.inertia[clumps] *= factor[:n][clumps, None, None]
        self.inv_inertia[clumps] /= factor[:n][clumps, None, None]
        for c in np.flatnonzero(clumps):  # L follows the inertia: the clump keeps its ω
            self.set_spin(c, self.spin[c].copy())
        s = state.spheres
        s.inv_mass[self.balls[balls]] = 1.0 / new_mass[n:][balls]
        s.inv_inertia[self.balls[balls]] = 1.0 / (factor[n:][balls] * smallest[n:][balls])
        self._label_pebbles(s)
        return float(new_mass[free].sum() / true_mass)

    def _body_inertias(self, spheres) -> tuple[np.ndarray, np.ndarray]:
        """The bodies' masses (inf: driven) and smallest principal moments: the clumps', then
        the balls'."""
        with np.errstate(divide="ignore"):
            mass = 1.0 / np.concatenate([self.inv_mass, spheres.inv_mass[self.balls]])
            ball_inertia = 1.0 / spheres.inv_inertia[self.balls]
        smallest = np.array([smallest_eigenvalue(t) for t in self.inertia])
        return mass, np.concatenate([smallest, ball_inertia])

    def _body_stiffness_sums(self, state) -> tuple[np.ndarray, np.ndarray]:
        """Each body's translational and rotational stiffness, summed over its pebbles
        (`simulate.stiffness_sums`). A pebble at distance d from its clump's centroid turns a
        pair's contact point (lever arm at most d + R) and its normal line (at most d) with the
        clump; its sphere's sums bound that: k_rot + k_trans ((d + R)² - R² + d²)."""
        k_trans, k_rot = simulate.stiffness_sums(state)
        arm = np.zeros(state.n_spheres)
        arm[self.pebbles] = np.sqrt((self.offsets**2).sum(axis=1))
        r = state.spheres.radius
        k_rot = k_rot + k_trans * ((arm + r) ** 2 - r**2 + arm**2)
        body = self.clump_of.copy()
        body[self.balls] = self.n_clumps + np.arange(len(self.balls))
        bodies = self.n_clumps + len(self.balls)
        return (np.bincount(body, k_trans, minlength=bodies), np.bincount(body, k_rot, minlength=bodies))

    def _label_pebbles(self, spheres) -> None:
        """Give each pebble's row its clump's inverse mass (0 tells a driven pebble)."""
        spheres.inv_mass[self.pebbles] = self.inv_mass[self.clump_of[self.pebbles]]
        spheres.inv_inertia[self.pebbles] = 0.0  # a pebble turns with its clump alone


def smallest_eigenvalue(t: np.ndarray) -> float:
    """The smallest eigenvalue of the symmetric 3 x 3 matrix `t`, in closed form (the
    trigonometric solution of its characteristic cubic: the same numbers on every processor)."""
    q = (t[0, 0] + t[1, 1] + t[2, 2]) / 3.0
    off = t[0, 1] ** 2 + t[0, 2] ** 2 + t[1, 2] ** 2
    p = math.sqrt(((t[0, 0] - q) ** 2 + (t[1, 1] - q) ** 2 + (t[2, 2] - q) ** 2 + 2.0 * off) / 6.0)
    if p == 0.0:
        return q
    b = (t - q * np.eye(3)) / p
    det = (b[0, 0] * (b[1, 1] * b[2, 2] - b[1, 2] * b[2, 1]) - b[0, 1] * (b[1, 0] * b[2, 2] - b[1, 2] * b[2, 0])
           + b[0, 2] * (b[1, 0] * b[2, 1] - b[1, 1] * b[2, 0]))
    phi = math.acos(min(1.0, max(-1.0, 0.5 * det))) / 3.0
    return q + 2.0 * p * math.cos(phi + 2.0 * math.pi / 3.0)


def inverse_3x3(t: np.ndarray) -> np.ndarray:
    """The inverse of a 3 x 3 matrix by its adjugate, written out (LAPACK's rounds by processor)."""
    a = np.array([[t[1, 1] * t[2, 2] - t[1, 2] * t[2, 1], t[0, 2] * t[2, 1] - t[0, 1] * t[2, 2],
                   t[0, 1] * t[1, 2] - t[0, 2] * t[1, 1]],
                  [t[1, 2] * t[2, 0] - t[1, 0] * t[2, 2], t[0, 0] * t[2, 2] - t[0, 2] * t[2, 0],
                   t[0, 2] * t[1, 0] - t[0, 0] * t[1, 2]],
                  [t[1, 0] * t[2, 1] - t[1, 1] * t[2, 0], t[0, 1] * t[2, 0] - t[0, 0] * t[2, 1],
                   t[0, 0] * t[1, 1] - t[0, 1] * t[1, 0]]])
    return a / (t[0, 0] * a[0, 0] + t[0, 1] * a[1, 0] + t[0, 2] * a[2, 0])


def clump(state, clump_of, density: float) -> Clumps3D:
    """Make the spheres of `state` pebbles of rigid clumps (`clump_of`: per sphere its clump
    0..n_clumps-1, or -1: a ball) of `density` (kg/m³), at rest where the pebbles lie: each
    clump of its pebbles' union's mass and inertia tensor (`clumps.union_properties`), driven if
    one of its pebbles is (inverse mass 0). Sets `state.clumps`, drops the pairs within a clump
    from the neighbour list and sets the time step; ValueError if a bond joins two pebbles of
    one clump. Returns the clumps."""
    s, nlist = state.spheres, state.neighbours
    clump_of = np.asarray(clump_of, np.int64)
    if clump_of.shape != (state.n_spheres,):
        raise ValueError("clump_of: one entry per sphere")
    first, pebbles = members(clump_of)
    bi, bj = nlist.pi[:nlist.n_bonds], nlist.pj[:nlist.n_bonds]
    if ((clump_of[bi] == clump_of[bj]) & (clump_of[bi] >= 0)).any():
        raise ValueError("a bond joins two pebbles of one clump")
    n = len(first) - 1
    bodies = np.zeros((n, BODY_WIDTH))
    inertia = np.empty((n, 3, 3))
    for c in range(n):
        own = pebbles[first[c]:first[c + 1]]
        volume, bodies[c, Body.X:Body.Z + 1], shape = union_properties(s.pos[own], s.radius[own])
        bodies[c, Body.INV_MASS] = 1.0 / (density * volume)
        inertia[c] = density * shape
    bodies[:, Body.QW] = 1.0
    driven = np.zeros(n, bool)
    np.logical_or.at(driven, clump_of[pebbles], s.inv_mass[pebbles] == 0.0)
    bodies[driven, Body.INV_MASS] = 0.0
    clumps = Clumps3D(clump_of=clump_of, first=first, pebbles=pebbles,
                      offsets=s.pos[pebbles] - bodies[clump_of[pebbles], Body.X:Body.Z + 1],
                      balls=np.flatnonzero(clump_of < 0), bodies=bodies, inertia=inertia,
                      inv_inertia=np.array([inverse_3x3(t) for t in inertia]).reshape(n, 3, 3),
                      applied=np.zeros((n, 6)))
    s.vel[pebbles] = 0.0
    s.spin[pebbles] = 0.0
    clumps._label_pebbles(s)
    state.neighbours = neighbours.update(replace(nlist, clump_of=clump_of), s.pos, s.radius)
    state.clumps = clumps
    state.dt = simulate.stable_time_step(state)
    return clumps


@njit(cache=True, error_model="numpy", inline="always")
def _rotation(bodies, c):
    """The rotation matrix of clump c's quaternion."""
    w, x, y, z = bodies[c, Body.QW], bodies[c, Body.QX], bodies[c, Body.QY], bodies[c, Body.QZ]
    r = np.empty((3, 3))
    r[0, 0] = 1.0 - 2.0 * (y * y + z * z)
    r[0, 1] = 2.0 * (x * y - w * z)
    r[0, 2] = 2.0 * (x * z + w * y)
    r[1, 0] = 2.0 * (x * y + w * z)
    r[1, 1] = 1.0 - 2.0 * (x * x + z * z)
    r[1, 2] = 2.0 * (y * z - w * x)
    r[2, 0] = 2.0 * (x * z - w * y)
    r[2, 1] = 2.0 * (y * z + w * x)
    r[2, 2] = 1.0 - 2.0 * (x * x + y * y)
    return r


@njit(cache=True, error_model="numpy", inline="always")
def _spin_of(r, inv_inertia, momentum):
    """ω = R I⁻¹ Rᵀ L."""
    body = np.zeros(3)
    for a in range(3):
        for b in range(3):
            body[a] += r[b, a] * momentum[b]
    turned = np.zeros(3)
    for a in range(3):
        for b in range(3):
            turned[a] += inv_inertia[a, b] * body[b]
    spin = np.zeros(3)
    for a in range(3):
        for b in range(3):
            spin[a] += r[a, b] * turned[b]
    return spin


@njit(cache=True, error_model="numpy", inline="always")
def _turn(bodies, c, q, spin, dt):
    """Clump c's quaternion set to `q` turned by the angular velocity `spin` for dt (the
    rotation by |ω| dt about ω, composed on the world side), normalised."""
    angle = math.sqrt(spin[0] * spin[0] + spin[1] * spin[1] + spin[2] * spin[2]) * dt
    w = math.cos(0.5 * angle)
    k = 0.5 * dt if angle == 0.0 else math.sin(0.5 * angle) * dt / angle
    x, y, z = k * spin[0], k * spin[1], k * spin[2]
    qw = w * q[0] - x * q[1] - y * q[2] - z * q[3]
    qx = w * q[1] + x * q[0] + y * q[3] - z * q[2]
    qy = w * q[2] - x * q[3] + y * q[0] + z * q[1]
    qz = w * q[3] + x * q[2] - y * q[1] + z * q[0]
    norm = math.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    bodies[c, Body.QW] = qw / norm
    bodies[c, Body.QX] = qx / norm
    bodies[c, Body.QY] = qy / norm
    bodies[c, Body.QZ] = qz / norm


@njit(cache=True, error_model="numpy")
def _place_clumps(first_clump, last_clump, first, pebbles, offsets, bodies, spheres, pos_at_build):
    """Carry the pebbles of clumps first_clump..last_clump-1 with their bodies
    (`_place_clump`). Returns their largest squared displacement from `pos_at_build`."""
    moved = 0.0
    for c in range(numba.uint64(first_clump), numba.uint64(last_clump)):
        moved = max(moved, _place_clump(c, first, pebbles, offsets, bodies, spheres, pos_at_build))
    return moved


@njit(cache=True, error_model="numpy", inline="always")
def _place_clump(c, first, pebbles, offsets, bodies, spheres, pos_at_build):
    """Carry clump c's pebbles with its body: centre at centroid + R offset, velocity v + ω × r,
    spin ω. Returns their largest squared displacement from `pos_at_build`."""
    moved = 0.0
    r = _rotation(bodies, c)
    w = bodies[c, Body.WX:Body.WZ + 1]
    for q in range(numba.uint64(first[c]), numba.uint64(first[c + 1])):
        k = numba.uint64(pebbles[q])
        arm = np.empty(3)
        for a in range(3):
            arm[a] = r[a, 0] * offsets[q, 0] + r[a, 1] * offsets[q, 1] + r[a, 2] * offsets[q, 2]
        dist_sq = 0.0
        for a in range(3):
            b, e = (a + 1) % 3, (a + 2) % 3
            spheres[k, Sphere.X + a] = bodies[c, Body.X + a] + arm[a]
            spheres[k, Sphere.VX + a] = bodies[c, Body.VX + a] + w[b] * arm[e] - w[e] * arm[b]
            spheres[k, Sphere.WX + a] = w[a]
            step = spheres[k, Sphere.X + a] - pos_at_build[k, a]
            dist_sq += step * step
        moved = max(moved, dist_sq)
    return moved


@njit(cache=True, error_model="numpy")
def _move_clumps(first_clump, last_clump, first, pebbles, offsets, bodies, inv_inertia, applied,
                 spheres, loads, damping, dt, pos_at_build):
    """Sum each clump's pebble forces and moments about its centroid (pebbles in order, then
    the applied load), PFC local damping, central differences on the body (module docstring),
    then carry its pebbles. Returns their largest squared displacement since the neighbour
    list was built."""
    moved = 0.0
    for c in range(numba.uint64(first_clump), numba.uint64(last_clump)):
        force = np.zeros(3)
        moment = np.zeros(3)
        for q in range(numba.uint64(first[c]), numba.uint64(first[c + 1])):
            k = numba.uint64(pebbles[q])
            for a in range(3):
                b, e = (a + 1) % 3, (a + 2) % 3
                rb = spheres[k, Sphere.X + b] - bodies[c, Body.X + b]
                re = spheres[k, Sphere.X + e] - bodies[c, Body.X + e]
                force[a] += loads[k, Load.FX + a]
                moment[a] += loads[k, Load.MX + a] + (rb * loads[k, Load.FX + e] - re * loads[k, Load.FX + b])
        for a in range(3):
            force[a] += applied[c, a]
            moment[a] += applied[c, 3 + a]
        inv_mass = bodies[c, Body.INV_MASS]
        q0 = bodies[c, Body.QW:Body.QZ + 1].copy()
        if inv_mass > 0.0:
            for a in range(3):
                f = force[a] - damping * abs(force[a]) * np.sign(bodies[c, Body.VX + a])
                bodies[c, Body.VX + a] += f * inv_mass * dt
                m = moment[a] - damping * abs(moment[a]) * np.sign(bodies[c, Body.WX + a])
                bodies[c, Body.LX + a] += m * dt
            momentum = bodies[c, Body.LX:Body.LZ + 1]
            # the midpoint rule: ω at the orientation half a step on turns q the whole step
            _turn(bodies, c, q0, _spin_of(_rotation(bodies, c), inv_inertia[c], momentum), 0.5 * dt)
            _turn(bodies, c, q0, _spin_of(_rotation(bodies, c), inv_inertia[c], momentum), dt)
            spin = _spin_of(_rotation(bodies, c), inv_inertia[c], momentum)
            for a in range(3):
                bodies[c, Body.WX + a] = spin[a]
        else:  # driven: turned at its prescribed angular velocity
            _turn(bodies, c, q0, bodies[c, Body.WX:Body.WZ + 1].copy(), dt)
        for a in range(3):
            bodies[c, Body.X + a] += bodies[c, Body.VX + a] * dt
        moved = max(moved, _place_clump(c, first, pebbles, offsets, bodies, spheres, pos_at_build))
    return moved


@njit(cache=True, error_model="numpy")
def _move_balls(first_ball, last_ball, balls, spheres, loads, damping, dt, pos_at_build):
    """`simulate._move` on balls first_ball..last_ball-1 of the list `balls`."""
    moved = 0.0
    for b in range(numba.uint64(first_ball), numba.uint64(last_ball)):
        k = balls[b]
        moved = max(moved, simulate._move(k, k + 1, spheres, loads, damping, dt, pos_at_build))
    return moved


@njit(cache=True, error_model="numpy")
def _advance_clumps(n_steps, bodies, loads, pi, pj, shear, table, bond_state, break_xyz,
                    n_bonds, pos_at_build, half_skin_sq, laws, damping, dt, walls, wall_force,
                    first, pebbles, offsets, clump_bodies, inv_inertia, applied, balls):
    """`simulate._advance`'s steps for a state of clumps, on one thread: each step the pair
    forces in the list's order (the bonds, then the contacts), the walls' pushes, the clumps
    (`_move_clumps`) and balls (`_move_balls`) moved, the walls moved. Stops early when the
    list must be rebuilt; returns the steps done and whether it must."""
    n = bodies.shape[0]
    for s in range(n_steps):
        loads[:, :LOAD_COMPONENTS] = 0.0
        forces.add_bond_forces(0, n_bonds, bodies, loads, pi, pj, table, bond_state, break_xyz, laws, dt)
        forces.add_contact_forces(n_bonds, pi.shape[0], bodies, loads, pi, pj, shear, laws, dt)
        wall_force[:] = 0.0
        planes.add_wall_forces(0, n, bodies, loads, walls, wall_force)
        moved = max(_move_clumps(0, clump_bodies.shape[0], first, pebbles, offsets, clump_bodies,
                                 inv_inertia, applied, bodies, loads, damping, dt, pos_at_build),
                    _move_balls(0, balls.shape[0], balls, bodies, loads, damping, dt, pos_at_build))
        planes.move_walls(walls, dt)
        if moved > half_skin_sq:
            return s + 1, True
    return n_steps, False
