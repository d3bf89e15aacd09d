"""The specimen settings of a lab test's runs: resolution, size and genesis of the virtual
specimens and how the tests read them (a campaign file's [specimen] keys), with their 3D
defaults."""

from __future__ import annotations

from typing import Literal

import numbers

from pydantic import Field, field_validator, model_validator

from rockcal.materials.clump_templates import DEFAULT_SHAPE, GRAIN_SHAPES
from rockcal.specimens.genesis import Genesis
from rockcal.dem.simulate import CONTACT_STIFFNESS, DEFAULT_CONTACT_STIFFNESS
from rockcal.dem3d.laws import CONTACT_STIFFNESS as CONTACT_STIFFNESS_3D
from rockcal.specimens3d.genesis import DEFAULT_GENESIS_3D
from rockcal.labtests.brazilian import STRIP_MODULUS_GPA
from rockcal.labtests.kind import DIMENSIONS
from rockcal.labtests.ucs import DEFAULT_MAX_AXIAL_STRAIN, DEFAULT_STRAIN, POST_PEAK_FRACTION

MAX_PACKINGS = 100  # an upper bound on the packings of one specimen a campaign runs (work and memory)


# The specimen settings whose default differs in 3D: the 3D genesis' cloud porosity (2D's 0.09
# would overfill a vessel of spheres), PFC 5's contact stiffness, the 3D engine's only one, and
# the confined test's triaxial cell (2D has side walls alone).
DEFAULTS_3D = {"cloud_porosity": DEFAULT_GENESIS_3D.cloud_porosity, "contact_stiffness": CONTACT_STIFFNESS_3D,
               "confined_vessel": "cylinder"}


