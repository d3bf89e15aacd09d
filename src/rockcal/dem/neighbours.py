"""Neighbour search: a cell grid gives the Verlet list of near, unbonded pairs.

The pair list (`NeighbourList`) is the permanent bonded pairs followed by the unbonded pairs
closer than R_i + R_j + skin. It is a value: `allocate` makes one, `update` makes the next from
new positions, and `needs_update` tells when that is due (JAX MD's `partition.neighbor_list`
is the model): when some particle has moved more than skin / 2 since the last build, so new
contacts are never missed.

Parallel and deterministic: particles are split into blocks of consecutive indices (specimens
number them strip by strip, so a block is a band of the specimen). Pairs are grouped by block
when both ends lie in one, the rest (pairs across a block border) go last: the blocks' pairs
are summed in parallel without write races, the border pairs after them, always in the same
order whatever the number of threads.

Pebbles of one rigid clump (`clumps`) never touch: a list given their `clump_of` drops their
pairs.
"""

from dataclasses import dataclass

import numpy as np
from numba import njit

PARTICLES_PER_BLOCK = 2000
# More movers than this at once are the specimen deforming, not a few grains flying free: a
# rebuild, without looking at each.
LONE_MOVERS_AT_MOST = 8


@dataclass(frozen=True)
class NeighbourList:
    """Pairs i < j: the bonds (pair p < n_bonds is bond p), then the near unbonded pairs; each
    part grouped by block (`block_layout`), pairs across a block border last.

    `shear` is the contact shear force of each pair (N): the force laws update it in place,
    and `update` carries it over for the pairs that stay listed, so it lives with the pairs.
    """

    pi: np.ndarray
    pj: np.ndarray
    n_bonds: int
    shear: np.ndarray
    block_starts: np.ndarray  # first particle of each block, and n
    bond_offsets: np.ndarray  # bonds of block b: bond_offsets[b]:[b + 1]; border bonds last
    contact_offsets: np.ndarray  # the same for the unbonded pairs (from n_bonds on)
    pos_at_build: np.ndarray  # particle positions when the list was built
    skin: float  # listed: gap below the skin
    # per particle its rigid clump (-1: a ball, `clumps.members`): pairs within one clump are
    # never listed; None: no clumps
    clump_of: np.ndarray | None = None

    @property
    def rebuild_distance_sq(self) -> float:
        """The squared displacement beyond which the list must be rebuilt, (skin / 2)^2."""
        return (0.5 * self.skin) ** 2


def allocate(pos: np.ndarray, radius: np.ndarray, bonds: np.ndarray, skin: float):
    """A list with the bonded pairs `bonds` (i < j) and the near unbonded pairs at `pos`, and
    the order of the bonds in it (its bond k is bonds[order[k]]): sorted by (i, j), grouped
    by block. Every pair starts with zero shear force."""
    n = pos.shape[0]
    bonds = np.asarray(bonds, np.int64).reshape(-1, 2)
    order = np.argsort(bonds[:, 0] * n + bonds[:, 1])
    starts = block_starts(n)
    by_block, bond_offsets = block_layout(bonds[order, 0], bonds[order, 1], starts)
    order = order[by_block]
    bonded = NeighbourList(
        pi=bonds[order, 0], pj=bonds[order, 1], n_bonds=len(bonds),
        shear=np.zeros(len(bonds)), block_starts=starts, bond_offsets=bond_offsets,
        contact_offsets=np.full(len(bond_offsets), len(bonds), np.int64), pos_at_build=pos,
        skin=skin)
    return update(bonded, pos, radius), order


def update(nlist: NeighbourList, pos: np.ndarray, radius: np.ndarray) -> NeighbourList:
    """The list rebuilt at `pos`: the same bonds, new near unbonded pairs; a pair already
    listed keeps its shear force."""
    n, nb = pos.shape[0], nlist.n_bonds
    bond_keys = nlist.pi[:nb] * n + nlist.pj[:nb]
    old_keys = nlist.pi[nb:] * n + nlist.pj[nb:]
    order = np.argsort(old_keys)
    ci, cj, shear = contact_pairs(pos, radius, nlist.skin, np.sort(bond_keys), old_keys[order],
                                  nlist.shear[nb:][order])
    if nlist.clump_of is not None:  # pebbles of one clump: parts of one rigid body
        clump = nlist.clump_of
        apart = (clump[ci] != clump[cj]) | (clump[ci] < 0)
        ci, cj, shear = ci[apart], cj[apart], shear[apart]
    by_block, offsets = block_layout(ci, cj, nlist.block_starts)
    return NeighbourList(
        pi=np.concatenate([nlist.pi[:nb], ci[by_block]]),
        pj=np.concatenate([nlist.pj[:nb], cj[by_block]]), n_bonds=nb,
        shear=np.concatenate([nlist.shear[:nb], shear[by_block]]),
        block_starts=nlist.block_starts, bond_offsets=nlist.bond_offsets,
        contact_offsets=nb + offsets, pos_at_build=pos.copy(), skin=nlist.skin,
        clump_of=nlist.clump_of)


