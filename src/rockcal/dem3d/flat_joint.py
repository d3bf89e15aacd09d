"""PFC3D's flat joint between two spheres (the `flatjoint` contact model of PFC 5-9 in 3D;
Potyondy 2012): the law of one joint (`update_joint`) and its force loop over the bonded pairs
(`add_flatjoint_forces`, which the engine runs on the bonded pairs of a state whose bonds are
`FlatJoints3D`). The 2D joint is `rockcal.dem.flatjoint`; the names and meanings are the same.

The interface:
- a flat disk of radius R̄ = λ min(R_i, R_j) (`fj_rmul` = λ, `fj_radius` = R̄) centred at
  the contact point (mid-gap, as the parallel bond's in `laws.py`), normal n along the line of
  centres, cut into N_r rings of equal radial width (`fj_nr`) each split into N_α equal
  sectors (`fj_nal`): element (k, s) spans ρ in [k, k + 1] R̄ / N_r and φ in [s, s + 1]
  2π / N_α, φ measured from a tangent t₁ that turns with the contact plane (t₂ = n × t₁);
- stiffnesses per area k_n = E* / (R_i + R_j) (`fj_emod`) and k_s = k_n / κ* (`fj_kratio`);
- the interface's state: its surface gap g_s = g_0 + (overlap at installation - overlap)
  (opening positive, g_0 = `fj_gap0`), its relative bend-rotation θ_b (in the plane, summed
  from (ω_j - ω_i) dt across n; `fj_relbr`); the gap over the disk is the linear field
  g(ρ) = g_s + ρ · (n × θ_b) (j turning relative to i closes one side and opens the other);
- an element's normal force (tension positive) and its first moment S = ∫ σ ρ dA are the
  stress σ = k_n g integrated over it if bonded, k_n min(g, 0) if not (compression only, so an
  unbonded element may be partly open): in closed form over an element wholly closed, and over
  a partly open one in closed form along each ray and by 5-point Gauss-Legendre in φ between
  the angles where the opening line crosses the element's arcs (the integrand is smooth
  there: `closed_part`);
- its shear force (in the plane, incremental): F_s += k_s (A Δδ_s + Δθ_t n × ∫ ρ dA), the
  relative shear displacement of its points averaged, Δθ_t = (ω_j - ω_i) · n dt the twist; a
  bonded element also twists about its centroid, M_t += k_s J_c Δθ_t (J_c its polar second
  moment there), so a bonded interface twists at k_s J whatever N_r, N_α; an unbonded one
  carries no twisting moment of its own;
- a bonded element breaks in tension when σ = F_n / A > σ_c (`fj_ten`), else in shear when
  |F_s| / A > c - σ tan φ (`fj_coh`, `fj_fa`); it is then unbonded at once, in the same step:
  it carries compression only and slips at |F_s| = μ max(-F_n, 0) (`fj_fric`), one broken in
  shear at μ max(-F_n, 0) + c_r A_c (`fj_cohres`, with `fj_resmode` 1; A_c its closed area);
- the interface's force and moment on i are the sums of the elements': F_n n + Σ F_s along
  the plane, bending moment S × n summed, twisting moment Σ (c_e × F_s + M_t) · n about n
  (c_e the element's centroid); on j the opposite force and moment, each sphere's lever arm
  times the shear force added, as the parallel bond's (`forces.add_bond_forces`).

With every element bonded the interface is a parallel bond of the same R̄ and moduli: k_n A,
k_s A, k_n I in bending and k_s J in twist, A = π R̄², I = π R̄⁴/4, J = 2I, whatever N_r, N_α.

The element shear forces and θ_b are kept in the plane's frame (t₁, t₂): the frame turns with
the contact plane each step (`laws.rotate`, as the parallel bond's vectors), so they turn with
it without being rotated themselves. SI units throughout.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit, uint64

from rockcal.dem.laws import pair_rows
from rockcal.dem3d.forces import TileRow, _gather, _put3, _row3
from rockcal.dem3d.fused import fma
from rockcal.dem3d.laws import (
    axpy,
    cross,
    dot,
    inverse_length_near,
    pair_geometry,
    past_normals,
    plane_rotation,
    rotate,
    scale,
    slip,
)
from rockcal.dem3d.state import Load, Sphere
from rockcal.dem3d.vectors import norms

# PFC's fj_state codes, as the 2D joint's (an element broken in tension or shear is a crack)
UNBONDED, BROKEN_TENSION, BROKEN_SHEAR, BONDED = 0, 1, 2, 3
# rows of the joints table, one column per joint: overlap at installation (m), initial gap g_0
# (m), bend-rotation θ_b in (t₁, t₂) (rad), the tangent t₁, k_n and k_s (Pa/m), λ, μ, tan φ,
# residual cohesion c_r (Pa); then what the law hands back: the surface gap (m), the
# interface's normal force on i (N, tension positive), shear force, bending moment vector and
# twisting moment on i (N, N m)
(REF_OVERLAP, GAP0, THETA1, THETA2, T1X, T1Y, T1Z, KN, KS, RMUL, FRIC, TAN_FA, COHRES,
 GAP, FN, FSX, FSY, FSZ, MBX, MBY, MBZ, MT) = range(22)
JOINT_ROWS = 22
# rows of the elements array (rows x joints x N_r x N_α): normal force (N, tension positive),
# shear force in (t₁, t₂) (N), own twisting moment (N m), tensile strength and cohesion (Pa)
E_FN, E_FS1, E_FS2, E_MT, E_TEN, E_COH = range(6)
ELEMENT_ROWS = 6
# an element's area A, first moment ∫ρ dA in (t₁, t₂) and second moments ∫ρ₁², ∫ρ₂², ∫ρ₁ρ₂,
# on a disk of unit radius (`unit_table`: times R̄², R̄³, R̄⁴); then, for the loop, its
# centroid in (t₁, t₂) (times R̄) and polar second moment about the centroid (times R̄⁴)
AREA, C1, C2, J11, J22, J12, X1, X2, POLAR = range(9)
UNIT_ROWS = 9
# 5-point Gauss-Legendre nodes and weights on [-1, 1]
GAUSS_X = np.array([-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                    0.9061798459386640])
GAUSS_W = np.array([0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                    0.4786286704993665, 0.2369268850561891])


class FlatJoints3D(NamedTuple):
    """The state of a set of 3D flat joints of N_r x N_α elements each."""

    table: np.ndarray  # (JOINT_ROWS, joints)
    state: np.ndarray  # (joints, N_r, N_α) int64: BONDED, UNBONDED, BROKEN_*
    elements: np.ndarray  # (ELEMENT_ROWS, joints, N_r, N_α)
    break_xyz: np.ndarray  # (joints, N_r, N_α, 3): where each element broke (its centroid), m

    REPLACES_CONTACT = True  # a flat joint is its pair's only spring

    def springs(self, rmin, length=None, laws=None):
        """Each joint's stiffnesses as a bonded interface of its spheres' smaller radius `rmin`
        (m): k_n A, k_s A (N/m), k_s J (twist) and k_n I (bending) (N m/rad)."""
        rb = self.table[RMUL] * rmin
        area, inertia = np.pi * rb * rb, np.pi * (rb * rb) * (rb * rb) / 4
        kn, ks = self.table[KN], self.table[KS]
        return kn * area, ks * area, ks * 2 * inertia, kn * inertia

    def take_radii(self, ri, rj) -> None:
        """Nothing: a flat joint reads its spheres' radii from them."""

    def broken(self) -> np.ndarray:
        """Each element's break: BROKEN_TENSION, BROKEN_SHEAR, or 0 (not broken), flat."""
        state = self.state.ravel()
        return np.where((state == BROKEN_TENSION) | (state == BROKEN_SHEAR), state, 0)

    def breaks(self) -> tuple[np.ndarray, np.ndarray]:
        """Each element's break (`broken`) and where (its centroid, m; NaN where unbroken)."""
        return self.broken(), self.break_xyz.reshape(-1, 3)


