"""Crack-initiation (CI) and crack-damage (CD) stresses read from a compression curve.

A compression curve here is, row by row: axial strain (shortening positive), lateral strain
(extension positive), deviatoric stress q = sigma1 - sigma3 (MPa; sigma1 in a UCS test) and
the bonds broken so far. Three readings, all on the curve up to its peak q:

- CI by the onset of cracking (the virtual counterpart of acoustic emission, Eberhardt et al.
  1998, Can. Geotech. J. 35): the q of the first broken bond from which cracking is sustained,
  that is, never pauses until the peak for more than PAUSE_FRACTION of the peak q (q rising by
  that much with no bond breaking). Isolated early breaks followed by a longer pause do not count.
- CI by the crack volumetric strain (Martin & Chandler 1994, IJRMMS 31(6):643-659): crack
  strain = measured volumetric strain - elastic volumetric strain. The volumetric strain is
  eps_v = eps_axial - k eps_lateral (compaction positive, the small-strain sum of the principal
  strains) over the specimen's k lateral strains (`rig.Rig.lateral_strains`): in 2D (k = 1) the
  areal strain of the plane, in 3D (k = 2) eps_1 + 2 eps_3. The elastic part follows from E and
  nu read as the test reads them (the deviatoric load gives eps_axial = q / E, eps_lateral =
  nu q / E), so eps_v elastic = (1 - k nu) q / E: (1 - nu) q / E in 2D, (1 - 2 nu) q / E in 3D. E and nu are the tangents over the elastic part of the curve
  (least-squares slopes of both strains against q over ELASTIC_WINDOW of the peak, whose
  intercept sets the strains' origin). CI is the q of the last reading before the peak at which
  the crack strain is not yet below -3 x its scatter over that window (the noise of the
  elastic part): from there on the specimen dilates beyond elasticity until the peak.
- CD at the reversal of the volumetric strain: the q of the largest compaction eps_v before the
  peak (Martin & Chandler 1994; Bieniawski 1967). A specimen that compacts up to its peak has
  CD at the peak.

Each stress is also given as a ratio to the peak q (the UCS in a UCS test).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rockcal.labtests.kind import Response
from rockcal.labtests.line_fit import fit_line
from rockcal.labtests.result import RunFailed

PAUSE_FRACTION = 0.1  # cracking that pauses over more than this x peak q was not yet sustained
ELASTIC_WINDOW = (0.1, 0.3)  # the part of the rising curve (x peak q) E and nu are read over
NOISE_MULTIPLE = 3.0  # crack strain below -this x its scatter over the elastic part is dilatancy
MIN_TOLERANCE = 1e-9  # the tolerance of a noiseless curve (strain)
VOLUMETRIC_NAME = {1: "areal", 2: "volumetric"}  # the volumetric strain's name, by lateral strains
# The responses of every compression test. Not yet targets: a campaign section must first hold
# them (`campaign.targets.LabTargets.scalars` reads every target of its test).
CRACK_RESPONSES = (
    Response("ci_MPa", "MPa", target=False, label="crack initiation CI (cracking onset)"),
    Response("ci_ratio", "", target=False, label="CI / peak"),
    Response("ci_strain_MPa", "MPa", target=False, label="CI (crack volumetric strain)"),
    Response("ci_strain_ratio", "", target=False, label="CI (crack strain) / peak"),
    Response("cd_MPa", "MPa", target=False, label="crack damage CD (volumetric strain reversal)"),
    Response("cd_ratio", "", target=False, label="CD / peak"))


@dataclass(frozen=True)
class CrackStresses:
    """CI (by cracking onset, and by crack volumetric strain), CD and the peak, deviatoric MPa,
    with the tangent E (MPa) and nu the crack strain was reckoned with."""

    ci_MPa: float
    ci_strain_MPa: float
    cd_MPa: float
    peak_MPa: float
    E_tangent_MPa: float
    nu_tangent: float

    @property
    def responses(self) -> dict[str, float]:
        """The stresses and their ratios to the peak, as a test reports them."""
        p = self.peak_MPa
        return {"ci_MPa": self.ci_MPa, "ci_ratio": self.ci_MPa / p,
                "ci_strain_MPa": self.ci_strain_MPa, "ci_strain_ratio": self.ci_strain_MPa / p,
                "cd_MPa": self.cd_MPa, "cd_ratio": self.cd_MPa / p}


def crack_stresses(axial, lateral, q_MPa, broken, lateral_strains: int = 1,
                   pause_fraction: float = PAUSE_FRACTION, window=ELASTIC_WINDOW) -> CrackStresses:
    """CI, CI by crack strain and CD of a compression curve whose volumetric strain takes
    `lateral_strains` lateral strains (see the module docstring)."""
    axial, lateral, q, broken = (np.asarray(v, float) for v in (axial, lateral, q_MPa, broken))
    peak = int(np.argmax(q))
    a, l, q, n = axial[:peak + 1], lateral[:peak + 1], q[:peak + 1], broken[:peak + 1]
    E, nu, crack = crack_strain(a, l, q, window, lateral_strains)
    return CrackStresses(ci_MPa=ci_by_cracking(q, n, pause_fraction),
                         ci_strain_MPa=ci_by_crack_strain(q, crack.strain, crack.tolerance),
                         cd_MPa=cd_by_reversal(a, l, q, lateral_strains), peak_MPa=float(q[-1]),
                         E_tangent_MPa=E, nu_tangent=nu)


def volumetric_strain(axial, lateral, lateral_strains: int = 1) -> np.ndarray:
    """The volumetric strain, compaction positive: eps_axial - lateral_strains x eps_lateral
    (axial shortening and lateral extension positive); 2D's areal strain with one lateral
    strain, 3D's eps_1 + 2 eps_3 with two."""
    return np.asarray(axial, float) - lateral_strains * np.asarray(lateral, float)


