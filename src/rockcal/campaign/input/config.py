"""The campaign file (TOML): a rock's lab targets and how to calibrate against them.

Validated with pydantic; unknown keys, missing targets and inverted bounds are errors that name
the key. With no file, the embedded granite default (`granite.toml`, the lab data of the
source study) is used.
"""

from __future__ import annotations

import functools
import itertools
import math
import tomllib
from importlib import resources
from pathlib import Path
from typing import Literal

import numpy as np
from pydantic import Field, PrivateAttr, ValidationError, field_validator, model_validator

from rockcal.campaign.input.raw_values import check_numbers
from rockcal.campaign.outputs.safe_text import unsafe_character
from rockcal.campaign.input.targets import LabTargets, Section, Targets, ValidationTests
from rockcal.labtests.lab_values import read_curve  # noqa: F401  (here too)
from rockcal.labtests.ucs import UCSValues as UCSTargets  # noqa: F401  (the UCS section, here too)
from rockcal.labtests.specimen_settings import MAX_PACKINGS, SpecimenSettings
from rockcal.user_files import read_user_text
from rockcal.specimens.genesis import make_genesis
from rockcal.errors import InputError, fields_named, from_validation_error
from rockcal.inverse.arrays import design
from rockcal.inverse.identifiability import PINNED_WITHIN
from rockcal.labtests.registry import LAB_TESTS, PRIMARY_TEST, lab_test
from rockcal.materials import DEFAULT_MATERIAL, MATERIALS, material, parameters

RESPONSES = lab_test(PRIMARY_TEST).targets  # what the primary (UCS) test gives and the calibration can fit
# Upper bounds on the numbers that decide work or memory. A surrogate solves a dense system of
# its runs (MAX_DEM_RUNS runs: 200 MB); a search evaluates it ants x iterations times, in
# batches of `ants` points (MAX_EVALUATIONS: seconds to a minute per search); MAX_PACKINGS is
# `labtests.specimen_settings`'.
MAX_DEM_RUNS = 5000
MAX_ANTS = 10_000
MAX_EVALUATIONS = 1_000_000
MAX_DRAWS = 10_000
# The Latin hypercube's centred-discrepancy improvement grows with the square of its points
# (1,000: about 2 s; 5,000: 12 s, each time a campaign is planned), and an RBF surrogate of a
# few parameters gains nothing from more runs than this
MAX_SAMPLES = 1000
# The searches the main process makes on the surrogate, beside no DEM run the first screen
# counts: the intervals' draws x ants x iterations, a verification round's candidates x ants x
# iterations (x2: the searches tried per candidate); at ~8 us an evaluation, 50 million are
# about 7 min (the defaults: 2 million)
MAX_SEARCH_EVALUATIONS = 50_000_000
# DEM runs a campaign may ask for at most: its budget of parameter sets x each set's runs (every
# test's series x its packings). Planning lists each run (six times, ~0.05 ms each: seconds),
# and 20,000 runs of even a small specimen are days on a few cores
MAX_CAMPAIGN_RUNS = 20_000


class Rock(Section):
    """The rock: its name (the output folder's and the report's) and density."""

    name: str = Field("rock", min_length=1, max_length=200, description="Names the default output folder (runs/NAME) and the report.")
    density_kg_m3: float = Field(2622.0, gt=0, description="Density of the rock, kg/m³ (the particles' density).")

    @field_validator("name")
    @classmethod
    def _printable(cls, name):
        bad = unsafe_character(name)
        if bad is not None:
            raise ValueError(f"a rock name is one line of text; {name!r} holds {bad}")
        return name


NAMES = tuple(dict.fromkeys(name for m in MATERIALS.values() for name in m.parameters))
# genesis settings a campaign may search (in [search] bounds or [sensitivity] levels) beside the
# micro-parameters: the installation gap only decides which pairs of the packed grains bond
SEARCHED_GENESIS = ("install_gap",)


