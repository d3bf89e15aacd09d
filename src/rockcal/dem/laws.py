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

The loops index with unsigned integers (`uint64`): numba then adds no negative-index
wraparound to each array access, which was a seventh of the engine's step.
"""

from enum import IntEnum
from typing import NamedTuple

import numpy as np
from numba import int64, njit, uint64

from rockcal.dem.bonded import bond_phase

INTACT, BROKEN_TENSION, BROKEN_SHEAR = 0, 1, 2
# squared centre distance / squared contact distance above which a pair surely does not touch
APART = 1.0 + 1e-9
TILE = 128  # bonds whose law runs as one vector loop


class Disk(IntEnum):
    """Columns of a disk's row in `disks`: all the force loops gather of it, and its inverse
    mass and inertia (64 bytes, one cache line)."""

    X = 0
    Y = 1
    VX = 2
    VY = 3
    SPIN = 4
    RADIUS = 5
    INV_MASS = 6
    INV_INERTIA = 7


class Load(IntEnum):
    """Columns of a disk's row in `loads`: the force and moment summed on it."""

    FORCE_X = 0
    FORCE_Y = 1
    MOMENT = 2


LOAD_COMPONENTS = len(Load)  # the columns of `loads` a sum fills (its row has room for one more)


class BondRow(IntEnum):
    """Rows of the bonds' table (`Bonds.table`), one column per bond."""

    FN = 0  # normal force, tension positive, N
    FS = 1  # shear force, N
    M = 2  # moment, N m
    REF_OVERLAP = 3  # overlap at installation (PFC's reference gap, negated), m
    TEN = 4  # tensile strength, Pa
    COH = 5  # cohesion, Pa
    # its particles' radii R_i, R_j (m) and 1 / (R_i + R_j), read here rather than gathered
    # and divided each step (`set_radii`)
    R_I = 6
    R_J = 7
    INV_LENGTH = 8


class TileRow(IntEnum):
    """Rows of a tile (one column per bond of the tile): data gathered from the bonds'
    particles, then what the law hands back."""

    DX = 0  # x_j - x_i
    DY = 1
    DVX = 2  # v_j - v_i
    DVY = 3
    SPIN_I = 4
    SPIN_J = 5
    SHEAR = 6  # the contact's new shear force
    MODE = 7  # the mode the bond broke in (INTACT: none)
    FX = 8  # the pair's force on i and its moments on i and j
    FY = 9
    MI = 10
    MJ = 11
    FN = 12  # the bond's new forces and moment
    FS = 13
    M = 14


TILE_ROWS = len(TileRow)  # a constant for the kernels, which cannot take an enum's length


class Laws(NamedTuple):
    """The law constants, SI: contact modulus (Pa), ks/kn, friction, bond modulus (Pa),
    k̄s/k̄n, bond radius multiplier λ̄, tan of the bond friction angle, moment factor β̄, and
    whether a contact's kn is PFC 3.x/4.0's t·E_c whatever the radii (True) rather than
    PFC 5's 2·min(R)·t·E_c / (R_A + R_B) (False)."""

    E_c: float
    ks_per_kn: float
    mu: float
    Ebar_c: float
    ksbar_per_knbar: float
    lam: float
    tan_phi: float
    mcf: float
    pfc4_contacts: bool


class Bonds(NamedTuple):
    """Per-bond arrays, in the order of the first pairs of the pair list: the bonded-pair
    state of the parallel-bonded material (`bonded`)."""

    state: np.ndarray  # INTACT, BROKEN_TENSION or BROKEN_SHEAR
    break_xy: np.ndarray  # where it broke, m
    table: np.ndarray  # (len(BondRow), n): what the force loop reads and writes of a bond

    REPLACES_CONTACT = False  # a bonded pair's contact acts beside its bond

    def breaks(self) -> tuple[np.ndarray, np.ndarray]:
        """How each bond broke (INTACT, BROKEN_TENSION, BROKEN_SHEAR) and where (m, NaN where
        intact)."""
        return self.state, self.break_xy

    def take_radii(self, radius, pi, pj) -> None:
        """Keep the radii of the bonds' grains pi, pj (`set_radii`): after they change."""
        set_radii(self, radius[pi], radius[pj])

    def springs(self, rmin, length, law: "Laws", thickness: float):
        """Each bond's stiffnesses k̄n Ā, k̄s Ā (N/m) and k̄n Ī (N m/rad), of its grains' smaller
        radius `rmin` and R_i + R_j = `length` (m)."""
        rb = law.lam * rmin
        kbn = law.Ebar_c / length * 2 * rb * thickness
        return kbn, kbn * law.ksbar_per_knbar, law.Ebar_c / length * 2 / 3 * (rb * rb * rb) * thickness


