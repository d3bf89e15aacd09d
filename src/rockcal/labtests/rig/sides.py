"""Side walls that confine the specimen between the platens at a stress sigma3, as FISHTank's
compression test with a confining pressure (`ct.fis`, ct_Pc): PFC's wall servo
(`rockcal.labtests.rig.servo`) seats the specimen with all four walls at sigma3 until
equilibrium, then holds sigma3 on the side walls while the platens load it.
"""

from __future__ import annotations

import numpy as np

from rockcal.dem.simulate import BOTTOM, LEFT, RIGHT, THICKNESS_M, TOP, unbalanced_forces
from rockcal.specimens.specimen import Specimen
from rockcal.labtests.result import RunFailed, failed_run
from rockcal.labtests.rig.platens import Platens
from rockcal.labtests.rig.servo import SPEED_LIMIT, WallServo
from rockcal.params import MPa

SEATING_TOLERANCE = 0.005  # each wall's stress within this of sigma3 (FISHTank's ct_PTol)
EQUILIBRIUM_RATIO = 1e-4  # mean unbalanced force / (sigma3 x mean diameter x t)
SEATING_ROUNDS = 20_000  # servo updates at most before the seating counts as failed


class SideWalls:
    """Two side walls touching `specimen` between `platens`, servo-controlled to `target_Pa`
    (compression positive) at speeds up to SPEED_LIMIT x the platens' full speed; `steps` time
    steps between the servo's updates."""

    def __init__(self, platens: Platens, specimen: Specimen, target_Pa: float):
        self.state = state = platens.state
        walls = state.walls
        walls.pos[LEFT] = (specimen.pos[:, 0] - specimen.radius).min()
        walls.pos[RIGHT] = (specimen.pos[:, 0] + specimen.radius).max()
        walls.active[LEFT] = walls.active[RIGHT] = True
        self.limit = SPEED_LIMIT * platens.speed
        self.grain_diameter = 2 * specimen.radius.mean()
        self.servo = WallServo(state, (LEFT, RIGHT), target_Pa, self.limit)
        self.steps = self.servo.steps

    def seat(self) -> int:
        """Servo all four walls to sigma3 until equilibrium (`settle`, the unbalanced force's
        scale sigma3 x mean grain diameter x t) and stop them; the steps it took."""
        state = self.state
        servo = WallServo(state, (LEFT, RIGHT, BOTTOM, TOP), self.servo.target, self.limit)
        steps = settle(servo, state.advance, lambda: np.hypot(*unbalanced_forces(state).T),
                       servo.target * self.grain_diameter * THICKNESS_M)
        if steps is None:
            raise RunFailed(f"the specimen did not settle at the confinement of {servo.target / MPa:g} MPa "
                            f"in {SEATING_ROUNDS * servo.steps} steps (the servo-controlled walls could not "
                            "bring it to equilibrium): a confinement near 0 is below what the servo resolves, "
                            "one near the grains' stiffness or the bonds' strength crushes the specimen; try "
                            "another confinement, or a larger specimen")
        return steps

    def update(self) -> None:
        """Set the side walls' speeds from the stresses they bear now."""
        self.servo.update()

    def stress_Pa(self) -> float:
        """sigma3: the side walls' mean normal stress, Pa."""
        return float(self.servo.stresses()[[LEFT, RIGHT]].mean())


@failed_run()  # a model that broke while seating: the test's RunFailed
def settle(servo, advance_steps, unbalanced_N, scale_N: float) -> int | None:
    """Update `servo` and step (`advance_steps(n)`) until every one of its walls is within
    SEATING_TOLERANCE of its target and the bodies' mean unbalanced force (`unbalanced_N()`,
    one magnitude per free body) is below EQUILIBRIUM_RATIO x `scale_N`, then stop the walls;
    the steps it took, or None after SEATING_ROUNDS updates."""
    for round_ in range(1, SEATING_ROUNDS + 1):
        servo.update()
        advance_steps(servo.steps)
        off = np.abs(servo.stresses() / servo.target - 1.0)
        if off.max() < SEATING_TOLERANCE and unbalanced_N().mean() < EQUILIBRIUM_RATIO * scale_N:
            servo.hold()
            return round_ * servo.steps
    return None
