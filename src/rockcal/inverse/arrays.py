"""Orthogonal arrays for the sensitivity study: L4, L8, L9, L16(4^5), L18(2^1 3^7), L25, L27.

Arrays are built by construction rather than taken from pyDOE3 or oapackage: pyDOE3 has no
Taguchi arrays of mixed or four-level type and oapackage is a compiled package we would
add as a runtime dependency for seven small tables. Two constructions cover them:

- Rao-Hamming (Bose) for s = prime power levels: the runs are all vectors u of GF(s)^t and
  each column is a projective point v (first non-zero coordinate 1); the entry is u·v in
  GF(s). This gives L_{s^t}(s^{(s^t-1)/(s-1)}) of strength 2: L9(3^4), L16(4^5) (with GF(4)
  arithmetic), L27(3^13), L8(2^7), L25(5^6).
- L18(2^1 3^7) from a difference scheme D(6,6;3) D: rows D[i] + s for s in Z3 give six
  three-level columns and a six-level column i, which splits into a two-level column
  (i // 3) and a three-level column (i % 3).

Levels are coded 0 .. s-1 (column-wise); `to_values` maps them to physical factor values.
"""

from __future__ import annotations

import itertools
import re

import numpy as np

from rockcal.errors import InputError

# GF(4) = GF(2)[x]/(x^2 + x + 1), elements coded 0, 1, x = 2, x + 1 = 3; addition is XOR.
_GF4_MUL = np.array([[0, 0, 0, 0],
                     [0, 1, 2, 3],
                     [0, 2, 3, 1],
                     [0, 3, 1, 2]])

# A difference scheme D(6,6;3): for any two columns, the differences take each value of Z3
# exactly twice. Found by a small back-tracking search; `is_orthogonal` checks the result.
_D663 = np.array([[0, 0, 0, 0, 0, 0],
                  [0, 0, 1, 1, 2, 2],
                  [0, 1, 0, 2, 1, 2],
                  [0, 1, 2, 0, 2, 1],
                  [0, 2, 1, 2, 0, 1],
                  [0, 2, 2, 1, 1, 0]])


def _gf_dot(u: np.ndarray, v: np.ndarray, s: int) -> np.ndarray:
    """Rows of u dotted with vector v in GF(s), s prime or 4."""
    if s == 4:
        out = np.zeros(len(u), dtype=int)
        for j, vj in enumerate(v):
            out ^= _GF4_MUL[u[:, j], vj]
        return out
    return (u @ v) % s


def rao_hamming(levels: int, t: int) -> np.ndarray:
    """L_{s^t}(s^k), k = (s^t - 1)/(s - 1), strength 2; s prime (2, 3, 5, 7) or 4."""
    if levels not in (2, 3, 4, 5, 7):
        raise InputError("levels", f"Rao-Hamming construction here needs 2, 3, 4, 5 or 7, got {levels}")
    runs = np.array(list(itertools.product(range(levels), repeat=t)), dtype=int)
    points = [v for v in itertools.product(range(levels), repeat=t)
              if any(v) and v[next(i for i, x in enumerate(v) if x)] == 1]
    # Order columns so the basic (unit-vector) factors come first, as in Taguchi's tables.
    points.sort(key=lambda v: (sum(1 for x in v if x), v[::-1]))
    return np.column_stack([_gf_dot(runs, np.array(v), levels) for v in points])


def l16() -> np.ndarray:
    """L16(4^5) as Taguchi's standard table, the one the source study's Table 3 follows: the
    GF(4) construction with its last two columns swapped and multiplied by x and x + 1 (the
    same projective points, other level labels), so a campaign's L16 runs are the source's."""
    a = rao_hamming(4, 2)
    return np.column_stack([a[:, :3], _GF4_MUL[2][a[:, 4]], _GF4_MUL[3][a[:, 3]]])


def l18() -> np.ndarray:
    """L18(2^1 3^7): the two-level column first, then seven three-level columns."""
    rows = []
    for i, d in enumerate(_D663):
        for s in range(3):
            rows.append([i // 3, i % 3, *((d + s) % 3)])
    return np.array(rows, dtype=int)


_BUILDERS = {
    "L4(2^3)": lambda: rao_hamming(2, 2),
    "L8(2^7)": lambda: rao_hamming(2, 3),
    "L9(3^4)": lambda: rao_hamming(3, 2),
    "L16(4^5)": l16,
    "L18(2^1 3^7)": l18,
    "L25(5^6)": lambda: rao_hamming(5, 2),
    "L27(3^13)": lambda: rao_hamming(3, 3),
}

ARRAY_NAMES = tuple(_BUILDERS)


def _key(name: str) -> str:
    return re.sub(r"[\s_*]", "", name).upper()


def orthogonal_array(name: str) -> np.ndarray:
    """The array called `name` (e.g. "L16(4^5)"; case, spaces and "L18" alone are accepted)."""
    wanted = _key(name)
    for full, build in _BUILDERS.items():
        if _key(full) == wanted or _key(full).split("(")[0] == wanted:
            return build()
    raise InputError("array", f"unknown orthogonal array {name!r}; known: {', '.join(ARRAY_NAMES)}")


def is_orthogonal(array: np.ndarray) -> bool:
    """Strength-2 check: every pair of columns shows every level pair equally often."""
    a = np.asarray(array)
    if a.ndim != 2 or a.shape[0] == 0:
        return False
    levels = [np.unique(col) for col in a.T]
    for i, j in itertools.combinations(range(a.shape[1]), 2):
        counts = {}
        for pair in zip(a[:, i].tolist(), a[:, j].tolist()):
            counts[pair] = counts.get(pair, 0) + 1
        if len(counts) != len(levels[i]) * len(levels[j]) or len(set(counts.values())) != 1:
            return False
    if a.shape[1] == 1:
        _, c = np.unique(a[:, 0], return_counts=True)
        return len(set(c.tolist())) == 1
    return True


def to_values(array: np.ndarray, levels: dict[str, list[float]]) -> dict[str, np.ndarray]:
    """Coded levels -> factor values: factor k takes column k; level i is `levels[factor][i]`.

    The array needs at least as many columns as factors, and each factor exactly as many
    values as its column has levels. Unused columns are left out.
    """
    a = np.asarray(array)
    if len(levels) > a.shape[1]:
        raise InputError("factors", f"{len(levels)} factors but the array has only {a.shape[1]} columns")
    out = {}
    for k, (factor, values) in enumerate(levels.items()):
        n = int(a[:, k].max()) + 1
        if len(values) != n:
            raise InputError(f"levels.{factor}", f"column {k + 1} has {n} levels, got {len(values)} values")
        out[factor] = np.asarray(values, dtype=float)[a[:, k]]
    return out


def design(name: str, levels: dict[str, list[float]]) -> dict[str, np.ndarray]:
    """The runs of array `name` in factor values: {factor: values per run}.

    Factors are given in order; a factor with fewer levels is placed on the first free
    column with that many levels (so L18's two-level column goes to a two-level factor).
    """
    a = orthogonal_array(name)
    counts = [int(col.max()) + 1 for col in a.T]
    free = list(range(a.shape[1]))
    out = {}
    for factor, values in levels.items():
        col = next((c for c in free if counts[c] == len(values)), None)
        if col is None:
            raise InputError(f"levels.{factor}",
                             f"{name} has no free column with {len(values)} levels")
        free.remove(col)
        out[factor] = np.asarray(values, dtype=float)[a[:, col]]
    return out
