"""The flat-jointed material: PFC's flat joints (the law: `rockcal.dem.flatjoint` in 2D,
`rockcal.dem3d.flat_joint` in 3D) and linear contacts elsewhere. Its parameters with their PFC
names, its genesis step, its assignment on a packed specimen as FISHTank makes it (`ft.fis`:
`_mpAssignFJ`, `_mpAssignFJProps`, `_mpFJrmulReduce`, `_mpFJsetMicroStruc`), its engine state
and its FISHTank parameters.

1. Every grain pair whose gap is <= the installation gap (`fjm_igap`; rockcal's genesis
   `install_gap` x R_min) gets a flat joint; every other grain pair a linear contact of the
   linear-material group (`lnm_emod`, `lnm_krat`, `lnm_fric`), as do contacts that form later.
2. Each flat joint: N_r elements (`fjm_Nr`; in 3D N_r rings of N_α, `fjm_Nal`), radius
   multiplier λ (`fjm_rmulVal`), friction (`fjm_fric`), tensile strength and cohesion drawn per
   joint from normal distributions truncated at zero (`fjm_ten_m/_sd`, `fjm_coh_m/_sd`:
   FISHTank redraws negative values; every element of a joint gets the joint's draw, since
   `fj_ten` and `fj_coh` are properties of the contact in PFC), friction angle (`fjm_fa`), the
   residual cohesion of elements broken in shear (PFC 7+'s `fj_cohres` with `fj_resmode` 1;
   FISHTank has no name for it), and stiffnesses from the effective modulus and stiffness ratio
   (`fjm_emod`, `fjm_krat`): k_n = E*/(R_i + R_j), k_s = k_n/κ*, fixed then.
3. λ is reduced where two flat-joint faces of one grain would overlap (`fjm_rmulCode`): a face
   of joint c seen from the grain's centre spans the half-angle α = atan(R̄_c / l_c), l_c the
   distance from the centre to the contact point (FISHTank subtracts half the initial gap,
   which is still 0 at this point); two faces overlap when α_1 + α_2 > β, the angle between
   their contact directions (disks or spheres alike). Code 0 keeps λ; code 1 visits the grains
   in turn and, for each pair of its joints that overlap, multiplies both joints' λ by 0.99
   until they do not; code 2 multiplies the one λ of all joints by 0.99 until no pair overlaps.
4. The microstructure: of the n flat joints, round(B n) are bonded (every element bonded, g_0 =
   0), round(G n) gapped (unbonded, g_0 drawn from a normal distribution of mean `fjm_G_m` and
   sd `fjm_G_sd` truncated at zero) and the rest slit (unbonded, g_0 = 0). FISHTank takes them
   in the order of PFC's contact list; rockcal ranks the joints by a uniform draw of each
   (seeded), so the fractions are met exactly (to rounding), the choice is reproducible, and a
   joint keeps its rank whatever the fractions.

Every random quantity comes from uniform draws per joint (`flatjoint_draws`; a 3D specimen's
seeded by its bonds' draws, `joint_draws_3d`): strengths and gaps are truncated-normal at them
(`strengths.truncated_normal`, as the parallel bond's), so one specimen and seed serve every
parameter set.
"""

from __future__ import annotations

import hashlib
import logging
import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numba import njit
from pydantic import BaseModel, ConfigDict, Field, model_validator

from rockcal.dem import flatjoint, laws, simulate
from rockcal.dem.neighbours import install_bonds
from rockcal.errors import InputError
from rockcal.materials.fishtank import FLAT_JOINTED, common_pfc, pfc_names, pfc_values
from rockcal.materials.material import MAX_DAMPING, MIN_DENSITY, MIN_STIFFNESS_RATIO, Material, validated
from rockcal.materials.strengths import truncated_normal
from rockcal.materials.units import GPa, MM, MPa

