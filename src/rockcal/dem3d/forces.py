"""The compiled pair loops: each adds the forces and moments of a range of listed pairs to
their spheres' `loads`, in pair order (so every sum is fixed by the pair list, whatever the
threads). The laws are `laws`'; the loops only gather, call them and scatter.

The bonded pairs run tile by tile (as the 2D engine's): their spheres' data are gathered into
a tile, the laws run without branches over the tile and the bonds' own rows (so that the loop
compiles to vector instructions), the bonds' new state is stored, and the forces are
scattered in pair order.
"""

from enum import IntEnum

import numpy as np
from numba import njit, uint64

from rockcal.dem.laws import pair_rows
from rockcal.dem3d.bonds import Bond
from rockcal.dem3d.laws import (
    BROKEN_SHEAR,
    BROKEN_TENSION,
    INTACT,
    axpy,
    bond_breaks,
    bond_force,
    bond_section,
    contact_force,
    cross,
    dot,
    pair_geometry,
    past_normals,
    plane_rotation,
    rotate,
    scale,
    slip,
)
from rockcal.dem3d.state import Load, Sphere

# squared centre distance / squared contact distance above which a pair surely does not touch
APART = 1.0 + 1e-9
TILE = 64  # bonds whose law runs as one vector loop


class TileRow(IntEnum):
    """Rows of a tile (one column per bond of the tile): what is gathered of the bonds'
    spheres, then what the law hands back."""

    DX = 0  # x_j - x_i
    DY = 1
    DZ = 2
    DVX = 3  # v_j - v_i
    DVY = 4
    DVZ = 5
    WIX = 6  # ω_i
    WIY = 7
    WIZ = 8
    WJX = 9  # ω_j
    WJY = 10
    WJZ = 11
    FX = 12  # the pair's force on i
    FY = 13
    FZ = 14
    MIX = 15  # its moment on i
    MIY = 16
    MIZ = 17
    MJX = 18  # its moment on j
    MJY = 19
    MJZ = 20
    MODE = 21  # the mode the bond broke in this step (INTACT: none)
    FN = 22  # the bond's new state: rows FN..CSZ of `Bond`, in their order
    CSZ = 32


TILE_ROWS = TileRow.CSZ + 1
NEW_STATE = TileRow.FN - Bond.FN  # tile row of a bond row FN..CSZ


@njit(cache=True, error_model="numpy", inline="always")
def _row3(a, r, q):
    return (a[r, q], a[r + 1, q], a[r + 2, q])


@njit(cache=True, error_model="numpy", inline="always")
def _put3(a, r, q, v):
    a[r, q] = v[0]
    a[r + 1, q] = v[1]
    a[r + 2, q] = v[2]


@njit(cache=True, error_model="numpy")
def add_bond_forces(first, last, bodies, loads, pi, pj, table, bond_state, break_xyz, laws,
                    dt, into_rows=-1):
    """Bonded pairs first..last-1 (pair p is bond p): the linear contact (with the bond's
    reference overlap) plus, while intact, the parallel bond; a bond that exceeds a strength
    breaks this step, carries nothing from then on and leaves its contact. Their forces and
    moments go to the spheres' `loads`, or into rows of their own (`pair_rows`)."""
    tile = np.empty((TILE_ROWS, TILE))
    for start in range(first, last, TILE):
        count = min(TILE, last - start)
        _gather(start, count, bodies, pi, pj, tile)
        _bond_law(start, count, table, bond_state, laws, dt, tile)
        _store(start, count, tile, table)
        _scatter(start, count, bodies, pi, pj, tile, bond_state, break_xyz, loads, into_rows)


@njit(cache=True, error_model="numpy", inline="always")
def _gather(start, count, bodies, pi, pj, tile):
    for q in range(uint64(count)):
        p = uint64(start) + q
        i = uint64(pi[p])
        j = uint64(pj[p])
        for a in range(3):
            tile[TileRow.DX + a, q] = bodies[j, Sphere.X + a] - bodies[i, Sphere.X + a]
            tile[TileRow.DVX + a, q] = bodies[j, Sphere.VX + a] - bodies[i, Sphere.VX + a]
            tile[TileRow.WIX + a, q] = bodies[i, Sphere.WX + a]
            tile[TileRow.WJX + a, q] = bodies[j, Sphere.WX + a]


