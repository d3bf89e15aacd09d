"""Rigid clumps of spheres (PFC3D's clumps): the union's mass properties against closed forms,
the 3D templates, a torque-free clump's motion against Euler's solution for a symmetric top,
and two clumps colliding.

A clump's mass and inertia tensor are those of its pebbles' union at the density
(`dem3d.clumps.union_properties`), and `dem3d.clump_motion.clump` turns a state's spheres into
pebbles of clumps (-1: a ball).
"""

import math

import numpy as np
import pytest

from rockcal.dem3d.clump_motion import clump
from rockcal.dem3d.clumps import union_properties
from rockcal.dem3d.laws import Laws
from rockcal.dem3d.simulate import assemble_state
from rockcal.materials.clump_templates import template
from rockcal.materials.clump_templates_3d import GRAIN_SHAPES_3D, random_rotation

DENSITY = 2650.0
LAWS = Laws(E_c=10e9, ks_per_kn=0.4, mu=0.5, Ebar_c=10e9, ksbar_per_knbar=0.4, lam=1.0, tan_phi=0.5, mcf=True)


def sphere_inertia(r: float) -> float:
    """∫(x² + y²) dV of a sphere about a diameter: 2/5 V r² (per unit density)."""
    return 0.4 * 4.0 / 3.0 * math.pi * r**5


def test_apart_pebbles_give_the_spheres_sum_and_the_parallel_axis_theorem():
    r1, r2, d = 1.0, 0.5, 2.0  # touching at a point: no overlap
    volume, centroid, inertia = union_properties([[0, 0, 0], [d, 0, 0]], [r1, r2])
    v1, v2 = 4 / 3 * math.pi * r1**3, 4 / 3 * math.pi * r2**3
    assert volume == pytest.approx(v1 + v2, rel=1e-14)
    x = v2 * d / (v1 + v2)
    assert centroid == pytest.approx([x, 0, 0], abs=1e-14)
    across = sphere_inertia(r1) + sphere_inertia(r2) + v1 * x**2 + v2 * (d - x) ** 2
    assert np.diag(inertia) == pytest.approx([sphere_inertia(r1) + sphere_inertia(r2), across, across], rel=1e-13)
    assert np.abs(inertia - np.diag(np.diag(inertia))).max() < 1e-13 * across  # principal axes x, y, z


def test_overlapping_pebbles_count_their_lens_once():
    """Two equal spheres overlapping: the lens π (2r - d)² (d + 4r) / 12 counted once; a sphere
    inside another adds nothing; turned, the tensor turns with the clump (R I Rᵀ)."""
    r, d = 1.0, 1.0
    volume, centroid, inertia = union_properties([[0, 0, 0], [d, 0, 0]], [r, r])
    lens = math.pi * (2 * r - d) ** 2 * (d + 4 * r) / 12
    assert volume == pytest.approx(8 / 3 * math.pi - lens, rel=1e-14)
    assert centroid == pytest.approx([0.5, 0, 0], abs=1e-14)
    # about the axis, the union is a solid of revolution: the slices' polar moments π ρ⁴ / 2
    # summed over x, ρ² = r² - (x - d)² for x >= d/2 and its mirror image
    axial = 2 * math.pi / 2 * ((r**4 * r - 2 * r**2 * r**3 / 3 + r**5 / 5)
                               - (r**4 * (-d / 2) - 2 * r**2 * (-d / 2) ** 3 / 3 + (-d / 2) ** 5 / 5))
    assert inertia[0, 0] == pytest.approx(axial, rel=1e-13)
    assert union_properties([[0, 0, 0], [0.2, 0, 0]], [1.0, 0.5])[0] == pytest.approx(4 / 3 * math.pi, rel=1e-14)
    turn = random_rotation(np.random.default_rng(1))
    centres = np.array([[0, 0, 0], [d, 0, 0]]) @ turn.T
    turned = union_properties(centres, [r, r])[2]
    assert turned == pytest.approx(turn @ inertia @ turn.T, abs=1e-12 * inertia.max())


