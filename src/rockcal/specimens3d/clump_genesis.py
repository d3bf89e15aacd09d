"""The 3D genesis of a clumped specimen (PFC3D's clumped materials): the balls' packing
(`packing.pack_cuboid`) with every sphere replaced by a rigid clump of a template's pebbles
(`materials.clump_templates_3d`) of the same volume, at its centre, turned at random; then
settled in the vessel to the material pressure P_m.

A grain's size is its equivalent radius, that of a sphere of its volume: each clump takes the
radius of the sphere it replaces, so the grains' volumes are the balls' and the size
distribution is theirs. Elongated or flat clumps jam denser than spheres: at the balls'
solid fraction frictionless clumps would turn and slide into a loose pack that bears no
pressure. So the clumps are first grown about their centroids to the solid fraction
CLUMP_JAMMING_FRACTION, above their jamming, then cycled with frictionless contacts in the
rigid vessel (the balls' packing laws) and scaled, their pebbles' offsets and radii alike, by
the balls' servo (`packing.servo_factor`) for up to MAX_SERVO_ROUNDS rounds, until the mean
wall stress comes down to within PRESSURE_TOLERANCE of P_m (from above, as the balls' grain
scaling reaches it). The pebbles of one clump are numbered
next to each other, the clumps in the order of the balls they replace; bonds join pebbles of
different clumps within the installation gap, pebble to pebble, never two of one clump.
"""

from __future__ import annotations

import math

import numpy as np

from rockcal.dem3d.clump_motion import clump
from rockcal.dem3d.laws import Laws
from rockcal.dem3d.simulate import assemble_state, rebuild_neighbours
from rockcal.dem3d.walls import box_walls
from rockcal.materials.clump_templates_3d import ClumpTemplate3D, random_rotation
from rockcal.materials.units import GPa, MPa
from rockcal.specimens.packing import MAX_SERVO_ROUNDS, PACKING_MODULUS_GPA, PRESSURE_TOLERANCE, servo_factor
from rockcal.specimens3d.genesis import install_bonds
from rockcal.specimens3d.packing import (FLOATER_STEPS_PER_ROW, MAX_FLOATER_STEPS, MIN_ROUND_STEPS, PACKING_DENSITY,
                                         settled_stress)

CLUMP_STREAM = 3  # the orientations' random stream, beside the packing's seed
CLUMP_JAMMING_FRACTION = 0.72  # solid fraction the clumps start settling from, above their jamming


def clumps_for_spheres(pos, radius, template: ClumpTemplate3D, seed: int):
    """Pebble centres, radii and clump numbers of clumps of `template` in place of the spheres
    (`pos`, `radius`, m): each of the sphere's volume at its centre, turned by a rotation drawn
    uniformly (stream [seed, CLUMP_STREAM])."""
    rng = np.random.default_rng([seed, CLUMP_STREAM])
    centres, radii = [], []
    for centre, size in zip(pos, radius):
        offsets, r = template.pebbles(size, random_rotation(rng))
        centres.append(centre + offsets)
        radii.append(r)
    clump_of = np.repeat(np.arange(len(radius)), template.n_pebbles)
    return np.vstack(centres), np.concatenate(radii), clump_of


def settle_clumps(pos, radius, clump_of, size, pressure_mpa: float):
    """Cycle the clumps (pebbles `pos`, `radius`, m) in the vessel [0, size] with frictionless
    contacts, each round scaling them about their centroids by the servo's factor, until the
    mean wall stress is within PRESSURE_TOLERANCE of `pressure_mpa` (at most MAX_SERVO_ROUNDS
    rounds). Returns the pebbles' centres and radii and the stress reached, MPa."""
    size = np.asarray(size, float)
    laws = Laws(E_c=PACKING_MODULUS_GPA * GPa, ks_per_kn=1.0, mu=0.0, Ebar_c=0.0, ksbar_per_knbar=1.0, lam=1.0,
                tan_phi=0.0, mcf=1.0)
    state = assemble_state(pos, radius, np.empty((0, 2)), PACKING_DENSITY, laws, damping=0.7,
                           skin=0.5 * radius.min(), walls=box_walls(np.zeros(3), size, PACKING_MODULUS_GPA * GPa))
    clumps = clump(state, clump_of, PACKING_DENSITY)
    unit_radius, unit_offsets = radius.copy(), clumps.offsets.copy()
    rows = size.max() / (2.0 * radius.mean())
    # the floater rounds' short rounds: a clump settles among its neighbours
    steps = int(np.clip(FLOATER_STEPS_PER_ROW * rows, MIN_ROUND_STEPS, MAX_FLOATER_STEPS))
    target = pressure_mpa * MPa
    # the grains' solid fraction, summed exactly (numpy's sum rounds by processor)
    fraction = math.fsum(1.0 / clumps.inv_mass) / PACKING_DENSITY / (size[0] * size[1] * size[2])
    scale = (CLUMP_JAMMING_FRACTION / fraction) ** (1.0 / 3.0)

    def resize(scale):
        state.spheres.radius[:] = unit_radius * scale
        clumps.offsets[:] = unit_offsets * scale
        clumps.carry_pebbles(state.spheres)
        rebuild_neighbours(state)

    resize(scale)
    for _ in range(MAX_SERVO_ROUNDS):
        stress = settled_stress(state, size, steps)
        if abs(stress - target) < PRESSURE_TOLERANCE * target:
            break
        scale *= servo_factor(stress, target)
        resize(scale)
    s = state.spheres
    return s.pos.copy(), s.radius.copy(), stress / MPa


def clump_bonds(pos, radius, clump_of, gap: float) -> np.ndarray:
    """The pairs of pebbles i < j of different clumps whose gap is <= `gap` (m)."""
    pairs = install_bonds(pos, radius, gap)
    return pairs[clump_of[pairs[:, 0]] != clump_of[pairs[:, 1]]]
