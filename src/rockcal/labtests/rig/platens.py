"""Two frictionless platens closing on a specimen at a quasi-static speed: the loading of the
UCS, confined compression and Brazilian tests; bare, or each with a `BearingStrip` (a thin
cushion, as ASTM D3967 allows in the Brazilian test) between it and the specimen.

The platens close at an axial strain per step of STRAIN_PER_STEP_PER_ROW / (rows of particles
between them), so the number of wave transits to the peak is the same for every specimen size.
The elastic part is rate-insensitive; `rockcal.labtests.loading` ramps the platens in and slows
them down where bonds break.
"""

from __future__ import annotations

from dataclasses import dataclass

from rockcal.dem.simulate import BOTTOM, DEFAULT_CONTACT_STIFFNESS, THICKNESS_M, TOP, stable_time_step
from rockcal.specimens.specimen import Specimen
from rockcal.errors import InputError
from rockcal.materials import new_state

STRAIN_PER_STEP_PER_ROW = 2e-5


@dataclass(frozen=True)
class BearingStrip:
    """A thin cushion between a platen and the specimen, linear elastic through its thickness:
    its Young's modulus `modulus_GPa` that way and its `thickness_mm`. Under a grain it is a
    column as wide as the grain, so each grain's contact with the platen is that column (normal
    stiffness E_strip x grain width x t / thickness, N/m) in series with the bare platen's
    contact (the grain's own deformability). The platen stays frictionless: the strip changes
    the normal stiffness alone."""

    modulus_GPa: float
    thickness_mm: float

    def __post_init__(self):
        for name, value in (("strip_modulus_GPa", self.modulus_GPa), ("strip_thickness_mm", self.thickness_mm)):
            if not (value > 0 and value < float("inf")):
                raise InputError(name, f"must be a finite number > 0, got {value}")

    def column_stiffness(self, grain_width_m: float) -> float:
        """The normal stiffness of the strip's column under a grain `grain_width_m` wide, N/m
        (per m of thickness, 2D)."""
        return 1e9 * self.modulus_GPa * grain_width_m * THICKNESS_M / (1e-3 * self.thickness_mm)

    def contact_stiffness(self, grain_width_m: float, bare_N_per_m: float) -> float:
        """A grain's normal contact stiffness with the platen through the strip: its column in
        series with the bare platen's contact `bare_N_per_m`, N/m."""
        return 1.0 / (1.0 / self.column_stiffness(grain_width_m) + 1.0 / bare_N_per_m)


@dataclass(frozen=True)
class Disk:
    """A Brazilian disk as its test reads it: its diameter and thickness (m), the centre of its
    outline in the loaded plane (across the loaded diameter, along it; m), the loaded axis (the
    platens' normal: y in 2D, z in 3D) and how many grains deep a crack across it is counted
    (`grains_deep`: one in 2D, the thickness in grains in 3D)."""

    diameter_m: float
    thickness_m: float
    centre: tuple[float, float]
    axis: int
    grains_deep: float


def disk_of(specimen: Specimen) -> Disk:
    """A 2D disk: its grains' extent along the loaded diameter, the slab's unit thickness."""
    pos, radius = specimen.pos, specimen.radius
    diameter = (pos[:, 1] + radius).max() - (pos[:, 1] - radius).min()
    centre = tuple(0.5 * ((pos[:, a] - radius).min() + (pos[:, a] + radius).max()) for a in range(2))
    return Disk(diameter, THICKNESS_M, centre, 1, 1.0)


class Platens:
    """A specimen between a bottom and a top platen that touch it: the engine `state`, the
    platens' starting heights `bottom` and `top` (m), the `rows` of particles between them, the
    `chunk` of steps between readings, the specimen's `thickness_m` and its loaded `area_m2`
    (width x thickness). With a bearing `strip` on each platen a grain's contact with it has
    the strip's stiffness under a grain of the specimen's mean diameter (the engine's platens
    have one contact stiffness), and the time step is the one it allows. `contact_stiffness`:
    PFC's convention for kn (`simulate.CONTACT_STIFFNESS`; None: the default)."""

    def __init__(self, specimen: Specimen, params, rate_factor: float, contact_stiffness: str | None = None,
                 strip: BearingStrip | None = None, side_walls: bool = False):
        pos, radius = specimen.pos, specimen.radius
        self.bottom, self.top = (pos[:, 1] - radius).min(), (pos[:, 1] + radius).max()
        # the side walls are in the state whatever `side_walls`, at rest until `SideWalls` moves them
        self.state = new_state(params, specimen, walls=(0.0, 0.0, self.bottom, self.top),
                               wall_active=(False, False, True, True),
                               contact_stiffness=contact_stiffness or DEFAULT_CONTACT_STIFFNESS)
        if strip is not None:
            walls = self.state.walls
            self.state.walls = walls._replace(
                stiffness=strip.contact_stiffness(2 * radius.mean(), walls.stiffness))
            self.state.dt = stable_time_step(self.state)
        height = self.top - self.bottom
        self.rows = height / (2 * radius.mean())
        self.speed = 0.5 * rate_factor * STRAIN_PER_STEP_PER_ROW / self.rows * height / self.state.dt
        self.chunk = max(5, int(self.rows / 8))
        self.thickness_m = THICKNESS_M
        self.area_m2 = specimen.width_m * THICKNESS_M

    def move(self, factor: float) -> None:
        """Close the platens at `factor` x the full speed."""
        state = self.state
        state.walls.vel[BOTTOM], state.walls.vel[TOP] = self.speed * factor, -self.speed * factor

    def load(self) -> float:
        """The force on the platens (mean of the two), N per m of thickness."""
        f = self.state.walls.total_force()
        return 0.5 * (f[BOTTOM] + f[TOP])

    def strain(self) -> float:
        """The axial strain from the platens' separation (FISHTank's wall-based strain),
        shortening positive."""
        at = self.state.walls.pos
        return 1.0 - (at[TOP] - at[BOTTOM]) / (self.top - self.bottom)

    def closure_m(self) -> float:
        """How far the platens have closed in since the start (both together), m."""
        at = self.state.walls.pos
        return (at[BOTTOM] - self.bottom) + (self.top - at[TOP])

    def zero(self) -> None:
        """Read strain and closure from the platens' present heights on (after a seating)."""
        self.bottom, self.top = self.state.walls.pos[BOTTOM], self.state.walls.pos[TOP]
