"""A kind of lab test as a campaign runs it: its name, its responses, the specimen settings
its specimen is made from, and how the specimen is made and the test run.

Each test module declares its kind as `TEST`; `rockcal.labtests.registry` lists them.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Callable

import numpy as np

from rockcal.materials.clump_templates import DEFAULT_SHAPE
from rockcal.specimens.genesis import Genesis
from rockcal.specimens.grain_limit import expected_grains
from rockcal.specimens.packing import check_packing_pressure
from rockcal.specimens.specimen import packing_name
from rockcal.specimens3d.specimen import packing_name as packing_name_3d
from rockcal.dem3d.laws import CONTACT_STIFFNESS as CONTACT_STIFFNESS_3D
from rockcal.errors import InputError
from rockcal.materials import check_dimensions, material

GENESIS = tuple(Genesis.model_fields)  # install_gap, cloud_porosity, pressure_mpa
PACKING_SETTINGS = {"rmin_mm", "radius_ratio", "seed", *GENESIS}  # what a random packing is made of
# Settings added after runs were stored, with the value the engine had before them: a run's
# key names one only where it differs from that, so the runs stored before keep their keys.
LATER_SETTINGS = {"contact_stiffness": "pfc5", "max_axial_strain": 0.02, "brazilian_loading": "flat",
                  "grain_shape": DEFAULT_SHAPE, "dimensions": 2, "strip_modulus_gpa": 1.0,
                  "confined_vessel": "prism", "beam_thickness_mm": None}
# A specimen's dimensions: 2, PFC2D's disks, or 3, PFC3D's spheres (the tests with the setting
# `dimensions` alone, on a material the 3D engine has: `Material.states`).
DIMENSIONS = (2, 3)


# the tests with a 3D implementation, in words
TESTS_3D = ("ucs, brazilian, direct_tension, biaxial: confined (a triaxial cell, or a square prism in "
            "polyaxial walls), bending, scb")


def in_3d(s: dict) -> bool:
    """The settings `s` ask for a 3D specimen (PFC3D: `dimensions` 3)."""
    return s.get("dimensions", 2) == 3


def check_3d_settings(s: dict) -> None:
    """None of the 2D engine's settings alone in a 3D test's settings `s` (a grain shape with no
    3D template, PFC 4's contact stiffness) and R_min at least MIN_RMIN_MM, as in 2D; an
    InputError naming the setting."""
    from rockcal.materials.clump_templates_3d import GRAIN_SHAPES_3D

    check_rmin(s["rmin_mm"])
    if s.get("grain_shape", DEFAULT_SHAPE) not in GRAIN_SHAPES_3D:
        raise InputError("grain_shape", f"the 3D engine's grains are {', '.join(GRAIN_SHAPES_3D)}, got "
                                        f"{s['grain_shape']!r} with dimensions = 3")
    if s["contact_stiffness"] != CONTACT_STIFFNESS_3D:
        raise InputError("contact_stiffness", f"the 3D engine's contacts take PFC 5's stiffness "
                                              f"({CONTACT_STIFFNESS_3D!r}), got {s['contact_stiffness']!r} "
                                              "with dimensions = 3")


@dataclass(frozen=True)
class Response:
    """A response a test reports, its unit ("" when it has none), and whether a lab measures
    it too (a target a calibration can fit)."""

    name: str
    unit: str
    target: bool = True
    label: str = ""  # in words, for tables ("" : the name)


@dataclass(frozen=True)
class Setting:
    """A specimen setting a test brings with it (beyond those every campaign knows): its
    default and unit, `check(value)` raising an InputError that names it, and whether a command
    or a campaign may give a list of values (`series`): one run per value, in `check_series`'s
    order (which rejects an empty, unsorted or repeated list, naming the setting)."""

    name: str
    default: Any
    unit: str
    check: Callable[[Any], None]
    help: str
    series: bool = False
    check_series: Callable[[list], None] | None = None


@dataclass(frozen=True)
class SeriesFigure:
    """A figure of a series' runs together (the envelope through the peaks): its title, caption
    and `draw`, the `rockcal.plots` function of (runs, path, title) that draws it, runs being
    (responses, curve) in the series' order."""

    title: str
    caption: str
    draw: str
    min_runs: int = 1  # it needs this many runs (an envelope: two)

    def file(self, test: str) -> str:
        """Its PNG file's name for a test: biaxial_strength_envelope.png."""
        return f"{test}_{self.title.lower().replace(' ', '_')}.png"

    def heading(self, test_title: str) -> str:
        """Its title under a test's ("Confined compression: strength envelope"), the test's
        title said once ("Confined compression curves")."""
        if self.title.lower().startswith(test_title.lower()):
            return self.title
        return f"{test_title[0].upper()}{test_title[1:]}: {self.title.lower()}"


@dataclass(frozen=True)
class Outline:
    """A test's specimen as a plan sees it: in words, and the packing it is cut from (width and
    height, mm; in 3D its vessel's three sides) with the share of that packing's grains it keeps
    (in 3D: of a width x width x height cuboid's, as `plan.cost` counts them)."""

    text: str
    width_mm: float
    height_mm: float
    share: float = 1.0
    vessel_mm: tuple[float, float, float] | None = None  # a 3D packing's cuboid, x y z
    vessel_cylinder: bool = False  # the 3D packing fills the vertical cylinder inscribed in its cuboid

    @property
    def vessel_volume_mm3(self) -> float:
        """The 3D packing's vessel's volume, mm³."""
        return (np.pi / 4 if self.vessel_cylinder else 1.0) * float(np.prod(self.vessel_mm))


@dataclass(frozen=True)
class LabTest:
    """A kind of lab test. `settings` are the specimen settings a run depends on (in this
    order they key its stored run); from a dict of them, `check` rejects what no specimen can
    be made of (an InputError naming the setting) and `make` makes the specimen;
    `run(params, specimen, settings, progress)` runs the test and returns its result, which
    has each response as an attribute; `reading(x, y)` puts what `progress` gets into words;
    `outline(settings)` is the specimen's `Outline`; `title` names the test in a sentence.
    `revision` counts changes of the test's procedure within one engine version: a stored run
    of an earlier revision is not reused. `curve_columns` name the columns of its result's
    curve (a CSV's header). `own_settings` declare the settings among `settings` that only this
    test has (default, check, whether a list of them makes a series of runs); over a series,
    `combine(responses of each run, in order)` gives `combined_responses` (the envelope of
    confined compression tests) and `series_figures` draw the runs together."""

    name: str
    responses: tuple[Response, ...]
    settings: tuple[str, ...]
    check: Callable[[dict], None]
    make: Callable[[dict], Any]
    run: Callable[..., Any]
    reading: Callable[[float, float], str]
    outline: Callable[[dict], Outline]
    title: str  # the test's name in a sentence
    revision: int = 1
    lab_values: type | None = None  # its [targets.<name>] section (LabValues); None: made from `targets`
    # its run time over a UCS run's of the same work (grains x rows), with these specimen settings
    time_factor: Callable[[dict], float] = lambda settings: 1.0
    # whether its steps grow with its rows of grains (its loading speed set per row), with these
    # settings; where not, its steps are its pin's or platens' travel to the peak (`plan.cost`)
    steps_follow_rows: Callable[[dict], bool] = lambda settings: True
    curve_columns: tuple[str, ...] = ()  # the columns of its result's curve, with units
    plot: str | None = None  # the `rockcal.plots` function of (curve, path, title, rig) that draws it
    flags: tuple[tuple[str, str], ...] = ()  # (setting, its CLI flag's name) where they differ
    defaults: tuple[tuple[str, Any], ...] = ()  # (setting, its default for this test alone)
    # (setting, its help in this test's command) where the campaign key's, shared by tests, says other
    setting_help: tuple[tuple[str, str], ...] = ()
    hexagonal: Callable[[dict], Any] | None = None  # its specimen as a hexagonal lattice, if it has one
    help: str = ""  # what `rockcal simulate <name>` does, in a line
    own_settings: tuple[Setting, ...] = ()  # settings it brings beyond the campaign file's [specimen]
    combine: Callable[[list[dict]], dict] | None = None  # one response set from a series' runs
    combined_responses: tuple[Response, ...] = ()  # what `combine` gives
    series_figures: tuple[SeriesFigure, ...] = ()  # figures of a series' runs together
    strength: str = ""  # the response that is its strength (a crack figure's title); "": the first
    # what a 3D run reports otherwise (a load in kN, not kN per m of thickness): (field, its
    # value in 3D) pairs, such as `responses`, `curve_columns`, `reading`, `revision`, that
    # `of_dimensions(3)` takes
    changes_3d: tuple[tuple[str, Any], ...] = ()

    def __post_init__(self):
        if self.lab_values is not None:
            self.lab_values.kind = self  # its section reads its targets here, not by name

    def of_dimensions(self, dimensions: int) -> LabTest:
        """The test as a run in `dimensions` reports it: with `changes_3d` in 3D (its campaign
        file section, `lab_values`, stays this test's: one for both)."""
        if dimensions != 3 or not self.changes_3d:
            return self
        return replace(self, **dict(self.changes_3d), changes_3d=(), lab_values=None)

    @property
    def strength_response(self) -> Response:
        """The response that is its strength (`strength`, or the first)."""
        return next((r for r in self.responses if r.name == self.strength), self.responses[0])

    @property
    def series(self) -> Setting | None:
        """Its setting a list of values of which makes a series of runs, if it has one."""
        return next((s for s in self.own_settings if s.series), None)

    def point_responses(self, runs: list[dict], values: list) -> dict:
        """The responses of one parameter set from its runs: the targets of its one run, or
        (a series, one run per value of `values`) what `combine` gives, each list of a
        target response spread out by value (`series_name`)."""
        if not values:
            return {r: runs[0][r] for r in self.targets}
        unit = self.series.unit
        found = {}
        for name, value in self.combine(runs).items():
            if not isinstance(value, list):
                found[name] = value
            elif name in self.targets:
                found |= {series_name(name, v, unit): x for v, x in zip(values, value)}
        return found

    def check_dimensions(self, dimensions: int, model: str) -> None:
        """InputError when the test cannot run in `dimensions` on the material `model`: naming
        the test (`name`) where it has no 3D implementation, `model` where the 3D engine has
        no such material."""
        if dimensions != 3:  # 2, or a value the setting's own check refuses
            return
        if "dimensions" not in self.settings:
            raise InputError(self.name, f"no 3D implementation yet (3D has {TESTS_3D})")
        check_dimensions(material(model), dimensions)

    @property
    def targets(self) -> tuple[str, ...]:
        """The responses a lab measures too."""
        return tuple(r.name for r in self.responses if r.target)

    def settings_of(self, specimen_settings) -> dict:
        """This test's settings, in their order, from an object that has them as attributes (a
        setting of its own that the object lacks at its default, a LATER_SETTINGS one at the
        value it had before it existed)."""
        missing = LATER_SETTINGS | {s.name: s.default for s in self.own_settings}
        return {name: getattr(specimen_settings, name, missing.get(name)) for name in self.settings}

    def key_settings(self, specimen_settings) -> dict:
        """The settings that key a stored run: `settings_of` less LATER_SETTINGS at their old
        values (`all_settings` puts them back)."""
        return {name: value for name, value in self.settings_of(specimen_settings).items()
                if not (name in LATER_SETTINGS and value == LATER_SETTINGS[name])}

    def packing(self, specimen_settings) -> dict:
        """The random packing this test's specimen is cut from, as `random_packing`'s arguments:
        its outline's box, grains, seed, genesis and grain shape (balls for a test without the
        `grain_shape` setting)."""
        s = self.settings_of(specimen_settings)
        box = self.outline(s)
        return dict(width_mm=box.width_mm, height_mm=box.height_mm, rmin_mm=s["rmin_mm"],
                    radius_ratio=s["radius_ratio"], seed=s["seed"], genesis=genesis_of(s),
                    grain_shape=s.get("grain_shape", DEFAULT_SHAPE))

    def packing_file(self, specimen_settings) -> str | None:
        """The file name (in the specimen cache) of the random packing this test's specimen is
        cut from, 2D or 3D; None for a test whose settings make no such packing."""
        if not PACKING_SETTINGS <= set(self.settings):
            return None
        p = self.packing(specimen_settings)
        outline = self.outline(self.settings_of(specimen_settings))
        if outline.vessel_mm is None:
            return packing_name(**p)
        return packing_name_3d(tuple(1e-3 * v for v in outline.vessel_mm), 1e-3 * p["rmin_mm"], p["radius_ratio"],
                               p["seed"], p["genesis"], outline.vessel_cylinder, p["grain_shape"])

    def responses_of(self, result) -> dict:
        """The declared responses of a test's result, in their declared order."""
        return {r.name: getattr(result, r.name) for r in self.responses}


def series_name(response: str, value: float, unit: str) -> str:
    """A response of one run of a series, by its value: sigma1_MPa@5MPa."""
    return f"{response}@{value:g}{unit}"


# The smallest grain a specimen may have, 1 µm: the finest mineral grains of a rock (clay); a
# finer R_min is no rock's grain, and (below 1e-154 mm) its area is no number.
MIN_RMIN_MM = 1e-3
# The fewest grains a specimen's cloud may hold: 4 x 4, a specimen 4 grains across as its size
# must be (`specimens.specimen.check_geometry`); a cloud porosity near 1 leaves fewer (1 or 2 grains:
# no gauge, platen or pin has a grain to read or load).
MIN_GRAINS = 16


def check_rmin(rmin_mm: float) -> None:
    """R_min at least MIN_RMIN_MM; an InputError naming it."""
    if not rmin_mm >= MIN_RMIN_MM:
        raise InputError("rmin_mm", f"must be at least {MIN_RMIN_MM:g} mm (1 µm, the finest mineral "
                                    f"grains), got {rmin_mm:g}")


def check_grain_cloud(width_mm: float, height_mm: float, s: dict) -> None:
    """The grains of a test's packing (width x height mm, the settings `s`): R_min at least
    MIN_RMIN_MM, and the grain cloud at least MIN_GRAINS grains; before the genesis."""
    check_rmin(s["rmin_mm"])
    if s.get("grain_shape", DEFAULT_SHAPE) != DEFAULT_SHAPE:
        check_packing_pressure(s["pressure_mpa"], f"{s['grain_shape']} clumps")
    grains = expected_grains(width_mm, height_mm, s["rmin_mm"], s["radius_ratio"], s["cloud_porosity"])
    if grains < MIN_GRAINS:
        raise InputError("cloud_porosity", f"a cloud porosity of {s['cloud_porosity']:.10g} leaves about "
                                           f"{grains:.3g} grains in the {width_mm:g} x {height_mm:g} mm packing, "
                                           f"fewer than {MIN_GRAINS} (4 grains across): lower it, or make the "
                                           "specimen larger or R_min smaller")


def genesis_of(settings: dict) -> Genesis:
    """The genesis part of a test's specimen settings."""
    return Genesis(**{name: settings[name] for name in GENESIS})


def load_reading(unit: str) -> Callable[[float, float], str]:
    """A running load-displacement test's reading in words, its load in `unit` (kN/m, kN)."""
    return lambda displacement_mm, load: f"{displacement_mm:.3f} mm, {load:.2f} {unit}"


def all_settings(key_settings: dict) -> dict:
    """A stored run's settings with LATER_SETTINGS its key leaves out."""
    return LATER_SETTINGS | key_settings
