"""PFC's 2D flat-joint contact (Potyondy 2012; the `flatjoint` contact model of PFC 5-9): the
law over plain arrays (`update_joint`) and the engine's flat-joint phase (`add_flatjoint_forces`,
the bond phase of `FlatJoints`, `bonded`), run on the first pairs of the neighbour list.

The interface (PFC manual, "Flat-Joint Model"; see the docs, "FISHTank's flat-joint names"):
- a segment of half-length R̄ = λ min(R_i, R_j) (`fj_rmul` = λ; `fj_radius` = R̄), unit
  thickness, centred at the contact point (mid-gap, as for the parallel bond in `laws.py`) and
  normal to the line of centres; it is cut into N_r elements of equal length L = 2R̄ / N_r
  (`fj_nr`); element e spans ξ in [-R̄ + e L, -R̄ + (e + 1) L] along the tangent t = (-n_y, n_x),
  its centroid at ξ_e = -R̄ + (e + ½) L, its area A_e = L t;
- element stiffnesses per area k_n = E* / (R_i + R_j) (`fj_emod`, set once when the joint is
  assigned, PFC's `deformability` method) and k_s = k_n / κ* (`fj_kratio`);
- the interface state is its surface gap g_s (opening positive; it starts at the initial gap
  g_0, `fj_gap0`: 0 for a bonded or slit joint, > 0 for a gapped one) and its relative
  bend-rotation θ_b = θ_j - θ_i; both are updated incrementally from the relative motion.
  The gap along the interface is then g(ξ) = g_s - θ_b ξ (j turning counter-clockwise
  relative to i closes the side ξ > 0);
- normal stress (tension positive, PFC's convention for bonded interfaces): σ(ξ) = k_n g(ξ)
  over a bonded element, k_n min(g(ξ), 0) over an unbonded one (no tension). An element's
  normal force F_n^e (tension positive) and bending moment M^e about its centroid are this
  stress integrated over it (in closed form, also over the closed part of an element that is
  partly open): the normal force is a function of the current gap and rotation, so a gapped
  element carries nothing until its gap closes. With g linear across a bonded element,
  F_n^e = k_n A_e g(ξ_e) and M^e = k_n θ_b L³ t / 12;
- shear force per element, incremental: F_s^e += k_s A_e Δδ_s, with Δδ_s the relative shear
  displacement of the element centroid; in 2D the centroids lie on the line through the
  contact point along t, so the bend-rotation adds nothing to it and Δδ_s is the contact's;
- a bonded element (state BONDED) breaks in tension when σ^e = F_n^e / A_e > σ_c (`fj_ten`),
  else in shear when |F_s^e| / A_e > τ_c = c - σ^e tan φ (`fj_coh`, `fj_fa`: compression
  raises the strength); it is then unbonded at once, in the same step;
- an unbonded element carries compression only and slips at |F_s^e| = μ |F_n^e| (`fj_fric`);
  one broken in shear slips at |F_s^e| = μ |F_n^e| + c_r L_c t (`fj_cohres`, acting with
  `fj_resmode` 1; L_c its closed length, where g <= 0): the sheared surface keeps a residual
  cohesion over the part of it that touches;
- the interface force is the sum of the elements' (F_n = Σ F_n^e along n on i, tension
  positive; F_s = Σ F_s^e along t on i), its moment on i about the contact point
  M = Σ (M^e - ξ_e F_n^e); so a partly broken interface still resists rotation. On i act
  F_n n + F_s t and the moment arm_i F_s + M; on j the opposite force and arm_j F_s - M
  (arm = the centre's distance to the contact point), as `laws.py` does for the bond.

With every element bonded the interface is exactly a parallel bond of the same R̄ and moduli:
k_n A and k_s A for translation, k_n I for rotation with I = Σ_e (A_e ξ_e² + L³ t / 12) =
(2/3) R̄³ t, whatever N_r (the centroid sum alone is (2/3) R̄³ t (1 - 1/N_r²)).

State, SI: a joints table (rows GAP to M, one column per joint) and per element a state array
(joints x N_r, PFC's `fj_state` codes) and an elements array (rows E_FN to E_COH, joints x
N_r). With c_r = 0 (PFC's defaults: `fj_cohres` 0, `fj_resmode` 0) the residual term is not
evaluated at all, so the law is the one without it to the last bit.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit, uint64

from rockcal.dem.bonded import bond_phase
from rockcal.dem.laws import Disk, Load, contact_velocity, force_xy, pair_geometry, pair_rows

# PFC's fj_state codes (FISHTank counts an element with fj_state 3 as bonded)
UNBONDED, BROKEN_TENSION, BROKEN_SHEAR, BONDED = 0, 1, 2, 3
# rows of the joints table, one column per flat joint: surface gap g_s (m), relative
# bend-rotation θ_b (rad), k_n and k_s (Pa/m), radius multiplier λ, friction μ, tan φ, and the
# interface's normal force (N, tension positive), shear force (N) and moment on i (N m), and
# the residual cohesion c_r of its elements broken in shear (Pa)
GAP, THETA, KN, KS, RMUL, FRIC, TAN_FA, FN, FS, M, COHRES = range(11)
JOINT_ROWS = 11
# rows of the elements array (rows x joints x N_r): normal force (N, tension positive), shear
# force (N), bending moment on i about the element centroid (N m), tensile strength and
# cohesion (Pa)
E_FN, E_FS, E_M, E_TEN, E_COH = range(5)
ELEMENT_ROWS = 5


class FlatJoints(NamedTuple):
    """The state of a set of flat joints with N_r elements each."""

    table: np.ndarray  # (JOINT_ROWS, joints)
    state: np.ndarray  # (joints, N_r) int64: BONDED, UNBONDED, BROKEN_TENSION, BROKEN_SHEAR
    elements: np.ndarray  # (ELEMENT_ROWS, joints, N_r)
    break_xy: np.ndarray  # (joints, N_r, 2): where each element broke (its centroid), m

    REPLACES_CONTACT = True  # a flat joint is its pair's only spring

    @property
    def nr(self) -> int:
        return self.state.shape[1]

    def breaks(self) -> tuple[np.ndarray, np.ndarray]:
        """Each element's break (`broken`) and where (its centroid, m; NaN where unbroken),
        flat: an element is one crack."""
        return self.broken(), self.break_xy.reshape(-1, 2)

    def take_radii(self, radius, pi, pj) -> None:
        """Nothing: a flat joint reads its grains' radii from them."""

    def springs(self, rmin, length, law, thickness: float):
        """Each joint's stiffnesses as a bonded interface, k_n A, k_s A (N/m) and k_n I
        (N m/rad), of its grains' smaller radius `rmin` (m)."""
        rb = self.table[RMUL] * rmin
        return (self.table[KN] * 2 * rb * thickness, self.table[KS] * 2 * rb * thickness,
                self.table[KN] * 2 / 3 * (rb * rb * rb) * thickness)

    def taken(self, order) -> "FlatJoints":
        """These joints in the order `order` (indices into them)."""
        return FlatJoints(*(np.ascontiguousarray(a) for a in (
            self.table[:, order], self.state[order], self.elements[:, order], self.break_xy[order])))

    def broken(self) -> np.ndarray:
        """Each element's break: BROKEN_TENSION, BROKEN_SHEAR, or 0 (not broken), flat
        (joint p's element e at p N_r + e)."""
        state = self.state.ravel()
        return np.where((state == BROKEN_TENSION) | (state == BROKEN_SHEAR), state, 0)


