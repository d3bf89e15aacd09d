"""The bonded pairs' state: one column per parallel bond in `Bonds.table` (rows `Bond`: its
forces, its contact's shear force, reference overlap, strengths and its spheres' radii),
whether and how it broke, and where. Rows rather than columns per bond, so that the force loop
reads each quantity of consecutive bonds as one vector."""

from enum import IntEnum
from typing import NamedTuple

import numpy as np

from rockcal.dem3d.laws import INTACT, bond_springs


class Bond(IntEnum):
    """Rows of the bonds' table, one column per bond."""

    FN = 0  # bond normal force, tension positive, N
    FSX = 1  # bond shear force on i, N
    FSY = 2
    FSZ = 3
    MBX = 4  # bond bending moment on i, N m
    MBY = 5
    MBZ = 6
    MT = 7  # bond twisting moment on i about n (from i to j), N m
    CSX = 8  # the pair's linear-contact shear force on i, N
    CSY = 9
    CSZ = 10
    REF_OVERLAP = 11  # overlap at installation (PFC's reference gap, negated), m
    TEN = 12  # tensile strength σ̄c, Pa
    COH = 13  # cohesion c̄, Pa
    # the radii R_i, R_j of its spheres, 1 / (R_i + R_j) and 1 / min(R_i, R_j), read here
    # rather than gathered and divided each step (`set_radii`)
    R_I = 14
    R_J = 15
    INV_LENGTH = 16
    INV_RMIN = 17


TABLE_ROWS = len(Bond)


class Bonds(NamedTuple):
    """Per-bond arrays, in the order of the first pairs of the pair list (bond p is pair p)."""

    table: np.ndarray  # (TABLE_ROWS, n)
    state: np.ndarray  # laws.INTACT, BROKEN_TENSION or BROKEN_SHEAR
    break_xyz: np.ndarray  # (n, 3): where it broke (its contact point), m; NaN while intact

    def shear_force(self) -> np.ndarray:
        """(n, 3) bond shear forces on i, N."""
        return self.table[Bond.FSX:Bond.FSZ + 1].T

    def bending_moment(self) -> np.ndarray:
        """(n, 3) bond bending moments on i, N m."""
        return self.table[Bond.MBX:Bond.MBZ + 1].T

    def contact_shear(self) -> np.ndarray:
        """(n, 3) shear forces of the bonded pairs' linear contacts on i, N."""
        return self.table[Bond.CSX:Bond.CSZ + 1].T

    REPLACES_CONTACT = False  # a bonded pair keeps its linear contact

    def springs(self, rmin, length, laws):
        """Each bond's springs (`laws.bond_springs`), zero once broken."""
        intact = self.state == INTACT
        return tuple(np.where(intact, k, 0.0) for k in bond_springs(rmin, length, laws))

    def take_radii(self, ri, rj) -> None:
        """The radii of the bonds' spheres (`set_radii`)."""
        set_radii(self, ri, rj)

    def breaks(self) -> tuple[np.ndarray, np.ndarray]:
        """How each bond broke (laws.INTACT, BROKEN_TENSION, BROKEN_SHEAR) and where (m)."""
        return self.state, self.break_xyz


def new_bonds(ref_overlap, ten, coh, ri, rj) -> Bonds:
    """Intact bonds at zero force between spheres of radii ri, rj, with the overlap of their
    pair at installation (m; negative: a gap) and their tensile strength and cohesion (Pa)."""
    n = len(ref_overlap)
    table = np.zeros((TABLE_ROWS, n))
    table[Bond.REF_OVERLAP] = ref_overlap
    table[Bond.TEN] = ten
    table[Bond.COH] = coh
    bonds = Bonds(table=table, state=np.zeros(n, np.int64), break_xyz=np.full((n, 3), np.nan))
    set_radii(bonds, ri, rj)
    return bonds


def no_bonds() -> Bonds:
    """No bonds: what the engine is given for a state of flat joints."""
    return new_bonds(np.empty(0), np.empty(0), np.empty(0), np.empty(0), np.empty(0))


def set_radii(bonds: Bonds, ri, rj) -> None:
    """The radii of the bonds' spheres, kept in their table: set anew whenever they change."""
    table = bonds.table
    table[Bond.R_I] = ri
    table[Bond.R_J] = rj
    table[Bond.INV_LENGTH] = 1.0 / (table[Bond.R_I] + table[Bond.R_J])
    table[Bond.INV_RMIN] = 1.0 / np.minimum(table[Bond.R_I], table[Bond.R_J])
