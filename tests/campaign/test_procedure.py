"""The procedure's logic on a synthetic forward model (no DEM): failed sensitivity runs are
filled in and the campaign goes on, and the loop recovers the model's known parameters."""

import numpy as np
import pytest

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.procedure.steps import calibrate, spread_out
from rockcal.campaign.procedure.result import FailedRun
from rockcal.campaign.runs.spec import RunResult
from rockcal.errors import InputError

CAMPAIGN = """
[targets.ucs]
E_GPa = 50.0
nu = 0.2
ucs_MPa = 120.0
[sensitivity]
array = "L16(4^5)"
levels = { E_c = [15, 20, 25, 30], kn_ks = [1.0, 1.67, 2.33, 3.0], sigma_c = [20, 30, 40, 50], tau_c = [50, 70, 90, 110], mu = [0.3, 0.4, 0.5, 0.6] }
[surrogate]
samples = 12
checks = 2
[optimizer]
iterations = 60
[acceptance]
max_dem_runs = 40
"""


def responses(p: dict) -> dict:
    """A smooth stand-in for the DEM: E from E_c, nu from kn/ks, UCS from sigma_c, small side effects."""
    return {"E_GPa": 2.0 * p["E_c"] * (1 + 0.02 * p["mu"]), "nu": 0.1 * p["kn_ks"] + 0.0002 * p["E_c"],
            "ucs_MPa": 3.0 * p["sigma_c"] + 0.01 * p["tau_c"]}


class SyntheticExecutor:
    """Executor interface over `responses`; the run at E_c 15, mu 0.3 fails, as a DEM run may."""

    class store:
        @staticmethod
        def get(spec):
            return None

    def run(self, specs, progress=None):
        out = []
        for spec in specs:
            p = dict(spec.params)
            if p["E_c"] == 15 and p["mu"] == 0.3:
                out.append(RunResult("failed", {}, None, 0.0, "ValueError: unstable"))
            else:
                out.append(RunResult("ok", responses(p), None, 0.0))
        return out


def test_a_failed_sensitivity_run_is_filled_in_and_the_campaign_recovers_the_parameters(tmp_path):
    record = calibrate(planned(parse_campaign(CAMPAIGN, tmp_path)), SyntheticExecutor())
    sensitivity = record.sensitivity
    assert len(sensitivity.imputed_runs) == 1
    assert sensitivity.chosen == ["E_c", "kn_ks", "sigma_c"]
    assert record.failed_runs == [FailedRun(stage="sensitivity", message="ValueError: unstable")]
    assert record.accepted
    mu, tau_c = record.fixed["mu"], record.fixed["tau_c"]  # the middle of their levels
    assert (mu, tau_c) == pytest.approx((0.45, 80.0))
    truth = {"E_c": 25.0 / (1 + 0.02 * mu), "sigma_c": (120.0 - 0.01 * tau_c) / 3.0}
    truth["kn_ks"] = (0.2 - 0.0002 * truth["E_c"]) / 0.1
    for name, value in truth.items():
        assert record.identified[name] == pytest.approx(value, rel=0.05)


JOINT = CAMPAIGN.replace("[sensitivity]", """[targets.brazilian]
sigma_t_MPa = 10.0
[targets.bending]
K_IC_MPa_sqrt_m = 1.2
[validation]
tests = ["brazilian"]
[sensitivity]""").replace("ucs_MPa = 120.0", "ucs_MPa = 150.0")


def joint_responses(kind: str, p: dict) -> dict:
    """The stand-in for each test: UCS as above but mostly from the bond cohesion; the Brazilian
    test's tensile strength from the bond tensile strength; K_IC from both."""
    if kind == "brazilian":
        return {"sigma_t_MPa": 0.25 * p["sigma_c"] + 0.01 * p["tau_c"], "P_max_kN_per_m": 1.0,
                "displacement_at_peak_mm": 0.1}
    if kind == "bending":
        return {"K_IC_MPa_sqrt_m": 0.02 * p["sigma_c"] + 0.005 * p["tau_c"], "P_max_kN_per_m": 2.0,
                "displacement_at_peak_mm": 0.2}
    return responses(p) | {"ucs_MPa": 1.5 * p["tau_c"] + 0.5 * p["sigma_c"]}


