"""The genesis of a clumped specimen (FISHTank's clumped materials): PFC's genesis
(`rockcal.specimens.genesis`) with every grain a rigid clump of a template's pebbles
(`clump_templates`), randomly oriented.

A grain's size is its equivalent radius, the radius of a disk of its area: the cloud's sizes are
drawn as the balls' are (`packing.pack_grains`), each clump is placed at a random centre (the
same draws as a ball's) and turned by a random angle (drawn after them), and grain scaling
scales every clump about its centroid, its pebbles' offsets and radii alike. The pebbles of one
clump are numbered next to each other, the clumps in the spatial order of their centroids; bonds
join pebbles of different clumps within the installation gap, pebble to pebble (`clump_bonds`),
never two of one clump.

A floater, as PFC counts a clump's contacts: a clump with fewer than MIN_CONTACTS (3) contacts,
a contact being one of its pebbles touching a pebble of another clump or a wall (two of its
pebbles on one neighbour are two contacts: together they hold its turning as well as its
sliding). The rule is the whole clump's, never a pebble's (`floating_clumps`).

Clumps of two or more pebbles are packed by `pack_clumps` in the balls' steps (cloud, growth,
grain scaling to the pressure P_m, floaters), with three differences that frictionless clumps
call for:
- the cloud is scaled to CLUMP_JAMMING_FRACTION, above the clumps' jamming (elongated grains jam
  denser than disks), so that grain scaling reaches P_m from above, as the balls' does: below
  jamming frictionless clumps turn and slide into any room they are given, and a servo growing
  them towards P_m from below overshoots, collapses and creeps;
- the pressure and the floaters are one loop of rounds. Each round scales every clump by
  exp(step), step = SERVO_GAIN (P_m - σ) / K plus an integral part, INTEGRAL_GAIN times the sum
  of those terms since the stress came near P_m (K = 2 E_c, the balls' contact estimate of the
  packing's stiffness per unit log-size; the integral takes up the slow creep of frictionless
  clumps at P_m), the step doubling round after round while the wall stress σ stays below
  P_m / PRESSURE_BAND (up to MAX_SERVO_BOOST). While σ lies within a factor PRESSURE_BAND of
  P_m, the round first enlarges all the floaters of that round. A round cycles the servo's steps
  (`packing.scale_to_pressure`'s) until σ first comes within that band, then the floater
  rounds' steps. The loop ends once no floater is left and σ is within PRESSURE_TOLERANCE of P_m;
- a floater is enlarged about its centroid, its pebbles as they lie, until its MIN_CONTACTS-th
  nearest contact overlaps by `overlap` x its size (each pebble's reach solved exactly,
  `sizes_to_reach`), but by at most
  MAX_FLOATER_GROWTH a round (a rattler grown at once into a far neighbour pushes the whole
  packing far above P_m), and that overlap doubles each time the same clump is found floating
  again (up to 2^MAX_FLOATER_DOUBLINGS): a clump in a cage turns and slides off the contacts it
  was grown to, which a ball cannot, so it must be wedged in.

One-pebble clumps ("ball") take the balls' path (`packing.pack_grains`, through
`ClumpedGrains`' methods): every step is a ball's, to the bit (the engine moves a one-pebble
clump as the ball, and the floater rules reduce to the balls'). The clumps' genesis is versioned
by CLUMP_GENESIS_VERSION: a packing of clumps made under an earlier one is another packing.
"""

from __future__ import annotations

import logging
import math

import numpy as np

from rockcal.specimens import packing
from rockcal.dem.clump_motion import clump
from rockcal.materials.clump_templates import ClumpTemplate
from rockcal.specimens.genesis import MIN_CONTACTS, PRESSURE_BAND, check_given_up, cloud_radii, wall_gaps
from rockcal.dem.neighbours import CONTACT_GAP, install_bonds, near_pairs, pair_gaps, spatial_order
from rockcal.specimens.packing import JAMMING_FRACTION, pack_grains
from rockcal.dem.simulate import advance, rebuild_neighbours
from rockcal.materials.parallel_bond import MicroParams, new_state
from rockcal.materials.units import GPa, MPa

log = logging.getLogger(__name__)