logger = logging.getLogger(__name__)
FLATJOINT_STREAM = 2  # the flat joints' random stream (the parallel bonds' strengths use 1)
TYPE, TEN, COH, GAP = range(4)  # columns of the draws: rank for the microstructure, strengths, gap
DRAWS_PER_JOINT = 4
# a flat joint's initial microstructural type, coded as PFC's fj_mtype (FISHTank's counts read
# 1 as bonded, 2 as gapped, 3 as slit)
BONDED, GAPPED, SLIT = 1, 2, 3
REDUCTION = 0.99  # FISHTank's factor on λ per overlap check
FRACTION_TOLERANCE = 1e-9
CODE = {"code": True}  # marks a whole-number parameter that picks a rule rather than counts


class FlatJointParams(BaseModel):
    """The flat-jointed material's parameters: the flat joints' (PFC's `fj_*` contact
    properties, the material's `fjm_*` distributions) and the linear contacts' (`lnm_*`), in
    rockcal's units: GPa, MPa, degrees, mm."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    fj_emod: float = Field(21.65, gt=0, le=1e4, description="flat-joint effective modulus E*, GPa (fjm_emod)")
    fj_kratio: float = Field(1.9, ge=MIN_STIFFNESS_RATIO, le=1e3, description="flat-joint stiffness ratio k_n/k_s (fjm_krat)")
    fj_ten: float = Field(36.55, ge=0, le=1e5, description="element tensile strength (mean), MPa (fjm_ten_m)")
    fj_ten_sd: float = Field(0.0, ge=0, le=1e5, description="tensile strength sd, MPa (fjm_ten_sd)")
    fj_ten_cv: float = Field(0.0, ge=0, le=10, description="tensile strength sd / mean")
    fj_coh: float = Field(90.0, ge=0, le=1e5, description="element cohesion (mean), MPa (fjm_coh_m)")
    fj_coh_sd: float = Field(0.0, ge=0, le=1e5, description="cohesion sd, MPa (fjm_coh_sd)")
    fj_coh_cv: float = Field(0.0, ge=0, le=10, description="cohesion sd / mean")
    fj_fa: float = Field(0.0, ge=0, lt=90, description="element friction angle, degrees (fjm_fa)")
    # PFC 7+'s residual strength; left out of `key()` at their defaults, so runs stored before
    # them keep their keys
    fj_cohres: float = Field(0.0, ge=0, le=1e5, exclude_if=lambda v: v == 0,
                             description="residual cohesion of an element broken in shear, MPa "
                                         "(fj_cohres; acts with fj_resmode 1)")
    fj_resmode: int = Field(0, ge=0, le=1, exclude_if=lambda v: v == 0, json_schema_extra=CODE,
                            description="residual mode: 0 an element broken in shear keeps friction, "
                                        "1 friction and fj_cohres (fj_resmode)")
    fj_fric: float = Field(0.5, ge=0, le=10, description="element friction coefficient (fjm_fric)")
    fj_nr: int = Field(2, ge=1, le=64,
                       description="elements per flat joint in 2D, rings of elements in 3D (fjm_Nr)")
    # left out of `key()` at its default, so runs stored before it keep their keys
    fj_nal: int = Field(4, ge=3, le=64, exclude_if=lambda v: v == 4,
                        description="elements per ring in 3D, circumferential (fjm_Nal; PFC2D has none)")
    fj_rmul: float = Field(1.0, ge=0.1, le=10, description="radius multiplier λ, starting value (fjm_rmulVal)")
    fjm_rmulCode: int = Field(0, ge=0, le=2, json_schema_extra=CODE,
                              description="λ reduction: 0 none, 1 per joint, 2 uniform")
    fjm_B_frac: float = Field(1.0, ge=0, le=1, description="bonded fraction of the flat joints")
    fjm_G_frac: float = Field(0.0, ge=0, le=1, description="gapped fraction (slit: the rest)")
    fjm_G_m: float = Field(0.0, ge=0, le=1e3, description="initial gap of gapped joints (mean), mm")
    fjm_G_sd: float = Field(0.0, ge=0, le=1e3, description="initial gap sd, mm")
    lnm_emod: float | None = Field(None, ge=0, le=1e4, description="linear contacts' effective modulus, GPa (default fj_emod)")
    lnm_krat: float | None = Field(None, ge=MIN_STIFFNESS_RATIO, le=1e3, description="linear contacts' stiffness ratio (default fj_kratio)")
    lnm_fric: float | None = Field(None, ge=0, le=10, description="linear contacts' friction (default fj_fric)")
    density: float = Field(2622.0, ge=MIN_DENSITY, le=1e5, description="grain density, kg/m³")
    damping: float = Field(0.7, ge=0, le=MAX_DAMPING, description="local damping coefficient")

    @model_validator(mode="after")
    def _check(self):
        for name, default in (("lnm_emod", "fj_emod"), ("lnm_krat", "fj_kratio"),
                              ("lnm_fric", "fj_fric")):
            if getattr(self, name) is None:
                object.__setattr__(self, name, getattr(self, default))
        slit = 1.0 - self.fjm_B_frac - self.fjm_G_frac
        if slit < -FRACTION_TOLERANCE:
            raise ValueError(f"fjm_G_frac: fjm_B_frac + fjm_G_frac = "
                             f"{self.fjm_B_frac + self.fjm_G_frac:g} exceeds 1 (the slit "
                             "fraction is what they leave)")
        for name in ("fj_ten", "fj_coh"):
            if getattr(self, name + "_sd") and getattr(self, name + "_cv"):
                raise ValueError(f"{name}_cv: set {name}_sd or {name}_cv, not both")
        if self.fj_cohres and self.fj_resmode == 0:
            raise ValueError(f"fj_cohres: {self.fj_cohres:g} MPa acts only with fj_resmode = 1 "
                             "(mode 0 keeps no residual cohesion); set fj_resmode = 1 or fj_cohres = 0")
        return self

    def key(self) -> dict[str, float]:
        """All values by name (for storage and reports)."""
        return self.model_dump()

    CONTACT_MODULUS: ClassVar[str] = "lnm_emod"  # the linear contacts' modulus (GPa), by name

    @property
    def bonded_modulus_GPa(self) -> float:
        """A bonded pair's modulus in compression, λ E* (the flat joint replaces the contact):
        an estimate of the rock's, for its wave speed."""
        return self.fj_rmul * self.fj_emod

    @property
    def slit_fraction(self) -> float:
        """1 - fjm_B_frac - fjm_G_frac (FISHTank's fjm_S_frac), 0 within rounding."""
        slit = 1.0 - self.fjm_B_frac - self.fjm_G_frac
        return slit if slit > FRACTION_TOLERANCE else 0.0

    @property
    def strength_sds(self) -> tuple[float, float]:
        """The sd (MPa) of the tensile strength and cohesion (fjm_ten_sd, fjm_coh_sd)."""
        return (self.fj_ten_sd or self.fj_ten_cv * self.fj_ten,
                self.fj_coh_sd or self.fj_coh_cv * self.fj_coh)


