"""Which parameters the sheet pins, on a synthetic forward model (no DEM): tau_c moves none of
the UCS targets, so the accepted point leaves it free; the record marks it not pinned with a
range, read in the DEM, that holds the truth, and names the Brazilian test (its strength sees
tau_c most per run of lab work); with the Brazilian strength of the truth added to the targets,
the campaign recovers tau_c. A range read in the DEM reaches out to the runs that miss the
sheet by more than the surrogate's error, and holds the set. A searched parameter the
sensitivity runs show no target sees is warned of as soon as they are done."""

import json

import numpy as np
import pytest

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.plan.screen import describe, identifiability_cost, stages
from rockcal.campaign.procedure import pinning
from rockcal.campaign.procedure.steps import calibrate
from rockcal.campaign.runs.spec import RunResult
from rockcal.campaign.runs.store import RunStore
from rockcal.cli.calibrate import summary
from rockcal.inverse.identifiability import largest_error, parameter_ranges
from tiny import StandInExecutor

TRUE = {"E_c": 20.0, "sigma_c": 15.0, "tau_c": 60.0}


def ucs(p: dict) -> dict:
    return {"E_GPa": p["E_c"], "nu": 0.2, "ucs_MPa": 3 * p["sigma_c"], "ci_MPa": 1.2 * p["sigma_c"],
            "cd_MPa": 2.4 * p["sigma_c"], "n_particles": 100}


def others(p: dict) -> dict:
    """Each other test's strength: the Brazilian and the direct tension see tau_c, the
    confined test and the beam barely."""
    return {"brazilian": {"sigma_t_MPa": 0.1 * p["sigma_c"] + 0.05 * p["tau_c"]},
            "direct_tension": {"sigma_t_direct_MPa": 0.04 * p["sigma_c"] + 0.02 * p["tau_c"]},
            "biaxial": {"sigma1_MPa": 3 * p["sigma_c"] + 30.0},
            "bending": {"K_IC_MPa_sqrt_m": 0.1 * p["sigma_c"] + 0.001 * p["tau_c"]}}


FLAT_JOINT = {"fj_emod": "E_c", "fj_ten": "sigma_c", "fj_coh": "tau_c"}  # the same model on its parameters


class Executor(StandInExecutor):
    def __init__(self):
        self.kinds = []

    def result(self, spec):
        self.kinds.append(spec.kind)
        p = {FLAT_JOINT.get(name, name): value for name, value in dict(spec.params).items()}
        return RunResult("ok", ucs(p) if spec.kind == "ucs" else others(p)[spec.kind], None, 0.0)


ROUTES = {"2D": ("", ""), "3D": ("dimensions = 3", ""), "flat joint": ("", ""),
          "multi-fidelity": ("", "coarse_samples = 10\ncoarse_factor = 1.2")}
# the tests the ranking may name: by default those dearer than MOST_UCS_RUNS are left out
RANKED = {"2D": '["ucs", "brazilian", "direct_tension", "biaxial", "bending"]', "3D": '["ucs", "brazilian", "biaxial"]'}
NAMED = f"[identifiability]\ntests = {RANKED['2D']}\n"


def campaign_text(extra: str = "", route: str = "2D") -> str:
    specimen, surrogate = ROUTES[route]
    text = f"""
[targets.ucs]
E_GPa = {ucs(TRUE)["E_GPa"]!r}
ucs_MPa = {ucs(TRUE)["ucs_MPa"]!r}
{extra}
[specimen]
rmin_mm = 0.4
width_mm = 8
height_mm = 16
disk_diameter_mm = 12
beam_length_mm = 22
beam_height_mm = 8
notch_mm = 2.4
notch_width_mm = 1.0
span_mm = 16
{specimen}
[search]
bounds = {{ E_c = [10, 30], sigma_c = [8, 25], tau_c = [20, 100] }}
[surrogate]
samples = 12
checks = 2
{surrogate}
[optimizer]
iterations = 60
[acceptance]
tolerance = 0.02
max_dem_runs = 30
"""
    if route != "flat joint":
        return text
    for name, ours in FLAT_JOINT.items():
        text = text.replace(f"{ours} = [", f"{name} = [")
    return '[material]\nmodel = "flatjoint"\n' + text


