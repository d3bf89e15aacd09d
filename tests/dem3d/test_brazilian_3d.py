"""The Brazilian test on a 3D disk (`rockcal.labtests.brazilian` on the 3D rig) against what
must hold:

- sigma_t = 2 P / (pi D t), with the disk's nominal D and t, at the curve's peak load;
- an elastic bonded simple-cubic disk between the flat platens is in equilibrium: the two
  platens bear the same load, and the load is linear in the closure (the lattice's contacts
  are linear and no new one forms);
- a bearing strip is a softer column in series with the platen's contact;
- the split rule: a crack in the plane of the loaded diameter and the axis, across the disk's
  thickness, is a split; a crush at the platens, a crack off the centre, a wedge's side
  cracks, a crack through one layer of the thickness are not;
- a small genesis disk loads, peaks and stops past the peak by the 2D test's rules, and the
  same seed gives the same numbers bit for bit.
"""

import numpy as np
import pytest

from rockcal.specimens3d.specimen import Specimen3D, random_disk
from rockcal.errors import InputError
from rockcal.labtests.brazilian import DEFAULT_MAX_STRAIN, POST_PEAK_FRACTION, broken_through, central_split
from rockcal.labtests.brazilian import simulate_brazilian
from rockcal.labtests.loading import (LOCALISED_DAMAGE, PAST_PEAK_FRACTION, RAMP_STEPS_PER_ROW, Loading, Reading,
                                      load_to_failure)
from rockcal.labtests.rig import BearingStrip, Disk
from rockcal.labtests.rig.jaws_3d import Jaws3D
from rockcal.labtests.rig.platens_3d import BOTTOM, TOP, Platens3D, strip_modulus_pa
from rockcal.materials.parallel_bond import make_params

GRANITE = make_params({"E_c": 62, "kn_ks": 2.5, "sigma_c": 175, "tau_c": 175,
                       "sigma_c_cv": 0.23, "tau_c_cv": 0.23, "mu": 0.5, "density": 2630})
ELASTIC = make_params({"E_c": 20, "Ebar_c": 40, "kn_ks": 2.5, "sigma_c": 1e5, "tau_c": 1e5})
LOAD = 1  # the curve's load column, kN (a 2D slab's: kN per m of its thickness)


def tensile_strength_MPa(load_N: float, diameter_m: float, thickness_m: float) -> float:
    """sigma_t = 2 P / (pi D t) (ISRM 1978; ASTM D3967), MPa."""
    return 2.0 * load_N / (np.pi * diameter_m * thickness_m) / 1e6


def platen_loads(params, disk, closure_m: float, strip: BearingStrip | None = None) -> np.ndarray:
    """Rows (closure mm, bottom platen's load kN, top platen's kN) as the test's platens close on
    `disk` by its loading rule up to `closure_m`: the test's run, read at each platen."""
    platens = Platens3D(disk, params, 1.0, strip=strip)

    def read() -> Reading:
        bottom, top = platens.state.walls.normal_force()[[BOTTOM, TOP]]
        return Reading(platens.load(), platens.closure_m(), (1e3 * platens.closure_m(), bottom / 1e3, top / 1e3))

    return load_to_failure(platens, Loading(RAMP_STEPS_PER_ROW * platens.rows, LOCALISED_DAMAGE), read,
                           lambda reading: False, closure_m, full_speed_past_peak=True)


@pytest.fixture(scope="module")
def disk():
    """A genesis disk D 12 x t 8 mm at R_min 0.6 mm (about 270 spheres)."""
    return random_disk(12.0, 8.0, 0.6, seed=3, cache=False)


