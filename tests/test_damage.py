"""Crack-initiation and crack-damage stresses: synthetic curves with a known onset of cracking,
of dilatancy and a known reversal of the areal strain, then a UCS curve."""

import numpy as np
import pytest

from rockcal import make_params, random_packing, simulate_ucs
from rockcal.labtests.damage import (cd_by_reversal, ci_by_crack_strain, ci_by_cracking, crack_strain,
                                     crack_stresses, volumetric_strain)

E_MPA, NU, PEAK = 50e3, 0.2, 100.0
Q = np.linspace(0.0, PEAK, 2001)  # deviatoric stress, MPa, every 0.05 MPa
ONSET, REVERSAL = 40.0, 80.0
# lateral crack strain c (q - onset)^2: the areal strain (1 - nu) q / E - c (q - onset)^2 turns
# back where its slope vanishes, at q = onset + (1 - nu) / (2 c E)
C = (1 - NU) / (2 * E_MPA * (REVERSAL - ONSET))


def synthetic_curve(noise=0.0, seed=0):
    """Axial and lateral strain of an elastic plane (E, nu) that dilates past ONSET."""
    rng = np.random.default_rng(seed)
    axial = Q / E_MPA + noise * rng.standard_normal(len(Q))
    lateral = (NU * Q / E_MPA + C * np.maximum(0.0, Q - ONSET) ** 2
               + noise * rng.standard_normal(len(Q)))
    return axial, lateral


def test_volumetric_strain_is_compaction_positive_over_the_lateral_strains():
    assert volumetric_strain([1e-3], [2e-4])[0] == pytest.approx(8e-4)  # 2D: the areal strain
    assert volumetric_strain([1e-3], [2e-4], 2)[0] == pytest.approx(6e-4)  # 3D: eps_1 + 2 eps_3


def test_in_3d_the_two_lateral_strains_give_the_true_nu_and_an_earlier_reversal():
    """A cylinder dilating by c (q - onset)^2 in each of its two lateral directions: nu read as
    itself, the crack volumetric strain twice the lateral one, and eps_v = (1 - 2 nu) q / E -
    2 c (q - onset)^2 turning back at q = onset + (1 - 2 nu) / (4 c E), before the plane's."""
    axial, lateral = synthetic_curve()
    E, nu, crack = crack_strain(axial, lateral, Q, lateral_strains=2)
    assert E == pytest.approx(E_MPA, rel=1e-9) and nu == pytest.approx(NU, rel=1e-9)
    np.testing.assert_allclose(crack.strain, -2 * C * np.maximum(0.0, Q - ONSET) ** 2, atol=1e-12)
    reversal = ONSET + (1 - 2 * NU) / (4 * C * E_MPA)
    assert cd_by_reversal(axial, lateral, Q, 2) == pytest.approx(reversal, abs=0.05)
    assert reversal < REVERSAL


def test_crack_strain_recovers_the_elastic_constants_and_the_onset_of_dilatancy():
    axial, lateral = synthetic_curve()
    E, nu, crack = crack_strain(axial, lateral, Q)
    assert E == pytest.approx(E_MPA, rel=1e-9) and nu == pytest.approx(NU, rel=1e-9)
    np.testing.assert_allclose(crack.strain, -C * np.maximum(0.0, Q - ONSET) ** 2, atol=1e-12)
    # noiseless: the onset within the curve's sampling (0.05 MPa) and the tolerance's reach
    assert ONSET <= ci_by_crack_strain(Q, crack.strain, crack.tolerance) <= ONSET + 0.1


def test_noise_moves_the_dilatancy_onset_by_the_noise_reach_only():
    """With 1e-6 scatter on the strains the onset is read where the crack strain has outgrown
    3 x its scatter over the elastic part: (q - onset) = sqrt(3 x scatter / c) at most, here
    about 6 MPa for a scatter of 1.4e-6 (two strains' noise)."""
    axial, lateral = synthetic_curve(noise=1e-6)
    _, _, crack = crack_strain(axial, lateral, Q)
    reach = np.sqrt(crack.tolerance / C)
    ci = ci_by_crack_strain(Q, crack.strain, crack.tolerance)
    assert 3e-6 < crack.tolerance < 6e-6
    assert ONSET - 2.0 < ci <= ONSET + reach + 1.0


