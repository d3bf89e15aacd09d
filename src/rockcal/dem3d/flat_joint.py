"""PFC3D's flat joint between two spheres (the `flatjoint` contact model of PFC 5-9 in 3D;
Potyondy 2012): its force loop over the bonded pairs (`add_flatjoint_forces`, which the
engine runs on the bonded pairs of a state whose bonds are `FlatJoints3D`). The 2D joint is
`rockcal.dem.flatjoint`; the names and meanings are the same.

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
  unbonded element may be partly open): in closed form, over a partly open one as sectors and
  triangles cut by the opening line (`closed_part`);
- its shear force (in the plane, incremental): F_s += k_s (A Δδ_s + Δθ_t n × ∫ ρ dA), the
  relative shear displacement of its points averaged, Δθ_t = (ω_j - ω_i) · n dt the twist; a
  bonded element also twists about its centroid, M_t += k_s J_c Δθ_t (J_c its polar second
  moment there), so a bonded interface twists at k_s J whatever N_r, N_α; an unbonded one
  carries no twisting moment of its own. While bonded the sums are k_s (A δ_s + θ_t n × ∫ ρ dA)
  and k_s J_c θ_t, of the joint's shear displacement δ_s and twist θ_t since installation:
  only an unbonded element keeps a shear force of its own;
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

The element shear forces, δ_s and θ_b are kept in the plane's frame (t₁, t₂): the frame turns
with the contact plane each step (`laws.rotate`, as the parallel bond's vectors), so they turn
with it without being rotated themselves.

The loop works tile by tile (as the parallel bond's, `forces`): the joints' motion, then their
elements element by element across the joints' columns, as vector loops over arrays laid out
element by element (`FlatJoints3D`); only an element that breaks, or an unbonded one in a joint
whose gap is neither closed nor open over the whole disk, is worked out on its own. SI units
throughout.
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
# residual cohesion c_r, the bonded elements' tensile strength and cohesion (Pa), the relative
# shear displacement in (t₁, t₂) (m) and twist (rad) summed since installation; then what the
# law hands back: the surface gap (m), the interface's normal force on i (N, tension
# positive), shear force, bending moment vector and twisting moment on i (N, N m)
(REF_OVERLAP, GAP0, THETA1, THETA2, T1X, T1Y, T1Z, KN, KS, RMUL, FRIC, TAN_FA, COHRES, TEN,
 COH, SHEAR1, SHEAR2, TWIST_SUM, GAP, FN, FSX, FSY, FSZ, MBX, MBY, MBZ, MT) = range(27)
JOINT_ROWS = 27
# rows of the elements array (rows x N_r x N_α x joints, each element's values contiguous
# across the joints): an unbonded element's shear force in (t₁, t₂) (N). A bonded element's is
# k_s (A Δ_s + Θ_t n × ∫ ρ dA), Δ_s and Θ_t its joint's shear displacement and twist since
# installation (`SHEAR1`, `TWIST_SUM`): kept in the array from the step it is unbonded
E_FS1, E_FS2 = range(2)
ELEMENT_ROWS = 2
# an element's area A, first moment ∫ρ dA in (t₁, t₂) and second moments ∫ρ₁², ∫ρ₂², ∫ρ₁ρ₂,
# on a disk of unit radius (`unit_table`: times R̄², R̄³, R̄⁴); then, for the loop, its
# centroid in (t₁, t₂) (times R̄), polar second moment about the centroid (times R̄⁴), inner
# and outer radii (times R̄) and the directions (cos, sin) of its sides φ = φ₀ and φ = φ₁
AREA, C1, C2, J11, J22, J12, X1, X2, POLAR, R0, R1, COS0, SIN0, COS1, SIN1 = range(15)
UNIT_ROWS = 15

class FlatJoints3D(NamedTuple):
    """The state of a set of 3D flat joints of N_r x N_α elements each."""

    table: np.ndarray  # (JOINT_ROWS, joints)
    state: np.ndarray  # (N_r, N_α, joints) int64: BONDED, UNBONDED, BROKEN_*
    elements: np.ndarray  # (ELEMENT_ROWS, N_r, N_α, joints)
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
        state = np.moveaxis(self.state, 2, 0).ravel()  # joint by joint, as `break_xyz`
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
                       (TAN_FA, tan_fa), (GAP0, gap0), (GAP, gap0), (COHRES, cohres), (TEN, ten),
                       (COH, coh)):
        table[row] = value
    table[T1X:T1Z + 1] = tangents(normal).T
    state = np.where(np.broadcast_to(np.asarray(bonded, bool), (nr, nal, n)), BONDED,
                     UNBONDED).astype(np.int64)
    elements = np.zeros((ELEMENT_ROWS, nr, nal, n))
    return FlatJoints3D(table, state, elements, np.full((n, nr, nal, 3), np.nan))


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


@njit(cache=True, error_model="numpy")
def _piece(gs, a1, a2, r, u1, u2, w1, w2, span):
    """Area, first and second moments (AREA .. J12) of the closed part of the sector ρ < r
    between the unit directions u and w, `span` apart, along each of whose rays the closed
    part is alike: the whole ray (a sector), none, the ray up to the line g = 0 (a triangle
    with a corner at the centre) or beyond it (a sector less such a triangle)."""
    mid1, mid2 = u1 + w1, u2 + w2
    # the gap at the arc mid-piece, times the length of (mid1, mid2)
    rim = fma(gs, np.sqrt(fma(mid1, mid1, mid2 * mid2)), r * fma(a1, mid1, a2 * mid2))
    closed = rim <= 0.0 and gs <= 0.0 or rim < 0.0  # the ray, out to the arc
    area = m1 = m2 = j11 = j22 = j12 = 0.0
    if closed:
        half = 0.5 * span
        mixed = 0.5 * fma(w2, w1, -u2 * u1)
        r2 = r * r
        r3 = r2 * r / 3
        r4 = r2 * r2 / 4
        area, m1, m2 = r2 * half, r3 * (w2 - u2), r3 * (u1 - w1)
        j11, j22, j12 = r4 * (half + mixed), r4 * (half - mixed), r4 * 0.5 * fma(w2, w2, -u2 * u2)
    if gs < 0.0 and not closed or gs > 0.0 and closed:  # up to the line, or beyond it
        reach_u = -gs / fma(a1, u1, a2 * u2)
        reach_w = -gs / fma(a1, w1, a2 * w2)
        p1, p2, q1, q2 = reach_u * u1, reach_u * u2, reach_w * w1, reach_w * w2
        t = (0.5 if gs < 0.0 else -0.5) * fma(p1, q2, -p2 * q1)  # its signed area
        area += t
        m1 += t * (p1 + q1) / 3
        m2 += t * (p2 + q2) / 3
        j11 += t * fma(p1, p1 + q1, q1 * q1) / 6
        j22 += t * fma(p2, p2 + q2, q2 * q2) / 6
        j12 += t * (p1 * (2 * p2 + q2) + q1 * (p2 + 2 * q2)) / 12
    return area, m1, m2, j11, j22, j12


@njit(cache=True, error_model="numpy", inline="always")
def _plus(a, b):
    return a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3], a[4] + b[4], a[5] + b[5]


@njit(cache=True, error_model="numpy")
def _closed_moments(gs, a1, a2, r, c0, s0, c1, s1, span):
    """Area, first and second moments (AREA .. J12) of the part of the sector ρ < r between the
    unit directions (c0, s0) and (c1, s1), `span` (< π) apart, where the gap gs + a₁ρ₁ + a₂ρ₂
    is closed (<= 0): the directions where the line g = 0 crosses the arc (at most two) cut
    it into pieces (`_piece`)."""
    grad_sq = fma(a1, a1, a2 * a2)
    reach_sq = r * r * grad_sq - gs * gs  # the line crosses the arc if > 0
    cuts = 0
    x0 = y0 = angle0 = x1 = y1 = angle1 = 0.0
    if reach_sq > 0.0:
        root = np.sqrt(reach_sq)
        for sign in (-1.0, 1.0):  # the crossings (-gs a ± root n × a) / |a|², over r
            x = fma(-gs, a1, -sign * root * a2) / (grad_sq * r)
            y = fma(-gs, a2, sign * root * a1) / (grad_sq * r)
            across0 = fma(c0, y, -s0 * x)
            if across0 > 0.0 and fma(x, s1, -y * c1) > 0.0:  # strictly inside the sector
                angle = np.arctan2(across0, fma(c0, x, s0 * y))
                if cuts == 0:
                    x0, y0, angle0 = x, y, angle
                elif angle < angle0:
                    x0, y0, angle0, x1, y1, angle1 = x, y, angle, x0, y0, angle0
                else:
                    x1, y1, angle1 = x, y, angle
                cuts += 1
    if cuts == 0:
        return _piece(gs, a1, a2, r, c0, s0, c1, s1, span)
    total = _piece(gs, a1, a2, r, c0, s0, x0, y0, angle0)
    if cuts == 2:
        total = _plus(total, _piece(gs, a1, a2, r, x0, y0, x1, y1, angle1 - angle0))
        x0, y0, angle0 = x1, y1, angle1
    return _plus(total, _piece(gs, a1, a2, r, x0, y0, c1, s1, span - angle0))


@njit(cache=True, error_model="numpy")
def closed_part(gs, a1, a2, r0, r1, c0, s0, c1, s1, span):
    """The compression-only stress integrals of an unbonded element r0 < ρ < r1 between the
    unit directions (c0, s0) and (c1, s1), `span` apart, under the gap g = gs + a₁ρ₁ + a₂ρ₂:
    ∫ min(g, 0) dA, its first moments (t₁, t₂) and the closed area; the closed part's moments
    (`_closed_moments`) out to r1 less those out to r0."""
    area, m1, m2, j11, j22, j12 = _closed_moments(gs, a1, a2, r1, c0, s0, c1, s1, span)
    if r0 > 0.0:
        inner = _closed_moments(gs, a1, a2, r0, c0, s0, c1, s1, span)
        area -= inner[0]
        m1 -= inner[1]
        m2 -= inner[2]
        j11 -= inner[3]
        j22 -= inner[4]
        j12 -= inner[5]
    return (fma(gs, area, fma(a1, m1, a2 * m2)), fma(gs, m1, fma(j11, a1, j12 * a2)),
            fma(gs, m2, fma(j12, a1, j22 * a2)), area)


@njit(cache=True, error_model="numpy")
def unit_table(nr, nal):
    """(UNIT_ROWS, N_r N_α): each element's moments on a disk of unit radius (`AREA` ..
    `POLAR`), its radii and the directions of its sides (`R0` .. `SIN1`); element (k, s) is
    column k N_α + s."""
    unit = np.empty((UNIT_ROWS, nr * nal))
    for k in range(nr):
        for s in range(nal):
            e = k * nal + s
            p0, p1 = 2 * np.pi * s / nal, 2 * np.pi * (s + 1.0) / nal
            moments = sector_moments(k / nr, (k + 1.0) / nr, p0, p1)
            for r in range(6):
                unit[r, e] = moments[r]
            area, m1, m2, j11, j22 = moments[:5]
            unit[X1, e] = m1 / area
            unit[X2, e] = m2 / area
            unit[POLAR, e] = j11 + j22 - (m1 * m1 + m2 * m2) / area
            unit[R0, e] = k / nr
            unit[R1, e] = (k + 1.0) / nr
            unit[COS0, e], unit[SIN0, e] = np.cos(p0), np.sin(p0)
            unit[COS1, e], unit[SIN1, e] = np.cos(p1), np.sin(p1)
    return unit


TILE = 64  # joints whose motion, then whose elements, are worked out as vector loops
# rows of a tile, one column per joint: what is gathered of its spheres (x_j - x_i, v_j - v_i,
# ω_i, ω_j in the parallel bonds' rows, `forces.TileRow`; R_i, R_j), then its motion
# (`_motion`): n, t₁, t₂, lever arms, R̄, surface gap, bend-rotation, shear displacement
# (t₁, t₂) and twist of the step; then (`_bend`) the gap's gradient n × θ_b in (t₁, t₂), the
# joint's k_n, k_s, tan φ, μ, c_r, σ_c and c, its θ_b, shear displacement (t₁, t₂) and twist
# since installation, the gradient's length and whether the gap is closed or open over the
# whole disk; the interface's
# normal force, shear force (t₁, t₂), first moment S (t₁, t₂) and twisting moment (`_sums`);
# how many of its elements broke this step; its shear force and bending moment vectors and
# the force and moments on its spheres (`_forces`)
DX, DVX, WIX, WJX = TileRow.DX, TileRow.DVX, TileRow.WIX, TileRow.WJX
(RI, RJ, NX, T1, T2, ARM_I, ARM_J, RB, GS, BEND1, BEND2, DS1, DS2, TWIST, A1, A2, J_KN, J_KS,
 J_TAN_FA, J_FRIC, J_COHRES, J_TEN, J_COH, J_THETA1, J_THETA2, J_SHEAR1, J_SHEAR2, J_TWIST_SUM,
 GRAD, WHOLE, SUM_FN, SUM_FS1, SUM_FS2, SUM_S1, SUM_S2, SUM_MT, BROKE, OUT_FS, OUT_MB, OUT_F,
 OUT_MI, OUT_MJ) = (12, 13, 14, 17, 20, *range(23, 55), 55, 58, 61, 64, 67)
TILE_ROWS = 70
# a joint's gap field over its disk (row WHOLE): closed throughout, open throughout, or neither
CLOSED, OPEN, PARTLY = 1.0, -1.0, 0.0
# rows of an element tile (N_r N_α x rows x TILE): the element's new normal force, first
# moment S (t₁, t₂), shear force (t₁, t₂) and own twisting moment; the mode it breaks in this
# step (0: none) and whether it is to be worked out as unbonded (`_unbonded`)
W_FN, W_S1, W_S2, W_FS1, W_FS2, W_MT, W_BREAK, W_FIX = range(8)
WORK_ROWS = 8


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


@njit(cache=True, error_model="numpy", inline="always")
def _bend(start, count, table, tile):
    """The joints' constants and their θ_b, shear displacement and twist after the step to the
    tile; the gap's gradient n × θ_b and whether the gap is closed or open over the whole disk.
    Row by row (vector loops)."""
    for constant, row in ((KN, J_KN), (KS, J_KS), (TAN_FA, J_TAN_FA), (FRIC, J_FRIC),
                          (COHRES, J_COHRES), (TEN, J_TEN), (COH, J_COH)):
        for q in range(uint64(count)):
            tile[row, q] = table[constant, uint64(start) + q]
    for total, step, row in ((THETA1, BEND1, J_THETA1), (THETA2, BEND2, J_THETA2),
                             (SHEAR1, DS1, J_SHEAR1), (SHEAR2, DS2, J_SHEAR2),
                             (TWIST_SUM, TWIST, J_TWIST_SUM)):
        for q in range(uint64(count)):
            tile[row, q] = table[total, uint64(start) + q] + tile[step, q]
    for q in range(uint64(count)):
        th1 = tile[J_THETA1, q]
        th2 = tile[J_THETA2, q]
        tile[A1, q] = -th2
        tile[A2, q] = th1
        tile[GRAD, q] = np.sqrt(th1 * th1 + th2 * th2)
        reach = tile[RB, q] * tile[GRAD, q]
        gs = tile[GS, q]
        tile[WHOLE, q] = CLOSED if gs + reach <= 0.0 else (OPEN if gs - reach > 0.0 else PARTLY)
        tile[BROKE, q] = 0.0


@njit(cache=True, error_model="numpy", inline="always")
def _store(start, count, tile, table):
    """The joints' new state to their table, row by row (vector loops): θ_b, shear
    displacement and twist, the frame, the surface gap and the interface's force and moments
    on i (`_forces`)."""
    for row, total in ((J_THETA1, THETA1), (J_THETA2, THETA2), (J_SHEAR1, SHEAR1),
                       (J_SHEAR2, SHEAR2), (J_TWIST_SUM, TWIST_SUM), (T1, T1X), (T1 + 1, T1Y),
                       (T1 + 2, T1Z), (GS, GAP), (SUM_FN, FN), (OUT_FS, FSX), (OUT_FS + 1, FSY),
                       (OUT_FS + 2, FSZ), (OUT_MB, MBX), (OUT_MB + 1, MBY), (OUT_MB + 2, MBZ),
                       (SUM_MT, MT)):
        for q in range(uint64(count)):
            table[total, uint64(start) + q] = tile[row, q]


@njit(cache=True, error_model="numpy", inline="always")
def _elements(start, count, state, unit, tile, work):
    """Every element of the tile's joints as if bonded, element by element across the joints
    (a vector loop, as selections rather than branches, that reads the tile and the elements'
    state only): the linear field over it, its shear force and twisting moment from its joint's
    shear displacement and twist since installation, and whether it breaks. Marked for
    `_unbonded`: those that break. Returns how many elements are unbonded and how many break."""
    unbonded = breaking = 0
    for e in range(state.shape[0]):
        area_u, c1_u, c2_u = unit[AREA, e], unit[C1, e], unit[C2, e]
        j11_u, j22_u, j12_u, polar_u = unit[J11, e], unit[J22, e], unit[J12, e], unit[POLAR, e]
        for q in range(uint64(count)):
            rb = tile[RB, q]
            r2 = rb * rb
            r3 = r2 * rb
            r4 = r2 * r2
            area = area_u * r2
            m1 = c1_u * r3
            m2 = c2_u * r3
            j11 = j11_u * r4
            j22 = j22_u * r4
            j12 = j12_u * r4
            gs, a1, a2 = tile[GS, q], tile[A1, q], tile[A2, q]
            kn = tile[J_KN, q]
            ks = tile[J_KS, q]
            twist = tile[J_TWIST_SUM, q]
            fn = kn * fma(gs, area, fma(a1, m1, a2 * m2))
            fs1 = ks * fma(area, tile[J_SHEAR1, q], -twist * m2)
            fs2 = ks * fma(area, tile[J_SHEAR2, q], twist * m1)
            # compared as forces: σ A = F_n and |F_s| > (c - σ tan φ) A
            rest = fma(tile[J_COH, q], area, -fn * tile[J_TAN_FA, q])
            tension = fn > tile[J_TEN, q] * area
            sheared = (rest < 0.0) | (fma(fs1, fs1, fs2 * fs2) > rest * rest)
            bonded = state[e, uint64(start) + q] == BONDED
            work[e, W_FN, q] = fn
            work[e, W_S1, q] = kn * fma(gs, m1, fma(j11, a1, j12 * a2))
            work[e, W_S2, q] = kn * fma(gs, m2, fma(j12, a1, j22 * a2))
            work[e, W_FS1, q] = fs1
            work[e, W_FS2, q] = fs2
            work[e, W_MT, q] = ks * polar_u * r4 * twist if bonded else 0.0
            breaks = bonded & (tension | sheared)
            work[e, W_BREAK, q] = (BROKEN_TENSION if tension else BROKEN_SHEAR) if breaks else 0
            work[e, W_FIX, q] = 1.0 if breaks else 0.0
            unbonded += 0 if bonded else 1
            breaking += 1 if breaks else 0
    return unbonded, breaking


@njit(cache=True, error_model="numpy", inline="always")
def _unbonded_elements(start, count, state, elements, unit, tile, work):
    """The unbonded elements of the tile's joints, element by element across the joints (a
    vector loop, as selections): each one's shear force, its own plus the step's increment
    (into the work tile); where the gap is closed or open over the whole element (its joint's
    disk is, or the field's extremes over the element say so: at its corners, or on its outer
    arc where that faces along or against the gradient), its normal force, first moment and
    shear force slipping at μ max(-F_n, 0), plus c_r A once broken in shear (into the work
    tile, the shear force to `elements`). Those partly open are marked for `_unbonded`;
    returns how many."""
    partly_open = 0
    for e in range(state.shape[0]):
        area_u, c1_u, c2_u = unit[AREA, e], unit[C1, e], unit[C2, e]
        r0_u, r1_u = unit[R0, e], unit[R1, e]
        cos0, sin0, cos1, sin1 = unit[COS0, e], unit[SIN0, e], unit[COS1, e], unit[SIN1, e]
        for q in range(uint64(count)):
            p = uint64(start) + q
            code = state[e, p]
            unbonded = code != BONDED
            rb = tile[RB, q]
            r2 = rb * rb
            r3 = r2 * rb
            area = area_u * r2
            m1 = c1_u * r3
            m2 = c2_u * r3
            ks = tile[J_KS, q]
            twist = tile[TWIST, q]
            last1 = elements[E_FS1, e, p]
            last2 = elements[E_FS2, e, p]
            fs1 = last1 + ks * fma(area, tile[DS1, q], -twist * m2)
            fs2 = last2 + ks * fma(area, tile[DS2, q], twist * m1)
            gs, a1, a2 = tile[GS, q], tile[A1, q], tile[A2, q]
            r0 = r0_u * rb
            r1 = r1_u * rb
            along0 = fma(a1, cos0, a2 * sin0)
            along1 = fma(a1, cos1, a2 * sin1)
            high = max(max(along0 * r0, along0 * r1), max(along1 * r0, along1 * r1))
            low = min(min(along0 * r0, along0 * r1), min(along1 * r0, along1 * r1))
            left = fma(cos0, a2, -sin0 * a1)  # e₀ × a
            right = fma(a1, sin1, -a2 * cos1)  # a × e₁
            arc = r1 * tile[GRAD, q]
            high = arc if (left >= 0.0) & (right >= 0.0) else high
            low = -arc if (left <= 0.0) & (right <= 0.0) else low
            whole = tile[WHOLE, q]
            is_open = (whole == OPEN) | ((whole == PARTLY) & (gs + low > 0.0))
            partly = (whole == PARTLY) & (gs + low <= 0.0) & (gs + high > 0.0)
            fn = 0.0 if is_open else work[e, W_FN, q]
            cap = tile[J_FRIC, q] * max(-fn, 0.0)
            cohres = tile[J_COHRES, q]
            cap += cohres * area if (cohres > 0.0) & (code == BROKEN_SHEAR) & ~is_open else 0.0
            size_sq = fs1 * fs1 + fs2 * fs2
            factor = cap / np.sqrt(size_sq) if size_sq > cap * cap else 1.0
            done = unbonded & ~partly
            work[e, W_FS1, q] = (fs1 * factor if done else fs1) if unbonded else work[e, W_FS1, q]
            work[e, W_FS2, q] = (fs2 * factor if done else fs2) if unbonded else work[e, W_FS2, q]
            elements[E_FS1, e, p] = fs1 * factor if done else last1
            elements[E_FS2, e, p] = fs2 * factor if done else last2
            opened = unbonded & is_open
            work[e, W_FN, q] = 0.0 if opened else work[e, W_FN, q]
            work[e, W_S1, q] = 0.0 if opened else work[e, W_S1, q]
            work[e, W_S2, q] = 0.0 if opened else work[e, W_S2, q]
            work[e, W_FIX, q] = 1.0 if unbonded & partly else work[e, W_FIX, q]
            partly_open += 1 if unbonded & partly else 0
    return partly_open


@njit(cache=True, error_model="numpy")
def _unbonded(p, q, e, nal, state, elements, unit, tile, work):
    """Element e of joint p (tile column q), unbonded and partly open, or broken this step (its
    state as bonded in the work tile), into the work tile and its shear force to
    `elements`: compression only over its closed part (open or closed throughout where its
    joint's disk is, or its field's extremes over it say so: at its corners, or on its outer
    arc where that faces along or against the gradient; else `closed_part`), its shear force
    slipping at μ max(-F_n, 0), plus c_r A_c once broken in shear, and no twisting moment of
    its own."""
    rb = tile[RB, q]
    gs, a1, a2 = tile[GS, q], tile[A1, q], tile[A2, q]
    closed = unit[AREA, e] * (rb * rb)
    whole = tile[WHOLE, q]
    if whole == PARTLY:
        r0 = unit[R0, e] * rb
        r1 = unit[R1, e] * rb
        along0 = fma(a1, unit[COS0, e], a2 * unit[SIN0, e])
        along1 = fma(a1, unit[COS1, e], a2 * unit[SIN1, e])
        high = max(max(along0 * r0, along0 * r1), max(along1 * r0, along1 * r1))
        low = min(min(along0 * r0, along0 * r1), min(along1 * r0, along1 * r1))
        left = fma(unit[COS0, e], a2, -unit[SIN0, e] * a1)  # e₀ × a
        right = fma(a1, unit[SIN1, e], -a2 * unit[COS1, e])  # a × e₁
        arc = r1 * tile[GRAD, q]
        if left >= 0.0 and right >= 0.0:
            high = arc
        if left <= 0.0 and right <= 0.0:
            low = -arc
        whole = OPEN if gs + low > 0.0 else (CLOSED if gs + high <= 0.0 else PARTLY)
    if whole == OPEN:
        work[e, W_FN, q] = work[e, W_S1, q] = work[e, W_S2, q] = 0.0
        closed = 0.0
    elif whole == PARTLY:
        f, s1, s2, closed = closed_part(gs, a1, a2, unit[R0, e] * rb, unit[R1, e] * rb,
                                        unit[COS0, e], unit[SIN0, e], unit[COS1, e],
                                        unit[SIN1, e], 2 * np.pi / nal)
        kn = tile[J_KN, q]
        work[e, W_FN, q] = kn * f
        work[e, W_S1, q] = kn * s1
        work[e, W_S2, q] = kn * s2
    cap = tile[J_FRIC, q] * max(-work[e, W_FN, q], 0.0)
    if tile[J_COHRES, q] > 0.0 and state[e, p] == BROKEN_SHEAR:
        cap += tile[J_COHRES, q] * closed
    fs1, fs2 = work[e, W_FS1, q], work[e, W_FS2, q]
    size_sq = fs1 * fs1 + fs2 * fs2
    if size_sq > cap * cap:
        factor = cap / np.sqrt(size_sq)
        fs1 *= factor
        fs2 *= factor
    work[e, W_FS1, q] = elements[E_FS1, e, p] = fs1
    work[e, W_FS2, q] = elements[E_FS2, e, p] = fs2
    work[e, W_MT, q] = 0.0


@njit(cache=True, error_model="numpy", inline="always")
def _breaks_and_partly_open(start, count, nal, state, elements, unit, tile, work):
    """The marked elements: those that break this step (`_elements`: their new state, counted
    per joint) and those unbonded and partly open (`_unbonded_elements`), each worked out as
    unbonded (`_unbonded`)."""
    for e in range(state.shape[0]):
        for q in range(uint64(count)):
            if work[e, W_FIX, q] == 0.0:
                continue
            p = uint64(start) + q
            if work[e, W_BREAK, q] != 0.0:
                state[e, p] = int(work[e, W_BREAK, q])
                tile[BROKE, q] += 1.0
            _unbonded(p, q, e, nal, state, elements, unit, tile, work)


@njit(cache=True, error_model="numpy", inline="always")
def _sums(count, unit, tile, work):
    """The interface's force and moments summed over its elements, in element order, to the
    tile (a vector loop across the joints)."""
    for r in range(SUM_FN, SUM_MT + 1):
        for q in range(uint64(count)):
            tile[r, q] = 0.0
    for e in range(work.shape[0]):
        x1, x2 = unit[X1, e], unit[X2, e]
        for q in range(uint64(count)):
            fs1 = work[e, W_FS1, q]
            fs2 = work[e, W_FS2, q]
            mt = work[e, W_MT, q]
            tile[SUM_FN, q] += work[e, W_FN, q]
            tile[SUM_FS1, q] += fs1
            tile[SUM_FS2, q] += fs2
            tile[SUM_S1, q] += work[e, W_S1, q]
            tile[SUM_S2, q] += work[e, W_S2, q]
            tile[SUM_MT, q] += fma(fma(x1, fs2, -x2 * fs1), tile[RB, q], mt)


@njit(cache=True, error_model="numpy", inline="always")
def _forces(count, tile):
    """The interface's shear force and bending moment S × n as vectors, and the force and
    moments on its spheres, to the tile (a vector loop)."""
    for q in range(uint64(count)):
        n = _row3(tile, NX, q)
        t1 = _row3(tile, T1, q)
        t2 = _row3(tile, T2, q)
        fn, mt = tile[SUM_FN, q], tile[SUM_MT, q]
        fs = axpy(tile[SUM_FS1, q], t1, scale(tile[SUM_FS2, q], t2))
        mb = axpy(tile[SUM_S2, q], t1, scale(-tile[SUM_S1, q], t2))  # t₁ × n = -t₂, t₂ × n = t₁
        moment = axpy(mt, n, mb)
        n_fs = cross(n, fs)
        _put3(tile, OUT_FS, q, fs)
        _put3(tile, OUT_MB, q, mb)
        _put3(tile, OUT_F, q, axpy(fn, n, fs))
        _put3(tile, OUT_MI, q, axpy(tile[ARM_I, q], n_fs, moment))
        _put3(tile, OUT_MJ, q, axpy(tile[ARM_J, q], n_fs, scale(-1.0, moment)))


@njit(cache=True, error_model="numpy", inline="always")
def _scatter(start, count, nr, nal, bodies, pi, pj, state, break_xyz, loads, unit, tile,
             into_rows):
    """Where each element broken this step broke (its centroid), and the tile's forces and
    moments added to the spheres, pair by pair."""
    for q in range(uint64(count)):
        p = uint64(start) + q
        i = uint64(pi[p])
        j = uint64(pj[p])
        if tile[BROKE, q] > 0.0:
            rb = tile[RB, q]
            t1 = _row3(tile, T1, q)
            t2 = _row3(tile, T2, q)
            centre = axpy(tile[ARM_I, q], _row3(tile, NX, q),
                          (bodies[i, Sphere.X], bodies[i, Sphere.Y], bodies[i, Sphere.Z]))
            for e in range(nr * nal):
                k, s = e // nal, e % nal
                if state[e, p] != BONDED and state[e, p] != UNBONDED \
                        and np.isnan(break_xyz[p, k, s, 0]):
                    at = axpy(rb * unit[X1, e], t1, axpy(rb * unit[X2, e], t2, centre))
                    for a in range(3):
                        break_xyz[p, k, s, a] = at[a]
        i, j = pair_rows(p, i, j, into_rows)
        for a in range(3):
            f = tile[OUT_F + a, q]
            loads[i, Load.FX + a] += f
            loads[j, Load.FX + a] -= f
            loads[i, Load.MX + a] += tile[OUT_MI + a, q]
            loads[j, Load.MX + a] += tile[OUT_MJ + a, q]


@njit(cache=True, error_model="numpy")
def add_flatjoint_forces(first, last, bodies, loads, pi, pj, joints, dt, into_rows=-1):
    """Joints first..last-1 between spheres pi[p] and pj[p] (rows of `bodies`), tile by tile:
    their motion over the step (`_motion`, `_bend`), their elements (`_elements`,
    `_unbonded_elements`, then those that break or are partly open,
    `_breaks_and_partly_open`), the interface's force and moments (`_sums`, `_forces`), their
    new state (`_store`), and where each newly broken element broke and their forces and
    moments added to the spheres' `loads` in pair order, or into rows of their own
    (`pair_rows`), as `forces.add_bond_forces` (`_scatter`)."""
    table, state3, elements4, break_xyz = joints
    nr, nal, n = state3.shape
    state = state3.reshape((nr * nal, n))
    elements = elements4.reshape((ELEMENT_ROWS, nr * nal, n))
    unit = unit_table(nr, nal)
    tile = np.empty((TILE_ROWS, TILE))
    work = np.empty((nr * nal, WORK_ROWS, TILE))
    for start in range(first, last, TILE):
        count = min(TILE, last - start)
        _gather(start, count, bodies, pi, pj, tile)
        _gather_radii(start, count, bodies, pi, pj, tile)
        _motion(start, count, table, dt, tile)
        _bend(start, count, table, tile)
        unbonded, marked = _elements(start, count, state, unit, tile, work)
        if unbonded > 0:
            marked += _unbonded_elements(start, count, state, elements, unit, tile, work)
        if marked > 0:
            _breaks_and_partly_open(start, count, nal, state, elements, unit, tile, work)
        _sums(count, unit, tile, work)
        _forces(count, tile)
        _store(start, count, tile, table)
        _scatter(start, count, nr, nal, bodies, pi, pj, state, break_xyz, loads, unit, tile,
                 into_rows)
