"""The comments heading a PFC file of a calibration: where it came from (`origin_lines`), the
FISHTank it targets and what its values mean in PFC2D (`notes_2d`) or PFC3D (`notes_3d`), its
packing seed (`seed_line`) and, calibrated with PFC 3.x/4.0's contacts, that FISHTank cannot
give them (`pfc4_lines`, which the first screen says too); each line in printable ASCII
(`comment_text`), so that no user text (a rock's name, a folder) leaves its comment and becomes
code."""

from __future__ import annotations

from rockcal.materials import PARALLEL_BOND, material_of
from rockcal.materials.fishtank import FIRST_PK_SEED, FISHTANKS, MATERIAL_TYPES, grain_template, template_name
from rockcal.params import GPa
from rockcal.pfc.calibrated import Calibrated, fishtank_of, in_3d

# What a file says it targets in each dimension: where, and the FISHTank materials it can be
TARGETS = {2: ("", ("parallel-bonded", "flat-jointed")), 3: (" in PFC3D", ("parallel-bonded",))}
# What FISHTank's names mean in PFC3D, where they differ from PFC2D (`parameter_file`)
PFC3D_NOTES = (
    "PFC3D: spheres; SI units; FISHTank's names, as in PFC2D, with PFC3D's meanings:",
    "pbm_emod, lnm_emod: kn = E* pi min(R)^2 / (R_A + R_B) (PFC3D's deformability method)",
    ("pbm_bemod: kbar_n = Ebar* / (R_A + R_B) on a bond disk of radius Rbar = pbm_rmul min(R): "
     "area pi Rbar^2, I = pi Rbar^4 / 4, J = pi Rbar^4 / 2"),
    "pbm_mcf: the bending moment in the bond's normal stress, the twisting moment in its shear stress",
    "pk_nc: the 3D grain cloud's porosity (FISHTank's 3D default 0.35); cm_Dlo, cm_Dup: sphere diameters",
    ("the vessel, the UCS specimen's cylinder: mvParams.p3dat, which rockcal export --to "
     "FOLDER/mpParams.p3dat writes beside this file"),
)
# the flat-jointed material's lines in place of the parallel bond's (pbm_*)
FLAT_JOINT_3D_NOTES = (
    "PFC3D: spheres; SI units; FISHTank's names, as in PFC2D, with PFC3D's meanings:",
    "lnm_emod: kn = E* pi min(R)^2 / (R_A + R_B) (PFC3D's deformability method)",
    ("fjm_emod: k_n = E* / (R_A + R_B) per unit area of a joint's disk of radius "
     "fjm_rmulVal min(R) (area pi R^2)"),
    "fjm_Nr: the disk's rings of elements (PFC2D: its elements); fjm_Nal: the elements of each ring",
    *PFC3D_NOTES[4:],
)
# Why a calibration with PFC 3.x/4.0's contacts (contact_stiffness = "pfc4") does not carry
# over to PFC 5+: FISHTank's linear groups set kn, ks by the deformability method only
PFC4_NOT_IN_FISHTANK = ("no FISHTank file (PFC 5+) reproduces these contacts: FISHTank sets kn only as "
                        "PFC 5's 2 min(R) t E_c / (R_A + R_B), softer between unequal grains; for a model "
                        'to run in PFC 5+, calibrate with contact_stiffness = "pfc5"')


def comment_text(text: str) -> str:
    """`text` in printable ASCII: every other character as its Python escape (\\n, \\x1b,
    \\u2028), so that no line break, control or encoding trick leaves a comment line."""
    return "".join(c if " " <= c <= "~" else c.encode("unicode_escape").decode("ascii") for c in str(text))


def header_lines(calibrated: Calibrated) -> list[str]:
    """The export's header, one comment line each, in printable ASCII (`comment_text`): no
    user text can leave its comment."""
    return [comment_text(line) for line in header_of(calibrated)]


def header_of(calibrated: Calibrated) -> list[str]:
    """The header's lines as written (not yet made safe): the origin, the dimension's notes,
    the packing seed."""
    notes = (notes_3d(fishtank_of(calibrated), material_of(calibrated.params).pfc_group, calibrated.specimen)
             if in_3d(calibrated) else notes_2d(calibrated))
    return origin_lines(calibrated) + notes + [seed_line(calibrated.specimen)]


def seed_line(specimen) -> str:
    """What the packing seed pk_seed is: FISHTank's first seed + the calibration's."""
    return (f"pk_seed: FISHTank's first seed {FIRST_PK_SEED} + the calibration's packing seed "
            f"{specimen.seed}; PFC's random numbers are not rockcal's, so it packs grains of the same "
            "statistics, not the same grains (rockcal export-specimen lists those)")


