"""Packing a sphere cloud by grain scaling in a rigid cuboid vessel, or the vertical cylinder
inscribed in it (FISHTank's cylindrical material vessel), steps 1-3 of PFC's genesis as the 2D
`rockcal.specimens.packing`: the cloud's spheres are dropped at random with half the size
they have at jamming, grown in stages to it with frictionless contacts, then all radii are
scaled by one factor until the mean wall stress is the material pressure P_m (a servo that
measures the packing's stiffness as it goes: `RadiusServo`); floaters are enlarged and the
packing cycled and scaled back to P_m until a few are left, which are enlarged in place.
"""

from __future__ import annotations

import logging

import math

import numpy as np

from rockcal.errors import InputError
from rockcal.specimens.genesis import MIN_CONTACTS, check_given_up
from rockcal.specimens.packing import (
    FLOATER_ROUNDS,
    GROWTH_STAGES,
    MAX_SERVO_ROUNDS,
    PACKING_MODULUS_GPA,
    PRESSURE_TOLERANCE,
    SAMPLES_PER_SERVO,
    STEPS_PER_STAGE,
)
from rockcal.specimens3d.genesis import cloud_radii, enlarge_floaters, floaters
from rockcal.dem3d.laws import Laws
from rockcal.dem3d.neighbours import spatial_order
from rockcal.dem3d.simulate import advance, assemble_state, rebuild_neighbours
from rockcal.dem3d.vectors import cubes
from rockcal.dem3d.walls import box_walls, new_walls, with_cylinder
from rockcal.materials.units import GPa, MPa

log = logging.getLogger(__name__)

JAMMING_FRACTION = 0.64  # solid fraction of frictionless polydisperse spheres at jamming
PACKING_DENSITY = 2650.0  # kg/m³; the packing is cycled to rest, so the mass sets only its pace
# Rounds are at most this many steps per row of spheres along the vessel's longest side (the
# 2D genesis' rule; at least the floor, so a small vessel still settles).
SERVO_STEPS_PER_ROW = 60
FLOATER_STEPS_PER_ROW = 20
MIN_ROUND_STEPS = 400
MAX_SERVO_STEPS = 8000
MAX_FLOATER_STEPS = 2000
# The servo's first guess of the packing's stiffness, the mean wall stress per relative change
# of all radii, over the contacts' modulus (a jammed frictionless packing's is about 0.5); the
# servo then measures it within these bounds, and moves this share of the way to P_m each round
SERVO_STIFFNESS_GUESS = 1.0
SERVO_STIFFNESS_BOUNDS = (0.2, 2.0)
SERVO_RELAXATION = 0.8
# A floater is grown to overlap its third nearest neighbour by this many times a contact's
# overlap at P_m (P_m / E of a radius), times one more for each round at P_m it floated in
# before: grown by just one, most are pushed off their neighbours again as the packing is
# cycled, and grown by the same amount each round, the last few (short of a stable cage by a
# few per cent of their radius) float on for dozens of rounds, each cycling the whole packing
FLOATER_OVERLAP = 10.0
# Once the wall stress is at P_m and at most this share of the spheres float, they are grown so
# in place, the packing not cycled again: the last rounds, of a few floaters each, took half of
# the floater rounds' steps
FLOATERS_GROWN_IN_PLACE = 0.001


