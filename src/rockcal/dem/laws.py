"""Interaction laws of PFC2D's linear contact and linear parallel bond (Potyondy & Cundall 2004).

Sign conventions, per pair (i, j) with unit normal n from i to j and tangent t = (-n_y, n_x):
- linear contact: Fn = kn * overlap (compression, no tension), kn = A * E_c / L with
  A = 2 * min(R_i, R_j) * t, L = R_i + R_j; shear force updated incrementally with
  ks = kn / (kn/ks) and capped by Coulomb's mu * Fn;
- parallel bond: radius Rb = lambda * min(R_i, R_j), area A = 2 Rb t, inertia I = 2/3 Rb^3 t,
  normal stiffness per area kbn = Ebar_c / L, kbs = kbn / (kbn/kbs); normal force
  (tension positive), shear force and moment updated incrementally from the relative motion;
  it breaks in tension when Fn/A + mcf |M| Rb / I > sigma_c, else in shear when
  |Fs| / A > c - (Fn/A) tan(phi) (PFC 5+: tensile strength sigma_c and cohesion c per bond,
  friction angle phi, moment contribution factor mcf; phi = 0, mcf = 1 is Potyondy & Cundall
  2004's constant shear strength c = tau_c);
- reference gap: a bond installed at an overlapping pair takes that overlap as the contact's
  reference, so the linear contact carries only the overlap added since installation;
- contact point: midway through the gap (or overlap) between the two surfaces, as in PFC, so
  the lever arms R_i + g/2 and R_j + g/2 add up to the centre distance: a pair bonded across a
  gap g that turns as a rigid body loads nothing, and the moments conserve angular momentum.
The force a pair exerts on i is added to i's force and taken from j's; each gets its moment.
"""

from typing import NamedTuple

import numpy as np
from numba import njit

INTACT, BROKEN_TENSION, BROKEN_SHEAR = 0, 1, 2


class Laws(NamedTuple):
    """The law constants, SI: contact modulus (Pa), ks/kn, friction, bond modulus (Pa),
    k̄s/k̄n, bond radius multiplier λ̄, tan of the bond friction angle, moment factor β̄."""

    E_c: float
    ks_per_kn: float
    mu: float
    Ebar_c: float
    ksbar_per_knbar: float
    lam: float
    tan_phi: float
    mcf: float


class Bonds(NamedTuple):
    """Per-bond arrays, in the order of the first pairs of the pair list."""

    state: np.ndarray  # INTACT, BROKEN_TENSION or BROKEN_SHEAR
    fn: np.ndarray  # normal force, tension positive, N
    fs: np.ndarray  # shear force, N
    m: np.ndarray  # moment, N m
    break_xy: np.ndarray  # where it broke, m
    ref_overlap: np.ndarray  # overlap at installation (PFC's reference gap, negated), m
    ten: np.ndarray  # tensile strength, Pa
    coh: np.ndarray  # cohesion, Pa