def lattice_disk(across: int, layers: int, r: float) -> Specimen3D:
    """Equal spheres of radius r on a simple-cubic lattice, those whose centres lie within
    `across` / 2 spacings of the middle column (x, z) kept, `layers` deep along y; lattice
    neighbours bonded. `across` odd: one column of spheres stands highest (and lowest), on the
    loaded diameter."""
    d = 2 * r
    c = (across - 1) / 2
    index = np.array([(i, j, k) for k in range(across) for j in range(layers) for i in range(across)
                      if np.hypot(i - c, k - c) <= across / 2])
    flat = {tuple(v): n for n, v in enumerate(index)}
    bonds = [(flat[tuple(v)], flat[tuple(v + step)]) for v in index for step in np.eye(3, dtype=int)
             if tuple(v + step) in flat]
    return Specimen3D(index * d + r, np.full(len(index), r), np.array(bonds), "disk",
                      (across * d, layers * d, across * d), "simple-cubic disk",
                      np.full((len(bonds), 2), 0.5))


def test_an_elastic_lattice_disk_is_loaded_alike_top_and_bottom_and_linearly():
    disk = lattice_disk(9, 4, 1e-3)
    result = simulate_brazilian(ELASTIC, disk, max_strain=2e-3)
    assert result.n_broken_tension + result.n_broken_shear == 0
    closure, load = result.curve[:, 0], result.curve[:, LOAD]
    assert closure[-1] >= 2e-3 * 18.0  # stopped at the largest closure: no peak, no fall
    assert int(np.argmax(load)) == len(load) - 1
    # sigma_t from the peak load and the nominal D x t
    assert result.sigma_t_MPa == pytest.approx(2 * 1e3 * load.max() / (np.pi * 18e-3 * 8e-3) / 1e6, rel=1e-12)
    assert result.diameter_mm == pytest.approx(18.0)
    each = platen_loads(ELASTIC, disk, 2e-3 * 18e-3)
    assert np.array_equal(each[:, 0], closure)  # the test's run
    # the peak load is the platens' force in kN (N / 1000), the disk's whole thickness's
    assert result.P_max_kN == pytest.approx(each[:, 1:].mean(axis=1).max(), rel=1e-12)
    loaded = load > 0.2 * load[-1]
    bottom, top = each[loaded, 1], each[loaded, 2]
    assert np.abs(bottom - top).max() < 1e-4 * load[-1]  # equilibrium: the same load on both
    half = np.argmin(np.abs(closure - 0.5 * closure[-1]))
    # linear: the same secant stiffness at half and at the full closure
    assert load[half] / closure[half] == pytest.approx(load[-1] / closure[-1], rel=2e-3)


def test_a_3d_brazilian_reports_its_load_in_kN_and_2d_per_m_of_thickness():
    """A 3D run's peak load, curve and reading are in kN, and its stored runs of the load per m
    are run again (a 3D revision of its own); a 2D run's keep kN per m and their keys."""
    from rockcal.campaign.runs.spec import ENGINE, run_spec
    from rockcal.labtests.brazilian import TEST
    from rockcal.labtests.specimen_settings import SpecimenSettings

    units = {d: {r.name: r.unit for r in TEST.of_dimensions(d).responses} for d in (2, 3)}
    assert units[3]["P_max_kN"] == "kN" and "P_max_kN_per_m" not in units[3]
    assert units[2]["P_max_kN_per_m"] == "kN/m" and "P_max_kN" not in units[2]
    assert TEST.of_dimensions(3).curve_columns[1] == "load_kN"
    assert TEST.of_dimensions(3).reading(0.1, 2.5) == "0.100 mm, 2.50 kN"
    assert TEST.of_dimensions(2).reading(0.1, 2.5) == "0.100 mm, 2.50 kN/m"
    engine = {d: run_spec("brazilian", SpecimenSettings(dimensions=d, disk_diameter_mm=50.0), {}).engine
              for d in (2, 3)}
    assert engine[2] == f"{ENGINE}, brazilian test revision 2"
    assert engine[3].startswith(f"{ENGINE}, brazilian test revision 3, 3D engine")


