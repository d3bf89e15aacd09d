"""The first screen of a campaign: what will run, on what specimens, and about how long."""

import pytest

from rockcal.campaign.input.config import parse_campaign, SpecimenSettings
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.plan import screen as plan
from rockcal.campaign.plan.cost import grain_count
from rockcal.campaign.plan.screen import describe, stage_runs, stages
from rockcal.campaign.procedure.steps import calibrate
from rockcal.campaign.runs.spec import RunResult
from rockcal.campaign.runs.store import RunStore
from rockcal.specimens.specimen import random_packing
from tiny import tiny_campaign


@pytest.mark.parametrize("rmin_mm, cloud_porosity", [(0.4, 0.09), (0.3, 0.15)])
def test_grain_count_is_the_genesis_count(rmin_mm, cloud_porosity):
    settings = SpecimenSettings(rmin_mm=rmin_mm, cloud_porosity=cloud_porosity)
    made = random_packing(10, 20, rmin_mm, settings.radius_ratio, genesis=settings)
    assert grain_count(10, 20, settings) == pytest.approx(made.n_particles, rel=0.03)


def test_stages_and_the_expected_time(tmp_path):
    campaign = planned(parse_campaign("""
[targets.ucs]
E_GPa = 20.0
spread = { E_GPa = 1.0 }
[targets.bending]
K_IC_MPa_sqrt_m = 1.0
[specimen]
bending_seeds = 2
[sensitivity]
array = "L9(3^4)"
levels = { E_c = [10, 20, 30], sigma_c = [20, 40, 60] }
[surrogate]
samples = 12
checks = 2
[uncertainty]
packings = 4
""", tmp_path))
    assert stages(campaign) == [("sensitivity", "ucs", 9), ("samples and checks", "ucs", 14),
                                ("verification", "ucs", 1),
                                ("packings and validation", "bending", 2),
                                ("packings and validation", "ucs", 3), ("identifiability", "ucs", 6)]
    lines = describe(campaign, RunStore(tmp_path / "out"), workers=2)
    assert "about 12940 grains" in lines[0]
    assert lines[1] == ("stages: sensitivity 9, samples and checks 14, verification 1 a round (2 when the "
                        "surrogate has a second optimum), packings and validation 5, identifiability 6 to 12 (about 6 "
                        "to 12 UCS runs' time: each range it reads in the DEM runs each end 3 times, the widest range "
                        "not pinned first, the next where the DEM pins it, every searched parameter's at most; none "
                        "where the sheet pins every parameter): 35 runs, plus a second optimum's run and more rounds "
                        "if needed (at most 80 UCS runs)")
    assert lines[-1].startswith("expected: about ") and "33 UCS and 2 bending runs" in lines[-1]


def test_each_stage_runs_every_test_calibrated_against(tmp_path):
    campaign = planned(parse_campaign("""
[targets.ucs]
E_GPa = 20.0
[targets.brazilian]
sigma_t_MPa = 9.0
[specimen]
disk_diameter_mm = 40
[search]
bounds = { E_c = [10, 30] }
[surrogate]
samples = 12
checks = 2
""", tmp_path))
    assert stages(campaign) == [("samples and checks", "ucs", 14), ("samples and checks", "brazilian", 14),
                                ("verification", "ucs", 1), ("verification", "brazilian", 1),
                                ("identifiability", "ucs", 6), ("identifiability", "brazilian", 6)]
    lines = describe(campaign, RunStore(tmp_path / "out"), workers=1)
    assert "; disk D 40 mm, about 3252 grains" in lines[0]
    assert lines[1].endswith("each parameter set runs UCS and Brazilian")
    assert "21 UCS and 21 Brazilian runs" in lines[-1]


@pytest.mark.parametrize("specimen, says", [("", True), ('contact_stiffness = "pfc5"', False),
                                            ('dimensions = 3\nwidth_mm = 12\nheight_mm = 24\nrmin_mm = 0.75', False)])
def test_the_first_screen_says_when_no_fishtank_file_reproduces_the_contacts(tmp_path, specimen, says):
    """PFC 3.x/4.0's contacts (2D's default) have no FISHTank (PFC 5+) equivalent: the first
    screen says so and how to calibrate for PFC 5+; PFC 5's contacts (3D's only) need no word."""
    campaign = planned(parse_campaign(f"""
[targets.ucs]
E_GPa = 20.0
[specimen]
{specimen}
[search]
bounds = {{ E_c = [10, 30] }}
""", tmp_path))
    lines = [line for line in describe(campaign, RunStore(tmp_path / "out"), workers=None)
             if line.startswith("contacts: ")]
    assert len(lines) == says
    if says:
        assert 'PFC 3.x/4.0\'s (contact_stiffness = "pfc4"' in lines[0]
        assert 'no FISHTank file (PFC 5+) reproduces' in lines[0] and 'contact_stiffness = "pfc5"' in lines[0]


