"""Range analysis of an orthogonal design: which factor drives which response.

For factor A at level i: K_i = sum of the response over the runs at level i,
k_i = K_i / (runs per level), R = max_i k_i - min_i k_i. Within a response, the factor with
the largest R is the most influential. R carries the response's unit, so factors are ranked
per response, never across responses.
"""

from __future__ import annotations

import csv
import itertools
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rockcal.errors import InputError


@dataclass(frozen=True)
class FactorEffect:
    """K_i, k_i and R of one factor for one response; `levels` are the factor values, sorted."""

    levels: np.ndarray
    K: np.ndarray
    k: np.ndarray
    R: float


@dataclass(frozen=True)
class RangeAnalysis:
    """`effects[response][factor]` -> FactorEffect; factor and response orders as given."""

    factors: tuple[str, ...]
    responses: tuple[str, ...]
    effects: dict[str, dict[str, FactorEffect]]

    def ranking(self, response: str) -> list[str]:
        """Factors by decreasing R for `response` (ties keep the given factor order)."""
        effects = self.effects[response]
        return sorted(self.factors, key=lambda f: -effects[f].R)

    def chosen(self, threshold: float | None = None) -> list[str]:
        """Parameters to invert: the most influential factor of each response (the source's
        rule), plus, with `threshold` t in (0, 1], every factor whose R >= t * (largest R of
        that response). Returned in the given factor order."""
        if threshold is not None and not (0 < threshold <= 1):
            raise InputError("threshold", f"must be in (0, 1], got {threshold}")
        picked = set()
        for response in self.responses:
            ranked = self.ranking(response)
            picked.add(ranked[0])
            if threshold is not None:
                top = self.effects[response][ranked[0]].R
                picked.update(f for f in ranked if self.effects[response][f].R >= threshold * top)
        return [f for f in self.factors if f in picked]

    def unseen(self, targets: dict[str, float], tolerance: float, factors: list[str]) -> list[str]:
        """The `factors` whose range R on every response is below `tolerance` of its target
        (response: value): the targets barely see them, and a calibration will not pin them."""
        return [f for f in factors if f in self.factors and
                all(self.effects[r][f].R < tolerance * abs(t) for r, t in targets.items())]

    def to_dict(self, threshold: float | None = None) -> dict:
        """{"responses": {response: {factor: {"levels", "K", "k", "R"}}},
        "ranking": {response: [factors by decreasing R]}, "chosen": [factors]}."""
        return {
            "responses": {r: {f: {"levels": e.levels.tolist(), "K": e.K.tolist(), "k": e.k.tolist(),
                                  "R": float(e.R)}
                              for f, e in self.effects[r].items()} for r in self.responses},
            "ranking": {r: self.ranking(r) for r in self.responses},
            "chosen": self.chosen(threshold),
        }


def _levels(name: str, column: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sorted level values of a factor column and the coded level of each run; balance checked."""
    levels, codes, counts = np.unique(column, return_inverse=True, return_counts=True)
    if len(levels) < 2:
        raise InputError(name, f"a factor needs at least 2 levels, found {len(levels)}")
    if len(set(counts.tolist())) != 1:
        detail = ", ".join(f"{v:g}: {c}" for v, c in zip(levels, counts))
        raise InputError(name, f"unbalanced levels (runs per level {detail}); "
                               "range analysis needs every level run equally often")
    return levels, codes


def _check_orthogonal(codes: dict[str, np.ndarray], n_levels: dict[str, int], runs: int) -> None:
    for a, b in itertools.combinations(codes, 2):
        cells = n_levels[a] * n_levels[b]
        if runs % cells or runs < cells:
            raise InputError("runs", f"{runs} runs are too few for an orthogonal design of {a} "
                                     f"({n_levels[a]} levels) and {b} ({n_levels[b]} levels): "
                                     f"need a multiple of {cells}")
        pairs = codes[a] * n_levels[b] + codes[b]
        if len(set(np.bincount(pairs, minlength=cells).tolist())) != 1:
            raise InputError("runs", f"factors {a} and {b} are not orthogonal in these runs: "
                                     "every pair of their levels must occur equally often")


def range_analysis(factors: dict[str, np.ndarray], responses: dict[str, np.ndarray], *,
                   require_orthogonal: bool = True) -> RangeAnalysis:
    """Range analysis of runs given as factor values and responses, one entry per run.

    Levels of a factor are the sorted unique values of its column. Every level must occur
    equally often, and (unless `require_orthogonal=False`) the runs must form an orthogonal
    design, without which the k_i of one factor mix in the effects of the others.
    """
    if not factors or not responses:
        raise InputError("factors" if not factors else "responses", "at least one is needed")
    columns = {**{f: np.asarray(v, dtype=float) for f, v in factors.items()},
               **{r: np.asarray(v, dtype=float) for r, v in responses.items()}}
    runs = {len(v) for v in columns.values()}
    if len(runs) != 1 or any(v.ndim != 1 for v in columns.values()):
        raise InputError("runs", "every factor and response needs one value per run")
    n = runs.pop()
    for name, values in columns.items():
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise InputError(name, f"run {bad[0] + 1} has a non-finite value ({values[bad[0]]})")
    coded = {f: _levels(f, columns[f]) for f in factors}
    if require_orthogonal:
        _check_orthogonal({f: c for f, (_, c) in coded.items()},
                          {f: len(lv) for f, (lv, _) in coded.items()}, n)
    effects = {}
    for r in responses:
        y = columns[r]
        effects[r] = {}
        for f, (levels, codes) in coded.items():
            K = np.bincount(codes, weights=y, minlength=len(levels))
            k = K / (n // len(levels))
            effects[r][f] = FactorEffect(levels=levels, K=K, k=k, R=float(k.max() - k.min()))
    return RangeAnalysis(tuple(factors), tuple(responses), effects)


def read_results(path: Path | str, factors: list[str], responses: list[str]) -> tuple[dict, dict]:
    """Factor and response columns of a results CSV (header row, one row per run)."""
    path = Path(path)
    field = path.name
    try:
        with path.open(newline="") as fh:
            rows = list(csv.reader(fh))
    except FileNotFoundError:
        raise InputError(field, "no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(field, f"cannot read: {exc}") from None
    rows = [row for row in rows if any(cell.strip() for cell in row)]
    if len(rows) < 2:
        raise InputError(field, "needs a header row and at least one run")
    header = [h.strip() for h in rows[0]]
    for kind, names in (("--factors", factors), ("--responses", responses)):
        if not names:
            raise InputError(kind, "at least one column name is needed")
        missing = [name for name in names if name not in header]
        if missing:
            raise InputError(kind, f"no column {missing[0]!r} in {field} (columns: {', '.join(header)})")
    if set(factors) & set(responses):
        raise InputError("--responses", f"{sorted(set(factors) & set(responses))[0]!r} is also a factor")

    def column(name: str) -> np.ndarray:
        j = header.index(name)
        values = []
        for i, row in enumerate(rows[1:], start=2):
            cell = row[j].strip() if j < len(row) else ""
            try:
                value = float(cell)
            except ValueError:
                raise InputError(field, f"line {i}, column {name}: {cell!r} is not a number") from None
            if not math.isfinite(value):
                raise InputError(field, f"line {i}, column {name}: {cell!r} is not a finite number")
            values.append(value)
        return np.array(values)

    return {f: column(f) for f in factors}, {r: column(r) for r in responses}
