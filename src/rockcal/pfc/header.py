"""The comments heading a PFC file of a calibration: where it came from (`origin_lines`), the
FISHTank it targets and what its values mean in PFC2D (`notes_2d`) or PFC3D (`notes_3d`); each
line in printable ASCII (`comment_text`), so that no user text (a rock's name, a folder) leaves
its comment and becomes code."""

from __future__ import annotations

from rockcal.materials.fishtank import FISHTANKS, MATERIAL_TYPES, grain_template, template_name
from rockcal.params import GPa, MicroParams
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
    "the vessel (mvParams.p3dat) is not set here: rockcal packs a cuboid and carves the specimen from it",
)


def comment_text(text: str) -> str:
    """`text` in printable ASCII: every other character as its Python escape (\\n, \\x1b,
    \\u2028), so that no line break, control or encoding trick leaves a comment line."""
    return "".join(c if " " <= c <= "~" else c.encode("unicode_escape").decode("ascii") for c in str(text))


def header_lines(calibrated: Calibrated) -> list[str]:
    """The export's header, one comment line each, in printable ASCII (`comment_text`): no
    user text can leave its comment."""
    return [comment_text(line) for line in header_of(calibrated)]


def header_of(calibrated: Calibrated) -> list[str]:
    """The header's lines as written (not yet made safe): the origin, then the dimension's notes."""
    notes = notes_3d(fishtank_of(calibrated)) if in_3d(calibrated) else notes_2d(calibrated)
    return origin_lines(calibrated) + notes


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
    lines = []
    if calibrated.specimen.contact_stiffness == "pfc4" and isinstance(calibrated.params, MicroParams):
        kn = calibrated.params.E_c * GPa
        ks = kn / calibrated.params.kn_ks
        lines.append(f"contacts as PFC 3.x/4.0: ball kn {2 * kn:.6g} N/m, ks {2 * ks:.6g} N/m (kn = t E_c "
                     f"per contact whatever the radii; in PFC 5+ set the contacts' kn {kn:.6g}, ks "
                     f"{ks:.6g} N/m directly); pbm_emod below is PFC 5+'s deformability method, "
                     "softer by 2 min(R)/(R_A + R_B) between unequal grains")
    lines.append(target_line(fishtank_of(calibrated), 2))
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


def notes_3d(version: int) -> list[str]:
    """What a PFC3D file's values mean: the target FISHTank, PFC3D's meanings (`PFC3D_NOTES`)."""
    return [target_line(version, 3), *PFC3D_NOTES]
