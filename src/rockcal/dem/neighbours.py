"""Neighbour search: a cell grid gives the Verlet list of near, unbonded pairs.

The pair list is the permanent bonded pairs followed by the unbonded pairs closer than
R_i + R_j + skin. It is rebuilt only when some particle has moved more than skin / 2 since
the last build, so new contacts are never missed.

Parallel and deterministic: particles are split into blocks of consecutive indices (specimens
number them strip by strip, so a block is a band of the specimen). Pairs are grouped by block
when both ends lie in one, the rest (pairs across a block border) go last: the blocks' pairs
are summed in parallel without write races, the border pairs after them, always in the same
order whatever the number of threads.
"""

import numpy as np
from numba import njit

PARTICLES_PER_BLOCK = 2000


def spatial_order(pos: np.ndarray, strip: float) -> np.ndarray:
    """Order of the particles strip by strip (strips of height `strip`, then by x): neighbours
    then sit close in memory (the pair loops run from cache, not from RAM), and blocks of
    consecutive indices are bands of the specimen."""
    return np.lexsort((pos[:, 0], np.floor(pos[:, 1] / strip)))


def block_starts(n: int) -> np.ndarray:
    """First particle of each block, and n: an even number of blocks of about
    PARTICLES_PER_BLOCK particles (one block below that), set by n alone."""
    blocks = 1 if n < PARTICLES_PER_BLOCK else 2 * max(1, round(n / (2 * PARTICLES_PER_BLOCK)))
    return np.linspace(0, n, blocks + 1).astype(np.int64)


def block_layout(pi: np.ndarray, pj: np.ndarray, starts: np.ndarray):
    """Order of the pairs grouped by block (pairs across a border last, each group in its
    given order) and the offsets of the groups in that order (blocks + 2 entries)."""
    blocks = len(starts) - 1
    bi = np.searchsorted(starts, pi, side="right") - 1
    bj = np.searchsorted(starts, pj, side="right") - 1
    group = np.where(bi == bj, bi, blocks)
    order = np.argsort(group, kind="stable")
    offsets = np.concatenate([[0], np.cumsum(np.bincount(group, minlength=blocks + 1))])
    return order, offsets.astype(np.int64)


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
