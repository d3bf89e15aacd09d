"""The side walls of the 3D rig: four walls confining a prism between its platens at a stress
sigma3 (a polyaxial vessel with sigma2 = sigma3, FISHTank's compression test with a confining
pressure in PFC3D): the 2D rig's side walls (`rockcal.labtests.rig.sides`) on the four lateral
faces.

The servo is the 2D rig's law (`rockcal.labtests.rig.servo`: velocity G (sigma - sigma3) plus
an integral term, G = alpha A / (k_n N_c dt_servo), updated every STEPS steps, capped at
SPEED_LIMIT x the platens' speed) with a wall's stress its normal force over its current face:
a side wall's face is the other pair of side walls' span times the platens' span, a platen's
the two spans of the side walls, so a face shrinks or grows as the other walls move. k_n is a
wall contact's pi E R at the mean radius and N_c the spheres touching the wall now.
"""

from __future__ import annotations

import numpy as np

from rockcal.dem3d.vectors import norms
from rockcal.dem3d.walls import Wall, touching_counts
from rockcal.labtests.result import RunFailed
from rockcal.labtests.rig.platens_3d import BOTTOM, SIDES, TOP, Platens3D
from rockcal.labtests.rig.servo import (
    ALPHA,
    BETA,
    SPEED_LIMIT,
    STEPS,
    servo_gain,
    servo_speed,
)
from rockcal.labtests.rig.sides import SEATING_ROUNDS, settle
from rockcal.params import MPa


class WallServo3D:
    """Some walls of `state` servo-controlled to `target_Pa` (compression positive), their
    speeds along their normals updated every `steps` time steps and capped at `limit` (m/s)."""

    def __init__(self, state, walls: tuple[int, ...], target_Pa: float, limit: float,
                 steps: int = STEPS):
        self.state, self.walls, self.target, self.limit, self.steps = state, walls, target_Pa, limit, steps
        self.integral = {w: 0.0 for w in walls}
        self.kn = np.pi * state.walls.table[0, Wall.MODULUS] * float(state.spheres.radius.mean())

    def faces(self) -> np.ndarray:
        """Each wall's present face (bottom, top, -x, +x, -y, +y), m²: the product of the
        vessel's two spans across its normal, between the other walls."""
        at = self.state.walls.point
        x, y = float(at[SIDES[1], 0] - at[SIDES[0], 0]), float(at[SIDES[3], 1] - at[SIDES[2], 1])
        z = float(at[TOP, 2] - at[BOTTOM, 2])
        return np.array([x * y, x * y, y * z, y * z, x * z, x * z])

    def stresses(self) -> np.ndarray:
        """Each wall's normal stress (bottom, top, -x, +x, -y, +y), Pa: its normal force over
        its present face."""
        return self.state.walls.normal_force() / self.faces()

    def update(self) -> None:
        """Set the servo walls' speeds from the stresses they bear now."""
        walls, faces = self.state.walls, self.faces()
        stress = walls.normal_force() / faces
        touching = touching_counts(walls.table, self.state.spheres.bodies)
        for w in self.walls:
            push = servo_gain(ALPHA, float(faces[w]), self.kn * max(1, int(touching[w])), self.steps,
                              self.state.dt) * (float(stress[w]) - self.target)
            speed, self.integral[w] = servo_speed(push, self.integral[w], BETA, self.limit)
            self.drive(w, speed)

    def drive(self, w: int, speed: float) -> None:
        """Move wall w outward at `speed` (m/s): against its normal, which faces in."""
        self.state.walls.vel[w] = -speed * self.state.walls.normal[w]

    def hold(self) -> None:
        """Stop the servo walls."""
        for w in self.walls:
            self.drive(w, 0.0)
            self.integral[w] = 0.0


class SideWalls3D:
    """The four side walls of `platens` (built with `side_walls`), servo-controlled to
    `target_Pa` at speeds up to SPEED_LIMIT x the platens' full speed; `steps` time steps
    between the servo's updates."""

    walls = SIDES  # the confining walls, which keep sigma3 through the loading

    def __init__(self, platens: Platens3D, specimen, target_Pa: float):
        self.state = platens.state
        self.limit = SPEED_LIMIT * platens.speed
        self.grain_diameter = 2 * float(specimen.radius.mean())
        self.servo = self.servo_of(self.walls, target_Pa)
        self.steps = self.servo.steps

    def servo_of(self, walls: tuple[int, ...], target_Pa: float) -> WallServo3D:
        """A servo of some of the rig's walls."""
        return WallServo3D(self.state, walls, target_Pa, self.limit)

    def seat(self) -> int:
        """Servo all six walls to sigma3 until equilibrium (`rig.sides.settle`, the unbalanced
        force's scale sigma3 x the mean sphere diameter squared) and stop them; the steps it took."""
        state = self.state
        servo = self.servo_of((BOTTOM, TOP, *self.walls), self.servo.target)
        free = state.spheres.inv_mass > 0
        steps = settle(servo, state.advance, lambda: norms(state.spheres.force[free]),
                       servo.target * self.grain_diameter**2)
        if steps is None:
            raise RunFailed(f"the specimen did not settle at the confinement of {servo.target / MPa:g} MPa in "
                            f"{SEATING_ROUNDS * servo.steps} steps (the servo-controlled walls could not bring "
                            "it to equilibrium): a confinement near the spheres' stiffness or the bonds' "
                            "strength crushes the specimen; try another confinement, or a larger specimen")
        return steps

    def update(self) -> None:
        """Set the side walls' speeds from the stresses they bear now."""
        self.servo.update()

    def stresses_Pa(self) -> np.ndarray:
        """Each confining wall's normal stress (a prism's -x, +x, -y, +y; the cell's cylinder), Pa."""
        return self.servo.stresses()[list(self.walls)]

    def stress_Pa(self) -> float:
        """sigma3: the confining walls' mean normal stress, Pa."""
        return float(self.stresses_Pa().mean())