class JointExecutor(SyntheticExecutor):
    """Every test over `joint_responses`; the Brazilian run at E_c 15, mu 0.3 fails."""

    def run(self, specs, progress=None):
        out = []
        for spec in specs:
            p = dict(spec.params)
            if spec.kind == "brazilian" and p["E_c"] == 15 and p["mu"] == 0.3:
                out.append(RunResult("failed", {}, None, 0.0, "ValueError: unstable"))
            else:
                out.append(RunResult("ok", joint_responses(spec.kind, p), None, 0.0))
        return out


def test_joint_targets_free_more_parameters_and_are_recovered(tmp_path):
    """UCS, Brazilian and bending targets: range analysis picks tau_c as well, the loop fits
    every response, the Brazilian test (listed in [validation]) is a check only."""
    record = calibrate(planned(parse_campaign(JOINT, tmp_path)), JointExecutor())
    assert record.target_tests == {"ucs": ["E_GPa", "nu", "ucs_MPa"], "bending": ["K_IC_MPa_sqrt_m"]}
    assert record.sensitivity.chosen == ["E_c", "kn_ks", "sigma_c", "tau_c"]
    assert record.failed_runs == []  # the Brazilian test runs only at the identified point
    assert record.accepted and set(record.errors) == {"E_GPa", "nu", "ucs_MPa", "K_IC_MPa_sqrt_m"}
    p = record.identified_params
    for name, target in (("K_IC_MPa_sqrt_m", 1.2), ("ucs_MPa", 150.0)):
        assert joint_responses("bending" if name.startswith("K") else "ucs", p)[name] == \
            pytest.approx(target, rel=0.05)
    [check] = record.checks
    assert check.test == "brazilian" and check.lab == {"sigma_t_MPa": 10.0}
    sigma_t = joint_responses("brazilian", p)["sigma_t_MPa"]
    assert check.errors["sigma_t_MPa"] == pytest.approx(sigma_t / 10 - 1)
    assert record.validation is None


class RememberingExecutor(JointExecutor):
    """JointExecutor with a memory of the runs done, as the store is; it keeps the (test, seed)
    of the runs each call of `run` did anew."""

    def __init__(self):
        self.done, self.calls = set(), []

    def run(self, specs, progress=None):
        new = [spec for spec in dict((spec.key, spec) for spec in specs).values() if spec.key not in self.done]
        self.done |= {spec.key for spec in new}
        self.calls.append([(spec.kind, dict(spec.specimen)["seed"]) for spec in new])
        return super().run(specs, progress)


def test_the_validation_beams_and_the_other_packings_run_as_one_batch_beams_first(tmp_path):
    """After the search, the beams (the longest runs) and the other packings of each calibrated
    test go to the workers as one batch, so that none waits for another stage; the steps that
    read them run nothing more (the identifiability stage, which may run after them, off)."""
    text = JOINT.replace('tests = ["brazilian"]', 'tests = ["bending"]').replace(
        "[sensitivity]", "[specimen]\nbending_seeds = 2\n[sensitivity]") + \
        "[uncertainty]\nenabled = true\ndraws = 10\npackings = 3\n[identifiability]\nruns = false\n"
    executor = RememberingExecutor()
    record = calibrate(planned(parse_campaign(text, tmp_path)), executor)
    last = max(k for k, call in enumerate(executor.calls) if call)
    assert executor.calls[last] == [("bending", 1), ("bending", 2), ("ucs", 2), ("ucs", 3),
                                    ("brazilian", 2), ("brazilian", 3)]
    assert record.validation.seeds == [1, 2] and record.uncertainty.seeds == [1, 2, 3]


