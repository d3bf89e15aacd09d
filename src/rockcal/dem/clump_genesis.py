"""The genesis of a clumped specimen (FISHTank's clumped materials): PFC's genesis
(`rockcal.dem.genesis`, `packing.pack_grains`) with every grain a rigid clump of a template's
pebbles (`clump_templates`), randomly oriented.

A grain's size is its equivalent radius, the radius of a disk of its area: the cloud's sizes are
drawn as the balls' are, each clump is placed at a random centre (the same draws as a ball's)
and turned by a random angle (drawn after them), and grain scaling scales every clump about its
centroid, its pebbles' offsets and radii alike; the servo's gain grows while the stress stays
short of the pressure (`packing.Servo`: frictionless clumps turn and slide into room, so their
stress relaxes more than the contacts alone say). A floater is a clump touching fewer than 3 other
clumps or walls; it is enlarged, about its centroid, until its 3rd nearest clump or wall is
reached, as a floating ball. The pebbles of one clump are numbered next to each other, the
clumps in the spatial order of their centroids; bonds join pebbles of different clumps within
the installation gap, pebble to pebble (`clump_bonds`), never two of one clump.

With the "ball" template (one pebble) every step is a ball's, to the bit: the engine moves a
one-pebble clump as the ball, and the floater rules reduce to the balls'.
"""

from __future__ import annotations

import numpy as np

from rockcal.dem.clump_motion import clump
from rockcal.dem.clump_templates import ClumpTemplate
from rockcal.dem.genesis import CONTACT_GAP, MIN_CONTACTS, install_bonds, pair_gaps, wall_gaps
from rockcal.dem.neighbours import spatial_order
from rockcal.dem.packing import JAMMING_FRACTION, pack_grains

SERVO_GROWTH = 2.0  # the servo's gain doubles round after round short of the pressure (`packing.Servo`)
from rockcal.materials.parallel_bond import new_state


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


def floating_clumps(pos, radius, clump_of, width: float, height: float) -> np.ndarray:
    """True for the clumps touching fewer than MIN_CONTACTS other clumps and walls."""
    walls = clump_wall_gaps(pos, radius, clump_of, width, height) <= CONTACT_GAP * radius.min()
    return clump_contacts(pos, radius, clump_of) + walls.sum(axis=1) < MIN_CONTACTS


def clump_bonds(pos, radius, clump_of, gap: float) -> np.ndarray:
    """The pairs of pebbles i < j of different clumps whose gap is <= `gap` (m): the bonds of
    PFC's installation gap, pebble to pebble."""
    pairs = install_bonds(pos, radius, gap)
    return pairs[clump_of[pairs[:, 0]] != clump_of[pairs[:, 1]]]


class ClumpedGrains:
    """Grains that are rigid clumps of `template`'s pebbles, sized by their equivalent radii, for
    `packing.pack_grains`; after `new_state`, `clump_of` numbers each pebble's clump."""

    jamming_fraction = JAMMING_FRACTION

    def __init__(self, template: ClumpTemplate):
        self.template = template
        self.extent = template.extent
        # a one-pebble clump is a ball, which turns into no room: the balls' servo
        self.servo_growth = SERVO_GROWTH if template.n_pebbles > 1 else 1.0

    def orientations(self, rng: np.random.Generator, n: int) -> np.ndarray:
        if self.template.n_pebbles == 1:
            return np.zeros(n)  # one pebble at the centroid: no orientation, no draw
        return rng.uniform(0.0, 2.0 * np.pi, n)

    def new_state(self, pos, size, angle, params, width: float, height: float):
        """The clumps at centroids `pos`, equivalent radii `size` and angles `angle` in the
        vessel's engine state (`Balls.new_state`'s), at rest."""
        t = self.template
        k = t.n_pebbles
        c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
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
        """The sizes with every floating clump grown about its centroid until it overlaps its
        MIN_CONTACTS-th nearest clump or wall by `overlap` x its size, the nearer ones more
        (`genesis.enlarge_floaters`, clump by clump, its nearest gaps from any of its pebbles;
        the pebbles of clumps grown earlier in the pass as grown)."""
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


def pack_clumps(template: ClumpTemplate, width: float, height: float, rmin: float,
                radius_ratio: float, seed: int, cloud_porosity: float, pressure_mpa: float):
    """The cloud of clumps of `template` packed in [0, width] x [0, height] to the pressure
    (`packing.pack_grains`): pebble centres and radii (m) (the clumps in
    the spatial order of their centroids, each one's pebbles next to each other), the mean
    wall stress reached (MPa) and each pebble's clump."""
    grains = ClumpedGrains(template)
    state, pressure = pack_grains(grains, width, height, rmin, radius_ratio, seed, cloud_porosity,
                                  pressure_mpa)
    clumps, p = state.clumps, state.particles
    order = spatial_order(clumps.pos, 4 * radius_ratio * rmin)
    pebbles = np.concatenate([clumps.pebbles[clumps.first[c]:clumps.first[c + 1]] for c in order])
    renumber = np.empty(len(order), np.int64)
    renumber[order] = np.arange(len(order))
    return p.pos[pebbles].copy(), p.radius[pebbles].copy(), pressure, renumber[grains.clump_of[pebbles]]
