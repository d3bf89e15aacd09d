"""The pairs across block borders, as both engines run them (2D disks, 3D spheres).

A block's pair task writes only its own particles' loads; a pair across a border would write
two blocks'. So the border pairs are `TASKS` tasks of their own in the same phase as the
blocks' pair tasks (one per thread of two), each a half of the border bonds and of the border
contacts, writing each pair's forces into two rows of its own (`rows`: on i, on j; the law
kernels' `into_rows`, `laws.pair_rows`). Each block's motion task then adds the rows to its
particles in the pairs' order, bonds then contacts (`add_forces`): the same sums in the same
order as one task adding the pairs to the particles after the blocks', to the last bit.
"""

from __future__ import annotations

import numpy as np
from numba import njit

TASKS = 2


@njit(cache=True)
def rows(bond_offsets, contact_offsets, width):
    """Two zeroed rows of `width` loads (a particle's force and moment components) for each
    pair across block borders (the group after the blocks' in `neighbours.block_layout`'s
    offsets): made here, as `tasks.scratch`."""
    blocks = bond_offsets.shape[0] - 2
    pairs = (bond_offsets[blocks + 1] - bond_offsets[blocks]
             + contact_offsets[blocks + 1] - contact_offsets[blocks])
    return np.zeros((2 * pairs, width))


@njit(cache=True, inline="always")
def _row_starts(bond_offsets, contact_offsets):
    """The kernels' into_rows for the border bonds and for the border contacts (whose rows
    follow the bonds')."""
    blocks = bond_offsets.shape[0] - 2
    border_bonds = bond_offsets[blocks + 1] - bond_offsets[blocks]
    return bond_offsets[blocks], contact_offsets[blocks] - border_bonds


@njit(cache=True, error_model="numpy")
def task_pairs(task, bond_offsets, contact_offsets, rows):
    """Border task `task`'s bonds and contacts, each as (first, last, into_rows): the first or
    second half of the border bonds and of the border contacts; their rows zeroed."""
    bond_rows, contact_rows = _row_starts(bond_offsets, contact_offsets)
    bonds = _half(bond_offsets, task) + (bond_rows,)
    contacts = _half(contact_offsets, task) + (contact_rows,)
    for first, last, into_rows in (bonds, contacts):
        rows[2 * (first - into_rows):2 * (last - into_rows)] = 0.0
    return bonds, contacts


@njit(cache=True, inline="always")
def _half(offsets, task):
    blocks = offsets.shape[0] - 2
    first, last = offsets[blocks], offsets[blocks + 1]
    middle = first + (last - first) // 2
    return (first, middle) if task == 0 else (middle, last)


@njit(cache=True, error_model="numpy")
def add_forces(first, last, pi, pj, bond_offsets, contact_offsets, rows, loads):
    """Add the border pairs' rows to particles first..last-1, in pair order: the border
    bonds', then the border contacts'."""
    blocks = bond_offsets.shape[0] - 2
    bond_rows, contact_rows = _row_starts(bond_offsets, contact_offsets)
    _add_rows(first, last, pi, pj, bond_offsets[blocks], bond_offsets[blocks + 1], bond_rows,
              rows, loads)
    _add_rows(first, last, pi, pj, contact_offsets[blocks], contact_offsets[blocks + 1],
              contact_rows, rows, loads)


@njit(cache=True, error_model="numpy", inline="always")
def _add_rows(first, last, pi, pj, first_pair, last_pair, into_rows, rows, loads):
    for p in range(first_pair, last_pair):
        row = 2 * (p - into_rows)
        if first <= pi[p] < last:
            _add_row(rows, row, loads, pi[p])
        if first <= pj[p] < last:
            _add_row(rows, row + 1, loads, pj[p])


@njit(cache=True, error_model="numpy", inline="always")
def _add_row(rows, row, loads, k):
    for c in range(rows.shape[1]):
        loads[k, c] += rows[row, c]