def test_a_failed_run_of_one_test_fails_its_parameter_set(tmp_path):
    text = JOINT.replace('tests = ["brazilian"]', 'tests = ["bending"]').replace(
        "sigma_t_MPa = 10.0",
        "sigma_t_MPa = 10.0\nweights = { sigma_t_MPa = 2 }\nspread = { sigma_t_MPa = 0.5 }",
    ) + "[uncertainty]\ndraws = 10\npackings = 2\n"
    record = calibrate(planned(parse_campaign(text, tmp_path)), JointExecutor())
    assert record.target_tests == {"ucs": ["E_GPa", "nu", "ucs_MPa"], "brazilian": ["sigma_t_MPa"]}
    assert record.weights == {"sigma_t_MPa": 2.0} and "sigma_t_MPa 2" in record.objective
    assert record.failed_runs == [FailedRun(stage="sensitivity (brazilian)", message="ValueError: unstable")]
    assert len(record.sensitivity.imputed_runs) == 1
    assert record.accepted and abs(record.errors["sigma_t_MPa"]) <= 0.05
    assert record.validation is not None and record.checks is None
    u = record.uncertainty  # on: the Brazilian target gives a spread
    assert u.spread == {"sigma_t_MPa": 0.5} and len(u.run_keys) == 4 and set(u.scatter) == set(record.targets)


SEARCH = """
[targets.ucs]
E_GPa = 50.0
nu = 0.2
ucs_MPa = 120.0
[search]
bounds = { E_c = [15, 35], kn_ks = [1, 3], sigma_c = [20, 60] }
fixed = { tau_c = 90, mu = 0.5 }
[surrogate]
samples = 12
checks = 2
[optimizer]
iterations = 60
"""


def two_valleys(p: dict) -> dict:
    """A stand-in whose targets are met at two points: kn/ks 1.5 and 2.5."""
    return {"E_GPa": 2.0 * p["E_c"], "nu": 0.1 + 0.4 * (p["kn_ks"] - 2) ** 2,
            "ucs_MPa": 3.0 * p["sigma_c"] + 0.1 * p["kn_ks"] ** 3}


class Workers:
    """A deterministic executor over `model` that runs `workers` parameter sets at once; it
    keeps the parameter sets of each call of `run`."""

    class store:
        @staticmethod
        def get(spec):
            return None

    def __init__(self, workers: int, model=two_valleys):
        self.workers, self.model, self.calls = workers, model, []

    def run(self, specs, progress=None):
        self.calls.append([dict(spec.params) for spec in specs])
        return [RunResult("ok", self.model(dict(spec.params)), None, 0.0) for spec in specs]


def test_distinct_optima_verified_together_whatever_the_workers(tmp_path):
    """A round verifies both distinct optima at once, on one worker or two alike (the same
    record); the point accepted is the one-candidate loop's (the search's own optimum),
    within the tolerance of every target. (The two valleys leave kn_ks not pinned: no identifiability
    runs, so that the last batch is the verification's.)"""
    campaign = planned(parse_campaign(SEARCH + "[identifiability]\nruns = false\n", tmp_path))
    serial, parallel = Workers(1), Workers(2)
    one, two = (calibrate(campaign, ex) for ex in (serial, parallel))
    assert one.model_dump() == two.model_dump() and two.accepted
    verified_together = parallel.calls[-1]
    assert serial.calls[-1] == verified_together and len(verified_together) == 2
    kn_ks = sorted(p["kn_ks"] for p in verified_together)
    assert kn_ks == pytest.approx([1.5, 2.5], abs=0.05)  # the two valleys, not one point twice
    assert all(abs(e) <= two.tolerance for it in two.iterations for e in it.errors.values())
    single = Workers(2)
    alone = calibrate(planned(parse_campaign(SEARCH + "[acceptance]\ncandidates = 1\n[identifiability]\nruns = false\n",
                                             tmp_path)), single)
    assert len(single.calls[-1]) == 1 and alone.identified == two.identified