def _check_names(values: dict, genesis: bool = True) -> None:
    """Names of some material's parameters (`_check_values` checks them against the chosen one),
    or of a searched genesis setting."""
    known = (*NAMES, *SEARCHED_GENESIS) if genesis else NAMES
    for name in values:
        if name in SEARCHED_GENESIS and not genesis:
            raise ValueError(f"{name}: a genesis setting; set it in [specimen], or search it in [search] bounds")
        if name not in known:
            raise ValueError(f"{name}: unknown parameter; known: {', '.join(known)}")


def split_genesis(values: dict) -> tuple[dict, dict]:
    """A parameter set's micro-parameters, and the genesis settings searched among them."""
    return ({k: v for k, v in values.items() if k not in SEARCHED_GENESIS},
            {k: v for k, v in values.items() if k in SEARCHED_GENESIS})


class SensitivitySettings(Section):
    """Sensitivity runs on an orthogonal array and their range analysis: which parameter
    drives which response (optional when [search] bounds name the parameters to invert)."""

    array: str = Field("L16(4^5)", description="Orthogonal array: L4(2^3), L8(2^7), L9(3^4), L16(4^5), L18(2^1 3^7), "
                       "L25(5^6) or L27(3^13).")
    levels: dict[str, list[float]] = Field(description="The level values of each factor (micro-parameter), "
                                           "as many as the array's levels.")
    threshold: float | None = Field(None, gt=0, le=1, description="Also invert every factor whose range R is at "
                                    "least this fraction of the largest R of a response.")
    rmin_mm: float | None = Field(None, gt=0, description="R_min of the sensitivity runs, mm (default: the "
                                  "specimen's); coarser grains rank the factors alike in a fraction of the time.")

    @field_validator("levels")
    @classmethod
    def _levels(cls, levels):
        _check_names(levels)
        for name, values in levels.items():
            if len(values) < 2 or len(set(values)) != len(values):
                raise ValueError(f"{name}: needs at least 2 distinct values")
        return levels


class Search(Section):
    """The parameters to invert and their box; the others held fixed."""

    bounds: dict[str, tuple[float, float]] = Field({}, description="[low, high] of each parameter to invert; "
                                                   "may name install_gap (a fraction of R_min, as in [specimen]); "
                                                   "a whole number's (fj_nr) are whole, and its runs round it.")
    fixed: dict[str, float] = Field({}, description="Values of parameters held constant (others keep rockcal's "
                                    "defaults, the source study's granite).")

    @field_validator("bounds")
    @classmethod
    def _bounds(cls, bounds):
        _check_names(bounds)
        for name, (low, high) in bounds.items():
            if not (math.isfinite(low) and math.isfinite(high) and low < high):
                raise ValueError(f"{name}: lower bound must be below the upper, got [{low}, {high}]")
        return bounds

    @field_validator("fixed")
    @classmethod
    def _fixed(cls, fixed):
        _check_names(fixed, genesis=False)
        return fixed


class Surrogate(Section):
    """The Latin hypercube runs the RBF surrogate is fitted on, and its check runs."""

    samples: int = Field(30, ge=4, le=MAX_SAMPLES, description="Latin hypercube DEM runs in the search box "
                         "(at least the searched parameters + 2, the surrogate's fewest).")
    checks: int = Field(3, ge=1, le=MAX_DEM_RUNS, description="Fresh random DEM runs that check the surrogate.")
    tolerance: float = Field(0.05, gt=0, description="The surrogate is trusted when every check is within this "
                             "relative error.")
    seed: int = Field(1, ge=0, description="Seed of the Latin hypercube and the check points.")
    coarse_samples: int = Field(0, ge=0, le=MAX_SAMPLES, description="Multi-fidelity: Latin hypercube runs at coarse resolution "
                                "(R_min x coarse_factor) that train a low-fidelity surrogate, which the samples "
                                "correct; 0: none.")
    coarse_factor: float = Field(2.0, gt=1, le=4, description="R_min of the coarse samples over the campaign's "
                                 "(2: about 1/8 of a run's work).")
    samples_every_test: int | None = Field(None, ge=2, le=MAX_DEM_RUNS, description="Multi-fidelity: of the samples, "
                                           "how many run every test calibrated against (the others run the UCS "
                                           "test alone); default: all.")

    @model_validator(mode="after")
    def _every_test(self):
        n = self.samples_every_test
        if n is not None and not self.coarse_samples:
            raise ValueError("samples_every_test: needs coarse_samples (the coarse runs train every response)")
        if n is not None and n > self.samples:
            raise ValueError(f"samples_every_test: at most samples ({self.samples}), got {n}")
        return self


