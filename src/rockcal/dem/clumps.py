"""Rigid clumps of pebbles: which pebbles form each clump, and the shape properties of a clump,
the union of its pebbles (disks of unit thickness).

A clump (PFC's `clump`: a rigid body of overlapping `pebbles`) is described per particle by
`clump_of`: its clump's number 0..n_clumps-1, or -1 for a ball of its own (in no clump).
`members` turns that into the clumps' pebble lists. Pebbles of one clump are never in contact
nor bonded with each other (`neighbours.NeighbourList.clump_of`).

A clump's mass, centroid and moment of inertia are those of the union of its pebbles at the
material's density, overlaps counted once, as PFC takes a clump's by default (PFC evaluates
them numerically, filling the shape at some resolution). Here the union's area, centroid and
polar moment per unit thickness (`union_properties`) are integrated exactly, not by a fill:
by Green's theorem over the union's boundary, the arcs of each pebble's circle not inside
another pebble, each in closed form. So they are exact for any number of pebbles (two
overlapping disks give the lens formula's area), holes in the union included (their arcs run
clockwise about the hole and subtract), with no resolution to choose, and deterministic: a
fixed sequence of arithmetic and libm calls, the same on every processor to round-off. A fill
or grid would converge only as its cell size.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


def members(clump_of) -> tuple[np.ndarray, np.ndarray]:
    """The pebbles of each clump from `clump_of` (per particle: its clump 0..n_clumps-1, or -1:
    a ball in no clump): `first` (n_clumps + 1) and `pebbles`, clump c's pebbles being
    pebbles[first[c]:first[c + 1]] in increasing order. ValueError unless every clump number
    from 0 to the largest has a pebble."""
    clump_of = np.asarray(clump_of, np.int64)
    if clump_of.ndim != 1 or (clump_of < -1).any():
        raise ValueError("clump_of: one clump number >= 0 (or -1: a ball) per particle")
    clumped = np.flatnonzero(clump_of >= 0)
    counts = np.bincount(clump_of[clumped], minlength=0)
    if (counts == 0).any():
        raise ValueError(f"clump_of: clump {int(np.argmin(counts))} has no pebble; number the "
                         "clumps 0..n_clumps-1")
    pebbles = clumped[np.argsort(clump_of[clumped], kind="stable")]
    first = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    return first, pebbles


def union_properties(centres, radii) -> tuple[float, np.ndarray, float]:
    """The union of disks (centres (k, 2), radii, m) per unit thickness: its area (m²),
    centroid (m) and polar moment of area about the centroid (m⁴), exact (module docstring)."""
    centres = np.ascontiguousarray(centres, float).reshape(-1, 2)
    radii = np.ascontiguousarray(radii, float)
    if len(radii) == 0 or (radii <= 0).any():
        raise ValueError("a union of disks of positive radii")
    area, cx, cy, polar = _union(centres, radii)
    return area, np.array([cx, cy]), polar


def clump_properties(pos, radius, first, pebbles):
    """Each clump's union (`union_properties`): areas (m²), centroids (n_clumps, 2) (m) and
    polar moments of area about them (m⁴), per unit thickness."""
    pos = np.ascontiguousarray(pos, float)
    radius = np.ascontiguousarray(radius, float)
    n = len(first) - 1
    area, centroid, polar = np.empty(n), np.empty((n, 2)), np.empty(n)
    for c in range(n):
        own = pebbles[first[c]:first[c + 1]]
        area[c], centroid[c, 0], centroid[c, 1], polar[c] = _union(pos[own], radius[own])
    return area, centroid, polar


@njit(cache=True, error_model="numpy")
def _union(centres, radii):
    """Area, centroid (x, y) and polar moment about the centroid of a union of disks, by
    Green's theorem over its boundary arcs (`_arc_integrals`), about a point near the centre
    (the mean of the centres) so that the terms stay of the size of the result."""
    k = radii.shape[0]
    ox = 0.0
    oy = 0.0
    for i in range(k):
        ox += centres[i, 0]
        oy += centres[i, 1]
    ox /= k
    oy /= k
    area = 0.0
    sx = 0.0
    sy = 0.0
    polar = 0.0
    for i in range(k):
        arcs = _free_arcs(centres, radii, i)
        for a in range(arcs.shape[0]):
            da, dsx, dsy, dj = _arc_integrals(centres[i, 0] - ox, centres[i, 1] - oy, radii[i],
                                              arcs[a, 0], arcs[a, 1])
            area += da
            sx += dsx
            sy += dsy
            polar += dj
    cx = sx / area
    cy = sy / area
    return area, ox + cx, oy + cy, polar - area * (cx * cx + cy * cy)


@njit(cache=True, error_model="numpy")
def _free_arcs(centres, radii, i):
    """The arcs (rows: from, to angle, rad, within [0, 2π]) of disk i's circle that lie inside
    no other disk. Of two identical disks the later one is taken as covered."""
    k = radii.shape[0]
    two_pi = 2.0 * math.pi
    covered = np.empty((2 * k, 2))
    m = 0
    ri = radii[i]
    for j in range(k):
        if j == i:
            continue
        dx = centres[j, 0] - centres[i, 0]
        dy = centres[j, 1] - centres[i, 1]
        rj = radii[j]
        d = math.sqrt(dx * dx + dy * dy)
        if d >= ri + rj or d <= ri - rj and not (d == 0.0 and ri == rj):
            continue  # apart (or touching at a point), or disk j inside disk i
        if d <= rj - ri:  # disk i inside disk j (of identical disks: the later one)
            if d == 0.0 and ri == rj and j > i:
                continue
            return np.empty((0, 2))
        # the circle of i inside disk j: centred on the direction to j, half-angle beta
        half = math.acos(min(1.0, max(-1.0, (ri * ri + d * d - rj * rj) / (2.0 * ri * d))))
        start = (math.atan2(dy, dx) - half) % two_pi
        end = start + 2.0 * half
        if end > two_pi:  # it wraps past angle 0: two intervals
            covered[m, 0] = start
            covered[m, 1] = two_pi
            covered[m + 1, 0] = 0.0
            covered[m + 1, 1] = end - two_pi
            m += 2
        else:
            covered[m, 0] = start
            covered[m, 1] = end
            m += 1
    order = np.argsort(covered[:m, 0], kind="mergesort")
    free = np.empty((m + 1, 2))
    f = 0
    reached = 0.0
    for q in range(m):
        start = covered[order[q], 0]
        if start > reached:
            free[f, 0] = reached
            free[f, 1] = start
            f += 1
        reached = max(reached, covered[order[q], 1])
    if reached < two_pi:
        free[f, 0] = reached
        free[f, 1] = two_pi
        f += 1
    return free[:f]


@njit(cache=True, error_model="numpy", inline="always")
def _arc_integrals(a, b, r, t1, t2):
    """The contributions of the arc t1 -> t2 (counter-clockwise) of the circle of centre (a, b)
    and radius r to a region's area ½∮(x dy - y dx), first moments ½∮x² dy, -½∮y² dx, and
    polar moment ⅓∮(x³ dy - y³ dx) (Green's theorem), in closed form: x = a + r cos t,
    y = b + r sin t turn each into integrals of powers of cos t and sin t."""
    s1, c1 = math.sin(t1), math.cos(t1)
    s2, c2 = math.sin(t2), math.cos(t2)
    dt = t2 - t1
    ds = s2 - s1
    dc = c2 - c1
    d_sin2 = math.sin(2.0 * t2) - math.sin(2.0 * t1)
    d_sin4 = math.sin(4.0 * t2) - math.sin(4.0 * t1)
    cos2 = 0.5 * dt + 0.25 * d_sin2  # ∫cos², ∫sin²
    sin2 = 0.5 * dt - 0.25 * d_sin2
    cos3 = ds - (s2 * s2 * s2 - s1 * s1 * s1) / 3.0  # ∫cos³, ∫sin³
    sin3 = -dc + (c2 * c2 * c2 - c1 * c1 * c1) / 3.0
    area = 0.5 * r * (a * ds - b * dc + r * dt)
    first_x = 0.5 * r * (a * a * ds + 2.0 * a * r * cos2 + r * r * cos3)
    first_y = 0.5 * r * (-b * b * dc + 2.0 * b * r * sin2 + r * r * sin3)
    # ∫cos⁴ + ∫sin⁴ = 3t/4 + sin 4t / 16
    polar = r / 3.0 * (a * a * a * ds + 3.0 * a * a * r * cos2 + 3.0 * a * r * r * cos3
                       - b * b * b * dc + 3.0 * b * b * r * sin2 + 3.0 * b * r * r * sin3
                       + r * r * r * (0.75 * dt + d_sin4 / 16.0))
    return area, first_x, first_y, polar