# 2: clumps packed from above jamming, pressure and floaters in one loop, PFC's contact count
# 3: no BLAS and none of numpy's vectorised cos, sin, exp or pow: the same on every processor
CLUMP_GENESIS_VERSION = 3
CLUMP_JAMMING_FRACTION = 0.90  # the cloud of clumps starts above jamming
SERVO_GAIN = 0.75  # of a full step to the pressure at the contacts' stiffness estimate
INTEGRAL_GAIN = 0.1
MAX_SERVO_BOOST = 16.0  # the step's doubling below the band
MAX_FLOATER_GROWTH = 0.02  # a floater grows by at most this fraction of its size a round
MAX_FLOATER_DOUBLINGS = 6  # a floater found again overlaps up to 2^6 x the first overlap
CLUMP_ROUNDS = packing.MAX_SERVO_ROUNDS + packing.FLOATER_ROUNDS


def clump_contacts(pos, radius, clump_of) -> np.ndarray:
    """Per clump, the number of other clumps its pebbles touch."""
    pi, pj, _ = pair_gaps(pos, radius, CONTACT_GAP * radius.min())
    ci, cj = clump_of[pi], clump_of[pj]
    apart = ci != cj
    touching = np.unique(np.column_stack([np.minimum(ci, cj), np.maximum(ci, cj)])[apart], axis=0)
    return np.bincount(touching.ravel(), minlength=int(clump_of.max()) + 1)


def clump_wall_gaps(pos, radius, clump_of, width: float, height: float) -> np.ndarray:
    """Per clump, its gap to the vessel's left, right, bottom and top walls, (n_clumps, 4) m."""
    gaps = np.full((int(clump_of.max()) + 1, 4), np.inf)
    np.minimum.at(gaps, clump_of, wall_gaps(pos, radius, width, height))
    return gaps


def vessel_contacts(pos, radius, clump_of, width: float, height: float) -> np.ndarray:
    """Per clump, its contacts as PFC counts them: its pebbles' contacts with pebbles of other
    clumps and with the walls."""
    touch = CONTACT_GAP * radius.min()
    pi, pj, _ = pair_gaps(pos, radius, touch)
    ci, cj = clump_of[pi], clump_of[pj]
    apart = ci != cj
    n = int(clump_of.max()) + 1
    walls = np.count_nonzero(wall_gaps(pos, radius, width, height) <= touch, axis=1)
    return (np.bincount(np.concatenate([ci[apart], cj[apart]]), minlength=n)
            + np.bincount(clump_of, walls, minlength=n).astype(np.int64))


def floating_clumps(pos, radius, clump_of, width: float, height: float) -> np.ndarray:
    """True for the clumps with fewer than MIN_CONTACTS contacts (`vessel_contacts`)."""
    return vessel_contacts(pos, radius, clump_of, width, height) < MIN_CONTACTS


def clump_bonds(pos, radius, clump_of, gap: float) -> np.ndarray:
    """The pairs of pebbles i < j of different clumps whose gap is <= `gap` (m): the bonds of
    PFC's installation gap, pebble to pebble."""
    pairs = install_bonds(pos, radius, gap)
    return pairs[clump_of[pairs[:, 0]] != clump_of[pairs[:, 1]]]


def sizes_to_reach(centroid, offset, radius, pos, reach_radius, overlap) -> np.ndarray:
    """For a pebble at centroid + s `offset` of radius s `radius` (s: its clump's size), the
    smallest s >= 0 at which it overlaps each disk (`pos`, `reach_radius`) by `overlap` (m):
    the root of |a + s u| = s ρ + L (a = centroid - pos, L = reach_radius - overlap), a
    quadratic in s; inf where no size reaches, 0 where it overlaps already at s = 0."""
    # products written out: a BLAS dot product (numpy's @) rounds by the processor's kernel
    a = centroid - pos
    far = reach_radius - overlap
    A = offset[0] * offset[0] + offset[1] * offset[1] - radius * radius
    B = 2.0 * (a[:, 0] * offset[0] + a[:, 1] * offset[1] - radius * far)
    C = a[:, 0] * a[:, 0] + a[:, 1] * a[:, 1] - far * far
    with np.errstate(invalid="ignore", divide="ignore"):
        if A == 0.0:  # a linear equation
            root = np.where(B < 0.0, -C / B, np.inf)
        else:
            # A < 0 (the pebble covers the centroid): overlapping from the larger root on;
            # A > 0: between the roots. Either way the first is (-B - sqrt(disc)) / 2A.
            disc = B * B - 4.0 * A * C
            root = (-B - np.sqrt(np.maximum(disc, 0.0))) / (2.0 * A)
            root = np.where((disc >= 0.0) & (root >= 0.0), root, np.inf)
    return np.where(C <= 0.0, 0.0, root)