class Optimizer(Section):
    """Ant colony optimisation on the surrogate."""

    method: Literal["aco", "ant-system", "acor"] = Field("aco", description="The source's Ant System (aco = "
                                                         "ant-system) or ACO_R (acor; alpha, beta and rho do not "
                                                         "apply to it).")
    ants: int = Field(50, ge=2, le=MAX_ANTS, description="Ants per iteration.")
    iterations: int = Field(200, ge=1, le=MAX_EVALUATIONS, description="Iterations of the colony.")
    alpha: float = Field(1.0, ge=0, description="Ant System: weight of the pheromone.")
    beta: float = Field(5.0, ge=0, description="Ant System: weight of the heuristic desirability.")
    rho: float = Field(0.5, gt=0, le=1, description="Ant System: evaporation rate of the pheromone.")
    seed: int = Field(1, ge=0, description="Seed of the search.")

    @model_validator(mode="after")
    def _evaluations(self):
        if self.ants * self.iterations > MAX_EVALUATIONS:
            raise ValueError(f"iterations: ants x iterations = {self.ants * self.iterations:,} surrogate "
                             f"evaluations per search; at most {MAX_EVALUATIONS:,}")
        return self


class Acceptance(Section):
    """When a verified point is accepted, and the budget of DEM runs."""

    tolerance: float = Field(0.05, gt=0, lt=1, description="Accept a point when every response is within this "
                             "relative error of the lab's.")
    max_dem_runs: int = Field(80, ge=1, le=MAX_DEM_RUNS, description="Budget of parameter sets run in the DEM (UCS runs).")
    # set here, not by --workers, so that the workers never change the result
    candidates: int = Field(2, ge=1, le=MAX_DEM_RUNS, description="Distinct optima of the surrogate verified at once per loop "
                            "round.")
    ucs_first: bool = Field(False, description="Verify a point's UCS test first and run its other tests only "
                            "where the UCS responses meet the tolerance (on where those tests are dear).")


class UncertaintySettings(Section):
    """Intervals of the identified parameters (Monte Carlo on the surrogate)."""

    enabled: bool | None = Field(None, description="Default: on when a calibration target gives a spread.")
    draws: int = Field(200, ge=10, le=MAX_DRAWS, description="Target sets drawn from the lab's spread, each solved on the "
                       "surrogate.")
    packings: int = Field(3, ge=1, le=MAX_PACKINGS, description="UCS packings run at the identified point for the model's own "
                          "scatter (the first is the verified run).")
    seed: int = Field(1, ge=0, description="Seed of the draws.")


class IdentifiabilitySettings(Section):
    """Which parameters the lab sheet pins, and which lab test it lacks would pin the others."""

    pinned_within: float = Field(PINNED_WITHIN, gt=0, description="A searched parameter is pinned by the sheet "
                                 "when the value found lies within this relative error of every point of its range "
                                 "over the points that meet every target (within the tolerance, or the lab's spread "
                                 "where wider): the range holds the truth, so the value found lies that near it.")
    pinned_share: float = Field(1.0, gt=0, le=1, description="A further condition: a pinned parameter's range spans "
                                "at most this share of its search box (default 1: none).")
    runs: bool = Field(True, description="Read the loosest range not pinned in the DEM (the calibrated tests at "
                       "its two ends) and run the lab tests the sheet lacks there, to name the test that would pin "
                       "it.")
    tests: list[str] | None = Field(None, description="The lab tests the ranking runs at the ends, whatever "
                                    "they cost (\"ucs\": the CI and CD of its runs there). Default: CI and CD, and "
                                    "each test [targets] lacks whose two runs take at most a UCS run's time on a "
                                    "packing rockcal ships.")

    @field_validator("tests")
    @classmethod
    def _tests(cls, tests):
        for name in tests or []:
            if name not in LAB_TESTS:
                raise ValueError(f"no lab test named {name!r}; known: {', '.join(LAB_TESTS)}")
        return tests


