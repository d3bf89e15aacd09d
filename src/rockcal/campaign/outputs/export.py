"""Carry a finished calibration into PFC: the identified micro-parameters under the names of
Itasca's FISHTank material (`cm_matType`, the common and packing groups and the material's
group: `mpSetPBParams` for the parallel-bonded material, `mpSetFJParams` for the flat-jointed
one, each with the linear material group `lnm_*`), in SI units, as complete as FISHTank's own
parameter files, for the FISHTank of one PFC version (`cm_matType` differs between them); a
clumped material's grains as the clump template FISHTank's `clump distribute` takes, created
first (`clump template create`); and the specimen itself as ball and bond lists."""

from __future__ import annotations

import json
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from rockcal.campaign.input.config import SpecimenSettings
from rockcal.campaign.runs.spec import ENGINE
from rockcal.campaign.procedure.result import read_result
from rockcal.campaign.outputs.safe_text import comment_text
from rockcal.errors import InputError
from rockcal.materials import DEFAULT_MATERIAL, material, material_of
from rockcal.materials.fishtank import (DEFAULT_FISHTANK, FISHTANKS, MATERIAL_TYPES, fishtank_version,
                                        grain_template, template_name, template_pebbles)
from rockcal.output_files import write_csv
from rockcal.params import GPa, MicroParams

FORMATS = ("pfc-fish", "pfc-python", "json")


@dataclass(frozen=True)
class Calibrated:
    """What a finished campaign identified: the material, its specimen settings and where it
    came from (for the export's header); and the FISHTank the export targets, by PFC version."""

    params: object  # of its material (`rockcal.materials`)
    specimen: SpecimenSettings
    origin: dict
    fishtank: int = DEFAULT_FISHTANK


def for_fishtank(calibrated: Calibrated, version, field: str = "--fishtank") -> Calibrated:
    """The calibration exported for the FISHTank of PFC `version` (5, 6 or 7); InputError
    naming `field` for another."""
    return replace(calibrated, fishtank=fishtank_version(version, field))


def _fishtank(calibrated) -> int:
    return getattr(calibrated, "fishtank", DEFAULT_FISHTANK)


def read_calibration(store, folder: Path) -> Calibrated:
    """The identified material of the campaign in `store`; InputError if it has not finished."""
    result = read_result(store)
    if result is None:
        raise InputError("OUT", f"the campaign in {folder} has not finished; run "
                                f"`rockcal calibrate --resume --out {folder}`")
    final_run = store.run(result.final_ucs_run_key)
    u = result.uncertainty
    origin = {"rock": result.rock, "campaign": str(folder), "accepted": result.accepted,
              "dem_runs": result.dem_runs, "targets": result.targets, "verified": result.verified,
              "identified": result.identified,
              "intervals": {} if u is None else {n: i.to_dict() for n, i in u.intervals.items()},
              "engine": final_run.engine if final_run else ENGINE}
    if result.quick_look:
        origin["quick_look"] = result.quick_look
    model = material(result.material or DEFAULT_MATERIAL)
    return Calibrated(model.make(result.identified_params), result.specimen, origin)


def pfc_parameters(calibrated: Calibrated) -> dict[str, float | int | bool | str]:
    """FISHTank's parameters (SI) of a calibrated material (`rockcal.materials`), its name
    first: cm_matName 'rockcal_<material>' (the rock's own name stays in the header's comments:
    no user text becomes code)."""
    chosen = material_of(calibrated.params)
    return {"cm_matName": f"rockcal_{chosen.name}"} | chosen.pfc_parameters(
        calibrated.params, calibrated.specimen, _fishtank(calibrated))


def clump_templates(calibrated: Calibrated) -> dict[str, list[tuple[float, float, float]]]:
    """The clump template of a clumped material by its PFC name (`cm_ctName`): each pebble's
    radius and centre x, y in the template's frame (`fishtank.template_pebbles`); none for
    balls."""
    shape = grain_template(calibrated.specimen)
    return {} if shape is None else {template_name(shape): template_pebbles(shape)}


def template_command(name: str, pebbles) -> list[str]:
    """PFC's command creating the clump template `name` of `pebbles` (radius, x, y), its
    inertial properties computed from the pebbles as FISHTank's clumped examples do
    (`pebcalculate`): one line per pebble, each number to the last bit."""
    lines = [f"clump template create pebcalculate name {name} pebbles {len(pebbles)} ..."]
    lines += [" ".join(["   ", *(repr(float(v)) for v in pebble)]) + " ..." for pebble in pebbles]
    lines[-1] = lines[-1].removesuffix(" ...")
    return lines