NAMES = tuple(FlatJointParams.model_fields)

# FISHTank's flat-jointed material group, in its order: PFC property -> (rockcal name, unit):
# fjm_igap is the installation gap as a length, fjm_Nr the elements per joint (2D) or rings (3D),
# fjm_Nal the elements per ring (3D only: FISHTank sets it in PFC3D alone), fjm_rmulVal λ
PFC_PROPERTIES = {
    "fjm_igap": ("install_gap_mm", "mm"), "fjm_B_frac": ("fjm_B_frac", None),
    "fjm_G_frac": ("fjm_G_frac", None), "fjm_G_m": ("fjm_G_m", "mm"), "fjm_G_sd": ("fjm_G_sd", "mm"),
    "fjm_Nr": ("fj_nr", None), "fjm_Nal": ("fj_nal", None), "fjm_rmulCode": ("fjm_rmulCode", None),
    "fjm_rmulVal": ("fj_rmul", None),
    "fjm_emod": ("fj_emod", "GPa"), "fjm_krat": ("fj_kratio", None), "fjm_fric": ("fj_fric", None),
    "fjm_ten_m": ("fj_ten", "MPa"), "fjm_ten_sd": ("fj_ten_sd", "MPa"), "fjm_coh_m": ("fj_coh", "MPa"),
    "fjm_coh_sd": ("fj_coh_sd", "MPa"), "fjm_fa": ("fj_fa", None),
    "fjm_trackMS": ("track_microstructure", None),
    "lnm_emod": ("lnm_emod", "GPa"), "lnm_krat": ("lnm_krat", None), "lnm_fric": ("lnm_fric", None),
}