def test_the_three_pebble_core_is_counted_once():
    """Three unit spheres on a triangle of side 1 share a core: the grid over it puts the
    union's volume within the error of a Monte Carlo count's (an independent estimate)."""
    shape = template("three-pebble", dimensions=3)
    volume = union_properties(shape.offsets, shape.radii)[0]
    assert volume == pytest.approx(4 / 3 * math.pi, rel=1e-12)  # unit equivalent radius
    rng = np.random.default_rng(2)
    lo = (shape.offsets - shape.radii[:, None]).min(axis=0)
    hi = (shape.offsets + shape.radii[:, None]).max(axis=0)
    points = rng.uniform(lo, hi, (1_000_000, 3))
    inside = np.zeros(len(points), bool)
    for c, r in zip(shape.offsets, shape.radii):
        inside |= ((points - c) ** 2).sum(axis=1) < r * r
    counted = np.prod(hi - lo) * inside.mean()
    assert volume == pytest.approx(counted, rel=3e-3)  # the count's own error: 1e-3; the core: 7e-2


def test_the_3d_templates_have_the_2d_names_and_unit_equivalent_radius():
    assert GRAIN_SHAPES_3D == ("ball", "two-pebble", "three-pebble")
    for name in GRAIN_SHAPES_3D:
        shape = template(name, dimensions=3)
        volume, centroid, _ = union_properties(shape.offsets, shape.radii)
        assert volume == pytest.approx(4 / 3 * math.pi, rel=1e-12) and np.abs(centroid).max() < 1e-12
    with pytest.raises(Exception, match="grain_shape"):
        template("cloud", dimensions=3)


def free_clump(centres, radii, spin):
    """One clump of pebbles at `centres` (m) of `radii`, spinning at `spin` (rad/s), undamped."""
    state = assemble_state(np.asarray(centres, float), np.asarray(radii, float), np.empty((0, 2)), DENSITY, LAWS,
                           damping=0.0)
    clumps = clump(state, np.zeros(len(radii), np.int64), DENSITY)
    clumps.set_spin(0, spin)
    clumps.carry_pebbles(state.spheres)
    state.dt = 2e-6
    return state, clumps


def test_a_free_symmetric_top_precesses_as_euler_says():
    """Torque-free, a body symmetric about its axis e turns that axis about its fixed angular
    momentum L at the rate |L| / I⊥ (I⊥ its moment across the axis); L stays to the bit, the
    kinetic energy to 1e-9."""
    state, clumps = free_clump([[-0.5e-3, 0, 0], [0.5e-3, 0, 0]], [1e-3, 1e-3], [400.0, 300.0, 0.0])
    momentum, energy = clumps.momentum[0].copy(), clumps.kinetic_energy()
    across = np.linalg.eigvalsh(clumps.inertia[0]).max()  # the moment across the axis
    steps = 2000
    state.advance(steps)
    assert np.array_equal(clumps.momentum[0], momentum)
    assert clumps.kinetic_energy() == pytest.approx(energy, rel=1e-9)
    axis = state.spheres.pos[1] - state.spheres.pos[0]
    axis /= np.linalg.norm(axis)
    size = np.linalg.norm(momentum)
    unit = momentum / size
    turn = size / across * steps * state.dt  # Euler's precession angle, rad
    start = np.array([1.0, 0.0, 0.0])
    along = unit * (unit @ start)
    expected = along + (start - along) * math.cos(turn) + np.cross(unit, start) * math.sin(turn)
    assert turn > 1.0  # a fair part of a turn
    assert axis == pytest.approx(expected, abs=1e-5)
    # the pebbles move rigidly with the body: their distance and the spin they carry
    assert np.linalg.norm(state.spheres.pos[1] - state.spheres.pos[0]) == pytest.approx(1e-3, rel=1e-12)
    assert np.array_equal(state.spheres.spin[0], clumps.spin[0])