UNITS = {"cm_densityVal": "kg/m3", "cm_Dlo": "m", "cm_Dup": "m", "pk_Pm": "Pa", "pbm_emod": "Pa",
         "pbm_igap": "m", "pbm_bemod": "Pa", "pbm_ten_m": "Pa", "pbm_ten_sd": "Pa",
         "pbm_coh_m": "Pa", "pbm_coh_sd": "Pa", "pbm_fa": "degrees", "fjm_igap": "m",
         "fjm_G_m": "m", "fjm_G_sd": "m", "fjm_emod": "Pa", "fjm_ten_m": "Pa", "fjm_ten_sd": "Pa",
         "fjm_coh_m": "Pa", "fjm_coh_sd": "Pa", "fjm_fa": "degrees", "lnm_emod": "Pa"}
# FISHTank's size-distribution arrays, one entry each (cm_nSD = 1); cm_ctName for clumps only
SIZE_ARRAYS = ("cm_typeSD", "cm_ctName", "cm_Dlo", "cm_Dup", "cm_Vfrac")


def header_lines(calibrated: Calibrated) -> list[str]:
    """The export's header, one comment line each, in printable ASCII (`comment_text`): no
    user text can leave its comment."""
    return [comment_text(line) for line in _header(calibrated)]


def _header(calibrated: Calibrated) -> list[str]:
    return origin_lines(calibrated) + _material_lines(calibrated)


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


def _material_lines(calibrated: Calibrated) -> list[str]:
    """What the 2D export's values mean in PFC: the contacts, the target FISHTank, the grains."""
    lines = []
    if calibrated.specimen.contact_stiffness == "pfc4" and isinstance(calibrated.params, MicroParams):
        kn = calibrated.params.E_c * GPa
        ks = kn / calibrated.params.kn_ks
        lines.append(f"contacts as PFC 3.x/4.0: ball kn {2 * kn:.6g} N/m, ks {2 * ks:.6g} N/m (kn = t E_c "
                     f"per contact whatever the radii; in PFC 5+ set the contacts' kn {kn:.6g}, ks "
                     f"{ks:.6g} N/m directly); pbm_emod below is PFC 5+'s deformability method, "
                     "softer by 2 min(R)/(R_A + R_B) between unequal grains")
    version = _fishtank(calibrated)
    codes = MATERIAL_TYPES[version]
    lines.append(f"for {FISHTANKS[version]}: cm_matType {codes['parallel-bonded']} parallel-bonded, "
                 f"{codes['flat-jointed']} flat-jointed (rockcal export --fishtank 5, 6 or 7)")
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


def _fish_value(value) -> str:
    """A value as FISH reads it: a string quoted, a boolean and an integer as one, a float to
    15 significant digits (a double's own precision: no 8190300.000000001 from a product) and
    always with a point or an exponent, so FISH reads a float."""
    if isinstance(value, str):
        return f"'{value}'"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    text = f"{float(value):.15g}"
    return text if any(c in text for c in ".en") else text + ".0"


def in_3d(calibrated: Calibrated) -> bool:
    """A calibration of PFC3D's spheres (`[specimen] dimensions = 3`)."""
    return calibrated.specimen.dimensions == 3


def to_fish(calibrated: Calibrated) -> str:
    """A FISH data file in the layout of FISHTank's mpParams: the common, packing and material
    group functions, then FISHTank's own check (`_mpCheckAllParams`); for a 3D calibration
    PFC3D's (`rockcal.dem3d.export.to_fish_3d`)."""
    if in_3d(calibrated):
        from rockcal.dem3d.export import to_fish_3d  # it builds on this module

        return to_fish_3d(calibrated.params, calibrated.specimen, fishtank=_fishtank(calibrated),
                          header=origin_lines(calibrated))
    out = [f"; {line}" for line in header_lines(calibrated)]
    for name, pebbles in clump_templates(calibrated).items():
        out += [*template_command(name, pebbles), ""]
    return "\n".join(out + fish_groups(pfc_parameters(calibrated), material_of(calibrated.params).pfc_group))


def fish_groups(values: dict, group: str) -> list[str]:
    """FISHTank's parameter groups of `values` (PFC names, SI), one line each: the common and
    packing group functions, the material group function `group`, FISHTank's own check
    (`_mpCheckAllParams`), and a last empty line (shared by the PFC3D export, `rockcal.dem3d.export`)."""
    arrays = [name for name in SIZE_ARRAYS if name in values]

    def assign(name: str, target: str | None = None) -> str:
        unit = f"  ; {UNITS[name]}" if name in UNITS else ""
        return f"  {target or name} = {_fish_value(values[name])}{unit}"

    common = [name for name in values if name.startswith("cm_") and name not in arrays]
    out = ["def mpSetCommonParams", *(assign(name) for name in common), "  cm_matNameSAV = cm_matName"]
    out += [f"  {name} = array.create(cm_nSD)" for name in arrays]
    out += [assign(name, f"{name}(1)") for name in arrays]
    out += ["end", "@mpSetCommonParams", "", "def mpSetPackingParams",
            *(assign(name) for name in values if name.startswith("pk_")),
            "end", "@mpSetPackingParams", "", f"def {group}",
            *(assign(name) for name in values if not name.startswith(("cm_", "pk_"))),
            "end", f"@{group}", "", "@_mpCheckAllParams", ""]
    return out