def make_flatjoint_params(values: dict[str, float]) -> FlatJointParams:
    """Validate a mapping of names to values; any mistake raises InputError naming the field."""
    return validated(FlatJointParams, NAMES, values, "flat-jointed material parameter")


def flatjoint_draws(n_joints: int, seed: int) -> np.ndarray:
    """Uniform draws (n_joints x DRAWS_PER_JOINT) for the joints of a specimen, in the order of
    its flat-joint pairs: one stream per seed, apart from the packing's and the bonds'."""
    return np.random.default_rng([int(seed), FLATJOINT_STREAM]).random((n_joints, DRAWS_PER_JOINT))


@njit(cache=True)
def _faces_overlap(rbar1, l1, rbar2, l2, beta):
    return math.atan2(rbar1, l1) + math.atan2(rbar2, l2) - beta > 0.0


@njit(cache=True, inline="always")
def _angle_between(v1, v2):
    """The angle between two vectors (2 or 3 components), from their cross and dot products."""
    if v1.shape[0] == 2:
        across = abs(v1[0] * v2[1] - v1[1] * v2[0])
    else:
        c0 = v1[1] * v2[2] - v1[2] * v2[1]
        c1 = v1[2] * v2[0] - v1[0] * v2[2]
        c2 = v1[0] * v2[1] - v1[1] * v2[0]
        across = math.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
    return math.atan2(across, np.sum(v1 * v2))


@njit(cache=True)
def _reduce_rmul(pos, radius, pi, pj, rmul, code):
    """FISHTank's _mpFJrmulReduce on joints (pi, pj) in place: grains in index order, each
    grain's joints in pair order; disks (pos: n x 2) or spheres (n x 3). Returns the number of
    reductions."""
    n = pos.shape[0]
    m = pi.shape[0]
    counts = np.zeros(n + 1, np.int64)
    for c in range(m):
        counts[pi[c] + 1] += 1
        counts[pj[c] + 1] += 1
    start = np.cumsum(counts)
    fill = start[:-1].copy()
    members = np.empty(2 * m, np.int64)
    for c in range(m):
        members[fill[pi[c]]] = c
        fill[pi[c]] += 1
        members[fill[pj[c]]] = c
        fill[pj[c]] += 1
    # each joint's contact point (mid-gap) and the smaller radius of its grains
    point = np.empty((m, pos.shape[1]))
    rmin = np.empty(m)
    for c in range(m):
        i = pi[c]
        j = pj[c]
        d = pos[j] - pos[i]
        dist = math.sqrt(np.sum(d * d))
        arm = radius[i] + 0.5 * (dist - radius[i] - radius[j])
        point[c] = pos[i] + d / dist * arm
        rmin[c] = min(radius[i], radius[j])
    reductions = 0
    for b in range(n):
        for a1 in range(start[b], start[b + 1]):
            c1 = members[a1]
            v1 = point[c1] - pos[b]
            l1 = math.sqrt(np.sum(v1 * v1))
            for a2 in range(a1 + 1, start[b + 1]):
                c2 = members[a2]
                v2 = point[c2] - pos[b]
                l2 = math.sqrt(np.sum(v2 * v2))
                beta = _angle_between(v1, v2)
                while (_faces_overlap(rmul[c1] * rmin[c1], l1, rmul[c2] * rmin[c2], l2, beta)
                       and rmul[c1] > 1e-12 and rmul[c2] > 1e-12):
                    reductions += 1
                    if code == 1:
                        rmul[c1] *= REDUCTION
                        rmul[c2] *= REDUCTION
                    else:  # one λ for all
                        value = rmul[c1] * REDUCTION
                        for c in range(m):
                            rmul[c] = value
    return reductions