def takes_pfc4_contacts(specimen, model: str) -> bool:
    """A calibration whose contacts are PFC 3.x/4.0's: a parallel-bonded material (the flat
    joint's are PFC 5's) with contact_stiffness "pfc4" (2D only)."""
    return specimen.contact_stiffness == "pfc4" and model == PARALLEL_BOND.name


def pfc4_lines(calibrated: Calibrated) -> list[str]:
    """Calibrated with PFC 3.x/4.0's contacts: their kn, ks, and that this file does not give
    them to PFC 5+ (`PFC4_NOT_IN_FISHTANK`); none otherwise."""
    params = calibrated.params
    if not takes_pfc4_contacts(calibrated.specimen, material_of(params).name):
        return []
    kn = params.E_c * GPa
    ks = kn / params.kn_ks
    return [f"contacts as calibrated: PFC 3.x/4.0's (contact_stiffness = \"pfc4\"): kn = t E_c = {kn:.6g} "
            f"N/m, ks = {ks:.6g} N/m at every contact whatever the radii (in PFC 3.x/4.0 ball kn "
            f"{2 * kn:.6g}, ks {2 * ks:.6g} N/m, in series)",
            "NOTE: " + PFC4_NOT_IN_FISHTANK + " (pbm_emod, lnm_emod below: E_c in that formula)"]


def origin_lines(calibrated: Calibrated) -> list[str]:
    """Where the calibration came from: its verdict, campaign, targets, identified values."""
    o = calibrated.origin
    verdict = "accepted" if o["accepted"] else "NOT accepted (closest verified point)"
    lines = [f"rockcal calibration of {o['rock']}: {verdict}, {o['dem_runs']} DEM runs",
             f"campaign: {o['campaign']}; engine: {o['engine']}",
             "targets: " + ", ".join(f"{k} {v:g}" for k, v in o["targets"].items())]
    if o.get("quick_look"):
        lines.insert(1, o["quick_look"])
    if o["verified"]:
        lines.append("verified: " + ", ".join(f"{k} {o['verified'][k]:.4g}" for k in o["targets"]))
    lines.append("identified: " + ", ".join(f"{k} {v:.4g}" for k, v in o["identified"].items()))
    for name, i in o.get("intervals", {}).items():
        pinned = "" if i["pinned"] else " (not pinned down by the lab data)"
        lines.append(f"  {name}: 5-95 % interval {i['p5']:.4g} to {i['p95']:.4g}{pinned}")
    return lines


def target_line(version: int, dimensions: int) -> str:
    """The FISHTank a file targets and the cm_matType of each material it can be there."""
    where, materials = TARGETS[dimensions]
    codes = MATERIAL_TYPES[version]
    return (f"for {FISHTANKS[version]}{where}: cm_matType "
            + ", ".join(f"{codes[name]} {name}" for name in materials)
            + " (rockcal export --fishtank 5, 6 or 7)")


def notes_2d(calibrated: Calibrated) -> list[str]:
    """What the 2D export's values mean in PFC: the contacts, the target FISHTank, the grains."""
    lines = [*pfc4_lines(calibrated), target_line(fishtank_of(calibrated), 2)]
    shape = grain_template(calibrated.specimen)
    if shape is None:
        lines.append("2D: disks of unit thickness; SI units")
    else:
        lines += [f"2D: clumps of {shape.n_pebbles} disks of unit thickness (template "
                  f"{template_name(shape)}, rockcal's {shape.name!r}); SI units",
                  "the template's pebbles: radius, then centre x, y, in the template's frame (centroid "
                  "at the origin, lengths in equivalent radii: its equivalent diameter is 2);",
                  "FISHTank's clump distribute (diameter) sizes each clump's equivalent diameter "
                  "(of a disk of its area) in cm_Dlo..cm_Dup and turns it at random"]
    return lines


def notes_3d(version: int, group: str = "mpSetPBParams", settings=None) -> list[str]:
    """What a PFC3D file's values mean: the target FISHTank, PFC3D's meanings of its material
    group's names (`PFC3D_NOTES`, the flat joint's `FLAT_JOINT_3D_NOTES`) and, of clumped grains
    (`settings`' grain_shape), their template."""
    shape = None if settings is None else grain_template(settings)
    clumps = [] if shape is None else [
        f"3D: clumps of {shape.n_pebbles} spheres (template {template_name(shape)}, rockcal's {shape.name!r})",
        "the template's pebbles: radius, then centre x, y, z, in the template's frame (centroid at the origin, "
        "lengths in equivalent radii: its equivalent diameter, of a sphere of its volume, is 2);",
        "its mass properties computed by PFC from the pebbles (pebcalculate), overlaps counted once as rockcal's"]
    meanings = FLAT_JOINT_3D_NOTES if group == "mpSetFJParams" else PFC3D_NOTES
    return [target_line(version, 3), *meanings, *clumps]
