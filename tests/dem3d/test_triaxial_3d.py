"""The confined test on a 3D prism (`rockcal.labtests.biaxial` on the 3D rig: a square prism
between platens and four servo-controlled side walls) against what must hold:

- an elastic bonded simple-cubic prism is a cubic lattice of C11 = (kn + k̄nĀ) / d in
  compression and C12 = 0 (`test_lattice_3d`): seated at sigma3 every wall settles at sigma3
  and the lattice shortens by sigma3 / C11 each way; loaded axially it reads E = C11 and no
  Poisson effect, and its side walls keep sigma3;
- on that symmetric lattice the four side walls bear the same stress throughout;
- a genesis prism is stronger at sigma3 = 5 MPa than unconfined, and its side walls hold
  sigma3 within the 2D rig's scatter through the loading; unconfined it is the 3D UCS test on
  the prism, to the last bit;
- the same prism and seed give the same numbers bit for bit;
- a confinement below 0 or above the bound is refused in one line naming the key, exit 2.
"""

import numpy as np
from rockcal.specimens3d.specimen import random_specimen
import pytest
from test_input_3d import calibrate, campaign, one_line
from test_ucs_3d import GRANITE, cubic_prism

from rockcal.dem3d.laws import bond_springs, contact_springs
from rockcal.materials.parallel_bond import laws_3d
from rockcal.labtests.rig.platens_3d import SIDES, Platens3D
from rockcal.labtests.rig.sides_3d import SideWalls3D
from rockcal.labtests.biaxial import simulate_biaxial
from rockcal.labtests.ucs import simulate_ucs
from rockcal.labtests.biaxial import MAX_CONFINEMENT_MPA
from rockcal.labtests.rig.sides import SEATING_TOLERANCE
from rockcal.materials.parallel_bond import make_params
from rockcal.params import MPa

ELASTIC = make_params({"E_c": 10, "Ebar_c": 30, "kn_ks": 2.5, "sigma_c": 1e5, "tau_c": 1e5})
R = 1e-3
SIGMA3_MPA = 20.0


@pytest.fixture(scope="module")
def lattice():
    return cubic_prism(5, R)


def c11(params) -> float:
    """The simple-cubic lattice's C11 in compression, Pa: bond and contact in parallel over d."""
    laws = laws_3d(params)
    kbn_a, _, _, _ = bond_springs(R, 2 * R, laws)
    kn, _ = contact_springs(R, 2 * R, laws)
    return (kn + kbn_a) / (2 * R)


def seated(specimen, params, sigma3_mpa):
    platens = Platens3D(specimen, params, 1.6, side_walls=True)
    platens.state.scale_density()
    sides = SideWalls3D(platens, specimen, sigma3_mpa * MPa)
    return platens, sides, sides.seat()


def test_a_seated_lattice_is_at_sigma3_and_shortened_by_sigma3_over_c11(lattice):
    platens, sides, steps = seated(lattice, ELASTIC, SIGMA3_MPA)
    assert steps > 0
    stresses = sides.servo.stresses()  # bottom, top and the side walls
    assert np.abs(stresses / (SIGMA3_MPA * MPa) - 1).max() < SEATING_TOLERANCE
    pos, start = platens.state.spheres.pos, lattice.pos
    for a in range(3):  # the spacing of the outer layers of spheres each way
        first, last = start[:, a] < start[:, a].min() + R, start[:, a] > start[:, a].max() - R
        spacing = pos[last, a].mean() - pos[first, a].mean()
        strain = 1 - spacing / (start[last, a].mean() - start[first, a].mean())
        assert strain == pytest.approx(SIGMA3_MPA * MPa / c11(ELASTIC), rel=3e-3), a


def test_a_confined_lattice_reads_c11_and_no_poisson_effect(lattice):
    result = simulate_biaxial(ELASTIC, lattice, SIGMA3_MPA, max_axial_strain=5e-3)
    assert result.n_broken_tension + result.n_broken_shear == 0
    # q is read on the original cross-section, which the seating shrank by sigma3 / C11 each way
    seated_area = (1 - SIGMA3_MPA * MPa / c11(ELASTIC)) ** 2
    assert result.E_GPa == pytest.approx(seated_area * c11(ELASTIC) / 1e9, rel=1.5e-3)
    # C12 = 0: no Poisson effect but the side walls' faces shortening with the prism, so that
    # holding sigma3 on them unloads the lattice sideways by about sigma3 / C11 x the axial strain
    assert 0 <= result.nu < 2 * SIGMA3_MPA * MPa / c11(ELASTIC)
    sigma3 = result.curve[1:, 4]
    assert np.abs(sigma3 / SIGMA3_MPA - 1).max() < SEATING_TOLERANCE
    assert result.sigma3_MPa == pytest.approx(SIGMA3_MPA, rel=1e-3)
    assert result.sigma1_MPa == pytest.approx(result.q_MPa + result.curve[-1, 4], rel=1e-12)


