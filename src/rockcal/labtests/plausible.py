"""The range of a rock's lab value in each unit it is given in, and the unit a value outside it
was likely given in: a UCS of 1.388e+08 "MPa" is a UCS in Pa, refused before any run.

A lab value's unit is its name's ending (E_GPa, ucs_MPa, confinement_mpa, K_IC_MPa_sqrt_m,
P_max_kN, diameter_mm), as the campaign file and the command line write it. A value of 0 is a
setting (an unconfined test), not a measurement, and is not checked.
"""

from __future__ import annotations

from rockcal.errors import InputError

# unit: (lowest, highest) of a rock's lab value in it, and the units a value outside that range
# was likely given in, with how many of each make one of this unit
PLAUSIBLE = {
    # E: soft chalk and weak sandstone (0.1 GPa) to the stiffest basalts and eclogites (about 150 GPa)
    "GPa": (0.1, 200.0, {"MPa": 1e3, "kPa": 1e6, "Pa": 1e9}),
    # strengths and stresses: weak tensile strengths (0.01 MPa) to confined peaks of the
    # strongest rocks (UCS at most about 500 MPa)
    "MPa": (0.01, 1000.0, {"kPa": 1e3, "Pa": 1e6, "GPa": 1e-3}),
    # K_IC: soft rock (0.01 MPa·m^0.5) to the toughest (a few MPa·m^0.5)
    "MPa·m^0.5": (0.01, 20.0, {"kPa·m^0.5": 1e3, "Pa·m^0.5": 1e6, "MPa·mm^0.5": 1e3**0.5}),
    "kN": (1e-3, 1000.0, {"N": 1e3}),  # a lab specimen's peak load
    "mm": (1.0, 2000.0, {"m": 1e-3, "µm": 1e3}),  # a lab specimen's size
}
# a name's ending: its unit
UNIT_OF_ENDING = {"_GPa": "GPa", "_MPa_sqrt_m": "MPa·m^0.5", "_MPa": "MPa", "_mpa": "MPa", "_kn": "kN",
                  "_kN": "kN", "_mm": "mm"}


def unit_of(name: str) -> str | None:
    """The unit a lab value's name ends in, if PLAUSIBLE has a range for it."""
    return next((unit for ending, unit in UNIT_OF_ENDING.items() if name.endswith(ending)), None)


def implausible(name: str, value) -> str | None:
    """What is wrong with a lab value named `name` (its unit its name's ending; a number, or a
    list of them) in words, with the unit it was likely given in; None when it is a rock's, or
    not a number of a unit with a range."""
    unit = unit_of(name)
    if unit is None:
        return None
    low, high, others = PLAUSIBLE[unit]
    for v in value if isinstance(value, (list, tuple)) else [value]:
        if isinstance(v, bool) or not isinstance(v, (int, float)) or v == 0 or low <= abs(v) <= high:
            continue
        likely = next((other for other, per in others.items() if low <= abs(v) / per <= high), None)
        cause = f"; did you give {likely}? (give {unit})" if likely else f" (a rock's is {low:g} to {high:g} {unit})"
        return f"{v:.4g} {unit} is not a rock's value{cause}"
    return None


def check_plausible(field: str, name: str, value) -> None:
    """InputError naming `field` when the lab value `value` named `name` is not a rock's
    (`implausible`)."""
    problem = implausible(name, value)
    if problem:
        raise InputError(field, problem)