class MaterialChoice(Section):
    """[material]: the bonded material the campaign calibrates (`rockcal.materials`)."""

    model: str = Field(DEFAULT_MATERIAL, description="The bonded material: " + ", ".join(MATERIALS) + ".")

    @field_validator("model")
    @classmethod
    def _known(cls, model):
        if model not in MATERIALS:
            raise ValueError(f"no material named {model!r}; known: {', '.join(MATERIALS)}")
        return model


class Campaign(Section):
    """A whole calibration campaign, as read from its TOML file (`plan.planned` sets the
    defaults its file leaves open from its runs' cost: `plan.route`)."""

    _route: object = PrivateAttr(None)  # `plan.route.Route`, when the defaults were changed

    rock: Rock = Rock()
    material: MaterialChoice = MaterialChoice()
    targets: Targets
    specimen: SpecimenSettings = SpecimenSettings()
    sensitivity: SensitivitySettings | None = None
    search: Search = Search()
    surrogate: Surrogate = Surrogate()
    optimizer: Optimizer = Optimizer()
    acceptance: Acceptance = Acceptance()
    uncertainty: UncertaintySettings = UncertaintySettings()
    identifiability: IdentifiabilitySettings = IdentifiabilitySettings()
    validation: ValidationTests = ValidationTests()

    @model_validator(mode="after")
    def _consistent(self):
        if not self.targets.ucs.scalars():
            raise ValueError("targets.ucs: give at least one of E_GPa, nu, ucs_MPa")
        if self.sensitivity is None and not self.search.bounds:
            raise ValueError("search.bounds: name the parameters to invert (or add [sensitivity])")
        both = set(self.search.bounds) & set(self.search.fixed)
        if both:
            raise ValueError(f"search.fixed: {sorted(both)[0]!r} is also in search.bounds")
        _check_budget(self)
        _check_enough_samples(self)
        _check_search_work(self)
        _check_campaign_runs(self)
        _check_dimensions(self)
        given = self.targets.given()
        if "tests" in self.validation.model_fields_set:
            for test in self.validation.tests:
                if test not in given:
                    raise ValueError(f"validation.tests: {test} has no [targets.{test}] to check against")
        for test in self.validation_tests():
            for key in ("spread", "weights"):
                if getattr(given[test], key):
                    raise ValueError(f"targets.{test}.{key}: {test} is a validation check only "
                                     "([validation] tests), not fitted")
        return self

    def wants_uncertainty(self) -> bool:
        u = self.uncertainty.enabled
        return any(s.spread for s in self.target_sections().values()) if u is None else u

    def target_sections(self) -> dict[str, LabTargets]:
        """The lab tests calibrated against, by name, with their targets: UCS, and each other
        test given in [targets] that [validation] does not name."""
        return {t: s for t, s in self.targets.given().items() if t not in self.validation.tests}

    def validation_tests(self) -> list[str]:
        """The tests given in [targets] that are validation checks only."""
        return [t for t in self.targets.given() if t in self.validation.tests]

    def tests(self) -> list[str]:
        """The lab tests the campaign runs: those given in [targets]."""
        return list(self.targets.given())

    def sensitivity_specimen(self) -> SpecimenSettings:
        """The specimen settings of the sensitivity runs: the campaign's, at [sensitivity]
        rmin_mm if given (the range analysis ranks the factors alike on coarser grains)."""
        rmin = self.sensitivity.rmin_mm if self.sensitivity else None
        return self.specimen if rmin is None else self.specimen.model_copy(update={"rmin_mm": rmin})

    def coarse_specimen(self) -> SpecimenSettings:
        """The specimen settings of the coarse samples: R_min x [surrogate] coarse_factor."""
        return self.specimen.model_copy(update={"rmin_mm": self.surrogate.coarse_factor * self.specimen.rmin_mm})

    def fixed_params(self) -> dict[str, float]:
        """Parameters held constant: the density of the rock, then [search].fixed."""
        return {"density": self.rock.density_kg_m3} | dict(self.search.fixed)


