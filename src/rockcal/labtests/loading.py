"""Quasi-static loading shared by the lab tests: how fast the platens or the pin move.

A test's loading moves at a base speed (each test sets it so that the specimen stays in
equilibrium while it deforms elastically), ramped in over `ramp_steps`. Where bonds break,
the specimen needs time for the stress to flow around each new crack, so the loading slows
down in proportion to how busy it is breaking: the speed factor is

    1 / (1 + bonds broken in the last ramp_steps steps / breaks_at_half_speed),

never below 1 / SLOWEST. It speeds up again gradually (at most doubling per ramp_steps) once
breaking calms down. Isolated weak bonds breaking far below the peak thus cost little time, and
the cascade at the peak runs at the slowest speed. Until the first bond breaks the specimen is
linear elastic, and a test may load it faster there (`intact_speed`). In a UCS test damage
spreads through the specimen (DISTRIBUTED_DAMAGE: halving the loading rate of the full-size
granite specimen at the source's point moves E, nu and UCS by at most 1.5 %); in bending the
30-40 bonds at the notch tip break in a burst (NOTCH_TIP_DAMAGE: on three 110 x 25 mm beams
this rule and the slowest speed from the first break agree within 1.3 % in K_IC, with a third
of the steps; the pin runs faster until the first break, at 60-90 % of the peak). The Brazilian disk crushes under the platens long before it splits, and there
the loading runs at the slowest speed from the first broken bond on (LOCALISED_DAMAGE). Where
the test no longer needs the peak (bending and Brazilian tests once the load has fallen well
past it) it may run at full speed.

`load_to_failure` is the loop every test runs with its own rig (a `rig.Loader`: the platens,
the pin, the grips), readings and stop rule.
"""

from __future__ import annotations

from typing import Callable, NamedTuple

import numpy as np

from rockcal.errors import InputError
from rockcal.labtests.result import failed_run
from rockcal.labtests.rig import Loader

SLOWEST = 8.0
# breaks_at_half_speed of each kind of damage
DISTRIBUTED_DAMAGE = 4.0  # UCS: a full-size specimen has many bonds, so a few breaking per ramp is no cascade
NOTCH_TIP_DAMAGE = 2.0
LOCALISED_DAMAGE = 0.0  # slowest from the first break
# The loading is ramped in over RAMP_STEPS_PER_ROW x (rows of particles across the loaded
# direction) steps, so the same number of wave transits for every specimen size.
RAMP_STEPS_PER_ROW = 10
# Once the load has fallen below PAST_PEAK_FRACTION of the peak with bonds broken, the peak is
# known: a test that goes on for its crack path may go back to full speed.
PAST_PEAK_FRACTION = 0.8


class Loading:
    """The speed factor of a test's loading, chunk by chunk, and the settled peak of its load.

    A change of speed leaves a transient: the load read at the platens is not yet the
    specimen's and falls as the specimen catches up. With spread bond strengths the weakest
    bonds break in the first steps, and that fall looked like failure (a granite UCS of 2 MPa).
    So a test may stop, and its deciding peak counts, only on loads read `ramp_steps` or more
    after the loading last slowed down (by however little); the reported peak is the largest
    of the curve. A specimen that rings longer than that (a beam swings at its flexural period
    about the load the pin's travel gives) needs a fall below the settled peak to last instead:
    it counts once every reading for `confirm_steps` has been below, settled or not (a
    slow-down's transient is a few per cent of the load and passes within `ramp_steps`; a fall
    that lasts a flexural period is the crack's), until the peak is known (`peak_known`,
    set by `load_to_failure`); from then on the test runs for its crack, and a fall counts at
    once.
    """

    def __init__(self, ramp_steps: float, breaks_at_half_speed: float, confirm_steps: float = 0.0,
                 intact_speed: float = 1.0):
        self.ramp_steps = ramp_steps
        self.breaks_at_half_speed = breaks_at_half_speed
        self.confirm_steps = confirm_steps
        self.intact_speed = intact_speed  # the speed factor while no bond has broken
        self.factor = 0.0
        self.settled_from = ramp_steps
        self.peak = 0.0
        self.peak_travel = 0.0  # the travel at which the settled peak was read
        self.settled = False
        self.peak_known = False  # the load fell below PAST_PEAK_FRACTION of the peak, confirmed
        self.step = 0  # of the last load read
        self._below_since: dict[float, int] = {}  # fraction: step of the first reading below
        self._broken = [(0, 0)]  # (step, bonds broken so far), over the last ramp_steps

    def speed(self, step: int, broken: int, chunk: int, full_speed: bool = False) -> float:
        """The speed factor for the next `chunk` steps, given the bonds broken so far."""
        self._broken.append((step, broken))
        while self._broken[1][0] <= step - self.ramp_steps:
            self._broken.pop(0)
        recent = broken - self._broken[0][1]
        target = min(1.0, (step + chunk) / self.ramp_steps)
        if not full_speed:
            target = min(target, self._damage_speed(recent)) if broken else target * self.intact_speed
        if target < self.factor:
            self.settled_from = max(self.settled_from, step + self.ramp_steps)
        if step >= self.ramp_steps:
            target = min(target, self.factor * 2.0 ** (chunk / self.ramp_steps))
        self.factor = target
        return target

    def _damage_speed(self, recent: int) -> float:
        """The speed factor once bonds have broken, `recent` of them in the last ramp_steps."""
        if self.breaks_at_half_speed == LOCALISED_DAMAGE:
            return 1.0 / SLOWEST
        return max(1.0 / SLOWEST, 1.0 / (1.0 + recent / self.breaks_at_half_speed))

    def update(self, step: int, load: float, travel: float = 0.0) -> bool:
        """Record a load read at `step` (and the loading's travel there); whether it is a new
        settled peak."""
        self.step = step
        self.settled = step >= self.settled_from
        if self.settled and load > self.peak:
            self.peak, self.peak_travel = load, travel
            return True
        return False

    def wait(self, step: int, steps: float) -> None:
        """Loads read in the `steps` after `step` do not count: a change the loading did not make
        itself (the pin touching the beam) leaves a transient too."""
        self.settled_from = max(self.settled_from, step + steps)

    def fallen_below(self, fraction: float, load: float) -> bool:
        """Whether the load has fallen below `fraction` of the settled peak: read where the
        loading has settled (`confirm_steps` 0), or staying below for `confirm_steps` (at once
        once the peak is known)."""
        counts = self.settled or self.confirm_steps > 0
        if not (counts and self.peak > 0 and load < fraction * self.peak):
            self._below_since.pop(fraction, None)
            return False
        since = self._below_since.setdefault(fraction, self.step)
        return self.peak_known or self.step - since >= self.confirm_steps


