"""A calibrated material as JSON, for a tool of one's own: where it came from, the FISHTank
targeted, a clumped material's template, FISHTank's parameters (SI) with their units, and
rockcal's own parameters."""

from __future__ import annotations

import json

from rockcal.materials import material_of
from rockcal.materials.fishtank import FISHTANKS
from rockcal.pfc.calibrated import Calibrated, fishtank_of
from rockcal.pfc.parameters import UNITS, clump_templates, pfc_parameters


def to_json(calibrated: Calibrated) -> str:
    """The calibration as one JSON document (indented, a final newline)."""
    values = pfc_parameters(calibrated)
    version = fishtank_of(calibrated)
    templates = {name: {"pebbles": [{"radius": r, "x": x, "y": y} for r, x, y in pebbles],
                        "frame": "centroid at the origin; lengths in equivalent radii (equivalent diameter 2)"}
                 for name, pebbles in clump_templates(calibrated).items()}
    return json.dumps({"origin": calibrated.origin, "model": material_of(calibrated.params).name,
                       "fishtank": {"pfc": version, "target": FISHTANKS[version]},
                       "clump_templates": templates,
                       "parameters": values,
                       "units": {name: UNITS.get(name, "1") for name in values},
                       "rockcal_params": calibrated.params.key()}, indent=1) + "\n"
