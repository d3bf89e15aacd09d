"""PFC's material genesis in 3D (`rockcal.specimens3d.packing`, `genesis`, `specimen`) on a small
cuboid vessel (`conftest.small_cuboid`): the walls feel the material pressure P_m, read afresh from the spheres'
overlaps with them (π E R × overlap over each face's area); no sphere has fewer than 3
contacts; a floater is grown to overlap its third nearest sphere or wall by its own overlap,
without cycling; exactly the pairs within the installation gap are bonded; the same seed makes the
same packing bit for bit, on one thread or two; a carved cylinder keeps the spheres centred inside it, each bonded.
"""

import numba
import numpy as np
import pytest

from rockcal.dem3d import neighbours

from rockcal.specimens.packing import PACKING_MODULUS_GPA, PRESSURE_TOLERANCE
from rockcal.specimens3d.genesis import DEFAULT_GENESIS_3D as GENESIS
from rockcal.specimens3d.genesis import enlarge_floaters, floaters, wall_gaps
from rockcal.specimens3d.packing import pack_vessel
from rockcal.specimens3d.specimen import carve_cylinder, random_specimen, vessel_floaters


@pytest.fixture
def cuboid(small_cuboid):
    return small_cuboid


def test_the_vessel_walls_feel_the_material_pressure(cuboid):
    size = np.array(cuboid.size_m)
    overlap = np.maximum(0.0, -wall_gaps(cuboid.pos, cuboid.radius, size))
    push = np.pi * PACKING_MODULUS_GPA * 1e9 * cuboid.radius[:, None] * overlap
    stress = push.sum(axis=0) / (np.prod(size) / np.repeat(size, 2))
    assert stress.mean() == pytest.approx(GENESIS.pressure_mpa * 1e6, rel=PRESSURE_TOLERANCE)
    assert cuboid.pressure_mpa == pytest.approx(GENESIS.pressure_mpa, rel=PRESSURE_TOLERANCE)
    assert stress.min() > 0.5 * stress.mean()  # every face pressed: an isotropic packing


def test_the_genesis_leaves_no_floaters(cuboid):
    assert cuboid.floaters == 0
    assert vessel_floaters(cuboid) == 0


def test_a_floater_grows_to_overlap_its_third_neighbour_by_its_own_overlap():
    rng = np.random.default_rng(4)
    size = np.full(3, 6e-3)
    pos, radius = rng.uniform(1e-3, 5e-3, (40, 3)), rng.uniform(0.4e-3, 0.6e-3, 40)
    overlap = rng.uniform(0.0, 0.01, 40)  # of its radius, one per sphere
    grown = enlarge_floaters(pos, radius, size, overlap)
    floating = floaters(pos, radius, size)
    assert floating.any() and np.array_equal(grown != radius, floating)
    assert not floaters(pos, grown, size).any()
    for k in np.flatnonzero(floating):
        gaps = np.linalg.norm(pos - pos[k], axis=1) - radius - grown[k]
        walls = wall_gaps(pos[k:k + 1], grown[k:k + 1], size)[0]
        third = np.sort(np.concatenate([np.delete(gaps, k), walls]))[2]
        assert third == pytest.approx(-overlap[k] * radius[k], abs=1e-15)


def test_exactly_the_pairs_within_the_installation_gap_are_bonded(cuboid):
    pos, radius = cuboid.pos, cuboid.radius
    gap = np.linalg.norm(pos[:, None] - pos[None], axis=2) - radius[:, None] - radius[None]
    reach = cuboid.install_gap * cuboid.rmin_mm * 1e-3 + 1e-6 * radius.min()
    i, j = np.nonzero(np.triu(gap <= reach, 1))
    assert np.array_equal(np.column_stack([i, j]), cuboid.bonds[np.lexsort(cuboid.bonds.T[::-1])])
    assert 2 * len(cuboid.bonds) / cuboid.n_spheres > 4.0


def test_the_same_seed_makes_the_same_packing(cuboid):
    x, _, z = cuboid.size_m
    again = random_specimen("cuboid", 1e3 * x, 1e3 * z, cuboid.rmin_mm, seed=3, cache=False)
    assert np.array_equal(again.pos, cuboid.pos) and np.array_equal(again.radius, cuboid.radius)
    assert np.array_equal(again.bond_draws, cuboid.bond_draws)


def test_the_same_seed_makes_the_same_packing_on_one_thread_or_two(monkeypatch):
    # a vessel of about 190 spheres, split in two blocks of the engine as a large one is
    monkeypatch.setattr(neighbours, "SPLIT_FROM", 100)
    monkeypatch.setattr(neighbours, "PARTICLES_PER_BLOCK", 100)
    packs = []
    cap = numba.get_num_threads()
    for threads in (1, 2):
        numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
        try:
            packs.append(pack_vessel([8e-3, 8e-3, 10e-3], 0.6e-3, 1.65, 5, GENESIS.cloud_porosity,
                                     GENESIS.pressure_mpa))
        finally:
            numba.set_num_threads(cap)
    (pos, radius, *_), (pos2, radius2, *_) = packs
    assert len(neighbours.block_starts(len(radius))) == 3
    assert np.array_equal(pos, pos2) and np.array_equal(radius, radius2)


def test_a_carved_cylinder_keeps_the_spheres_centred_inside_it_each_bonded(cuboid):
    cylinder = carve_cylinder(cuboid)
    side = cuboid.size_m[0]
    assert np.hypot(*(cylinder.pos[:, :2] - side / 2).T).max() <= side / 2
    assert np.all(np.bincount(cylinder.bonds.ravel(), minlength=cylinder.n_spheres) > 0)
    inside = np.hypot(*(cuboid.pos[:, :2] - side / 2).T) <= side / 2
    assert 0.98 * np.count_nonzero(inside) <= cylinder.n_spheres <= np.count_nonzero(inside)
