"""Measuring a specimen: boundary particle sets, gauge lengths under homogeneous strain, the
secant modulus and Poisson's ratio at half the peak, crack positions by mode."""

import numpy as np
import pytest

from rockcal.dem.laws import BROKEN_SHEAR, BROKEN_TENSION, INTACT
from rockcal.dem.measure import boundary_sets, cracks, gauge_lengths, secant_at_half_peak


def disks(seed, n=400):
    rng = np.random.default_rng(seed)
    return rng.uniform([0, 0], [10e-3, 20e-3], (n, 2)), rng.uniform(0.2e-3, 0.35e-3, n)


def test_boundary_sets_hold_the_particles_whose_edge_is_within_the_band():
    """Each side's set is exactly the particles whose edge lies within `band` of the
    specimen's outermost edge on that side."""
    pos, radius = disks(1)
    band = 0.5e-3
    sets = boundary_sets(pos, radius, band)
    lo, hi = (pos - radius[:, None]).min(axis=0), (pos + radius[:, None]).max(axis=0)
    expected = {"left": pos[:, 0] - radius < lo[0] + band,
                "right": pos[:, 0] + radius > hi[0] - band,
                "bottom": pos[:, 1] - radius < lo[1] + band,
                "top": pos[:, 1] + radius > hi[1] - band}
    for side, mask in expected.items():
        np.testing.assert_array_equal(sets[side], np.flatnonzero(mask))
        assert 0 < len(sets[side]) < len(pos) // 4


@pytest.mark.parametrize("ex, ey", [(1e-3, -2e-3), (-5e-4, 0.0)])
def test_gauge_lengths_follow_a_homogeneous_strain(ex, ey):
    """Under x' = (1 + ex)(x - c) + c + u, y' likewise, the gauge lengths read on the same
    boundary sets scale by (1 + ex) and (1 + ey): strains are read exactly."""
    pos, radius = disks(2)
    sets = boundary_sets(pos, radius, 0.6e-3)
    w0, h0 = gauge_lengths(pos, sets)
    assert 8e-3 < w0 < 10e-3 and 18e-3 < h0 < 20e-3
    moved = (pos - [5e-3, 7e-3]) * [1 + ex, 1 + ey] + [5.3e-3, 6e-3]
    w, h = gauge_lengths(moved, sets)
    assert w == pytest.approx(w0 * (1 + ex), rel=1e-12)
    assert h == pytest.approx(h0 * (1 + ey), rel=1e-12)


def test_secant_at_half_peak_on_a_linear_then_softening_curve():
    """A curve linear with slope E up to the peak (sampled coarsely, so half the peak falls
    between samples), then softening: the secant at half the peak is E, nu is the ratio of the
    strains there, and the peak index is the maximum's."""
    E, nu = 40e9, 0.21
    axial = np.concatenate([np.linspace(0, 3e-3, 7), [3.2e-3, 3.5e-3]])
    stress = np.where(axial <= 3e-3, E * axial, E * 3e-3 - 80e9 * (axial - 3e-3))
    lateral = nu * axial
    e, v, peak = secant_at_half_peak(axial, lateral, stress)
    assert peak == 6
    assert e == pytest.approx(E, rel=1e-12)
    assert v == pytest.approx(nu, rel=1e-12)
    # a curve that bends: secant, not tangent, at half the peak (stress = s0 tanh(axial / a))
    axial = np.linspace(0, 2e-3, 2001)
    stress = 100e6 * np.tanh(axial / 1e-3)
    e, _, _ = secant_at_half_peak(axial, 0.25 * axial, stress)
    half = 0.5 * stress.max()
    assert e == pytest.approx(half / (1e-3 * np.arctanh(half / 100e6)), rel=1e-5)


def test_cracks_are_the_break_positions_of_broken_bonds_by_mode():
    state = np.array([INTACT, BROKEN_TENSION, BROKEN_SHEAR, BROKEN_TENSION, INTACT])
    xy = np.arange(10.0).reshape(5, 2)
    out = cracks(state, xy)
    np.testing.assert_array_equal(out["tension"], xy[[1, 3]])
    np.testing.assert_array_equal(out["shear"], xy[[2]])
