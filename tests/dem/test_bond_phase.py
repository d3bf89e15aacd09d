"""The bond phase (`laws.add_bond_forces`) runs its law on tiles of bonds as vector code and
sums a disk's load in registers over consecutive pairs; its numbers must be those of adding
the pairs one at a time, in pair order, to the last bit: that is what makes a run's numbers
independent of the tile size, of the thread count and of the order the pairs come in."""

import numpy as np

from rockcal import hexagonal
from rockcal.dem import laws
from rockcal.dem.laws import BondRow
from rockcal.dem import border
from rockcal.dem.simulate import rebuild_neighbours
from rockcal.materials.parallel_bond import new_state
from rockcal.params import make_params

PARAMS = {"E_c": 20, "kn_ks": 2.0, "sigma_c": 10, "tau_c": 20, "sigma_c_cv": 0.3,
          "tau_c_cv": 0.3, "phi_b": 20}


def moving_lattice():
    """A bonded lattice of 12 x 12 mm, its disks moving and spinning at random; the generator."""
    specimen = hexagonal(12, 12, 0.25)
    state = new_state(specimen.pos, specimen.radius, specimen.bonds, make_params(PARAMS),
                      bond_draws=np.random.default_rng(1).random(2 * len(specimen.bonds)))
    rng = np.random.default_rng(0)
    state.particles.vel[:] = rng.normal(0, 0.05, state.particles.vel.shape)
    state.particles.spin[:] = rng.normal(0, 100.0, state.particles.spin.shape)
    return state, rng


def test_tiles_give_the_sums_of_adding_pairs_one_by_one():
    state, rng = moving_lattice()
    p, nb = state.particles, state.neighbours.n_bonds
    # pairs in no particular order, some (j, i), runs of one first disk, several tiles
    order = rng.permutation(nb)
    pi, pj = state.neighbours.pi[:nb][order], state.neighbours.pj[:nb][order]
    swap = rng.random(nb) < 0.3
    pi, pj = np.where(swap, pj, pi), np.where(swap, pi, pj)
    table = state.bonds.table[:, order]
    bonds = laws.new_bonds(table[BondRow.REF_OVERLAP], table[BondRow.TEN], table[BondRow.COH],
                           p.radius[pi], p.radius[pj])
    area = 2 * p.radius.min()
    bonds.table[BondRow.FN] = rng.normal(0, 10e6 * area, nb)  # some beyond their strength
    bonds.table[BondRow.FS] = rng.normal(0, 10e6 * area, nb)
    shear = rng.normal(0, 1e3, nb)
    assert nb > 2 * laws.TILE

    def run(ranges):
        copy = bonds._replace(state=bonds.state.copy(), break_xy=bonds.break_xy.copy(),
                              table=bonds.table.copy())  # what the kernel reads and writes
        loads, contact_shear = np.zeros_like(p.loads), shear.copy()
        for first, last in ranges:
            laws.add_bond_forces(first, last, p.disks, pi, pj, contact_shear, copy, state.laws,
                                 state.dt, loads)
        return loads, contact_shear, copy.table, copy.state, copy.break_xy

    tiled = run([(0, nb)])
    one_by_one = run([(k, k + 1) for k in range(nb)])
    assert np.count_nonzero(tiled[3]) > 0  # bonds broke
    for a, b in zip(tiled, one_by_one):
        np.testing.assert_array_equal(a, b)


def test_border_pairs_kept_in_rows_add_to_the_same_sums_as_pair_by_pair():
    """The pairs across block borders write their forces into rows of their own, added to the
    particles afterwards (`border.add_forces`): the loads must be those of adding the
    pairs to them directly, bonds then contacts, to the last bit."""
    state, rng = moving_lattice()
    p, nb = state.particles, state.neighbours.n_bonds
    p.pos[:] += rng.normal(0, 1e-6, p.pos.shape)  # the touching pairs press, as contacts too
    # the bonds, then the same pairs as contacts: all of them the border's (one empty block)
    pi = np.concatenate([state.neighbours.pi[:nb]] * 2)
    pj = np.concatenate([state.neighbours.pj[:nb]] * 2)
    bond_offsets, contact_offsets = np.array([0, 0, nb]), np.array([nb, nb, 2 * nb])
    start = rng.normal(0, 1.0, p.loads.shape)  # the blocks' own pair forces
    start_shear = rng.normal(0, 1e3, 2 * nb)

    def run(into_rows):
        bonds = state.bonds._replace(state=state.bonds.state.copy(),
                                     break_xy=state.bonds.break_xy.copy(),
                                     table=state.bonds.table.copy())
        loads, shear = start.copy(), start_shear.copy()
        rows = border.rows(bond_offsets, contact_offsets, 3) if into_rows else loads
        laws.add_bond_forces(0, nb, p.disks, pi, pj, shear, bonds, state.laws, state.dt, rows,
                             0 if into_rows else -1)
        laws.add_contact_forces(nb, 2 * nb, p.disks, pi, pj, shear, state.laws, state.dt, rows,
                                0 if into_rows else -1)
        if into_rows:
            border.add_forces(0, len(p.pos), pi, pj, bond_offsets, contact_offsets, rows, loads)
        return loads, shear, bonds.table

    direct, through_rows = run(False), run(True)
    assert np.count_nonzero(direct[1][nb:]) > 0  # contacts sheared
    for a, b in zip(direct, through_rows):
        np.testing.assert_array_equal(a, b)


def test_bonds_take_their_particles_new_radii_when_the_list_is_rebuilt():
    specimen = hexagonal(4, 4, 0.25)
    state = new_state(specimen.pos, specimen.radius, specimen.bonds, make_params(PARAMS))
    p, nb = state.particles, state.neighbours.n_bonds
    p.radius[:] *= np.linspace(0.9, 1.1, len(p.radius))
    rebuild_neighbours(state)
    ri, rj = p.radius[state.neighbours.pi[:nb]], p.radius[state.neighbours.pj[:nb]]
    np.testing.assert_array_equal(state.bonds.table[BondRow.R_I], ri)
    np.testing.assert_array_equal(state.bonds.table[BondRow.R_J], rj)
    np.testing.assert_array_equal(state.bonds.table[BondRow.INV_LENGTH], 1.0 / (ri + rj))
