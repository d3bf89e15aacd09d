"""The platens of the 3D rig: two frictionless platens (walls normal to z) closing on a 3D
specimen at the 2D rig's quasi-static speed rule (`rockcal.labtests.rig.platens`): an axial
strain per step of STRAIN_PER_STEP_PER_ROW / (rows of spheres between them), so the number of
wave transits to the peak is the same for every specimen size; `rockcal.labtests.loading`
ramps them in and slows them where bonds break. Optionally a confining vessel's walls at rest
after them: four side walls about a prism (`sides_3d`), a cylindrical wall about a cylinder
(`cell_3d`); and a bearing strip on each platen (`BearingStrip`).

A bearing strip under a sphere of radius R is a column of its cross-section pi R^2, stiffness
E_strip pi R^2 / thickness, in series with the bare platen's contact pi E R. The engine's walls
have one modulus per wall (a sphere's contact pi E R), so the strip's contact is the series
stiffness at the specimen's mean radius, as the 2D platens take it at the mean diameter
(`strip_modulus_pa`).
"""

from __future__ import annotations

import numpy as np

from rockcal.dem3d.laws import CONTACT_STIFFNESS
from rockcal.dem3d.simulate import stable_time_step
from rockcal.dem3d.walls import Wall, with_cylinder
from rockcal.errors import InputError
from rockcal.labtests.rig.platens import STRAIN_PER_STEP_PER_ROW, BearingStrip, Disk
from rockcal.materials import new_state

BOTTOM, TOP = 0, 1
SIDES = (2, 3, 4, 5)  # with side walls: -x, +x, -y, +y, after the platens
CYLINDER = 2  # a cylinder's confining wall, after the platens


def strip_modulus_pa(strip: BearingStrip, bare_modulus_pa: float, radius_m: float) -> float:
    """The platen's contact modulus with a bearing `strip` on it: E such that a sphere of
    `radius_m`'s contact pi E R is its strip column (E_strip pi R^2 / thickness) in series
    with the bare platen's contact (pi `bare_modulus_pa` R), Pa."""
    column = 1e9 * strip.modulus_GPa * np.pi * radius_m**2 / (1e-3 * strip.thickness_mm)
    bare = np.pi * bare_modulus_pa * radius_m
    return float(1.0 / (1.0 / column + 1.0 / bare) / (np.pi * radius_m))


def disk_of(specimen) -> Disk:
    """A 3D disk (`specimens3d.specimen.random_disk`): the nominal D and t it was carved to, its axis
    along y, loaded along z."""
    if specimen.shape != "disk":
        raise InputError("specimen", f"the Brazilian test needs a disk, got a {specimen.shape}")
    pos, radius = specimen.pos, specimen.radius
    diameter, thickness, _ = specimen.size_m
    centre = tuple(float(0.5 * ((pos[:, a] - radius).min() + (pos[:, a] + radius).max())) for a in (0, 2))
    return Disk(diameter, thickness, centre, 2, thickness / (2 * float(radius.mean())))


def check_contact_stiffness(contact_stiffness: str | None) -> None:
    """The 3D engine's contacts take PFC 5's stiffness alone (None: it)."""
    if contact_stiffness not in (None, CONTACT_STIFFNESS):
        raise InputError("contact_stiffness", f"the 3D engine's contacts take PFC 5's stiffness "
                                              f"({CONTACT_STIFFNESS!r}), got {contact_stiffness!r}")


class Platens3D:
    """A specimen between a bottom and a top platen that touch it: the engine `state`, the
    platens' starting heights (m), the `rows` of spheres between them, the `chunk` of steps
    between readings, the loaded `area_m2` (the nominal cross-section) and, of a disk, its
    `thickness_m`. With a bearing `strip` on each platen their contacts have the strip's
    modulus under a sphere of the mean radius. With `side_walls`, the state has four more
    walls at rest (SIDES: -x, +x, -y, +y) touching the specimen's outermost spheres (a
    confining vessel, `sides_3d`). `contact_stiffness`: PFC 5's, the 3D engine's only (None:
    it). A cylinder's vessel (`side_walls`) is instead a cylindrical wall about its axis touching
    its outermost spheres (CYLINDER: the triaxial cell, `cell_3d`)."""

    def __init__(self, specimen, params, rate_factor: float, contact_stiffness: str | None = None,
                 strip: BearingStrip | None = None, side_walls: bool = False):
        check_contact_stiffness(contact_stiffness)
        pos, radius = specimen.pos, specimen.radius
        self.bottom, self.top = (pos[:, 2] - radius).min(), (pos[:, 2] + radius).max()
        centre = pos.mean(axis=0)
        points, normals = [(centre[0], centre[1], self.bottom), (centre[0], centre[1], self.top)], \
            [(0, 0, 1), (0, 0, -1)]
        cell = side_walls and specimen.shape == "cylinder"
        if side_walls and not cell:
            low, high = (pos - radius[:, None]).min(axis=0), (pos + radius[:, None]).max(axis=0)
            for a in (0, 1):
                for at, facing in ((low, 1.0), (high, -1.0)):
                    point = centre.copy()
                    point[a] = at[a]
                    points.append(tuple(point))
                    normals.append(tuple(facing * np.eye(3)[a]))
        self.state = new_state(params, specimen, walls=(points, normals))
        if cell:
            axis = 0.5 * np.asarray(specimen.size_m[:2])  # its vessel's, as the genesis packed it
            reach = float((np.hypot(*(pos[:, :2] - axis).T) + radius).max())
            walls = self.state.walls
            self.state.walls = with_cylinder(walls, (*axis, centre[2]), (0, 0, 1), reach,
                                             float(walls.table[0, Wall.MODULUS]))
        if strip is not None:
            table = self.state.walls.table
            table[:, Wall.MODULUS] = strip_modulus_pa(strip, float(table[0, Wall.MODULUS]), float(radius.mean()))
        if cell or strip is not None:
            self.state.dt = stable_time_step(self.state)
        height = self.top - self.bottom
        self.rows = height / (2 * radius.mean())
        self.speed = 0.5 * rate_factor * STRAIN_PER_STEP_PER_ROW / self.rows * height / self.state.dt
        self.chunk = max(5, int(self.rows / 8))
        x, y, _ = specimen.size_m
        self.area_m2 = np.pi / 4 * x * y if specimen.shape == "cylinder" else x * y
        self.thickness_m = y  # a disk's, along its axis

    def move(self, factor: float) -> None:
        """Close the platens at `factor` x the full speed."""
        vel = self.state.walls.vel
        vel[BOTTOM, 2], vel[TOP, 2] = self.speed * factor, -self.speed * factor

    def load(self) -> float:
        """The force on the platens (mean of the two), N."""
        return float(self.state.walls.normal_force()[[BOTTOM, TOP]].mean())

    def strain(self) -> float:
        """The axial strain from the platens' separation, shortening positive."""
        z = self.state.walls.point[:, 2]
        return 1.0 - (z[TOP] - z[BOTTOM]) / (self.top - self.bottom)

    def closure_m(self) -> float:
        """How far the platens have closed in since the start (both together), m."""
        z = self.state.walls.point[:, 2]
        return float((z[BOTTOM] - self.bottom) + (self.top - z[TOP]))

    def zero(self) -> None:
        """Read strain and closure from the platens' present heights on (after a seating)."""
        z = self.state.walls.point[:, 2]
        self.bottom, self.top = float(z[BOTTOM]), float(z[TOP])