@njit(cache=True)
def release_lone_movers(pos, radius, pos_at_build, skin) -> bool:
    """Whether the list stays valid with the particles that moved more than skin / 2 since it
    was built taken as built where they are now; if so their `pos_at_build` is set there (if
    not, nothing changes and the list must be rebuilt). So a grain flying free of the specimen
    does not rebuild the list at every half skin of its flight.

    A mover k may be taken so if every other particle j is more than a skin from it with j's
    own travel since the list was built taken off, gap(k, j) - |x_j - x_j,build| >= skin: until
    either has moved another half skin (when the list is looked at again) their gap stays
    positive. A bonded or touching particle fails this, so only the isolated are taken: the
    list holds every pair a rebuild would list that can touch (and perhaps pairs now apart,
    which add zeros), and the forces, summed in the list's fixed order, stay the same to the bit.
    """
    n = pos.shape[0]
    half_skin_sq = (0.5 * skin) ** 2
    travel = np.empty(n)
    movers = np.empty(n, np.int64)
    count = 0
    for k in range(n):
        dx = pos[k, 0] - pos_at_build[k, 0]
        dy = pos[k, 1] - pos_at_build[k, 1]
        travel_sq = dx * dx + dy * dy
        travel[k] = np.sqrt(travel_sq)
        if travel_sq > half_skin_sq:
            movers[count] = k
            count += 1
    if count > LONE_MOVERS_AT_MOST:
        return False
    for m in range(count):
        k = movers[m]
        for j in range(n):
            if j == k:
                continue
            dx = pos[j, 0] - pos[k, 0]
            dy = pos[j, 1] - pos[k, 1]
            if np.sqrt(dx * dx + dy * dy) - radius[j] - radius[k] - travel[j] < skin:
                return False
    for m in range(count):
        pos_at_build[movers[m], 0] = pos[movers[m], 0]
        pos_at_build[movers[m], 1] = pos[movers[m], 1]
    return True


def needs_update(nlist: NeighbourList, pos: np.ndarray) -> bool:
    """Whether some particle has moved more than skin / 2 since the list was built (a change
    of radii also calls for an `update`, which this does not see)."""
    d = pos - nlist.pos_at_build
    return bool((d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1]).max(initial=0.0)
                > nlist.rebuild_distance_sq)


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
    """All pairs i < j with gap < skin, found through a cell grid (cell = largest diameter + skin),
    in the order of i, then j."""
    n = pos.shape[0]
    cap, width = 8 * n + 16, 32
    while True:  # room for the pairs, and for the j of one i; more if they did not fit
        pi = np.empty(cap, np.int64)
        pj = np.empty(cap, np.int64)
        m = _fill_pairs(pos, radius, skin, pi, pj, np.empty(width, np.int64))
        if m >= 0:
            return pi[:m], pj[:m]
        cap, width = 2 * cap, 2 * width


@njit(cache=True)
def _fill_pairs(pos, radius, skin, pi, pj, found):
    """`near_pairs` written into pi, pj; their count, or -1 if pi or `found` (the j of one i,
    kept sorted as they come) is too short. (Arrays grown inside the loop would be counted
    references at every access: 3 x the time.)"""
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
    m = 0
    for i in range(n):
        count = 0
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
                        if count == found.shape[0]:
                            return -1
                        at = count
                        while at > 0 and found[at - 1] > j:
                            found[at] = found[at - 1]
                            at -= 1
                        found[at] = j
                        count += 1
        if m + count > pi.shape[0]:
            return -1
        for a in range(count):
            pi[m] = i
            pj[m] = found[a]
            m += 1
    return m


@njit(cache=True)
def contact_pairs(pos, radius, skin, bond_keys, old_keys, old_shear):
    """Unbonded near pairs with their contact shear force carried over from the last list.

    bond_keys and old_keys are sorted keys i * n + j; a pair keeps its shear force if it was
    in the old list, and starts at zero otherwise.
    """
    n = pos.shape[0]
    ci, cj = near_pairs(pos, radius, skin)  # in key order: the sorted keys are walked along
    keep = np.ones(ci.shape[0], np.bool_)
    shear = np.zeros(ci.shape[0])
    b = o = 0
    for p in range(ci.shape[0]):
        key = ci[p] * n + cj[p]
        while b < bond_keys.shape[0] and bond_keys[b] < key:
            b += 1
        if b < bond_keys.shape[0] and bond_keys[b] == key:
            keep[p] = False
            continue
        while o < old_keys.shape[0] and old_keys[o] < key:
            o += 1
        if o < old_keys.shape[0] and old_keys[o] == key:
            shear[p] = old_shear[o]
    return ci[keep], cj[keep], shear[keep]


# gaps below this fraction of R_min count as contact (floating-point touching)
CONTACT_GAP = 1e-6


def pair_gaps(pos: np.ndarray, radius: np.ndarray, reach: float):
    """Pairs (i, j), i < j, with gap R_i + R_j - d below `reach` (m), and their gaps."""
    pi, pj = near_pairs(pos, radius, reach)
    gap = np.hypot(*(pos[pj] - pos[pi]).T) - radius[pi] - radius[pj]
    return pi, pj, gap


def install_bonds(pos: np.ndarray, radius: np.ndarray, gap: float) -> np.ndarray:
    """Pairs i < j whose gap is <= `gap` (m): the bonds of PFC's installation gap."""
    pi, pj, g = pair_gaps(pos, radius, gap + CONTACT_GAP * radius.min())
    keep = g <= gap + CONTACT_GAP * radius.min()
    return np.column_stack([pi[keep], pj[keep]]).astype(np.int64)
