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
  load and closure, as the platens'. In 3D (`jaws_3d`) they are drawn out along the disk's axis.
- `Pins`: the loading pin and the two supports of three-point bending; the load, each
  support's reaction, the pin's displacement. Jaws and pins are rigid arcs of small driven
  disks (`arc`); the 3D pins (`pins_3d`) are cylinders along the specimen's thickness, rows
  of those arcs' spheres.
- `Grips`: rigid grips pulling a prism apart (direct tension); the pull, the strain between
  them, the loaded area. In 3D (`grips_3d`) they grip a cylinder's ends.
- `Gauge`: the specimen's own axial and lateral strains, from the grains along its sides.

Every loading part (platens, jaws, pins, grips) is a `Loader`, which `loading.load_to_failure` drives.

The 2D rig holds disks in a slab of unit thickness `THICKNESS_M`, so loads are N per metre of
thickness and an area is a width x THICKNESS_M. The 3D rig (`platens_3d`, `sides_3d`,
`gauge_3d`) holds spheres: its `Loader`s' `load()` is in N, its platens' `area_m2` the
specimen's cross-section (pi D^2 / 4 for a cylinder) and `thickness_m` a Brazilian disk's
length; its confining vessel is four side walls about a prism (polyaxial) or a cylindrical
wall about a cylinder (the triaxial cell, `cell_3d`); its gauge's lateral strain is the mean of
the two widths' (or the diametral) strain. `rig_for(specimen)` gives the parts
of the specimen's dimension (`Rig`), so a lab test is one procedure in 2D and 3D.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Protocol

from rockcal.engine import ModelState
from rockcal.labtests.rig.gauge import Gauge, check_gauges
from rockcal.labtests.rig.grips import Grips
from rockcal.labtests.rig.jaws import Jaws
from rockcal.labtests.rig.pins import Pins
from rockcal.labtests.rig.platens import BearingStrip, Disk, Platens, disk_of
from rockcal.labtests.rig.sides import SideWalls

__all__ = ["BearingStrip", "Disk", "Gauge", "Grips", "Jaws", "Loader", "Pins", "Platens", "Rig", "SideWalls", "rig_for"]


class Loader(Protocol):
    """What moves to load the specimen and bears the load: the engine `state` it is part of,
    the `rows` of particles along the loaded direction (a loading's ramp scales with them) and
    the `chunk` of steps between readings."""

    state: ModelState
    rows: float
    chunk: int

    def move(self, factor: float) -> None:
        """Move at `factor` x the full loading speed."""

    def load(self) -> float:
        """The load borne, compression or pull positive: N per m of thickness (2D), N (3D)."""


@dataclass(frozen=True)
class Rig:
    """The rig's parts of one dimension, each built as the 2D one is:
    `platens(specimen, params, rate_factor, contact_stiffness, strip, side_walls)` (a
    `Loader` with `area_m2`, `thickness_m`, `strain()`, `closure_m()`, `zero()`), `side_walls(platens,
    specimen, target_Pa)`, `gauge(specimen, state)` and `check_gauges(specimen)`;
    `lateral_strains`, the lateral strains a volumetric strain takes (2D's areal strain one, a
    3D specimen's two); `disk(specimen)` a Brazilian disk's `Disk`; `load_unit`, the unit of a
    loader's load / 1000 (kN per m of the 2D slab's thickness, kN in 3D); `jaws` ISRM's curved
    jaws; `pins(specimen, params, pin_x_m, support_x_m, radius_m,
    step_m, contact_stiffness)` three-point bending's pin and supports (a `Loader`);
    `grips(specimen, params, grip_fraction, rate_factor, contact_stiffness)` direct tension's
    grips (a `Loader` with `area_m2`, `strain()`, `free_length_m`)."""

    dimensions: int
    platens: Callable
    side_walls: Callable
    gauge: Callable
    check_gauges: Callable
    lateral_strains: int
    disk: Callable
    load_unit: str
    jaws: Callable
    pins: Callable
    grips: Callable


def rig_for(specimen) -> Rig:
    """The rig of the specimen's dimension (`specimen.dimensions`)."""
    if specimen.dimensions == 2:
        return Rig(2, Platens, SideWalls, Gauge, check_gauges, lateral_strains=1, disk=disk_of,
                   load_unit="kN/m", jaws=Jaws, pins=Pins, grips=Grips)
    # the 3D rig, and with it the 3D engine's kernels: loaded for a 3D run alone
    from rockcal.labtests.rig.gauge_3d import Gauge3D
    from rockcal.labtests.rig.gauge_3d import check_gauges as check_gauges_3d
    from rockcal.labtests.rig.grips_3d import Grips3D
    from rockcal.labtests.rig.jaws_3d import Jaws3D
    from rockcal.labtests.rig.pins_3d import Pins3D
    from rockcal.labtests.rig.platens_3d import Platens3D
    from rockcal.labtests.rig.platens_3d import disk_of as disk_of_3d
    from rockcal.labtests.rig.cell_3d import confining_walls

    return Rig(3, Platens3D, confining_walls, Gauge3D, check_gauges_3d, lateral_strains=2, disk=disk_of_3d,
               load_unit="kN", jaws=Jaws3D, pins=Pins3D, grips=Grips3D)