def test_coarser_sensitivity_runs_are_shown_and_expected_sooner(tmp_path, monkeypatch):
    monkeypatch.setattr(plan, "probe_ms_per_step", lambda: 0.66)  # one machine speed for both
    text = """
[targets.ucs]
E_GPa = 20.0
[sensitivity]
array = "L9(3^4)"
levels = { E_c = [10, 20, 30], sigma_c = [20, 40, 60] }
"""
    full = describe(planned(parse_campaign(text, tmp_path)), RunStore(tmp_path / "a"), workers=2)
    coarse = describe(planned(parse_campaign(text + "rmin_mm = 0.5\n", tmp_path)), RunStore(tmp_path / "b"), workers=2)
    assert "sensitivity 9 (R_min 0.5 mm), samples" in coarse[1] and "(R_min" not in full[1]

    def minutes(lines):
        number, unit = lines[-1].split("about ")[1].split(" ")[:2]
        return float(number) * {"s": 1 / 60, "min": 1, "h": 60}[unit]
    assert minutes(coarse) < minutes(full)


def test_a_last_short_round_shares_the_cores():
    """Three runs on two workers of two cores: a round of two, then the third on both cores."""
    from rockcal.campaign.plan.screen import LONE_RUN_SPEED_UP, stage_rounds

    assert stage_rounds(4, 2, cores=2) == 2
    assert stage_rounds(3, 2, cores=2) == pytest.approx(1 + 1 / LONE_RUN_SPEED_UP)
    assert stage_rounds(1, 2, cores=2) == pytest.approx(1 / LONE_RUN_SPEED_UP)
    assert stage_rounds(3, 1, cores=2) == pytest.approx(3 / LONE_RUN_SPEED_UP)  # each alone
    assert stage_rounds(3, 1, cores=1) == 3
    assert stage_rounds(3, 2, cores=1) == 2  # no core to spare


def test_the_campaign_bar_counts_expected_seconds_not_runs():
    """16 coarse sensitivity runs weigh less than 2 full-size ones: after the first stage the
    campaign's bar (and so its ETA) stands at the expected fraction of the time, and a run the
    store already held counts as no time spent."""
    from rockcal.cli.calibrate import _stage_progress

    progress = _stage_progress(True, {"sensitivity": 16, "samples and checks": 2},
                               {"sensitivity": (16, 60.0), "samples and checks": (2, 180.2)})

    def campaign():
        task = progress.bar.tasks[progress.campaign]
        return task.completed, task.total, task.fields["count"]

    progress("sensitivity", 0, 16)
    progress("sensitivity", 16, 16)
    assert campaign() == (60.0, 240, "16/18")  # whole seconds: a new total resets the rate
    progress("samples and checks", 1, 2)  # one from the store
    assert campaign() == (60.0, 150, "17/18")
    progress("samples and checks", 2, 2)
    assert campaign() == (150.1, 150, "18/18")


def test_a_machine_twice_as_slow_expects_twice_the_time(tmp_path, monkeypatch):
    """Before the store holds any run, the expected time follows this machine's engine probe."""
    from rockcal.campaign.plan import screen as plan

    campaign = planned(parse_campaign("[targets.ucs]\nE_GPa = 20.0\n[search]\nbounds = { E_c = [10, 30] }\n",
                                      tmp_path))
    store = RunStore(tmp_path / "out")
    monkeypatch.setattr(plan, "probe_ms_per_step", lambda: plan.REFERENCE_PROBE_MS)
    here = plan.expected_s(campaign, store, workers=2) - plan._main_process_s(campaign)
    monkeypatch.setattr(plan, "probe_ms_per_step", lambda: 2 * plan.REFERENCE_PROBE_MS)
    assert plan.expected_s(campaign, store, workers=2) - plan._main_process_s(campaign) == pytest.approx(2 * here)
    assert "0.5x the reference machine's" in describe(campaign, store, workers=2)[-1]



def test_other_work_on_the_cores_lengthens_the_estimate(tmp_path, monkeypatch):
    """Two runs at a time beside two CPU-bound processes get half the machine each: twice the
    time, and a last lone run no second core; the main process gets two thirds of a core."""
    from rockcal.campaign.plan import screen as plan

    campaign = planned(parse_campaign("[targets.ucs]\nE_GPa = 20.0\n[search]\nbounds = { E_c = [10, 30] }\n", tmp_path))
    store = RunStore(tmp_path / "out")

    def runs_s():
        return sum(seconds for _, seconds in plan.stage_times(campaign, store, workers=2).values())

    monkeypatch.setattr(plan, "busy_cores", lambda: (2, 0.0))
    idle, idle_main = runs_s(), plan._main_process_s(campaign)
    monkeypatch.setattr(plan, "busy_cores", lambda: (2, 2.0))
    assert runs_s() > 2 * idle
    assert plan._main_process_s(campaign) == pytest.approx(1.5 * idle_main)
    assert "other work asks for 2.0 cores of this machine's 2" in describe(campaign, store, workers=2)[-1]
    monkeypatch.setattr(plan, "busy_cores", lambda: (2, 4.0))  # more than the cores: a third each
    assert runs_s() > 2.9 * idle


