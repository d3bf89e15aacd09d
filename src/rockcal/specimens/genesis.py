"""Material genesis settings, as PFC's FISHTank names them (`ft.fis`; Potyondy & Cundall 2004).

A random specimen is made in four steps, each set here with PFC's meaning:
1. a grain cloud: as many grains (radii uniform in [R_min, ratio R_min]) as fill the vessel
   to the cloud porosity n_c, overlaps not counted (FISHTank `pk_nc`);
2. packing by grain scaling: frictionless grains rearrange and all radii are scaled by one
   factor until the vessel walls feel the material pressure P_m (`pk_Pm`);
3. floaters (grains with fewer than 3 contacts, walls counted) are enlarged until they touch
   3, the packing is cycled so that their neighbours make room and scaled back to P_m, until
   no floater is left;
4. bonds at every grain pair whose gap is <= the installation gap g_i (`pbm_igap`), given
   here as a fraction of R_min; a bond at an overlapping pair takes the overlap as its
   contact's reference gap, so the specimen leaves the vessel free of locked-in force.
"""

from __future__ import annotations

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from rockcal.dem.neighbours import CONTACT_GAP, pair_gaps
from rockcal.errors import InputError, from_validation_error

MIN_CONTACTS = 3  # a grain with fewer contacts in the vessel (walls counted) is a floater
# a genesis that ran out of rounds with its wall stress outside P_m / 2 .. 2 P_m gave up (the
# clumped genesis enlarges its floaters only within this band)
PRESSURE_BAND = 2.0


class Genesis(BaseModel):
    """Genesis settings of a random specimen (see the module docstring for their PFC names).
    The defaults reproduce the source study's PFC2D results (its L16 table)."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    install_gap: float = Field(0.6, ge=0, le=10, description="bond installation gap / R_min")
    cloud_porosity: float = Field(0.09, gt=0, lt=1, description="porosity of the grain cloud")
    pressure_mpa: float = Field(0.1, gt=0, le=1e3, description="material pressure P_m, MPa")


def make_genesis(values: dict) -> Genesis:
    """Validated genesis settings; a bad one raises InputError naming the field."""
    try:
        return Genesis(**values)
    except ValidationError as exc:
        raise from_validation_error(exc) from None


def cloud_radii(rng: np.random.Generator, area: float, rmin: float, radius_ratio: float,
                cloud_porosity: float) -> np.ndarray:
    """Radii drawn one after another until the grains' area reaches (1 - n_c) x `area`."""
    mean_area = np.pi * rmin**2 * (1 + radius_ratio + radius_ratio**2) / 3
    target = (1.0 - cloud_porosity) * area
    radius = rng.uniform(rmin, radius_ratio * rmin, int(1.2 * target / mean_area) + 16)
    count = int(np.searchsorted(np.cumsum(np.pi * radius**2), target)) + 1
    return radius[:count]


def grain_contacts(pos: np.ndarray, radius: np.ndarray) -> np.ndarray:
    """Number of grain-grain contacts of each grain."""
    pi, pj, _ = pair_gaps(pos, radius, CONTACT_GAP * radius.min())
    return np.bincount(np.concatenate([pi, pj]), minlength=len(radius))


def wall_gaps(pos: np.ndarray, radius: np.ndarray, width: float, height: float) -> np.ndarray:
    """Gap of each grain to the vessel's left, right, bottom and top walls, (n, 4) m."""
    return np.column_stack([pos[:, 0] - radius, width - pos[:, 0] - radius,
                            pos[:, 1] - radius, height - pos[:, 1] - radius])


def vessel_contacts(pos: np.ndarray, radius: np.ndarray, width: float, height: float) -> np.ndarray:
    """Contacts of each grain in the vessel: with grains and with the walls."""
    touching = wall_gaps(pos, radius, width, height) <= CONTACT_GAP * radius.min()
    return grain_contacts(pos, radius) + touching.sum(axis=1)


def floaters(pos: np.ndarray, radius: np.ndarray, width: float, height: float) -> np.ndarray:
    """True for the grains with fewer than MIN_CONTACTS contacts in the vessel, walls counted."""
    return vessel_contacts(pos, radius, width, height) < MIN_CONTACTS


def enlarge_floaters(pos: np.ndarray, radius: np.ndarray, width: float, height: float,
                     overlap: float) -> np.ndarray:
    """Radii with every floater (fewer than MIN_CONTACTS contacts in the vessel, walls counted)
    grown until it overlaps its MIN_CONTACTS-th nearest grain or wall by `overlap` x its radius,
    and the nearer ones more: the packing must then be cycled so that its neighbours make room
    (Potyondy & Cundall 2004 enlarge floaters, they do not delete them)."""
    radius = radius.copy()
    walls = wall_gaps(pos, radius, width, height)
    for k in np.flatnonzero(floaters(pos, radius, width, height)):
        gaps = np.hypot(*(pos - pos[k]).T) - radius - radius[k]
        gaps[k] = np.inf
        nearest = np.partition(np.concatenate([gaps, walls[k]]), MIN_CONTACTS - 1)
        radius[k] += max(0.0, nearest[MIN_CONTACTS - 1]) + overlap * radius[k]
    return radius


def check_given_up(genesis: str, grains: str, stress_mpa: float, pressure_mpa: float, left: int, n: int) -> None:
    """A packing its genesis (in words: "clumped", "3D") gave up on, its wall stress not within
    a factor PRESSURE_BAND of P_m or every one of its n `grains` a floater (`left` of them), is
    no material: an InputError naming `cloud_porosity`."""
    if left < n and pressure_mpa / PRESSURE_BAND < stress_mpa < PRESSURE_BAND * pressure_mpa:
        return
    raise InputError("cloud_porosity", f"the {genesis} genesis gave up: {left} of {n} {grains} have fewer than "
                                       f"{MIN_CONTACTS} contacts at a wall stress of {stress_mpa:.3g} MPa "
                                       f"(P_m {pressure_mpa:g} MPa): lower the cloud porosity, or make the "
                                       "specimen larger or R_min smaller")
