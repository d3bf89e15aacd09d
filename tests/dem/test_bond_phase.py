"""The bond phase (`laws.add_bond_forces`) runs its law on tiles of bonds as vector code and
sums a disk's load in registers over consecutive pairs; its numbers must be those of adding
the pairs one at a time, in pair order, to the last bit: that is what makes a run's numbers
independent of the tile size, of the thread count and of the order the pairs come in."""

import numpy as np

from rockcal import hexagonal
from rockcal.dem import laws
from rockcal.dem.laws import BondRow
from rockcal.dem.simulate import rebuild_neighbours
from rockcal.materials.parallel_bond import new_state
from rockcal.params import make_params

PARAMS = {"E_c": 20, "kn_ks": 2.0, "sigma_c": 10, "tau_c": 20, "sigma_c_cv": 0.3,
          "tau_c_cv": 0.3, "phi_b": 20}


def test_tiles_give_the_sums_of_adding_pairs_one_by_one():
    specimen = hexagonal(12, 12, 0.25)
    state = new_state(specimen.pos, specimen.radius, specimen.bonds, make_params(PARAMS),
                      bond_draws=np.random.default_rng(1).random(2 * len(specimen.bonds)))
    rng = np.random.default_rng(0)
    p, nb = state.particles, state.neighbours.n_bonds
    p.vel[:] = rng.normal(0, 0.05, p.vel.shape)
    p.spin[:] = rng.normal(0, 100.0, p.spin.shape)
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