@pytest.mark.parametrize("route", ROUTES)
def test_a_parameter_no_target_sees_is_not_pinned_and_the_brazilian_test_would_pin_it(route, tmp_path):
    ranked = NAMED if route != "3D" else f"[identifiability]\ntests = {RANKED['3D']}\n"
    campaign = planned(parse_campaign(campaign_text(route=route) + ranked, tmp_path))
    executor = Executor()
    record = calibrate(campaign, executor)
    assert record.accepted
    found = record.identifiability
    # the model is linear: the surrogate's error at the verified points is nil, the bands the tolerance's
    assert found.surrogate_error["E_GPa"] < 1e-6 and (found.pinned_within, found.pinned_share) == (0.05, 1)
    assert found.bands["E_GPa"] == pytest.approx((19.6, 20.4), abs=1e-5)
    named = {ours: name for name, ours in FLAT_JOINT.items()} if route == "flat joint" else {n: n for n in TRUE}
    for name in ("E_c", "sigma_c"):  # the targets pin them: recovered within 5 %
        assert found.ranges[named[name]].pinned, name
        assert record.identified[named[name]] == pytest.approx(TRUE[name], rel=0.05)
        assert found.ranges[named[name]].low <= TRUE[name] <= found.ranges[named[name]].high
    # a truly flat direction: both ends met the sheet at their first DEM runs, an end farther
    # than EDGE_GAP of the box from its bound pushed out towards it met it again, and no run
    # missed it: the range is the box, not pinned, the points found meeting it nearly as wide
    tau = found.ranges[named["tau_c"]]
    assert tau.verified_ends == ["low", "high"] and all(r.met for r in found.end_runs)
    assert 2 <= len(found.end_runs) <= 6 and {r.parameter for r in found.end_runs} == {named["tau_c"]}
    assert (tau.low, tau.high, tau.share) == (20, 100, 1) and not tau.pinned
    met = [r.point[named["tau_c"]] for r in found.end_runs]
    assert (tau.met_low, tau.met_high) == (min(met), max(met)) and tau.met_high - tau.met_low > 0.8 * 80
    assert min(tau.met_low - 20, 100 - tau.met_high) <= pinning.EDGE_GAP * 80
    assert [p[named["tau_c"]] for p in found.points] == [tau.met_low, tau.met_high]  # each other test ranks there
    assert found.tests[0].test == "brazilian" and found.tests[0].spread > 0.5
    in_2d = {"sigma_t_direct_MPa", "K_IC_MPa_sqrt_m"} if route != "3D" else set()  # tests 3D lacks
    assert {t.response for t in found.tests} == {"sigma_t_MPa", "sigma1_MPa", "ci_MPa", "cd_MPa"} | in_2d
    assert f"does not pin {named['tau_c']}: the points that meet it lie within {named['tau_c']} 20–100 (±" \
        f"{100 * (100 - record.identified[named['tau_c']]) / 20:.1f} % of the value found, 100 % of its box, read in the DEM: both ends met the sheet; met over {tau.met_low:.4g}–{tau.met_high:.4g}, bounded by " \
        f"runs that miss it beyond the surrogate's error or by the box) ({len(found.end_runs)} runs in the DEM). " \
        "Measure the Brazilian" in found.text
    assert found.runs == len(found.end_runs) + 2 * (2 + len(in_2d)) and executor.kinds.count("brazilian") == 2
    told = summary(record)["identifiability"]
    assert told["ranges"][named["tau_c"]]["pinned"] is False and told["tests"][0]["test"] == "brazilian"
    json.dumps(told)