class SpecimenSettings(Genesis):
    """Resolution, size and genesis of the virtual specimens (UCS, Brazilian disk, notched
    beam: one genesis for all) and how the UCS test reads them (defaults: the source's; the
    genesis keys are `rockcal.specimens.genesis.Genesis`'s)."""

    rmin_mm: float = Field(0.25, gt=0, description="Smallest particle radius R_min, mm: the resolution.")
    radius_ratio: float = Field(1.65, ge=1, le=10, description="Largest / smallest radius; radii are uniform between.")
    seed: int = Field(1, ge=0, description="Packing seed; other packings (intervals, validation beams) take seed + 1, ...")
    width_mm: float = Field(50.0, gt=0, description="Width of the UCS, confined and direct tension specimens, mm "
                            "(in 3D the UCS and confined cylinders' diameter, the confined square prism's side).")
    height_mm: float = Field(100.0, gt=0, description="Height of the UCS, confined and direct tension specimens, mm.")
    beam_length_mm: float = Field(220.0, gt=0, description="Notched beam length, mm.")
    beam_height_mm: float = Field(50.0, gt=0, description="Notched beam depth W, mm.")
    notch_mm: float = Field(18.0, gt=0, description="Notch depth a, mm, from the beam's lower edge at mid-span.")
    notch_width_mm: float = Field(2.0, ge=0, description="Notch width, mm; 0 is a cut: the bonds across the notch line "
                                  "are removed (a sharp crack).")
    span_mm: float = Field(160.0, gt=0, description="Distance S between the beam's supports, mm.")
    # left out of a record at its default, as out of a run's key (`kind.LATER_SETTINGS`)
    beam_thickness_mm: float | None = Field(None, gt=0, exclude_if=lambda v: v is None,
                                            description="Notched beam thickness, mm, in 3D (default: eight of its "
                                                        "largest spheres across, 16 x R_min x radius_ratio); a 2D "
                                                        "beam is a slab of unit thickness.")
    disk_diameter_mm: float = Field(50.0, gt=0, description="Diameter of the Brazilian test's disk, mm.")
    # the semi-circular bend's (ISRM 2014), left out of a record at their defaults as LATER_SETTINGS are
    scb_radius_mm: float = Field(50.0, gt=0, exclude_if=lambda v: v == 50.0,
                                 description="Radius R of the semi-circular bend specimen, mm.")
    scb_notch_mm: float = Field(25.0, gt=0, exclude_if=lambda v: v == 25.0,
                                description="Notch length a of the semi-circular bend specimen, mm, up from the "
                                            "middle of its flat side: 0.4-0.6 R (ISRM).")
    scb_span_ratio: float = Field(0.8, gt=0, exclude_if=lambda v: v == 0.8,
                                  description="S/R of the semi-circular bend: each support S from the notch, "
                                              "0.5-0.8 (ISRM).")
    scb_notch_width_mm: float = Field(2.0, ge=0, exclude_if=lambda v: v == 2.0,
                                      description="Notch width of the semi-circular bend specimen, mm; 0 is a cut.")
    bending_seeds: int = Field(1, ge=1, le=MAX_PACKINGS, description="The validation K_IC is the mean over this many packings of the "
                               "beam (seed, seed + 1, ...).")
    strain: Literal["gauge", "platen"] = Field(DEFAULT_STRAIN, description="Axial strain of the UCS test read on the "
                                               "specimen's end particles (gauge) or from the platens (platen, PFC's).")
    stop_fraction: float = Field(POST_PEAK_FRACTION, gt=0, lt=1, description="UCS and bending runs stop once past "
                                 "the peak the load is below this fraction of it (PFC's ct_loadFac).")
    contact_stiffness: Literal[CONTACT_STIFFNESS] = Field(DEFAULT_CONTACT_STIFFNESS, description="A contact's kn "
                                                          "from E_c as PFC 3.x/4.0 (pfc4, 2D only: t E_c) or PFC 5+ "
                                                          "(pfc5: 2 min(R) t E_c / (R_A + R_B) in 2D, t = 1 m; "
                                                          "pi min(R)^2 E_c / (R_A + R_B) in 3D) computes it.")
    # left out of a record at its default, as out of a run's key (`kind.LATER_SETTINGS`)
    max_axial_strain: float = Field(DEFAULT_MAX_AXIAL_STRAIN, gt=0, le=0.5,
                                    exclude_if=lambda v: v == DEFAULT_MAX_AXIAL_STRAIN,
                                    description="UCS: stop at this axial strain at the latest.")
    brazilian_loading: Literal["flat", "isrm", "strips"] = Field(
        "flat", exclude_if=lambda v: v == "flat",
        description="Brazilian test: the disk between flat frictionless platens (flat, FISHTank's), ISRM's curved "
                    "jaws of radius 1.5 x the disk's radius (isrm) or the flat platens with a bearing strip on each, "
                    "plywood 0.01 D thick (strips, ASTM D3967's cushion).")
    strip_modulus_gpa: float = Field(
        STRIP_MODULUS_GPA, gt=0, le=100, exclude_if=lambda v: v == STRIP_MODULUS_GPA,
        description="Brazilian test between strips: the strips' modulus through their thickness, GPa (plywood's, "
                    "1; a softer cushion spreads the load over more rim grains).")
    grain_shape: Literal[GRAIN_SHAPES] = Field(
        DEFAULT_SHAPE, exclude_if=lambda v: v == DEFAULT_SHAPE,
        description="The grains: balls (ball) or rigid clumps of overlapping pebbles, randomly oriented "
                    "(two-pebble, three-pebble, cloud: four pebbles of random sizes; FISHTank's clumped materials, "
                    "PFC's clump templates), sized by the radius of a disk of their area; every 2D test "
                    "takes them (the direct tension test's grips hold a clump whole by its centroid).")
    dimensions: int = Field(
        2, exclude_if=lambda v: v == 2,
        description="2: PFC2D's disks; 3: PFC3D's spheres, the UCS and direct tension tests on a cylinder of "
                    "width_mm as diameter and height_mm tall, the confined test in a triaxial cell or on a square "
                    "prism (confined_vessel), the Brazilian test on a disk D x D/2, the notched beam "
                    "beam_thickness_mm thick; in 3D cloud_porosity is 0.35, contact_stiffness pfc5 and "
                    "confined_vessel cylinder unless given.")
    # in every record: a 3D record without it would read back as the cell
    confined_vessel: Literal["cylinder", "prism"] = Field(
        "prism",
        description="The 3D confined test's vessel: a cylinder of width_mm diameter packed in a cylindrical cell "
                    "whose wall is servo-controlled to sigma3 (cylinder, the lab's triaxial cell; 3D's default) or a "
                    "square prism between four servo side walls (prism, polyaxial); 2D's is prism alone.")

    @model_validator(mode="before")
    @classmethod
    def _defaults_in_3d(cls, data):
        """In 3D the settings not given take their 3D defaults (DEFAULTS_3D). `dimensions` must be
        a whole number: a string "3" would pass as 3 after the 3D defaults were passed over."""
        given = data.get("dimensions", 2) if isinstance(data, dict) else 2
        if isinstance(given, bool) or not isinstance(given, numbers.Real):
            raise ValueError(f"dimensions: must be the number 2 or 3 (dimensions = 3, no quotes), got {given!r}")
        if isinstance(data, dict) and data.get("dimensions") == 3:
            return DEFAULTS_3D | data
        return data

    @field_validator("dimensions")
    @classmethod
    def _dimensions(cls, dimensions):
        if dimensions not in DIMENSIONS:
            raise ValueError(f"must be 2 (PFC2D) or 3 (PFC3D), got {dimensions}")
        return dimensions
