"""The cylindrical wall (`rockcal.dem3d.walls.with_cylinder`), the triaxial cell's (`test_cell_3d`):

- a sphere pressed into the cylinder's inner surface is pushed towards the axis by π E R times
  its overlap, wherever it sits along and around the axis; the wall bears that push as its
  radial force, with no moment on the sphere; the radius grows at its radial speed;
- the walls' reactions are the same bits on one thread or two.
"""

import numpy as np
import pytest
from test_walls_3d import DENSITY, E_WALL, LAWS, R, squeezed_block

from rockcal.dem3d.simulate import advance, assemble_state
from rockcal.dem3d.walls import Wall, new_walls, no_walls, with_cylinder

AXIS = np.array([2.0, -1.0, 2.0]) / 3.0
RADIUS = 5e-3


@pytest.mark.parametrize("angle, along", [(0.0, 0.0), (2.0, 3e-3), (4.5, -7e-3)])
def test_a_sphere_pressed_into_a_cylinder_is_pushed_to_its_axis_by_pi_E_R_times_the_overlap(angle, along):
    overlap = 2e-6
    across = np.cross(AXIS, [0.0, 0.0, 1.0])
    across /= np.linalg.norm(across)
    outward = np.cos(angle) * across + np.sin(angle) * np.cross(AXIS, across)
    centre = np.array([1e-3, 2e-3, -1e-3])
    walls = with_cylinder(no_walls(), centre, AXIS, RADIUS, E_WALL)
    state = assemble_state([centre + along * AXIS + (RADIUS - R + overlap) * outward], [R],
                           np.empty((0, 2)), DENSITY, LAWS, driven=[0], walls=walls)
    advance(state, 1)
    push = np.pi * E_WALL * R * overlap
    assert state.walls.normal_force()[0] == pytest.approx(push, rel=1e-9)
    assert np.allclose(state.spheres.force[0], -push * outward, rtol=1e-9, atol=1e-12 * push)
    assert not state.spheres.moment.any()


def test_the_radius_grows_at_its_radial_speed_and_a_plane_beside_it_is_unchanged():
    walls = with_cylinder(new_walls([(0.0, 0.0, 0.0)], [(0.0, 0.0, 1.0)], E_WALL), (0, 0, 0), (0, 0, 1),
                          RADIUS, E_WALL)
    walls.table[1, Wall.RADIAL_VEL] = 0.3
    state = assemble_state([(0.0, 0.0, 2 * R)], [R], np.empty((0, 2)), DENSITY, LAWS, walls=walls)
    state.dt = 1e-7
    advance(state, 100)
    assert state.walls.table[1, Wall.RADIUS] == pytest.approx(RADIUS + 100 * 1e-7 * 0.3, rel=1e-12)
    assert state.walls.cylinder.tolist() == [False, True]
    assert (state.walls.point == 0).all()


def closing_cylinder(pos, radius):
    """Two plates at a block's ends and a cylinder about it closing in on it."""
    low, high = pos.min(axis=0) - R, pos.max(axis=0) + R
    centre = 0.5 * (low + high)
    plates = new_walls([(*centre[:2], low[2]), (*centre[:2], high[2])], [(0, 0, 1), (0, 0, -1)], E_WALL)
    reach = float((np.hypot(*(pos[:, :2] - centre[:2]).T) + radius).max())
    walls = with_cylinder(plates, centre, (0, 0, 1), reach - 0.5 * R, E_WALL)
    walls.table[2, Wall.RADIAL_VEL] = -0.5
    return walls


def test_the_cylinder_s_force_is_bit_reproducible_on_one_thread_or_two():
    one, two = squeezed_block(1, closing_cylinder), squeezed_block(2, closing_cylinder)
    assert len(one.neighbours.block_starts) == 3
    assert (one.walls.normal_force() > 0).all()
    assert np.array_equal(one.spheres.bodies, two.spheres.bodies)
    assert np.array_equal(one.walls.force, two.walls.force)