def no_flatjoints_3d() -> FlatJoints3D:
    """No joints: what the engine is given for a state of parallel bonds."""
    return new_flatjoints_3d(1, 3, np.empty((0, 3)), [], [], [], [], [], [], [], [], [], [])


def new_flatjoints_3d(nr: int, nal: int, normal, ref_overlap, kn, ks, rmul, fric, tan_fa, gap0,
                      bonded, ten, coh, cohres=0.0) -> FlatJoints3D:
    """Joints at zero force of N_r = `nr` rings of N_α = `nal` sectors, between spheres along
    the unit `normal`s (joints x 3) at their overlap at installation `ref_overlap` (m). Per
    joint: kn, ks (Pa/m), λ, μ, tan φ, g_0 (m), whether its elements are bonded, ten and coh
    (Pa), c_r (Pa; 0: none)."""
    normal = np.atleast_2d(np.asarray(normal, float))
    n = len(normal)
    table = np.zeros((JOINT_ROWS, n))
    for row, value in ((REF_OVERLAP, ref_overlap), (KN, kn), (KS, ks), (RMUL, rmul), (FRIC, fric),
                       (TAN_FA, tan_fa), (GAP0, gap0), (GAP, gap0), (COHRES, cohres)):
        table[row] = value
    table[T1X:T1Z + 1] = tangents(normal).T
    shape = (n, nr, nal)
    state = np.where(np.broadcast_to(np.asarray(bonded, bool).reshape(-1, 1, 1), shape),
                     BONDED, UNBONDED).astype(np.int64)
    elements = np.zeros((ELEMENT_ROWS,) + shape)
    elements[E_TEN] = np.asarray(ten, float).reshape(-1, 1, 1)
    elements[E_COH] = np.asarray(coh, float).reshape(-1, 1, 1)
    return FlatJoints3D(table, state, elements, np.full(shape + (3,), np.nan))


