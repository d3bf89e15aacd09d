"""The bonded materials rockcal models, by name: the one place a material is known.

A material is its micro-parameters (with their PFC property names), the genesis step that
decides which grain pairs it bonds, the engine state its laws run in, and its FISHTank
parameters for the export. `rockcal simulate --model NAME` and a campaign's
`[material] model = "NAME"` choose one; the parallel-bonded material is the default.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from rockcal.dem.genesis import install_bonds
from rockcal.dem.simulate import new_state
from rockcal.errors import InputError
from rockcal.params import GPa, MPa, NAMES, MicroParams, make_params

MM = 1e-3


@dataclass(frozen=True)
class Material:
    """A bonded material. `parameters` are its micro-parameters' names (rockcal's units) and
    `make(values)` validates them; `pfc_names` gives each one's PFC property; `bond_pairs(pos,
    radius, gap_m)` is its genesis step (the grain pairs bonded within the installation gap);
    `new_state(...)` the engine state its laws run in; `pfc_parameters(params, specimen)` its
    FISHTank material parameters in SI units, with `pfc_material_type` (`cm_matType`)."""

    name: str
    title: str
    parameters: tuple[str, ...]
    make: Callable[[dict], object]
    pfc_names: dict[str, str]
    bond_pairs: Callable
    new_state: Callable
    pfc_parameters: Callable[[object, object], dict[str, float]]
    pfc_material_type: int


def parallel_bond_pfc(params: MicroParams, specimen) -> dict[str, float]:
    """FISHTank's parallel-bonded material parameters (SI) of a rockcal material.

    PFC's 2D disks have unit thickness, as rockcal's; the size distribution is one group of
    diameters from 2 R_min to 2 R_min x ratio; pbm_igap is the installation gap as a length.
    """
    ten_sd, coh_sd = params.strength_sds
    rmin_m = specimen.rmin_mm * MM
    return {
        "cm_densityVal": params.density,
        "cm_localDampFac": params.damping,
        "cm_Dlo": 2 * rmin_m,
        "cm_Dup": 2 * rmin_m * specimen.radius_ratio,
        "pk_Pm": specimen.pressure_mpa * MPa,
        "pk_nc": specimen.cloud_porosity,
        "pbm_emod": params.E_c * GPa,
        "pbm_krat": params.kn_ks,
        "pbm_fric": params.mu,
        "pbm_igap": specimen.install_gap * rmin_m,
        "pbm_rmul": params.lambda_,
        "pbm_bemod": params.Ebar_c * GPa,
        "pbm_bkrat": params.knbar_ksbar,
        "pbm_mcf": params.mcf,
        "pbm_ten_m": params.sigma_c * MPa,
        "pbm_ten_sd": ten_sd * MPa,
        "pbm_coh_m": params.tau_c * MPa,
        "pbm_coh_sd": coh_sd * MPa,
        "pbm_fa": params.phi_b,
    }


PARALLEL_BOND = Material(
    name="parallel_bond", title="parallel-bonded (linear contact + linear parallel bond)",
    parameters=NAMES, make=make_params,
    pfc_names={"E_c": "pbm_emod", "kn_ks": "pbm_krat", "mu": "pbm_fric", "lambda": "pbm_rmul",
               "Ebar_c": "pbm_bemod", "knbar_ksbar": "pbm_bkrat", "mcf": "pbm_mcf",
               "sigma_c": "pbm_ten_m", "sigma_c_sd": "pbm_ten_sd", "tau_c": "pbm_coh_m",
               "tau_c_sd": "pbm_coh_sd", "phi_b": "pbm_fa", "density": "cm_densityVal",
               "damping": "cm_localDampFac"},
    bond_pairs=install_bonds, new_state=new_state, pfc_parameters=parallel_bond_pfc,
    pfc_material_type=2)

MATERIALS: dict[str, Material] = {m.name: m for m in (PARALLEL_BOND,)}
DEFAULT_MATERIAL = PARALLEL_BOND.name


def material(name: str, field: str = "model") -> Material:
    """The material of that name; InputError naming `field` for a name no material has."""
    try:
        return MATERIALS[name]
    except KeyError:
        raise InputError(field, f"no material named {name!r}; known: {', '.join(MATERIALS)}") from None