def reduce_radius_multipliers(pos, radius, pairs, rmul, code: int) -> np.ndarray:
    """The joints' radius multipliers after FISHTank's reduction of overlapping faces (code 0:
    unchanged; 1: per joint; 2: one for all; see the module docstring)."""
    rmul = np.array(rmul, float)
    if code == 0 or len(pairs) == 0:
        return rmul
    pairs = np.asarray(pairs, np.int64).reshape(-1, 2)
    _reduce_rmul(np.ascontiguousarray(pos, float), np.asarray(radius, float),
                 np.ascontiguousarray(pairs[:, 0]), np.ascontiguousarray(pairs[:, 1]), rmul, int(code))
    return rmul


def faces_overlap(pos, radius, pairs, rmul) -> np.ndarray:
    """For each grain, whether two of its flat-joint faces overlap (FISHTank's test)."""
    pos = np.asarray(pos, float)
    pairs = np.asarray(pairs, np.int64).reshape(-1, 2)
    i, j = pairs[:, 0], pairs[:, 1]
    d = pos[j] - pos[i]
    dist = np.hypot(*d.T)
    arm = radius[i] + 0.5 * (dist - radius[i] - radius[j])
    point = pos[i] + d / dist[:, None] * arm[:, None]
    rbar = np.asarray(rmul) * np.minimum(radius[i], radius[j])
    out = np.zeros(len(radius), bool)
    for b in range(len(radius)):
        cs = np.flatnonzero((i == b) | (j == b))
        v = point[cs] - pos[b]
        alpha = np.arctan2(rbar[cs], np.hypot(*v.T))
        for a in range(len(cs)):
            for c in range(a + 1, len(cs)):
                beta = np.arctan2(abs(v[a, 0] * v[c, 1] - v[a, 1] * v[c, 0]),
                                  v[a, 0] * v[c, 0] + v[a, 1] * v[c, 1])
                out[b] |= alpha[a] + alpha[c] - beta > 1e-12
    return out


@dataclass(frozen=True)
class FlatJointedMaterial:
    """A flat-jointed material on a specimen: its flat joints (pairs i < j) with their
    properties, SI, and the linear contacts' constants for every other grain pair."""

    pairs: np.ndarray  # (n, 2)
    kind: np.ndarray  # (n,) BONDED, GAPPED or SLIT (PFC's fj_mtype)
    gap0: np.ndarray  # (n,) initial surface gap, m
    rmul: np.ndarray  # (n,) radius multiplier after reduction
    kn: np.ndarray  # (n,) element normal stiffness per area, Pa/m
    ks: np.ndarray  # (n,) Pa/m
    ten: np.ndarray  # (n, N_r) element tensile strength, Pa
    coh: np.ndarray  # (n, N_r) element cohesion, Pa
    fric: float
    tan_fa: float
    lnm_emod: float  # Pa
    lnm_krat: float
    lnm_fric: float
    cohres: float = 0.0  # residual cohesion of elements broken in shear, Pa (0: none)

    @property
    def nr(self) -> int:
        return self.ten.shape[1]

    def fractions(self) -> dict[str, float]:
        """Realised bonded, gapped and slit fractions of the flat joints."""
        n = max(1, len(self.kind))
        return {name: float(np.count_nonzero(self.kind == code)) / n
                for name, code in (("bonded", BONDED), ("gapped", GAPPED), ("slit", SLIT))}

    def joints(self) -> flatjoint.FlatJoints:
        """The flat joints' initial law state (`rockcal.dem.flatjoint`)."""
        return flatjoint.new_flatjoints(self.nr, self.kn, self.ks, self.rmul, self.fric,
                                        self.tan_fa, self.gap0, self.kind == BONDED, self.ten,
                                        self.coh, self.cohres)