def test_the_four_side_walls_of_a_symmetric_lattice_bear_the_same_stress(lattice):
    platens, sides, _ = seated(lattice, ELASTIC, SIGMA3_MPA)
    state = platens.state
    platens.zero()
    platens.move(1.0)
    for _ in range(1000):
        sides.update()
        state.advance(sides.steps)
        side = sides.stresses_Pa()
        # alike to 1e-4 of sigma3 (3e-5 measured), 50 x finer than the seating's tolerance:
        # the walls differ by rounding alone, in the order their spheres' forces are summed
        assert len(side) == len(SIDES) and np.ptp(side) < 1e-4 * SIGMA3_MPA * MPa, side
    assert platens.strain() > 5e-3


@pytest.fixture(scope="module")
def runs(small_cuboid):
    """`conftest.small_cuboid` (10 x 10 x 20 mm at R_min 0.6 mm) unconfined and at 5 MPa."""
    return {s3: simulate_biaxial(GRANITE, small_cuboid, s3) for s3 in (0.0, 5.0)}


def test_confinement_raises_the_peak_and_the_side_walls_hold_sigma3(runs):
    free, confined = runs[0.0], runs[5.0]
    assert confined.sigma1_MPa > free.sigma1_MPa and confined.seating_steps > 0
    assert confined.sigma3_MPa == pytest.approx(5.0, rel=0.01)
    peak = int(np.argmax(confined.curve[:, 2]))
    off = np.abs(confined.curve[1:peak + 1, 4] - 5.0)
    # the 2D rig's scatter: 95 % of the readings within 0.05-0.2 MPa of sigma3
    assert np.percentile(off, 95) < 0.2 and off.max() < 1.0
    assert free.sigma3_MPa == 0.0 and not free.curve[:, 4].any()


def test_unconfined_it_is_the_ucs_test_on_the_prism_to_the_last_bit(small_cuboid, runs):
    ucs = simulate_ucs(GRANITE, small_cuboid)
    assert np.array_equal(ucs.curve, runs[0.0].curve[:, :4])
    assert ucs.ucs_MPa == runs[0.0].sigma1_MPa and ucs.E_GPa == runs[0.0].E_GPa


def test_the_same_prism_gives_the_same_numbers_bit_for_bit(small_cuboid):
    first, second = (simulate_biaxial(GRANITE, small_cuboid, 5.0, max_axial_strain=2e-3) for _ in range(2))
    assert np.array_equal(first.curve, second.curve)
    assert first.seating_steps == second.seating_steps and np.array_equal(first.positions, second.positions)


TINY = ["--dimensions", "3", "--width-mm", "7", "--height-mm", "14", "--rmin-mm", "0.5"]


@pytest.mark.parametrize("value", ["-5", f"{2 * MAX_CONFINEMENT_MPA:g}"])
def test_a_confinement_out_of_bounds_is_refused(cli, tmp_path, value):
    one_line(cli("simulate", "biaxial", *TINY, "--confinement-mpa", value), "--confinement-mpa", value)
    targets = f"[targets.biaxial]\nconfinement_mpa = [0, {value}]\nphi_deg = 40.0"
    one_line(calibrate(cli, tmp_path, campaign(targets)), "targets.biaxial.confinement_mpa")


def test_a_3d_campaign_with_confined_targets_is_accepted(cli, tmp_path):
    run = calibrate(cli, tmp_path, campaign("[targets.biaxial]\nconfinement_mpa = [0, 5, 10]\nphi_deg = 40.0"))
    assert run.returncode == 0, run.stderr


@pytest.mark.slow  # three small prisms' genesis and six confined runs: about 30 s
def test_halving_the_loading_speed_moves_the_mean_confined_peak_by_less_than_3_percent(small_cuboid):
    """On 10 x 10 x 20 mm prisms (about 590 spheres) at sigma3 = 10 MPa. One prism's peak is one
    failure path: between the two speeds it moves by a few per cent either way, packing by
    packing; the rate's own effect is what stays in the mean over packings."""
    prisms = [small_cuboid] + [random_specimen("cuboid", 10.0, 20.0, 0.6, seed=seed, cache=False) for seed in (1, 2)]
    full, half = (np.mean([simulate_biaxial(GRANITE, prism, 10.0, rate_factor=rate).sigma1_MPa for prism in prisms])
                  for rate in (1.0, 0.5))
    assert half == pytest.approx(full, rel=0.03)