class ClumpedGrains:
    """Grains that are rigid clumps of `template`'s pebbles, sized by their equivalent radii, for
    `packing.pack_grains` (one-pebble clumps) and `pack_clumps`; after `new_state`, `clump_of`
    numbers each pebble's clump."""

    jamming_fraction = JAMMING_FRACTION

    def __init__(self, template: ClumpTemplate):
        self.template = template
        self.extent = template.extent

    def orientations(self, rng: np.random.Generator, n: int) -> np.ndarray:
        if self.template.n_pebbles == 1:
            return np.zeros(n)  # one pebble at the centroid: no orientation, no draw
        return rng.uniform(0.0, 2.0 * np.pi, n)

    def new_state(self, pos, size, angle, params, width: float, height: float):
        """The clumps at centroids `pos`, equivalent radii `size` and angles `angle` in the
        vessel's engine state (`Balls.new_state`'s), at rest."""
        t = self.template
        k = t.n_pebbles
        # the C library's cos and sin: numpy's vectorised ones round by the processor (AVX-512)
        c = np.array([math.cos(a) for a in angle])[:, None]
        s = np.array([math.sin(a) for a in angle])[:, None]
        ox, oy = t.offsets[:, 0], t.offsets[:, 1]  # turned counter-clockwise, per clump
        self.unit_offsets = np.stack([c * ox - s * oy, s * ox + c * oy], axis=-1).reshape(-1, 2)
        self.unit_radii = np.tile(t.radii, len(size))
        self.clump_of = np.repeat(np.arange(len(size)), k)
        self.size = np.array(size, float)
        per_pebble = self.size[self.clump_of]
        state = new_state(np.repeat(pos, k, axis=0) + self.unit_offsets * per_pebble[:, None],
                          self.unit_radii * per_pebble, np.empty((0, 2)), params,
                          walls=(0.0, width, 0.0, height), wall_active=(True,) * 4,
                          contact_stiffness="pfc5")
        clump(state, self.clump_of, params.density)
        return state

    def sizes(self, state) -> np.ndarray:
        return self.size

    def resize(self, state, sizes: np.ndarray) -> None:
        """Scale every clump about its centroid to the equivalent radii `sizes`."""
        self.size = np.array(sizes, float)
        clumps, p = state.clumps, state.particles
        p.radius[:] = self.unit_radii * self.size[self.clump_of]
        q = clumps.pebbles
        clumps.offsets[:] = self.unit_offsets[q] * self.size[self.clump_of[q]][:, None]
        clumps.carry_pebbles(p)

    def enlarge_floaters(self, state, width: float, height: float, overlap: float) -> np.ndarray:
        """One-pebble clumps (balls, in `packing.pack_grains`): the sizes with every floater
        grown about its centroid until it overlaps its MIN_CONTACTS-th nearest clump or wall by
        `overlap` x its size, the nearer ones more (`genesis.enlarge_floaters`, clump by clump;
        the clumps grown earlier in the pass as grown)."""
        p, clumps = state.particles, state.clumps
        pos, radius = p.pos.copy(), p.radius.copy()
        size = self.size.copy()
        walls = clump_wall_gaps(pos, radius, self.clump_of, width, height)
        first, pebbles = clumps.first, clumps.pebbles
        for k in np.flatnonzero(floating_clumps(pos, radius, self.clump_of, width, height)):
            own = pebbles[first[k]:first[k + 1]]
            gaps = np.hypot(*(pos - pos[own[0]]).T) - radius - radius[own[0]]
            for q in own[1:]:
                gaps = np.minimum(gaps, np.hypot(*(pos - pos[q]).T) - radius - radius[q])
            nearest_clump = np.full(len(size), np.inf)
            np.minimum.at(nearest_clump, self.clump_of, gaps)
            nearest_clump[k] = np.inf
            nearest = np.partition(np.concatenate([nearest_clump, walls[k]]), MIN_CONTACTS - 1)
            size[k] += max(0.0, nearest[MIN_CONTACTS - 1]) + overlap * size[k]
            centroid = clumps.pos[k]
            pos[own] = centroid + self.unit_offsets[own] * size[k]
            radius[own] = self.unit_radii[own] * size[k]
        return size

    def count_floaters(self, state, width: float, height: float) -> int:
        p = state.particles
        return int(np.count_nonzero(floating_clumps(p.pos, p.radius, self.clump_of, width, height)))

    def wedge_floaters(self, state, floating, width: float, height: float,
                       overlaps: np.ndarray) -> np.ndarray:
        """The sizes with each clump of `floating` grown about its centroid until its
        MIN_CONTACTS-th nearest contact (pebble to pebble of another clump, or pebble to wall)
        overlaps by its `overlaps` x its size, the nearer ones more, but by at most
        MAX_FLOATER_GROWTH of its size; clump by clump, those grown earlier as grown."""
        p, clumps = state.particles, state.clumps
        pos, radius = p.pos.copy(), p.radius.copy()
        size = self.size.copy()
        first, pebbles, clump_of = clumps.first, clumps.pebbles, self.clump_of
        # only pebbles this near can be reached within the growth allowed (both clumps growing)
        reach = 2.0 * MAX_FLOATER_GROWTH * self.extent * size.max()
        pi, pj = near_pairs(pos, radius, reach)
        apart = clump_of[pi] != clump_of[pj]
        pi, pj = pi[apart], pj[apart]
        side_i, side_j = np.concatenate([pi, pj]), np.concatenate([pj, pi])
        order = np.argsort(clump_of[side_i], kind="stable")
        side_i, side_j = side_i[order], side_j[order]
        starts = np.searchsorted(clump_of[side_i], np.arange(len(size) + 1))
        bounds = np.array([width, height])
        for k in np.flatnonzero(floating):
            own = pebbles[first[k]:first[k + 1]]
            centroid = clumps.pos[k]
            cap = size[k] * (1.0 + MAX_FLOATER_GROWTH)
            delta = overlaps[k] * size[k]
            mine, theirs = side_i[starts[k]:starts[k + 1]], side_j[starts[k]:starts[k + 1]]
            turned = (pos[own] - centroid) / size[k]  # the pebbles' offsets as the clump lies now
            needed = [np.full(MIN_CONTACTS, np.inf)]
            for q, u in zip(own, turned):
                rho = self.unit_radii[q]
                others = theirs[mine == q]
                needed.append(sizes_to_reach(centroid, u, rho, pos[others], radius[others], delta))
                # the walls: left, right, bottom, top
                for low, sign, axis in ((0.0, 1.0, 0), (bounds[0], -1.0, 0), (0.0, 1.0, 1),
                                        (bounds[1], -1.0, 1)):
                    speed = rho - sign * u[axis]  # the pebble's approach to the wall per size
                    if speed > 0.0:
                        needed.append([(sign * (centroid[axis] - low) + delta) / speed])
            nth = np.partition(np.concatenate(needed), MIN_CONTACTS - 1)[MIN_CONTACTS - 1]
            size[k] = min(cap, max(size[k] * (1.0 + overlaps[k]), nth))
            pos[own] = centroid + turned * size[k]
            radius[own] = self.unit_radii[own] * size[k]
        return size