def tangents(normal) -> np.ndarray:
    """A unit vector across each unit normal (rows): the cross product with the axis least
    along it, normalised (`vectors.norms`: the same bits on every processor)."""
    normal = np.atleast_2d(normal)
    axis = np.zeros_like(normal)
    axis[np.arange(len(normal)), np.argmin(np.abs(normal), axis=1)] = 1.0
    t = np.cross(normal, axis)
    return t / norms(t)[:, None]


@njit(cache=True, error_model="numpy", inline="always")
def sector_moments(r0, r1, p0, p1):
    """Area, first moments and second moments (AREA .. J12) of the annular sector r0 < ρ < r1,
    p0 < φ < p1 in the frame (t₁, t₂)."""
    c0, s0, c1, s1 = np.cos(p0), np.sin(p0), np.cos(p1), np.sin(p1)
    r2 = (r1 * r1 - r0 * r0) / 2
    r3 = (r1 * r1 * r1 - r0 * r0 * r0) / 3
    r4 = (r1 * r1 * r1 * r1 - r0 * r0 * r0 * r0) / 4
    half = (p1 - p0) / 2
    mixed = (s1 * c1 - s0 * c0) / 2
    return (r2 * (p1 - p0), r3 * (s1 - s0), r3 * (c0 - c1), r4 * (half + mixed),
            r4 * (half - mixed), r4 * (s1 * s1 - s0 * s0) / 2)


@njit(cache=True, error_model="numpy", inline="always")
def _ray(gs, b, r0, r1):
    """Along the ray of slope b (g = gs + ρ b), the closed part of r0 < ρ < r1: ∫ g ρ dρ,
    ∫ g ρ² dρ and ∫ ρ dρ over it."""
    lo, hi = r0, r1
    if b > 0.0:
        hi = min(r1, -gs / b)
    elif b < 0.0:
        lo = max(r0, -gs / b)
    elif gs > 0.0:
        hi = lo
    if hi <= lo:
        return 0.0, 0.0, 0.0
    d2 = (hi * hi - lo * lo) / 2
    d3 = (hi * hi * hi - lo * lo * lo) / 3
    d4 = (hi * hi * hi * hi - lo * lo * lo * lo) / 4
    return fma(gs, d2, b * d3), fma(gs, d3, b * d4), d2


