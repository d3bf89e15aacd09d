"""Carving specimens out of a packing: geometric truths of the region tests, of removing
particles (with their bonds, and the particles left without any bond) and of cutting the
bonds across a line."""

import numpy as np
import pytest

from rockcal.specimens.carving import (cut_bonds, inside_circle, keep_particles, outside_rectangle)
from rockcal.dem.neighbours import near_pairs
from rockcal.specimens.specimen import Specimen

R = 0.5e-3


def packing(seed, nx=24, ny=16):
    """A jittered triangular lattice of polydisperse disks, pairs closer than 0.2 R bonded;
    each bond carries two distinct strength draws so that we can follow it."""
    rng = np.random.default_rng(seed)
    rows = [np.column_stack([(np.arange(nx) + 0.5 * (k % 2)) * 2 * R,
                             np.full(nx, k * np.sqrt(3) * R)]) for k in range(ny)]
    pos = np.vstack(rows) + R + rng.uniform(-0.1 * R, 0.1 * R, (nx * ny, 2))
    radius = rng.uniform(0.8 * R, 1.0 * R, nx * ny)
    i, j = near_pairs(pos, radius, 0.2 * R)
    bonds = np.column_stack([i, j])
    draws = rng.random((len(bonds), 2))
    return Specimen(pos, radius, bonds, (nx + 1) * 2 * R, ny * np.sqrt(3) * R + 2 * R,
                    f"test packing {seed}", draws)


def bond_set(spec):
    """The bonds as a set of ((x_i, y_i), (x_j, y_j)), keyed by the particles' positions."""
    return {tuple(map(tuple, spec.pos[b])) for b in spec.bonds}


@pytest.mark.parametrize("seed", [1, 2])
def test_outside_rectangle_is_no_overlap_with_the_rectangle(seed):
    """A disk is outside the rectangle iff its centre is at least R from the rectangle's
    closest point (corners rounded, not the bounding box); touching counts as outside."""
    rng = np.random.default_rng(seed)
    pos = rng.uniform(-3e-3, 3e-3, (2000, 2))
    radius = rng.uniform(0.2e-3, 0.8e-3, 2000)
    x0, x1, y0, y1 = -1e-3, 0.5e-3, -0.2e-3, 1.5e-3
    closest = np.column_stack([np.clip(pos[:, 0], x0, x1), np.clip(pos[:, 1], y0, y1)])
    overlaps = np.hypot(*(pos - closest).T) < radius
    np.testing.assert_array_equal(outside_rectangle(pos, radius, x0, x1, y0, y1), ~overlaps)
    # by hand: diagonal off a corner (inside the bounding box of the rounded rectangle), a
    # centre inside, a disk just touching an edge, one just into it
    r = 0.5e-3
    cases = np.array([[x1 + 0.75 * r, y1 + 0.75 * r],  # 1.06 r from the corner
                      [0.0, 0.0],
                      [x1 + r, 0.0],
                      [x1 + 0.999 * r, 0.0]])
    np.testing.assert_array_equal(outside_rectangle(cases, np.full(4, r), x0, x1, y0, y1),
                                  [True, False, True, False])


def test_inside_circle_means_every_point_of_the_disk_is_inside():
    """A disk is wholly inside the circle iff all points of its rim are (sampled at 720
    angles; disks within 0.1 % of the boundary are left out of the comparison)."""
    rng = np.random.default_rng(4)
    pos = rng.uniform(-5e-3, 5e-3, (1500, 2))
    radius = rng.uniform(0.1e-3, 1e-3, 1500)
    centre, big = np.array([0.3e-3, -0.2e-3]), 4e-3
    angles = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    rim = pos[:, None, :] + radius[:, None, None] * np.stack([np.cos(angles), np.sin(angles)], -1)
    far = np.hypot(*(rim - centre).transpose(2, 0, 1)).max(axis=1)
    clear = np.abs(np.hypot(*(pos - centre).T) + radius - big) > 1e-3 * big
    got = inside_circle(pos, radius, centre, big)
    np.testing.assert_array_equal(got[clear], (far <= big)[clear])
    assert 100 < np.count_nonzero(got) < 1400


def check_kept(spec, keep, out):
    """The truths of keep_particles: the survivors are the kept particles that keep a bond to
    another kept one, in their original order; the bonds are exactly the original bonds
    between survivors (with their draws); indices are valid, i < j."""
    kept_bonds = keep[spec.bonds[:, 0]] & keep[spec.bonds[:, 1]]
    has_bond = np.zeros(spec.n_particles, bool)
    has_bond[spec.bonds[kept_bonds].ravel()] = True
    survivors = keep & has_bond
    np.testing.assert_array_equal(out.pos, spec.pos[survivors])
    np.testing.assert_array_equal(out.radius, spec.radius[survivors])
    assert out.bonds.min() >= 0 and out.bonds.max() < out.n_particles
    assert np.all(out.bonds[:, 0] < out.bonds[:, 1])
    assert bond_set(out) == {tuple(map(tuple, spec.pos[b])) for b in spec.bonds[kept_bonds]}
    expected_draws = {tuple(map(tuple, spec.pos[b])): tuple(d)
                      for b, d in zip(spec.bonds[kept_bonds], spec.bond_draws[kept_bonds])}
    got_draws = {tuple(map(tuple, out.pos[b])): tuple(d)
                 for b, d in zip(out.bonds, out.bond_draws)}
    assert got_draws == expected_draws
    bonded = np.zeros(out.n_particles, bool)
    bonded[out.bonds.ravel()] = True
    assert bonded.all()  # no floating particle left


