"""Neighbour search in 3D: a cell grid gives the Verlet list of near, unbonded pairs.

The pair list is the permanent bonded pairs followed by the unbonded pairs closer than
R_i + R_j + skin, each part grouped by block of consecutive particles with the pairs across a
block border last (`rockcal.dem.neighbours.block_layout`, shared with the 2D engine): blocks
are summed in parallel without write races, the border pairs after them, in an order fixed by
the specimen alone. It is rebuilt when some sphere has moved more than skin / 2.

Spheres of one rigid body (the pebbles of a clump, the spheres of a rig's jaw) never touch: a
list given their `clump_of` drops their pairs.
"""

from dataclasses import dataclass

import numpy as np
from numba import njit

from rockcal.dem.neighbours import block_layout
from rockcal.engine import ModelBroke

PARTICLES_PER_BLOCK = 4000
# From this many spheres on a specimen is split in blocks, as the 2D engine's from as many
# disks: a sphere's step costs about three disks', so each block has work enough for a thread
SPLIT_FROM = 2000


@dataclass(frozen=True)
class NeighbourList:
    """Pairs i < j: the bonds (pair p < n_bonds is bond p), then the near unbonded pairs.
    `shear` is each unbonded pair's contact shear force vector (N), carried over by `update`;
    a bonded pair's is kept with its bond (`bonds.Bond.CSX`), its row here unused."""

    pi: np.ndarray
    pj: np.ndarray
    n_bonds: int
    shear: np.ndarray  # (pairs, 3)
    block_starts: np.ndarray  # first sphere of each block, and n
    bond_offsets: np.ndarray  # bonds of block b: bond_offsets[b]:[b + 1]; border bonds last
    contact_offsets: np.ndarray  # the same for the unbonded pairs (from n_bonds on)
    pos_at_build: np.ndarray
    skin: float
    clump_of: np.ndarray | None = None  # per sphere its rigid body, -1: none (a ball)

    @property
    def rebuild_distance_sq(self) -> float:
        """The squared displacement beyond which the list must be rebuilt, (skin / 2)²."""
        return (0.5 * self.skin) ** 2


def spatial_order(pos: np.ndarray, slab: float) -> np.ndarray:
    """Order of the spheres slab by slab along z (slabs `slab` thick), then row by row along y,
    then by x: neighbours sit close in memory and blocks of consecutive indices are slabs."""
    return np.lexsort((pos[:, 0], np.floor(pos[:, 1] / slab), np.floor(pos[:, 2] / slab)))


def block_starts(n: int) -> np.ndarray:
    """First sphere of each block, and n: one block below SPLIT_FROM spheres, else an even
    number (at least two) of blocks of about PARTICLES_PER_BLOCK spheres."""
    blocks = 1 if n < SPLIT_FROM else 2 * max(1, round(n / (2 * PARTICLES_PER_BLOCK)))
    return np.linspace(0, n, blocks + 1).astype(np.int64)


def allocate(pos: np.ndarray, radius: np.ndarray, bonds: np.ndarray, skin: float):
    """A list with the bonded pairs `bonds` (i < j) and the near unbonded pairs at `pos`, and
    the order of the bonds in it (its bond k is bonds[order[k]]). Every pair starts with zero
    shear force."""
    n = pos.shape[0]
    bonds = np.asarray(bonds, np.int64).reshape(-1, 2)
    order = np.argsort(bonds[:, 0] * n + bonds[:, 1])
    starts = block_starts(n)
    by_block, bond_offsets = block_layout(bonds[order, 0], bonds[order, 1], starts)
    order = order[by_block]
    bonded = NeighbourList(
        pi=bonds[order, 0], pj=bonds[order, 1], n_bonds=len(bonds),
        shear=np.zeros((len(bonds), 3)), block_starts=starts, bond_offsets=bond_offsets,
        contact_offsets=np.full(len(bond_offsets), len(bonds), np.int64), pos_at_build=pos,
        skin=skin)
    return update(bonded, pos, radius), order


# A packing's cell grid (cell = largest diameter + skin) has about a cell per sphere or fewer;
# spheres spread over more than this many cells per sphere have left any packing (an unstable
# run) and the grid would outgrow memory.
MAX_CELLS_PER_SPHERE = 64
MIN_CELLS = 2**20


class SpheresScattered(ModelBroke):
    """The spheres' positions are no packing's: not finite, or scattered far beyond it."""