@njit(cache=True, error_model="numpy", inline="always")
def _bond_law(start, count, table, bond_state, laws, dt, tile):
    """The laws of bonded pairs start..start+count-1 from the tile's gathered data and the
    bonds' rows; writes their new state, the mode they broke in and the force and moments on
    their spheres to the tile, as selections rather than branches (it only reads the bonds'
    arrays: written to, they would keep the loop from vectorising)."""
    for q in range(uint64(count)):
        p = uint64(start) + q
        d = _row3(tile, TileRow.DX, q)
        dv = _row3(tile, TileRow.DVX, q)
        wi = _row3(tile, TileRow.WIX, q)
        wj = _row3(tile, TileRow.WJX, q)
        ri = table[Bond.R_I, p]
        rj = table[Bond.R_J, p]
        n, inv_dist, overlap, arm_i, arm_j = pair_geometry(d, ri, rj)
        n_old, n_mid = past_normals(d, dv, inv_dist, dt)
        k, c, inv_opc, cos_t, sin_t = plane_rotation(n_old, n, wi, wj, dt)
        ds = slip(dv, wi, wj, n_mid, n, arm_i, arm_j, dt)
        rmin = min(ri, rj)
        inv_length = table[Bond.INV_LENGTH, p]
        kn = laws.E_c * np.pi * rmin * rmin * inv_length
        ref = table[Bond.REF_OVERLAP, p]
        last_cs = rotate(_row3(table, Bond.CSX, p), n, k, c, inv_opc, cos_t, sin_t)
        # the contact's reference: the overlap at installation, or touching for a bond installed
        # across a gap (its contact carries nothing until the spheres touch, as PFC's and 2D's)
        fn, fs = contact_force(overlap - max(ref, 0.0), kn, last_cs, ds, laws)

        inv_rb, area = bond_section(rmin, table[Bond.INV_RMIN, p], laws)
        last_fs = rotate(_row3(table, Bond.FSX, p), n, k, c, inv_opc, cos_t, sin_t)
        last_mb = rotate(_row3(table, Bond.MBX, p), n, k, c, inv_opc, cos_t, sin_t)
        last_mt = table[Bond.MT, p]
        dtheta = (wj[0] - wi[0]) * dt, (wj[1] - wi[1]) * dt, (wj[2] - wi[2]) * dt
        bfn, bfs, bmb, bmt = bond_force(ref - overlap, last_fs, last_mb, last_mt, ds, dtheta,
                                        n, laws.lam * rmin, area, inv_length, laws)
        tension, sheared = bond_breaks(bfn, bfs, bmb, bmt, inv_rb, area, table[Bond.TEN, p],
                                       table[Bond.COH, p], laws)
        intact = bond_state[p] == INTACT
        holds = 1.0 if intact & ~tension & ~sheared else 0.0
        tile[TileRow.MODE, q] = (BROKEN_TENSION if tension else BROKEN_SHEAR) \
            if intact & (tension | sheared) else INTACT
        tile[Bond.FN + NEW_STATE, q] = holds * bfn
        bfs = scale(holds, bfs)
        bmb = scale(holds, bmb)
        bmt = holds * bmt
        _put3(tile, Bond.FSX + NEW_STATE, q, bfs)
        _put3(tile, Bond.MBX + NEW_STATE, q, bmb)
        tile[Bond.MT + NEW_STATE, q] = bmt
        _put3(tile, Bond.CSX + NEW_STATE, q, fs)
        total_fs = (fs[0] + bfs[0], fs[1] + bfs[1], fs[2] + bfs[2])
        moment = axpy(bmt, n, bmb)
        n_fs = cross(n, total_fs)
        _put3(tile, TileRow.FX, q, axpy(fn + holds * bfn, n, total_fs))
        _put3(tile, TileRow.MIX, q, axpy(arm_i, n_fs, moment))
        _put3(tile, TileRow.MJX, q, axpy(arm_j, n_fs, scale(-1.0, moment)))