def test_a_range_pins_where_the_value_found_lies_within_pinned_within_of_every_point_of_it():
    """kn/ks over 2.85-3.69, 24 % of a box 1.5-5: a truth at 2.85 lies 18.7 % below 3.384 found, so
    the range does not pin it at 5 %, whatever its share of the box; 3.1-3.3 with 3.2 found pins
    it (3.2 % at most), unless pinned_share asks for less of the box than its 5.7 %. A range's
    error is against its end nearest zero: -1.05 to -1.0 pins -1.02 (within 3 %), a range
    reaching zero pins nothing."""
    box = np.array([[1.5, 5.0]])
    ranges = [parameter_ranges(np.array([[low], [high]]), box, ["kn_ks"], np.array([found]), 0.05, share)["kn_ks"]
              for low, high, found, share in ((2.85, 3.69, 3.384, 1.0), (3.1, 3.3, 3.2, 1.0), (3.1, 3.3, 3.2, 0.05))]
    assert ranges[0]["share"] == pytest.approx(0.24) and not ranges[0]["pinned"]
    assert ranges[1]["pinned"] and not ranges[2]["pinned"]
    assert largest_error(2.85, 3.69, 3.384) == pytest.approx((3.384 - 2.85) / 2.85)
    assert largest_error(-1.05, -1.0, -1.02) == pytest.approx(0.03)
    assert largest_error(0.0, 0.1, 0.05) == largest_error(-0.1, 0.1, 0.0) == np.inf and largest_error(2, 2, 2) == 0


def test_with_the_brazilian_strength_added_the_sheet_pins_tau_c(tmp_path):
    value = others(TRUE)["brazilian"]["sigma_t_MPa"]
    again = calibrate(planned(parse_campaign(campaign_text(f"[targets.brazilian]\nsigma_t_MPa = {value!r}"),
                                             tmp_path)), Executor())
    assert again.accepted and all(r.pinned for r in again.identifiability.ranges.values())
    for name, truth in TRUE.items():
        assert again.identified[name] == pytest.approx(truth, rel=0.05), name
    assert "pins every searched parameter" in again.identifiability.text


def test_a_lab_spread_wider_than_the_tolerance_sets_the_bands(tmp_path):
    """E's spread (19 to 21 GPa, +-5 %) is wider than the 2 % tolerance: the points E_c may take
    widen to it; UCS's (44.5 to 45.5 MPa) is narrower: its band stays the tolerance's."""
    spread = "spread = { E_GPa = [19.0, 21.0], ucs_MPa = [44.5, 45.5] }\n[uncertainty]\ndraws = 20\npackings = 2"
    record = calibrate(planned(parse_campaign(campaign_text(spread) + NAMED, tmp_path)), Executor())
    found = record.identifiability
    assert found.bands == {"E_GPa": pytest.approx((19.0, 21.0), abs=1e-6),
                           "ucs_MPa": pytest.approx((44.1, 45.9), abs=1e-6)}
    assert (found.ranges["E_c"].low, found.ranges["E_c"].high) == (pytest.approx(19.0, abs=0.1),
                                                                    pytest.approx(21.0, abs=0.1))
    # a truth at 19 GPa lies 5.3 % from 20: the spread does not pin E_c within 5 %, whatever share of the box
    assert not found.ranges["E_c"].pinned and found.ranges["E_c"].share < 0.25 and found.ranges["sigma_c"].pinned
    assert "E_c 19–21 (±5.3 % of the value found, 10 % of its box, on the surrogate)" in found.text
    tau = found.ranges["tau_c"]
    assert not tau.pinned and tau.low <= TRUE["tau_c"] <= tau.high  # whatever the intervals' draws say of it
    assert found.tests[0].test == "brazilian"


