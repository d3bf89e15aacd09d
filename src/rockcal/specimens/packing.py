"""Packing a grain cloud by grain scaling in a rigid box (steps 1-2 of PFC's genesis).

The cloud's grains (`genesis.cloud_radii`) are dropped at random with half the size they have
at jamming, grown in stages to it with frictionless contacts, then all their radii are scaled
by one factor until the mean wall stress is the material pressure. What comes out is a
dense packing under a small isotropic stress, whose grains are the cloud's scaled by one factor.
The grains are balls (`Balls`) or rigid clumps (`clump_genesis.ClumpedGrains`), sized alike by
their equivalent radii and put through the same steps (`pack_grains`).
"""

from __future__ import annotations

import logging

import numpy as np

from rockcal.errors import InputError
from rockcal.specimens.genesis import MIN_CONTACTS, cloud_radii, enlarge_floaters, floaters
from rockcal.dem.neighbours import spatial_order
from rockcal.dem.simulate import BOTTOM, LEFT, RIGHT, TOP, THICKNESS_M, advance, rebuild_neighbours
from rockcal.materials.parallel_bond import MicroParams, new_state
from rockcal.materials.units import GPa, MPa

log = logging.getLogger(__name__)

GROWTH_STAGES = 5
STEPS_PER_STAGE = 1000
STEPS_PER_SERVO = 8000  # rounds long enough for a 220 mm box to jam evenly (2000 left loose zones)
SAMPLES_PER_SERVO = 8
MAX_SERVO_ROUNDS = 60
PACKING_MODULUS_GPA = 1.0  # frictionless contacts used only to make the packing
# The largest material pressure a packing of spheres or clumps is made at: its contacts overlap
# by about P_m / E of a radius (E = PACKING_MODULUS_GPA) and its floaters are enlarged by that;
# at 10 % (100 MPa) the genesis still settles, at 1 GPa a grain would sit inside its neighbour
# (the 3D and clumped packings then fail). PFC's P_m is 0.1 MPa (FISHTank's default).
MAX_PACKING_PRESSURE_MPA = 0.1 * PACKING_MODULUS_GPA * 1e3
JAMMING_FRACTION = 0.845  # solid fraction of frictionless 2D polydisperse disks at jamming
PRESSURE_TOLERANCE = 0.05  # relative; the servo stops once the wall stress is this close to P_m
FLOATER_ROUNDS = 200  # at most this many rounds of enlarging floaters, servo step and cycling
STEPS_PER_FLOATER_ROUND = 2000
# Small vessels settle sooner: rounds are at most this many steps per row of grains along the
# vessel's longer side (the caps above hold from about 130 rows, e.g. 100 mm at R_min 0.25 mm).
SERVO_STEPS_PER_ROW = 60
FLOATER_STEPS_PER_ROW = 20


class Balls:
    """Grains that are balls: the engine's particles themselves, sized by their radii."""

    extent = 1.0  # a grain's reach from its centre, in sizes
    jamming_fraction = JAMMING_FRACTION

    def orientations(self, rng: np.random.Generator, n: int) -> np.ndarray:
        return np.zeros(n)  # a ball has none: no draw

    def new_state(self, pos, size, angle, params, width: float, height: float):
        # packed with PFC 5's contacts whatever the test's: generator v6's specimens, as cached
        return new_state(pos, size, np.empty((0, 2)), params, walls=(0.0, width, 0.0, height),
                         wall_active=(True,) * 4, contact_stiffness="pfc5")

    def sizes(self, state) -> np.ndarray:
        return state.particles.radius

    def resize(self, state, sizes: np.ndarray) -> None:
        state.particles.radius[:] = sizes

    def enlarge_floaters(self, state, width: float, height: float, overlap: float) -> np.ndarray:
        p = state.particles
        return enlarge_floaters(p.pos, p.radius, width, height, overlap)

    def count_floaters(self, state, width: float, height: float) -> int:
        p = state.particles
        return int(np.count_nonzero(floaters(p.pos, p.radius, width, height)))


def pack_box(width: float, height: float, rmin: float, radius_ratio: float, seed: int,
             cloud_porosity: float, pressure_mpa: float):
    """Centres and radii (m) of the cloud packed in [0, width] x [0, height] to the pressure,
    and the mean wall stress reached (MPa)."""
    state, pressure = pack_grains(Balls(), width, height, rmin, radius_ratio, seed,
                                  cloud_porosity, pressure_mpa)
    return state.particles.pos.copy(), state.particles.radius.copy(), pressure


