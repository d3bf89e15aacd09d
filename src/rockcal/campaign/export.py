"""Carry a finished calibration into PFC: the identified micro-parameters under the names of
Itasca's FISHTank parallel-bonded material (`mpSetPBParams` and its common and packing
groups), in SI units, and the specimen itself as ball and bond lists."""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rockcal.campaign.atomic import atomic_path
from rockcal.campaign.config import SpecimenSettings
from rockcal.campaign.forward import ENGINE
from rockcal.campaign.result import read_result
from rockcal.campaign.safe_text import comment_text
from rockcal.errors import InputError
from rockcal.materials import DEFAULT_MATERIAL, material
from rockcal.params import GPa, MicroParams, make_params

FORMATS = ("pfc-fish", "pfc-python", "json")


@dataclass(frozen=True)
class Calibrated:
    """What a finished campaign identified: the material, its specimen settings and where it
    came from (for the export's header)."""

    params: MicroParams
    specimen: SpecimenSettings
    origin: dict


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
    return Calibrated(make_params(result.identified_params), result.specimen, origin)


def pfc_parameters(params: MicroParams, specimen: SpecimenSettings,
                   model: str = DEFAULT_MATERIAL) -> dict[str, float]:
    """FISHTank's material parameters (SI) of a rockcal material (`rockcal.materials`)."""
    return material(model).pfc_parameters(params, specimen)


UNITS = {"cm_densityVal": "kg/m3", "cm_Dlo": "m", "cm_Dup": "m", "pk_Pm": "Pa", "pbm_emod": "Pa",
         "pbm_igap": "m", "pbm_bemod": "Pa", "pbm_ten_m": "Pa", "pbm_ten_sd": "Pa",
         "pbm_coh_m": "Pa", "pbm_coh_sd": "Pa", "pbm_fa": "degrees"}


def header_lines(calibrated: Calibrated) -> list[str]:
    """The export's header, one comment line each, in printable ASCII (`comment_text`): no
    user text can leave its comment."""
    return [comment_text(line) for line in _header(calibrated)]


def _header(calibrated: Calibrated) -> list[str]:
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
    if calibrated.specimen.contact_stiffness == "pfc4":
        kn = calibrated.params.E_c * GPa
        ks = kn / calibrated.params.kn_ks
        lines.append(f"contacts as PFC 3.x/4.0: ball kn {2 * kn:.6g} N/m, ks {2 * ks:.6g} N/m (kn = t E_c "
                     f"per contact whatever the radii; in PFC 5+ set the contacts' kn {kn:.6g}, ks "
                     f"{ks:.6g} N/m directly); pbm_emod below is PFC 5+'s deformability method, "
                     "softer by 2 min(R)/(R_A + R_B) between unequal grains")
    lines.append("2D: disks of unit thickness; SI units")
    return lines


def _fish_number(value: float) -> str:
    return repr(float(value))


def to_fish(calibrated: Calibrated) -> str:
    """A FISH data file in the layout of FISHTank's mpParams (three parameter functions)."""
    values = pfc_parameters(calibrated.params, calibrated.specimen)
    out = [f"; {line}" for line in header_lines(calibrated)]
    out += ["def mpSetCommonParams",
            f"  cm_localDampFac = {_fish_number(values['cm_localDampFac'])}",
            "  cm_densityCode = 1",
            f"  cm_densityVal = {_fish_number(values['cm_densityVal'])}  ; kg/m3",
            "  cm_nSD = 1",
            "  cm_Dlo = array.create(cm_nSD)",
            "  cm_Dup = array.create(cm_nSD)",
            "  cm_Vfrac = array.create(cm_nSD)",
            f"  cm_Dlo(1) = {_fish_number(values['cm_Dlo'])}  ; m",
            f"  cm_Dup(1) = {_fish_number(values['cm_Dup'])}  ; m",
            "  cm_Vfrac(1) = 1.0",
            "end", "@mpSetCommonParams", "",
            "def mpSetPackingParams",
            f"  pk_Pm = {_fish_number(values['pk_Pm'])}  ; Pa",
            f"  pk_nc = {_fish_number(values['pk_nc'])}",
            "end", "@mpSetPackingParams", "",
            "def mpSetPBParams"]
    for name, value in values.items():
        if name.startswith("pbm_"):
            unit = f"  ; {UNITS[name]}" if name in UNITS else ""
            out.append(f"  {name} = {_fish_number(value)}{unit}")
    out += ["end", "@mpSetPBParams", ""]
    return "\n".join(out)


def to_python(calibrated: Calibrated) -> str:
    """A PFC Python script that sets the FISH parameters (itasca.fish.set); outside PFC it only
    defines them."""
    values = pfc_parameters(calibrated.params, calibrated.specimen)
    # a fixed first line: the coding declaration no later comment can set
    out = ["# -*- coding: utf-8 -*-"] + [f"# {line}" for line in header_lines(calibrated)]
    out.append("PARAMETERS = {")
    for name, value in values.items():
        unit = f"  # {UNITS[name]}" if name in UNITS else ""
        out.append(f"    {name!r}: {float(value)!r},{unit}")
    out += ["}", "",
            "try:",
            "    import itasca",
            "except ImportError:  # not inside PFC",
            "    itasca = None",
            "if itasca is not None:",
            "    for name, value in PARAMETERS.items():",
            "        if name in ('cm_Dlo', 'cm_Dup'):",
            "            itasca.fish.set(name, [value])",
            "        else:",
            "            itasca.fish.set(name, value)",
            ""]
    return "\n".join(out)


def to_json(calibrated: Calibrated) -> str:
    values = pfc_parameters(calibrated.params, calibrated.specimen)
    return json.dumps({"origin": calibrated.origin, "parameters": values,
                       "units": {name: UNITS.get(name, "1") for name in values},
                       "rockcal_params": calibrated.params.key()}, indent=1) + "\n"


WRITERS = {"pfc-fish": to_fish, "pfc-python": to_python, "json": to_json}


def write_specimen(specimen, params: MicroParams, folder: Path) -> tuple[Path, Path]:
    """The specimen as balls.csv (id, x, y, radius; m) and bonds.csv (ball ids, tensile strength
    and cohesion of each bond at `params`; Pa), ids from 1 as in PFC."""
    from rockcal.dem.simulate import bond_strengths

    bonds = np.asarray(specimen.bonds)
    ten, coh = bond_strengths(params, specimen.bond_draws, len(bonds))
    folder.mkdir(parents=True, exist_ok=True)
    balls_path, bonds_path = folder / "balls.csv", folder / "bonds.csv"
    with atomic_path(balls_path) as tmp, open(tmp, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["id", "x_m", "y_m", "radius_m"])
        for i, ((x, y), r) in enumerate(zip(specimen.pos, specimen.radius), start=1):
            w.writerow([i, repr(float(x)), repr(float(y)), repr(float(r))])
    with atomic_path(bonds_path) as tmp, open(tmp, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["ball1", "ball2", "tensile_strength_Pa", "cohesion_Pa"])
        for (i, j), t, c in zip(bonds, ten, coh):
            w.writerow([int(i) + 1, int(j) + 1, repr(float(t)), repr(float(c))])
    return balls_path, bonds_path