def test_isrm_jaws_are_curved_rows_of_spheres_that_bear_alike_top_and_bottom():
    """ISRM's jaws on an elastic lattice disk: faces of radius 1.5 R across the disk's whole
    thickness; the two jaws bear the same load along z, and the sideways forces on each cancel
    (the disk is symmetric about the loaded diameter)."""
    disk = lattice_disk(9, 4, 1e-3)
    jaws = Jaws3D(disk, ELASTIC, 1.0)
    s = jaws.state.spheres
    assert jaws.jaw_radius_m == pytest.approx(1.5 * 9e-3)
    for is_jaw, (x, z) in ((jaws.is_top, jaws.centres[0]), (jaws.is_bottom, jaws.centres[1])):
        reach = np.hypot(s.pos[is_jaw, 0] - x, s.pos[is_jaw, 2] - z) - s.radius[is_jaw]
        assert reach == pytest.approx(jaws.jaw_radius_m, rel=1e-12)  # the face, radius 1.5 R
        y = s.pos[is_jaw, 1]
        assert y.min() <= 0.0 and y.max() >= 8e-3  # across the disk's thickness
    result = simulate_brazilian(ELASTIC, disk, loading="isrm", max_strain=2e-3)
    assert result.n_broken_tension + result.n_broken_shear == 0 and result.curve[-1, LOAD] > 0
    jaws.move(1.0)
    jaws.state.advance(3000)
    force = s.force
    top, bottom = force[jaws.is_top].sum(axis=0), force[jaws.is_bottom].sum(axis=0)
    assert top[2] > 0 and top[2] == pytest.approx(-bottom[2], rel=1e-4)
    assert jaws.load() == pytest.approx(top[2], rel=1e-4)
    assert abs(top[0]) < 1e-4 * top[2] and abs(bottom[0]) < 1e-4 * top[2]


def test_a_bearing_strip_is_a_softer_column_in_series_with_the_platen():
    strip = BearingStrip(1.0, 0.2)
    r, bare = 1e-3, 62e9
    column = 1e9 * np.pi * r**2 / 0.2e-3
    k = np.pi * strip_modulus_pa(strip, bare, r) * r
    assert k == pytest.approx(1 / (1 / column + 1 / (np.pi * bare * r)), rel=1e-12)
    disk = lattice_disk(9, 4, 1e-3)
    flat, strips = (simulate_brazilian(ELASTIC, disk, loading=loading, max_strain=2e-3)
                    for loading in ("flat", "strips"))
    slope = [run.curve[-1, LOAD] / run.curve[-1, 0] for run in (flat, strips)]
    assert slope[1] < 0.5 * slope[0]


# The split rule on synthetic cracks: a disk D 50 x t 25 mm of 1 mm grains centred at (25, 25) mm
# in (x, z), its axis along y.
D, T, GRAIN, CENTRE = 50e-3, 25e-3, 1e-3, (25e-3, 25e-3)


def crack_plane(x: float, z_from: float, z_to: float, y_step: float = 1.0) -> np.ndarray:
    """Breaks over the plane x = const, from z_from to z_to, across the disk's thickness, one
    per mm of z and per `y_step` of y: a planar crack's bonds, one per grain face of this disk
    at y_step 1 (mm in, m out)."""
    z = np.arange(z_from, z_to, 1.0)
    y = np.arange(0.5, 1e3 * T, y_step)
    zz, yy = np.meshgrid(z, y)
    return 1e-3 * np.column_stack([np.full(zz.size, x), yy.ravel(), zz.ravel()])


DISK = Disk(D, T, CENTRE, 2, T / GRAIN)


def split(cracks) -> bool:
    return central_split(cracks, DISK, GRAIN)


def test_a_crack_in_the_loaded_plane_across_the_thickness_is_a_split():
    cracks = crack_plane(25.3, 0.5, 50)
    assert split(cracks) and broken_through(cracks, DISK, GRAIN)
    assert split(crack_plane(25.3, 10, 40))  # the middle only, the ends crushed or not


def test_a_crush_at_the_platens_is_no_split():
    crushed = np.vstack([crack_plane(x, 0, 5) for x in (22, 25, 28)]
                        + [crack_plane(x, 45, 50) for x in (22, 25, 28)])
    assert not split(crushed)
    assert not broken_through(crushed, DISK, GRAIN)


