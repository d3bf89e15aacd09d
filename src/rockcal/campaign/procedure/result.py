"""What a calibration campaign found, as one typed result, and its record (record.json).

The one schema here is what the procedure writes and what the report, the CLI and the export
read back, so they cannot drift apart. A record it does not fit (written by another version,
or edited by hand) is an InputError naming the field.
"""

from __future__ import annotations

import json

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from rockcal.campaign.input.config import SpecimenSettings
from rockcal.errors import InputError, from_validation_error
from rockcal.inverse.uncertainty import Interval
from rockcal.labtests.registry import PRIMARY_TEST

RECORD_NAME = "record.json"

Values = dict[str, float]  # by parameter or response name
Responses = dict[str, float | int]  # of a forward run, as its lab test reports them


def _absent():
    """A piece a campaign may lack: None, and then left out of the record."""
    return Field(None, exclude_if=lambda value: value is None)


class _Part(BaseModel):
    model_config = ConfigDict(extra="forbid")


class FailedRun(_Part):
    stage: str
    message: str


class Effect(_Part):
    """One factor's effect on one response: its levels, the response's sum K and mean k at
    each level, and their range R."""

    levels: list[float]
    K: list[float]
    k: list[float]
    R: float


class Sensitivity(_Part):
    """The sensitivity step: the orthogonal array's runs and responses (None: failed, then imputed) and
    their range analysis."""

    array: str
    runs: list[Values]
    run_responses: list[Responses | None]
    imputed_runs: list[int]
    responses: dict[str, dict[str, Effect]]
    ranking: dict[str, list[str]]
    chosen: list[str]
    rmin_mm: float | None = _absent()  # R_min of its runs, where coarser than the campaign's
    # the searched parameters whose effect on every target is below the tolerance
    unseen: list[str] | None = _absent()


class Samples(_Part):
    """The samples step: the Latin hypercube points and their DEM responses (None: failed), and the
    sensitivity runs that train the surrogate too (by index)."""

    x: list[list[float]]
    responses: list[Responses | None]
    reused_sensitivity_runs: list[int] | None = _absent()  # also train the surrogate: runs of the search


class SurrogateCheck(_Part):
    """The samples step: the surrogate against the DEM at fresh random points."""

    x: list[list[float]]
    dem: list[Responses | None]
    predicted: list[Values]
    max_relative_error: Values | None  # None: no check run succeeded
    trusted: bool | None
    tolerance: float
    epsilon: Values


class Iteration(_Part):
    """The verification step, one point: an optimum of the search on the surrogate and its DEM run."""

    x: list[float]
    objective_surrogate: float
    predicted: Values
    verified: Responses | None  # None: the verification run failed
    errors: Values | None
    history_fun: list[float]
    history_x: list[list[float]]
    nfev: int
    loop: int | None = _absent()  # the loop round; several distinct optima are verified in one


class Uncertainty(_Part):
    """The identified parameters' intervals: the model's scatter over packings, the lab's
    spread (an sd, or [min, max]) and the parameters solved for each drawn target set."""

    seeds: list[int]
    run_keys: list[str]
    packing_responses: list[Responses]
    scatter: Values
    spread: dict[str, float | list[float]]
    draws: int
    intervals: dict[str, Interval]
    samples: list[list[float]]
    drawn_targets: dict[str, list[float]]


class CurveFit(_Part):
    """The final runs: RE and CC of the stress-strain curve against the measured one."""

    RE: float
    CC: float


class BendingValidation(BaseModel):
    """The final runs: the bending test at the identified parameters over packings, against the lab's
    K_IC. Each other response's mean and sd over the packings (`name`, `name_std`) comes too."""

    model_config = ConfigDict(extra="allow")

    lab_K_IC_MPa_sqrt_m: float
    seeds: list[int]
    run_keys: list[str]
    status: str
    run_key: str
    ok_seeds: list[int] | None = _absent()
    K_IC_per_seed: list[float] | None = _absent()
    K_IC_MPa_sqrt_m: float | None = _absent()
    K_IC_MPa_sqrt_m_std: float | None = _absent()
    P_max_kN_per_m: float | None = _absent()
    displacement_at_peak_mm: float | None = _absent()
    K_IC_error: float | None = _absent()
    message: str | None = _absent()  # why the run did not give a result
    warning: str | None = _absent()  # the lab's P_max and K_IC disagree


