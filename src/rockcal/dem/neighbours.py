"""Neighbour search: a cell grid gives the Verlet list of near, unbonded pairs.

The pair list is the permanent bonded pairs followed by the unbonded pairs closer than
R_i + R_j + skin. It is rebuilt only when some particle has moved more than skin / 2 since
the last build, so new contacts are never missed. A CSR table (particle -> its pairs) lets
forces be gathered per particle without write races, so loops run in parallel and stay
deterministic.
"""

import numpy as np
from numba import njit


@njit(cache=True)
def near_pairs(pos, radius, skin):
    """All pairs i < j with gap < skin, found through a cell grid (cell = largest diameter + skin)."""
    n = pos.shape[0]
    cell = 2.0 * radius.max() + skin
    x0 = pos[:, 0].min() - cell
    y0 = pos[:, 1].min() - cell
    nx = int((pos[:, 0].max() - x0) / cell) + 2
    ny = int((pos[:, 1].max() - y0) / cell) + 2
    cx = np.empty(n, np.int64)
    cy = np.empty(n, np.int64)
    counts = np.zeros(nx * ny + 1, np.int64)
    for k in range(n):
        cx[k] = int((pos[k, 0] - x0) / cell)
        cy[k] = int((pos[k, 1] - y0) / cell)
        counts[cy[k] * nx + cx[k] + 1] += 1
    start = np.cumsum(counts)
    fill = start.copy()
    members = np.empty(n, np.int64)
    for k in range(n):
        c = cy[k] * nx + cx[k]
        members[fill[c]] = k
        fill[c] += 1
    cap = 8 * n + 16
    pi = np.empty(cap, np.int64)
    pj = np.empty(cap, np.int64)
    m = 0
    for i in range(n):
        for dy in range(-1, 2):
            for dx in range(-1, 2):
                c = (cy[i] + dy) * nx + cx[i] + dx
                for s in range(start[c], start[c + 1]):
                    j = members[s]
                    if j <= i:
                        continue
                    ddx = pos[j, 0] - pos[i, 0]
                    ddy = pos[j, 1] - pos[i, 1]
                    reach = radius[i] + radius[j] + skin
                    if ddx * ddx + ddy * ddy < reach * reach:
                        if m == cap:
                            cap *= 2
                            pi2 = np.empty(cap, np.int64)
                            pj2 = np.empty(cap, np.int64)
                            pi2[:m] = pi[:m]
                            pj2[:m] = pj[:m]
                            pi, pj = pi2, pj2
                        pi[m] = i
                        pj[m] = j
                        m += 1
    order = np.argsort(pi[:m] * n + pj[:m])
    return pi[:m][order], pj[:m][order]


@njit(cache=True)
def contact_pairs(pos, radius, skin, bond_keys, old_keys, old_shear):
    """Unbonded near pairs with their contact shear force carried over from the last list.

    bond_keys and old_keys are sorted keys i * n + j; a pair keeps its shear force if it was
    in the old list, and starts at zero otherwise.
    """
    n = pos.shape[0]
    ci, cj = near_pairs(pos, radius, skin)
    keep = np.ones(ci.shape[0], np.bool_)
    shear = np.zeros(ci.shape[0])
    for p in range(ci.shape[0]):
        key = ci[p] * n + cj[p]
        b = np.searchsorted(bond_keys, key)
        if b < bond_keys.shape[0] and bond_keys[b] == key:
            keep[p] = False
            continue
        o = np.searchsorted(old_keys, key)
        if o < old_keys.shape[0] and old_keys[o] == key:
            shear[p] = old_shear[o]
    return ci[keep], cj[keep], shear[keep]


@njit(cache=True)
def pair_table(n, pi, pj):
    """CSR table: for particle k, entries start[k]:start[k+1] of (pair index, +1 if k is i else -1)."""
    counts = np.zeros(n + 1, np.int64)
    for p in range(pi.shape[0]):
        counts[pi[p] + 1] += 1
        counts[pj[p] + 1] += 1
    start = np.cumsum(counts)
    fill = start[:-1].copy()
    pair = np.empty(2 * pi.shape[0], np.int64)
    side = np.empty(2 * pi.shape[0], np.int64)
    for p in range(pi.shape[0]):
        pair[fill[pi[p]]] = p
        side[fill[pi[p]]] = 1
        fill[pi[p]] += 1
        pair[fill[pj[p]]] = p
        side[fill[pj[p]]] = -1
        fill[pj[p]] += 1
    return start, pair, side
