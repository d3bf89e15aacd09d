"""The parallel-bonded material: PFC2D's linear contact + linear parallel bond (Potyondy &
Cundall 2004). Its micro-parameters with their PFC names, its genesis step, its engine state
(the law: `rockcal.dem.laws`) and its FISHTank parameters.

Names follow PFC2D: E_c and kn_ks for the linear contact; Ebar_c, knbar_ksbar, lambda, sigma_c,
tau_c for the parallel bond, and PFC 5's bond options: per-bond normal spreads sigma_c_sd,
tau_c_sd (pb_ten, pb_coh sd; or sigma_c_cv, tau_c_cv, the sd as a fraction of the mean, which
Potyondy & Cundall quote and which stays meaningful while a calibration moves the mean),
friction angle phi_b (pb_fa; shear strength tau_c - sigma tan phi_b) and moment contribution
factor mcf (pb_mcf); their defaults give Potyondy & Cundall's constant-strength bond.
Defaults are the source study's identified granite values (E_c 21.65 GPa, kn/ks 1.9,
sigma_c 36.55 MPa) and its fixed ones (tau_c 90 MPa, mu 0.5, lambda 1).
"""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, model_validator

from rockcal.dem import laws
from rockcal.dem.simulate import CONTACT_STIFFNESS, DEFAULT_CONTACT_STIFFNESS, State, assemble_state
from rockcal.errors import InputError
from rockcal.materials.fishtank import PARALLEL_BONDED, common_pfc, pfc_names, pfc_values
from rockcal.materials.material import MAX_DAMPING, MIN_DENSITY, MIN_STIFFNESS_RATIO, Material, validated
from rockcal.materials.strengths import truncated_normal
from rockcal.materials.units import GPa, MPa


class MicroParams(BaseModel):
    """BPM micro-parameters (GPa, MPa, kg/m³; others dimensionless)."""

    model_config = ConfigDict(extra="forbid", frozen=True, populate_by_name=True)

    E_c: float = Field(21.65, ge=0, le=1e4, description="contact effective modulus, GPa (0 = bonds only)")
    Ebar_c: float | None = Field(None, ge=0, le=1e4, description="bond effective modulus, GPa (default E_c)")
    kn_ks: float = Field(1.9, ge=MIN_STIFFNESS_RATIO, le=1e3, description="contact normal-to-shear stiffness ratio")
    knbar_ksbar: float | None = Field(None, ge=MIN_STIFFNESS_RATIO, le=1e3, description="bond stiffness ratio (default kn_ks)")
    sigma_c: float = Field(36.55, gt=0, le=1e5, description="bond tensile strength (mean), MPa")
    tau_c: float = Field(90.0, gt=0, le=1e5, description="bond cohesion (mean shear strength), MPa")
    sigma_c_sd: float = Field(0.0, ge=0, le=1e5, description="bond tensile strength sd, MPa")
    tau_c_sd: float = Field(0.0, ge=0, le=1e5, description="bond cohesion sd, MPa")
    sigma_c_cv: float = Field(0.0, ge=0, le=10, description="bond tensile strength sd / mean")
    tau_c_cv: float = Field(0.0, ge=0, le=10, description="bond cohesion sd / mean")
    phi_b: float = Field(0.0, ge=0, lt=90, description="bond friction angle, degrees")
    mcf: float = Field(1.0, ge=0, le=1, description="bond moment contribution factor")
    mu: float = Field(0.5, ge=0, le=10, description="contact friction coefficient")
    lambda_: float = Field(1.0, gt=0, le=1, alias="lambda", description="bond radius multiplier")
    density: float = Field(2622.0, ge=MIN_DENSITY, le=1e5, description="particle density, kg/m³")
    damping: float = Field(0.7, ge=0, le=MAX_DAMPING, description="local damping coefficient")

    @model_validator(mode="after")
    def _fill_bond_defaults(self):
        if self.Ebar_c is None:
            object.__setattr__(self, "Ebar_c", self.E_c)
        if self.knbar_ksbar is None:
            object.__setattr__(self, "knbar_ksbar", self.kn_ks)
        if self.E_c == 0 and self.Ebar_c == 0:
            raise ValueError("E_c and Ebar_c cannot both be 0")
        for name in ("sigma_c", "tau_c"):
            if getattr(self, name + "_sd") and getattr(self, name + "_cv"):
                raise ValueError(f"{name}_cv: set {name}_sd or {name}_cv, not both")
        return self

    @property
    def strength_sds(self) -> tuple[float, float]:
        """The sd (MPa) of the bond tensile strength and cohesion: PFC's pb_ten, pb_coh sd."""
        return (self.sigma_c_sd or self.sigma_c_cv * self.sigma_c,
                self.tau_c_sd or self.tau_c_cv * self.tau_c)

    def key(self) -> dict[str, float]:
        """All values by their user names (for storage and reports)."""
        return self.model_dump(by_alias=True)

    CONTACT_MODULUS: ClassVar[str] = "E_c"  # the linear contacts' modulus (GPa), by name

    @property
    def bonded_modulus_GPa(self) -> float:
        """A bonded pair's modulus, contact and parallel bond side by side, E_c + λ Ē_c: an
        estimate of the rock's, for its wave speed."""
        return self.E_c + self.lambda_ * self.Ebar_c


