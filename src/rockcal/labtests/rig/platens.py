"""Two frictionless platens closing on a specimen at a quasi-static speed: the loading of the
UCS, confined compression and Brazilian tests.

The platens close at an axial strain per step of STRAIN_PER_STEP_PER_ROW / (rows of particles
between them), so the number of wave transits to the peak is the same for every specimen size.
The elastic part is rate-insensitive; `rockcal.labtests.loading` ramps the platens in and slows
them down where bonds break.
"""

from __future__ import annotations

from rockcal.dem.simulate import BOTTOM, DEFAULT_CONTACT_STIFFNESS, THICKNESS_M, TOP
from rockcal.dem.specimen import Specimen
from rockcal.materials import new_state

STRAIN_PER_STEP_PER_ROW = 2e-5


class Platens:
    """A specimen between a bottom and a top platen that touch it: the engine `state`, the
    platens' starting heights `bottom` and `top` (m), the `rows` of particles between them, the
    `chunk` of steps between readings, the specimen's `thickness_m` and its loaded `area_m2`
    (width x thickness)."""

    def __init__(self, specimen: Specimen, params, rate_factor: float,
                 contact_stiffness: str = DEFAULT_CONTACT_STIFFNESS):
        pos, radius = specimen.pos, specimen.radius
        self.bottom, self.top = (pos[:, 1] - radius).min(), (pos[:, 1] + radius).max()
        self.state = new_state(params, specimen, walls=(0.0, 0.0, self.bottom, self.top),
                               wall_active=(False, False, True, True),
                               contact_stiffness=contact_stiffness)
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
