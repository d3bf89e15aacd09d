"""The bonded materials rockcal models, by name: the one table a material is added to.

A material is one module (`parallel_bond`, `flat_joint`): its micro-parameters with their PFC
property names, the genesis step that decides which grain pairs it bonds, the engine state its
laws run in, and its FISHTank parameters for the export, gathered in its `MATERIAL` record
(`material.Material`). `rockcal simulate --model NAME` and a campaign's `[material] model =
"NAME"` choose one; the parallel-bonded material is the default. A lab test builds its engine
state with `new_state`, whatever the material, and reads its parameters as `BondedParams`.
"""

from __future__ import annotations

import numpy as np

from rockcal.dem.clump_motion import clump
from rockcal.engine import ModelState
from rockcal.errors import InputError
from rockcal.materials import flat_joint, parallel_bond
from rockcal.materials.fishtank import FLAT_JOINTED, PARALLEL_BONDED, common_pfc
from rockcal.materials.material import BondedParams, Material

PARALLEL_BOND = parallel_bond.MATERIAL
FLATJOINT = flat_joint.MATERIAL
MATERIALS: dict[str, Material] = {m.name: m for m in (PARALLEL_BOND, FLATJOINT)}
DEFAULT_MATERIAL = PARALLEL_BOND.name
_BY_PARAMS = {m.params_type: m for m in MATERIALS.values()}

__all__ = ["BondedParams", "DEFAULT_MATERIAL", "FLATJOINT", "FLAT_JOINTED", "MATERIALS", "Material",
           "PARALLEL_BOND", "PARALLEL_BONDED", "as_params", "check_dimensions", "common_pfc",
           "dimensions_of", "material", "material_of", "new_state", "parameters"]


def material(name: str, field: str = "model") -> Material:
    """The material of that name; InputError naming `field` for a name no material has."""
    try:
        return MATERIALS[name]
    except KeyError:
        raise InputError(field, f"no material named {name!r}; known: {', '.join(MATERIALS)}") from None


def parameters(chosen: Material, values: dict) -> BondedParams:
    """`chosen.make(values)`, with a parameter of another material named as such, and
    parameters no rock can have (`Material.check_rock`) refused."""
    for name in values:
        others = [m.name for m in MATERIALS.values() if name in m.parameters]
        if name not in chosen.parameters and others:
            raise InputError(name, f"a parameter of the {others[0]} material, not of "
                                   f"{chosen.name}: choose model {others[0]}")
    params = chosen.make(values)
    if chosen.check_rock is not None:
        chosen.check_rock(params)
    return params


def material_of(params: BondedParams) -> Material:
    """The material whose micro-parameters `params` are."""
    return _BY_PARAMS[type(params)]


def as_params(params) -> BondedParams:
    """A material's micro-parameters as given, or the default material's from a dict of
    values (None: its defaults)."""
    if type(params) in _BY_PARAMS:
        return params
    return MATERIALS[DEFAULT_MATERIAL].make(params or {})


def dimensions_of(chosen: Material) -> tuple[int, ...]:
    """The dimensions the engine has the material in (2: PFC2D, 3: PFC3D)."""
    return tuple(sorted(chosen.states))


def check_dimensions(chosen: Material, dimensions: int, field: str = "model") -> None:
    """InputError naming `field` where the engine has no `chosen` material in `dimensions`."""
    if dimensions not in chosen.states:
        have = [m.name for m in MATERIALS.values() if dimensions in m.states]
        raise InputError(field, f"the {dimensions}D engine has no {chosen.name} material; with dimensions = "
                                f"{dimensions} (PFC{dimensions}D) the material is {' or '.join(have)}")


def new_state(params: BondedParams, specimen, pos=None, radius=None, **options) -> ModelState:
    """The engine state of `specimen` in the material of `params`, of the specimen's dimension
    (`Material.states`): its grains, or `pos` and `radius` (m) with the test's rig after them;
    `options` that dimension's rig options (2D: `simulate.assemble_state`'s walls,
    wall_active, driven, skin and a parallel bond's `contact_stiffness`; 3D: the walls and
    driven). A clumped specimen's pebbles are made its rigid clumps (`clump_motion.clump`, in 3D
    `dem3d.clump_motion.clump`), the rig's particles after them staying balls."""
    chosen = material_of(params)
    check_dimensions(chosen, specimen.dimensions)
    clump_of = getattr(specimen, "clump_of", None)
    if clump_of is not None and len(clump_of) != specimen.n_particles:
        raise ValueError(f"the specimen's clump_of has {len(clump_of)} entries for its "
                         f"{specimen.n_particles} particles")
    state = chosen.states[specimen.dimensions](specimen.pos if pos is None else pos,
                                               specimen.radius if radius is None else radius,
                                               specimen, params, **options)
    if clump_of is not None:
        rig = state.n_particles - len(clump_of)
        if specimen.dimensions == 3:  # the 3D engine: loaded for a 3D run alone
            from rockcal.dem3d.clump_motion import clump as clump_3d
            clump_3d(state, np.concatenate([clump_of, np.full(rig, -1, np.int64)]), params.density)
        else:
            clump(state, np.concatenate([clump_of, np.full(rig, -1, np.int64)]), params.density)
    return state