def test_the_probe_counts_what_other_work_asks_for():
    """Two CPU-bound processes ready to run are two tasks besides this one, whatever share of
    the cores they get."""
    import subprocess
    import sys

    from rockcal.dem import cores

    if cores.others_runnable() is None:
        pytest.skip("no /proc/stat here")
    code = "import sys; print(flush=True); sys.stdin.close()\nwhile True: pass"
    hogs = [subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stdin=subprocess.PIPE)
            for _ in range(2)]
    try:
        for hog in hogs:
            hog.stdout.readline()  # spinning from here on
        assert min(cores.others_runnable() for _ in range(5)) >= 2
    finally:
        for hog in hogs:
            hog.kill()
            hog.wait()


class Twin:
    """A synthetic forward model with a single optimum (E from E_c, UCS from sigma_c) that
    reports its progress as the executors do: the runs it already holds at once, then each run
    done; a run asked for again is held (as the store holds it)."""

    def __init__(self):
        self.held, self.made = set(), 0

    def run(self, specs, progress):
        progress(sum(spec.key in self.held for spec in specs), len(specs))
        for spec in specs:
            if spec.key not in self.held:
                self.held.add(spec.key)
                self.made += 1
                progress(len({s.key for s in specs} & self.held), len(specs))
        return [RunResult("ok", {"E_GPa": dict(spec.params)["E_c"], "nu": 0.2, "ucs_MPa": dict(spec.params)["sigma_c"],
                                 "n_particles": 100}, None, 0.0) for spec in specs]


def test_two_candidates_on_a_single_optimum_make_the_planned_runs(tmp_path):
    """[acceptance] candidates = 2 plans the search's optimum only: where the surrogate has no
    second optimum, the campaign makes the runs the first screen counts, and the campaign's bar
    ends at that count without lowering its total while it runs; the identifiability stage's
    planned runs leave it at the end, the sheet pinning both parameters (within 10 %: the 5 %
    tolerance leaves each up to 5.3 % from the value found)."""
    from rockcal.cli.calibrate import _stage_progress

    text = tiny_campaign().replace("max_dem_runs = 9", "max_dem_runs = 9\ncandidates = 2")
    campaign = planned(parse_campaign(text + "[identifiability]\npinned_within = 0.1\n", tmp_path))
    counted = sum(stage_runs(campaign).values())
    assert counted == 6 + 1 + 1 + 6  # samples, check, the search's optimum, the identifiability stage's ends
    progress = _stage_progress(True, stage_runs(campaign), {stage: (n, 10.0 * n)
                                                            for stage, n in stage_runs(campaign).items()})
    counts = []

    def shown(stage, done, total):
        progress(stage, done, total)
        counts.append(progress.bar.tasks[progress.campaign].fields["count"])

    twin = Twin()
    with progress:
        record = calibrate(campaign, twin, shown)
    assert record.accepted and len(record.iterations) == 1  # the second searches found the same optimum
    assert all(r.pinned for r in record.identifiability.ranges.values())
    stage = 6  # the identifiability stage's planned runs
    assert twin.made == record.dem_runs == counted - stage
    assert counts[-1] == f"{counted - stage}/{counted}" and {count.split("/")[1] for count in counts} == {str(counted)}
    assert progress.bar.tasks[progress.campaign].fields["count"] == f"{counted - stage}/{counted - stage}"


def test_a_second_optimum_and_a_run_held_only_add_to_the_count():
    """A verification round that verifies a second optimum adds its run to the campaign's count;
    the identified point's first packing, held since its verification, is no run of the last
    stage, and a second round counts on from the first."""
    from rockcal.cli.calibrate import _stage_progress

    progress = _stage_progress(True, {"verification": 1, "packings and validation": 5},
                               {"verification": (1, 10.0), "packings and validation": (5, 50.0)})

    def campaign():
        return progress.bar.tasks[progress.campaign].fields["count"]

    progress("verification", 0, 2)
    assert campaign() == "0/7"  # grew by the second optimum's run
    progress("verification", 2, 2)
    progress("verification", 0, 1)  # a second round
    assert campaign() == "2/8"
    progress("verification", 1, 1)
    progress("packings and validation", 1, 6)  # the identified point's first packing, held
    assert campaign() == "3/8"
    progress("packings and validation", 6, 6)
    assert campaign() == "8/8"

