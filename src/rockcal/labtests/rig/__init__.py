"""The rig a lab test loads its specimen in: what holds it, what moves, what bears the load and
what reads the strains. A lab test is a short script over a specimen, a rig, a loading schedule
(`rockcal.labtests.loading`) and readings; the engine's walls, their indices and the unit
thickness of the 2D model live here and nowhere else in the lab tests.

- `Platens`: two frictionless platens closing on the specimen (UCS, confined compression,
  Brazilian); their load, closure and axial strain, the specimen's loaded area. A
  `BearingStrip` on each (Brazilian, `brazilian_loading = "strips"`) softens their contacts.
- `SideWalls`: the side walls, servo-controlled to a confining stress (confined compression);
  the seating at it, sigma3.
- `Jaws`: ISRM's curved jaws closing on a disk (Brazilian, `brazilian_loading = "isrm"`); their
  load and closure, as the platens'.
- `Pins`: the loading pin and the two supports of three-point bending; the load, the pin's
  displacement. Jaws and pins are rigid arcs of small driven disks (`arc`).
- `Grips`: rigid grips pulling a prism apart (direct tension); the pull, the strain between
  them, the loaded area.
- `Gauge`: the specimen's own axial and lateral strains, from the grains along its sides.

Every loading part (platens, jaws, pins, grips) is a `Loader`, which `loading.load_to_failure` drives.

This is the 2D rig: disks in a slab of unit thickness `THICKNESS_M`, so loads are N per metre of
thickness and an area is a width x THICKNESS_M. A 3D rig (spheres; a cylinder or cuboid
specimen) is a second implementation of the same names: `Loader`s whose `load()` is in N; the
platens' `area_m2` the specimen's cross-section (pi D^2 / 4 for a cylinder) and `thickness_m`
a Brazilian disk's length; side walls that confine on every lateral face (four walls, or a
servo-controlled cylindrical membrane); pins and supports that are cylinders across the beam's
breadth, and their contact load per breadth; a `Gauge` whose lateral strain is the mean of the
two lateral (or the diametral) strains.
"""

from __future__ import annotations

from typing import Protocol

from rockcal.dem.simulate import State
from rockcal.labtests.rig.gauge import Gauge
from rockcal.labtests.rig.grips import Grips
from rockcal.labtests.rig.jaws import Jaws
from rockcal.labtests.rig.pins import Pins
from rockcal.labtests.rig.platens import BearingStrip, Platens
from rockcal.labtests.rig.sides import SideWalls

__all__ = ["BearingStrip", "Gauge", "Grips", "Jaws", "Loader", "Pins", "Platens", "SideWalls"]


class Loader(Protocol):
    """What moves to load the specimen and bears the load: the engine `state` it is part of,
    the `rows` of particles along the loaded direction (a loading's ramp scales with them) and
    the `chunk` of steps between readings."""

    state: State
    rows: float
    chunk: int

    def move(self, factor: float) -> None:
        """Move at `factor` x the full loading speed."""

    def load(self) -> float:
        """The load borne, N per m of thickness (2D), compression or pull positive."""