def assign_flatjointed(pos, radius, params: FlatJointParams, install_gap: float,
                       draws: np.ndarray | None = None, seed: int = 1) -> FlatJointedMaterial:
    """FISHTank's flat-jointed material on grains at `pos` with `radius` (m): flat joints at the
    pairs whose gap is <= `install_gap` (m), their properties from `params` and the uniform
    `draws` of each joint (`flatjoint_draws`; by default those of `seed`)."""
    pos = np.asarray(pos, float)
    radius = np.asarray(radius, float)
    pairs = install_bonds(pos, radius, install_gap) if len(radius) > 1 else np.empty((0, 2), np.int64)
    return flatjointed(pos, radius, pairs, params, draws, seed)


def flatjointed(pos, radius, pairs, params: FlatJointParams, draws: np.ndarray | None = None,
                seed: int = 1) -> FlatJointedMaterial:
    """The flat-jointed material with flat joints at `pairs` (i < j; a specimen's bonded pairs,
    in their order), as `assign_flatjointed`."""
    pos = np.asarray(pos, float)
    radius = np.asarray(radius, float)
    pairs = np.asarray(pairs, np.int64).reshape(-1, 2)
    n = len(pairs)
    u = flatjoint_draws(n, seed) if draws is None else np.asarray(draws, float).reshape(n, DRAWS_PER_JOINT)
    i, j = pairs[:, 0], pairs[:, 1]
    kn = params.fj_emod * GPa / (radius[i] + radius[j])
    rmul = reduce_radius_multipliers(pos, radius, pairs, np.full(n, params.fj_rmul),
                                     params.fjm_rmulCode)
    n_bonded = min(n, int(math.floor(params.fjm_B_frac * n + 0.5)))
    n_gapped = min(n - n_bonded, int(math.floor(params.fjm_G_frac * n + 0.5)))
    rank = np.empty(n, np.int64)
    rank[np.argsort(u[:, TYPE], kind="stable")] = np.arange(n)
    kind = np.where(rank < n_bonded, BONDED, np.where(rank < n_bonded + n_gapped, GAPPED, SLIT))
    gap0 = np.where(kind == GAPPED, truncated_normal(params.fjm_G_m, params.fjm_G_sd, u[:, GAP]),
                    0.0) * MM
    ten_sd, coh_sd = params.strength_sds
    per_joint = (n, params.fj_nr)
    ten = np.broadcast_to(truncated_normal(params.fj_ten, ten_sd, u[:, TEN])[:, None] * MPa, per_joint)
    coh = np.broadcast_to(truncated_normal(params.fj_coh, coh_sd, u[:, COH])[:, None] * MPa, per_joint)
    return FlatJointedMaterial(
        pairs=pairs, kind=kind.astype(np.int8), gap0=gap0, rmul=rmul, kn=kn,
        ks=kn / params.fj_kratio, ten=np.ascontiguousarray(ten), coh=np.ascontiguousarray(coh),
        fric=params.fj_fric, tan_fa=math.tan(math.radians(params.fj_fa)),
        lnm_emod=params.lnm_emod * GPa, lnm_krat=params.lnm_krat, lnm_fric=params.lnm_fric,
        cohres=params.fj_cohres * MPa if params.fj_resmode == 1 else 0.0)


def linear_contacts(params: FlatJointParams) -> laws.Laws:
    """The engine's constants of the linear contacts (`lnm_*`; PFC 5's deformability method,
    kn = 2 min(R) t E* / (R_i + R_j), as FISHTank's `linear` contacts)."""
    return laws.Laws(params.lnm_emod * GPa, 1.0 / params.lnm_krat, params.lnm_fric, 0.0, 1.0,
                     1.0, 0.0, 1.0, False)