def pack_vessel(size, rmin: float, radius_ratio: float, seed: int, cloud_porosity: float,
                pressure_mpa: float, cylinder: bool = False):
    """Centres (in spatial order) and radii (m) of the cloud packed in the vessel [0, size]
    (m, 3 sides), or the vertical `cylinder` inscribed in it, to the pressure, the mean wall
    stress reached (MPa) and the floaters left."""
    size = np.asarray(size, float)
    rng = np.random.default_rng(seed)
    volume = np.pi / 4 * float(np.prod(size)) if cylinder else float(np.prod(size))
    radius = cloud_radii(rng, volume, rmin, radius_ratio, cloud_porosity)
    n = len(radius)
    fraction = float(4 / 3 * np.pi * cubes(radius).sum() / volume)
    radius *= min(1.0, (JAMMING_FRACTION / fraction) ** (1 / 3))  # a float's: the C library's pow
    rmax = radius.max()
    pos = rng.uniform(rmax, size - rmax, (n, 3))
    while cylinder and (outside := _off_cylinder(pos, size, rmax)).any():  # drawn again
        pos[outside] = rng.uniform(rmax, size - rmax, (np.count_nonzero(outside), 3))
    order = spatial_order(pos, 4 * rmax)
    pos, radius = pos[order], radius[order]
    laws = Laws(E_c=PACKING_MODULUS_GPA * GPa, ks_per_kn=1.0, mu=0.0, Ebar_c=0.0,
                ksbar_per_knbar=1.0, lam=1.0, tan_phi=0.0, mcf=1.0)
    state = assemble_state(pos, 0.5 * radius, np.empty((0, 2)), PACKING_DENSITY, laws,
                           damping=0.7, skin=0.5 * radius.min(),
                           walls=vessel_walls(size, cylinder, PACKING_MODULUS_GPA * GPa))
    if not np.isfinite(state.dt):  # no spring anywhere: a step of inf would make every centre NaN
        raise InputError("cloud_porosity", f"the {n} spheres of a cloud porosity of {cloud_porosity:g} touch "
                                           "nothing in the vessel: lower it (FISHTank's 3D examples take 0.30-0.35)")
    s = state.spheres
    for stage in range(GROWTH_STAGES):
        s.radius[:] = radius * (0.5 + 0.5 * (stage + 1) / GROWTH_STAGES)
        rebuild_neighbours(state)
        advance(state, STEPS_PER_STAGE)

    rows = size.max() / (2.0 * radius.mean())
    servo_steps = int(np.clip(SERVO_STEPS_PER_ROW * rows, MIN_ROUND_STEPS, MAX_SERVO_STEPS))
    floater_steps = int(np.clip(FLOATER_STEPS_PER_ROW * rows, MIN_ROUND_STEPS, MAX_FLOATER_STEPS))
    target = pressure_mpa * MPa
    servo = RadiusServo(target)
    stress = settled_stress(state, size, servo_steps, cylinder)
    for _ in range(MAX_SERVO_ROUNDS):
        if abs(stress - target) < PRESSURE_TOLERANCE * target:
            break
        s.radius[:] = radius * servo.scale(stress)
        stress = settled_stress(state, size, servo_steps, cylinder)
    overlap = FLOATER_OVERLAP * target / (PACKING_MODULUS_GPA * GPa)
    floated = np.zeros(n)  # the rounds at P_m each sphere was a floater in
    for round_ in range(FLOATER_ROUNDS):
        grown = enlarge_floaters(s.pos, s.radius, size, overlap * (1 + floated), cylinder)
        floating = grown != s.radius
        log.debug("floater round %d: %d floaters, wall stress %.3g MPa", round_,
                  np.count_nonzero(floating), stress / MPa)
        at_pressure = abs(stress - target) < PRESSURE_TOLERANCE * target
        if at_pressure and np.count_nonzero(floating) <= FLOATERS_GROWN_IN_PLACE * n:
            s.radius[:] = grown
            break
        floated += floating & at_pressure  # a packing off P_m floats spheres that are no rattlers
        s.radius[:] = grown * servo.factor(stress)
        rebuild_neighbours(state)
        stress = settled_stress(state, size, floater_steps, cylinder)
    left = int(np.count_nonzero(floaters(s.pos, s.radius, size, cylinder)))
    check_given_up("3D", "spheres", stress / MPa, pressure_mpa, left, n)
    if left:
        log.warning("3D genesis of %s mm, seed %d: %d of %d spheres have fewer than %d contacts",
                    np.round(1e3 * size, 3), seed, left, n, MIN_CONTACTS)
    return s.pos.copy(), s.radius.copy(), stress / MPa, left


class RadiusServo:
    """The factor on all radii that brings the mean wall stress to `target` (Pa): a Newton step
    on the stress against the radii's log scale, its slope the secant of the last two rounds
    in which the radii changed (`SERVO_STIFFNESS_GUESS` until then)."""

    def __init__(self, target: float):
        self.target = target
        self.stiffness = SERVO_STIFFNESS_GUESS * PACKING_MODULUS_GPA * GPa
        self.log_scale = 0.0
        self.last = None  # (log scale, stress) of the round before

    def factor(self, stress: float) -> float:
        """The factor for a packing at `stress` (Pa), as a change of its current radii."""
        # the C library's exp and log: numpy's SIMD ones round by processor
        return math.exp(SERVO_RELAXATION * (self.target - stress) / self.stiffness)

    def scale(self, stress: float) -> float:
        """The radii's scale over the servo's start after a round that ended at `stress` (Pa),
        the slope measured where the radii changed since the round before."""
        if self.last is not None and self.log_scale != self.last[0]:
            secant = (stress - self.last[1]) / (self.log_scale - self.last[0])
            low, high = (b * PACKING_MODULUS_GPA * GPa for b in SERVO_STIFFNESS_BOUNDS)
            self.stiffness = float(np.clip(secant, low, high))
        self.last = (self.log_scale, stress)
        self.log_scale += math.log(self.factor(stress))
        return math.exp(self.log_scale)


def _off_cylinder(pos, size, rmax: float) -> np.ndarray:
    """The centres farther than its radius less `rmax` from the axis of the cylinder inscribed
    in the vessel [0, size]."""
    return np.hypot(*(pos[:, :2] - 0.5 * size[:2]).T) > 0.5 * size[0] - rmax


def vessel_walls(size, cylinder: bool, modulus_pa: float):
    """The vessel's walls: the six faces of [0, size] (`box_walls`), or the bottom, the top and
    the side of the `cylinder` inscribed in it."""
    if not cylinder:
        return box_walls(np.zeros(3), size, modulus_pa)
    x, y, z = size
    ends = new_walls([(x / 2, y / 2, 0.0), (x / 2, y / 2, z)], [(0, 0, 1), (0, 0, -1)], modulus_pa)
    return with_cylinder(ends, (x / 2, y / 2, z / 2), (0, 0, 1), x / 2, modulus_pa)


def wall_stress(state, size, cylinder: bool = False) -> float:
    """Mean normal stress on the walls of the vessel [0, size] (`vessel_walls`), Pa."""
    x, _, z = size
    area = [np.pi / 4 * x**2, np.pi / 4 * x**2, np.pi * x * z] if cylinder else np.prod(size) / np.repeat(size, 2)
    return float(np.mean(state.walls.normal_force() / area))


def settled_stress(state, size, steps: int, cylinder: bool = False) -> float:
    """Cycle `steps` steps; the mean wall stress over their second half, Pa."""
    samples = []
    for _ in range(SAMPLES_PER_SERVO):
        advance(state, steps // SAMPLES_PER_SERVO)
        samples.append(wall_stress(state, size, cylinder))
    return float(np.mean(samples[SAMPLES_PER_SERVO // 2:]))