@njit(cache=True, error_model="numpy")
def closed_part(gs, a1, a2, r0, r1, p0, p1):
    """The compression-only stress integrals of an unbonded element r0 < ρ < r1, p0 < φ < p1
    under the gap g = gs + a₁ρ₁ + a₂ρ₂: ∫ min(g, 0) dA, its first moments (t₁, t₂) and the
    closed area. Between the angles where the line g = 0 crosses the arcs ρ = r0 and ρ = r1,
    each ray is closed all along, not at all, or up to the line: the first two are
    `sector_moments`' closed forms, the last Gauss-Legendre in φ of closed forms along rays."""
    grad = np.sqrt(a1 * a1 + a2 * a2)
    psi = np.arctan2(a2, a1)
    cuts = np.empty(6)
    cuts[0] = p0
    n = 1
    for r in (r0, r1):
        if r > 0.0 and grad > 0.0 and abs(gs) < grad * r:  # g = 0 crosses this arc
            delta = np.arccos(-gs / (grad * r))
            for angle in (psi - delta, psi + delta):
                angle = p0 + (angle - p0) % (2 * np.pi)
                if angle < p1:
                    k = n  # insertion in order
                    while cuts[k - 1] > angle:
                        cuts[k] = cuts[k - 1]
                        k -= 1
                    cuts[k] = angle
                    n += 1
    cuts[n] = p1
    f = s1 = s2 = area = 0.0
    for piece in range(n):
        lo, hi = cuts[piece], cuts[piece + 1]
        if hi <= lo:
            continue
        mid = 0.5 * (lo + hi)
        cm, sm = np.cos(mid), np.sin(mid)
        b = fma(a1, cm, a2 * sm)
        inner, outer = fma(b, r0, gs), fma(b, r1, gs)
        if inner <= 0.0 and outer <= 0.0:  # closed all along: the sector's closed forms
            a, m1, m2, j11, j22, j12 = sector_moments(r0, r1, lo, hi)
            f += fma(gs, a, fma(a1, m1, a2 * m2))
            s1 += fma(gs, m1, fma(j11, a1, j12 * a2))
            s2 += fma(gs, m2, fma(j12, a1, j22 * a2))
            area += a
        elif inner < 0.0 or outer < 0.0:  # closed up to the line g = 0
            half = 0.5 * (hi - lo)
            for q in range(5):
                phi = fma(half, GAUSS_X[q], mid)
                c, s = np.cos(phi), np.sin(phi)
                g0, g1, d = _ray(gs, fma(a1, c, a2 * s), r0, r1)
                w = half * GAUSS_W[q]
                f += w * g0
                s1 += w * g1 * c
                s2 += w * g1 * s
                area += w * d
    return f, s1, s2, area


@njit(cache=True, error_model="numpy", inline="always")
def update_joint(p, rb, gs, bend1, bend2, ds1, ds2, twist, table, state, elements, unit):
    """PFC's flat-joint law for joint p of radius R̄ = `rb` (m) at surface gap `gs`, given the
    step's bend-rotation (bend1, bend2), shear displacement (ds1, ds2) in (t₁, t₂) and twist
    (rad): updates its θ_b, elements and the interface's normal force, shear force (t₁, t₂),
    first moment S (t₁, t₂) and twisting moment; returns those and how many elements broke."""
    th1 = table[THETA1, p] + bend1
    th2 = table[THETA2, p] + bend2
    table[THETA1, p] = th1
    table[THETA2, p] = th2
    table[GAP, p] = gs
    a1, a2 = -th2, th1  # the gap's gradient n × θ_b in (t₁, t₂)
    kn = table[KN, p]
    ks = table[KS, p]
    fric = table[FRIC, p]
    tan_fa = table[TAN_FA, p]
    cohres = table[COHRES, p]
    nr, nal = state.shape[1], state.shape[2]
    r2 = rb * rb
    r3 = r2 * rb
    r4 = r2 * r2
    dr = rb / nr
    dphi = 2 * np.pi / nal
    grad = np.sqrt(a1 * a1 + a2 * a2)
    fn_sum = fs1_sum = fs2_sum = s1_sum = s2_sum = mt_sum = 0.0
    breaks = 0
    for k in range(uint64(nr)):
        for s in range(uint64(nal)):
            area = unit[AREA, k, s] * r2
            m1 = unit[C1, k, s] * r3
            m2 = unit[C2, k, s] * r3
            j11 = unit[J11, k, s] * r4
            j22 = unit[J22, k, s] * r4
            j12 = unit[J12, k, s] * r4
            bonded = state[p, k, s] == BONDED
            # the linear field over the whole element (bonded, or closed throughout)
            fn = kn * fma(gs, area, fma(a1, m1, a2 * m2))
            sm1 = kn * fma(gs, m1, fma(j11, a1, j12 * a2))
            sm2 = kn * fma(gs, m2, fma(j12, a1, j22 * a2))
            fs1 = elements[E_FS1, p, k, s] + ks * fma(area, ds1, -twist * m2)
            fs2 = elements[E_FS2, p, k, s] + ks * fma(area, ds2, twist * m1)
            mt = elements[E_MT, p, k, s] + ks * unit[POLAR, k, s] * r4 * twist
            if bonded:  # compared as forces: σ A = F_n, and |F_s| > (c - σ tan φ) A
                rest = fma(elements[E_COH, p, k, s], area, -fn * tan_fa)
                if fn > elements[E_TEN, p, k, s] * area:
                    state[p, k, s] = BROKEN_TENSION
                    bonded = False
                elif rest < 0.0 or fma(fs1, fs1, fs2 * fs2) > rest * rest:
                    state[p, k, s] = BROKEN_SHEAR
                    bonded = False
                breaks += 0 if bonded else 1
            if not bonded:
                mt = 0.0
                closed = area
                if fma(grad, (k + 1.0) * dr, gs) > 0.0:  # it may be open somewhere
                    f, q1, q2, closed = closed_part(gs, a1, a2, k * dr, (k + 1.0) * dr,
                                                    s * dphi, (s + 1.0) * dphi)
                    fn, sm1, sm2 = kn * f, kn * q1, kn * q2
                cap = fric * max(-fn, 0.0)
                if cohres > 0.0 and state[p, k, s] == BROKEN_SHEAR:
                    cap += cohres * closed
                size_sq = fs1 * fs1 + fs2 * fs2
                if size_sq > cap * cap:
                    factor = cap / np.sqrt(size_sq)
                    fs1 *= factor
                    fs2 *= factor
            elements[E_FN, p, k, s] = fn
            elements[E_FS1, p, k, s] = fs1
            elements[E_FS2, p, k, s] = fs2
            elements[E_MT, p, k, s] = mt
            fn_sum += fn
            fs1_sum += fs1
            fs2_sum += fs2
            s1_sum += sm1
            s2_sum += sm2
            mt_sum += fma(fma(unit[X1, k, s], fs2, -unit[X2, k, s] * fs1), rb, mt)
    return fn_sum, fs1_sum, fs2_sum, s1_sum, s2_sum, mt_sum, breaks


