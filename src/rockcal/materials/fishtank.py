"""FISHTank's parameters of a rockcal material (PFC's material-modelling support, `ft.fis`):
the common and packing groups every material shares, and a material group read from the
material's table of PFC properties; for clumped grains, the clump template FISHTank's
`clump distribute` takes (`cm_ctName`).

`cm_matType` numbers the materials differently from one FISHTank to the next: the export
targets one (`FISHTANKS`), PFC 6.0's by default."""

from __future__ import annotations

from rockcal.materials.clump_templates import DEFAULT_SHAPE, ClumpTemplate, template
from rockcal.errors import InputError
from rockcal.materials.units import GPa, MM, MPa

# cm_matType of rockcal's materials in each FISHTank, by PFC version (ft.fis: the case list of
# _mpCheckAllParams and the header's list of the common parameters):
# - 5: fistPkg25, "PFC 5.0 FISHTank version 25" (0 linear, 1 contact-bonded, 2 parallel-bonded,
#   3 flat-jointed, 4 user-defined);
# - 6: "PFC 6.0 FISHTank {version 6.6}" (0 linear, 1 contact-bonded, 2 parallel-bonded,
#   3 soft-bonded, 4 flat-jointed, 5 user-defined);
# - 7: PFC 6.0's numbering; no PFC 7 FISHTank was at hand to check it.
MATERIAL_TYPES = {
    5: {"parallel-bonded": 2, "flat-jointed": 3},
    6: {"parallel-bonded": 2, "flat-jointed": 4},
    7: {"parallel-bonded": 2, "flat-jointed": 4},
}
FISHTANKS = {5: "PFC 5.0's FISHTank (fistPkg25)", 6: "PFC 6.0's FISHTank (version 6.6)",
             7: "PFC 7.0, numbered as PFC 6.0's FISHTank (version 6.6)"}
DEFAULT_FISHTANK = 6
# the default FISHTank's codes (`Material.pfc_material_type`)
PARALLEL_BONDED = MATERIAL_TYPES[DEFAULT_FISHTANK]["parallel-bonded"]
FLAT_JOINTED = MATERIAL_TYPES[DEFAULT_FISHTANK]["flat-jointed"]
# the common group's properties that are a material's parameters: PFC property -> (name, unit)
COMMON_PROPERTIES = {"cm_localDampFac": ("damping", None), "cm_densityVal": ("density", None)}
SI = {None: None, "GPa": GPa, "MPa": MPa, "mm": MM}
# FISHTank's lowest packing seed (`pk_seed`, ft.fis: at least 10000); a calibration's packing
# seed s is FISHTank's FIRST_PK_SEED + s
FIRST_PK_SEED = 10000


def fishtank_version(value, field: str = "--fishtank") -> int:
    """The FISHTank a user names by its PFC version (5, 6 or 7); InputError naming `field`."""
    try:
        version = int(str(value).strip())
    except ValueError:
        version = None
    if version not in FISHTANKS:
        raise InputError(field, f"no FISHTank for PFC {value!r}; known: {', '.join(map(str, FISHTANKS))}")
    return version


def material_type(kind: str, fishtank: int | None = None) -> int:
    """`cm_matType` of the FISHTank material `kind` ("parallel-bonded", "flat-jointed") in the
    FISHTank of PFC `fishtank` (None: DEFAULT_FISHTANK)."""
    return MATERIAL_TYPES[fishtank_version(DEFAULT_FISHTANK if fishtank is None else fishtank)][kind]


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


def grain_template(specimen) -> ClumpTemplate | None:
    """The clump template of the specimen's grains (of its dimension: a 3D specimen's is a
    `clump_templates_3d.ClumpTemplate3D`); None for balls."""
    shape = getattr(specimen, "grain_shape", DEFAULT_SHAPE)
    if shape == DEFAULT_SHAPE:
        return None
    return template(shape, dimensions=getattr(specimen, "dimensions", 2))


def template_name(shape: ClumpTemplate) -> str:
    """The PFC name of a rockcal template (`cm_ctName`): rockcal_ and its name, a word."""
    return "rockcal_" + shape.name.replace("-", "_")


def template_pebbles(shape) -> list[tuple[float, ...]]:
    """Each pebble of the template as PFC's `clump template create ... pebbles` takes it:
    radius, then centre x, y (PFC2D) or x, y, z (PFC3D), in the template's frame (the clump's
    centroid at the origin, lengths in units of its equivalent radius: the template's
    equivalent diameter is 2)."""
    return [(float(r), *(float(v) for v in offset)) for r, offset in zip(shape.radii, shape.offsets)]


def common_pfc(params, specimen, kind: str, fishtank: int | None = None) -> dict[str, float | int | str]:
    """FISHTank's common and packing groups (SI) of a rockcal material (`kind`, as
    `material_type`) on its specimen, for the FISHTank of PFC `fishtank` (None: the
    default): one uniform size distribution (cm_typeSD 0) of diameters 2 R_min to
    2 R_min x ratio, of disks (cm_shape 0) or of clumps of one template (cm_shape 1,
    cm_ctName: FISHTank's `clump distribute diameter` takes the sizes as equivalent diameters,
    as rockcal's genesis does), the grains' own density (cm_densityCode 0: rockcal's density
    is the grains'), packing by grain scaling (pk_procCode 1) from the packing seed FIRST_PK_SEED
    + the specimen's seed (PFC's random numbers are not rockcal's: a packing of the same
    statistics, not the same grains)."""
    rmin_m = specimen.rmin_mm * MM
    shape = grain_template(specimen)
    grains = {"cm_shape": 0} if shape is None else {"cm_shape": 1, "cm_ctName": template_name(shape)}
    return {"cm_matType": material_type(kind, fishtank)} | pfc_values(COMMON_PROPERTIES, params.key()) | {
        "cm_densityCode": 0,
        **grains,
        "cm_nSD": 1,
        "cm_typeSD": 0,
        "cm_Dlo": 2 * rmin_m,
        "cm_Dup": 2 * rmin_m * specimen.radius_ratio,
        "cm_Vfrac": 1.0,
        "cm_Dmult": 1.0,
        "pk_seed": FIRST_PK_SEED + specimen.seed,
        "pk_Pm": specimen.pressure_mpa * MPa,
        "pk_procCode": 1,
        "pk_nc": specimen.cloud_porosity,
    }