class Check(_Part):
    """The final runs, for a validation test other than bending (whose check is `BendingValidation`): the
    test at the identified parameters, on the packing `specimen.seed`, against the lab."""

    test: str
    lab: Values
    run_key: str  # the first run of a series
    status: str
    responses: Responses | None = _absent()
    errors: Values | None = _absent()
    message: str | None = _absent()  # why the run did not give a result


class Conflict(_Part):
    """Two targets no point of the search box meets together within the tolerance."""

    targets: list[str]
    least_error: float  # the surrogate's least larger relative error of the two in the box


class TradeOff(_Part):
    """Two responses' relative errors at every DEM run of the search, and the runs no other
    beats in both (their indices, by the first response's error)."""

    responses: list[str]
    errors: list[list[float]]
    pareto: list[int]


class Verdict(_Part):
    """Why no verified point met every target (`rockcal.campaign.procedure.verdict`)."""

    unreachable: Values  # target: the surrogate's least relative error alone, above the tolerance
    conflicts: list[Conflict]  # the pairs that conflict, most first
    least_error_all: float  # the surrogate's least largest relative error over every target
    binding: list[str] = []  # the targets at that largest error there: those that hold the others back
    trade_off: TradeOff
    text: str


class ParameterRange(_Part):
    """A searched parameter's range over the points that meet the sheet, the share of its
    search box it spans, and whether the sheet pins it (`rockcal.inverse.identifiability.pins`:
    the value found within `pinned_within` of every point of it, the range within `pinned_share`
    of its box).
    Read in the DEM, the range reaches from the points found meeting the sheet (`met_low`
    to `met_high`) and the runs of its read that miss it within the surrogate's error, out to
    the nearest runs beyond that miss it by more, or to the box's bounds: the set's edges along
    the read lie between."""

    low: float
    high: float
    share: float
    pinned: bool
    # read in the DEM: the sides ("low", "high") whose end met the sheet there, the accepted
    # point standing for a side whose runs all missed it (None: read on the surrogate)
    verified_ends: list[str] | None = None
    met_low: float | None = _absent()  # read in the DEM: the span of the points found meeting the sheet
    met_high: float | None = _absent()


class EndRun(_Part):
    """The calibrated tests' DEM runs at a trial end of the range the DEM reads: its side,
    the point, the responses' relative errors against the targets (None: a run failed) and
    whether they met the sheet (each within its tolerance, or the lab's spread where wider)."""

    side: str
    point: Values
    errors: Values | None
    met: bool
    parameter: str | None = _absent()  # whose range the run read


class SpreadOfTest(_Part):
    """A lab test the sheet lacks (or a reading of a test it has, `ucs` for CI and CD), its
    response at each end (None: the run failed), their spread (max - min over |mean|) and its
    rank's score: spread per lab work."""

    test: str
    response: str
    label: str  # what to measure, in words
    values: list[float | None]
    spread: float
    score: float


class Identifiability(_Part):
    """Which searched parameters the sheet pins (`rockcal.inverse.identifiability`): the bands
    of predicted responses that meet it, a sample of the points in them and their ranges; the
    DEM runs at the ends of the widest range not pinned (`end_runs`), the ends kept
    (`points`), each lacking test's spread between them, the tests ranked and in words."""

    bands: dict[str, tuple[float, float]]  # each target's: the tolerance or spread, with `surrogate_error`
    surrogate_error: Values  # the surrogate's relative error at the verified points, near the accepted one
    pinned_share: float
    pinned_within: float | None = _absent()  # None: a record whose verdicts took the share of the box alone
    ranges: dict[str, ParameterRange]
    set_points: list[list[float]]  # a sample of the set (the figure)
    end_runs: list[EndRun]  # in the order they ran
    points: list[Values]  # the ends kept, where the lacking tests ran (none: no test ranked)
    tests: list[SpreadOfTest]  # ranked, best first
    runs: int  # DEM runs the stage asked for that no earlier stage ran
    text: str


AT_BOUND = 0.01  # a parameter within this share of its search box from a bound is on it