def new_state(pos, radius, pairs, params: FlatJointParams, *, joint_draws=None,
              **options) -> simulate.State:
    """An engine state at rest with flat joints at `pairs` (i < j) and linear contacts
    elsewhere (`linear_contacts`); joint_draws: each joint's uniform draws (`flatjoint_draws`,
    in the order of `pairs`; None: those of seed 1). Walls have the flat joints' modulus
    (normal stiffness 2 t E*). Other options as `simulate.assemble_state`."""
    def joints(pos, radius, nlist, order):
        material = flatjointed(pos, radius, pairs, params, joint_draws)
        return material.joints().taken(order)

    return simulate.assemble_state(pos, radius, pairs, params.density, params.damping,
                                   linear_contacts(params), params.fj_emod * GPa, joints, **options)


def pfc_parameters(params: FlatJointParams, specimen,
                   fishtank: int | None = None) -> dict[str, float | int | bool | str]:
    """FISHTank's flat-jointed material parameters (SI) of a rockcal material for the FISHTank
    of PFC `fishtank` (its cm_matType; None: the default's): the common groups and
    `PFC_PROPERTIES`, the strengths' sd as PFC takes them (`strength_sds`), the microstructure
    not tracked."""
    if params.fj_resmode == 1 and params.fj_cohres > 0:
        logger.warning("fj_cohres %g MPa: FISHTank has no name for the residual cohesion; after the genesis "
                       "set the flat joints' fj_cohres and fj_resmode 1 in PFC 7+", params.fj_cohres)
    ten_sd, coh_sd = params.strength_sds
    values = params.key() | {"fj_nal": params.fj_nal, "fj_ten_sd": ten_sd, "fj_coh_sd": coh_sd,
                             "track_microstructure": False,
                             "install_gap_mm": specimen.install_gap * specimen.rmin_mm}
    properties = {pfc: name for pfc, name in PFC_PROPERTIES.items()
                  if pfc != "fjm_Nal" or getattr(specimen, "dimensions", 2) == 3}
    return common_pfc(params, specimen, "flat-jointed", fishtank) | pfc_values(properties, values)


def pair_properties(params: FlatJointParams, specimen) -> dict:
    """Each flat joint's type (PFC's fj_mtype: 1 bonded, 2 gapped, 3 slit), initial gap, radius
    multiplier (after FISHTank's reduction) and strengths."""
    m = flatjointed(specimen.pos, specimen.radius, specimen.bonds, params, specimen.joint_draws)
    return {"type": m.kind, "initial_gap_m": m.gap0, "radius_multiplier": m.rmul,
            "tensile_strength_Pa": m.ten[:, 0], "cohesion_Pa": m.coh[:, 0]}


def _specimen_state(pos, radius, specimen, params, *, contact_stiffness=None, **options):
    """The material's state on `specimen`; its linear contacts are PFC 5's whatever
    `contact_stiffness` says (a parallel-bonded setting)."""
    return new_state(pos, radius, specimen.bonds, params, joint_draws=specimen.joint_draws, **options)


def joint_draws_3d(specimen) -> np.ndarray:
    """Each flat joint's uniform draws on a 3D specimen (`flatjoint_draws`), seeded by its
    bonds' own draws, so a specimen always gets the same joints."""
    digest = hashlib.sha256(np.ascontiguousarray(specimen.bond_draws, float).tobytes()).digest()
    return flatjoint_draws(len(specimen.bonds), int.from_bytes(digest[:4], "little"))