def check_grid(pos: np.ndarray, radius: np.ndarray, skin: float) -> None:
    """Before `near_pairs`'s cell grid: positions finite and spread over at most
    MAX_CELLS_PER_SPHERE cells per sphere (a non-finite one gives no cell: the grid would be
    indexed out of bounds); else SpheresScattered."""
    if not (np.isfinite(pos).all() and np.isfinite(radius).all()):
        raise SpheresScattered("a sphere's position or radius is no longer a number")
    cell = 2.0 * float(radius.max()) + skin
    cells = np.prod((pos.max(axis=0) - pos.min(axis=0)) / cell + 3.0)
    if not cells <= MAX_CELLS_PER_SPHERE * len(pos) + MIN_CELLS:
        raise SpheresScattered(f"the spheres are scattered over {cells:.3g} cells of the neighbour grid")


def update(nlist: NeighbourList, pos: np.ndarray, radius: np.ndarray) -> NeighbourList:
    """The list rebuilt at `pos`: the same bonds, new near unbonded pairs; a pair already
    listed keeps its shear force. SpheresScattered where they are no packing (`check_grid`)."""
    n, nb = pos.shape[0], nlist.n_bonds
    check_grid(pos, radius, nlist.skin)
    bond_keys = np.sort(nlist.pi[:nb] * n + nlist.pj[:nb])
    old_keys = nlist.pi[nb:] * n + nlist.pj[nb:]
    order = np.argsort(old_keys)
    ci, cj, shear = _contact_pairs(pos, radius, nlist.skin, bond_keys, old_keys[order],
                                   nlist.shear[nb:][order])
    if nlist.clump_of is not None:  # spheres of one rigid body
        body = nlist.clump_of
        apart = (body[ci] != body[cj]) | (body[ci] < 0)
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
def near_pairs(pos, radius, skin):
    """All pairs i < j with gap < skin, sorted by (i, j), found through a cell grid (cell =
    largest diameter + skin, so a sphere's partners lie in its own and the 26 next cells)."""
    n = pos.shape[0]
    cell = 2.0 * radius.max() + skin
    lo = np.empty(3)
    size = np.empty(3, np.int64)
    for a in range(3):
        lo[a] = pos[:, a].min() - cell
        size[a] = int((pos[:, a].max() - lo[a]) / cell) + 2
    home = np.empty(n, np.int64)
    counts = np.zeros(size[0] * size[1] * size[2] + 1, np.int64)
    for k in range(n):
        cx = int((pos[k, 0] - lo[0]) / cell)
        cy = int((pos[k, 1] - lo[1]) / cell)
        cz = int((pos[k, 2] - lo[2]) / cell)
        home[k] = (cz * size[1] + cy) * size[0] + cx
        counts[home[k] + 1] += 1
    start = np.cumsum(counts)
    fill = start.copy()
    members = np.empty(n, np.int64)
    for k in range(n):
        members[fill[home[k]]] = k
        fill[home[k]] += 1
    # at most as many pairs as spheres in each sphere's 27 cells: room enough, so that the lists
    # are never grown (an array rebound in the loop would cost more than the search itself)
    room = 0
    for i in range(n):
        for dz in range(-1, 2):
            for dy in range(-1, 2):
                c = home[i] + (dz * size[1] + dy) * size[0]
                room += start[c + 2] - start[c - 1]
    pi = np.empty(room, np.int64)
    pj = np.empty(room, np.int64)
    m = 0
    for i in range(n):
        first = m
        for dz in range(-1, 2):
            for dy in range(-1, 2):
                for dx in range(-1, 2):
                    c = home[i] + (dz * size[1] + dy) * size[0] + dx
                    for s in range(start[c], start[c + 1]):
                        j = members[s]
                        if j <= i:
                            continue
                        ddx = pos[j, 0] - pos[i, 0]
                        ddy = pos[j, 1] - pos[i, 1]
                        ddz = pos[j, 2] - pos[i, 2]
                        reach = radius[i] + radius[j] + skin
                        if ddx * ddx + ddy * ddy + ddz * ddz < reach * reach:
                            r = m  # i's partners kept in increasing order
                            while r > first and pj[r - 1] > j:
                                pj[r] = pj[r - 1]
                                r -= 1
                            pj[r] = j
                            pi[m] = i
                            m += 1
    return pi[:m].copy(), pj[:m].copy()


@njit(cache=True)
def _contact_pairs(pos, radius, skin, bond_keys, old_keys, old_shear):
    """Unbonded near pairs with their contact shear force carried over from the last list
    (sorted keys i n + j of the bonds and of the last list's unbonded pairs)."""
    n = pos.shape[0]
    ci, cj = near_pairs(pos, radius, skin)
    keep = np.ones(ci.shape[0], np.bool_)
    shear = np.zeros((ci.shape[0], 3))
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