def _check_budget(campaign: Campaign) -> None:
    """The DEM runs the file asks for before any search fit in [acceptance] max_dem_runs."""
    s, budget = campaign.surrogate, campaign.acceptance.max_dem_runs
    if s.samples + s.checks > budget:
        raise ValueError(f"surrogate.samples: {s.samples} samples and {s.checks} checks are more DEM runs than "
                         f"the budget of {budget} (acceptance.max_dem_runs)")


def _check_enough_samples(campaign: Campaign) -> None:
    """The runs a surrogate of the searched parameters is fitted on (d + 2: the samples, or
    with coarse samples those, which the samples only correct), with the sensitivity runs that
    may be reused, are enough: a campaign does not stop after its samples' DEM runs."""
    searched, s = len(campaign.search.bounds), campaign.surrogate
    key, runs = ("coarse_samples", s.coarse_samples) if s.coarse_samples else ("samples", s.samples)
    if searched and runs + _reusable_runs(campaign) < searched + 2:
        raise ValueError(f"surrogate.{key}: {runs} {key.replace('_', ' ')} are too few for a surrogate of {searched} searched "
                         f"parameters (search.bounds); at least {searched + 2}")


def _reusable_runs(campaign: Campaign) -> int:
    """The sensitivity runs that may be runs of the search (those at the campaign's R_min)."""
    sensitivity = campaign.sensitivity
    if sensitivity is None or sensitivity.rmin_mm not in (None, campaign.specimen.rmin_mm):
        return 0
    try:
        return len(next(iter(design(sensitivity.array, sensitivity.levels).values())))
    except (InputError, StopIteration):
        return 0  # a bad array is named by `_check_values`


def _check_search_work(campaign: Campaign) -> None:
    """The searches on the surrogate beside the DEM runs fit in MAX_SEARCH_EVALUATIONS: the
    intervals' and a verification round's."""
    per_search = campaign.optimizer.ants * campaign.optimizer.iterations
    draws, candidates = campaign.uncertainty.draws, campaign.acceptance.candidates
    if campaign.wants_uncertainty() and draws * per_search > MAX_SEARCH_EVALUATIONS:
        raise ValueError(f"uncertainty.draws: {draws:,} draws x {per_search:,} evaluations a search "
                         f"(optimizer.ants x optimizer.iterations) = {draws * per_search:,}; at most "
                         f"{MAX_SEARCH_EVALUATIONS:,} (fewer draws, ants or iterations)")
    if 2 * candidates * per_search > MAX_SEARCH_EVALUATIONS:
        raise ValueError(f"acceptance.candidates: {candidates:,} candidates x 2 searches x {per_search:,} "
                         f"evaluations a search (optimizer.ants x optimizer.iterations) = "
                         f"{2 * candidates * per_search:,} a round; at most {MAX_SEARCH_EVALUATIONS:,}")


def _check_campaign_runs(campaign: Campaign) -> None:
    """[acceptance] max_dem_runs parameter sets and, for the intervals, [uncertainty] packings
    more, each run by every calibrated test over its series and its packings, are at most
    MAX_CAMPAIGN_RUNS DEM runs."""
    per_set = sum(max(1, len(section.series())) * section.packings for section in campaign.target_sections().values())
    budget = campaign.acceptance.max_dem_runs
    packings = campaign.uncertainty.packings if campaign.wants_uncertainty() else 0
    each = f"x {per_set:,} DEM runs each (the tests' series x their packings)"
    if budget * per_set > MAX_CAMPAIGN_RUNS:
        raise ValueError(f"acceptance.max_dem_runs: {budget:,} parameter sets {each} = {budget * per_set:,} runs; "
                         f"at most {MAX_CAMPAIGN_RUNS:,} (a smaller budget, fewer packings or a shorter series)")
    if (budget + packings) * per_set > MAX_CAMPAIGN_RUNS:
        raise ValueError(f"uncertainty.packings: {budget:,} parameter sets and {packings:,} packings {each} = "
                         f"{(budget + packings) * per_set:,} runs; at most {MAX_CAMPAIGN_RUNS:,}")