def test_a_crack_off_the_centre_or_a_wedge_is_no_split():
    assert not split(crack_plane(25 + 0.25 * 50, 5, 45))  # along a chord a quarter D off
    wedge = np.vstack([crack_plane(25.3, 0, 50), crack_plane(25 - 0.3 * 50, 5, 45),
                       crack_plane(25 + 0.3 * 50, 5, 45)])
    assert not split(wedge)


def test_a_crack_through_one_layer_of_a_thick_disk_is_no_split():
    """The 2D rule counts grains along the slice; in 3D a crack crosses the thickness too."""
    one_layer = crack_plane(25.3, 0, 50, y_step=1e3)  # one break per mm of z, at one y
    assert not split(one_layer)
    assert split(crack_plane(25.3, 0, 50, y_step=2.0))  # every other grain: a crack


def test_bad_loadings_and_disks_are_refused(disk):
    with pytest.raises(InputError, match="loading"):
        simulate_brazilian(GRANITE, disk, loading="curved")
    with pytest.raises(InputError, match="thickness_mm"):
        random_disk(20.0, 6.0, 0.8)


def test_a_small_disk_peaks_and_stops_past_the_peak_as_in_2D(disk):
    result = simulate_brazilian(GRANITE, disk)
    closure, load = result.curve[:, 0], result.curve[:, LOAD]
    peak = int(np.argmax(load))
    assert 0 < peak < len(load) - 1
    # the flat platens' stop rule: the load fallen below POST_PEAK_FRACTION of the peak with the
    # platens closed by one more mean radius since, or (a coarse disk: 0.77 mm against 12 mm) the
    # largest closure, DEFAULT_MAX_STRAIN x D
    assert load[-1] < POST_PEAK_FRACTION * load[peak]
    assert closure[-1] > closure[peak] + 1e3 * disk.radius.mean() or closure[-1] >= DEFAULT_MAX_STRAIN * 12.0
    assert result.sigma_t_MPa == pytest.approx(tensile_strength_MPa(1e3 * load[peak], 12e-3, 8e-3), rel=1e-12)
    each = platen_loads(GRANITE, disk, 1e-3 * closure[peak])
    assert np.array_equal(each[:, 0], closure[:len(each)])  # the test's run, up to the peak
    before = (load[:len(each)] > 0.2 * load[peak]) & (np.arange(len(each)) <= peak)
    bottom, top = each[before, 1], each[before, 2]
    # quasi-static: the platens bear the same load, but for the moments a break shakes the disk
    assert np.mean(np.abs(bottom - top)) < 0.01 * load[peak]
    assert np.median(np.abs(bottom - top)) < 0.002 * load[peak]
    # the cracks read for `split` are those broken by just after the peak
    assert sum(len(v) for v in result.peak_cracks.values()) <= result.n_broken_tension + result.n_broken_shear


def test_strips_stop_at_the_first_fall_that_left_a_crack_across(disk):
    result = simulate_brazilian(GRANITE, disk, loading="strips")
    load = result.curve[:, LOAD]
    assert load[-1] < PAST_PEAK_FRACTION * load.max()
    cracks = np.vstack(list(result.peak_cracks.values()))
    pos, radius = disk.pos, disk.radius
    centre = tuple(0.5 * ((pos[:, a] - radius).min() + (pos[:, a] + radius).max()) for a in (0, 2))
    grain = 2 * radius.mean()
    assert broken_through(cracks, Disk(12e-3, 8e-3, centre, 2, 8e-3 / grain), grain)


def test_the_same_seed_gives_the_same_numbers_bit_for_bit(disk):
    again = random_disk(12.0, 8.0, 0.6, seed=3, cache=False)
    for name in ("pos", "radius", "bonds", "bond_draws"):
        assert np.array_equal(getattr(disk, name), getattr(again, name)), name
    runs = [simulate_brazilian(GRANITE, specimen) for specimen in (disk, again)]
    assert np.array_equal(runs[0].curve, runs[1].curve)
    assert runs[0].sigma_t_MPa == runs[1].sigma_t_MPa and runs[0].split == runs[1].split