def ci_by_cracking(q, broken, pause_fraction: float = PAUSE_FRACTION) -> float:
    """The q (MPa) at the first broken bond of the sustained cracking that leads to the peak:
    no later rise of q by more than pause_fraction x the peak passes without a break. q and
    broken run up to the peak, its last row; the pauses are measured on q's running maximum.
    Without a break before the peak, the peak."""
    q, broken = np.asarray(q, float), np.asarray(broken, float)
    top = np.maximum.accumulate(q)
    breaks = np.flatnonzero(np.diff(broken) > 0) + 1  # the rows where bonds broke
    if len(breaks) == 0:
        return float(q[-1])
    reached = np.append(top[breaks], top[-1])  # q reached at each break, then at the peak
    pauses = np.diff(reached)  # the rise of q from each break to the next (the last: to the peak)
    long = np.flatnonzero(pauses > pause_fraction * top[-1])
    first = long[-1] + 1 if len(long) else 0
    if first == len(breaks):  # cracking paused up to the peak itself
        return float(q[-1])
    return float(q[breaks[first]])


@dataclass(frozen=True)
class CrackStrain:
    """The crack volumetric strain along the curve and the tolerance of its elastic part."""

    strain: np.ndarray
    tolerance: float


def crack_strain(axial, lateral, q, window=ELASTIC_WINDOW, lateral_strains: int = 1) -> tuple[float, float, CrackStrain]:
    """Tangent E (MPa) and nu over `window` of the peak q (the curve runs up to its peak) and
    the crack volumetric strain over `lateral_strains` lateral strains (k): eps_v less its
    elastic line (a0 - k l0) + (1 - k nu) q / E."""
    axial, lateral, q = (np.asarray(v, float) for v in (axial, lateral, q))
    rows = (q >= window[0] * q.max()) & (q <= window[1] * q.max())
    rows[np.argmax(q > window[1] * q.max()):] = False  # the rising part only
    if np.count_nonzero(rows) < 3:  # a curve too coarse there: its whole rise
        rows = np.arange(len(q)) < len(q) - 1
    if np.count_nonzero(rows) < 2:
        raise RunFailed("the compression curve has fewer than two readings before its peak (the "
                        "test stopped before the specimen took up load): nothing to read E, nu, CI "
                        "and CD from; try a larger maximum axial strain")
    slope_a, a0 = fit_line(q[rows], axial[rows])
    slope_l, l0 = fit_line(q[rows], lateral_strains * lateral[rows])  # of the lateral strains' sum
    E, k_nu = 1.0 / slope_a, slope_l / slope_a
    crack = volumetric_strain(axial, lateral, lateral_strains) - ((a0 - l0) + (1.0 - k_nu) * q / E)
    tolerance = max(NOISE_MULTIPLE * float(np.sqrt(np.mean(crack[rows] ** 2))), MIN_TOLERANCE)
    return float(E), float(k_nu / lateral_strains), CrackStrain(crack, tolerance)


def ci_by_crack_strain(q, crack, tolerance: float) -> float:
    """The q (MPa) at the last reading before the peak (the curve's last row) whose crack
    strain is not below -tolerance: the onset of the dilatancy that lasts to the peak."""
    q, crack = np.asarray(q, float), np.asarray(crack, float)
    holding = np.flatnonzero(crack >= -tolerance)
    return float(q[holding[-1]]) if len(holding) else float(q[0])


def cd_by_reversal(axial, lateral, q, lateral_strains: int = 1) -> float:
    """The q (MPa) at the largest volumetric compaction before the peak (the curve's last row)."""
    return float(np.asarray(q, float)[int(np.argmax(volumetric_strain(axial, lateral, lateral_strains)))])
