"""Walls servo-controlled to a normal stress: PFC's classic servo-mechanism (Itasca, PFC2D
manual, "servo-control of walls"; FISHTank's material vessel, `ct.fis`), plus an integral term.

Each servo wall moves outward at

    v = G (sigma_measured - sigma_target) + I,   G = alpha A / (k_n N_c dt_servo),

where A is the wall's loaded length x thickness (the specimen's current height for a side wall,
its width for a platen), k_n the wall contacts' normal stiffness, N_c the particles touching the
wall and dt_servo the time between updates (`steps` time steps): in one update the wall then
moves by alpha A (sigma - sigma_target) / (k_n N_c), which would correct the fraction alpha < 1
of the stress error if the wall contacts were the only compliance (the specimen behind them
makes it less, so the servo is stable). The velocity is set every `steps` time steps, not every
step as in PFC: a wall following a specimen that expands at a constant rate then lags behind by
a stress error v / G (4.5 % of sigma3 = 10 MPa with G alone, updates every 5 steps, on a
10 x 20 mm granite specimen under the UCS loading rate); the integral term
I += beta G (sigma - sigma_target) takes that lag up. Speeds are capped at `limit` (FISHTank's
ct_vLimit: 20 x the loading speed). Measured on two 10 x 20 mm granite specimens at sigma3 =
10 MPa (updates every 2 steps, alpha 0.5, beta 0.3): the side walls' mean stress over the axial
loading up to the peak within 0.01 % of sigma3, its mean over each ramp of the loading (40
readings) within 0.4 %, 95 % of the readings within 0.8 %, the largest 5 % (as the specimen
fails). A wall's stress scatters by about 0.1 MPa whatever sigma3, so at sigma3 = 1 MPa 95 % of
the readings are within 2-3.5 %; updates every 5 steps triple the errors.
"""

from __future__ import annotations

import numpy as np

from rockcal.dem.simulate import BOTTOM, LEFT, RIGHT, THICKNESS_M, TOP, State

ALPHA = 0.5  # the fraction of the stress error one update would correct through the wall contacts
BETA = 0.3  # the integral gain, per update, relative to G
STEPS = 2  # time steps between updates
SPEED_LIMIT = 20.0  # x the loading speed (FISHTank's ct_vLimit default)
OUTWARD = {LEFT: -1.0, RIGHT: 1.0, BOTTOM: -1.0, TOP: 1.0}  # a wall's outward direction


def servo_gain(alpha: float, area_m2: float, contacts_N_per_m: float, steps: int, dt: float) -> float:
    """G = alpha A / (k_n N_c dt_servo), (m/s)/Pa: `contacts_N_per_m` is k_n N_c, the wall's
    contacts' normal stiffness summed, dt_servo the `steps` time steps `dt` between updates."""
    return alpha * area_m2 / (contacts_N_per_m * steps * dt)


def servo_speed(push: float, integral: float, beta: float, limit: float) -> tuple[float, float]:
    """A servo wall's outward speed from its proportional term `push` = G (sigma - target)
    and its `integral` term (m/s), and the integral updated: I += beta push, each capped at
    `limit`."""
    integral = float(min(max(integral + beta * push, -limit), limit))  # np.clip's value, cheaper
    return float(min(max(push + integral, -limit), limit)), integral


class WallServo:
    """Some of the four walls of `state` servo-controlled to `target_Pa` (compression
    positive), their speeds updated every `steps` time steps and capped at `limit` (m/s)."""

    def __init__(self, state: State, walls: tuple[int, ...], target_Pa: float, limit: float,
                 steps: int = STEPS, alpha: float = ALPHA, beta: float = BETA):
        self.state, self.walls, self.target = state, walls, target_Pa
        self.limit, self.steps, self.alpha, self.beta = limit, steps, alpha, beta
        self.integral = {w: 0.0 for w in walls}

    def stresses(self) -> np.ndarray:
        """The normal stress on each wall (left, right, bottom, top), Pa: its force over the
        specimen's current height (side walls) or width (platens), thickness t."""
        at = self.state.walls.pos
        height, width = at[TOP] - at[BOTTOM], at[RIGHT] - at[LEFT]
        lengths = np.array([height, height, width, width])
        return self.state.walls.total_force() / (lengths * THICKNESS_M)

    def update(self) -> None:
        """Set the servo walls' speeds from the stresses they bear now."""
        walls, stress = self.state.walls, self.stresses()
        at = walls.pos
        for w in self.walls:
            length = (at[TOP] - at[BOTTOM]) if w in (LEFT, RIGHT) else (at[RIGHT] - at[LEFT])
            touching = max(1, int(np.count_nonzero(walls.force[:, w])))
            push = servo_gain(self.alpha, length * THICKNESS_M, walls.stiffness * touching, self.steps,
                              self.state.dt) * (stress[w] - self.target)
            speed, self.integral[w] = servo_speed(push, self.integral[w], self.beta, self.limit)
            walls.vel[w] = OUTWARD[w] * speed

    def hold(self) -> None:
        """Stop the servo walls."""
        for w in self.walls:
            self.state.walls.vel[w] = 0.0
            self.integral[w] = 0.0
