"""The bonded materials rockcal models, by name: the one place a material is known.

A material is its micro-parameters (with their PFC property names), the genesis step that
decides which grain pairs it bonds, the engine state its laws run in, and its FISHTank
parameters for the export. `rockcal simulate --model NAME` and a campaign's
`[material] model = "NAME"` choose one; the parallel-bonded material is the default. A lab
test builds its engine state with `new_state`, whatever the material.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from rockcal.dem import flatjoint_material
from rockcal.dem.flatjoint_material import FlatJointParams, make_flatjoint_params
from rockcal.dem.genesis import install_bonds
from rockcal.dem.simulate import State, bond_strengths
from rockcal.dem.simulate import new_state as parallel_bonded_state
from rockcal.errors import InputError
from rockcal.params import GPa, MPa, NAMES, MicroParams, make_params

MM = 1e-3


@dataclass(frozen=True)
class Material:
    """A bonded material. `parameters` are its micro-parameters' names (rockcal's units) and
    `make(values)` validates them into a `params_type`; `pfc_names` gives each one's PFC
    property; `bond_pairs(pos, radius, gap_m)` is its genesis step (the grain pairs bonded
    within the installation gap); `new_state(pos, radius, specimen, params, **options)` the
    engine state its laws run in (`simulate.assemble_state`'s options); `pfc_parameters(params,
    specimen)` its FISHTank material group's parameters in SI units, set by the FISH function
    `pfc_group`, with `pfc_material_type` (`cm_matType`); `pair_properties(params, specimen)`
    the properties of each bonded pair (columns by name, SI), for the specimen's export;
    `pairs_word` and `breaks_word` name its bonded pairs and what breaks in them."""

    name: str
    title: str
    parameters: tuple[str, ...]
    make: Callable[[dict], object]
    params_type: type
    pfc_names: dict[str, str]
    bond_pairs: Callable
    new_state: Callable[..., State]
    pfc_parameters: Callable[[object, object], dict[str, float | int | bool]]
    pfc_material_type: int
    pfc_group: str
    pair_properties: Callable[[object, object], dict]
    pairs_word: str = "bonds"  # its bonded pairs, in words
    breaks_word: str = "bonds"  # what breaks, each a crack

    def params(self, values: dict):
        """`make(values)`, and a name of another material's parameter named as such."""
        for name in values:
            others = [m.name for m in MATERIALS.values() if name in m.parameters]
            if name not in self.parameters and others:
                raise InputError(name, f"a parameter of the {others[0]} material, not of "
                                       f"{self.name}: choose model {others[0]}")
        return self.make(values)


def common_pfc(params, specimen, material_type: int) -> dict[str, float | int]:
    """FISHTank's common and packing groups (SI) of a rockcal material on its specimen: one
    uniform size distribution (cm_typeSD 0) of disks (cm_shape 0) of diameters 2 R_min to
    2 R_min x ratio, the grains' own density (cm_densityCode 0: rockcal's density is the
    grains'), packing by grain scaling (pk_procCode 1)."""
    rmin_m = specimen.rmin_mm * MM
    return {
        "cm_matType": material_type,
        "cm_localDampFac": params.damping,
        "cm_densityCode": 0,
        "cm_densityVal": params.density,
        "cm_shape": 0,
        "cm_nSD": 1,
        "cm_typeSD": 0,
        "cm_Dlo": 2 * rmin_m,
        "cm_Dup": 2 * rmin_m * specimen.radius_ratio,
        "cm_Vfrac": 1.0,
        "cm_Dmult": 1.0,
        "pk_Pm": specimen.pressure_mpa * MPa,
        "pk_procCode": 1,
        "pk_nc": specimen.cloud_porosity,
    }


def parallel_bond_pfc(params: MicroParams, specimen) -> dict[str, float | int]:
    """FISHTank's parallel-bonded material parameters (SI) of a rockcal material.

    PFC's 2D disks have unit thickness, as rockcal's; pbm_igap is the installation gap as a
    length; the linear material group (lnm_*, the contacts that form later) is the bonded
    contacts' linear part, as in FISHTank's own parallel-bonded files.
    """
    ten_sd, coh_sd = params.strength_sds
    return common_pfc(params, specimen, PARALLEL_BONDED) | {
        "pbm_emod": params.E_c * GPa,
        "pbm_krat": params.kn_ks,
        "pbm_fric": params.mu,
        "pbm_igap": specimen.install_gap * specimen.rmin_mm * MM,
        "pbm_rmul": params.lambda_,
        "pbm_bemod": params.Ebar_c * GPa,
        "pbm_bkrat": params.knbar_ksbar,
        "pbm_mcf": params.mcf,
        "pbm_ten_m": params.sigma_c * MPa,
        "pbm_ten_sd": ten_sd * MPa,
        "pbm_coh_m": params.tau_c * MPa,
        "pbm_coh_sd": coh_sd * MPa,
        "pbm_fa": params.phi_b,
        "lnm_emod": params.E_c * GPa,
        "lnm_krat": params.kn_ks,
        "lnm_fric": params.mu,
    }


def flatjoint_pfc(params: FlatJointParams, specimen) -> dict[str, float | int | bool]:
    """FISHTank's flat-jointed material parameters (SI) of a rockcal material: fjm_igap is the
    installation gap as a length, fjm_Nr the elements per joint (2D), fjm_rmulVal λ."""
    ten_sd, coh_sd = params.strength_sds
    return common_pfc(params, specimen, FLAT_JOINTED) | {
        "fjm_igap": specimen.install_gap * specimen.rmin_mm * MM,
        "fjm_B_frac": params.fjm_B_frac,
        "fjm_G_frac": params.fjm_G_frac,
        "fjm_G_m": params.fjm_G_m * MM,
        "fjm_G_sd": params.fjm_G_sd * MM,
        "fjm_Nr": params.fj_nr,
        "fjm_rmulCode": params.fjm_rmulCode,
        "fjm_rmulVal": params.fj_rmul,
        "fjm_emod": params.fj_emod * GPa,
        "fjm_krat": params.fj_kratio,
        "fjm_fric": params.fj_fric,
        "fjm_ten_m": params.fj_ten * MPa,
        "fjm_ten_sd": ten_sd * MPa,
        "fjm_coh_m": params.fj_coh * MPa,
        "fjm_coh_sd": coh_sd * MPa,
        "fjm_fa": params.fj_fa,
        "fjm_trackMS": False,
        "lnm_emod": params.lnm_emod * GPa,
        "lnm_krat": params.lnm_krat,
        "lnm_fric": params.lnm_fric,
    }


# FISHTank's cm_matType codes (ft.fis, _mpCheckCommonParams)
PARALLEL_BONDED, FLAT_JOINTED = 2, 4

PARALLEL_BOND = Material(
    name="parallel_bond", title="parallel-bonded (linear contact + linear parallel bond)",
    parameters=NAMES, make=make_params, params_type=MicroParams,
    pfc_names={"E_c": "pbm_emod", "kn_ks": "pbm_krat", "mu": "pbm_fric", "lambda": "pbm_rmul",
               "Ebar_c": "pbm_bemod", "knbar_ksbar": "pbm_bkrat", "mcf": "pbm_mcf",
               "sigma_c": "pbm_ten_m", "sigma_c_sd": "pbm_ten_sd", "tau_c": "pbm_coh_m",
               "tau_c_sd": "pbm_coh_sd", "phi_b": "pbm_fa", "density": "cm_densityVal",
               "damping": "cm_localDampFac"},
    bond_pairs=install_bonds,
    new_state=lambda pos, radius, specimen, params, **options: parallel_bonded_state(
        pos, radius, specimen.bonds, params, bond_draws=specimen.bond_draws, **options),
    pfc_parameters=parallel_bond_pfc, pfc_material_type=PARALLEL_BONDED, pfc_group="mpSetPBParams",
    pair_properties=lambda params, specimen: dict(zip(
        ("tensile_strength_Pa", "cohesion_Pa"),
        bond_strengths(params, specimen.bond_draws, len(specimen.bonds)))))


def _flat_joints(params: FlatJointParams, specimen) -> dict:
    """Each flat joint's type (PFC's fj_mtype: 1 bonded, 2 gapped, 3 slit), initial gap, radius
    multiplier (after FISHTank's reduction) and strengths."""
    m = flatjoint_material.flatjointed(specimen.pos, specimen.radius, specimen.bonds, params,
                                       specimen.joint_draws)
    return {"type": m.kind, "initial_gap_m": m.gap0, "radius_multiplier": m.rmul,
            "tensile_strength_Pa": m.ten[:, 0], "cohesion_Pa": m.coh[:, 0]}


def _flatjointed_state(pos, radius, specimen, params, *, contact_stiffness=None, **options):
    """The flat-jointed material's state; its linear contacts are PFC 5's whatever
    `contact_stiffness` says (a parallel-bonded setting)."""
    return flatjoint_material.new_state(pos, radius, specimen.bonds, params,
                                        joint_draws=specimen.joint_draws, **options)


FLATJOINT = Material(
    name="flatjoint", title="flat-jointed (flat joints + linear contacts)",
    parameters=flatjoint_material.NAMES, make=make_flatjoint_params, params_type=FlatJointParams,
    pfc_names={"fj_emod": "fjm_emod", "fj_kratio": "fjm_krat", "fj_ten": "fjm_ten_m",
               "fj_ten_sd": "fjm_ten_sd", "fj_coh": "fjm_coh_m", "fj_coh_sd": "fjm_coh_sd",
               "fj_fa": "fjm_fa", "fj_fric": "fjm_fric", "fj_nr": "fjm_Nr",
               "fj_rmul": "fjm_rmulVal", "fjm_rmulCode": "fjm_rmulCode",
               "fjm_B_frac": "fjm_B_frac", "fjm_G_frac": "fjm_G_frac", "fjm_G_m": "fjm_G_m",
               "fjm_G_sd": "fjm_G_sd", "lnm_emod": "lnm_emod", "lnm_krat": "lnm_krat",
               "lnm_fric": "lnm_fric", "density": "cm_densityVal", "damping": "cm_localDampFac"},
    bond_pairs=install_bonds, new_state=_flatjointed_state, pfc_parameters=flatjoint_pfc,
    pfc_material_type=FLAT_JOINTED, pfc_group="mpSetFJParams", pair_properties=_flat_joints,
    pairs_word="flat joints", breaks_word="elements")

MATERIALS: dict[str, Material] = {m.name: m for m in (PARALLEL_BOND, FLATJOINT)}
DEFAULT_MATERIAL = PARALLEL_BOND.name
_BY_PARAMS = {m.params_type: m for m in MATERIALS.values()}


def material(name: str, field: str = "model") -> Material:
    """The material of that name; InputError naming `field` for a name no material has."""
    try:
        return MATERIALS[name]
    except KeyError:
        raise InputError(field, f"no material named {name!r}; known: {', '.join(MATERIALS)}") from None


def material_of(params) -> Material:
    """The material whose micro-parameters `params` are."""
    return _BY_PARAMS[type(params)]


def as_params(params):
    """A material's micro-parameters as given, or the default material's from a dict of
    values (None: its defaults)."""
    if type(params) in _BY_PARAMS:
        return params
    return MATERIALS[DEFAULT_MATERIAL].make(params or {})


def new_state(params, specimen, pos=None, radius=None, **options) -> State:
    """The engine state of `specimen` in the material of `params`: its grains, or `pos` and
    `radius` (m) with the test's rig after them; `options` as `simulate.assemble_state`'s
    (walls, wall_active, driven, skin) and a parallel bond's `contact_stiffness`."""
    return material_of(params).new_state(specimen.pos if pos is None else pos,
                                         specimen.radius if radius is None else radius,
                                         specimen, params, **options)
