"""FISHTank's parameters of a rockcal material (PFC's material-modelling support, `ft.fis`):
the common and packing groups every material shares, and a material group read from the
material's table of PFC properties."""

from __future__ import annotations

from rockcal.materials.units import GPa, MM, MPa

# FISHTank's cm_matType codes (ft.fis, _mpCheckCommonParams)
PARALLEL_BONDED, FLAT_JOINTED = 2, 4
# the common group's properties that are a material's parameters: PFC property -> (name, unit)
COMMON_PROPERTIES = {"cm_localDampFac": ("damping", None), "cm_densityVal": ("density", None)}
SI = {None: None, "GPa": GPa, "MPa": MPa, "mm": MM}


def pfc_values(properties: dict[str, tuple[str, str | None]], values: dict) -> dict:
    """Each PFC property of `properties` (PFC name -> (rockcal name, its unit or None)) from
    `values` by rockcal name, in SI: a value without a unit as it is."""
    return {pfc: values[name] if unit is None else values[name] * SI[unit]
            for pfc, (name, unit) in properties.items()}


def pfc_names(properties: dict[str, tuple[str, str | None]], parameters) -> dict[str, str]:
    """Each of `parameters`' PFC property (its first in `properties`, then the common group's)."""
    names: dict[str, str] = {}
    for pfc, (name, _) in (properties | COMMON_PROPERTIES).items():
        if name in parameters:
            names.setdefault(name, pfc)
    return names


def common_pfc(params, specimen, material_type: int) -> dict[str, float | int]:
    """FISHTank's common and packing groups (SI) of a rockcal material on its specimen: one
    uniform size distribution (cm_typeSD 0) of disks (cm_shape 0) of diameters 2 R_min to
    2 R_min x ratio, the grains' own density (cm_densityCode 0: rockcal's density is the
    grains'), packing by grain scaling (pk_procCode 1)."""
    rmin_m = specimen.rmin_mm * MM
    return {"cm_matType": material_type} | pfc_values(COMMON_PROPERTIES, params.key()) | {
        "cm_densityCode": 0,
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