def pack_clumps(template: ClumpTemplate, width: float, height: float, rmin: float,
                radius_ratio: float, seed: int, cloud_porosity: float, pressure_mpa: float):
    """The cloud of clumps of `template` packed in [0, width] x [0, height] to the pressure
    (module docstring; one-pebble clumps by `packing.pack_grains`): pebble centres and radii (m)
    (the clumps in the spatial order of their centroids, each one's pebbles next to each other),
    the mean wall stress reached (MPa) and each pebble's clump."""
    grains = ClumpedGrains(template)
    if template.n_pebbles == 1:
        state, pressure = pack_grains(grains, width, height, rmin, radius_ratio, seed,
                                      cloud_porosity, pressure_mpa)
    else:
        state, pressure = _pack(grains, width, height, rmin, radius_ratio, seed, cloud_porosity,
                                pressure_mpa)
    clumps, p = state.clumps, state.particles
    order = spatial_order(clumps.pos, 4 * radius_ratio * rmin)
    pebbles = np.concatenate([clumps.pebbles[clumps.first[c]:clumps.first[c + 1]] for c in order])
    renumber = np.empty(len(order), np.int64)
    renumber[order] = np.arange(len(order))
    return p.pos[pebbles].copy(), p.radius[pebbles].copy(), pressure, renumber[grains.clump_of[pebbles]]