def test_cd_is_at_the_reversal_of_the_areal_strain_in_2d():
    axial, lateral = synthetic_curve()
    assert cd_by_reversal(axial, lateral, Q) == pytest.approx(REVERSAL, abs=0.05)


def test_cd_is_the_peak_of_a_specimen_compacting_to_its_peak():
    assert cd_by_reversal(Q / E_MPA, NU * Q / E_MPA, Q) == PEAK


def sustained_count(onset=45.0, total=500):
    """No break below `onset` but two isolated ones, then breaks growing as (q - onset)^2."""
    count = np.floor(total * (np.maximum(0.0, Q - onset) / (PEAK - onset)) ** 2)
    count += (Q >= 10.0).astype(float) + (Q >= 25.0)  # isolated early breaks, 15 and 20 MPa apart
    return count


def test_ci_by_cracking_skips_isolated_breaks_and_finds_the_sustained_onset():
    count = sustained_count()
    first_sustained = Q[np.argmax(np.floor(500 * (np.maximum(0.0, Q - 45.0) / 55.0) ** 2) > 0)]
    assert first_sustained == pytest.approx(45.0 + 55.0 / np.sqrt(500), abs=0.05)
    assert ci_by_cracking(Q, count) == first_sustained
    # the early breaks count once the pauses after them are short enough
    assert ci_by_cracking(Q, count, pause_fraction=0.25) == 10.0


def test_ci_by_cracking_without_a_break_or_with_a_pause_up_to_the_peak_is_the_peak():
    assert ci_by_cracking(Q, np.zeros(len(Q))) == PEAK
    assert ci_by_cracking(Q, (Q >= 20.0).astype(float)) == PEAK


def test_ci_by_cracking_reads_pauses_on_the_rising_stress():
    """A drop and recovery of the stress (a slow-down's transient) is no rise: the pause is
    measured on the running maximum."""
    q = np.array([0.0, 50.0, 52.0, 40.0, 53.0, 56.0, 60.0, 65.0, 70.0])
    n = np.array([0, 0, 1, 1, 2, 3, 4, 5, 9])
    assert ci_by_cracking(q, n) == 52.0
    assert ci_by_cracking(q, n, pause_fraction=0.01) == 70.0  # every rise above 0.7 MPa a pause


def test_crack_stresses_of_a_synthetic_curve():
    axial, lateral = synthetic_curve()
    r = crack_stresses(axial, lateral, Q, sustained_count()).responses
    assert r["ci_ratio"] == pytest.approx((45.0 + 55.0 / np.sqrt(500)) / PEAK, abs=5e-4)
    assert r["ci_strain_ratio"] == pytest.approx(ONSET / PEAK, abs=1e-3)
    assert r["cd_ratio"] == pytest.approx(REVERSAL / PEAK, abs=5e-4)
    assert r["cd_MPa"] == pytest.approx(REVERSAL, abs=0.05)


def test_the_ucs_curve_counts_broken_bonds_and_gives_ci_and_cd():
    """The curve's 4th column is the bonds broken so far, ending at the result's count; CI
    and CD lie between the first break and the peak."""
    spec = random_packing(10, 20, 0.25, 1.65, seed=3)
    r = simulate_ucs(make_params({}), spec)
    broken = r.curve[:, 3]
    assert r.curve.shape[1] == 4 and broken[0] == 0 and np.all(np.diff(broken) >= 0)
    assert broken[-1] == r.n_broken_tension + r.n_broken_shear
    first_break = r.curve[np.argmax(broken > 0), 2]
    assert first_break <= r.ci_MPa <= r.cd_MPa <= r.ucs_MPa
    assert r.ci_ratio == pytest.approx(r.ci_MPa / r.ucs_MPa)
    assert 0 < r.ci_strain_ratio <= 1 and r.cd_ratio == pytest.approx(r.cd_MPa / r.ucs_MPa)


def test_the_figure_marks_ci_and_cd(tmp_path):
    from rockcal.plots import plot_crack_stresses

    axial, lateral = synthetic_curve()
    path = tmp_path / "crack_stresses.png"
    plot_crack_stresses(np.column_stack([axial, lateral, Q, sustained_count()]), path)
    assert path.stat().st_size > 20_000
