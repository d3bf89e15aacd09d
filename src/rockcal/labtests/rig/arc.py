"""Rigid curved loading parts built from small driven disks: the bending test's pin and supports
(`rig.pins`), ISRM's jaws (`rig.jaws`). Disks of the specimen's smallest radius, half a disk
radius apart along an arc, make a surface smooth to a few per cent of that radius; the engine's
ordinary linear contacts (with the rock's friction, as steel's) carry the load, and the neighbour
grid stays fine.
"""

from __future__ import annotations

import math

import numpy as np

from rockcal.dem.simulate import State
from rockcal.specimens.specimen import Specimen
from rockcal.materials import new_state


def arc_disks(centre, arc_m: float, from_rad: float, to_rad: float, disk_m: float) -> np.ndarray:
    """Centres of disks of radius `disk_m` on the arc of radius `arc_m` about `centre`, from the
    angle `from_rad` to `to_rad` (anticlockwise from the x axis), at most half a disk radius
    apart along it."""
    count = int(np.ceil((to_rad - from_rad) * arc_m / (0.5 * disk_m))) + 1
    angle = np.linspace(from_rad, to_rad, count)
    # the C library's cos and sin: numpy's AVX-512 ones round otherwise on some angles
    cos, sin = np.array([math.cos(a) for a in angle]), np.array([math.sin(a) for a in angle])
    return np.column_stack([centre[0] + arc_m * cos, centre[1] + arc_m * sin])


def with_rigid_parts(specimen: Specimen, params, parts: list[np.ndarray], **options,
                     ) -> tuple[State, list[np.ndarray]]:
    """The engine state of the specimen's grains followed by the driven disks (of its smallest
    radius; spheres in 3D) centred at each of `parts`, in order, with the state's `options`
    (`materials.new_state`); each part's mask over the state's particles."""
    n, disk = specimen.n_particles, specimen.radius.min()
    rigid = np.vstack(parts)
    masks, start = [], n
    for part in parts:
        mask = np.zeros(n + len(rigid), bool)
        mask[start:start + len(part)] = True
        masks.append(mask)
        start += len(part)
    state = new_state(params, specimen, np.vstack([specimen.pos, rigid]),
                      np.concatenate([specimen.radius, np.full(len(rigid), disk)]),
                      driven=np.any(masks, axis=0), **options)
    return state, masks