NAMES = tuple(MicroParams.model_fields[f].alias or f for f in MicroParams.model_fields)

# FISHTank's parallel-bonded material group, in its order: PFC property -> (rockcal name, unit).
# PFC's 2D disks have unit thickness, as rockcal's; pbm_igap is the installation gap as a
# length; the linear material group (lnm_*, the contacts that form later) is the bonded
# contacts' linear part, as in FISHTank's own parallel-bonded files.
PFC_PROPERTIES = {
    "pbm_emod": ("E_c", "GPa"), "pbm_krat": ("kn_ks", None), "pbm_fric": ("mu", None),
    "pbm_igap": ("install_gap_mm", "mm"), "pbm_rmul": ("lambda", None),
    "pbm_bemod": ("Ebar_c", "GPa"), "pbm_bkrat": ("knbar_ksbar", None), "pbm_mcf": ("mcf", None),
    "pbm_ten_m": ("sigma_c", "MPa"), "pbm_ten_sd": ("sigma_c_sd", "MPa"),
    "pbm_coh_m": ("tau_c", "MPa"), "pbm_coh_sd": ("tau_c_sd", "MPa"), "pbm_fa": ("phi_b", None),
    "lnm_emod": ("E_c", "GPa"), "lnm_krat": ("kn_ks", None), "lnm_fric": ("mu", None),
}


def make_params(values: dict[str, float]) -> MicroParams:
    """Validate a mapping of user names to values; any mistake raises InputError naming the field."""
    return validated(MicroParams, NAMES, values, "parameter")


def law_constants(params: MicroParams, contact_stiffness: str = DEFAULT_CONTACT_STIFFNESS) -> laws.Laws:
    """The engine's constants of the linear contacts and parallel bonds (SI), the contacts'
    normal stiffness as `contact_stiffness` says (`simulate.CONTACT_STIFFNESS`)."""
    if contact_stiffness not in CONTACT_STIFFNESS:
        raise InputError("contact_stiffness", f"must be one of {', '.join(CONTACT_STIFFNESS)}, "
                                              f"got {contact_stiffness!r}")
    return laws.Laws(params.E_c * GPa, 1.0 / params.kn_ks, params.mu, params.Ebar_c * GPa,
                     1.0 / params.knbar_ksbar, params.lambda_,
                     math.tan(math.radians(params.phi_b)), params.mcf,
                     contact_stiffness == "pfc4")


def bond_strengths(params: MicroParams, draws: np.ndarray | None, n_bonds: int):
    """Tensile strength and cohesion (Pa) of each bond, truncated-normal (`truncated_normal`)
    at the bond's two uniform draws (columns of `draws`; None: the means)."""
    u = None if draws is None else np.asarray(draws, float).reshape(n_bonds, 2)
    means = (params.sigma_c, params.tau_c)
    return tuple(np.full(n_bonds, mean * MPa) if sd == 0 or u is None
                 else truncated_normal(mean, sd, u[:, column]) * MPa
                 for column, (mean, sd) in enumerate(zip(means, params.strength_sds)))


def new_state(pos, radius, bonds, params: MicroParams, *, walls=(0.0, 0.0, 0.0, 0.0),
              wall_active=(False,) * 4, driven=None, skin=None, laws_si=None,
              bond_draws=None, contact_stiffness: str = DEFAULT_CONTACT_STIFFNESS) -> State:
    """A state at rest with the given bonds (pairs i < j) installed at zero force; contacts
    as `contact_stiffness` says (CONTACT_STIFFNESS; platens as PFC 5's either way).

    bond_draws: two uniform draws per bond (in the order of `bonds`) that set its strengths
    (`bond_strengths`). A bond installed at an overlapping pair takes the overlap
    as reference, so installing it locks in no force.
    """
    laws_si = laws_si or law_constants(params, contact_stiffness)

    def parallel_bonds(pos, radius, nlist, order):
        nb = nlist.n_bonds
        ten, coh = bond_strengths(params, None if bond_draws is None else
                                  np.asarray(bond_draws, float).reshape(-1, 2)[order], nb)
        bi, bj = nlist.pi[:nb], nlist.pj[:nb]
        centre_gap = np.hypot(*(pos[bj] - pos[bi]).T)
        ref_overlap = np.maximum(0.0, radius[bi] + radius[bj] - centre_gap)
        return laws.new_bonds(ref_overlap, ten, coh, radius[bi], radius[bj])

    wall_modulus = laws_si.E_c if laws_si.E_c > 0 else laws_si.Ebar_c
    return assemble_state(pos, radius, bonds, params.density, params.damping, laws_si,
                          wall_modulus, parallel_bonds, walls=walls, wall_active=wall_active,
                          driven=driven, skin=skin)


