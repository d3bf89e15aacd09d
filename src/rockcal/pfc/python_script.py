"""A calibrated material as a script for PFC's own Python (`itasca`): it creates a clumped
material's clump template (`itasca.command`) and sets FISHTank's parameters
(`itasca.fish.set`), as the FISHTank parameter file does; PFC2D only."""

from __future__ import annotations

from rockcal.errors import InputError
from rockcal.pfc.calibrated import Calibrated, fishtank_of, in_3d
from rockcal.pfc.header import header_lines
from rockcal.pfc.parameters import SIZE_ARRAYS, UNITS, clump_templates, pfc_parameters


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
    out.append(f"FISHTANK = {fishtank_of(calibrated)!r}  # the PFC version whose FISHTank this targets")
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