def new_state_3d(pos, radius, specimen, params: FlatJointParams, *, walls=((), ()), driven=None):
    """A 3D specimen at rest in the material: PFC3D's flat joints at its bonded pairs
    (`rockcal.dem3d.flat_joint`; `fj_nr` rings of `fj_nal` sectors), PFC3D's linear contacts
    (`lnm_*`) elsewhere, between planar `walls` (points, inward normals) of the flat joints'
    modulus; the `driven` spheres (a mask or indices: a rig's) keep the velocity they are given."""
    from rockcal.dem3d import flat_joint as joints_3d  # the 3D engine: loaded for a 3D run alone
    from rockcal.dem3d.laws import Laws
    from rockcal.dem3d.simulate import assemble_state as assemble_3d
    from rockcal.dem3d.vectors import norms
    from rockcal.dem3d.walls import new_walls

    material = flatjointed(pos, radius, specimen.bonds, params, joint_draws_3d(specimen))

    def joints(pos, radius, pi, pj, order):
        d = pos[pj] - pos[pi]
        dist = norms(d)
        m = material
        return joints_3d.new_flatjoints_3d(
            params.fj_nr, params.fj_nal, d / dist[:, None], radius[pi] + radius[pj] - dist,
            m.kn[order], m.ks[order], m.rmul[order], m.fric, m.tan_fa, m.gap0[order],
            m.kind[order] == BONDED, m.ten[order, 0], m.coh[order, 0], m.cohres)

    linear = Laws(E_c=params.lnm_emod * GPa, ks_per_kn=1.0 / params.lnm_krat, mu=params.lnm_fric,
                  Ebar_c=0.0, ksbar_per_knbar=1.0, lam=1.0, tan_phi=0.0, mcf=1.0)
    points, normals = walls
    return assemble_3d(pos, radius, specimen.bonds, params.density, linear, damping=params.damping,
                       walls=new_walls(points, normals, params.fj_emod * GPa), joints=joints, driven=driven)


def check_bonded(params: FlatJointParams) -> None:
    """Some flat joints are bonded and their elements have a strength: with fjm_B_frac = 0
    every joint is slit or gapped (unbonded), with fj_ten = fj_coh = 0 every bonded element
    breaks at the first load; either way the specimen has no bonded element and is no rock.
    And gapped joints have a gap: with fjm_G_m = fjm_G_sd = 0 they would be slit ones."""
    if params.fjm_B_frac == 0:
        unbonded = "slit" if params.fjm_G_frac == 0 else "slit or gapped"
        raise InputError("fjm_B_frac", f"0 leaves every flat joint {unbonded} (unbonded): the specimen has "
                                       "no bonded element and is no rock; give fjm_B_frac > 0")
    if params.fj_ten == 0 and params.fj_coh == 0:
        raise InputError("fj_coh", "fj_ten and fj_coh both 0 leave the bonded elements without strength: "
                                   "they break at the first load and the specimen is no rock; give either > 0")
    if params.fjm_G_frac > 0 and params.fjm_G_m == 0 and params.fjm_G_sd == 0:
        raise InputError("fjm_G_frac", f"fjm_G_frac = {params.fjm_G_frac:g} asks for gapped joints but their initial "
                                       "gap is 0 (fjm_G_m = fjm_G_sd = 0: they would be slit joints); "
                                       "give fjm_G_m > 0, mm")


MATERIAL = Material(
    name="flatjoint", title="flat-jointed (flat joints + linear contacts)",
    parameters=NAMES, make=make_flatjoint_params, params_type=FlatJointParams,
    pfc_names=pfc_names(PFC_PROPERTIES, NAMES),
    states={2: _specimen_state, 3: new_state_3d},
    pfc_parameters=pfc_parameters, pfc_material_type=FLAT_JOINTED,
    pfc_group="mpSetFJParams", pair_properties=pair_properties, pairs_word="flat joints",
    breaks_word="elements", check_rock=check_bonded,
    # 2D: a step costs 1.4 x a parallel bond's (each joint sums its elements), and joints that
    # break element by element take more steps to the peak. 3D: a sphere-step 5-8 x (a slit
    # joint's partly open elements are worked out one by one) and 2-3 x the steps at the Lac du
    # Bonnet point: its Ø10 x 20 mm cylinder's UCS run 16.7 and 16.1 x the 3D granite point's at
    # R_min 0.5 and 0.75 mm (`NUMBA_NUM_THREADS=1 python benchmarks/plan_3d.py STORE
    # --parallel-bond` on a store of docs/campaigns/ldb-3d.toml's runs)
    slower_than_parallel_bond=((2, 2.0), (3, 16.0)))