def _check_dimensions(campaign: Campaign) -> None:
    """In 3D, every test the campaign runs has a 3D implementation and the material is one the
    3D engine has (`LabTest.check_dimensions`), named by its section's key."""
    for test in campaign.tests():
        try:
            lab_test(test).check_dimensions(campaign.specimen.dimensions, campaign.material.model)
        except InputError as exc:
            key = "material.model" if exc.field == "model" else f"targets.{test}"
            raise ValueError(f"{key}: {exc.problem}") from None
    for test in campaign.identifiability.tests or []:
        try:
            lab_test(test).check_dimensions(campaign.specimen.dimensions, campaign.material.model)
        except InputError as exc:
            raise ValueError(f"identifiability.tests: {exc.problem}") from None


DEFAULT_ROCK = "granite"
MAX_LINE = 4096  # characters on a line of a campaign file


def embedded_rocks() -> list[str]:
    """The names of the campaigns shipped with rockcal (`rockcal calibrate NAME`)."""
    return sorted(f.name.removesuffix(".toml") for f in resources.files("rockcal.campaign.input").iterdir()
                  if f.name.endswith(".toml"))


def default_text(rock: str = DEFAULT_ROCK) -> str:
    """An embedded campaign (TOML), by its rock's name."""
    return resources.files("rockcal.campaign.input").joinpath(f"{rock}.toml").read_text()


def load_campaign(path: Path | str | None) -> tuple[Campaign, str]:
    """The campaign of a file, or of an embedded rock by name (a file of that name wins), and
    its TOML text; InputError naming the key for anything wrong."""
    try:
        exists = path is not None and Path(path).exists()
    except OSError as exc:  # a name too long for the file system
        raise InputError("CONFIG", f"cannot read {str(path)[:80]}...: {exc.strerror}") from None
    if path is None or (str(path) in embedded_rocks() and not exists):
        text, base = default_text(str(path or DEFAULT_ROCK)), Path.cwd()
    elif not Path(path).suffix and not exists:
        raise InputError("CONFIG", f"no file {path} and no embedded rock of that name "
                                   f"(embedded: {', '.join(embedded_rocks())})")
    else:
        text = read_user_text(Path(path), "CONFIG")
        base = Path(path).resolve().parent
    return parse_campaign(text, base), text


def parse_campaign(text: str, base: Path) -> Campaign:
    """Validate campaign TOML text, values, specimens and curve file, so that bad input fails
    before any store or run is touched; relative curve paths are taken from `base`. The
    defaults the file leaves open stay as they are: `plan.planned` sets them from the runs' cost."""
    long = next((n for n, line in enumerate(text.splitlines(), start=1) if len(line) > MAX_LINE), None)
    if long is not None:  # TOML's parser takes the square of a long dotted key's parts
        raise InputError("CONFIG", f"line {long} is longer than {MAX_LINE} characters; not a campaign file")
    try:
        data = tomllib.loads(text)
        check_numbers(data)
    except tomllib.TOMLDecodeError as exc:
        raise InputError("CONFIG", f"not valid TOML: {exc}") from None
    except RecursionError:
        raise InputError("CONFIG", "its tables or arrays nest too deeply; not a campaign file") from None
    try:
        campaign = Campaign.model_validate(data)
    except ValidationError as exc:
        raise from_validation_error(exc, Campaign) from None
    _check_values(campaign)
    check_specimens(campaign)
    return _curves_from(campaign, base)


def _curves_from(campaign: Campaign, base: Path) -> Campaign:
    """The campaign with each target section's relative curve path taken from `base`, every
    curve read once so that a broken CSV fails here, before any run."""
    sections = dict(campaign.targets.given())
    for name, section in sections.items():
        curve = getattr(section, "curve", None)
        if curve is not None and not curve.is_absolute():
            sections[name] = section.model_copy(update={"curve": base / curve})
        sections[name].measured_curve()
    return campaign.model_copy(update={"targets": Targets.model_validate(sections)})


