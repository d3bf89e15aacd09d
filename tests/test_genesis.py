"""PFC's material genesis: grain count from the cloud porosity, packing to the material pressure,
floaters enlarged, bonds at exactly the pairs within the installation gap, no locked-in force."""

import multiprocessing

import numpy as np
import pytest

from rockcal import make_params
from rockcal.specimens.genesis import Genesis, vessel_contacts
from rockcal.dem.laws import BondRow
from rockcal.specimens.packing import PRESSURE_TOLERANCE
from rockcal.dem.simulate import advance, rebuild_neighbours
from rockcal.specimens.specimen import random_packing
from rockcal.materials.parallel_bond import new_state

WIDTH_MM, HEIGHT_MM, RMIN_MM, RATIO = 10.0, 20.0, 0.25, 1.65


def small(**genesis):
    return random_packing(WIDTH_MM, HEIGHT_MM, RMIN_MM, RATIO, seed=2, genesis=Genesis(**genesis))


@pytest.fixture(scope="module")
def specimen():
    return small(install_gap=0.5)


def test_no_floaters_and_the_material_pressure(specimen):
    contacts = vessel_contacts(specimen.pos, specimen.radius, specimen.width_m, specimen.height_m)
    assert contacts.min() >= 3
    assert specimen.floaters == 0 and specimen.description()["floaters"] == 0
    assert specimen.pressure_mpa == pytest.approx(0.1, rel=PRESSURE_TOLERANCE)


def test_floaters_left_when_the_rounds_run_out_are_counted(monkeypatch, caplog):
    from rockcal.specimens import packing

    monkeypatch.setattr(packing, "FLOATER_ROUNDS", 0)
    specimen = random_packing(WIDTH_MM, HEIGHT_MM, 2 * RMIN_MM, RATIO, seed=2, cache=False)
    contacts = vessel_contacts(specimen.pos, specimen.radius, specimen.width_m, specimen.height_m)
    assert specimen.floaters == np.count_nonzero(contacts < 3) > 0
    assert f"{specimen.floaters} of {specimen.n_particles} grains" in caplog.text


@pytest.mark.slow
def test_grain_count_follows_the_cloud_porosity():
    mean_area = np.pi * (RMIN_MM * 1e-3) ** 2 * (1 + RATIO + RATIO**2) / 3
    area = WIDTH_MM * HEIGHT_MM * 1e-6
    for cloud in (0.09, 0.2):
        count = small(cloud_porosity=cloud).n_particles
        # the cloud's radii are random: its grain area misses (1 - n_c) A by a few grains
        assert count == pytest.approx((1 - cloud) * area / mean_area, rel=0.03), cloud


def test_bonds_at_exactly_the_pairs_within_the_installation_gap(specimen):
    i, j = np.triu_indices(specimen.n_particles, 1)
    gap = np.hypot(*(specimen.pos[j] - specimen.pos[i]).T) - specimen.radius[i] - specimen.radius[j]
    within = gap <= 0.5 * RMIN_MM * 1e-3
    expected = {(a, b) for a, b in zip(i[within], j[within])}
    assert {tuple(bond) for bond in specimen.bonds} == expected
    assert specimen.bonds_per_particle() > specimen.coordination() > 3.5


def test_a_specimen_leaves_the_vessel_at_rest(specimen):
    """Bonds installed at overlapping pairs take the overlap as reference: no locked-in force."""
    state = new_state(specimen.pos, specimen.radius, specimen.bonds, make_params({}))
    advance(state, 200)
    assert np.abs(state.particles.pos - specimen.pos).max() < 1e-12
    assert np.abs(state.particles.force).max() < 1e-9


def test_two_overlapping_disks_bonded_carry_no_force():
    pos = np.array([[0.0, 0.0], [1.9e-3, 0.0]])
    state = new_state(pos, np.array([1e-3, 1e-3]), [[0, 1]], make_params({}))
    advance(state, 100)
    assert state.bonds.table[BondRow.REF_OVERLAP, 0] == pytest.approx(1e-4)
    np.testing.assert_allclose(state.particles.pos, pos, atol=1e-15)
    # moved 1 um closer (not through a velocity, so the incremental bond does not see it),
    # the contact pushes with kn x 1 um: only the overlap added since bonding counts
    state.particles.pos[1, 0] -= 1e-6
    rebuild_neighbours(state)
    advance(state, 1)
    kn = 2 * 1e-3 * 21.65e9 / 2e-3
    assert -state.particles.force[0, 0] == pytest.approx(kn * 1e-6, rel=1e-3)


def test_genesis_is_deterministic_and_cached():
    a = small(install_gap=0.5)
    b = random_packing(WIDTH_MM, HEIGHT_MM, RMIN_MM, RATIO, seed=2,
                       genesis=Genesis(install_gap=0.5), cache=False)
    np.testing.assert_array_equal(a.pos, b.pos)
    np.testing.assert_array_equal(a.bonds, b.bonds)
    np.testing.assert_array_equal(a.bond_draws, b.bond_draws)


def test_sizes_given_as_integers_find_the_same_cached_specimen(monkeypatch, tmp_path):
    monkeypatch.setenv("ROCKCAL_CACHE", str(tmp_path))
    a = random_packing(WIDTH_MM, HEIGHT_MM, RMIN_MM, RATIO, seed=2)
    b = random_packing(int(WIDTH_MM), int(HEIGHT_MM), RMIN_MM, RATIO, seed=2)
    assert len(list(tmp_path.glob("*.npz"))) == 1
    np.testing.assert_array_equal(a.pos, b.pos)


def _make_and_log(log):
    import rockcal.specimens.specimen as specimen

    pack = specimen._pack

    def logged(*args):
        with open(log, "a") as f:
            f.write("made\n")
        return pack(*args)

    specimen._pack = logged
    return random_packing(WIDTH_MM, HEIGHT_MM, RMIN_MM, RATIO, seed=3).pos


def test_two_processes_needing_the_same_packing_make_it_once(monkeypatch, tmp_path):
    monkeypatch.setenv("ROCKCAL_CACHE", str(tmp_path / "cache"))
    log = tmp_path / "log"
    with multiprocessing.get_context("spawn").Pool(2) as pool:
        a, b = pool.map(_make_and_log, [log, log])
    assert log.read_text() == "made\n"
    np.testing.assert_array_equal(a, b)