def new_flatjoints(nr: int, kn, ks, rmul, fric, tan_fa, gap0, bonded, ten, coh,
                   cohres=0.0) -> FlatJoints:
    """Flat joints at zero force with N_r = `nr` elements each. Per joint: kn, ks (Pa/m), λ,
    μ, tan φ, initial surface gap g_0 (m) and whether its elements are bonded (a bool per joint,
    or per element as (joints, nr)); ten, coh (Pa) per joint or per element; the residual
    cohesion c_r (Pa) of elements broken in shear (0: none)."""
    if int(nr) != nr or nr < 1:
        raise ValueError(f"nr must be a whole number >= 1, got {nr}")
    kn = np.atleast_1d(np.asarray(kn, float))
    n = len(kn)
    table = np.zeros((JOINT_ROWS, n))
    table[KN] = kn
    for row, value in ((KS, ks), (RMUL, rmul), (FRIC, fric), (TAN_FA, tan_fa), (GAP, gap0),
                       (COHRES, cohres)):
        table[row] = value
    state = np.where(_per_element(bonded, bool, n, nr), BONDED, UNBONDED).astype(np.int64)
    elements = np.zeros((ELEMENT_ROWS, n, nr))
    elements[E_TEN] = _per_element(ten, float, n, nr)
    elements[E_COH] = _per_element(coh, float, n, nr)
    return FlatJoints(table, state, elements, np.full((n, nr, 2), np.nan))


