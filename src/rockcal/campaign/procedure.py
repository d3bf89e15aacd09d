"""The inverse procedure end to end: sensitivity runs and range analysis,
Latin hypercube runs, Gaussian RBF surrogate and its check, ant colony search on the
surrogate, DEM verification and the adaptive loop, the intervals of the identified parameters
(when the lab gives a spread), then the validation checks.

Each parameter set is run in every lab test calibrated against (UCS, and the Brazilian or
bending test when they are targets), and their responses make one dict: the steps see one
forward model whatever the tests behind it.

Every forward run goes through the executor and its store, and every other step is seeded,
so running a campaign again (after a kill, or to rebuild a report) gives the same answer and
runs only what the store does not hold.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from rockcal.campaign.config import Campaign, SpecimenSettings, read_curve
from rockcal.campaign.forward import SPECIMEN_KEYS, Executor, run_spec
from rockcal.campaign.result import (CalibrationResult, Check, CurveFit, FailedRun, Iteration, Samples,
                                     Sensitivity, SurrogateCheck, Uncertainty, Validation)
from rockcal.inverse import (RBFSurrogate, Objective, ant_colony, curve_fit, design, latin_hypercube,
                             range_analysis)
from rockcal.inverse.uncertainty import parameter_intervals
from rockcal.labtests.kic import pmax_kic_disagreement
from rockcal.labtests.registry import lab_test
from rockcal.labtests.seeds import mean_over_seeds, seed_list
from rockcal.dem.measure import secant_at_half_peak
from rockcal.params import make_params

SIGNIFICANT_DIGITS = 4  # parameters of verification runs are rounded to this (stable store keys)
DISTINCT = 0.05  # optima closer than this (box-normalised distance) are one optimum
SEARCHES_PER_CANDIDATE = 2  # searches tried for each other candidate optimum before giving up

Stage = Callable[[str, int, int], None]  # progress(stage, done, total)


class CalibrationFailed(Exception):
    """The campaign cannot go on (e.g. every forward run of a stage failed)."""


def ucs_targets(campaign: Campaign) -> tuple[dict[str, float], np.ndarray | None]:
    """Scalar targets, completed from the measured curve when one is given (E secant at half
    the peak, UCS = peak), and the curve itself."""
    targets = campaign.targets.ucs.scalars()
    curve = None
    if campaign.targets.ucs.curve is not None:
        curve = read_curve(campaign.targets.ucs.curve)
        E_MPa, _, peak = secant_at_half_peak(curve[:, 0], np.zeros(len(curve)), curve[:, 1])
        targets.setdefault("E_GPa", E_MPa / 1e3)
        targets.setdefault("ucs_MPa", float(curve[peak, 1]))
    return targets, curve


def _round(x: np.ndarray) -> np.ndarray:
    return np.array([float(f"{v:.{SIGNIFICANT_DIGITS}g}") for v in x])


SAMPLES_AND_CHECKS = "samples and checks"  # the stage of step 3's DEM runs
# the stage of the runs at the identified point: the other packings and the validation tests
PACKINGS_AND_VALIDATION = "packings and validation"


class Calibration:
    """One campaign's run: call `run()`; the result it returns is what reports are made of."""

    def __init__(self, campaign: Campaign, executor: Executor, progress: Stage | None = None):
        self.campaign = campaign
        self.executor = executor
        self.progress = progress or (lambda stage, done, total: None)
        sections = campaign.target_sections()
        ucs, self.curve = ucs_targets(campaign)
        self.tests = {t: list(ucs) if t == "ucs" else list(s.scalars()) for t, s in sections.items()}
        self.targets = ucs | {r: v for t, s in sections.items() if t != "ucs" for r, v in s.scalars().items()}
        self.weights = {r: w for s in sections.values() for r, w in s.weights.items()}
        self.spread = {r: list(v) if isinstance(v, tuple) else v
                       for s in sections.values() for r, v in s.spread.items()}
        self.fixed = campaign.fixed_params()
        self.dem_runs: list[str] = []  # keys of the distinct UCS runs: one per parameter set
        self.failed_runs: list[FailedRun] = []
        self.ucs_specimen: dict | None = None  # of the first UCS run that succeeded

    # -- forward runs ---------------------------------------------------------------------
    def _forward(self, stage: str, points: list[tuple[SpecimenSettings, dict]], shown: bool = True):
        """Every target test at each (specimen settings, parameters) point: the responses of
        each point (None when a run of it failed), the specs of each test, the failed runs.
        The runs are shown as `stage`'s progress unless `shown` is False."""
        specs = {t: [run_spec(t, settings, self.fixed | row) for settings, row in points] for t in self.tests}
        results = self._run([spec for t in self.tests for spec in specs[t]], stage if shown else None)
        n = len(points)
        by_test = {t: results[k * n:(k + 1) * n] for k, t in enumerate(self.tests)}
        responses, failed = [], []
        for i in range(n):
            runs = {t: by_test[t][i] for t in self.tests}
            failed += [FailedRun(stage=stage if t == "ucs" else f"{stage} ({t})", message=r.message)
                       for t, r in runs.items() if r.status != "ok"]
            ok = all(r.status == "ok" for r in runs.values())
            responses.append(merge_responses({t: r.responses for t, r in runs.items()}) if ok else None)
        if self.ucs_specimen is None:  # of the first UCS run that succeeded on the campaign's specimen
            done = next((r.responses for r, (settings, _) in zip(by_test["ucs"], points)
                         if r.status == "ok" and settings == self.campaign.specimen), None)
            if done is not None:
                self.ucs_specimen = {k: done[k] for k in SPECIMEN_KEYS if k in done}
        return responses, specs, failed

    def _run(self, specs: list, stage: str | None) -> list:
        """The executor's results of `specs`, shown as `stage`'s progress (None: not shown)."""
        shown = stage and (lambda done, total: self.progress(stage, done, total))
        return self.executor.run(specs, shown)

    def _evaluate(self, stage: str, rows: list[dict], specimen: SpecimenSettings | None = None) -> list[dict | None]:
        """The responses of each parameter set on the campaign's specimens (or `specimen`; None
        for a failed run); every run counts against the budget and a failure is recorded."""
        specimen = specimen or self.campaign.specimen
        responses, specs, failed = self._forward(stage, [(specimen, row) for row in rows])
        for spec in specs["ucs"]:
            if spec.key not in self.dem_runs:
                self.dem_runs.append(spec.key)
        self.failed_runs += failed
        if failed and all(r is None for r in responses):
            raise CalibrationFailed(f"every forward run of stage '{stage}' failed; "
                                    f"first: {failed[0].message}")
        return responses

    # -- the steps ------------------------------------------------------------------------
    def sensitivity(self) -> tuple[dict[str, tuple[float, float]], Sensitivity | None]:
        """Step 2: orthogonal-array runs, range analysis; returns the search bounds and the
        study (None without [sensitivity])."""
        settings = self.campaign.sensitivity
        bounds = dict(self.campaign.search.bounds)
        if settings is None:
            return bounds, None
        runs = design(settings.array, settings.levels)
        n = len(next(iter(runs.values())))
        rows = [{f: float(v[i]) for f, v in runs.items()} for i in range(n)]
        specimen = self.campaign.sensitivity_specimen()
        responses = self._evaluate("sensitivity", rows, specimen)  # the array's values override [search].fixed
        names = list(self.targets)
        table = _fill_failed({r: [None if v is None else v[r] for v in responses] for r in names})
        analysis = range_analysis({f: np.array(v) for f, v in runs.items()}, table)
        chosen = analysis.chosen(settings.threshold)
        study = Sensitivity(array=settings.array, runs=rows, run_responses=responses,
                            imputed_runs=[i for i, v in enumerate(responses) if v is None],
                            rmin_mm=specimen.rmin_mm if specimen != self.campaign.specimen else None,
                            **analysis.to_dict(settings.threshold))
        if not bounds:
            bounds = {f: (min(settings.levels[f]), max(settings.levels[f])) for f in chosen}
        for f, levels in settings.levels.items():  # factors neither inverted nor fixed: middle
            if f not in bounds and f not in self.fixed:
                self.fixed[f] = float(np.mean(levels))
        return bounds, study

    def run(self) -> CalibrationResult:
        """Steps 2-8; returns what the campaign found."""
        bounds, sensitivity = self.sensitivity()
        names = list(bounds)
        box = np.array([bounds[n] for n in names], dtype=float)
        fixed = dict(self.fixed)
        s = self.campaign.surrogate

        # step 3: Latin hypercube runs (with the sensitivity runs that are runs of the search),
        # surrogate, check on fresh random points; the samples and checks run as one batch
        x, checks = sample_points(box, s)
        y_all = self._evaluate(SAMPLES_AND_CHECKS, [dict(zip(names, row)) for row in [*x, *checks]])
        y, y_checks = y_all[:len(x)], y_all[len(x):]
        reused = self._reusable(sensitivity, names, box)
        train_x, train_y = _usable(np.vstack([x, _points(sensitivity, reused, names)]),
                                   y + [sensitivity.run_responses[i] for i in reused])
        surrogate = self._fit(train_x, train_y, box)
        check_x, check_y = _usable(checks, y_checks)
        validation = surrogate.validate(check_x, {r: np.array([v[r] for v in check_y]) for r in self.targets},
                                        s.tolerance) if len(check_x) else None
        surrogate_check = SurrogateCheck(
            x=checks.tolist(), dem=y_checks, predicted=[surrogate.predict(row) for row in checks],
            max_relative_error=None if validation is None else validation.max_relative_error,
            trusted=None if validation is None else validation.trusted,
            tolerance=s.tolerance, epsilon=surrogate.epsilon)
        train_x = np.vstack([train_x, check_x])
        train_y = train_y + check_y

        # steps 4-6: search on the surrogate, verify with the DEM (the search's optimum and other
        # distinct optima, [acceptance] candidates), refit, until a verified point is accepted
        tolerance = self.campaign.acceptance.tolerance
        iterations, accepted = [], None
        for loop in range(self.campaign.acceptance.max_dem_runs):
            surrogate = self._fit(train_x, train_y, box)
            objective = Objective(surrogate.predict, self.targets, weights=self.weights or None)
            found = self._candidates(objective, surrogate, box)
            xs = [_round(opt.x) for opt in found]
            verified = self._evaluate("verification", [dict(zip(names, x_best)) for x_best in xs])
            start = len(iterations)
            iterations += [self._iteration(opt, x_best, surrogate, v, loop)
                           for opt, x_best, v in zip(found, xs, verified)]
            new = [(x_best, v) for x_best, v in zip(xs, verified)
                   if v is not None and not any(np.allclose(x_best, row) for row in train_x)]
            train_x = np.vstack([train_x, *[x_best for x_best, _ in new]])
            train_y = train_y + [v for _, v in new]
            passed = [i for i in range(start, len(iterations)) if _within(iterations[i].errors, tolerance)]
            if passed:
                accepted = passed[0]  # the first in the order searched: the serial loop's answer
                break
            if len(self.dem_runs) >= self.campaign.acceptance.max_dem_runs or not new:
                break
        best = accepted if accepted is not None else _closest(iterations)
        identified = dict(zip(names, iterations[best].x))
        dem_run_keys = list(self.dem_runs)
        final_runs = self._final_runs(identified)
        if final_runs:
            self._run(final_runs, PACKINGS_AND_VALIDATION)
        uncertainty = self._uncertainty(identified, self._fit(train_x, train_y, box), box, names) \
            if self.campaign.wants_uncertainty() else None
        final_ucs_run_key, curve_fit = self._curve_fit(identified)
        return CalibrationResult(
            rock=self.campaign.rock.name, targets=self.targets, target_tests=self.tests,
            weights=self.weights or None, specimen=self.campaign.specimen,
            measured_curve=None if self.curve is None else self.curve.tolist(),
            failed_runs=self.failed_runs, ucs_specimen=self.ucs_specimen, sensitivity=sensitivity,
            parameters=names, bounds=bounds, fixed=fixed,
            samples=Samples(x=x.tolist(), responses=y, reused_sensitivity_runs=reused or None),
            surrogate_check=surrogate_check,
            iterations=iterations, accepted=accepted is not None, identified=identified,
            identified_params=make_params(self.fixed | identified).key(),
            verified=iterations[best].verified, errors=iterations[best].errors, tolerance=tolerance,
            objective=objective.describe(), dem_runs=len(dem_run_keys), best_iteration=best,
            dem_run_keys=dem_run_keys, uncertainty=uncertainty, final_ucs_run_key=final_ucs_run_key,
            curve_fit=curve_fit, validation=self._validate(identified), checks=self._checks(identified))

    def _reusable(self, study: Sensitivity | None, names: list[str], box: np.ndarray) -> list[int]:
        """The sensitivity runs that are runs of the search: inside the box, with every other
        parameter at its fixed value (the very run a sample at that point would be)."""
        if study is None or self.campaign.sensitivity_specimen() != self.campaign.specimen:
            return []
        keep = []
        for i, (row, responses) in enumerate(zip(study.runs, study.run_responses)):
            point = {n: row[n] for n in names if n in row}
            same = len(point) == len(names) and \
                make_params(self.fixed | row).key() == make_params(self.fixed | point).key()
            if responses is not None and same and _inside(point, names, box):
                keep.append(i)
        return keep

    def _candidates(self, objective: Objective, surrogate: RBFSurrogate, box: np.ndarray) -> list:
        """The search's optimum on the surrogate, then up to [acceptance] candidates - 1 other
        distinct optima within the run budget: the searches with the next seeds whose optimum
        the surrogate predicts within the tolerance of every target (none when the surrogate
        has a single optimum)."""
        first = self._optimise(objective, box)
        left = self.campaign.acceptance.max_dem_runs - len(self.dem_runs)
        found, wanted = [first], max(1, min(self.campaign.acceptance.candidates, left))
        tolerance, seed = self.campaign.acceptance.tolerance, self.campaign.optimizer.seed
        for k in range(1, SEARCHES_PER_CANDIDATE * (wanted - 1) + 1):
            if len(found) >= wanted:
                break
            opt = self._optimise(objective, box, seed=seed + k)
            predicted = surrogate.predict(_round(opt.x))
            close = _within({r: predicted[r] / t - 1 for r, t in self.targets.items()}, tolerance)
            if close and all(_distinct(opt.x, other.x, box) for other in found):
                found.append(opt)
        return found

    def _iteration(self, opt, x_best, surrogate: RBFSurrogate, verified: dict | None, loop: int) -> Iteration:
        errors = None if verified is None else {r: verified[r] / t - 1 for r, t in self.targets.items()}
        return Iteration(
            x=x_best.tolist(), objective_surrogate=float(opt.fun), predicted=surrogate.predict(x_best),
            verified=verified, errors=errors, history_fun=list(map(float, opt.history_fun)),
            history_x=[list(map(float, h)) for h in opt.history_x], nfev=int(opt.nfev), loop=loop)

    def _fit(self, x, y, box) -> RBFSurrogate:
        return RBFSurrogate(x, {r: np.array([v[r] for v in y]) for r in self.targets}, box)

    def _optimise(self, objective, box, seed: int | None = None):
        o = self.campaign.optimizer
        seed = o.seed if seed is None else seed
        if o.method == "acor":
            return ant_colony(objective, box, method="acor", ants=o.ants, iterations=o.iterations,
                              seed=seed, vectorized=True)
        return ant_colony(objective, box, method="ant-system", ants=o.ants, iterations=o.iterations,
                          alpha=o.alpha, beta=o.beta, rho=o.rho, seed=seed, vectorized=True)

    def _final_runs(self, identified: dict) -> list:
        """The runs at the identified point after the search, as one batch that keeps the
        workers busy to its end: the validation tests' (the longest, first), then the other
        packings of the calibrated tests (the parameters' intervals)."""
        specs = [spec for test in self.campaign.validation_tests()
                 for spec in self._validation_runs(test, identified)]
        if self.campaign.wants_uncertainty():
            specs += [run_spec(test, settings, self.fixed | row) for test in self.tests
                      for settings, row in self._packings(identified)]
        return specs

    def _packings(self, identified: dict) -> list[tuple[SpecimenSettings, dict]]:
        """The (specimen settings, parameters) of the packings at the identified point whose
        scatter the parameters' intervals take in: the campaign's specimen and its next seeds."""
        return [(self.campaign.specimen.model_copy(update={"seed": s}), identified)
                for s in packing_seeds(self.campaign)]

    def _validation_runs(self, test: str, identified: dict) -> list:
        """The runs of a validation test at the identified point."""
        return [run_spec(test, self.campaign.specimen.model_copy(update={"seed": s}), self.fixed | identified)
                for s in validation_seeds(self.campaign, test)]

    def _uncertainty(self, identified: dict, surrogate: RBFSurrogate, box, names) -> Uncertainty:
        """The model's scatter over packings at the identified point (relative sd of each
        response), then the parameters' intervals for targets drawn from the lab's spread and
        that scatter (`rockcal.inverse.uncertainty`), each solved on the surrogate."""
        u = self.campaign.uncertainty
        points = self._packings(identified)
        seeds = [settings.seed for settings, _ in points]
        # run by _final_runs
        responses, specs, _ = self._forward(PACKINGS_AND_VALIDATION, points, shown=False)
        ok = [r for r in responses if r is not None]
        scatter = {r: float(np.std([v[r] for v in ok], ddof=1) / abs(np.mean([v[r] for v in ok])))
                   if len(ok) > 1 else 0.0 for r in self.targets}
        done = [0]

        def solve(targets: dict) -> np.ndarray:
            done[0] += 1
            self.progress("uncertainty (draws)", done[0], u.draws)
            return self._optimise(Objective(surrogate.predict, targets, weights=self.weights or None), box).x

        return Uncertainty(
            seeds=seeds, run_keys=[spec.key for t in self.tests for spec in specs[t]],
            packing_responses=ok, scatter=scatter, spread=self.spread, draws=u.draws,
            **parameter_intervals(solve, self.targets, self.spread, scatter, box, names,
                                  draws=u.draws, seed=u.seed))

    def _curve_fit(self, identified: dict) -> tuple[str, CurveFit | None]:
        """Step 7: the key of the UCS run at the identified parameters, and the RE and CC of
        its stress-strain curve (the simulated strain may dither at the start: only the points
        that advance it are kept), None without a measured curve or a stored run."""
        spec = run_spec("ucs", self.campaign.specimen, self.fixed | identified)
        result = self.executor.store.get(spec)
        if self.curve is None or result is None or result.curve is None:
            return spec.key, None
        strain, stress = result.curve[:, 0], result.curve[:, 2]
        ahead = strain > np.maximum.accumulate(np.concatenate([[-np.inf], strain[:-1]]))
        fit = curve_fit(strain[ahead], stress[ahead], self.curve[:, 0], self.curve[:, 1])
        return spec.key, CurveFit(RE=fit.RE, CC=fit.CC)

    def _validate(self, identified: dict) -> Validation | None:
        """Step 8: the notched-beam bending test with the identified parameters, K_IC averaged
        over `specimen.bending_seeds` packings (None unless bending is a validation check)."""
        bending = self.campaign.targets.bending
        if "bending" not in self.campaign.validation_tests():
            return None
        seeds = validation_seeds(self.campaign, "bending")
        specs = self._validation_runs("bending", identified)
        results = self._run(specs, None)  # run by _final_runs
        ok = [(seed, spec, r) for seed, spec, r in zip(seeds, specs, results) if r.status == "ok"]
        found = {"lab_K_IC_MPa_sqrt_m": bending.K_IC_MPa_sqrt_m, "seeds": seeds,
                 "run_keys": [spec.key for spec in specs]}
        if ok:
            k_per_seed = [r.responses["K_IC_MPa_sqrt_m"] for _, _, r in ok]
            found |= {"status": "ok", "run_key": ok[0][1].key, "ok_seeds": [s for s, _, _ in ok],
                      "K_IC_per_seed": k_per_seed}
            found |= mean_over_seeds([r.responses for _, _, r in ok])
            found["K_IC_error"] = found["K_IC_MPa_sqrt_m"] / bending.K_IC_MPa_sqrt_m - 1
        else:
            found |= {"status": results[0].status, "message": results[0].message,
                      "run_key": specs[0].key}
        if bending.P_max_kN is not None:
            found["warning"] = pmax_kic_disagreement(
                1e3 * bending.P_max_kN, 1e6 * bending.K_IC_MPa_sqrt_m, 1e-3 * bending.diameter_mm,
                1e-3 * bending.notch_mm, 1e-3 * bending.span_mm)
        return Validation(**found)


    def _checks(self, identified: dict) -> list[Check] | None:
        """Step 8 for each other validation test: its run at the identified parameters against
        the lab's values (None when there is none)."""
        tests = [t for t in self.campaign.validation_tests() if t != "bending"]
        checks = []
        for test in tests:
            lab = self.campaign.targets.given()[test].scalars()
            spec = self._validation_runs(test, identified)[0]
            run = self._run([spec], None)[0]  # run by _final_runs
            found = {"test": test, "lab": lab, "run_key": spec.key, "status": run.status}
            if run.status == "ok":
                found |= {"responses": run.responses,
                          "errors": {r: run.responses[r] / v - 1 for r, v in lab.items()}}
            else:
                found["message"] = run.message
            checks.append(Check(**found))
        return checks or None


