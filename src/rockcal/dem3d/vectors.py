"""Lengths and cubes of many numbers, the same to the bit on every processor.

numpy's vectorised `power` (`r**3`, `r**4`) and its reductions may run in SIMD code chosen for
the processor (AVX2, AVX-512), which rounds otherwise than the C library; a bonded specimen that
breaks amplifies a last bit into a different strength. These write the products and sums out,
each correctly rounded, in a fixed order.
"""

from __future__ import annotations

import numpy as np


def norms(v: np.ndarray) -> np.ndarray:
    """The length of each row of `v` (n, 3)."""
    return np.sqrt(v[:, 0] * v[:, 0] + v[:, 1] * v[:, 1] + v[:, 2] * v[:, 2])


def cubes(x: np.ndarray) -> np.ndarray:
    """x³, elementwise."""
    return x * x * x