def _per_element(value, dtype, n: int, nr: int) -> np.ndarray:
    """A value for all, per joint (n,) or per element (n, nr), as (n, nr)."""
    value = np.asarray(value, dtype)
    return np.broadcast_to(value[:, None] if value.ndim == 1 else value, (n, nr))


def element_centroids(rbar: float, nr: int) -> np.ndarray:
    """ξ_e of the N_r elements of an interface of half-length R̄ (m, along t)."""
    length = 2.0 * rbar / nr
    return -rbar + (np.arange(nr) + 0.5) * length


def second_moment(rbar: float, nr: int, thickness: float = 1.0) -> tuple[float, float]:
    """(Σ_e A_e ξ_e², Σ_e L³ t / 12) of an interface: the centroid sum and the elements' own
    second moments; their sum is the rotational stiffness per k_n of a bonded interface,
    (2/3) R̄³ t for every N_r."""
    length = 2.0 * rbar / nr
    xi = element_centroids(rbar, nr)
    return float(np.sum(length * thickness * xi**2)), nr * length**3 * thickness / 12.0


@njit(cache=True, error_model="numpy", inline="always")
def element_normal_force(kn, gap, theta, xc, length, bonded):
    """Normal force (N, tension positive) and bending moment on i about the centroid (N m) of
    an element of length `length` centred at ξ = xc (unit thickness), for surface gap `gap`
    and bend-rotation `theta`: the stress k_n g(ξ), g = gap - theta ξ, integrated over the
    element if bonded, else k_n min(g, 0) (compression only, over its closed part)."""
    gc = gap - theta * xc  # gap at the centroid; across the element g = gc - theta u
    half = 0.5 * length
    if bonded or (gc - theta * half <= 0.0 and gc + theta * half <= 0.0):  # whole element
        return kn * length * gc, kn * theta * length * length * length / 12.0
    # unbonded and partly or wholly open: integrate over the closed part u1 < u < u2
    u1 = -half
    u2 = half
    if theta > 0.0:  # closed where u > gc / theta
        u1 = max(u1, gc / theta)
    elif theta < 0.0:  # closed where u < gc / theta
        u2 = min(u2, gc / theta)
    else:
        u2 = u1  # open throughout (gc > 0)
    if u2 <= u1:
        return 0.0, 0.0
    s0 = gc * (u2 - u1) - 0.5 * theta * (u2 * u2 - u1 * u1)
    s1 = 0.5 * gc * (u2 * u2 - u1 * u1) - theta * (u2 * u2 * u2 - u1 * u1 * u1) / 3.0
    return kn * s0, -kn * s1


@njit(cache=True, error_model="numpy", inline="always")
def closed_length(gap, theta, xc, length):
    """The length of the part of an element (centred at ξ = xc, of length `length`) where the
    gap g(ξ) = gap - theta ξ is closed (g <= 0)."""
    gc = gap - theta * xc
    half = 0.5 * length
    if theta == 0.0:
        return length if gc <= 0.0 else 0.0
    edge = gc / theta  # g = 0 at u = edge (u from the centroid)
    if theta > 0.0:  # closed where u >= edge
        return min(max(half - edge, 0.0), length)
    return min(max(edge + half, 0.0), length)  # closed where u <= edge


