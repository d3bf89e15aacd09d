"""FISHTank's names and values (SI) of a calibrated material, which every PFC writer writes:
the material's own (`Material.pfc_parameters`) under its name `cm_matName`, their units, the
size-distribution arrays, a clumped material's clump template; and the checks of a PFC3D
material (the parallel bond, on spheres or clumps)."""

from __future__ import annotations

from rockcal.errors import InputError
from rockcal.materials import check_dimensions, material_of
from rockcal.materials.fishtank import (DEFAULT_FISHTANK, fishtank_version, grain_template, template_name,
                                        template_pebbles)
from rockcal.pfc.calibrated import Calibrated, fishtank_of

UNITS = {"cm_densityVal": "kg/m3", "cm_Dlo": "m", "cm_Dup": "m", "pk_Pm": "Pa", "pbm_emod": "Pa",
         "pbm_igap": "m", "pbm_bemod": "Pa", "pbm_ten_m": "Pa", "pbm_ten_sd": "Pa",
         "pbm_coh_m": "Pa", "pbm_coh_sd": "Pa", "pbm_fa": "degrees", "fjm_igap": "m",
         "fjm_G_m": "m", "fjm_G_sd": "m", "fjm_emod": "Pa", "fjm_ten_m": "Pa", "fjm_ten_sd": "Pa",
         "fjm_coh_m": "Pa", "fjm_coh_sd": "Pa", "fjm_fa": "degrees", "lnm_emod": "Pa"}
# FISHTank's size-distribution arrays, one entry each (cm_nSD = 1); cm_ctName for clumps only
SIZE_ARRAYS = ("cm_typeSD", "cm_ctName", "cm_Dlo", "cm_Dup", "cm_Vfrac")


def pfc_parameters(calibrated: Calibrated) -> dict[str, float | int | bool | str]:
    """FISHTank's parameters (SI) of a calibrated material (`rockcal.materials`), its name
    first: cm_matName 'rockcal_<material>' (the rock's own name stays in the header's comments:
    no user text becomes code)."""
    chosen = material_of(calibrated.params)
    return {"cm_matName": f"rockcal_{chosen.name}"} | chosen.pfc_parameters(
        calibrated.params, calibrated.specimen, fishtank_of(calibrated))


def clump_templates(calibrated: Calibrated) -> dict[str, list[tuple[float, float, float]]]:
    """The clump template of a clumped material by its PFC name (`cm_ctName`): each pebble's
    radius and centre x, y (3D: x, y, z) in the template's frame (`fishtank.template_pebbles`);
    none for balls."""
    shape = grain_template(calibrated.specimen)
    return {} if shape is None else {template_name(shape): template_pebbles(shape)}


def check_3d_material(params, settings) -> None:
    """A material the 3D engine has (`materials.check_dimensions`), on spheres or clumps of a 3D
    template; InputError naming the field."""
    from rockcal.materials.clump_templates_3d import GRAIN_SHAPES_3D

    check_dimensions(material_of(params), 3)
    shape = getattr(settings, "grain_shape", "ball")
    if shape not in GRAIN_SHAPES_3D:
        raise InputError("grain_shape", f"the 3D engine's grains are {', '.join(GRAIN_SHAPES_3D)}, got {shape!r}")


def pfc3d_parameters(params, settings, fishtank: int = DEFAULT_FISHTANK) -> dict:
    """FISHTank's parameters (SI) of the parallel-bonded material `params` on the genesis
    `settings` (anything with rmin_mm, radius_ratio, install_gap, cloud_porosity, pressure_mpa:
    a campaign's SpecimenSettings), for the FISHTank of PFC `fishtank`: the 2D names and values
    (`pfc_parameters`), which PFC3D's FISHTank reads alike."""
    check_3d_material(params, settings)
    return pfc_parameters(Calibrated(params, settings, {}, fishtank_version(fishtank)))