def _pack(grains: ClumpedGrains, width: float, height: float, rmin: float, radius_ratio: float,
          seed: int, cloud_porosity: float, pressure_mpa: float):
    """Clumps of two or more pebbles packed to the pressure (module docstring): the engine state
    and the mean wall stress reached (MPa)."""
    # the cloud, its draws and its growth as `packing.pack_grains`'s
    rng = np.random.default_rng(seed)
    radius = cloud_radii(rng, width * height, rmin, radius_ratio, cloud_porosity)
    n = len(radius)
    radius *= min(1.0, np.sqrt(CLUMP_JAMMING_FRACTION / (np.pi * (radius**2).sum() / (width * height))))
    rmax = radius.max()
    reach = rmax * grains.extent
    pos = np.column_stack([rng.uniform(reach, width - reach, n), rng.uniform(reach, height - reach, n)])
    angle = grains.orientations(rng, n)
    order = spatial_order(pos, 4 * rmax)
    pos, radius, angle = pos[order], radius[order], angle[order]
    params = MicroParams(E_c=packing.PACKING_MODULUS_GPA, mu=0.0, damping=0.7)
    state = grains.new_state(pos, radius, angle, params, width, height)
    for stage in range(packing.GROWTH_STAGES):
        grains.resize(state, radius * (0.5 + 0.5 * (stage + 1) / packing.GROWTH_STAGES))
        rebuild_neighbours(state)
        advance(state, packing.STEPS_PER_STAGE)

    rows = max(width, height) / (2.0 * radius.mean())
    servo_steps = min(packing.STEPS_PER_SERVO, int(packing.SERVO_STEPS_PER_ROW * rows))
    floater_steps = min(packing.STEPS_PER_FLOATER_ROUND, int(packing.FLOATER_STEPS_PER_ROW * rows))
    target = pressure_mpa * MPa
    stiffness = 2.0 * packing.PACKING_MODULUS_GPA * GPa  # d(stress) / d(log size), contacts' estimate
    overlap = target / (packing.PACKING_MODULUS_GPA * GPa)  # ~ a contact's at P_m, / R
    found = np.zeros(n, np.int64)  # how often each clump was found floating
    integral, boost, near = 0.0, 1.0, False
    stress = packing.settled_stress(state, servo_steps)
    floater_rounds = 0
    for round_ in range(CLUMP_ROUNDS):
        in_band = target / PRESSURE_BAND < stress < PRESSURE_BAND * target
        sizes = grains.size
        if in_band:
            floating = floating_clumps(state.particles.pos, state.particles.radius,
                                       grains.clump_of, width, height)
            log.debug("clump round %d: %d floaters, wall stress %.3g MPa", round_,
                      np.count_nonzero(floating), stress / MPa)
            if not floating.any() and abs(stress - target) < packing.PRESSURE_TOLERANCE * target:
                break
            found += floating
            overlaps = overlap * np.ldexp(1.0, np.minimum(np.maximum(found - 1, 0), MAX_FLOATER_DOUBLINGS))
            sizes = grains.wedge_floaters(state, floating, width, height, overlaps)
            integral += INTEGRAL_GAIN * (target - stress) / stiffness
            floater_rounds += 1
        else:
            log.debug("clump round %d: wall stress %.3g MPa", round_, stress / MPa)
            integral = 0.0
        near = near or in_band
        boost = min(MAX_SERVO_BOOST, 2.0 * boost) if stress * PRESSURE_BAND < target else 1.0
        grains.resize(state, sizes * math.exp(integral + boost * SERVO_GAIN * (target - stress) / stiffness))
        rebuild_neighbours(state)
        stress = packing.settled_stress(state, floater_steps if near else servo_steps)
    else:
        check_given_up("clumped", "clumps still", stress / MPa, pressure_mpa,
                       grains.count_floaters(state, width, height), n)
        log.warning("genesis of %g x %g mm clumps, seed %d: %d of %d clumps still have fewer "
                    "than %d contacts, wall stress %.3g MPa, after %d rounds", 1e3 * width,
                    1e3 * height, seed, grains.count_floaters(state, width, height), n,
                    MIN_CONTACTS, stress / MPa, CLUMP_ROUNDS)
    log.info("clumped genesis of %g x %g mm, seed %d: %d rounds, %d of them floater rounds "
             "(near the pressure), %d steps", 1e3 * width, 1e3 * height, seed, round_ + 1, floater_rounds, state.step)
    return state, stress / MPa