def test_two_clumps_colliding_keep_their_momentum():
    """Two two-pebble clumps meet off their centres' line: they bounce and spin, and their total
    linear and angular momentum (about the origin) stay what they were."""
    rng = np.random.default_rng(3)
    shape = template("two-pebble", dimensions=3)
    centres, radii, clump_of = [], [], []
    for c, (at, turn) in enumerate((((0.0, 0.0, 0.0), random_rotation(rng)),
                                    ((3.2e-3, 0.6e-3, 0.3e-3), random_rotation(rng)))):
        offsets, r = shape.pebbles(1e-3, turn)
        centres.append(np.asarray(at) + offsets)
        radii.append(r)
        clump_of += [c] * len(r)
    state = assemble_state(np.vstack(centres), np.concatenate(radii), np.empty((0, 2)), DENSITY, LAWS,
                           damping=0.0)
    clumps = clump(state, clump_of, DENSITY)
    clumps.vel[0], clumps.vel[1] = (2.0, 0.0, 0.0), (-1.0, 0.0, 0.0)
    clumps.carry_pebbles(state.spheres)
    state.dt = 1e-7  # 0.1 of sqrt(m / kn), a pebble's contact (none touch yet: no step of their own)
    mass = 1.0 / clumps.inv_mass

    def momenta():
        linear = (mass[:, None] * clumps.vel).sum(axis=0)
        angular = clumps.momentum.sum(axis=0) + (mass[:, None] * np.cross(clumps.pos, clumps.vel)).sum(axis=0)
        return linear, angular

    linear, angular = momenta()
    state.advance(int(2e-3 / state.dt))
    assert np.abs(clumps.vel[0] - (2.0, 0.0, 0.0)).max() > 0.5  # they met
    assert np.abs(clumps.spin).max() > 10.0  # off centre: they spin
    after_linear, after_angular = momenta()
    assert after_linear == pytest.approx(linear, abs=1e-12 * np.abs(linear).max())
    scale = np.abs(mass[:, None] * np.cross(clumps.pos, clumps.vel)).max()
    assert after_angular == pytest.approx(angular, abs=1e-6 * scale)


WEAK_GRANITE = {"E_c": 62, "kn_ks": 2.5, "sigma_c": 50, "tau_c": 50, "sigma_c_cv": 0.23, "tau_c_cv": 0.23,
                "mu": 0.5, "density": 2630}


def test_a_clumped_cylinder_is_whole_clumps_at_the_pressure_and_stronger_than_its_balls(small_cuboid, monkeypatch):
    """The 3D genesis on two-pebble clumps, from the balls' packing of `conftest.small_cuboid`:
    each clump of its sphere's volume, settled to P_m; the cylinder carved of whole clumps, no
    bond within one; its UCS positive and above the same packing's balls' at equal parameters
    (elongated grains interlock, and each bonds to more neighbours)."""
    from rockcal.labtests.ucs import simulate_ucs
    from rockcal.materials.parallel_bond import make_params
    from rockcal.specimens3d import specimen

    balls = small_cuboid
    monkeypatch.setattr(specimen, "packing", lambda *args, **kwargs: (balls.pos, balls.radius, balls.pressure_mpa, 0))
    clumped = specimen.random_specimen("cylinder", 10.0, 20.0, 0.6, seed=3, cache=False, grain_shape="two-pebble")
    assert clumped.pressure_mpa == pytest.approx(0.1, rel=0.05)
    counts = np.bincount(clumped.clump_of)
    assert (counts == 2).all()  # whole clumps, numbered 0..
    bi, bj = clumped.bonds.T
    assert (clumped.clump_of[bi] != clumped.clump_of[bj]).all()
    params = make_params(WEAK_GRANITE)
    ucs = [simulate_ucs(params, s).ucs_MPa for s in (specimen.carve_cylinder(balls), clumped)]
    assert 0 < ucs[0] < ucs[1]
