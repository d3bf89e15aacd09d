"""Which parameters a lab sheet pins: the set of points of the search box whose predicted
responses all lie in their targets' bands (the acceptance tolerance, or the lab's spread where
wider, with the surrogate's own error near the accepted point added), sampled by hit-and-run
walks, and each parameter's range over it against its box.

A parameter is pinned by the sheet where the value found lies within `pinned_within` (relative)
of every point of its range over the set (and the range spans at most `pinned_share` of its
box): the range holds the truth, so the value found lies that near it. Elsewhere it is not:
points that far apart meet every target alike, and the sheet cannot tell them apart.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

PINNED_WITHIN = 0.05  # the value found within this of every point of its range pins the parameter
PROBES = 2048  # Latin hypercube points over the box that seed the walks
CHAINS = 32  # walks at once, each a batch of LINE_POINTS surrogate points a step
STEPS = 120
LINE_POINTS = 24
SHORTEST_LINE = 0.02  # of the box: the walks also try short lines, which thin sets need
KEPT = 400  # points of the set kept in the record (its figure)
END_SLAB = 0.05  # of a range: the points this near its extreme may be its end (`ends_of`)

Predict = Callable[[np.ndarray], dict]


def bands(targets: dict[str, float], tolerance: float, spread: dict, surrogate_error: dict | None) -> dict:
    """Each target's band of predicted values that meet it: within `tolerance` (relative) of
    it or, where wider, within the lab's spread (a [min, max], or an sd: 2 sd either side),
    widened on both sides by the surrogate's relative error (`surrogate_error`, None: not)."""
    found = {}
    for r, t in targets.items():
        low, high = t - tolerance * abs(t), t + tolerance * abs(t)
        s = spread.get(r)
        if isinstance(s, (list, tuple)):
            low, high = min(low, s[0]), max(high, s[1])
        elif s is not None:
            low, high = min(low, t - 2 * s), max(high, t + 2 * s)
        error = (surrogate_error or {}).get(r)
        margin = abs(t) * float(error) if error is not None and np.isfinite(error) else 0.0
        found[r] = (low - margin, high + margin)
    return found


def meets(predict: Predict, bands: dict[str, tuple[float, float]]) -> Callable:
    """Whether points (m, d) meet every target: each predicted response within its band."""
    def inside(x: np.ndarray) -> np.ndarray:
        predicted = predict(x)
        return np.all([(low <= np.asarray(predicted[r])) & (np.asarray(predicted[r]) <= high)
                       for r, (low, high) in bands.items()], axis=0)
    return inside


def meeting_set(inside: Callable, box: np.ndarray, start: np.ndarray, seed: int = 0) -> np.ndarray:
    """Points (rows) of the set `inside` ((m, d) points -> (m,) booleans) in `box` ((d, 2)):
    the Latin hypercube probes that meet it, then CHAINS hit-and-run walks from them and from
    `start` (a point of the set: the identified one), each step to a random point of the set
    on a line through its point (of random direction and length); empty when no point meets it."""
    from rockcal.inverse.sampling import latin_hypercube  # here: the campaign file's keys import this module

    rng = np.random.default_rng(seed)
    low, width = box[:, 0], box[:, 1] - box[:, 0]
    probes = latin_hypercube(box, PROBES, seed=seed, optimization="none")
    found = [probes[inside(probes)], np.atleast_2d(start)[inside(np.atleast_2d(start))]]
    seeds = np.vstack(found)
    if not len(seeds):
        return seeds
    u = (seeds[rng.integers(len(seeds), size=CHAINS)] - low) / width
    walked = []
    for _ in range(STEPS):
        direction = rng.normal(size=u.shape)
        direction /= np.linalg.norm(direction, axis=1, keepdims=True)
        with np.errstate(divide="ignore", invalid="ignore"):
            ends = np.stack([-u / direction, (1 - u) / direction])
        reach = np.exp(rng.uniform(np.log(SHORTEST_LINE), 0, size=(len(u), 1)))
        t_low = np.maximum(np.nanmax(ends.min(axis=0), axis=1, keepdims=True), -reach)
        t_high = np.minimum(np.nanmin(ends.max(axis=0), axis=1, keepdims=True), reach)
        t = t_low + (np.arange(LINE_POINTS) + rng.random((len(u), 1))) / LINE_POINTS * (t_high - t_low)
        line = np.clip(u[:, None, :] + t[..., None] * direction[:, None, :], 0.0, 1.0)
        ok = inside(low + width * line.reshape(-1, u.shape[1])).reshape(len(u), LINE_POINTS)
        pick = np.argmax(rng.random(ok.shape) * ok, axis=1)
        moved = ok.any(axis=1)
        u[moved] = line[moved, pick[moved]]
        walked.append(u[moved].copy())
    return np.vstack([seeds, low + width * np.vstack(walked)])