def new_bonds(ref_overlap, ten, coh, ri, rj) -> Bonds:
    """Intact bonds at zero force between particles of radii ri and rj."""
    n = len(ref_overlap)
    table = np.zeros((len(BondRow), n))
    table[BondRow.REF_OVERLAP] = ref_overlap
    table[BondRow.TEN] = ten
    table[BondRow.COH] = coh
    bonds = Bonds(state=np.zeros(n, np.int64), break_xy=np.full((n, 2), np.nan), table=table)
    set_radii(bonds, ri, rj)
    return bonds


def set_radii(bonds: Bonds, ri, rj) -> None:
    """The radii of the bonds' particles, kept in their table: set anew whenever they change."""
    table = bonds.table
    table[BondRow.R_I] = ri
    table[BondRow.R_J] = rj
    table[BondRow.INV_LENGTH] = 1.0 / (table[BondRow.R_I] + table[BondRow.R_J])


# The laws, each written once and called by every force loop. They keep the order of each
# floating-point operation: a run's numbers are part of the engine's version.

@njit(cache=True, error_model="numpy", inline="always")
def pair_geometry(dx, dy, dist_sq, ri, rj):
    """Unit normal (nx, ny) from i to j (j - i = (dx, dy), squared length dist_sq), the
    overlap of the surfaces (negative: a gap) and the lever arms of the contact point,
    mid-gap (or mid-overlap), which add up to the centre distance."""
    dist = np.sqrt(dist_sq)
    surface_overlap = (ri + rj) - dist
    inv_dist = 1.0 / dist
    nx = dx * inv_dist
    ny = dy * inv_dist
    arm_i = ri - 0.5 * surface_overlap
    arm_j = rj - 0.5 * surface_overlap
    return nx, ny, surface_overlap, arm_i, arm_j


@njit(cache=True, error_model="numpy", inline="always")
def contact_velocity(dvx, dvy, spin_i, spin_j, nx, ny, arm_i, arm_j):
    """Velocity of j relative to i at the contact point, along n and t = (-ny, nx)."""
    w = spin_i * arm_i + spin_j * arm_j
    rvx = dvx + w * ny
    rvy = dvy - w * nx
    return rvx * nx + rvy * ny, rvy * nx - rvx * ny


@njit(cache=True, error_model="numpy", inline="always")
def contact_kn(rmin, inv_length, laws):
    """A linear contact's normal stiffness (N/m): PFC 3.x/4.0's t·E_c, or PFC 5's
    2·min(R)·t·E_c / (R_A + R_B) (t = 1 m)."""
    return laws.E_c if laws.pfc4_contacts else 2.0 * rmin * laws.E_c * inv_length


@njit(cache=True, error_model="numpy", inline="always")
def contact_force(overlap, kn, last_shear, vs, laws, dt):
    """Normal and shear force of a linear contact on i (along n and t): fn = -kn overlap
    (negative pushes i away from j), the shear force last_shear + ks vs dt capped by
    Coulomb's mu kn overlap; both zero when apart."""
    touching = (overlap > 0.0) & (laws.E_c > 0.0)
    shear = last_shear + kn * laws.ks_per_kn * vs * dt
    cap = laws.mu * kn * overlap
    shear = cap if shear > cap else shear
    shear = -cap if shear < -cap else shear
    return (-kn * overlap if touching else 0.0), (shear if touching else 0.0)


@njit(cache=True, error_model="numpy", inline="always")
def parallel_bond_force(last_fn, last_fs, last_m, vn, vs, spin_change, rb, inv_length, laws,
                        dt):
    """A parallel bond's normal force (tension positive), shear force and moment after one
    step, from the relative velocity (vn, vs) and spin_j - spin_i; bond radius rb."""
    k_area_dt = laws.Ebar_c * inv_length * (2.0 * rb) * dt  # k̄n Ā dt; Ī = Ā R̄² / 3
    fn = last_fn + k_area_dt * vn
    fs = last_fs + k_area_dt * laws.ksbar_per_knbar * vs
    m = last_m + k_area_dt * rb * rb / 3.0 * spin_change
    return fn, fs, m