def pack_grains(grains, width: float, height: float, rmin: float, radius_ratio: float, seed: int,
                cloud_porosity: float, pressure_mpa: float):
    """The cloud of `grains` (`Balls`, or clumps: `clump_genesis.ClumpedGrains`), sized by
    their equivalent radii, packed in [0, width] x [0, height] to the pressure (steps 1-3 of
    the genesis): the engine state, and the mean wall stress reached (MPa)."""
    rng = np.random.default_rng(seed)
    radius = cloud_radii(rng, width * height, rmin, radius_ratio, cloud_porosity)
    n = len(radius)
    radius *= min(1.0, np.sqrt(grains.jamming_fraction / (np.pi * (radius**2).sum() / (width * height))))
    rmax = radius.max()
    reach = rmax * grains.extent
    pos = np.column_stack([rng.uniform(reach, width - reach, n), rng.uniform(reach, height - reach, n)])
    angle = grains.orientations(rng, n)
    order = spatial_order(pos, 4 * rmax)  # blocks of the engine are then bands of the vessel
    pos, radius, angle = pos[order], radius[order], angle[order]
    params = MicroParams(E_c=PACKING_MODULUS_GPA, mu=0.0, damping=0.7)
    state = grains.new_state(pos, radius, angle, params, width, height)

    for stage in range(GROWTH_STAGES):
        grains.resize(state, radius * (0.5 + 0.5 * (stage + 1) / GROWTH_STAGES))
        rebuild_neighbours(state)
        advance(state, STEPS_PER_STAGE)

    rows = max(width, height) / (2.0 * radius.mean())
    servo_steps = min(STEPS_PER_SERVO, int(SERVO_STEPS_PER_ROW * rows))
    floater_steps = min(STEPS_PER_FLOATER_ROUND, int(FLOATER_STEPS_PER_ROW * rows))
    target = pressure_mpa * MPa
    stress = scale_to_pressure(state, grains, radius, target, servo_steps)
    overlap = target / (PACKING_MODULUS_GPA * GPa)  # ~ a contact's at P_m, / R
    for round_ in range(FLOATER_ROUNDS):
        grown = grains.enlarge_floaters(state, width, height, overlap)
        enlarged = np.count_nonzero(grown != grains.sizes(state))
        log.debug("floater round %d: %d floaters, wall stress %.3g MPa", round_, enlarged, stress / MPa)
        if not enlarged and abs(stress - target) < PRESSURE_TOLERANCE * target:
            break
        grains.resize(state, grown * servo_factor(stress, target))
        rebuild_neighbours(state)
        stress = settled_stress(state, floater_steps)
    else:
        left = grains.count_floaters(state, width, height)
        log.warning("genesis of %g x %g mm, seed %d: %d of %d grains still have fewer than %d "
                    "contacts after %d floater rounds", 1e3 * width, 1e3 * height, seed, left, n,
                    MIN_CONTACTS, FLOATER_ROUNDS)
    return state, stress / MPa


def check_packing_pressure(pressure_mpa: float, what: str) -> None:
    """P_m at most MAX_PACKING_PRESSURE_MPA for the genesis of `what` (its grains in words);
    an InputError naming `pressure_mpa`."""
    if pressure_mpa > MAX_PACKING_PRESSURE_MPA:
        raise InputError("pressure_mpa", f"{pressure_mpa:g} MPa is more than the genesis of {what} can "
                                         f"pack to: at most {MAX_PACKING_PRESSURE_MPA:g} MPa (10 % of its "
                                         f"contacts' {PACKING_MODULUS_GPA:g} GPa); PFC's default is 0.1 MPa")


def wall_stress(state, width: float, height: float) -> float:
    """Mean normal stress on the four walls of the vessel, Pa."""
    f = state.walls.total_force()
    return 0.5 * ((f[LEFT] + f[RIGHT]) / height + (f[BOTTOM] + f[TOP]) / width) / THICKNESS_M


def servo_factor(stress: float, target: float) -> float:
    """The factor on all radii that moves the wall stress towards `target` (Pa) at the packing's
    contacts' stiffness."""
    return 1.0 + 0.5 * (target - stress) / (PACKING_MODULUS_GPA * GPa)


def settled_stress(state, steps: int) -> float:
    """Cycle `steps` steps; the mean wall stress over their second half, Pa."""
    at = state.walls.pos
    width, height = at[RIGHT] - at[LEFT], at[TOP] - at[BOTTOM]
    samples = []
    for _ in range(SAMPLES_PER_SERVO):
        advance(state, steps // SAMPLES_PER_SERVO)
        samples.append(wall_stress(state, width, height))
    return float(np.mean(samples[SAMPLES_PER_SERVO // 2:]))


def scale_to_pressure(state, grains, radius: np.ndarray, target: float, steps: int) -> float:
    """Scale all grains (`radius`: their sizes) by one factor (`servo_factor`) until the mean
    wall stress is within PRESSURE_TOLERANCE of `target` (Pa), cycling `steps` steps between
    scalings; returns the stress reached."""
    scale = 1.0
    for round_ in range(MAX_SERVO_ROUNDS):
        stress = settled_stress(state, steps)
        log.debug("servo round %d: wall stress %.3g MPa", round_, stress / MPa)
        if abs(stress - target) < PRESSURE_TOLERANCE * target:
            break
        scale *= servo_factor(stress, target)
        grains.resize(state, radius * scale)
    return stress