@njit(cache=True, error_model="numpy")
def unit_table(nr, nal):
    """(UNIT_ROWS, N_r, N_α): each element's moments on a disk of unit radius (`AREA` ..
    `POLAR`)."""
    unit = np.empty((UNIT_ROWS, nr, nal))
    for k in range(nr):
        for s in range(nal):
            moments = sector_moments(k / nr, (k + 1.0) / nr, 2 * np.pi * s / nal,
                                     2 * np.pi * (s + 1.0) / nal)
            for r in range(6):
                unit[r, k, s] = moments[r]
            area, m1, m2, j11, j22 = moments[:5]
            unit[X1, k, s] = m1 / area
            unit[X2, k, s] = m2 / area
            unit[POLAR, k, s] = j11 + j22 - (m1 * m1 + m2 * m2) / area
    return unit


TILE = 64  # joints whose motion is worked out as one vector loop
# rows of a tile, one column per joint: what is gathered of its spheres (x_j - x_i, v_j - v_i,
# ω_i, ω_j in the parallel bonds' rows, `forces.TileRow`; R_i, R_j), then its motion
# (`_motion`): n, t₁, t₂, lever arms, R̄, surface gap, bend-rotation, shear displacement
# (t₁, t₂) and twist of the step
DX, DVX, WIX, WJX = TileRow.DX, TileRow.DVX, TileRow.WIX, TileRow.WJX
RI, RJ, NX, T1, T2, ARM_I, ARM_J, RB, GS, BEND1, BEND2, DS1, DS2, TWIST = (
    12, 13, 14, 17, 20, 23, 24, 25, 26, 27, 28, 29, 30, 31)
TILE_ROWS = 32


@njit(cache=True, error_model="numpy", inline="always")
def _gather_radii(start, count, bodies, pi, pj, tile):
    for q in range(uint64(count)):
        p = uint64(start) + q
        tile[RI, q] = bodies[uint64(pi[p]), Sphere.RADIUS]
        tile[RJ, q] = bodies[uint64(pj[p]), Sphere.RADIUS]


