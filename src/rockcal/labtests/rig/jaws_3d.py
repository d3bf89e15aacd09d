"""ISRM's curved jaws on a 3D disk (axis along y, loaded along z: `platens_3d.disk_of`): the 2D
jaws (`rig.jaws`) drawn out along the disk's axis. Each jaw is a concave cylindrical face of
radius JAW_RADIUS_PER_DISK_RADIUS x the disk's radius, its axis along y, made of driven spheres
of the disk's smallest radius: rows along y, each row an arc in the x-z plane, the spheres at
most half a radius apart along the arc and along y, over the disk's whole thickness. The
spheres of one jaw are one rigid body: they never touch each other (`neighbours.NeighbourList.
clump_of`), only the disk's grains, through the engine's ordinary linear contacts (with the
rock's friction, as a steel jaw has). The jaws close at the platens' speed rule, their load is
the mean of the two jaws' forces along z, in N.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from rockcal.dem3d import neighbours
from rockcal.dem3d.simulate import stable_time_step
from rockcal.labtests.rig.jaws import (JAW_HALF_ARC_DEG, JAW_RADIUS_PER_DISK_RADIUS, Jaws, jaw_offsets,
                                      touching_jaw_centre_y)
from rockcal.labtests.rig.platens import STRAIN_PER_STEP_PER_ROW
from rockcal.labtests.rig.platens_3d import check_contact_stiffness, disk_of
from rockcal.materials import new_state

TOP_JAW, BOTTOM_JAW = 0, 1  # the jaws' rigid bodies (`clump_of`)


def jaw_spheres(centre_xz, offsets_xz: np.ndarray, y_from: float, y_to: float, sphere_m: float) -> np.ndarray:
    """Centres (k, 3) of a jaw's spheres: its arc's `offsets_xz` (x, z) from `centre_xz`, repeated
    in rows from `y_from` to `y_to` at most half a sphere radius apart."""
    rows = np.linspace(y_from, y_to, int(np.ceil((y_to - y_from) / (0.5 * sphere_m))) + 1)
    x = np.tile(centre_xz[0] + offsets_xz[:, 0], len(rows))
    z = np.tile(centre_xz[1] + offsets_xz[:, 1], len(rows))
    return np.column_stack([x, np.repeat(rows, len(offsets_xz)), z])


class Jaws3D(Jaws):
    """ISRM's curved jaws touching the 3D disk `specimen` from above and below at its centre's
    x: the engine `state` holds the disk's spheres, then the top jaw's (`is_top`) and the bottom
    one's (`is_bottom`); `centres` the jaws' axes' (x, z) and `jaw_radius_m` their radius; the
    `rows` of spheres across the disk, `chunk` steps between readings, the disk's
    `thickness_m`. They move, bear and close as the 2D jaws (`Jaws`), along z."""

    axis = 2

    def __init__(self, specimen, params, rate_factor: float, contact_stiffness: str | None = None):
        check_contact_stiffness(contact_stiffness)
        disk = disk_of(specimen)
        pos, radius = specimen.pos, specimen.radius
        xz = pos[:, [0, 2]]
        diameter, x = disk.diameter_m, disk.centre[0]
        self.jaw_radius_m = jaw_radius = JAW_RADIUS_PER_DISK_RADIUS * 0.5 * diameter
        self.centres = np.array([
            (x, touching_jaw_centre_y(xz, radius, x, jaw_radius, above=True)),
            (x, touching_jaw_centre_y(xz, radius, x, jaw_radius, above=False))])
        sphere = float(radius.min())
        offsets = jaw_offsets(jaw_radius, sphere, 0.5 * diameter * math.sin(math.radians(JAW_HALF_ARC_DEG)))
        y_from, y_to = (pos[:, 1] - radius).min(), (pos[:, 1] + radius).max()
        top = jaw_spheres(self.centres[0], offsets, y_from, y_to, sphere)
        bottom = jaw_spheres(self.centres[1], offsets * (1.0, -1.0), y_from, y_to, sphere)
        n = specimen.n_particles
        jaw = np.concatenate([np.full(n, -1), np.full(len(top), TOP_JAW), np.full(len(bottom), BOTTOM_JAW)])
        self.is_top, self.is_bottom = jaw == TOP_JAW, jaw == BOTTOM_JAW
        self.state = new_state(params, specimen, np.vstack([pos, top, bottom]),
                               np.concatenate([radius, np.full(len(top) + len(bottom), sphere)]),
                               driven=jaw >= 0)
        s, grains = self.state.spheres, self.state.neighbours.clump_of  # a clumped disk's clumps
        body = jaw if grains is None else np.where(jaw >= 0, grains.max() + 1 + jaw, grains)
        self.state.neighbours = neighbours.update(replace(self.state.neighbours, clump_of=body), s.pos, s.radius)
        self.state.dt = stable_time_step(self.state)
        self.rows = disk.diameter_m / (2 * radius.mean())
        self.speed = 0.5 * rate_factor * STRAIN_PER_STEP_PER_ROW / self.rows * diameter / self.state.dt
        self.chunk = max(5, int(self.rows / 8))
        self.thickness_m = disk.thickness_m
        self.y0 = self._heights()
