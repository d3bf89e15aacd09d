"""Stepping in time: the state of a bonded-particle model and the explicit integrator.

The state is a structure of plain arrays. `advance` runs many steps inside one compiled
loop (force laws, walls, PFC local damping, central-difference motion) and hands back to
Python only to rebuild the neighbour list, so the per-step cost is the arithmetic alone.
Each step sums the pair forces block by block in parallel, then the pairs across block
borders, then moves the particles block by block (`neighbours.block_layout`): the order of
every sum is fixed by the specimen, so results do not depend on the number of threads.
Everything is SI; disks have unit thickness (PFC2D convention).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numba
from numba import njit, prange
from scipy import special

from rockcal.dem import laws, neighbours
from rockcal.params import GPa, MPa, MicroParams

THICKNESS_M = 1.0
TIME_STEP_SAFETY = 0.8
LEFT, RIGHT, BOTTOM, TOP = range(4)


@dataclass
class State:
    """Particles, pairs (bonds first, then near unbonded pairs; each part grouped by block),
    walls and their forces."""

    pos: np.ndarray
    vel: np.ndarray
    spin: np.ndarray
    radius: np.ndarray
    inv_mass: np.ndarray  # 0 for driven particles, whose velocity is prescribed
    inv_inertia: np.ndarray
    pi: np.ndarray
    pj: np.ndarray
    n_bonds: int
    contact_shear: np.ndarray
    bond_state: np.ndarray
    bond_fn: np.ndarray
    bond_fs: np.ndarray
    bond_m: np.ndarray
    bond_break_xy: np.ndarray
    bond_ref_overlap: np.ndarray  # overlap at installation (PFC's reference gap, negated)
    bond_ten: np.ndarray  # tensile strength of each bond, Pa
    bond_coh: np.ndarray  # cohesion of each bond, Pa
    walls: np.ndarray  # x_left, x_right, y_bottom, y_top
    wall_active: np.ndarray
    wall_vel: np.ndarray
    wall_force: np.ndarray  # (n, 4): force of each particle on each wall
    force: np.ndarray
    moment: np.ndarray
    laws: laws.Laws
    damping: float
    k_wall: float
    skin: float
    dt: float
    block_starts: np.ndarray  # first particle of each block, and n
    bond_offsets: np.ndarray  # bonds of block b: bond_offsets[b]:[b + 1]; border bonds last
    contact_offsets: np.ndarray | None = None  # the same for the unbonded pairs
    step: int = 0
    pos_at_build: np.ndarray | None = None

    @property
    def n_particles(self) -> int:
        return self.pos.shape[0]

    def total_wall_force(self) -> np.ndarray:
        """Force on each wall (left, right, bottom, top), compression positive, N per m."""
        return self.wall_force.sum(axis=0)

    def n_broken(self, mode: int) -> int:
        return int(np.count_nonzero(self.bond_state == mode))

    def bonds(self) -> laws.Bonds:
        return laws.Bonds(self.bond_state, self.bond_fn, self.bond_fs, self.bond_m,
                          self.bond_break_xy, self.bond_ref_overlap, self.bond_ten, self.bond_coh)


def law_constants(params: MicroParams) -> laws.Laws:
    return laws.Laws(params.E_c * GPa, 1.0 / params.kn_ks, params.mu, params.Ebar_c * GPa,
                     1.0 / params.knbar_ksbar, params.lambda_,
                     float(np.tan(np.radians(params.phi_b))), params.mcf)


def bond_strengths(params: MicroParams, draws: np.ndarray | None, n_bonds: int):
    """Tensile strength and cohesion (Pa) of each bond, normally distributed (mean, sd) and
    truncated at zero as PFC's FISHTank does (it redraws negative values): the bond's uniform
    draws u (columns of `draws`; None: the means) map through the truncated normal's inverse
    distribution function, so a bond keeps its rank in strength whatever the parameters."""
    u = None if draws is None else np.asarray(draws, float).reshape(n_bonds, 2)
    strengths = []
    means = (params.sigma_c, params.tau_c)
    for column, (mean, sd) in enumerate(zip(means, params.strength_sds)):
        if sd == 0 or u is None:
            strengths.append(np.full(n_bonds, mean * MPa))
            continue
        below = special.ndtr(-mean / sd)  # probability mass cut off below zero
        z = special.ndtri(below + u[:, column] * (1.0 - below))
        strengths.append(np.maximum(0.0, mean + sd * z) * MPa)
    return tuple(strengths)


def new_state(pos, radius, bonds, params: MicroParams, *, walls=(0.0, 0.0, 0.0, 0.0),
              wall_active=(False,) * 4, driven=None, skin=None, laws_si=None,
              bond_draws=None) -> State:
    """A state at rest with the given bonds (pairs i < j) installed at zero force.

    bond_draws: two uniform draws per bond (in the order of `bonds`) that set its strengths
    (`bond_strengths`). A bond installed at an overlapping pair takes the overlap
    as reference, so installing it locks in no force.
    """
    n = pos.shape[0]
    radius = np.array(radius, float)
    mass = params.density * np.pi * radius**2 * THICKNESS_M
    inv_mass = 1.0 / mass
    inv_inertia = 1.0 / (0.5 * mass * radius**2)
    if driven is not None:
        inv_mass[driven] = 0.0
        inv_inertia[driven] = 0.0
    bonds = np.asarray(bonds, np.int64).reshape(-1, 2)
    order = np.argsort(bonds[:, 0] * n + bonds[:, 1])
    starts = neighbours.block_starts(n)
    by_block, bond_offsets = neighbours.block_layout(bonds[order, 0], bonds[order, 1], starts)
    order = order[by_block]
    bonds = bonds[order]
    ten, coh = bond_strengths(params, None if bond_draws is None else
                              np.asarray(bond_draws, float).reshape(-1, 2)[order], len(bonds))
    pos = np.ascontiguousarray(pos, float)
    centre_gap = np.hypot(*(pos[bonds[:, 1]] - pos[bonds[:, 0]]).T)
    ref_overlap = np.maximum(0.0, radius[bonds[:, 0]] + radius[bonds[:, 1]] - centre_gap)
    laws_si = laws_si or law_constants(params)
    E_c, Ebar_c = laws_si.E_c, laws_si.Ebar_c
    state = State(
        pos=pos.copy(), vel=np.zeros((n, 2)), spin=np.zeros(n),
        radius=radius, inv_mass=inv_mass, inv_inertia=inv_inertia,
        pi=bonds[:, 0].copy(), pj=bonds[:, 1].copy(), n_bonds=len(bonds),
        contact_shear=np.zeros(len(bonds)), bond_state=np.zeros(len(bonds), np.int64),
        bond_fn=np.zeros(len(bonds)), bond_fs=np.zeros(len(bonds)), bond_m=np.zeros(len(bonds)),
        bond_break_xy=np.full((len(bonds), 2), np.nan), bond_ref_overlap=ref_overlap,
        bond_ten=ten, bond_coh=coh,
        walls=np.array(walls, float), wall_active=np.array(wall_active, np.bool_),
        wall_vel=np.zeros(4), wall_force=np.zeros((n, 4)), force=np.zeros((n, 2)),
        moment=np.zeros(n), laws=laws_si, damping=params.damping,
        k_wall=2.0 * THICKNESS_M * (E_c if E_c > 0 else Ebar_c),
        skin=skin if skin is not None else 0.5 * radius.min(), dt=0.0,
        block_starts=starts, bond_offsets=bond_offsets,
    )
    rebuild_neighbours(state)
    state.dt = stable_time_step(state)
    return state


def rebuild_neighbours(state: State) -> None:
    """New list of unbonded near pairs, keeping the shear force of pairs already listed."""
    n, nb = state.n_particles, state.n_bonds
    bond_keys = state.pi[:nb] * n + state.pj[:nb]
    old_keys = state.pi[nb:] * n + state.pj[nb:]
    order = np.argsort(old_keys)
    ci, cj, shear = neighbours.contact_pairs(state.pos, state.radius, state.skin,
                                             np.sort(bond_keys), old_keys[order],
                                             state.contact_shear[nb:][order])
    by_block, offsets = neighbours.block_layout(ci, cj, state.block_starts)
    state.pi = np.concatenate([state.pi[:nb], ci[by_block]])
    state.pj = np.concatenate([state.pj[:nb], cj[by_block]])
    state.contact_shear = np.concatenate([state.contact_shear[:nb], shear[by_block]])
    state.contact_offsets = nb + offsets
    state.pos_at_build = state.pos.copy()


def stable_time_step(state: State) -> float:
    """Safety x the smallest sqrt(m / k_translational) and sqrt(I / k_rotational) of any particle.

    Stiffness sums count every listed pair (as if touching) and the walls, as PFC does.
    """
    E_c, ks_per_kn, _, Ebar_c, ksbar_per_knbar, lam = state.laws[:6]
    ri, rj = state.radius[state.pi], state.radius[state.pj]
    length = ri + rj
    rmin = np.minimum(ri, rj)
    kn = 2 * rmin * THICKNESS_M * E_c / length
    ks = kn * ks_per_kn
    bonded = np.zeros(len(ri), bool)
    bonded[:state.n_bonds] = True
    rb = lam * rmin
    kbn = np.where(bonded, Ebar_c / length * 2 * rb * THICKNESS_M, 0.0)
    kbs = kbn * ksbar_per_knbar
    kbr = np.where(bonded, Ebar_c / length * 2 / 3 * rb**3 * THICKNESS_M, 0.0)
    n = state.n_particles
    k_trans = np.full(n, state.k_wall)
    k_rot = np.zeros(n)
    for idx, r in ((state.pi, ri), (state.pj, rj)):
        np.add.at(k_trans, idx, np.maximum(kn, ks) + np.maximum(kbn, kbs))
        np.add.at(k_rot, idx, (ks + kbs) * r**2 + kbr)
    free = state.inv_mass > 0
    with np.errstate(divide="ignore"):
        dt_t = np.sqrt(1.0 / (state.inv_mass[free] * k_trans[free]))
        dt_r = np.sqrt(1.0 / (state.inv_inertia[free] * np.maximum(k_rot[free], 1e-300)))
    return TIME_STEP_SAFETY * float(min(dt_t.min(), dt_r.min()))


@njit(cache=True, error_model="numpy")
def _move(first, last, pos, vel, spin, force, moment, inv_mass, inv_inertia, damping, dt,
          pos_at_build):
    """PFC local damping (force reduced by damping*|F| against the velocity), then leapfrog, of
    particles first..last-1. Returns their largest squared displacement since the neighbour
    list was built."""
    moved = 0.0
    for k in range(first, last):
        if inv_mass[k] > 0.0:
            for a in range(2):
                f = force[k, a]
                f -= damping * abs(f) * np.sign(vel[k, a])
                vel[k, a] += f * inv_mass[k] * dt
            m = moment[k] - damping * abs(moment[k]) * np.sign(spin[k])
            spin[k] += m * inv_inertia[k] * dt
        pos[k, 0] += vel[k, 0] * dt
        pos[k, 1] += vel[k, 1] * dt
        dx = pos[k, 0] - pos_at_build[k, 0]
        dy = pos[k, 1] - pos_at_build[k, 1]
        moved = max(moved, dx * dx + dy * dy)
    return moved


# numba caches this kernel with the law kernels compiled into it, keyed by this file alone:
# after editing laws.py in a checkout, clear the caches (__pycache__/*.nbi, *.nbc).
@njit(parallel=True, cache=True, error_model="numpy")
def _advance(n_steps, pos, vel, spin, radius, inv_mass, inv_inertia, pi, pj, contact_shear,
             bonds, n_bonds, starts, bond_offsets, contact_offsets, force, moment, walls,
             wall_active, wall_vel, wall_force, k_wall, pos_at_build, half_skin_sq, law,
             damping, dt):
    """Run up to n_steps; stop early when the list must be rebuilt. Returns the steps done
    and whether the list must be rebuilt."""
    blocks = starts.shape[0] - 1
    moved = np.zeros(blocks)
    for s in range(n_steps):  # no array expressions: each would be a parallel region
        for b in prange(blocks):  # explicit loops: an array expression here would nest parfors
            for k in range(starts[b], starts[b + 1]):
                force[k, 0] = 0.0
                force[k, 1] = 0.0
                moment[k] = 0.0
            laws.add_bond_forces(bond_offsets[b], bond_offsets[b + 1], pos, vel, spin, radius,
                                 pi, pj, contact_shear, bonds, law, dt, force, moment)
            laws.add_contact_forces(contact_offsets[b], contact_offsets[b + 1], pos, vel, spin,
                                    radius, pi, pj, contact_shear, law, dt, force, moment)
        # then the pairs across block borders
        laws.add_bond_forces(bond_offsets[blocks], bond_offsets[blocks + 1], pos, vel, spin,
                             radius, pi, pj, contact_shear, bonds, law, dt, force, moment)
        laws.add_contact_forces(contact_offsets[blocks], contact_offsets[blocks + 1], pos, vel,
                                spin, radius, pi, pj, contact_shear, law, dt, force, moment)
        for b in prange(blocks):
            laws.add_wall_forces(starts[b], starts[b + 1], pos, radius, walls, wall_active,
                                 k_wall, force, wall_force)
            moved[b] = _move(starts[b], starts[b + 1], pos, vel, spin, force, moment, inv_mass,
                             inv_inertia, damping, dt, pos_at_build)
        for w in range(4):
            walls[w] += wall_vel[w] * dt
        for b in range(blocks):
            if moved[b] > half_skin_sq:
                return s + 1, True
    return n_steps, False


def advance(state: State, n_steps: int) -> None:
    """Run n_steps time steps, rebuilding the neighbour list whenever particles moved enough.

    Runs on at most one thread per block: a small specimen is one block, and a parallel loop
    over it would cost more in synchronisation than it saves.
    """
    cap = numba.get_num_threads()
    numba.set_num_threads(max(1, min(cap, len(state.block_starts) - 1)))
    try:
        _advance_all(state, n_steps)
    finally:
        numba.set_num_threads(cap)


def _advance_all(state: State, n_steps: int) -> None:
    done = 0
    while done < n_steps:
        done_now, rebuild = _advance(
            n_steps - done, state.pos, state.vel, state.spin, state.radius, state.inv_mass,
            state.inv_inertia, state.pi, state.pj, state.contact_shear, state.bonds(),
            state.n_bonds, state.block_starts, state.bond_offsets, state.contact_offsets,
            state.force, state.moment, state.walls, state.wall_active, state.wall_vel,
            state.wall_force, state.k_wall, state.pos_at_build, (0.5 * state.skin) ** 2,
            state.laws, state.damping, state.dt)
        done += done_now
        state.step += done_now
        if rebuild:
            rebuild_neighbours(state)
