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
  reference, so the linear contact carries only the overlap added since installation.
Each pair writes the force it exerts on i (j gets the opposite) and the moments on i and j.
"""

import numpy as np
from numba import njit, prange

INTACT, BROKEN_TENSION, BROKEN_SHEAR = 0, 1, 2


@njit(parallel=True, cache=True, error_model="numpy")
def pair_forces(pos, vel, spin, radius, pi, pj, contact_shear, bond_state, bond_fn, bond_fs,
                bond_m, bond_break_xy, bond_ref_overlap, bond_ten, bond_coh, n_bonds, E_c, kn_ks,
                mu, Ebar_c, knbar_ksbar, lam, tan_phi, mcf, thickness, dt, force_on_i,
                moment_on_i, moment_on_j):
    """Forces of every listed pair for one time step; bonds that exceed a strength break."""
    ks_per_kn = 1.0 / kn_ks
    ksbar_per_knbar = 1.0 / knbar_ksbar
    for p in prange(pi.shape[0]):
        i = pi[p]
        j = pj[p]
        dx = pos[j, 0] - pos[i, 0]
        dy = pos[j, 1] - pos[i, 1]
        dist = np.sqrt(dx * dx + dy * dy)
        nx = dx / dist
        ny = dy / dist
        tx = -ny
        ty = nx
        ri = radius[i]
        rj = radius[j]
        rmin = min(ri, rj)
        length = ri + rj
        inv_length = 1.0 / length
        rvx = vel[j, 0] - vel[i, 0] - (spin[i] * ri + spin[j] * rj) * tx
        rvy = vel[j, 1] - vel[i, 1] - (spin[i] * ri + spin[j] * rj) * ty
        vn = rvx * nx + rvy * ny
        vs = rvx * tx + rvy * ty

        fn = 0.0  # along n on i: negative pushes i away from j
        fs = 0.0  # along t on i
        overlap = length - dist
        if p < n_bonds:
            overlap -= bond_ref_overlap[p]
        if overlap > 0.0 and E_c > 0.0:
            kn = 2.0 * rmin * thickness * E_c * inv_length
            shear = contact_shear[p] + kn * ks_per_kn * vs * dt
            cap = mu * kn * overlap
            if shear > cap:
                shear = cap
            elif shear < -cap:
                shear = -cap
            contact_shear[p] = shear
            fn = -kn * overlap
            fs = shear
        else:
            contact_shear[p] = 0.0
        mi = ri * fs
        mj = rj * fs

        if p < n_bonds and bond_state[p] == INTACT:
            rb = lam * rmin
            area = 2.0 * rb * thickness
            inertia = 2.0 / 3.0 * rb * rb * rb * thickness
            kbn = Ebar_c * inv_length
            bfn = bond_fn[p] + kbn * area * vn * dt
            bfs = bond_fs[p] + kbn * ksbar_per_knbar * area * vs * dt
            bm = bond_m[p] + kbn * inertia * (spin[j] - spin[i]) * dt
            inv_area = 1.0 / area
            sigma = (bfn + mcf * 3.0 * abs(bm) / rb) * inv_area  # |M| Rb / I = 3 |M| / (Rb A)
            tau = abs(bfs) * inv_area
            mode = INTACT
            if sigma > bond_ten[p]:
                mode = BROKEN_TENSION
            elif tau > bond_coh[p] - bfn * inv_area * tan_phi:
                mode = BROKEN_SHEAR
            if mode != INTACT:
                bond_state[p] = mode
                bond_break_xy[p, 0] = pos[i, 0] + nx * (ri - 0.5 * (length - dist))
                bond_break_xy[p, 1] = pos[i, 1] + ny * (ri - 0.5 * (length - dist))
                bond_fn[p] = 0.0
                bond_fs[p] = 0.0
                bond_m[p] = 0.0
            else:
                bond_fn[p] = bfn
                bond_fs[p] = bfs
                bond_m[p] = bm
                fn += bfn
                fs += bfs
                mi += ri * bfs + bm
                mj += rj * bfs - bm

        force_on_i[p, 0] = fn * nx + fs * tx
        force_on_i[p, 1] = fn * ny + fs * ty
        moment_on_i[p] = mi
        moment_on_j[p] = mj


@njit(parallel=True, cache=True, error_model="numpy")
def gather_forces(start, pair, side, force_on_i, moment_on_i, moment_on_j, force, moment):
    """Sum the pair forces on each particle in a fixed order (deterministic, race-free)."""
    for k in prange(start.shape[0] - 1):
        fx = 0.0
        fy = 0.0
        m = 0.0
        for e in range(start[k], start[k + 1]):
            p = pair[e]
            if side[e] > 0:
                fx += force_on_i[p, 0]
                fy += force_on_i[p, 1]
                m += moment_on_i[p]
            else:
                fx -= force_on_i[p, 0]
                fy -= force_on_i[p, 1]
                m += moment_on_j[p]
        force[k, 0] = fx
        force[k, 1] = fy
        moment[k] = m


@njit(parallel=True, cache=True, error_model="numpy")
def wall_forces(pos, radius, walls, wall_active, k_wall, force, wall_force):
    """Frictionless axis-aligned walls (left, right, bottom, top): normal force k_wall * overlap.

    walls holds the positions x_left, x_right, y_bottom, y_top; wall_force[k, w] receives the
    force particle k exerts on wall w along the wall's outward normal (compression positive).
    """
    for k in prange(pos.shape[0]):
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