def packing_seeds(campaign: Campaign) -> list[int]:
    """The packings whose scatter the parameters' intervals take in: the campaign's specimen's
    seed and the next ones."""
    return seed_list(campaign.specimen.seed, campaign.uncertainty.packings)


def validation_seeds(campaign: Campaign, test: str) -> list[int]:
    """The packings a validation test runs on: the bending test's `specimen.bending_seeds`,
    another test's the campaign's specimen."""
    s = campaign.specimen
    return seed_list(s.seed, s.bending_seeds) if test == "bending" else [s.seed]


def merge_responses(by_test: dict[str, dict]) -> dict:
    """One parameter set's responses: the UCS test's whole (its other readings too), and the
    target responses of each other test."""
    merged = dict(by_test["ucs"])
    for test, responses in by_test.items():
        if test != "ucs":
            merged |= {r: responses[r] for r in lab_test(test).targets}
    return merged


def _fill_failed(table: dict[str, list]) -> dict[str, np.ndarray]:
    """Responses of the array's runs with each failed run (None) given the mean of the runs that
    succeeded: the design stays balanced, and a failed run pulls no level up or down."""
    filled = {}
    for response, values in table.items():
        done = [v for v in values if v is not None]
        filled[response] = np.array([np.mean(done) if v is None else v for v in values])
    return filled