def test_runs_that_miss_the_sheet_within_the_surrogate_s_error_do_not_bound_the_set(tmp_path, monkeypatch):
    """A surrogate's error of 11 % on UCS (this one has none) widens sigma_c's set to about
    +-16 % of the truth, not pinned; the DEM runs at its ends miss the 5 % tolerance, twice,
    and each end pulled halfway towards the accepted point twice (+-4 %) meets it. The misses
    lie within the surrogate's error, as the DEM's scatter between nearby points may: none
    bounds the set, the range reaches the box's bounds and holds the true set (sigma_c within
    5 % of 15 MPa), which the points met lie in; not pinned, and said so (within 8 %, which
    pins E_c's 19-21 GPa, and which the points met lie in)."""
    monkeypatch.setattr(pinning, "surrogate_error", lambda state: {"E_GPa": 0.0, "ucs_MPa": 0.11})
    text = campaign_text().replace(", tau_c = [20, 100]", "").replace("tolerance = 0.02", "tolerance = 0.05")
    found = calibrate(planned(parse_campaign(text + "[identifiability]\npinned_within = 0.08\n", tmp_path)),
                      Executor()).identifiability
    sigma = found.ranges["sigma_c"]
    assert [(r.side, r.met) for r in found.end_runs] == [("low", False), ("high", False)] * 2 + \
        [("low", True), ("high", True)]
    assert (sigma.low, sigma.high) == (8, 25) and 0.95 * 15 <= sigma.met_low < sigma.met_high <= 1.05 * 15
    assert sigma.verified_ends == ["low", "high"] and not sigma.pinned
    assert "sigma_c 8–25 (±125.0 % of the value found, 100 % of its box, read in the DEM: both ends met the sheet; met over " \
           f"{sigma.met_low:.4g}–{sigma.met_high:.4g}, bounded by runs that miss it beyond the surrogate's error or by the " \
           "box); in sigma_c the points found " \
           "meeting it lie within 8 % of the value found, but the runs did not bound the set that closely" in found.text


class Cliff(Executor):
    """UCS 40 % off the linear model's beyond 2.7 MPa of sigma_c's truth."""

    def result(self, spec):
        result = super().result(spec)
        off = dict(spec.params)["sigma_c"] - TRUE["sigma_c"]
        if spec.kind == "ucs" and abs(off) > 2.7:
            result.responses["ucs_MPa"] *= 1 + 0.4 * (1 if off > 0 else -1)
        return result


def test_a_side_is_bisected_on_past_its_first_point_that_meets_the_sheet(tmp_path, monkeypatch):
    """At a tolerance of 12 % the set is sigma_c within 12 % of 15 MPa; a surrogate's error
    of 25 % on UCS widens its set past the cliff, where the DEM runs at its ends miss by more
    than that: they bound the set. Pulled in halfway, each end meets the sheet, still farther
    than EDGE_GAP of the box from its miss: each side runs once more and misses within the
    surrogate's error, which bounds nothing. The range reaches the misses that bound the set
    and holds it, the points met lie in it."""
    monkeypatch.setattr(pinning, "surrogate_error", lambda state: {"E_GPa": 0.0, "ucs_MPa": 0.25})
    text = campaign_text().replace(", tau_c = [20, 100]", "").replace("tolerance = 0.02", "tolerance = 0.12")
    found = calibrate(planned(parse_campaign(text, tmp_path)), Cliff()).identifiability
    sigma, runs = found.ranges["sigma_c"], found.end_runs
    assert [(r.side, r.met) for r in runs] == [("low", False), ("high", False), ("low", True), ("high", True),
                                               ("low", False), ("high", False)]
    assert [abs(r.errors["ucs_MPa"]) > 0.12 + 0.25 for r in runs] == [True, True, False, False, False, False]
    assert (sigma.low, sigma.high) == (runs[0].point["sigma_c"], runs[1].point["sigma_c"])
    assert sigma.low < 0.88 * 15 <= sigma.met_low < sigma.met_high <= 1.12 * 15 < sigma.high
    assert not sigma.pinned and sigma.verified_ends == ["low", "high"]


def test_the_first_screen_plans_one_range_read_and_every_searched_parameter_s_at_most(tmp_path):
    """The plan: the UCS runs at the two ends of one range, each run 1 + BISECTIONS times (CI
    and CD read there), and each lacking test's at the ends, none dearer than MOST_UCS_RUNS
    unless named; at most, each of the three searched parameters' ranges read alike; none with
    runs = false."""
    campaign = planned(parse_campaign(campaign_text(), tmp_path))
    read = 2 * (1 + pinning.BISECTIONS)
    assert [(test, n) for stage, test, n in stages(campaign) if stage == "identifiability"] == [("ucs", read)]
    assert identifiability_cost(campaign) == ((read, 3 * read), (pytest.approx(read), pytest.approx(3 * read)))
    store = RunStore(tmp_path / "out")
    assert f"identifiability {read} to {3 * read} (about {read} to {3 * read} UCS runs' time: each range it reads in " \
           "the DEM runs each end 3 times, the widest range not pinned first" in describe(campaign, store, workers=None)[1]
    named = planned(parse_campaign(campaign_text() + NAMED, tmp_path))
    assert identifiability_cost(named)[0] == (read + 2 * 4, 3 * read + 2 * 4)  # and the four other tests at each end
    off = planned(parse_campaign(campaign_text() + "[identifiability]\nruns = false\n", tmp_path))
    assert "identifiability" not in describe(off, store, workers=None)[1]


