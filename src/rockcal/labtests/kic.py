"""Fracture toughness K_IC from a peak load: the lab's round bar and the simulated notched beam.

All functions take SI units (N, m) and return Pa·m^0.5.
"""

from __future__ import annotations

import math

from rockcal.errors import InputError

PMAX_KIC_TOLERANCE = 0.05  # a stated P_max and K_IC further apart than this disagree


def ouchterlony_Y(a_over_D: float) -> float:
    """Shape factor of the straight-notched round bar in three-point bending (Ouchterlony 1980):
    Y = 12.75 (a/D)^0.5 [1 + 19.65 (a/D)^4.5]^0.5 / (1 - a/D)^0.25."""
    x = a_over_D
    return 12.75 * math.sqrt(x) * math.sqrt(1 + 19.65 * x**4.5) / (1 - x) ** 0.25


def round_bar_kic(pmax_N: float, diameter_m: float, notch_m: float, span_m: float) -> float:
    """K_IC = 0.25 (S/D) Y(a/D) P_max / D^1.5 of the straight-notched round bar (Ouchterlony 1980),
    the formula of the source study's lab tests; usually quoted for a/D <= 0.6."""
    check_round_bar(pmax_N, diameter_m, notch_m, span_m)
    return 0.25 * (span_m / diameter_m) * ouchterlony_Y(notch_m / diameter_m) * pmax_N / diameter_m**1.5


def check_round_bar(pmax_N: float, diameter_m: float, notch_m: float, span_m: float) -> None:
    for name, value in (("pmax_kn", pmax_N), ("diameter_mm", diameter_m),
                        ("notch_mm", notch_m), ("span_mm", span_m)):
        if not (math.isfinite(value) and value > 0):
            raise InputError(name, f"must be a finite number > 0, got {value:g}")
    if notch_m >= diameter_m:
        raise InputError("notch_mm", f"the notch ({1e3 * notch_m:g} mm) must be shallower than "
                         f"the diameter ({1e3 * diameter_m:g} mm)")


def pmax_kic_disagreement(pmax_N: float, kic_Pa_sqrt_m: float, diameter_m: float, notch_m: float,
                          span_m: float, tolerance: float = PMAX_KIC_TOLERANCE) -> str | None:
    """A warning when a stated K_IC differs from the one the round-bar formula gives for the
    stated P_max by more than `tolerance` (relative), else None."""
    computed = round_bar_kic(pmax_N, diameter_m, notch_m, span_m)
    difference = kic_Pa_sqrt_m / computed - 1
    if abs(difference) <= tolerance:
        return None
    return (f"stated K_IC {kic_Pa_sqrt_m / 1e6:.3f} MPa·m^0.5 differs by {100 * difference:+.1f} % "
            f"from {computed / 1e6:.3f} MPa·m^0.5 given by P_max {pmax_N / 1e3:.3f} kN with "
            f"Ouchterlony's round-bar formula (D {1e3 * diameter_m:g} mm, a {1e3 * notch_m:g} mm, "
            f"S {1e3 * span_m:g} mm)")


def senb_k_astm(a_over_W: float) -> float:
    """Dimensionless K of the single-edge-notched beam at S/W = 4, k = K / (sigma_N sqrt(W)) with
    sigma_N = 3 P S / (2 t W^2): ASTM E399 (Srawley 1976), k = (2/3) f(a/W) with
    f = 3 sqrt(x) [1.99 - x(1-x)(2.15 - 3.93x + 2.7x^2)] / [2 (1+2x) (1-x)^1.5]."""
    x = a_over_W
    return math.sqrt(x) * (1.99 - x * (1 - x) * (2.15 - 3.93 * x + 2.7 * x**2)) / (
        (1 + 2 * x) * (1 - x) ** 1.5)


def senb_k_pure_bending(a_over_W: float) -> float:
    """Dimensionless K of an edge crack in a strip under pure bending, k = K / (sigma sqrt(W)) with
    sigma = 6 M / (t W^2): Tada, Paris & Irwin (The Stress Analysis of Cracks Handbook),
    K = sigma sqrt(pi a) F, F = 1.122 - 1.40x + 7.33x^2 - 13.08x^3 + 14.0x^4 (0.2 % for x <= 0.6)."""
    x = a_over_W
    return math.sqrt(math.pi * x) * (1.122 - 1.40 * x + 7.33 * x**2 - 13.08 * x**3 + 14.0 * x**4)


def senb_k(a_over_W: float, span_over_W: float) -> float:
    """Dimensionless K of a three-point-bend beam of any span: linear in W/S between S/W = 4
    and pure bending (S/W -> infinity), the interpolation of Guinea, Pastor, Planas & Elices
    (1998), Int. J. Fracture 89:103-116, here with the ASTM E399 and Tada end solutions."""
    return senb_k_pure_bending(a_over_W) + 4 / span_over_W * (
        senb_k_astm(a_over_W) - senb_k_pure_bending(a_over_W))


def senb_kic(pmax_N_per_m: float, span_m: float, height_m: float, notch_m: float,
             thickness_m: float = 1.0) -> float:
    """K_IC = sigma_N sqrt(W) k(a/W, S/W), sigma_N = 3 P S / (2 t W^2), of a single-edge-notched
    beam (depth W, notch a, span S) in three-point bending; P per `thickness_m` of beam."""
    if not 0 < notch_m < 0.7 * height_m:
        raise InputError("notch_mm", f"must be in (0, 0.7 x height) for the notched-beam K formula, "
                         f"got {1e3 * notch_m:g} mm for a {1e3 * height_m:g} mm beam")
    sigma_N = 3 * pmax_N_per_m * span_m / (2 * thickness_m * height_m**2)
    return sigma_N * math.sqrt(height_m) * senb_k(notch_m / height_m, span_m / height_m)


def scb_y(a_over_R: float, S_over_R: float) -> float:
    """Dimensionless K of the semi-circular bend specimen (ISRM's suggested method, Kuruppu,
    Obara, Ayatollahi, Chong & Funatsu 2014, Rock Mech. Rock Eng. 47:267-274, their fit to
    finite elements for 0.5 <= S/R <= 0.8): Y' = -1.297 + 9.516 (S/R) - (0.47 + 16.457 (S/R))
    beta + (1.071 + 34.401 (S/R)) beta^2, beta = a/R; S is each support's distance from the
    centre."""
    s, b = S_over_R, a_over_R
    return -1.297 + 9.516 * s - (0.47 + 16.457 * s) * b + (1.071 + 34.401 * s) * b**2


def scb_kic(pmax_N: float, radius_m: float, notch_m: float, half_span_m: float, thickness_m: float = 1.0) -> float:
    """K_IC = Y' P_max sqrt(pi a) / (2 R B) of a semi-circular bend specimen (radius R, edge
    notch a, supports at +-S, thickness B; ISRM 2014, `scb_y`); P over `thickness_m` (a 2D
    specimen's load per metre of thickness, B = 1 m)."""
    y = scb_y(notch_m / radius_m, half_span_m / radius_m)
    return y * pmax_N * math.sqrt(math.pi * notch_m) / (2 * radius_m * thickness_m)