def largest_error(low: float, high: float, found: float) -> float:
    """The largest relative error of the value `found` against a truth anywhere in [low, high]
    (a range holding both): its distance to the range's farther end over the end nearest zero,
    than which no truth there is nearer zero (inf where the range reaches zero)."""
    nearest_zero = 0.0 if low <= 0 <= high else min(abs(low), abs(high))
    reach = max(found - low, high - found)
    return reach / nearest_zero if nearest_zero > 0 else (0.0 if reach == 0 else np.inf)


def pins(low: float, high: float, found: float, share: float, pinned_within: float, pinned_share: float) -> bool:
    """Whether a range [low, high] holding the value `found` and spanning `share` of its box
    pins its parameter: that value within `pinned_within` of every point of it (`largest_error`),
    the range within `pinned_share` of the box."""
    return largest_error(low, high, found) <= pinned_within and share <= pinned_share


def parameter_ranges(points: np.ndarray, box: np.ndarray, names: list[str], found: np.ndarray,
                     pinned_within: float, pinned_share: float) -> dict[str, dict]:
    """Each parameter's range over `points` (and the value `found`), the share of its box that
    range spans and whether that pins it (`pins`)."""
    ranges = {}
    for k, name in enumerate(names):
        low, high = float(min(points[:, k].min(), found[k])), float(max(points[:, k].max(), found[k]))
        share = float((high - low) / (box[k, 1] - box[k, 0]))
        ranges[name] = {"low": low, "high": high, "share": share,
                        "pinned": pins(low, high, found[k], share, pinned_within, pinned_share)}
    return ranges


def in_bands(responses: dict, band: dict[str, tuple[float, float]]) -> bool:
    """Whether every response lies in its band."""
    return all(low <= responses[r] <= high for r, (low, high) in band.items())


def ends_of(points: np.ndarray, k: int, worst: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The points of the set at the low and the high end of parameter k's range over it: of
    those within END_SLAB of the range from each extreme, the one predicted nearest the targets
    (`worst`: each point's largest predicted relative error, `worst_errors`), in the middle of
    the set in the other parameters, where a DEM run most likely meets the sheet too."""
    span = np.ptp(points[:, k])
    ends = []
    for extreme in (points[:, k].min(), points[:, k].max()):
        near = np.flatnonzero(np.abs(points[:, k] - extreme) <= END_SLAB * span)
        ends.append(points[near[np.argmin(worst[near])]])
    return ends[0], ends[1]


def worst_errors(predict: Predict, targets: dict[str, float], points: np.ndarray) -> np.ndarray:
    """Each point's largest relative error of the predicted responses against the targets."""
    predicted = predict(points)
    return np.max([np.abs(np.asarray(predicted[r]) / t - 1) for r, t in targets.items()], axis=0)


def kept(points: np.ndarray, seed: int = 0) -> np.ndarray:
    """At most KEPT of the set's points, drawn at random, for the record."""
    if len(points) <= KEPT:
        return points
    return points[np.sort(np.random.default_rng(seed).choice(len(points), KEPT, replace=False))]
