"""FISHTank's material-vessel file of a PFC3D calibration (`mvParams.p3dat`, which a FISHTank
project calls before `mpParams.p3dat`): the vessel of the calibration's UCS specimen, a
cylinder of `width_mm` diameter and `height_mm` height (`vessel_values`), in FISHTank's names
and SI units (`to_vessel_fish`).

rockcal packs that cylinder's square prism (`width_mm` x `width_mm` x `height_mm`) and keeps
the spheres whose centres lie in the cylinder; FISHTank packs in a cylindrical vessel
(`mv_shape = 1`) directly, so its specimen has the calibrated shape with no carving. The
vessel's walls have the modulus of rockcal's packing vessel (PFC's deformability method on a
ball-facet contact, kn = E* pi R, in both)."""

from __future__ import annotations

import math

from rockcal.materials.units import GPa, MM
from rockcal.pfc.fish_value import fish_value
from rockcal.pfc.header import comment_text
from rockcal.specimens.packing import PACKING_MODULUS_GPA

VESSEL_FILE = "mvParams.p3dat"  # FISHTank's name: a project runs `call mvParams.p3dat`
# FISHTank's hidden resolution of a cylindrical vessel (`_mvCylRes`): its wall is a polygon of
# 2 pi / _mvCylRes sides (FISHTank's default: 12, a section 4.5 % smaller than the circle's);
# 100 sides make it the circle's within 0.07 %
CYLINDER_SIDES = 100
UNITS = {"mv_H": "m", "mv_W": "m", "mv_D": "m", "mv_emod": "Pa"}


def vessel_values(specimen) -> dict[str, float | int]:
    """FISHTank's vessel (SI) of the calibration's UCS specimen (`specimen`: a campaign's
    SpecimenSettings): a physical (mv_type 0) cylinder (mv_shape 1) of height mv_H, diameter
    mv_W (mv_D, which FISHTank sets to mv_W itself), walls of modulus mv_emod."""
    return {"mv_type": 0, "mv_shape": 1, "mv_H": specimen.height_mm * MM, "mv_W": specimen.width_mm * MM,
            "mv_D": specimen.width_mm * MM, "mv_emod": PACKING_MODULUS_GPA * GPa,
            "_mvCylRes": 2 * math.pi / CYLINDER_SIDES}


def to_vessel_fish(specimen, header=()) -> str:
    """FISHTank's mvParams.p3dat: `header`'s lines as comments (made safe), the vessel group
    function `mvSetParams` (`vessel_values`), FISHTank's own check `_mvCheckParams`."""
    values = vessel_values(specimen)
    lines = [f"; {comment_text(line)}" for line in header]
    lines += ["; the vessel of the calibration's UCS specimen, a cylinder; call it before mpParams.p3dat",
              "def mvSetParams"]
    lines += [f"  {name} = {fish_value(value)}" + (f"  ; {UNITS[name]}" if name in UNITS else "")
              for name, value in values.items()]
    return "\n".join(lines + ["end", "@mvSetParams", "@_mvCheckParams", ""])