def test_a_sensitivity_run_trains_the_surrogate_only_when_it_is_a_run_of_the_search(tmp_path):
    """Of the L16 runs, only the one at the fixed tau_c and mu and inside the box is reused."""
    text = SEARCH.replace("E_c = [15, 35]", "E_c = [15, 30]").replace("[search]", """[sensitivity]
array = "L16(4^5)"
levels = { E_c = [15, 20, 25, 30], kn_ks = [1.0, 1.67, 2.33, 3.0], sigma_c = [20, 30, 40, 50], tau_c = [50, 70, 90, 110], mu = [0.3, 0.4, 0.5, 0.6] }
[search]""")
    record = calibrate(planned(parse_campaign(text, tmp_path)), Workers(1, responses))
    [i] = record.samples.reused_sensitivity_runs
    assert record.sensitivity.runs[i] == {"E_c": 15.0, "kn_ks": 2.33, "sigma_c": 40.0, "tau_c": 90.0, "mu": 0.5}
    narrow = text.replace("E_c = [15, 30]", "E_c = [20, 30]")  # that run is now outside the box
    assert calibrate(planned(parse_campaign(narrow, tmp_path)), Workers(1, responses)) \
        .samples.reused_sensitivity_runs is None


class Specimens(Workers):
    """Workers that keep the R_min of each run's specimen, by the stage's parameter sets."""

    def run(self, specs, progress=None):
        self.calls.append([dict(spec.specimen)["rmin_mm"] for spec in specs])
        return [RunResult("ok", self.model(dict(spec.params)), None, 0.0) for spec in specs]


def test_sensitivity_runs_at_their_own_resolution_train_no_surrogate(tmp_path):
    """[sensitivity] rmin_mm: the array runs on coarser grains, every later run on the
    campaign's; the one array run inside the box is then not a run of the search."""
    text = SEARCH.replace("E_c = [15, 35]", "E_c = [15, 30]").replace("[search]", """[sensitivity]
array = "L16(4^5)"
levels = { E_c = [15, 20, 25, 30], kn_ks = [1.0, 1.67, 2.33, 3.0], sigma_c = [20, 30, 40, 50], tau_c = [50, 70, 90, 110], mu = [0.3, 0.4, 0.5, 0.6] }
rmin_mm = 0.5
[search]""")
    executor = Specimens(1, responses)
    record = calibrate(planned(parse_campaign(text, tmp_path)), executor)
    first, *later = executor.calls
    assert first == [0.5] * 16 and {r for call in later for r in call} == {0.25}
    assert len(later[0]) == 12 + 2  # the samples and the surrogate's checks: one batch
    assert record.samples.reused_sensitivity_runs is None and record.accepted
    assert record.sensitivity.rmin_mm == 0.5


FIRST_UCS = """
[targets.ucs]
E_GPa = 50.0
nu = 0.2
ucs_MPa = 100.0
[targets.bending]
K_IC_MPa_sqrt_m = 1.0
[validation]
tests = []
[search]
bounds = { E_c = [15, 35], kn_ks = [1, 3], sigma_c = [20, 50] }
fixed = { tau_c = 90, mu = 0.5 }
[surrogate]
samples = 8
checks = 1
[optimizer]
iterations = 40
[acceptance]
tolerance = 0.03
candidates = 1
"""