def _check_values(campaign: Campaign) -> None:
    """Fixed values, bounds and levels must be valid values, named by their key: the fixed
    values (`_check_fixed`), the search box at every corner, the sensitivity runs row by row
    (fractions that must not sum past 1 may be searched together)."""
    _check_material_names(campaign)
    fixed = campaign.fixed_params()
    make_params = functools.partial(parameters, material(campaign.material.model))
    _check_fixed(campaign, make_params, fixed)
    _check_box(campaign, make_params, fixed)
    if campaign.sensitivity is not None:
        with fields_named(lambda field: f"sensitivity.{field}"):
            runs = design(campaign.sensitivity.array, campaign.sensitivity.levels)
        for row, values in enumerate(zip(*runs.values()), start=1):
            _check_point(make_params, fixed, dict(zip(runs, map(float, values))), "sensitivity.levels",
                         f"in run {row} of {campaign.sensitivity.array}")


def _check_material_names(campaign: Campaign) -> None:
    """Every parameter named in [search] bounds and fixed and [sensitivity] levels is one of the
    chosen material's (or a searched genesis setting), else named with the material that has it."""
    model = campaign.material.model
    own = set(material(model).parameters) | set(SEARCHED_GENESIS)
    named = {"search.bounds": campaign.search.bounds, "search.fixed": campaign.search.fixed,
             "sensitivity.levels": campaign.sensitivity.levels if campaign.sensitivity else {}}
    for key, values in named.items():
        for name in values:
            if name not in own:
                others = [m for m, record in MATERIALS.items() if name in record.parameters]
                raise InputError(f"{key}.{name}", f"a parameter of the {' or '.join(others)} material, not of "
                                 f"{model}: choose material.model = {others[0]!r}, or name {model}'s parameters "
                                 f"({', '.join(material(model).parameters)})")


def _check_fixed(campaign: Campaign, make_params, fixed: dict) -> None:
    """The fixed values are valid with the searched and varied parameters at their lowest or at
    their highest values (not at their defaults): a fault at both is the fixed values', one
    at some points only is left to the box's and the sensitivity runs' checks, which name it."""
    levels = campaign.sensitivity.levels if campaign.sensitivity else {}
    varied = split_genesis(campaign.search.bounds | levels)[0]
    fault = None
    for end in (min, max):
        try:
            make_params(fixed | {name: end(values) for name, values in varied.items()})
            return
        except InputError as exc:
            fault = fault or exc
    if fault.field not in varied:
        key = {"density": "rock.density_kg_m3"}.get(fault.field, f"search.fixed.{fault.field}")
        raise InputError(key if fault.field in fixed else "search.fixed", fault.problem) from None


MAX_CORNERS = 1024  # a larger box is checked on the corners of each pair of its parameters


def nearest_whole(value: float) -> float:
    """The whole number nearest `value`, halves up: the one rounding of a whole-number
    parameter wherever a point of the search is run."""
    return float(math.floor(value + 0.5))


def middle_levels(campaign: Campaign, searched) -> dict[str, float]:
    """The middle (mean) level of each sensitivity factor neither `searched` nor fixed, at
    which the search holds it (a whole number's nearest whole)."""
    levels = campaign.sensitivity.levels if campaign.sensitivity else {}
    fixed, counts = campaign.fixed_params(), whole_numbers(campaign.material.model)
    middle = {f: float(np.mean(v)) for f, v in levels.items() if f not in searched and f not in fixed}
    return {f: nearest_whole(v) if f in counts else v for f, v in middle.items()}


def whole_numbers(model: str) -> set[str]:
    """The parameters of the material `model` that count something (N_r): whole numbers that
    the search may vary, as real numbers rounded to whole ones wherever a point is run."""
    fields = material(model).params_type.model_fields
    return {name for name, info in fields.items() if info.annotation is int and not _is_code(info)}


def _is_code(info) -> bool:
    """A whole-number parameter that picks a rule (a mode, a method) rather than counts."""
    return bool((info.json_schema_extra or {}).get("code"))


