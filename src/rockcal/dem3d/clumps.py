"""The shape properties of a 3D clump, the union of its pebbles (spheres): its volume, centroid
and second moments, from which the clump's mass and inertia tensor at a density follow.

Overlaps are counted once, as PFC3D takes a clump's mass properties when its template gives
none (PFC computes them from the pebbles; its `clump template` also takes a volume and an
inertia tensor given by the user, which this engine does not). By inclusion-exclusion the
union is the pebbles, less each overlapping pair's lens (counted twice in the pebbles), plus
what three or more pebbles share (subtracted too often by the lenses). A lens is two spherical
caps, whose volume and moments are closed forms (`_cap`), so a clump whose pebbles overlap at
most two at a point (the two-pebble template) is exact; a region three pebbles share (the
three-pebble template's core) is integrated by the midpoint rule (compiled) on a grid of TRIPLE_GRID³
points over its bounding box, its weight (k - 1)(k - 2) / 2 at a point in k pebbles making each
point count once. Every step is a fixed sequence of arithmetic and libm calls: the same numbers
on any processor.

A union's `MassProperties` hold V, the first moment ∫x dV and the second moments ∫x xᵀ dV
about the origin; `inertia_tensor` turns them into the inertia tensor about the centroid per
unit density, ∫(|r|² 1 - r rᵀ) dV with r from the centroid.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

TRIPLE_GRID = 32  # midpoints per side of a triple overlap's box


def union_properties(centres, radii) -> tuple[float, np.ndarray, np.ndarray]:
    """The union of spheres (centres (k, 3), radii, m): its volume (m³), centroid (m) and
    inertia tensor about the centroid per unit density (m⁵)."""
    centres = np.ascontiguousarray(centres, float).reshape(-1, 3)
    radii = np.ascontiguousarray(radii, float)
    if len(radii) == 0 or len(radii) != len(centres) or not (radii > 0).all():
        raise ValueError("a union of spheres needs one or more centres, each with a radius > 0")
    volume, first, second = _union(centres, radii)
    centroid = first / volume
    return volume, centroid, inertia_tensor(volume, centroid, second)


def inertia_tensor(volume: float, centroid: np.ndarray, second: np.ndarray) -> np.ndarray:
    """∫(|r|² 1 - r rᵀ) dV about the centroid, from the second moments about the origin."""
    about = second - volume * np.outer(centroid, centroid)
    return (about[0, 0] + about[1, 1] + about[2, 2]) * np.eye(3) - about


def _union(centres, radii):
    """Volume, first moment (3,) and second moments (3, 3) of a union of spheres, about a point
    near it (the mean of the centres: the terms stay of the size of the result), then moved to
    the origin."""
    k = radii.shape[0]
    origin = np.zeros(3)
    for i in range(k):  # summed in order, not by numpy's reduction (which rounds by processor)
        origin += centres[i] / k
    local = centres - origin
    volume = 0.0
    first = np.zeros(3)
    second = np.zeros((3, 3))
    for i in range(k):
        v, f, s = _sphere(local[i], radii[i])
        volume, first, second = volume + v, first + f, second + s
    for i in range(k):
        for j in range(i + 1, k):
            v, f, s = _lens(local[i], radii[i], local[j], radii[j])
            volume, first, second = volume - v, first - f, second - s
            for m in range(j + 1, k):
                v, f, s = _shared_by_three(local, radii, i, j, m)
                volume, first, second = volume + v, first + f, second + s
    # moved from the local origin to the true one
    moved_second = second + np.outer(origin, first) + np.outer(first, origin) + volume * np.outer(origin, origin)
    return volume, first + volume * origin, moved_second


def _sphere(c, r):
    volume = 4.0 / 3.0 * math.pi * r * r * r
    return volume, volume * c, volume * np.outer(c, c) + 0.2 * volume * r * r * np.eye(3)


def _cap(c, r, n, d):
    """The part of the sphere (centre c, radius r) beyond the plane at distance d (-r <= d <= r)
    from its centre along the unit vector n: its volume, first and second moments. With z the
    distance along n, its slices are disks of radius² r² - z², so V = π∫(r² - z²), the moments
    along n π∫z(r² - z²), π∫z²(r² - z²), and across it (each direction) π/4 ∫(r² - z²)²."""
    def antiderivatives(z):
        z2 = z * z
        return (r * r * z - z2 * z / 3.0, r * r * z2 / 2.0 - z2 * z2 / 4.0,
                r * r * z2 * z / 3.0 - z2 * z2 * z / 5.0,
                r * r * r * r * z - 2.0 * r * r * z2 * z / 3.0 + z2 * z2 * z / 5.0)
    top, bottom = antiderivatives(r), antiderivatives(d)
    volume = math.pi * (top[0] - bottom[0])
    along = math.pi * (top[1] - bottom[1])
    along2 = math.pi * (top[2] - bottom[2])
    across2 = 0.25 * math.pi * (top[3] - bottom[3])
    nn = np.outer(n, n)
    second = (volume * np.outer(c, c) + along * (np.outer(c, n) + np.outer(n, c)) + along2 * nn
              + across2 * (np.eye(3) - nn))
    return volume, volume * c + along * n, second


def _lens(ci, ri, cj, rj):
    """What spheres i and j share: nothing, the smaller sphere if it lies inside the other, or
    the lens of two caps cut by the plane of their circle of intersection."""
    d = cj - ci
    distance = math.sqrt(float(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]))
    if distance >= ri + rj:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    if distance <= abs(ri - rj):
        return _sphere(ci, ri) if ri <= rj else _sphere(cj, rj)
    n = d / distance
    a = (distance * distance + ri * ri - rj * rj) / (2.0 * distance)  # the plane, from ci
    vi, fi, si = _cap(ci, ri, n, a)
    vj, fj, sj = _cap(cj, rj, -n, distance - a)
    return vi + vj, fi + fj, si + sj


@njit(cache=True, error_model="numpy")
def _shared_by_three(centres, radii, i, j, m):
    """The midpoint-rule integral, over the box the spheres i < j < m share, of (k - 1)(k - 2)/2
    at the points in k >= 3 spheres whose three lowest spheres are i, j, m (so that a point in
    several triples counts once): nothing unless each pair of the three overlaps."""
    volume = 0.0
    first = np.zeros(3)
    second = np.zeros((3, 3))
    three = (i, j, m)
    for p in range(3):
        for q in range(p + 1, 3):
            d = centres[three[q]] - centres[three[p]]
            if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] >= (radii[three[p]] + radii[three[q]]) ** 2:
                return volume, first, second
    lo = np.empty(3)
    step = np.empty(3)
    for a in range(3):
        low = max(centres[i, a] - radii[i], centres[j, a] - radii[j], centres[m, a] - radii[m])
        high = min(centres[i, a] + radii[i], centres[j, a] + radii[j], centres[m, a] + radii[m])
        lo[a] = low
        step[a] = (high - low) / TRIPLE_GRID
    cell = step[0] * step[1] * step[2]
    x = np.empty(3)
    for u in range(TRIPLE_GRID):
        for v in range(TRIPLE_GRID):
            for w in range(TRIPLE_GRID):
                x[0] = lo[0] + (u + 0.5) * step[0]
                x[1] = lo[1] + (v + 0.5) * step[1]
                x[2] = lo[2] + (w + 0.5) * step[2]
                inside = 0
                lowest_three = True
                for s in range(radii.shape[0]):
                    dx = x[0] - centres[s, 0]
                    dy = x[1] - centres[s, 1]
                    dz = x[2] - centres[s, 2]
                    if dx * dx + dy * dy + dz * dz < radii[s] * radii[s]:
                        if inside < 3 and s != three[inside]:
                            lowest_three = False
                        inside += 1
                if inside >= 3 and lowest_three:
                    weight = 0.5 * (inside - 1) * (inside - 2) * cell
                    volume += weight
                    for a in range(3):
                        first[a] += weight * x[a]
                        for b in range(3):
                            second[a, b] += weight * x[a] * x[b]
    return volume, first, second
