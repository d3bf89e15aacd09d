"""The clumped genesis' floater rules and its loop (`clump_genesis`): the exact size at which a
growing clump's pebble reaches a disk or a wall, PFC's count of a clump's contacts (pebble by
pebble, the whole clump's), a floater wedged to its third contact and no further than a round
allows, and a small genesis that ends with no floater at the pressure. Nothing here is timed:
the genesis time is `benchmarks/clump_genesis.py`'s.
"""

import logging

import numpy as np
import pytest

from rockcal.specimens import clump_genesis
from rockcal.specimens.clump_genesis import (
    MAX_FLOATER_GROWTH,
    ClumpedGrains,
    floating_clumps,
    sizes_to_reach,
    vessel_contacts,
)
from rockcal.materials.clump_templates import template
from rockcal.specimens.packing import PRESSURE_TOLERANCE
from rockcal.materials.parallel_bond import MicroParams


def gap(centroid, offset, radius, size, pos, reach_radius):
    return np.hypot(*(centroid + np.multiply.outer(size, offset) - pos).T) - size * radius - reach_radius


def test_sizes_to_reach_solve_the_first_overlap_exactly():
    rng = np.random.default_rng(3)
    checked = 0
    for _ in range(300):
        offset = rng.normal(size=2)
        offset *= rng.uniform(0.0, 1.3) / np.hypot(*offset)  # inside the pebble, or out of it
        radius = rng.uniform(0.4, 1.0)
        centroid = rng.normal(size=2) * 0.1
        pos, reach_radius = rng.normal(size=(6, 2)) * 4, rng.uniform(0.2, 1.0, 6)
        overlap = 0.01
        size = sizes_to_reach(centroid, offset, radius, pos, reach_radius, overlap)
        for k in np.flatnonzero(np.isfinite(size) & (size > 0)):
            g = gap(centroid, offset, radius, size[k], pos[k], reach_radius[k])
            assert g == pytest.approx(-overlap, abs=1e-9)  # overlapping by `overlap` there
            earlier = np.linspace(0.0, size[k], 50)[:-1]  # and not at any smaller size
            assert (gap(centroid, offset, radius, earlier, pos[k], reach_radius[k]) > -overlap).all()
            checked += 1
        for k in np.flatnonzero(~np.isfinite(size)):  # never: the gap only opens
            later = np.linspace(0.0, 100.0, 200)
            assert (gap(centroid, offset, radius, later, pos[k], reach_radius[k]) > -overlap).all()
    assert checked > 500


def test_a_ball_like_pebble_reaches_at_the_gap_plus_the_overlap():
    pos = np.array([[3.0, 0.0], [0.0, -5.0]])
    size = sizes_to_reach(np.zeros(2), np.zeros(2), 1.0, pos, np.array([1.0, 2.0]), 0.1)
    np.testing.assert_allclose(size, [2.0 + 0.1, 3.0 + 0.1])


def two_pebble_state(centroids, angles, sizes, width, height):
    grains = ClumpedGrains(template("two-pebble"))
    state = grains.new_state(np.array(centroids, float), np.array(sizes, float),
                             np.array(angles, float), MicroParams(E_c=1.0, mu=0.0), width, height)
    return grains, state


def test_a_clump_counts_its_pebbles_contacts_as_pfc_does():
    """Clump 0 lies flat on the bottom wall, clump 1 flat on it, pebble on pebble: clump 0 has 4
    contacts (two on the wall, two on clump 1) though it touches one clump and one wall, and is
    no floater; clump 1 has 2 and is one."""
    t = template("two-pebble")
    r, d = t.radii[0], np.hypot(*t.offsets[0])  # pebble radius and its offset, in sizes
    size = 1e-3
    y0 = r * size  # the pebbles resting on the bottom wall
    grains, state = two_pebble_state([[5e-3, y0], [5e-3, y0 + 2 * r * size]], [0.0, 0.0],
                                     [size, size], 2e-2, 2e-2)
    p = state.particles
    counts = vessel_contacts(p.pos, p.radius, grains.clump_of, 2e-2, 2e-2)
    assert counts.tolist() == [4, 2]  # clump 0: two on the wall, two on clump 1
    assert floating_clumps(p.pos, p.radius, grains.clump_of, 2e-2, 2e-2).tolist() == [False, True]
    assert clump_genesis.clump_contacts(p.pos, p.radius, grains.clump_of).tolist() == [1, 1]
    assert d < r  # the template's pebbles cover the centroid