@njit(cache=True, error_model="numpy", inline="always")
def update_joint(p, rbar, dn, ds, dtheta, table, state, elements):
    """PFC's flat-joint force-displacement law for joint p of half-length `rbar` (m), given the
    relative motion of the step: normal displacement dn (opening positive), shear displacement
    ds (of j relative to i along t) and bend-rotation dtheta (θ_j - θ_i), all at the contact
    point. Updates the joint's gap, rotation, elements and interface force and moment (rows FN,
    FS, M of `table`); returns how many elements broke. Unsigned indices, as in `laws.py`."""
    p = uint64(p)
    gap = table[GAP, p] + dn
    theta = table[THETA, p] + dtheta
    table[GAP, p] = gap
    table[THETA, p] = theta
    kn = table[KN, p]
    ks = table[KS, p]
    fric = table[FRIC, p]
    tan_fa = table[TAN_FA, p]
    cohres = table[COHRES, p]
    nr = state.shape[1]
    length = 2.0 * rbar / nr
    area = length  # unit thickness
    inv_area = 1.0 / area
    shear_step = ks * area * ds
    fn_sum = 0.0
    fs_sum = 0.0
    m_sum = 0.0
    breaks = 0
    for e in range(uint64(nr)):
        xc = -rbar + (e + 0.5) * length
        bonded = state[p, e] == BONDED
        fn, me = element_normal_force(kn, gap, theta, xc, length, bonded)
        fs = elements[E_FS, p, e] + shear_step
        if bonded:
            sigma = fn * inv_area
            if sigma > elements[E_TEN, p, e]:
                state[p, e] = BROKEN_TENSION
                bonded = False
            elif abs(fs) * inv_area > elements[E_COH, p, e] - sigma * tan_fa:
                state[p, e] = BROKEN_SHEAR
                bonded = False
            if not bonded:
                breaks += 1
                fn, me = element_normal_force(kn, gap, theta, xc, length, False)
        if not bonded:
            cap = fric * max(-fn, 0.0)
            if cohres > 0.0 and state[p, e] == BROKEN_SHEAR:
                cap += cohres * closed_length(gap, theta, xc, length)  # unit thickness
            if fs > cap:
                fs = cap
            elif fs < -cap:
                fs = -cap
        elements[E_FN, p, e] = fn
        elements[E_FS, p, e] = fs
        elements[E_M, p, e] = me
        fn_sum += fn
        fs_sum += fs
        m_sum += me - xc * fn
    table[FN, p] = fn_sum
    table[FS, p] = fs_sum
    table[M, p] = m_sum
    return breaks


@bond_phase(FlatJoints)
@njit(cache=True, error_model="numpy")
def add_flatjoint_forces(first, last, disks, pi, pj, contact_shear, joints, law, dt, loads,
                         into_rows=-1):
    """Joints first..last-1 between grains pi[p] and pj[p] (rows of `disks`, columns
    `laws.Disk`): their relative motion over a step dt at the contact point (mid-gap, as for
    the parallel bond), the law (`update_joint`), where each newly broken element broke (its
    centroid) and their forces and moments added to the grains' `loads`, as `laws.py` adds a
    bond's (the joint's force on i is taken from j), or into rows of their own (`pair_rows`).
    A bond phase (`bonded`): the contacts' shear forces and the law constants are not a flat
    joint's."""
    table, state, elements, break_xy = joints
    nr = state.shape[1]
    for p in range(uint64(first), uint64(last)):
        i = uint64(pi[p])
        j = uint64(pj[p])
        dx = disks[j, Disk.X] - disks[i, Disk.X]
        dy = disks[j, Disk.Y] - disks[i, Disk.Y]
        ri = disks[i, Disk.RADIUS]
        rj = disks[j, Disk.RADIUS]
        nx, ny, _, arm_i, arm_j = pair_geometry(dx, dy, dx * dx + dy * dy, ri, rj)
        spin_i = disks[i, Disk.SPIN]
        spin_j = disks[j, Disk.SPIN]
        vn, vs = contact_velocity(disks[j, Disk.VX] - disks[i, Disk.VX],
                                  disks[j, Disk.VY] - disks[i, Disk.VY], spin_i, spin_j, nx, ny,
                                  arm_i, arm_j)
        rbar = table[RMUL, p] * min(ri, rj)
        if update_joint(p, rbar, vn * dt, vs * dt, (spin_j - spin_i) * dt, table, state, elements):
            cx = disks[i, Disk.X] + nx * arm_i
            cy = disks[i, Disk.Y] + ny * arm_i
            length = 2.0 * rbar / nr
            for e in range(uint64(nr)):
                if state[p, e] != BONDED and state[p, e] != UNBONDED and np.isnan(break_xy[p, e, 0]):
                    xi = -rbar + (e + 0.5) * length
                    break_xy[p, e, 0] = cx - ny * xi
                    break_xy[p, e, 1] = cy + nx * xi
        fs = table[FS, p]
        m = table[M, p]
        fx, fy = force_xy(table[FN, p], fs, nx, ny)
        i, j = pair_rows(p, i, j, into_rows)
        loads[i, Load.FORCE_X] += fx
        loads[i, Load.FORCE_Y] += fy
        loads[j, Load.FORCE_X] -= fx
        loads[j, Load.FORCE_Y] -= fy
        loads[i, Load.MOMENT] += arm_i * fs + m
        loads[j, Load.MOMENT] += arm_j * fs - m
