"""Radius expansion in a rigid box (Potyondy & Cundall 2004, steps 1-2 of their genesis).

Disks are dropped at random with half their radii, grown in stages to the jamming density
with frictionless contacts, then their radii are scaled until the box walls feel a small
isotropic stress. What comes out is a dense, nearly stress-free packing.
"""

from __future__ import annotations

import logging

import numpy as np

from rockcal.dem.simulate import BOTTOM, LEFT, RIGHT, TOP, THICKNESS_M, advance, new_state, rebuild_neighbours
from rockcal.params import GPa, MPa, MicroParams

log = logging.getLogger(__name__)

GROWTH_STAGES = 5
STEPS_PER_STAGE = 1000
STEPS_PER_SERVO = 8000  # rounds long enough for a 220 mm box to jam evenly (2000 left loose zones)
SAMPLES_PER_SERVO = 8
MAX_SERVO_ROUNDS = 60


def pack_box(width: float, height: float, rmin: float, radius_ratio: float, seed: int):
    """Centres and radii (m) of a jammed packing in [0, width] x [0, height]."""
    from rockcal.dem.specimen import ISOTROPIC_STRESS_MPA, JAMMING_FRACTION, PACKING_MODULUS_GPA

    rng = np.random.default_rng(seed)
    mean_r2 = rmin**2 * (1 + radius_ratio + radius_ratio**2) / 3
    n = int(round(JAMMING_FRACTION * width * height / (np.pi * mean_r2)))
    radius = rng.uniform(rmin, radius_ratio * rmin, n)
    rmax = radius_ratio * rmin
    pos = np.column_stack([rng.uniform(rmax, width - rmax, n), rng.uniform(rmax, height - rmax, n)])
    params = MicroParams(E_c=PACKING_MODULUS_GPA, mu=0.0, damping=0.7)
    state = new_state(pos, radius, np.empty((0, 2)), params, walls=(0.0, width, 0.0, height),
                      wall_active=(True,) * 4)

    for stage in range(GROWTH_STAGES):
        state.radius[:] = radius * (0.5 + 0.5 * (stage + 1) / GROWTH_STAGES)
        rebuild_neighbours(state)
        advance(state, STEPS_PER_STAGE)

    target = ISOTROPIC_STRESS_MPA * MPa
    scale = 1.0
    for round_ in range(MAX_SERVO_ROUNDS):
        samples = []
        for _ in range(SAMPLES_PER_SERVO):
            advance(state, STEPS_PER_SERVO // SAMPLES_PER_SERVO)
            f = state.total_wall_force()
            samples.append(0.5 * ((f[LEFT] + f[RIGHT]) / height + (f[BOTTOM] + f[TOP]) / width))
        stress = float(np.mean(samples[SAMPLES_PER_SERVO // 2:])) / THICKNESS_M
        log.debug("servo round %d: wall stress %.3g MPa", round_, stress / MPa)
        if abs(stress - target) < 0.25 * target:
            break
        scale *= 1.0 + 0.5 * (target - stress) / (PACKING_MODULUS_GPA * GPa)
        state.radius[:] = radius * scale
    return state.pos.copy(), state.radius.copy()