@njit(cache=True, error_model="numpy", inline="always")
def parallel_bond_breaks(fn, fs, m, rb, ten, coh, laws):
    """Whether a parallel bond breaks in tension (Fn/Ā + β̄ |M| R̄ / Ī > σ̄c), else in shear
    (|Fs|/Ā > c̄ - (Fn/Ā) tan φ̄)."""
    inv_area = 1.0 / (2.0 * rb)
    sigma = (fn + laws.mcf * 3.0 * abs(m) / rb) * inv_area  # |M| R̄ / Ī = 3 |M| / (R̄ Ā)
    tau = abs(fs) * inv_area
    tension = sigma > ten
    shear = ~tension & (tau > coh - fn * inv_area * laws.tan_phi)
    return tension, shear


@njit(cache=True, error_model="numpy", inline="always")
def force_xy(fn, fs, nx, ny):
    """A pair's force on i along x and y from its parts along n and t = (-ny, nx)."""
    return fn * nx - fs * ny, fn * ny + fs * nx


@bond_phase(Bonds)
@njit(cache=True, error_model="numpy")
def add_bond_forces(first, last, disks, pi, pj, contact_shear, bonds, laws, dt, loads,
                    into_rows=-1):
    """Add the forces and moments of bonded pairs first..last-1 (pair p is bond p) to their
    particles (a pair's force on i is taken from j), or into rows of their own (`pair_rows`);
    intact bonds that exceed a strength break, broken ones act as contacts with their
    reference overlap. Thickness t = 1 m.

    Tile by tile: the particles' data are gathered, the law runs without branches over the
    tile and the bonds' own data (so that it compiles to vector instructions), the bonds' new
    data are stored, and the forces are scattered in pair order, so every sum is the one a
    pair-by-pair loop would make."""
    tile = np.empty((TILE_ROWS, TILE))
    for start in range(first, last, TILE):
        count = min(TILE, last - start)
        _gather(start, count, disks, pi, pj, tile)
        _bond_law(start, count, bonds.state, contact_shear, bonds.table, laws, dt, tile)
        _store(start, count, tile, contact_shear, bonds.table)
        _scatter(start, count, disks, pi, pj, tile, bonds, loads, into_rows)


@njit(cache=True, error_model="numpy", inline="always")
def pair_rows(p, i, j, into_rows):
    """The rows of `loads` a pair's forces go to: its particles i and j (into_rows < 0), or
    (pairs across block borders, summed into the particles later in their order) rows
    2 (p - into_rows) and the next, its own."""
    if into_rows < 0:
        return i, j
    row = uint64(2 * (int64(p) - into_rows))
    return row, row + uint64(1)


@njit(cache=True, error_model="numpy", inline="always")
def _gather(start, count, disks, pi, pj, tile):
    for q in range(uint64(count)):
        p = uint64(start) + q
        i = uint64(pi[p])
        j = uint64(pj[p])
        tile[TileRow.DX, q] = disks[j, Disk.X] - disks[i, Disk.X]
        tile[TileRow.DY, q] = disks[j, Disk.Y] - disks[i, Disk.Y]
        tile[TileRow.DVX, q] = disks[j, Disk.VX] - disks[i, Disk.VX]
        tile[TileRow.DVY, q] = disks[j, Disk.VY] - disks[i, Disk.VY]
        tile[TileRow.SPIN_I, q] = disks[i, Disk.SPIN]
        tile[TileRow.SPIN_J, q] = disks[j, Disk.SPIN]


