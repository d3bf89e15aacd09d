"""PFC3D's linear contact and linear parallel bond between two spheres (Itasca's `linear` and
`linearpbond` contact models, 3D; Potyondy & Cundall 2004). Each law is written once, as
small inline functions over 3-vectors (tuples), and called by every force loop (`forces`).

Per pair (i, j): unit normal n from i to j, overlap of the surfaces (negative: a gap), and the
contact point midway through the gap (or overlap), at lever arms R_i - overlap/2 and
R_j - overlap/2 that add up to the centre distance, so the pair's moments conserve angular
momentum and a rigid-body motion loads nothing. Forces and moments are those on i; j gets the
opposite force, its own lever-arm moment and the opposite bond moment.

Stiffnesses (PFC3D's deformability method):
- linear contact: kn = E_c A / L with A = π min(R_i, R_j)², L = R_i + R_j; ks = kn / (kn/ks);
- parallel bond: R̄ = λ̄ min(R_i, R_j), Ā = π R̄², Ī = π R̄⁴/4, J̄ = π R̄⁴/2, k̄n = Ē_c / L,
  k̄s = k̄n / (k̄n/k̄s); springs k̄n Ā, k̄s Ā (N/m), k̄s J̄ in twist and k̄n Ī in bending (N m/rad).

Parallel bond: normal force (tension positive) k̄n Ā × (gap - gap at installation); shear
force, twisting and bending moments incremental from zero (`bond_force`); it breaks in tension
when σ̄ = F̄n/Ā + β̄ |M̄b| R̄/Ī > σ̄c, else in shear when τ̄ = |F̄s|/Ā + β̄ |M̄t| R̄/J̄ >
c̄ - (F̄n/Ā) tan φ̄ (`bond_breaks`), and from then on carries nothing. Its pair keeps a
linear contact, active while the overlap exceeds the one at installation (PFC's reference
gap), so bonding locks in no force.

Shear force and bending moment are vectors in the contact plane. Each step they are first
rotated with the contact plane, as PFC does: the minimal rotation that takes the last step's
normal to the new one (tilt; the last normal is that of d - Δv dt, exactly the last step's
under central differences), then a turn about the new normal by the pair's mean spin along it
(twist); only then is the step's increment added, the slip taken in the plane of mid-step.
Both rotations are exact (norm-preserving), so a rigid-body rotation turns the forces without
creating any.

Dot and cross products and s a + b are written with fused multiply-adds (`fused.fma`): one
rounding and one instruction where a product and a sum take two, the same bits on every
processor.
"""

from typing import NamedTuple

import numpy as np
from numba import njit

from rockcal.dem3d.fused import fma

INTACT, BROKEN_TENSION, BROKEN_SHEAR = 0, 1, 2
# The contacts' normal stiffness as PFC 5 computes it (the deformability method above): the
# convention a campaign names "pfc5", the 3D engine's only one
CONTACT_STIFFNESS = "pfc5"


class Laws(NamedTuple):
    """The law constants, SI: contact modulus E_c (Pa), ks/kn, friction μ, bond modulus Ē_c
    (Pa), k̄s/k̄n, bond radius multiplier λ̄, tan of the bond friction angle φ̄, moment
    contribution factor β̄."""

    E_c: float
    ks_per_kn: float
    mu: float
    Ebar_c: float
    ksbar_per_knbar: float
    lam: float
    tan_phi: float
    mcf: float


def contact_springs(rmin, length, laws: Laws):
    """A linear contact's kn = E_c π rmin² / L and ks (N/m)."""
    kn = laws.E_c * np.pi * rmin**2 / length
    return kn, kn * laws.ks_per_kn


def bond_springs(rmin, length, laws: Laws):
    """A parallel bond's k̄n Ā, k̄s Ā (N/m), k̄s J̄ (twist) and k̄n Ī (bending) (N m/rad)."""
    rb = laws.lam * rmin
    kbn = laws.Ebar_c / length
    kbs = kbn * laws.ksbar_per_knbar
    area, inertia = np.pi * rb**2, np.pi * (rb * rb) * (rb * rb) / 4
    return kbn * area, kbs * area, kbs * 2 * inertia, kbn * inertia


