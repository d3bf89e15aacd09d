"""The curved loading jaws of ISRM's suggested method for the Brazilian test (ISRM 1978): two
rigid concave arcs of radius JAW_RADIUS_PER_DISK_RADIUS x the disk's radius (1.5 R, not 1.5 D),
one above and one below the disk, closing on it along its vertical diameter. As the bending
test's pins, each jaw is built from small driven disks (`rig.arc`), here on the arc that faces
the disk, so the engine's ordinary linear contacts (with the rock's friction, as a steel jaw
has) carry the load. The jaws close at the platens' speed rule (`rig.platens`), the load is read
as the platens' is (the mean of the two jaws' vertical forces).
"""

from __future__ import annotations

import math

import numpy as np

from rockcal.dem.simulate import DEFAULT_CONTACT_STIFFNESS, THICKNESS_M
from rockcal.specimens.specimen import Specimen
from rockcal.labtests.rig.arc import arc_disks, with_rigid_parts
from rockcal.labtests.rig.platens import STRAIN_PER_STEP_PER_ROW

# ISRM (1978): the jaws' face radius is 1.5 times the specimen's radius, so that the arc of
# contact is about 10 degrees at failure.
JAW_RADIUS_PER_DISK_RADIUS = 1.5
# Each jaw faces the disk's rim within this angle either side of the loaded diameter: 60
# degrees of it, six times ISRM's contact arc at failure, so the contact never reaches a jaw's
# edge (the standard gives the jaws' curvature, not their width).
JAW_HALF_ARC_DEG = 30.0


def jaw_offsets(jaw_radius: float, disk_radius: float, half_width: float) -> np.ndarray:
    """Centres of small disks of `disk_radius`, relative to the jaw's centre of curvature, whose
    inner envelope is the upper arc of radius `jaw_radius` up to `half_width` either side of
    the centre (the top jaw; the bottom one is its mirror image, y negated)."""
    half_angle = math.asin(half_width / jaw_radius)
    return arc_disks((0.0, 0.0), jaw_radius + disk_radius, 0.5 * math.pi - half_angle,
                     0.5 * math.pi + half_angle, disk_radius)


def touching_jaw_centre_y(pos, radius, x: float, jaw_radius: float, above: bool) -> float:
    """Height of a concave jaw's centre of curvature at `x` such that the jaw just touches the
    disk from above (or below): every grain under it then lies inside the jaw's circle, at a
    distance <= jaw_radius - its radius from the centre."""
    inner = jaw_radius - radius
    under = np.abs(pos[:, 0] - x) < inner
    drop = np.sqrt(inner[under] ** 2 - (pos[under, 0] - x) ** 2)
    return float((pos[under, 1] - drop).max() if above else (pos[under, 1] + drop).min())


class Jaws:
    """ISRM's curved jaws touching the disk `specimen` from above and below at its centre's x,
    made of disks of its smallest radius. The engine `state` holds the disk's grains, then the
    top jaw's disks (`is_top`) and the bottom one's (`is_bottom`); `centres` are the jaws'
    centres of curvature (top, bottom) and `jaw_radius_m` their radius; `rows` of grains
    across the disk, `chunk` steps between readings, the disk's `thickness_m`; the jaws move
    along the `axis` of the loaded diameter (y)."""

    axis = 1

    def __init__(self, specimen: Specimen, params, rate_factor: float, contact_stiffness: str | None = None):
        contact_stiffness = contact_stiffness or DEFAULT_CONTACT_STIFFNESS
        pos, radius = specimen.pos, specimen.radius
        top, bottom = (pos[:, 1] + radius).max(), (pos[:, 1] - radius).min()
        diameter = top - bottom
        x = 0.5 * ((pos[:, 0] - radius).min() + (pos[:, 0] + radius).max())
        self.jaw_radius_m = jaw_radius = JAW_RADIUS_PER_DISK_RADIUS * 0.5 * diameter
        self.centres = np.array([
            (x, touching_jaw_centre_y(pos, radius, x, jaw_radius, above=True)),
            (x, touching_jaw_centre_y(pos, radius, x, jaw_radius, above=False))])
        offsets = jaw_offsets(jaw_radius, radius.min(),
                              0.5 * diameter * math.sin(math.radians(JAW_HALF_ARC_DEG)))
        self.state, (self.is_top, self.is_bottom) = with_rigid_parts(
            specimen, params, [self.centres[0] + offsets, self.centres[1] + offsets * (1.0, -1.0)],
            contact_stiffness)
        self.rows = diameter / (2 * radius.mean())
        self.speed = 0.5 * rate_factor * STRAIN_PER_STEP_PER_ROW / self.rows * diameter / self.state.dt
        self.chunk = max(5, int(self.rows / 8))
        self.thickness_m = THICKNESS_M
        self.y0 = self._heights()

    def _heights(self) -> tuple[float, float]:
        """The top and the bottom jaw's mean height, m."""
        y = self.state.particles.pos[:, self.axis]
        return float(y[self.is_top].mean()), float(y[self.is_bottom].mean())

    def move(self, factor: float) -> None:
        """Close the jaws at `factor` x the full speed."""
        vel = self.state.particles.vel
        vel[self.is_top, self.axis] = -self.speed * factor
        vel[self.is_bottom, self.axis] = self.speed * factor

    def load(self) -> float:
        """The force on the jaws along the loaded diameter (mean of the two), N per m of
        thickness (2D), N (3D)."""
        force = self.state.particles.force
        return float(0.5 * (force[self.is_top, self.axis].sum() - force[self.is_bottom, self.axis].sum()))

    def closure_m(self) -> float:
        """How far the jaws have closed in since the start (both together), m."""
        top, bottom = self._heights()
        return (self.y0[0] - top) + (bottom - self.y0[1])