@njit(cache=True, error_model="numpy", inline="always")
def _bond_law(start, count, bond_state, contact_shear, table, laws, dt, tile):
    """The laws of bonded pairs start..start+count-1 (contact, then parallel bond while
    intact) from their particles' data in `tile` and their own (contact shear force, `table`);
    it writes their new shear and bond forces, the mode they broke in and the force and
    moments on their particles to `tile`, as selections rather than branches (it only reads
    the bonds' arrays: written to, they would keep the loop from vectorising)."""
    for q in range(uint64(count)):
        p = uint64(start) + q
        dx = tile[TileRow.DX, q]
        dy = tile[TileRow.DY, q]
        ri = table[BondRow.R_I, p]
        rj = table[BondRow.R_J, p]
        nx, ny, surface_overlap, arm_i, arm_j = pair_geometry(dx, dy, dx * dx + dy * dy, ri, rj)
        spin_i = tile[TileRow.SPIN_I, q]
        spin_j = tile[TileRow.SPIN_J, q]
        vn, vs = contact_velocity(tile[TileRow.DVX, q], tile[TileRow.DVY, q], spin_i, spin_j,
                                  nx, ny, arm_i, arm_j)
        rmin = min(ri, rj)
        inv_length = table[BondRow.INV_LENGTH, p]
        overlap = surface_overlap - table[BondRow.REF_OVERLAP, p]
        kn = contact_kn(rmin, inv_length, laws)
        fn, fs = contact_force(overlap, kn, contact_shear[p], vs, laws, dt)
        mi = arm_i * fs
        mj = arm_j * fs

        rb = laws.lam * rmin
        last_fn = table[BondRow.FN, p]
        last_fs = table[BondRow.FS, p]
        last_m = table[BondRow.M, p]
        bfn, bfs, bm = parallel_bond_force(last_fn, last_fs, last_m, vn, vs, spin_j - spin_i,
                                           rb, inv_length, laws, dt)
        in_tension, in_shear = parallel_bond_breaks(bfn, bfs, bm, rb, table[BondRow.TEN, p],
                                                    table[BondRow.COH, p], laws)
        intact = bond_state[p] == INTACT
        broke = intact & (in_tension | in_shear)
        holds = intact & ~broke
        tile[TileRow.MODE, q] = (BROKEN_TENSION if in_tension else BROKEN_SHEAR) if broke else \
            INTACT
        tile[TileRow.SHEAR, q] = fs  # stored among the last: stored early, it slows the loop
        tile[TileRow.FN, q] = bfn if holds else (0.0 if broke else last_fn)
        tile[TileRow.FS, q] = bfs if holds else (0.0 if broke else last_fs)
        tile[TileRow.M, q] = bm if holds else (0.0 if broke else last_m)
        fn = fn + bfn if holds else fn
        fs = fs + bfs if holds else fs
        tile[TileRow.MI, q] = mi + (arm_i * bfs + bm) if holds else mi
        tile[TileRow.MJ, q] = mj + (arm_j * bfs - bm) if holds else mj
        tile[TileRow.FX, q], tile[TileRow.FY, q] = force_xy(fn, fs, nx, ny)


@njit(cache=True, error_model="numpy", inline="always")
def _store(start, count, tile, contact_shear, table):
    """The tile's new contact shear forces, bond forces and moments to the bonds' arrays."""
    for q in range(uint64(count)):
        contact_shear[uint64(start) + q] = tile[TileRow.SHEAR, q]
    for q in range(uint64(count)):
        table[BondRow.FN, uint64(start) + q] = tile[TileRow.FN, q]
    for q in range(uint64(count)):
        table[BondRow.FS, uint64(start) + q] = tile[TileRow.FS, q]
    for q in range(uint64(count)):
        table[BondRow.M, uint64(start) + q] = tile[TileRow.M, q]


@njit(cache=True, error_model="numpy", inline="always")
def _scatter(start, count, disks, pi, pj, tile, bonds, loads, into_rows=-1):
    """Note the bonds the tile broke and add its forces to the particles, pair by pair. A pair
    apart and unbonded adds zeros, which change no sum (a force is never -0.0).

    The load on i is summed in registers while consecutive pairs share their i (pairs come
    sorted by i) and stored when i changes: no pair joins a disk to itself, so this is the
    same sum in the same order as adding pair by pair."""
    i_run, _ = pair_rows(uint64(start), uint64(pi[start]), uint64(pj[start]), into_rows)
    fx_run = loads[i_run, Load.FORCE_X]
    fy_run = loads[i_run, Load.FORCE_Y]
    m_run = loads[i_run, Load.MOMENT]
    for q in range(uint64(count)):
        p = uint64(start) + q
        i = uint64(pi[p])
        j = uint64(pj[p])
        if tile[TileRow.MODE, q] != INTACT:
            bonds.state[p] = int(tile[TileRow.MODE, q])
            _record_break(p, i, j, disks, bonds.break_xy)
        i, j = pair_rows(p, i, j, into_rows)
        if i != i_run:
            loads[i_run, Load.FORCE_X] = fx_run
            loads[i_run, Load.FORCE_Y] = fy_run
            loads[i_run, Load.MOMENT] = m_run
            i_run = i
            fx_run = loads[i, Load.FORCE_X]
            fy_run = loads[i, Load.FORCE_Y]
            m_run = loads[i, Load.MOMENT]
        fx = tile[TileRow.FX, q]
        fy = tile[TileRow.FY, q]
        fx_run += fx
        fy_run += fy
        m_run += tile[TileRow.MI, q]
        loads[j, Load.FORCE_X] -= fx
        loads[j, Load.FORCE_Y] -= fy
        loads[j, Load.MOMENT] += tile[TileRow.MJ, q]
    loads[i_run, Load.FORCE_X] = fx_run
    loads[i_run, Load.FORCE_Y] = fy_run
    loads[i_run, Load.MOMENT] = m_run