def on_bounds(identified: Values, bounds: dict[str, tuple[float, float]]) -> list[str]:
    """A warning for each identified parameter within AT_BOUND of its box from a bound: the
    search may have stopped there, not at the targets' optimum."""
    found = []
    for name, value in identified.items():
        if name not in bounds:
            continue
        low, high = bounds[name]
        near = AT_BOUND * (high - low)
        side, bound = ("lower", low) if value - low <= near else ("upper", high) if high - value <= near else ("", 0)
        if side:
            found.append(f"{name} is at its {side} bound {bound:g}: widen search.bounds.{name} and resume "
                         "(the runs done are kept)")
    return found


class CalibrationResult(_Part):
    """A campaign's result, in the order the procedure finds it: its inputs,
    each step's outcome, then the identified parameters (`identified`; every micro-parameter
    in `identified_params`), their verified responses and errors, and the validation. A
    parameter set's responses are those of every test calibrated against, in one dict; the
    UCS test's come with its other readings."""

    rock: str
    material: str | None = _absent()  # the bonded material (`rockcal.materials`); None: the default
    targets: Values  # of every test calibrated against
    target_tests: dict[str, list[str]] | None = _absent()  # each test's targets; None: UCS only
    weights: Values | None = _absent()  # the responses weighed otherwise than 1 in the objective
    specimen: SpecimenSettings
    measured_curve: list[list[float]] | None = _absent()
    failed_runs: list[FailedRun]
    ucs_specimen: Responses  # particles, porosity, contacts and bonds per particle
    sensitivity: Sensitivity | None = _absent()
    parameters: list[str]  # the inverted ones
    bounds: dict[str, tuple[float, float]]
    fixed: Values
    coarse_samples: Samples | None = _absent()  # multi-fidelity: the coarse runs (R_min x coarse_factor)
    samples: Samples
    surrogate_check: SurrogateCheck
    iterations: list[Iteration]
    accepted: bool
    identified: Values
    identified_params: Values
    verified: Responses
    errors: Values
    tolerance: float
    objective: str
    dem_runs: int
    best_iteration: int
    dem_run_keys: list[str]
    uncertainty: Uncertainty | None = _absent()
    final_ucs_run_key: str
    final_bending_run_key: str | None = _absent()  # K_IC a target: the beam at the identified point
    # the runs at the identified point of each test run as a series (confined compression at
    # each confinement), on the campaign's packing; None: no such test
    series_runs: dict[str, list[str]] | None = _absent()
    curve_fit: CurveFit | None = _absent()
    validation: BendingValidation | None = _absent()
    checks: list[Check] | None = _absent()
    verdict: Verdict | None = _absent()  # when not accepted: which targets conflict
    executed_runs: int | None = _absent()  # by this call of `rockcal calibrate`
    quick_look: str | None = _absent()  # what the quick look (`--quick`) was; None: the calibration
    at_bounds: list[str] | None = _absent()  # identified parameters on their search bound (`on_bounds`)
    identifiability: Identifiability | None = _absent()  # when accepted: which parameters the sheet pins

    def responses_by_test(self) -> dict[str, list[str]]:
        """The target responses of each lab test calibrated against."""
        return self.target_tests or {PRIMARY_TEST: list(self.targets)}

    def tests(self) -> list[str]:
        """The lab tests the campaign ran: its targets', its validations' and its series'."""
        tests = [*self.responses_by_test(), *(["bending"] if self.validation else []),
                 *(c.test for c in self.checks or []), *(self.series_runs or {})]
        return list(dict.fromkeys(tests))

    def to_json(self, indent: int | None = None) -> str:
        """The record."""
        return json.dumps(self.model_dump(mode="json"), indent=indent)

    @classmethod
    def from_json(cls, text: str) -> CalibrationResult:
        """The result a record holds; InputError naming the field that does not fit."""
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            raise InputError(RECORD_NAME, f"not valid JSON: {exc}") from None
        try:
            return cls.model_validate(data)
        except ValidationError as exc:
            error = from_validation_error(exc)
            raise InputError(error.field, f"{error.problem} (in {RECORD_NAME})") from None


def read_result(store) -> CalibrationResult | None:
    """The result of the campaign in a run store, or None when it has not finished."""
    text = store.document(RECORD_NAME)
    return None if text is None else CalibrationResult.from_json(text)


def save_result(store, result: CalibrationResult) -> None:
    """Keep a campaign's result in its run store."""
    store.save_document(RECORD_NAME, result.to_json())