def sample_points(box: np.ndarray, s) -> tuple[np.ndarray, np.ndarray]:
    """The Latin hypercube points and the surrogate's random check points in the box (rounded:
    stable store keys), as the campaign's [surrogate] settings and seed make them."""
    x = _round_rows(latin_hypercube(box, s.samples, seed=s.seed))
    rng = np.random.default_rng(s.seed + 1)
    checks = _round_rows(box[:, 0] + rng.random((s.checks, len(box))) * (box[:, 1] - box[:, 0]))
    return x, checks


def _round_rows(x: np.ndarray) -> np.ndarray:
    return np.array([_round(row) for row in x])


def _usable(x: np.ndarray, y: list) -> tuple[np.ndarray, list]:
    keep = [i for i, v in enumerate(y) if v is not None]
    return x[keep].reshape(len(keep), x.shape[1]), [y[i] for i in keep]


def _points(study: Sensitivity | None, runs: list[int], names: list[str]) -> np.ndarray:
    """The search-box points of some sensitivity runs, as rows."""
    return np.array([[study.runs[i][n] for n in names] for i in runs]).reshape(len(runs), len(names))


def _inside(point: dict, names: list[str], box: np.ndarray) -> bool:
    return all(low <= point[n] <= high for n, (low, high) in zip(names, box))


def _within(errors: dict | None, tolerance: float) -> bool:
    """The source's acceptance rule: every response within the tolerance of its target."""
    return errors is not None and all(abs(e) <= tolerance for e in errors.values())


def _distinct(a: np.ndarray, b: np.ndarray, box: np.ndarray) -> bool:
    """Two optima further apart than DISTINCT of the box (box-normalised distance)."""
    return float(np.linalg.norm((np.asarray(a) - b) / (box[:, 1] - box[:, 0]))) > DISTINCT


def _closest(iterations: list[Iteration]) -> int:
    """The verified iteration with the smallest largest error (when none was accepted)."""
    scored = [(max(abs(e) for e in it.errors.values()), i)
              for i, it in enumerate(iterations) if it.errors is not None]
    if not scored:
        raise CalibrationFailed("no verification run succeeded")
    return min(scored)[1]

