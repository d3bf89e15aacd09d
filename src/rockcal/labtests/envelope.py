"""The strength envelope of intact rock from peak stresses at several confinements.

- Mohr-Coulomb: a least-squares line sigma1 = sigma_c + k sigma3 through the peaks, with
  k = (1 + sin phi) / (1 - sin phi) and c = sigma_c (1 - sin phi) / (2 cos phi) (Jaeger, Cook &
  Zimmerman, Fundamentals of Rock Mechanics, 4th ed., sec. 4.5).
- Hoek-Brown, intact rock (s = 1, a = 0.5): sigma1 = sigma3 + sigma_ci (m_i sigma3 / sigma_ci
  + 1)^0.5, fitted as Hoek does (Hoek & Brown 1980; Hoek, Practical Rock Engineering 2007,
  ch. 11, "Determination of sigma_ci and m_i"): a linear least-squares regression of
  y = (sigma1 - sigma3)^2 on x = sigma3, y = m_i sigma_ci x + sigma_ci^2, so sigma_ci^2 is the
  intercept and m_i sigma_ci the slope; its quality is that regression's r^2 (Hoek's formula).
  Hoek advises confinements within 0 <= sigma3 <= 0.5 sigma_ci.

Each fit also gives the root-mean-square misfit of sigma1 (MPa) at the peaks. Stresses in MPa,
compression positive.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rockcal.errors import InputError
from rockcal.labtests.line_fit import fit_line


@dataclass(frozen=True)
class MohrCoulomb:
    """A Mohr-Coulomb envelope: its sigma1 intercept sigma_c (MPa), slope k, friction angle phi
    (degrees) and cohesion c (MPa), with the fit's R^2 and rms misfit of sigma1 (MPa)."""

    sigma_c_MPa: float
    k: float
    phi_deg: float
    c_MPa: float
    r2: float
    rms_MPa: float

    def sigma1(self, sigma3_MPa):
        return self.sigma_c_MPa + self.k * np.asarray(sigma3_MPa, float)


@dataclass(frozen=True)
class HoekBrown:
    """An intact Hoek-Brown envelope: sigma_ci (MPa) and m_i, with the regression's r^2 and the
    rms misfit of sigma1 (MPa)."""

    sigma_ci_MPa: float
    m_i: float
    r2: float
    rms_MPa: float

    def sigma1(self, sigma3_MPa):
        s3 = np.asarray(sigma3_MPa, float)
        return s3 + self.sigma_ci_MPa * np.sqrt(np.maximum(self.m_i * s3 / self.sigma_ci_MPa + 1, 0))


def check_peaks(sigma3_MPa, sigma1_MPa) -> tuple[np.ndarray, np.ndarray]:
    """The peaks as arrays; at least two distinct confinements, finite values, sigma1 > sigma3."""
    s3, s1 = np.asarray(sigma3_MPa, float), np.asarray(sigma1_MPa, float)
    if s3.shape != s1.shape or s3.ndim != 1:
        raise InputError("sigma1_MPa", f"needs one peak per confinement, got {s1.size} for {s3.size}")
    if len(np.unique(s3)) < 2:
        raise InputError("confinement_mpa", "an envelope needs peaks at two confinements or more")
    if not (np.all(np.isfinite(s3)) and np.all(np.isfinite(s1))):
        raise InputError("sigma1_MPa", "peaks and confinements must be finite numbers")
    if np.any(s1 <= s3):
        raise InputError("sigma1_MPa", "every peak sigma1 must exceed its confinement sigma3")
    return s3, s1


def fit_mohr_coulomb(sigma3_MPa, sigma1_MPa) -> MohrCoulomb:
    """The least-squares line sigma1 = sigma_c + k sigma3 and its phi and c."""
    s3, s1 = check_peaks(sigma3_MPa, sigma1_MPa)
    k, sigma_c = fit_line(s3, s1)
    if k <= 1:
        raise InputError("sigma1_MPa", f"the peaks rise with confinement at a slope of {k:.3g}; "
                         "Mohr-Coulomb needs k > 1 (phi > 0)")
    sin_phi = (k - 1) / (k + 1)
    phi = math.asin(sin_phi)
    c = sigma_c * (1 - sin_phi) / (2 * math.cos(phi))
    fitted = sigma_c + k * s3
    return MohrCoulomb(sigma_c_MPa=float(sigma_c), k=float(k), phi_deg=math.degrees(phi),
                       c_MPa=float(c), r2=_r2(s1, fitted), rms_MPa=_rms(s1 - fitted))


def fit_hoek_brown(sigma3_MPa, sigma1_MPa) -> HoekBrown:
    """Hoek's regression of (sigma1 - sigma3)^2 on sigma3 for sigma_ci and m_i."""
    s3, s1 = check_peaks(sigma3_MPa, sigma1_MPa)
    x, y = s3, (s1 - s3) ** 2
    n = len(x)
    sxy = np.sum(x * y) - np.sum(x) * np.sum(y) / n
    sxx = np.sum(x * x) - np.sum(x) ** 2 / n
    syy = np.sum(y * y) - np.sum(y) ** 2 / n
    slope = sxy / sxx
    intercept = np.sum(y) / n - slope * np.sum(x) / n
    if intercept <= 0:
        raise InputError("sigma1_MPa", "the Hoek-Brown regression gives sigma_ci^2 <= 0: the "
                         "deviatoric peaks grow too fast with confinement for an intact envelope")
    sigma_ci = math.sqrt(intercept)
    m_i = float(slope / sigma_ci)
    fitted = s3 + sigma_ci * np.sqrt(np.maximum(m_i * s3 / sigma_ci + 1, 0))
    r2 = float(sxy**2 / (sxx * syy)) if syy > 0 else 1.0
    return HoekBrown(sigma_ci_MPa=sigma_ci, m_i=m_i, r2=r2, rms_MPa=_rms(s1 - fitted))


def envelope_responses(sigma3_MPa, sigma1_MPa) -> dict[str, float]:
    """Both fits as responses: phi_deg, c_MPa, m_i, sigma_ci_MPa and their qualities."""
    mc = fit_mohr_coulomb(sigma3_MPa, sigma1_MPa)
    hb = fit_hoek_brown(sigma3_MPa, sigma1_MPa)
    return {"phi_deg": mc.phi_deg, "c_MPa": mc.c_MPa, "m_i": hb.m_i, "sigma_ci_MPa": hb.sigma_ci_MPa,
            "mc_sigma_c_MPa": mc.sigma_c_MPa, "mc_r2": mc.r2, "mc_rms_MPa": mc.rms_MPa,
            "hb_r2": hb.r2, "hb_rms_MPa": hb.rms_MPa}


def _r2(observed, fitted) -> float:
    """Coefficient of determination of a fit."""
    total = float(np.sum((observed - np.mean(observed)) ** 2))
    return 1.0 - float(np.sum((observed - fitted) ** 2)) / total if total > 0 else 1.0


def _rms(residual) -> float:
    return float(np.sqrt(np.mean(np.square(residual))))
