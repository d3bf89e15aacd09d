"""Strain gauges on the specimen: its axial and lateral strains from the grains along its sides,
like gauges on a lab sample (`dem.measure.gauge_lengths`: the platen contacts' compliance does
not enter)."""

from __future__ import annotations

from rockcal.dem import measure
from rockcal.errors import InputError
from rockcal.dem.simulate import State
from rockcal.specimens.specimen import Specimen


def _sides(specimen: Specimen) -> dict:
    """The grains within half the smallest radius of each side of `specimen` (as made)."""
    return measure.boundary_sets(specimen.pos, specimen.radius, 0.5 * specimen.radius.min())


def check_gauges(specimen: Specimen) -> None:
    """Gauges can read `specimen`: no grain lies on two opposite sides (an InputError, before
    the test builds its engine state)."""
    width, height = measure.gauge_lengths(specimen.pos, _sides(specimen))
    if not (width > 0 and height > 0):
        raise InputError("specimen", f"it holds only {specimen.n_particles} grain(s), too few for gauges on "
                                     "its sides (a grain lies on two opposite sides): make more grains (a "
                                     "larger specimen, a smaller R_min or a lower cloud porosity)")


class Gauge:
    """Gauges on the grains within half the smallest radius of each side of `specimen` (as
    made), zeroed at the lengths they read in `state` now."""

    def __init__(self, specimen: Specimen, state: State):
        self.state = state
        check_gauges(specimen)
        self.sets = _sides(specimen)
        self.width0, self.height0 = measure.gauge_lengths(state.particles.pos, self.sets)

    def strains(self) -> tuple[float, float]:
        """The axial strain (shortening positive) and the lateral strain (extension positive)."""
        width, height = measure.gauge_lengths(self.state.particles.pos, self.sets)
        return (self.height0 - height) / self.height0, (width - self.width0) / self.width0