@njit(cache=True, error_model="numpy", inline="always")
def _store(start, count, tile, table):
    """The tile's new bond state (rows FN..CSZ) to the bonds' table."""
    for r in range(Bond.FN, Bond.CSZ + 1):
        for q in range(uint64(count)):
            table[r, uint64(start) + q] = tile[r + NEW_STATE, q]


@njit(cache=True, error_model="numpy", inline="always")
def _scatter(start, count, bodies, pi, pj, tile, bond_state, break_xyz, loads, into_rows):
    """Note the bonds the tile broke (where: their contact point) and add its forces and
    moments to the spheres, pair by pair."""
    for q in range(uint64(count)):
        p = uint64(start) + q
        i = uint64(pi[p])
        j = uint64(pj[p])
        if tile[TileRow.MODE, q] != INTACT:
            bond_state[p] = int(tile[TileRow.MODE, q])
            d = _diff(bodies, j, i, Sphere.X)
            n, _, _, arm_i, _ = pair_geometry(d, bodies[i, Sphere.RADIUS],
                                              bodies[j, Sphere.RADIUS])
            for a in range(3):
                break_xyz[p, a] = bodies[i, Sphere.X + a] + arm_i * n[a]
        i, j = pair_rows(p, i, j, into_rows)
        for a in range(3):
            f = tile[TileRow.FX + a, q]
            loads[i, Load.FX + a] += f
            loads[j, Load.FX + a] -= f
            loads[i, Load.MX + a] += tile[TileRow.MIX + a, q]
            loads[j, Load.MX + a] += tile[TileRow.MJX + a, q]


@njit(cache=True, error_model="numpy", inline="always")
def _vec(a, k, c):
    return (a[k, c], a[k, c + 1], a[k, c + 2])


@njit(cache=True, error_model="numpy", inline="always")
def _diff(a, j, i, c):
    return (a[j, c] - a[i, c], a[j, c + 1] - a[i, c + 1], a[j, c + 2] - a[i, c + 2])


@njit(cache=True, error_model="numpy", inline="always")
def _store3(a, k, c, v):
    a[k, c] = v[0]
    a[k, c + 1] = v[1]
    a[k, c + 2] = v[2]


@njit(cache=True, error_model="numpy")
def add_contact_forces(first, last, bodies, loads, pi, pj, shear, laws, dt, into_rows=-1):
    """Unbonded pairs first..last-1: linear contacts; most are apart and cost one squared
    distance (their shear force is reset). Their forces and moments go as `add_bond_forces`'."""
    for p in range(uint64(first), uint64(last)):
        i = uint64(pi[p])
        j = uint64(pj[p])
        d = _diff(bodies, j, i, Sphere.X)
        ri = bodies[i, Sphere.RADIUS]
        rj = bodies[j, Sphere.RADIUS]
        length = ri + rj
        if dot(d, d) > APART * length * length:
            _store3(shear, p, 0, (0.0, 0.0, 0.0))
            continue
        n, inv_dist, overlap, arm_i, arm_j = pair_geometry(d, ri, rj)
        if overlap <= 0.0:
            _store3(shear, p, 0, (0.0, 0.0, 0.0))
            continue
        dv = _diff(bodies, j, i, Sphere.VX)
        wi = _vec(bodies, i, Sphere.WX)
        wj = _vec(bodies, j, Sphere.WX)
        n_old, n_mid = past_normals(d, dv, inv_dist, dt)
        k, c, inv_opc, cos_t, sin_t = plane_rotation(n_old, n, wi, wj, dt)
        ds = slip(dv, wi, wj, n_mid, n, arm_i, arm_j, dt)
        rmin = min(ri, rj)
        kn = laws.E_c * np.pi * rmin * rmin / length
        last_shear = rotate(_vec(shear, p, 0), n, k, c, inv_opc, cos_t, sin_t)
        fn, fs = contact_force(overlap, kn, last_shear, ds, laws)
        _store3(shear, p, 0, fs)
        n_fs = cross(n, fs)
        force = axpy(fn, n, fs)
        i, j = pair_rows(p, i, j, into_rows)
        for a in range(3):
            loads[i, Load.FX + a] += force[a]
            loads[j, Load.FX + a] -= force[a]
            loads[i, Load.MX + a] += arm_i * n_fs[a]
            loads[j, Load.MX + a] += arm_j * n_fs[a]