@njit(cache=True, inline="always")
def dot(a, b):
    return fma(a[0], b[0], fma(a[1], b[1], a[2] * b[2]))


@njit(cache=True, inline="always")
def cross(a, b):
    return (fma(a[1], b[2], -a[2] * b[1]), fma(a[2], b[0], -a[0] * b[2]),
            fma(a[0], b[1], -a[1] * b[0]))


@njit(cache=True, inline="always")
def axpy(s, a, b):
    """s a + b."""
    return (fma(s, a[0], b[0]), fma(s, a[1], b[1]), fma(s, a[2], b[2]))


@njit(cache=True, inline="always")
def scale(s, a):
    return (s * a[0], s * a[1], s * a[2])


@njit(cache=True, error_model="numpy", inline="always")
def pair_geometry(d, ri, rj):
    """Unit normal n from i to j (d = x_j - x_i), 1/|d|, the surfaces' overlap (negative: a
    gap) and the lever arms of the contact point, mid-gap."""
    dist = np.sqrt(dot(d, d))
    inv = 1.0 / dist
    overlap = (ri + rj) - dist
    return scale(inv, d), inv, overlap, ri - 0.5 * overlap, rj - 0.5 * overlap


@njit(cache=True, error_model="numpy", inline="always")
def inverse_length_near(size_sq, inv_near):
    """1 / sqrt(size_sq) for a vector whose length is within a few per mille of 1 / inv_near:
    a series in ε = size_sq inv_near² - 1 and one Newton step, accurate to round-off for
    |ε| < 1e-3 (a pair moves far less than that in a step), and without a square root or a
    division, which the vector loop would wait on."""
    eps = fma(size_sq * inv_near, inv_near, -1.0)
    y = inv_near * fma(-eps, fma(-0.375, eps, 0.5), 1.0)
    return y * fma(-0.5 * size_sq * y, y, 1.5)


@njit(cache=True, error_model="numpy", inline="always")
def past_normals(d, dv, inv_dist, dt):
    """The unit normals of the last step's end and of its middle, from d - Δv dt and
    d - Δv dt/2 (exactly the last step's under central differences); inv_dist = 1/|d|."""
    d_old = axpy(-dt, dv, d)
    d_mid = axpy(-0.5 * dt, dv, d)
    return scale(inverse_length_near(dot(d_old, d_old), inv_dist), d_old), \
        scale(inverse_length_near(dot(d_mid, d_mid), inv_dist), d_mid)


@njit(cache=True, error_model="numpy", inline="always")
def plane_rotation(n_old, n, wi, wj, dt):
    """The rotation of the contact plane over the last step: axis k = n_old × n and
    1 / (1 + n_old·n) for the tilt, (cos, sin) of the twist about n by the mean spin
    (ω_i + ω_j)/2 · n dt; the twist angle ψ is taken as 2 atan(ψ/2) (rational, exactly
    norm-preserving, ψ³/12 off)."""
    k = cross(n_old, n)
    c = dot(n_old, n)
    half = 0.25 * dt * (dot(wi, n) + dot(wj, n))
    inv = 1.0 / fma(half, half, 1.0)
    return k, c, 1.0 / (1.0 + c), fma(-half, half, 1.0) * inv, 2.0 * half * inv


@njit(cache=True, error_model="numpy", inline="always")
def rotate(v, n, k, c, inv_one_plus_c, cos_t, sin_t):
    """A vector of the last contact plane turned into the new one (`plane_rotation`):
    Rodrigues' minimal rotation taking n_old to n, v c + k × v + k (k·v) / (1 + c), then the
    twist about n."""
    kv = cross(k, v)
    s = dot(k, v) * inv_one_plus_c
    t = axpy(c, v, axpy(s, k, kv))
    return axpy(cos_t, t, scale(sin_t, cross(n, t)))