def test_a_floater_is_wedged_to_its_third_contact_within_a_round_s_growth():
    """A two-pebble clump in a ring of six larger others turned at random: it grows until its third
    nearest pebble overlaps it by the overlap asked for (by more if it did at once), or, where
    that lies farther than a round's growth, by the round's growth only; the others keep their
    size."""
    width = height = 4e-2
    size, overlap = 1e-3, 1e-4
    start = 0.99 * size  # the floater, a little smaller than its ring
    cap = start * (1 + MAX_FLOATER_GROWTH)
    cases = []
    for seed in range(40):
        rng = np.random.default_rng(seed)
        spacing = rng.uniform(1.9, 2.3)
        ring = [[2e-2 + spacing * size * np.cos(a), 2e-2 + spacing * size * np.sin(a)]
                for a in np.linspace(0, 2 * np.pi, 7)[:-1]]
        grains, state = two_pebble_state([[2e-2, 2e-2]] + ring, rng.uniform(0, np.pi, 7),
                                         [start] + [size] * 6, width, height)
        floating = np.arange(7) == 0
        grown = grains.wedge_floaters(state, floating, width, height, np.full(7, overlap))
        assert (grown[1:] == size).all()
        assert start * (1 + overlap) <= grown[0] <= cap * (1 + 1e-12)
        grains.resize(state, grown)
        p, own = state.particles, np.flatnonzero(grains.clump_of == 0)
        gaps = [np.hypot(*(p.pos[q] - p.pos[j])) - p.radius[q] - p.radius[j]
                for q in own for j in np.flatnonzero(grains.clump_of != 0)]
        third = np.sort(gaps)[2]
        if grown[0] >= cap * (1 - 1e-12):
            assert third > -overlap * start
            cases.append("capped")
        elif grown[0] <= start * (1 + overlap) * (1 + 1e-12):
            assert third <= -overlap * start * (1 - 1e-6)
            cases.append("at once")
        else:
            assert third == pytest.approx(-overlap * start, rel=1e-6)
            cases.append("wedged")
    assert set(cases) == {"capped", "at once", "wedged"}


@pytest.mark.parametrize("shape", ["two-pebble", "three-pebble"])
def test_a_small_clumped_genesis_ends_at_the_pressure_with_no_floater(shape, caplog):
    width, height = 8e-3, 16e-3
    with caplog.at_level(logging.INFO, logger="rockcal.specimens.clump_genesis"):
        pos, radius, pressure, clump_of = clump_genesis.pack_clumps(
            template(shape), width, height, 0.5e-3, 1.25, 1, 0.09, 0.1)
    assert not floating_clumps(pos, radius, clump_of, width, height).any()
    assert pressure == pytest.approx(0.1, rel=PRESSURE_TOLERANCE)
    assert not [r for r in caplog.records if r.levelno >= logging.WARNING]
    assert any("rounds" in r.getMessage() for r in caplog.records)
    # every clump whole and rigid: its pebbles at the template's offsets, scaled alike
    t = template(shape)
    k = t.n_pebbles
    sizes = radius.reshape(-1, k) / t.radii
    np.testing.assert_allclose(sizes, sizes[:, :1].repeat(k, axis=1), rtol=1e-12)
    assert (np.bincount(clump_of) == k).all()