def to_python(calibrated: Calibrated) -> str:
    """A PFC Python script that creates the clump template of a clumped material
    (itasca.command) and sets the FISH parameters (itasca.fish.set); outside PFC it only
    defines them."""
    if in_3d(calibrated):
        raise InputError("--format", "a 3D calibration exports as pfc-fish (PFC3D's mpParams.p3dat) or json")
    values = pfc_parameters(calibrated)
    arrays = tuple(name for name in SIZE_ARRAYS if name in values)
    # a fixed first line: the coding declaration no later comment can set
    out = ["# -*- coding: utf-8 -*-"] + [f"# {line}" for line in header_lines(calibrated)]
    out.append(f"FISHTANK = {_fishtank(calibrated)!r}  # the PFC version whose FISHTank this targets")
    out.append("CLUMP_TEMPLATES = {  # name: pebbles (radius, x, y) in the template's frame")
    for name, pebbles in clump_templates(calibrated).items():
        out.append(f"    {name!r}: [")
        out += [f"        {tuple(float(v) for v in pebble)!r}," for pebble in pebbles]
        out.append("    ],")
    out.append("}")
    out.append("PARAMETERS = {")
    for name, value in values.items():
        unit = f"  # {UNITS[name]}" if name in UNITS else ""
        shown = value if isinstance(value, (int, str)) else float(value)
        out.append(f"    {name!r}: {shown!r},{unit}")
    out += ["}", "",
            "try:",
            "    import itasca",
            "except ImportError:  # not inside PFC",
            "    itasca = None",
            "if itasca is not None:",
            "    for name, pebbles in CLUMP_TEMPLATES.items():",
            "        itasca.command('clump template create pebcalculate name %s pebbles %d %s' % (",
            "            name, len(pebbles), ' '.join(repr(v) for pebble in pebbles for v in pebble)))",
            "    for name, value in PARAMETERS.items():",
            f"        if name in {arrays!r}:",
            "            itasca.fish.set(name, [value])",
            "        else:",
            "            itasca.fish.set(name, value)",
            "    itasca.fish.set('cm_matNameSAV', PARAMETERS['cm_matName'])",
            ""]
    return "\n".join(out)


def to_json(calibrated: Calibrated) -> str:
    values = pfc_parameters(calibrated)
    version = _fishtank(calibrated)
    templates = {name: {"pebbles": [{"radius": r, "x": x, "y": y} for r, x, y in pebbles],
                        "frame": "centroid at the origin; lengths in equivalent radii (equivalent diameter 2)"}
                 for name, pebbles in clump_templates(calibrated).items()}
    return json.dumps({"origin": calibrated.origin, "model": material_of(calibrated.params).name,
                       "fishtank": {"pfc": version, "target": FISHTANKS[version]},
                       "clump_templates": templates,
                       "parameters": values,
                       "units": {name: UNITS.get(name, "1") for name in values},
                       "rockcal_params": calibrated.params.key()}, indent=1) + "\n"


WRITERS = {"pfc-fish": to_fish, "pfc-python": to_python, "json": to_json}


def write_specimen(specimen, params, folder: Path) -> tuple[Path, Path]:
    """The specimen as balls.csv (id, x, y, radius; m) and bonds.csv (ball ids and the
    properties of each bonded pair at `params` (`Material.pair_properties`): a parallel bond's
    tensile strength and cohesion, Pa; a flat joint's type, initial gap, λ and strengths), ids
    from 1 as in PFC; a 3D specimen's by `rockcal.dem3d.export.write_specimen_3d`."""
    if specimen.pos.shape[1] == 3:
        from rockcal.dem3d.export import write_specimen_3d  # it builds on this module

        return write_specimen_3d(specimen, params, folder)
    bonds = np.asarray(specimen.bonds)
    columns = material_of(params).pair_properties(params, specimen)
    folder.mkdir(parents=True, exist_ok=True)
    balls_path, bonds_path = folder / "balls.csv", folder / "bonds.csv"
    write_csv(balls_path, ["id", "x_m", "y_m", "radius_m"],
              ([i, repr(float(x)), repr(float(y)), repr(float(r))]
               for i, ((x, y), r) in enumerate(zip(specimen.pos, specimen.radius), start=1)))
    write_csv(bonds_path, ["ball1", "ball2", *columns],
              ([int(i) + 1, int(j) + 1, *(repr(v.item()) for v in values)]
               for (i, j), *values in zip(bonds, *columns.values())))
    return balls_path, bonds_path
