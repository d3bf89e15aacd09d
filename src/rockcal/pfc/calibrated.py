"""What the PFC writers take (`Calibrated`): the identified material, its specimen settings,
where it came from (for the files' headers) and the FISHTank targeted, by PFC version."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from rockcal.materials.fishtank import DEFAULT_FISHTANK, fishtank_version

if TYPE_CHECKING:  # the campaign's settings; the writers read only their attributes
    from rockcal.labtests.specimen_settings import SpecimenSettings


@dataclass(frozen=True)
class Calibrated:
    """What a finished campaign identified: the material, its specimen settings and where it
    came from (for the export's header); and the FISHTank the export targets, by PFC version."""

    params: object  # of its material (`rockcal.materials`)
    specimen: SpecimenSettings
    origin: dict
    fishtank: int = DEFAULT_FISHTANK


def for_fishtank(calibrated: Calibrated, version, field: str = "--fishtank") -> Calibrated:
    """The calibration exported for the FISHTank of PFC `version` (5, 6 or 7); InputError
    naming `field` for another."""
    return replace(calibrated, fishtank=fishtank_version(version, field))


def fishtank_of(calibrated) -> int:
    """The FISHTank version a calibration targets; the default for a record without one."""
    return getattr(calibrated, "fishtank", DEFAULT_FISHTANK)


def in_3d(calibrated) -> bool:
    """A calibration of PFC3D's spheres (`[specimen] dimensions = 3`)."""
    return calibrated.specimen.dimensions == 3