def check_stop_fraction(stop_fraction: float) -> None:
    """A test stops once its load has fallen below this fraction of the peak: it must be in (0, 1)."""
    if not 0 < stop_fraction < 1:
        raise InputError("stop_fraction", f"must be in (0, 1), got {stop_fraction}")


def check_max_strain(max_strain: float) -> None:
    """A test stops at this strain (the loading's travel over the specimen's size) at the
    latest: it must be in (0, 0.5]."""
    if not 0 < max_strain <= 0.5:
        raise InputError("max_strain", f"must be in (0, 0.5], got {max_strain}")


class Reading(NamedTuple):
    """What a test reads after a chunk of steps."""

    load: float  # the load whose peak the test is after (N per m, or Pa)
    travel: float  # how far the loading has gone (m, or a strain), in the unit of its limit
    sample: tuple  # the curve's row: the travel's reading first, the load's last


@failed_run()  # a model that broke while loading: the test's RunFailed
def load_to_failure(loader: Loader, loading: Loading, read: Callable[[], Reading],
                    may_stop: Callable[[Reading], bool], max_travel: float, *,
                    full_speed_past_peak: bool = False,
                    progress: Callable[[float, float], None] | None = None,
                    control: Callable[[], None] | None = None,
                    control_steps: int = 1,
                    samples: list | None = None,
                    snapshot: Callable[[], None] | None = None) -> np.ndarray:
    """Load the specimen quasi-statically until the test may stop; its curve.

    The test configures what differs: its `loader` (the platens, the pin, the grips) moves at
    `loading`'s speed factor; `read()` reads the specimen after each of the loader's `chunk` of
    steps; `may_stop(reading)` is its stop rule (asking `loading` about the settled peak);
    `max_travel` stops it at the latest. With `full_speed_past_peak` the loading goes back to
    full speed once the peak is known (`loading.peak_known`): the load has fallen below
    PAST_PEAK_FRACTION of it with bonds broken. progress(first, last value of the sample) is
    called after each chunk. `control()`, a boundary the test servo-controls, is called every
    `control_steps` steps within each chunk (splitting a chunk changes no number). The curve is
    the samples after a first row of zeros, the specimen unloaded; the loader's state steps by
    its engine's `advance` (`rockcal.engine`), in 2D or 3D. A test that
    takes snapshots (`rockcal.labtests.snapshots`) passes its `samples` list (so far: a run
    going on from a snapshot) and `snapshot()`, called after each reading the test goes on
    from, which saves what the test needs to go on from there.
    """
    state, chunk = loader.state, loader.chunk
    samples = [] if samples is None else samples
    while True:
        loader.move(loading.speed(state.step, state.n_broken(), chunk, loading.peak_known))
        if control is None:
            state.advance(chunk)
        else:
            for done in range(0, chunk, control_steps):
                control()
                state.advance(min(control_steps, chunk - done))
        reading = read()
        samples.append(reading.sample)
        loading.update(state.step, reading.load, reading.travel)
        if full_speed_past_peak and not loading.peak_known:
            loading.peak_known = (loading.fallen_below(PAST_PEAK_FRACTION, reading.load)
                                  and state.n_broken() > 0)
        if progress:
            progress(reading.sample[0], reading.sample[-1])
        if may_stop(reading) or reading.travel >= max_travel:
            return np.array([(0.0,) * len(reading.sample), *samples])
        if snapshot is not None:
            snapshot()
