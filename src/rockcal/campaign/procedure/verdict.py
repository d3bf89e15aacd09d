"""The verdict of a campaign whose targets no verified point met: which targets the model
cannot meet in the search box, alone or together, and the trade-off between the two that
conflict most.

On the surrogate, over a dense Latin hypercube of the box, and at the verified points (their DEM
errors: where the surrogate is rough a verified point may come closer than any it predicts),
each target's least relative error alone and each pair's least larger error together: a target
whose least error alone exceeds the tolerance is out of reach; two targets each within reach
alone whose least larger error exceeds it conflict. The trade-off is read on the DEM runs seen
(every full-resolution run of the search): their errors in the two responses and the points no
other beats in both (the Pareto front). The best compromise stays the verified point with the smallest largest error.
"""

from __future__ import annotations

from itertools import combinations
from typing import Callable

import numpy as np

from rockcal.campaign.procedure.result import Conflict, TradeOff, Verdict
from rockcal.inverse import latin_hypercube

PROBES = 4096  # surrogate points over the box
PROBE_SEED = 0
BINDING = 0.9  # a target within this fraction of the largest error there is one that binds


def verdict_of(targets: dict[str, float], tolerance: float, box: np.ndarray,
               predict: Callable[[np.ndarray], dict], seen: list[dict],
               best_errors: dict[str, float], verified: list[dict] = ()) -> Verdict:
    """The verdict for `targets` (response: value) and `tolerance` (relative), from the
    surrogate `predict` over `box` ((d, 2) bounds), the responses of the DEM runs `seen`, the
    best compromise's errors and every verified point's (relative errors by target; a point
    that did not measure every target is left out)."""
    probes = latin_hypercube(box, PROBES, seed=PROBE_SEED, optimization="none")
    predicted = predict(probes)
    measured = [e for e in verified if e and all(r in e for r in targets)]
    error = {r: np.abs(np.concatenate([np.asarray(predicted[r]) / t - 1.0,
                                       [e[r] for e in measured]]))
             for r, t in targets.items()}
    alone = {r: float(e.min()) for r, e in error.items()}
    unreachable = {r: e for r, e in alone.items() if e > tolerance}
    pairs = [Conflict(targets=[r, s], least_error=float(np.maximum(error[r], error[s]).min()))
             for r, s in combinations(targets, 2) if r not in unreachable and s not in unreachable]
    conflicts = sorted((c for c in pairs if c.least_error > tolerance), key=lambda c: -c.least_error)
    largest = np.max(np.vstack(list(error.values())), axis=0)
    best = int(np.argmin(largest))
    together = float(largest[best])
    # the targets that hold the others back where all come closest together
    binding = [r for r in targets if error[r][best] >= BINDING * together]
    shown = conflicts[0].targets if conflicts else _worst_two(best_errors)
    return Verdict(unreachable=unreachable, conflicts=conflicts, least_error_all=together,
                   binding=binding, trade_off=trade_off(shown, targets, seen),
                   text=_text(unreachable, conflicts, together, binding, tolerance))


def trade_off(responses: list[str], targets: dict[str, float], seen: list[dict]) -> TradeOff:
    """The DEM runs' relative errors in two responses and their Pareto front (the runs no
    other run beats in both absolute errors); a run that did not measure both is left out."""
    errors = [[seen_run[r] / targets[r] - 1.0 for r in responses] for seen_run in seen
              if all(r in seen_run for r in responses)]
    size = np.abs(np.array(errors, float).reshape(-1, 2))
    front = [i for i, (a, b) in enumerate(size)
             if not np.any((size[:, 0] <= a) & (size[:, 1] <= b) & ((size[:, 0] < a) | (size[:, 1] < b)))]
    return TradeOff(responses=responses, errors=errors, pareto=sorted(front, key=lambda i: size[i, 0]))


def _worst_two(errors: dict[str, float]) -> list[str]:
    ranked = sorted(errors, key=lambda r: -abs(errors[r]))
    return ranked[:2] if len(ranked) >= 2 else ranked * 2


def _text(unreachable: dict, conflicts: list[Conflict], together: float, binding: list[str],
          tolerance: float) -> str:
    """The verdict in a sentence or two."""
    within = f"±{100 * tolerance:g} %"
    parts = [f"{r} is out of reach in this box (the surrogate's closest: {100 * e:.1f} % off)"
             for r, e in unreachable.items()]
    parts += [f"{c.targets[0]} and {c.targets[1]} conflict: no point in the box meets both within "
              f"{within} (at best both within {100 * c.least_error:.1f} %)" for c in conflicts]
    if parts:
        return "; ".join(parts) + "."
    if together > tolerance:
        return (f"the targets conflict as a whole: every pair can be met within {within}, "
                f"not all together (at best all within {100 * together:.1f} %, held back by "
                f"{' and '.join(binding)}).")
    return (f"the surrogate has a point within {within} of every target that no verification "
            "confirmed: the budget ran out first (raise [acceptance] max_dem_runs, or add samples).")