@njit(cache=True, error_model="numpy", inline="always")
def slip(dv, wi, wj, n_mid, n, arm_i, arm_j, dt):
    """The step's shear displacement of j relative to i at the contact point,
    (v_j - v_i - (arm_i ω_i + arm_j ω_j) × n) dt in the plane of the step's middle (normal
    n_mid), then put into the new plane (normal n). Taken at mid-step it is second-order
    accurate: a rigid-body turn by θ per step slips by O(θ³) per step, not O(θ²)."""
    wn = cross(axpy(arm_i, wi, scale(arm_j, wj)), n_mid)
    r = (dv[0] - wn[0], dv[1] - wn[1], dv[2] - wn[2])
    r = axpy(-dot(r, n_mid), n_mid, r)
    return scale(dt, axpy(-dot(r, n), n, r))


@njit(cache=True, error_model="numpy", inline="always")
def contact_force(overlap, kn, shear, ds, laws):
    """A linear contact's normal force on i along n, fn = -kn overlap (pushes i off j), and
    its shear force vector: the rotated last one plus ks ds, scaled back onto the Coulomb
    limit μ kn overlap; both zero when apart."""
    touching = (overlap > 0.0) & (kn > 0.0)
    fs = axpy(kn * laws.ks_per_kn, ds, shear)
    cap = laws.mu * kn * overlap
    size_sq = dot(fs, fs)
    factor = cap / np.sqrt(size_sq) if size_sq > cap * cap else 1.0
    factor = factor if touching else 0.0
    return (-kn * overlap if touching else 0.0), scale(factor, fs)


@njit(cache=True, error_model="numpy", inline="always")
def bond_section(rmin, inv_rmin, laws):
    """The bond's 1 / R̄ (R̄ = λ̄ min(R)) and area Ā = π R̄²; Ī = Ā R̄²/4, J̄ = 2 Ī."""
    rb = laws.lam * rmin
    return inv_rmin * (1.0 / laws.lam), np.pi * rb * rb


@njit(cache=True, error_model="numpy", inline="always")
def bond_force(stretch, last_fs, last_mb, last_mt, ds, dtheta, n, rb, area, inv_length, laws):
    """A parallel bond's normal force (tension positive), shear force vector, bending moment
    vector and twisting moment on i after one step: F̄n = k̄n Ā × (gap - gap at installation)
    (the sum of PFC's increments k̄n Ā Δδn, exact under rigid-body motion), F̄s += k̄s Ā Δδs,
    M̄b += k̄n Ī Δθb, M̄t += k̄s J̄ Δθt, with Δθ = (ω_j - ω_i) dt split along n (twist) and
    across it (bending): the motion of j relative to i drags i along (PFC's -= is for the
    force on the other end). last_fs and last_mb already rotated into the new plane."""
    kbn = laws.Ebar_c * inv_length
    kbs = kbn * laws.ksbar_per_knbar
    inertia = 0.25 * area * rb * rb
    fn = kbn * area * stretch
    fs = axpy(kbs * area, ds, last_fs)
    twist = dot(dtheta, n)
    bend = axpy(-twist, n, dtheta)
    mb = axpy(kbn * inertia, bend, last_mb)
    mt = fma(kbs * 2.0 * inertia, twist, last_mt)
    return fn, fs, mb, mt


@njit(cache=True, error_model="numpy", inline="always")
def bond_breaks(fn, fs, mb, mt, inv_rb, area, ten, coh, laws):
    """Whether a parallel bond breaks in tension, σ̄ = F̄n/Ā + β̄ |M̄b| R̄/Ī > σ̄c, else in
    shear, τ̄ = |F̄s|/Ā + β̄ |M̄t| R̄/J̄ > c̄ - (F̄n/Ā) tan φ̄ (PFC: tension positive, so
    compression raises the shear strength). Compared as forces (× Ā): R̄ Ā/Ī = 4/R̄ and
    R̄ Ā/J̄ = 2/R̄; each as |vector| > rest, that is rest < 0 or |vector|² > rest², without
    a square root."""
    bending = laws.mcf * 4.0 * inv_rb
    rest = ten * area - fn
    tension = (rest < 0.0) | (bending * bending * dot(mb, mb) > rest * rest)
    rest = fma(coh, area, -fn * laws.tan_phi) - laws.mcf * 2.0 * inv_rb * abs(mt)
    shear = ~tension & ((rest < 0.0) | (dot(fs, fs) > rest * rest))
    return tension, shear