@njit(cache=True, error_model="numpy")
def add_pair_forces(first, last, pos, vel, spin, radius, pi, pj, contact_shear, bonds, n_bonds,
                    laws, dt, force, moment):
    """Add the forces and moments of pairs first..last-1 to their particles (a pair's force on i
    is taken from j); bonds that exceed a strength break. Thickness t = 1 m."""
    for p in range(first, last):
        i = pi[p]
        j = pj[p]
        dx = pos[j, 0] - pos[i, 0]
        dy = pos[j, 1] - pos[i, 1]
        dist = np.sqrt(dx * dx + dy * dy)
        inv_dist = 1.0 / dist
        nx = dx * inv_dist  # unit normal from i to j; tangent t = (-ny, nx)
        ny = dy * inv_dist
        ri = radius[i]
        rj = radius[j]
        length = ri + rj
        surface_overlap = length - dist
        overlap = surface_overlap
        intact = False
        if p < n_bonds:
            overlap -= bonds.ref_overlap[p]
            intact = bonds.state[p] == INTACT
        if overlap <= 0.0 and not intact:
            contact_shear[p] = 0.0
            continue
        rmin = min(ri, rj)
        inv_length = 1.0 / length
        arm_i = ri - 0.5 * surface_overlap  # the contact point is mid-gap (or mid-overlap)
        arm_j = rj - 0.5 * surface_overlap
        w = spin[i] * arm_i + spin[j] * arm_j
        rvx = vel[j, 0] - vel[i, 0] + w * ny
        rvy = vel[j, 1] - vel[i, 1] - w * nx
        vn = rvx * nx + rvy * ny
        vs = rvy * nx - rvx * ny

        fn = 0.0  # along n on i: negative pushes i away from j
        fs = 0.0  # along t on i
        if overlap > 0.0 and laws.E_c > 0.0:
            kn = 2.0 * rmin * laws.E_c * inv_length
            shear = contact_shear[p] + kn * laws.ks_per_kn * vs * dt
            cap = laws.mu * kn * overlap
            if shear > cap:
                shear = cap
            elif shear < -cap:
                shear = -cap
            contact_shear[p] = shear
            fn = -kn * overlap
            fs = shear
        else:
            contact_shear[p] = 0.0
        mi = arm_i * fs
        mj = arm_j * fs

        if intact:
            rb = laws.lam * rmin
            area = 2.0 * rb
            k_area_dt = laws.Ebar_c * inv_length * area * dt  # k̄n Ā dt; Ī = Ā R̄² / 3
            bfn = bonds.fn[p] + k_area_dt * vn
            bfs = bonds.fs[p] + k_area_dt * laws.ksbar_per_knbar * vs
            bm = bonds.m[p] + k_area_dt * rb * rb / 3.0 * (spin[j] - spin[i])
            inv_area = 1.0 / area
            sigma = (bfn + laws.mcf * 3.0 * abs(bm) / rb) * inv_area  # |M| R̄ / Ī = 3 |M| / (R̄ Ā)
            tau = abs(bfs) * inv_area
            mode = INTACT
            if sigma > bonds.ten[p]:
                mode = BROKEN_TENSION
            elif tau > bonds.coh[p] - bfn * inv_area * laws.tan_phi:
                mode = BROKEN_SHEAR
            if mode != INTACT:
                bonds.state[p] = mode
                bonds.break_xy[p, 0] = pos[i, 0] + nx * arm_i
                bonds.break_xy[p, 1] = pos[i, 1] + ny * arm_i
                bonds.fn[p] = 0.0
                bonds.fs[p] = 0.0
                bonds.m[p] = 0.0
            else:
                bonds.fn[p] = bfn
                bonds.fs[p] = bfs
                bonds.m[p] = bm
                fn += bfn
                fs += bfs
                mi += arm_i * bfs + bm
                mj += arm_j * bfs - bm

        fx = fn * nx - fs * ny
        fy = fn * ny + fs * nx
        force[i, 0] += fx
        force[i, 1] += fy
        force[j, 0] -= fx
        force[j, 1] -= fy
        moment[i] += mi
        moment[j] += mj


@njit(cache=True, error_model="numpy")
def add_wall_forces(first, last, pos, radius, walls, wall_active, k_wall, force, wall_force):
    """Frictionless axis-aligned walls (left, right, bottom, top) on particles first..last-1:
    normal force k_wall * overlap. walls holds x_left, x_right, y_bottom, y_top; wall_force[k, w]
    receives the force particle k exerts on wall w along its outward normal (compression
    positive)."""
    for k in range(first, last):
        r = radius[k]
        for w in range(4):
            f = 0.0
            if wall_active[w]:
                if w == 0:
                    f = k_wall * (walls[0] - (pos[k, 0] - r))
                elif w == 1:
                    f = k_wall * ((pos[k, 0] + r) - walls[1])
                elif w == 2:
                    f = k_wall * (walls[2] - (pos[k, 1] - r))
                else:
                    f = k_wall * ((pos[k, 1] + r) - walls[3])
            if f < 0.0:
                f = 0.0
            wall_force[k, w] = f
        force[k, 0] += wall_force[k, 0] - wall_force[k, 1]
        force[k, 1] += wall_force[k, 2] - wall_force[k, 3]