@njit(cache=True, error_model="numpy", inline="always")
def _record_break(p, i, j, disks, break_xy):
    """Where bond p broke: its contact point, mid-gap between the surfaces."""
    dx = disks[j, Disk.X] - disks[i, Disk.X]
    dy = disks[j, Disk.Y] - disks[i, Disk.Y]
    nx, ny, _, arm_i, _ = pair_geometry(dx, dy, dx * dx + dy * dy, disks[i, Disk.RADIUS],
                                        disks[j, Disk.RADIUS])
    break_xy[p, 0] = disks[i, Disk.X] + nx * arm_i
    break_xy[p, 1] = disks[i, Disk.Y] + ny * arm_i


@njit(cache=True, error_model="numpy")
def add_contact_forces(first, last, disks, pi, pj, contact_shear, laws, dt, loads, into_rows=-1):
    """Add the forces and moments of unbonded pairs first..last-1 to their particles (or into
    rows of their own, `pair_rows`); most are not touching and cost one squared distance."""
    for p in range(uint64(first), uint64(last)):
        i = uint64(pi[p])
        j = uint64(pj[p])
        dx = disks[j, Disk.X] - disks[i, Disk.X]
        dy = disks[j, Disk.Y] - disks[i, Disk.Y]
        dist_sq = dx * dx + dy * dy
        ri = disks[i, Disk.RADIUS]
        rj = disks[j, Disk.RADIUS]
        length = ri + rj
        if dist_sq > APART * length * length:  # surely apart, whatever the rounding
            contact_shear[p] = 0.0
            continue
        nx, ny, overlap, arm_i, arm_j = pair_geometry(dx, dy, dist_sq, ri, rj)
        if overlap <= 0.0:
            contact_shear[p] = 0.0
            continue
        _, vs = contact_velocity(disks[j, Disk.VX] - disks[i, Disk.VX],
                                 disks[j, Disk.VY] - disks[i, Disk.VY], disks[i, Disk.SPIN],
                                 disks[j, Disk.SPIN], nx, ny, arm_i, arm_j)
        kn = contact_kn(min(ri, rj), 1.0 / length, laws)
        fn, fs = contact_force(overlap, kn, contact_shear[p], vs, laws, dt)
        contact_shear[p] = fs
        i, j = pair_rows(p, i, j, into_rows)
        _add_pair_force(i, j, nx, ny, fn, fs, arm_i * fs, arm_j * fs, loads)


@njit(cache=True, error_model="numpy", inline="always")
def _add_pair_force(i, j, nx, ny, fn, fs, mi, mj, loads):
    fx, fy = force_xy(fn, fs, nx, ny)
    loads[i, Load.FORCE_X] += fx
    loads[i, Load.FORCE_Y] += fy
    loads[j, Load.FORCE_X] -= fx
    loads[j, Load.FORCE_Y] -= fy
    loads[i, Load.MOMENT] += mi
    loads[j, Load.MOMENT] += mj


@njit(cache=True, error_model="numpy")
def add_wall_forces(first, last, disks, walls, wall_active, k_wall, loads, wall_force):
    """Frictionless axis-aligned walls (left, right, bottom, top) on particles first..last-1:
    normal force k_wall * overlap. walls holds x_left, x_right, y_bottom, y_top; wall_force[k, w]
    receives the force particle k exerts on wall w along its outward normal (compression
    positive). The walls are read once, before the loop: its stores could otherwise be taken
    to change them, and they would be read again for every particle."""
    left, right, bottom, top = walls[0], walls[1], walls[2], walls[3]
    on_left, on_right, on_bottom, on_top = wall_active[0], wall_active[1], wall_active[2], \
        wall_active[3]
    for k in range(uint64(first), uint64(last)):
        x = disks[k, Disk.X]
        y = disks[k, Disk.Y]
        r = disks[k, Disk.RADIUS]
        f_left = _pushing(k_wall * (left - (x - r))) if on_left else 0.0
        f_right = _pushing(k_wall * ((x + r) - right)) if on_right else 0.0
        f_bottom = _pushing(k_wall * (bottom - (y - r))) if on_bottom else 0.0
        f_top = _pushing(k_wall * ((y + r) - top)) if on_top else 0.0
        wall_force[k, 0] = f_left
        wall_force[k, 1] = f_right
        wall_force[k, 2] = f_bottom
        wall_force[k, 3] = f_top
        loads[k, Load.FORCE_X] += f_left - f_right
        loads[k, Load.FORCE_Y] += f_bottom - f_top


@njit(cache=True, error_model="numpy", inline="always")
def _pushing(f):
    """A wall only pushes."""
    return 0.0 if f < 0.0 else f