def wavy_ucs(kind: str, p: dict) -> dict:
    """A stand-in whose UCS wiggles 10 % over the box (as a packing's does), so that the
    surrogate's first optimum misses it; K_IC follows sigma_c."""
    if kind == "bending":
        return {"K_IC_MPa_sqrt_m": 0.03 * p["sigma_c"], "P_max_kN_per_m": 1.0, "displacement_at_peak_mm": 0.1}
    wiggle = 1 + 0.1 * np.sin(0.8 * p["sigma_c"]) * np.sin(30 * p["kn_ks"])
    return {"E_GPa": 2 * p["E_c"], "nu": 0.1 * p["kn_ks"], "ucs_MPa": 3 * p["sigma_c"] * wiggle}


def test_ucs_first_runs_a_beam_only_where_the_ucs_test_met_its_targets(tmp_path):
    """[acceptance] ucs_first: a round runs its point's UCS test, then the beam only where E, nu
    and UCS are within the tolerance; a point that missed is recorded with its UCS responses
    (no K_IC), its beam never run, and the campaign accepts the point it accepts without."""
    plain, first = ByTest(), ByTest()
    without = calibrate(planned(parse_campaign(FIRST_UCS, tmp_path)), plain)
    record = calibrate(planned(parse_campaign(FIRST_UCS + "ucs_first = true\n", tmp_path)), first)
    assert record.accepted and record.identified == without.identified
    missed, accepted = record.iterations
    assert set(missed.errors) == {"E_GPa", "nu", "ucs_MPa"} and "K_IC_MPa_sqrt_m" not in missed.verified
    assert max(abs(e) for e in missed.errors.values()) > record.tolerance
    assert len(accepted.errors) == 4 and all(abs(e) <= record.tolerance for e in accepted.errors.values())
    assert first.calls[-3:] == [["ucs"], ["ucs"], ["ucs", "bending"]]  # the last UCS run from the store
    assert plain.calls[-2:] == [["ucs", "bending"], ["ucs", "bending"]]


class ByTest(Workers):
    """Workers over `wavy_ucs` that keep the tests of each call of `run`."""

    def __init__(self):
        super().__init__(1)

    def run(self, specs, progress=None):
        self.calls.append([spec.kind for spec in specs])
        return [RunResult("ok", wavy_ucs(spec.kind, dict(spec.params)), None, 0.0) for spec in specs]


def test_samples_every_test_runs_the_beam_at_that_many_samples_spread_over_the_box(tmp_path):
    """Multi-fidelity with [surrogate] samples_every_test = 3 of 8: the samples' batch runs 8 + 1
    UCS tests and 3 + 1 beams (the check runs every test); the other samples are recorded
    without K_IC, and the corrected K_IC still leads to the point the targets ask for."""
    workers = ByTest()
    text = FIRST_UCS.replace("checks = 1", "checks = 1\ncoarse_samples = 12\nsamples_every_test = 3")
    record = calibrate(planned(parse_campaign(text, tmp_path)), workers)
    assert sorted(workers.calls[1]) == ["bending"] * 4 + ["ucs"] * 9
    with_beam = [r for r in record.samples.responses if "K_IC_MPa_sqrt_m" in r]
    assert len(with_beam) == 3 and all("ucs_MPa" in r for r in record.samples.responses)
    assert record.accepted


def test_spread_out_takes_the_centre_then_the_farthest_points():
    box = np.array([[0.0, 10.0], [0.0, 1.0]])
    x = np.array([[5.0, 0.5], [0.0, 0.0], [4.0, 0.6], [10.0, 1.0], [9.0, 0.9]])
    assert spread_out(x, box, 1) == [0]
    assert spread_out(x, box, 3) == [0, 1, 3]
    assert spread_out(x, box, 9) == [0, 1, 2, 3, 4]


@pytest.mark.parametrize("setting", ["coarse_samples = 12\nsamples_every_test = 9", "samples_every_test = 3"])
def test_samples_every_test_above_samples_or_without_coarse_runs_is_refused(setting, tmp_path):
    with pytest.raises(InputError, match="samples_every_test"):
        parse_campaign(FIRST_UCS.replace("checks = 1", "checks = 1\n" + setting), tmp_path)