def test_keep_particles_removes_the_rest_with_their_bonds_and_the_floaters():
    """Random selections: survivors and bonds as check_kept says; a particle whose bonded
    neighbours are all removed goes too."""
    spec = packing(3)
    rng = np.random.default_rng(5)
    for fraction in (0.9, 0.6, 0.3):
        keep = rng.random(spec.n_particles) < fraction
        out = keep_particles(spec, keep, "kept")
        check_kept(spec, keep, out)
        assert out.label == "kept"
        assert (out.width_m, out.height_m) == (spec.width_m, spec.height_m)
    # an isolated particle: all its bonded neighbours removed
    k = spec.n_particles // 2
    keep = np.ones(spec.n_particles, bool)
    neighbours = spec.bonds[(spec.bonds == k).any(axis=1)].ravel()
    keep[neighbours[neighbours != k]] = False
    out = keep_particles(spec, keep, "isolated", width_m=1.0, height_m=2.0)
    assert not np.any(np.all(out.pos == spec.pos[k], axis=1))
    check_kept(spec, keep, out)
    assert (out.width_m, out.height_m) == (1.0, 2.0)


def test_notch_leaves_no_disk_in_the_slot():
    """A notch (rectangle from below the specimen up to a depth) removes every disk that
    overlaps it and nothing that doesn't (apart from floaters)."""
    spec = packing(6)
    mid, half, depth = spec.width_m / 2, 0.6 * R, 0.4 * spec.height_m
    keep = outside_rectangle(spec.pos, spec.radius, mid - half, mid + half, -1.0, depth)
    out = keep_particles(spec, keep, "notched")
    closest_x = np.clip(out.pos[:, 0], mid - half, mid + half)
    closest_y = np.clip(out.pos[:, 1], -1.0, depth)
    assert np.all(np.hypot(out.pos[:, 0] - closest_x, out.pos[:, 1] - closest_y) >= out.radius)
    check_kept(spec, keep, out)
    assert out.n_particles < spec.n_particles


def test_disk_carving_keeps_only_disks_wholly_inside():
    """A Brazilian disk: every survivor lies wholly inside the circle; every bonded pair wholly
    inside survives with its bond."""
    spec = packing(7, 20, 20)
    centre, big = np.array([spec.width_m / 2, spec.height_m / 2]), 0.45 * spec.height_m
    keep = inside_circle(spec.pos, spec.radius, centre, big)
    out = keep_particles(spec, keep, "disk")
    assert np.all(np.hypot(*(out.pos - centre).T) + out.radius <= big)
    check_kept(spec, keep, out)


def segments_intersect(p, q, a, b):
    """Proper intersection of segments pq and ab by orientations (no collinear cases)."""
    def orient(u, v, w):
        return np.sign((v[..., 0] - u[..., 0]) * (w[..., 1] - u[..., 1])
                       - (v[..., 1] - u[..., 1]) * (w[..., 0] - u[..., 0]))
    return ((orient(p, q, a) * orient(p, q, b) < 0) & (orient(a, b, p) * orient(a, b, q) < 0))


@pytest.mark.parametrize("seed, x_frac, top_frac", [(8, 0.5, 0.3), (9, 0.37, 0.8), (10, 0.5, 1.5)])
def test_cut_bonds_removes_exactly_the_bonds_crossing_the_line(seed, x_frac, top_frac):
    """A zero-width crack along x = const from below the specimen up to y_top: the bonds
    removed are those whose centre-to-centre segment crosses that segment; the others stay,
    with their draws, and no particle moves or goes."""
    spec = packing(seed)
    x, y_top = x_frac * spec.width_m, top_frac * spec.height_m
    out = cut_bonds(spec, x, y_top, "cut")
    p, q = spec.pos[spec.bonds[:, 0]], spec.pos[spec.bonds[:, 1]]
    a = np.broadcast_to([x, -1.0], p.shape)
    b = np.broadcast_to([x, y_top], p.shape)
    crossing = segments_intersect(p, q, a, b)
    assert crossing.any() and not crossing.all()
    np.testing.assert_array_equal(out.bonds, spec.bonds[~crossing])
    np.testing.assert_array_equal(out.bond_draws, spec.bond_draws[~crossing])
    np.testing.assert_array_equal(out.pos, spec.pos)
    np.testing.assert_array_equal(out.radius, spec.radius)
    assert out.label == "cut"
    if top_frac > 1:  # a crack right through: no bond joins the two halves
        left = spec.pos[:, 0] < x
        assert not np.any(left[out.bonds[:, 0]] != left[out.bonds[:, 1]])
