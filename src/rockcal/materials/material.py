"""What a bonded material is: its registry record (`Material`), what every material's
micro-parameters offer the lab tests (`BondedParams`), and their validation."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, ClassVar, Protocol, runtime_checkable

from pydantic import BaseModel, ValidationError

from rockcal.errors import InputError, from_validation_error


# Bounds that keep a run finite: a lighter grain, a stiffer shear spring or heavier damping
# than these makes the time step or the loading's settling time grow without end.
MIN_DENSITY = 100.0  # kg/m³, a tenth of the lightest rock's grains
MIN_STIFFNESS_RATIO = 0.1  # k_n / k_s: shear stiffness at most ten times the normal
MAX_DAMPING = 0.95  # local damping; PFC's default 0.7


@runtime_checkable
class BondedParams(Protocol):
    """A material's micro-parameters as the lab tests and the store use them, whatever the
    material: grain density (kg/m³), local damping, the name of the linear contacts' modulus
    (GPa; the pins and platens push through contacts), a bonded pair's modulus for the wave
    speed, and every value by name."""

    CONTACT_MODULUS: ClassVar[str]
    density: float
    damping: float

    @property
    def bonded_modulus_GPa(self) -> float: ...

    def key(self) -> dict[str, float]: ...


@dataclass(frozen=True)
class Material:
    """A bonded material. `parameters` are its micro-parameters' names (rockcal's units) and
    `make(values)` validates them into a `params_type`; `pfc_names` gives each one's PFC
    property; `states` its engine state builder per dimension (2: PFC2D's
    disks, 3: PFC3D's spheres), `states[d](pos, radius, specimen, params, **options)` the state
    its laws run in, with that dimension's rig options (2D: `simulate.assemble_state`'s; 3D:
    the walls), a dimension without an entry one the material has no engine for;
    `pfc_parameters(params,
    specimen)` its FISHTank material group's parameters in SI units, set by the FISH function
    `pfc_group`, with `pfc_material_type` (`cm_matType` in the default FISHTank's numbering, PFC 6's); `pair_properties(params, specimen)`
    the properties of each bonded pair (columns by name, SI), for the specimen's export;
    `pairs_word` and `breaks_word` name its bonded pairs and what breaks in them;
    `check_rock(params)` refuses valid parameters no rock can have (no bonded element), an
    InputError naming the parameter."""

    name: str
    title: str
    parameters: tuple[str, ...]
    make: Callable[[dict], BondedParams]
    params_type: type
    pfc_names: dict[str, str]
    states: dict[int, Callable]
    pfc_parameters: Callable[[BondedParams, object], dict[str, float | int | bool]]
    pfc_material_type: int
    pfc_group: str
    pair_properties: Callable[[BondedParams, object], dict]
    pairs_word: str = "bonds"  # its bonded pairs, in words
    breaks_word: str = "bonds"  # what breaks, each a crack
    check_rock: Callable[[BondedParams], None] | None = None
    # a UCS run's time over the parallel-bonded material's on the same specimen, per dimension
    # (the first screen's estimate, before the store holds a run); a dimension left out: 1
    slower_than_parallel_bond: tuple[tuple[int, float], ...] = ()

    def slower_in(self, dimensions: int) -> float:
        """`slower_than_parallel_bond` in `dimensions` (2 or 3)."""
        return dict(self.slower_than_parallel_bond).get(dimensions, 1.0)



def validated(model: type[BaseModel], names: tuple[str, ...], values: dict, what: str):
    """`model(**values)`, each name one of `names` and each value a finite number; any mistake
    raises InputError naming the field (`what`: the parameters' kind, in words)."""
    unknown = sorted(set(values) - set(names))
    if unknown:
        raise InputError(unknown[0], f"unknown {what}; known: {', '.join(names)}")
    for name, value in values.items():
        if not isinstance(value, (int, float)) or isinstance(value, bool) or not math.isfinite(value):
            raise InputError(name, f"must be a finite number, got {value!r}")
    try:
        return model(**values)
    except ValidationError as exc:
        raise from_validation_error(exc) from None