def wall_modulus_pa(params: MicroParams) -> float:
    """The modulus of the walls' contacts: the material's contact modulus (FISHTank's
    platens), or its bond modulus if the contacts have none."""
    return (params.E_c if params.E_c > 0 else params.Ebar_c) * GPa


def laws_3d(params: MicroParams):
    """The 3D engine's law constants (SI) of the micro-parameters: PFC3D's linear contact and
    linear parallel bond under the same names (a rock's values differ from its PFC2D ones)."""
    from rockcal.dem3d.laws import Laws  # the 3D engine: loaded for a 3D run alone

    return Laws(E_c=params.E_c * GPa, ks_per_kn=1.0 / params.kn_ks, mu=params.mu,
                Ebar_c=params.Ebar_c * GPa, ksbar_per_knbar=1.0 / params.knbar_ksbar,
                lam=params.lambda_, tan_phi=math.tan(math.radians(params.phi_b)), mcf=params.mcf)


def new_state_3d(pos, radius, specimen, params: MicroParams, *, walls=((), ()), driven=None):
    """A 3D specimen at rest in the material: each bond's strengths drawn at its uniform draws
    (`bond_strengths`), between planar `walls` (points, inward normals) of the walls' modulus
    (`wall_modulus_pa`); the `driven` spheres (a mask or indices: a rig's) keep the velocity they
    are given."""
    from rockcal.dem3d.simulate import assemble_state as assemble_3d
    from rockcal.dem3d.walls import new_walls

    ten, coh = bond_strengths(params, np.asarray(specimen.bond_draws), len(specimen.bonds))
    points, normals = walls
    return assemble_3d(pos, radius, specimen.bonds, params.density, laws_3d(params), damping=params.damping,
                       ten=ten, coh=coh, walls=new_walls(points, normals, wall_modulus_pa(params)), driven=driven)


def pfc_parameters(params: MicroParams, specimen, fishtank: int | None = None) -> dict[str, float | int | str]:
    """FISHTank's parallel-bonded material parameters (SI) of a rockcal material for the
    FISHTank of PFC `fishtank` (its cm_matType; None: the default's): the common groups and
    `PFC_PROPERTIES`, the strengths' sd as PFC takes them (`strength_sds`)."""
    ten_sd, coh_sd = params.strength_sds
    values = params.key() | {"sigma_c_sd": ten_sd, "tau_c_sd": coh_sd,
                             "install_gap_mm": specimen.install_gap * specimen.rmin_mm}
    return common_pfc(params, specimen, "parallel-bonded", fishtank) | pfc_values(PFC_PROPERTIES, values)


def check_bonded(params: MicroParams) -> None:
    """The bonds bear load: with Ebar_c = 0 they have no stiffness, never load and never
    break, and the specimen is a granular pack with no bonded element, not a rock."""
    if params.Ebar_c == 0:
        raise InputError("Ebar_c", "0 leaves the bonds without stiffness: they bear no load, so the "
                                   "specimen has no bonded element and is no rock; give Ebar_c > 0")


MATERIAL = Material(
    name="parallel_bond", title="parallel-bonded (linear contact + linear parallel bond)",
    parameters=NAMES, make=make_params, params_type=MicroParams,
    pfc_names=pfc_names(PFC_PROPERTIES, NAMES),
    states={2: lambda pos, radius, specimen, params, **options: new_state(
        pos, radius, specimen.bonds, params, bond_draws=specimen.bond_draws, **options),
        3: new_state_3d},
    pfc_parameters=pfc_parameters, pfc_material_type=PARALLEL_BONDED, pfc_group="mpSetPBParams",
    check_rock=check_bonded,
    pair_properties=lambda params, specimen: dict(zip(
        ("tensile_strength_Pa", "cohesion_Pa"),
        bond_strengths(params, specimen.bond_draws, len(specimen.bonds)))))