def test_runs_off_judge_the_parameters_without_a_run(tmp_path):
    text = campaign_text() + '[identifiability]\nruns = false\npinned_share = 0.5\n'
    executor = Executor()
    record = calibrate(planned(parse_campaign(text, tmp_path)), executor)
    assert not record.identifiability.ranges["tau_c"].pinned and record.identifiability.tests == []
    assert record.identifiability.runs == 0 and "runs = false" in record.identifiability.text
    assert set(executor.kinds) == {"ucs"}


def test_named_tests_alone_are_ranked(tmp_path):
    text = campaign_text() + '[identifiability]\ntests = ["biaxial"]\n'
    record = calibrate(planned(parse_campaign(text, tmp_path)), Executor())
    assert [t.test for t in record.identifiability.tests] == ["biaxial"]
    assert "No response run at the ends (sigma1_MPa) varies" in record.identifiability.text  # it barely moves


def test_a_parameter_the_sensitivity_runs_show_no_target_sees_is_warned_of_at_once(tmp_path):
    text = campaign_text() + """
[sensitivity]
array = "L9(3^4)"
levels = { E_c = [10, 20, 30], sigma_c = [8, 15, 25], tau_c = [20, 60, 100] }
"""
    notes = []

    class Progress:
        def __call__(self, stage, done, total):
            notes.append(("stage", stage))

        def note(self, text):
            notes.append(("note", text))

    record = calibrate(planned(parse_campaign(text, tmp_path)), Executor(), Progress())
    assert record.sensitivity.unseen == ["tau_c"]
    warned = notes.index(("note", next(text for kind, text in notes if kind == "note")))
    assert notes[warned][1].startswith("tau_c's effect on every target is below the tolerance (±2 %)")
    assert ("stage", "samples and checks") not in notes[:warned]  # before the surrogate's runs


def test_the_summary_the_notebook_and_the_report_say_which_parameter_is_not_pinned(tmp_path, capsys):
    from rockcal.api import Calibration
    from rockcal.campaign.outputs.figures import _meeting_set
    from rockcal.campaign.outputs.report import _identifiability
    from rockcal.cli.calibrate import _print_summary

    record = calibrate(planned(parse_campaign(campaign_text() + NAMED, tmp_path)), Executor())
    _print_summary(record, tmp_path / "report.html", False, {})
    table = capsys.readouterr().out
    assert "not pinned by the sheet" in table and "identifiability: the sheet does not pin tau_c" in table
    shown = Calibration(record, tmp_path)
    assert "identifiability: the sheet does not pin tau_c" in repr(shown)
    assert "Measure the Brazilian" in shown._repr_html_() and shown.identifiability.ranges["E_c"].pinned
    section = _identifiability(record)
    tau = record.identifiability.ranges["tau_c"]
    assert section.startswith("<h3>Identifiability</h3><p>The sheet does not pin tau_c")
    error = 100 * (100 - record.identified["tau_c"]) / 20  # a truth at 100 from the value found, against 20
    assert "<th>largest error of the value found</th><th>share of its box</th><th>pinned (within 5 %)</th>" in section
    assert f"<td>tau_c</td><td>{tau.low:.4g}</td><td>{tau.high:.4g}</td><td>{error:.1f} %</td><td>{100 * tau.share:.0f} %" \
           "</td><td>no</td>" \
           f"<td>ends met: low, high; met over {tau.met_low:.4g}–{tau.met_high:.4g}</td>" in section
    assert "<td>low</td><td>" in section and "</td><td>yes</td></tr>" in section  # the ends' runs
    assert "<td>1</td><td>measure the Brazilian (indirect tensile) strength</td><td>sigma_t_MPa</td>" in section
    assert _meeting_set(record, None, tmp_path / "meeting_set.png") is None and (tmp_path / "meeting_set.png").exists()
