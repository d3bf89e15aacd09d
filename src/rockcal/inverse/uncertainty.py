"""How well lab results pin each identified parameter down: the inverse problem solved again
on the surrogate for targets drawn from the lab's spread and the model's own scatter between
packings (Monte Carlo), and the 5-95 % range of each parameter over the draws.

A lab spread per response is either an sd (normal draws about the target) or the [min, max]
of the lab's samples (uniform draws over it). The model scatter is a relative sd per response
(the DEM's responses over packings at the identified point): a target drawn as y (1 + e),
e ~ N(0, scatter), is what another packing of the same material would need.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

AT_BOUND = 0.01  # a draw within this fraction of the box width from an edge is "at the bound"
WIDE = 0.5  # an interval wider than this fraction of the box does not pin the parameter down
BOUND_SHARE = 0.1  # nor does one whose draws sit at a bound this often


@dataclass(frozen=True)
class Interval:
    p5: float
    p50: float
    p95: float
    at_bound: float  # share of the draws at a bound of the search box
    pinned: bool

    def to_dict(self) -> dict:
        return {"p5": self.p5, "p50": self.p50, "p95": self.p95, "at_bound": self.at_bound,
                "pinned": self.pinned}


def interval(values: np.ndarray, low: float, high: float) -> Interval:
    """The 5-95 % range of one parameter's draws inside its search box [low, high]."""
    p5, p50, p95 = np.percentile(values, [5, 50, 95])
    edge = AT_BOUND * (high - low)
    at_bound = float(np.mean((values <= low + edge) | (values >= high - edge)))
    pinned = (p95 - p5) <= WIDE * (high - low) and at_bound < BOUND_SHARE
    return Interval(float(p5), float(p50), float(p95), at_bound, bool(pinned))


def draw_targets(targets: dict[str, float], spread: dict, scatter: dict[str, float], draws: int,
                 seed: int) -> dict[str, np.ndarray]:
    """`draws` target sets: the lab's spread (an sd, or a [min, max] range), times 1 + the
    model's relative scatter."""
    rng = np.random.default_rng(seed)
    drawn = {}
    for name, value in targets.items():
        s = spread.get(name)
        if s is None:
            lab = np.full(draws, float(value))
        elif isinstance(s, (tuple, list)):
            lab = rng.uniform(s[0], s[1], draws)
        else:
            lab = rng.normal(value, s, draws)
        drawn[name] = lab * (1.0 + rng.normal(0.0, scatter.get(name, 0.0), draws))
    return drawn


def parameter_intervals(solve: Callable[[dict[str, float]], np.ndarray], targets: dict[str, float],
                        spread: dict, scatter: dict[str, float], box: np.ndarray,
                        names: list[str], *, draws: int = 200, seed: int = 1) -> dict:
    """Solve the inverse problem (`solve`: targets -> parameters in the box) for each drawn
    target set; the intervals of each parameter, the draws and the targets behind them."""
    drawn = draw_targets(targets, spread, scatter, draws, seed)
    x = np.array([solve({r: float(v[i]) for r, v in drawn.items()}) for i in range(draws)])
    return {"intervals": {n: interval(x[:, k], *box[k]).to_dict() for k, n in enumerate(names)},
            "samples": x.tolist(), "drawn_targets": {r: v.tolist() for r, v in drawn.items()}}
