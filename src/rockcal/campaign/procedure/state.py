"""The state of a campaign's procedure: the results so far (`CampaignState`), which each step
of `steps` reads and adds to, and a verification round's points (`Round`)."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from rockcal.campaign.input.config import Campaign, whole_numbers
from rockcal.campaign.procedure.goals import Goals
from rockcal.campaign.procedure.points import CalibrationFailed
from rockcal.campaign.procedure.result import FailedRun, Iteration, Samples, Sensitivity, SurrogateCheck
from rockcal.campaign.procedure.rounding import stand_in
from rockcal.inverse import RBFSurrogate

if TYPE_CHECKING:
    from rockcal.campaign.procedure.pinning import Narrowing


@dataclass(frozen=True)
class CampaignState:
    """The results so far: each step adds its own and reads only what earlier steps found."""

    campaign: Campaign
    goals: Goals
    fixed: dict[str, float]  # parameters held constant (with the middle of unused levels)
    bounds: dict[str, tuple[float, float]] = field(default_factory=dict)
    sensitivity: Sensitivity | None = None
    samples: Samples | None = None
    surrogate_check: SurrogateCheck | None = None
    coarse: Samples | None = None  # the coarse samples (multi-fidelity)
    low_fidelity: RBFSurrogate | None = None  # the surrogate of the coarse runs, fitted once
    train_x: np.ndarray | None = None  # the surrogate's training points and their responses
    train_y: list = field(default_factory=list)
    # where targets are means over packings: the verified points and their means
    means_x: np.ndarray | None = None
    means_y: list = field(default_factory=list)
    iterations: tuple[Iteration, ...] = ()
    objective: str = ""
    accepted: int | None = None  # the accepted iteration
    settled: bool = False  # the verification loop is over
    dem_runs: tuple[str, ...] = ()  # keys of the distinct primary-test runs: one per parameter set
    failed_runs: tuple[FailedRun, ...] = ()
    specimen_description: dict | None = None  # of the first primary-test run on the campaign's specimen
    curves: dict = field(default_factory=dict)  # verification runs' curves, by run key
    final: dict = field(default_factory=dict)  # the last step's parts of the result
    planning: bool = False  # the first screen's state: points found by searching are stand-ins
    pending: Round | None = None  # a round's points whose UCS runs met the tolerance ([acceptance] ucs_first)
    notes: tuple[str, ...] = ()  # warnings the steps leave for the screen as they go
    narrowing: Narrowing | None = None  # the identifiability stage between its batches

    @property
    def names(self) -> list[str]:
        """The parameters searched."""
        return list(self.bounds)

    @property
    def box(self) -> np.ndarray:
        return np.array([self.bounds[n] for n in self.names], dtype=float)

    @property
    def whole(self) -> np.ndarray:
        """Which of the parameters searched are whole numbers (`rounded` rounds them so)."""
        counts = whole_numbers(self.campaign.material.model)
        return np.array([n in counts for n in self.names], dtype=bool)

    def best(self) -> int:
        """The accepted iteration, or the verified one with the smallest largest error."""
        return self.accepted if self.accepted is not None else _closest(list(self.iterations))

    def identified(self) -> dict[str, float]:
        if self.planning:
            return dict(zip(self.names, stand_in(self.box, self.whole)))
        return dict(zip(self.names, self.iterations[self.best()].x))


@dataclass(frozen=True)
class Round:
    """A verification round's points: the search's optima on the surrogate, rounded (`xs`)."""

    found: list
    xs: list
    surrogate: object
    objective: str
    loop: int

    def only(self, keep: list[int]) -> Round:
        return replace(self, found=[self.found[i] for i in keep], xs=[self.xs[i] for i in keep])


def _closest(iterations: list[Iteration]) -> int:
    """The verified iteration with the smallest largest error (when none was accepted)."""
    most = max((len(it.errors) for it in iterations if it.errors is not None), default=0)
    # a point verified on every test before one whose verification stopped after its UCS test
    scored = [(len(it.errors) < most, max(abs(e) for e in it.errors.values()), i)
              for i, it in enumerate(iterations) if it.errors is not None]
    if not scored:
        raise CalibrationFailed("no verification run succeeded")
    return min(scored)[2]