@njit(cache=True, error_model="numpy", inline="always")
def _motion(start, count, table, dt, tile):
    """The step's motion of joints start..start+count-1 at their contact points, from the
    tile's gathered data, into the tile: the frame (t₁ turned with the contact plane as the
    parallel bond's vectors, kept square to n and of unit length), the surface gap and the
    increments in (t₁, t₂). Without branches, and reading the joints' table only, so that it
    compiles to vector instructions."""
    for q in range(uint64(count)):
        p = uint64(start) + q
        d = _row3(tile, DX, q)
        dv = _row3(tile, DVX, q)
        wi = _row3(tile, WIX, q)
        wj = _row3(tile, WJX, q)
        ri = tile[RI, q]
        rj = tile[RJ, q]
        n, inv_dist, overlap, arm_i, arm_j = pair_geometry(d, ri, rj)
        n_old, n_mid = past_normals(d, dv, inv_dist, dt)
        k, c, inv_opc, cos_t, sin_t = plane_rotation(n_old, n, wi, wj, dt)
        ds = slip(dv, wi, wj, n_mid, n, arm_i, arm_j, dt)
        t1 = rotate(_row3(table, T1X, p), n, k, c, inv_opc, cos_t, sin_t)
        t1 = axpy(-dot(t1, n), n, t1)
        t1 = scale(inverse_length_near(dot(t1, t1), 1.0), t1)
        t2 = cross(n, t1)
        dtheta = ((wj[0] - wi[0]) * dt, (wj[1] - wi[1]) * dt, (wj[2] - wi[2]) * dt)
        _put3(tile, NX, q, n)
        _put3(tile, T1, q, t1)
        _put3(tile, T2, q, t2)
        tile[ARM_I, q] = arm_i
        tile[ARM_J, q] = arm_j
        tile[RB, q] = table[RMUL, p] * min(ri, rj)
        tile[GS, q] = table[GAP0, p] + (table[REF_OVERLAP, p] - overlap)
        tile[BEND1, q] = dot(dtheta, t1)
        tile[BEND2, q] = dot(dtheta, t2)
        tile[DS1, q] = dot(ds, t1)
        tile[DS2, q] = dot(ds, t2)
        tile[TWIST, q] = dot(dtheta, n)


@njit(cache=True, error_model="numpy")
def add_flatjoint_forces(first, last, bodies, loads, pi, pj, joints, dt, into_rows=-1):
    """Joints first..last-1 between spheres pi[p] and pj[p] (rows of `bodies`), tile by tile:
    their motion over the step (`_motion`), the law (`update_joint`), where each newly broken
    element broke (its centroid) and their forces and moments added to the spheres' `loads` in
    pair order, or into rows of their own (`pair_rows`), as `forces.add_bond_forces`."""
    table, state, elements, break_xyz = joints
    nr, nal = state.shape[1], state.shape[2]
    unit = unit_table(nr, nal)
    tile = np.empty((TILE_ROWS, TILE))
    for start in range(first, last, TILE):
        count = min(TILE, last - start)
        _gather(start, count, bodies, pi, pj, tile)
        _gather_radii(start, count, bodies, pi, pj, tile)
        _motion(start, count, table, dt, tile)
        for q in range(uint64(count)):
            p = uint64(start) + q
            n = _row3(tile, NX, q)
            t1 = _row3(tile, T1, q)
            t2 = _row3(tile, T2, q)
            _put3(table, T1X, p, t1)
            rb = tile[RB, q]
            fn, fs1, fs2, s1, s2, mt, broke = update_joint(
                p, rb, tile[GS, q], tile[BEND1, q], tile[BEND2, q], tile[DS1, q], tile[DS2, q],
                tile[TWIST, q], table, state, elements, unit)
            i = uint64(pi[p])
            j = uint64(pj[p])
            arm_i = tile[ARM_I, q]
            if broke:
                centre = axpy(arm_i, n, (bodies[i, Sphere.X], bodies[i, Sphere.Y],
                                         bodies[i, Sphere.Z]))
                for ring in range(nr):
                    for s in range(nal):
                        if state[p, ring, s] != BONDED and state[p, ring, s] != UNBONDED \
                                and np.isnan(break_xyz[p, ring, s, 0]):
                            at = axpy(rb * unit[X1, ring, s], t1,
                                      axpy(rb * unit[X2, ring, s], t2, centre))
                            for a in range(3):
                                break_xyz[p, ring, s, a] = at[a]
            fs = axpy(fs1, t1, scale(fs2, t2))
            # bending moment S × n: t₁ × n = -t₂, t₂ × n = t₁
            mb = axpy(s2, t1, scale(-s1, t2))
            _put3(table, FSX, p, fs)
            _put3(table, MBX, p, mb)
            table[FN, p] = fn
            table[MT, p] = mt
            moment = axpy(mt, n, mb)
            n_fs = cross(n, fs)
            force = axpy(fn, n, fs)
            mi = axpy(arm_i, n_fs, moment)
            mj = axpy(tile[ARM_J, q], n_fs, scale(-1.0, moment))
            i, j = pair_rows(p, i, j, into_rows)
            for a in range(3):
                loads[i, Load.FX + a] += force[a]
                loads[j, Load.FX + a] -= force[a]
                loads[i, Load.MX + a] += mi[a]
                loads[j, Load.MX + a] += mj[a]
