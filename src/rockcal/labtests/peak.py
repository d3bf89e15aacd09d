"""The peak load of a quasi-static test, counted only where the loading has settled.

A test's platens speed up over a ramp and slow down once bonds start breaking. Each change of
speed leaves a transient: the load read at the platens is not yet the specimen's, and it falls
as the specimen catches up. With spread bond strengths the weakest bonds break in the first
steps, and that fall looked like a failure (a granite UCS of 2 MPa). So the peak that decides
when a test may stop counts only the load read `settle_steps` or more after the last change of
speed; the reported peak is still the largest load of the whole curve.
"""

from __future__ import annotations


class SettledPeak:
    def __init__(self, settle_steps: float):
        self.settle_steps = settle_steps
        self.settled_from = settle_steps  # the first ramp
        self.value = 0.0
        self.slowed = False

    def slow_down(self, step: int) -> None:
        """The loading slows at `step` (once: the first broken bond)."""
        if not self.slowed:
            self.slowed = True
            self.settled_from = step + self.settle_steps

    def update(self, step: int, load: float) -> None:
        if step >= self.settled_from:
            self.value = max(self.value, load)

    def fallen_below(self, fraction: float, load: float) -> bool:
        """Whether the load has fallen below `fraction` of the settled peak."""
        return self.value > 0 and load < fraction * self.value