def _check_box(campaign: Campaign, make_params, fixed: dict) -> None:
    """The searched micro-parameters are real numbers or counts with whole bounds, valid
    together at every corner of the search box (of a large box, at the corners of each pair of
    its parameters, the others at their lower bounds: every constraint between two values)."""
    bounds = campaign.search.bounds
    fields = material(campaign.material.model).params_type.model_fields
    counts = whole_numbers(campaign.material.model)
    for name in split_genesis(bounds)[0]:
        info = fields[name]
        if info.annotation is int and _is_code(info):
            raise InputError(f"search.bounds.{name}", f"a whole number that picks a rule ({info.description}); "
                             "the search varies quantities: set it in [search] fixed")
        if name in counts and not all(float(v).is_integer() for v in bounds[name]):
            low, high = bounds[name]
            raise InputError(f"search.bounds.{name}", f"a whole number ({info.description}): its bounds must be "
                             f"whole numbers, got [{low:g}, {high:g}]")
    middle = split_genesis(middle_levels(campaign, bounds))[0]
    held = fixed | middle
    for values in _corners(bounds):
        try:
            _check_point(make_params, held, values, "search.bounds", "at a corner of the search box")
        except InputError as exc:
            if exc.field != "search.bounds" or not middle:
                raise
            _check_middle_levels(make_params, fixed, middle)
            raise


def _check_middle_levels(make_params, fixed: dict, middle: dict) -> None:
    """The middle levels the search holds the sensitivity factors it does not search at are
    valid with the fixed values, named `sensitivity.levels.<factor>`."""
    try:
        make_params(fixed | middle)
    except InputError as exc:
        key = f"sensitivity.levels.{exc.field}" if exc.field in middle else "sensitivity.levels"
        at = ", ".join(f"{n} {v:g}" for n, v in middle.items())
        raise InputError(key, f"{exc.problem}, at the middle levels the search holds its factors at ({at})") from None


def _corners(bounds: dict) -> list[dict]:
    """The corners of the box, or of a box of more than MAX_CORNERS corners the corners of each
    pair of its parameters with the others at their lower bounds."""
    if 2 ** len(bounds) <= MAX_CORNERS:
        return [dict(zip(bounds, corner)) for corner in itertools.product(*bounds.values())]
    low = {name: bound[0] for name, bound in bounds.items()}
    return [low | {a: va, b: vb} for a, b in itertools.combinations(bounds, 2)
            for va in bounds[a] for vb in bounds[b]]


def _check_point(make_params, fixed: dict, values: dict, where: str, what: str) -> None:
    """One point of the search (micro-parameters and genesis settings) is valid; an InputError
    names the key under `where` and, for several values, the point (`what`)."""
    params, genesis = split_genesis(values)
    try:
        make_genesis(genesis)
        make_params(fixed | params)
    except InputError as exc:
        key = f"{where}.{exc.field}" if exc.field in values else where
        at = "" if len(values) <= 1 else f", {what} ({', '.join(f'{n} {v:g}' for n, v in values.items())})"
        raise InputError(key, exc.problem + at) from None


def check_specimens(campaign: Campaign, quick: bool = False) -> None:
    """The specimen of each test the campaign runs can be made at every resolution it runs
    them (the campaign's, the coarse samples', the sensitivity runs'), naming the key that set
    the resolution (`--quick` for a quick look's)."""
    targets = list(campaign.target_sections())
    made = [("--quick" if quick else None, campaign.specimen, campaign.tests())]
    if campaign.sensitivity is not None and campaign.sensitivity.rmin_mm is not None:
        made.append(("sensitivity.rmin_mm", campaign.sensitivity_specimen(), targets))
    if campaign.surrogate.coarse_samples:
        made.append(("surrogate.coarse_factor", campaign.coarse_specimen(), targets))
    for key, specimen, tests in made:
        for test in map(lab_test, tests):
            try:
                test.check(test.settings_of(specimen))
            except InputError as exc:
                if key is None:
                    raise InputError(f"specimen.{exc.field}", exc.problem) from None
                raise InputError(key, f"at R_min {specimen.rmin_mm:g} mm the {test.title} specimen cannot be "
                                      f"made: specimen.{exc.field}: {exc.problem}") from None
