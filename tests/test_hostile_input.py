"""Hostile input, generated (Hypothesis): campaign files and argument lists of `rockcal calibrate
--dry-run` and `rockcal simulate <test>`. Whatever the input, rockcal ends with exit 0, with
exit 2 and one line `rockcal: error: <field>: ...` on stderr (or exit 1 and `rockcal: run failed:`
for a run whose physics failed), never a traceback, writes nothing
when it refuses (a dry run never writes), prints strict JSON with --json, and keeps within a
time and a memory bound.

Each case runs in this process (`rockcal.cli.app.main`, sys.argv set, SystemExit caught) in a
fresh folder that is its working directory, under:
- a time bound: `signal.setitimer` raises `CaseTimeout` in the case past its bound of the
  process's CPU time (ITIMER_PROF, so that a busy machine does not fail a case), or past
  WALL_FACTOR times it of wall time (ITIMER_REAL: a case that waits);
- a memory bound: the address space (`resource.RLIMIT_AS`) is capped at the process's size
  plus MEMORY_HEADROOM for the case and restored after, so that a huge allocation fails at once
  as a MemoryError (seen as a traceback) instead of swapping the machine; tracemalloc was not
  chosen: it slows every case and does not stop the allocation;
- stdout (UTF-8, strict) and stderr (UTF-8, backslashreplace) as a UTF-8 locale's process has
  them; Python warnings shown as a fresh process shows them (on stderr).
The state `main` leaves in the process (its command registrations, $ROCKCAL_MAX_GRAINS, numba's
threads, the cwd) is put back after each case.

Profiles: the default runs few examples (the quick loop; `simulate` cases stop where the DEM
run would begin, `EngineReached`); `@pytest.mark.slow` runs many, `simulate` ones through the
engine on specimens of at most SIM_MAX_GRAINS grains, and sweeps every option of `calibrate` and
`simulate <test>` (and every `--set` parameter) through its extremes one at a time. Examples are
derandomized and no example database is written: each run tries the same inputs.

`test_found_*` hold the smallest failing inputs the properties found, one case each: they fail
until rockcal is fixed, and then keep it fixed.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import re
import signal
import sys
import tempfile
import time
import traceback
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import hostile_strategies as hs
import numba
import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

from rockcal.campaign.input.config import SpecimenSettings, embedded_rocks

try:
    import resource
except ImportError:  # not on Windows: no memory bound there
    resource = None

MEMORY_HEADROOM = 1536 * 2**20  # bytes a case may add to the process's address space
DRY_RUN_S = 15.0  # CPU-time bound of a dry run (warm: 0.1 s; the first in a process: ~3 s; ldb: ~5 s)
SIM_CHECK_S = 10.0  # of a simulate case stopped where the DEM run would begin
# ROCKCAL_HOSTILE_EXAMPLES=N: the long profile by hand, N campaign files (1000 found the defects
# fixed so far) and the sweeps of every option at every extreme (about 10 min on 2 cores); CI's
# slow profile draws fewer
LONG = int(os.environ.get("ROCKCAL_HOSTILE_EXAMPLES", "0"))
long_only = pytest.mark.skipif(not LONG, reason="the long profile: set ROCKCAL_HOSTILE_EXAMPLES")
SIM_RUN_S = 60.0  # of a simulate case run through the engine (slow profile)
WALL_FACTOR = 4  # the wall-time bound is this many times the CPU-time bound (busy machines)
SIM_MAX_GRAINS = 400  # `rockcal --max-grains` of every simulate case: a tiny specimen at most
ERROR_LINE = re.compile(r"rockcal: error: [^:\s][^\n]*?: \S")

_COMMON = {"deadline": None, "derandomize": True, "database": None, "print_blob": False,
           "suppress_health_check": [HealthCheck.too_slow, HealthCheck.data_too_large,
                                     HealthCheck.large_base_example, HealthCheck.filter_too_much]}
QUICK = {**_COMMON, "phases": [Phase.explicit, Phase.generate]}  # a failure shows its example unshrunk
SLOW = {**_COMMON, "phases": [Phase.explicit, Phase.generate, Phase.shrink]}


class CaseTimeout(BaseException):
    """The case ran past its time bound (a BaseException: no `except Exception` swallows it)."""


class EngineReached(BaseException):
    """A simulate case passed every check and reached the DEM run (quick profile: stopped)."""


class NotADryRun(BaseException):
    """A calibrate case would have run a campaign: never allowed here."""


# ---------------------------------------------------------------------------------------------
# running a case

@dataclass
class Outcome:
    argv: list
    code: object = None  # exit code, or "engine" where a stopped simulate case reached the DEM
    stdout: str = ""
    stderr: str = ""
    exception: str | None = None  # the traceback's last line and where it was raised
    seconds: float = 0.0
    changed: list = field(default_factory=list)  # files made, changed or removed in the folder

    def __str__(self) -> str:
        argv = [a if len(a) < 120 else a[:60] + f"...({len(a)} chars)" for a in self.argv]
        return (f"argv={argv!r}\n  exit={self.code!r} in {self.seconds:.2f} s"
                f"\n  stdout={self.stdout[:300]!r}\n  stderr={self.stderr[:600]!r}"
                + (f"\n  exception: {self.exception}" if self.exception else "")
                + (f"\n  written: {self.changed[:10]}" if self.changed else ""))


def _tree(root: Path) -> dict:
    found = {}
    for folder, dirs, files in os.walk(root):
        for name in dirs + files:
            p = Path(folder, name)
            try:
                s = p.lstat()
                found[str(p.relative_to(root))] = (s.st_size, s.st_mtime_ns)
            except OSError:
                pass
    return found


def _vm_bytes() -> int | None:
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmSize:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        return None
    return None


@contextlib.contextmanager
def _memory_bound():
    size = _vm_bytes() if resource is not None else None
    if size is None:
        yield
        return
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    limit = size + MEMORY_HEADROOM
    if hard != resource.RLIM_INFINITY:
        limit = min(limit, hard)
    resource.setrlimit(resource.RLIMIT_AS, (limit, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


@contextlib.contextmanager
def _time_bound(cpu_s: float):
    """CaseTimeout past `cpu_s` of the process's CPU time (SIGPROF: other processes on the
    machine do not count), or past WALL_FACTOR times that of wall time (SIGALRM: a case
    that waits without computing)."""
    def alarm(signum, frame):
        kind = "CPU" if signum == signal.SIGPROF else "wall"
        raise CaseTimeout(f"past the time bound of {cpu_s if kind == 'CPU' else WALL_FACTOR * cpu_s:g} s of {kind} time")

    old = {sig: signal.signal(sig, alarm) for sig in (signal.SIGALRM, signal.SIGPROF)}
    signal.setitimer(signal.ITIMER_PROF, cpu_s)
    signal.setitimer(signal.ITIMER_REAL, WALL_FACTOR * cpu_s)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.setitimer(signal.ITIMER_PROF, 0)
        for sig, handler in old.items():
            signal.signal(sig, handler)


@contextlib.contextmanager
def _engine_stopped():
    """Every lab test's DEM run raises EngineReached (quick profile)."""
    from rockcal.labtests.registry import LAB_TESTS

    def stop(*args, **kwargs):
        raise EngineReached()

    saved = {name: test.run for name, test in LAB_TESTS.items()}
    for test in LAB_TESTS.values():
        object.__setattr__(test, "run", stop)  # a frozen dataclass
    try:
        yield
    finally:
        for name, test in LAB_TESTS.items():
            object.__setattr__(test, "run", saved[name])


@contextlib.contextmanager
def _no_campaign_runs():
    """A calibrate case that gets past --dry-run raises NotADryRun instead of running."""
    from rockcal.cli import calibrate

    def refuse(*args, **kwargs):
        raise NotADryRun()

    saved = calibrate._run_campaign
    calibrate._run_campaign = refuse
    try:
        yield
    finally:
        calibrate._run_campaign = saved


@contextlib.contextmanager
def _process_state_kept():
    """Put back what `main` changes in the process: argv, cwd, environment, its registrations,
    numba's threads and the engine's thread policy."""
    from rockcal.cli import app as cli
    from rockcal.dem import simulate as engine

    argv, cwd, environ = list(sys.argv), os.getcwd(), dict(os.environ)
    groups, commands = list(cli.app.registered_groups), list(cli.app.registered_commands)
    threads, follow = numba.get_num_threads(), engine._follow_load
    try:
        yield
    finally:
        sys.argv[:] = argv
        os.chdir(cwd)
        os.environ.clear()
        os.environ.update(environ)
        cli.app.registered_groups[:] = groups
        cli.app.registered_commands[:] = commands
        numba.set_num_threads(threads)
        engine._follow_load = follow


def _show_on_stderr(message, category, filename, lineno, file=None, line=None) -> None:
    sys.stderr.write(warnings.formatwarning(message, category, filename, lineno, line))


def run_cli(argv: list, folder: Path, seconds: float, env: dict | None = None, engine: bool = True) -> Outcome:
    """`rockcal ARGV` in this process, in `folder`, under the time and memory bounds."""
    from rockcal.cli.app import main

    outcome = Outcome(list(argv))
    before = _tree(folder)
    out_b, err_b = io.BytesIO(), io.BytesIO()
    out = io.TextIOWrapper(out_b, encoding="utf-8", errors="strict", write_through=True)
    err = io.TextIOWrapper(err_b, encoding="utf-8", errors="backslashreplace", write_through=True)
    started = time.perf_counter()
    with _process_state_kept(), _no_campaign_runs(), (contextlib.nullcontext() if engine else _engine_stopped()):
        os.chdir(folder)
        os.environ.update(env or {})
        sys.argv[:] = ["rockcal", *argv]
        try:
            with warnings.catch_warnings(), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
                warnings.simplefilter("default")
                warnings.showwarning = _show_on_stderr  # as rockcal's own process shows them
                with _memory_bound(), _time_bound(seconds):
                    main()
            outcome.code = 0
        except SystemExit as exc:
            outcome.code = 0 if exc.code is None else exc.code
        except EngineReached:
            outcome.code = "engine"
        except (Exception, CaseTimeout, NotADryRun) as exc:  # noqa: BLE001 (any of them is the finding)
            frames = traceback.extract_tb(exc.__traceback__)
            where = next((f"{Path(f.filename).name}:{f.lineno} in {f.name}" for f in reversed(frames)
                          if "rockcal" in f.filename), frames[-1].name if frames else "?")
            outcome.exception = f"{type(exc).__name__}: {str(exc)[:300]} (raised at {where})"
    outcome.seconds = time.perf_counter() - started
    outcome.stdout = out_b.getvalue().decode("utf-8", "backslashreplace")
    outcome.stderr = err_b.getvalue().decode("utf-8", "backslashreplace")
    after = _tree(folder)
    outcome.changed = sorted(k for k in before.keys() | after.keys() if before.get(k) != after.get(k))
    return outcome


def _strict_json(text: str):
    def refuse(constant):
        raise ValueError(f"{constant} is not JSON")
    return json.loads(text, parse_constant=refuse)


def check(outcome: Outcome, *, writes: bool, as_json: bool) -> None:
    """The rule of the project for one case; `writes`: may it write files when it succeeds."""
    assert outcome.exception is None, f"traceback: {outcome}"
    assert outcome.code in (0, 1, 2, "engine"), f"exit code {outcome.code!r}: {outcome}"
    assert "Traceback" not in outcome.stdout + outcome.stderr, f"a traceback in the output: {outcome}"
    if outcome.code == 1:  # a run that failed (the physics, not the input): said in one line
        assert outcome.stderr.splitlines()[-1].startswith("rockcal: run failed: "), f"exit 1 unexplained: {outcome}"
        return
    if outcome.code == 2:
        lines = outcome.stderr.splitlines()
        assert len(lines) == 1 and outcome.stderr.endswith("\n"), f"not one line on stderr: {outcome}"
        assert ERROR_LINE.match(lines[0]), f"not `rockcal: error: <field>: ...`: {outcome}"
        assert not outcome.changed, f"refused, yet wrote: {outcome}"
        return
    if not writes or outcome.code == "engine":
        assert not outcome.changed, f"wrote, where nothing may be written: {outcome}"
    if outcome.code == 0 and as_json and "--help" not in outcome.argv:
        try:
            _strict_json(outcome.stdout)
        except ValueError as exc:
            raise AssertionError(f"--json printed no strict JSON ({exc}): {outcome}") from None


# ---------------------------------------------------------------------------------------------
# campaign files: `rockcal calibrate FILE --dry-run --json`

CAMPAIGN = "campaign.toml"


def _write_case(folder: Path, case: hs.CampaignCase) -> None:
    with open(folder / CAMPAIGN, "wb") as f:
        f.write(case.text)
        if case.size is not None:
            f.truncate(case.size)  # sparse: larger than rockcal reads, written in no time
    for name, data in case.files.items():
        (folder / name).write_bytes(data)


def campaign_file_property(case: hs.CampaignCase) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        _write_case(folder, case)
        outcome = run_cli(["calibrate", "--dry-run", "--json", CAMPAIGN, "--out", "out"], folder, DRY_RUN_S)
        check(outcome, writes=False, as_json=True)


@settings(max_examples=15, **QUICK)
@given(hs.campaign_cases())
def test_campaign_file(case):
    campaign_file_property(case)


@pytest.mark.slow
@settings(max_examples=LONG or 150, **SLOW)
@given(hs.campaign_cases())
def test_campaign_file_many(case):
    campaign_file_property(case)


@settings(max_examples=12, **QUICK)
@given(hs.flat_joint_cases())
def test_flat_joint_campaign_file(case):
    """The flat-jointed material's bounds, fixed values and sensitivity levels: planned, or
    refused in one line naming the key, before any run."""
    campaign_file_property(case)


@pytest.mark.slow
@settings(max_examples=LONG or 100, **SLOW)
@given(hs.flat_joint_cases())
def test_flat_joint_campaign_file_many(case):
    campaign_file_property(case)


def test_the_base_campaigns_plan(tmp_path):
    """Every case starts from a valid campaign: the base with each optional section plans."""
    for optional in [(), *[(p,) for p in hs.OPTIONAL], tuple(hs.OPTIONAL)]:
        case = hs.CampaignCase(hs.toml_dumps(hs.base_campaign(optional)).encode())
        folder = Path(tempfile.mkdtemp(dir=tmp_path))
        _write_case(folder, case)
        outcome = run_cli(["calibrate", "--dry-run", "--json", CAMPAIGN], folder, DRY_RUN_S)
        assert outcome.code == 0, f"{optional}: {outcome}"


# ---------------------------------------------------------------------------------------------
# argument lists of `rockcal calibrate --dry-run`

COMMAND = hs.cli_command()
GLOBAL = hs.options_of(COMMAND)
CALIBRATE = hs.options_of(COMMAND.commands["calibrate"])
SIMULATE = {name: hs.options_of(cmd) for name, cmd in COMMAND.commands["simulate"].commands.items()}
CONFIG_TEXT = [CAMPAIGN, *embedded_rocks(), *(rock.upper() for rock in embedded_rocks()), "missing", "missing.toml",
               "/dev/zero", "/dev/null", "/proc/self/mem", CAMPAIGN + "/", ".", "", "a" * 300, "a" * 300 + ".toml",
               "\udcff.toml", "-"]
GRAIN_LIMIT = "ROCKCAL_MAX_GRAINS"  # rockcal.specimens.grain_limit.ENV


@st.composite
def _option(draw, table: dict, never: tuple = ()) -> list:
    """One option of a table with a hostile value (a flag given, or given a value)."""
    flag = draw(st.sampled_from([f for f in table if f not in never]))
    param = table[flag]
    if getattr(param, "is_flag", False):
        return [flag] if draw(st.booleans()) else [f"{flag}={draw(hs.arg_text)}"]
    if getattr(param, "multiple", False):
        return [flag, draw(hs.set_values(None))]
    return [flag, draw(hs.option_values(param, SpecimenSettings.model_fields.get(param.name)))]


@st.composite
def _extras(draw) -> list:
    return draw(st.sampled_from([["--nope"], ["extra"], ["--", "x"], ["-x"], ["--json", "--json"]]))


@st.composite
def calibrate_argv(draw) -> tuple[list, dict]:
    """(argv, environment) of a dry run: the global options, the calibrate options (--dry-run
    always first: no hostile value can take it), a config argument."""
    argv = []
    if draw(st.booleans()):
        argv += ["--max-grains", draw(hs.number_text)]
    argv += ["calibrate", "--dry-run", "--json"]
    config = draw(st.one_of(st.just(CAMPAIGN), st.sampled_from(CONFIG_TEXT), hs.arg_text))
    opts = []
    for _ in range(draw(st.integers(0, 3))):
        opts += draw(_option(CALIBRATE, never=("--dry-run", "--help")))
    if draw(st.integers(0, 4)) == 0:
        opts += draw(_extras())
    if "--out" not in opts:
        opts += ["--out", "out"]
    env = {GRAIN_LIMIT: draw(hs.arg_text)} if draw(st.integers(0, 5)) == 0 else {}
    return argv + [config, *opts], env


def calibrate_argv_property(case) -> None:
    argv, env = case
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / CAMPAIGN).write_text(hs.toml_dumps(hs.base_campaign()))
        check(run_cli(argv, folder, DRY_RUN_S, env), writes=False, as_json=True)


@settings(max_examples=10, **QUICK)
@given(calibrate_argv())
def test_calibrate_arguments(case):
    calibrate_argv_property(case)


@pytest.mark.slow
@settings(max_examples=LONG or 100, **SLOW)
@given(calibrate_argv())
def test_calibrate_arguments_many(case):
    calibrate_argv_property(case)


def _max_grains_of_base() -> int:
    """The most grains of a specimen the base campaign (all its sections) plans."""
    from rockcal.campaign.input.config import parse_campaign
    from rockcal.campaign.plan.planned import planned
    from rockcal.campaign.plan.screen import specimens
    from rockcal.specimens.grain_limit import expected_grains
    from rockcal.labtests.registry import lab_test

    campaign = planned(parse_campaign(hs.toml_dumps(hs.base_campaign(tuple(hs.OPTIONAL))), Path.cwd()))
    most = 0.0
    for test, s in specimens(campaign):
        p = lab_test(test).packing(s)
        most = max(most, expected_grains(p["width_mm"], p["height_mm"], p["rmin_mm"], p["radius_ratio"],
                                         p["genesis"].cloud_porosity))
    return math.ceil(most)


def max_grains_property(limit: int) -> None:
    """A grain limit the campaign's specimens are within is no reason to refuse its plan, in a
    fresh process (the engine-speed probe is cached per process: cleared)."""
    from rockcal.campaign.plan import engine_speed

    for cached in vars(engine_speed).values():  # as a fresh process: the probe measured anew
        if callable(getattr(cached, "cache_clear", None)):
            cached.cache_clear()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / CAMPAIGN).write_text(hs.toml_dumps(hs.base_campaign(tuple(hs.OPTIONAL))))
        outcome = run_cli(["--max-grains", str(limit), "calibrate", "--dry-run", "--json", CAMPAIGN],
                          folder, DRY_RUN_S)
        assert outcome.code == 0, f"a limit of {limit} grains, the specimens within it: {outcome}"


@settings(max_examples=6, **QUICK)
@given(st.integers(min_value=_max_grains_of_base(), max_value=2**63 - 1))
def test_a_grain_limit_above_the_specimens_plans(limit):
    max_grains_property(limit)


@pytest.mark.slow
@settings(max_examples=LONG // 30 or 10, **SLOW)
@given(st.integers(min_value=_max_grains_of_base(), max_value=2**63 - 1))
def test_a_grain_limit_above_the_specimens_plans_many(limit):
    max_grains_property(limit)


# ---------------------------------------------------------------------------------------------
# argument lists of `rockcal simulate <test>`

def tiny_geometry(table: dict) -> list:
    """A test's specimen at a tenth of its default size: each length option (`--*-mm` but
    the resolution --rmin-mm) at a tenth of its default."""
    argv = []
    for flag, param in table.items():
        if param.name.endswith("_mm") and param.name != "rmin_mm" and isinstance(param.default, float):
            argv += [flag, f"{param.default / 10:g}"]
    return argv


@st.composite
def simulate_argv(draw, drop: bool = True) -> list:
    """`rockcal --max-grains SIM_MAX_GRAINS simulate <test>` on its tiny specimen, with one to
    three options given hostile values, a --set, junk, or (`drop`) a tiny-geometry option left
    out: the default size, past the grain limit, except where rockcal ships the packing (it
    makes no genesis of it then, and runs it whatever the limit)."""
    test = draw(st.sampled_from(sorted(SIMULATE)))
    table = SIMULATE[test]
    geometry = tiny_geometry(table)
    cap = ["--max-grains", str(SIM_MAX_GRAINS)]
    if draw(st.integers(0, 9)) == 0:  # a limit that is no limit: refused before anything runs
        cap = ["--max-grains", draw(st.sampled_from(["0", "-1", "", "abc", "1.5", "nan", "10" * 50]))]
    opts = []
    for _ in range(draw(st.integers(1, 3))):
        kind = draw(st.sampled_from(["option", "option", "set", "drop", "extra"] if drop else
                                    ["option", "option", "set", "extra"]))
        if kind == "option":
            opts += draw(_option(table, never=("--help",)))
        elif kind == "set":
            model = draw(st.sampled_from(list(hs.MATERIALS)))
            opts += ["--model", model, "--set", draw(hs.set_values(model))]
        elif kind == "drop" and geometry:
            i = 2 * draw(st.integers(0, len(geometry) // 2 - 1))
            geometry = geometry[:i] + geometry[i + 2:]
        else:
            opts += draw(_extras())
    if draw(st.booleans()):
        opts += ["--json"]
    if draw(st.booleans()) and "--out" not in opts:
        opts += ["--out", "out"]
    return [*cap, "simulate", test, *geometry, *opts]


def simulate_property(argv: list, engine: bool) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        outcome = run_cli(argv, Path(tmp), SIM_RUN_S if engine else SIM_CHECK_S, engine=engine)
        check(outcome, writes="--out" in argv, as_json="--json" in argv)


@settings(max_examples=10, **QUICK)
@given(simulate_argv())
def test_simulate_arguments(argv):
    simulate_property(argv, engine=False)


@pytest.mark.slow
@settings(max_examples=LONG // 6 or 12, **SLOW)
@given(simulate_argv(drop=False))
def test_simulate_arguments_run(argv):
    simulate_property(argv, engine=True)


def test_the_tiny_specimens_are_accepted(tmp_path):
    """The simulate cases start from specimens within the grain limit that every check accepts."""
    for test, table in SIMULATE.items():
        outcome = run_cli(["--max-grains", str(SIM_MAX_GRAINS), "simulate", test, *tiny_geometry(table)],
                          tmp_path, SIM_CHECK_S, engine=False)
        assert outcome.code == "engine", f"{test}: {outcome}"


# ---------------------------------------------------------------------------------------------
# every option at every extreme, one at a time (slow): what random draws reach only by luck

SWEEP_FLOATS = ["0", "-0", "-1", "nan", "inf", "-inf", "1e300", "-1e300", "5e-324", "1e309", "", "abc",
                str(2**63), "9" * 5000]


def _sweep_values(param) -> list[str]:
    info = SpecimenSettings.model_fields.get(param.name)
    near = [hs._text(b) for b in hs._bounds_of(info)]
    annotation = param.type_descriptor.annotation
    if annotation is int:
        return [*near, *hs.INT_TEXT]
    if annotation is float:
        return [*near, *SWEEP_FLOATS]
    if annotation is Path:
        return hs.PATH_TEXT
    return ["", "abc", "\udcff", "a" * 5000, "0", "nan", "-1", "1,2", "0,0", "1e300,1"]


def _sweep(cases: list[list], run) -> None:
    failures = []
    for argv in cases:
        try:
            run(argv)
        except AssertionError as exc:
            failures.append(str(exc).split("\n  stdout")[0] + "\n  " + str(exc).split("stderr=")[-1][:200])
    assert not failures, f"{len(failures)} of {len(cases)} cases fail:\n" + "\n".join(failures[:40])


@long_only
@pytest.mark.parametrize("test", sorted(SIMULATE))
def test_simulate_each_option_at_each_extreme(test):
    table, base = SIMULATE[test], ["--max-grains", str(SIM_MAX_GRAINS), "simulate", test]
    cases = [[*base, *tiny_geometry(table), flag, value] for flag, param in table.items()
             if not getattr(param, "is_flag", False) and not getattr(param, "multiple", False)
             and flag != "--model" for value in _sweep_values(param)]
    for model in hs.MATERIALS:
        fields = hs.MATERIALS[model].params_type.model_fields
        cases += [[*base, *tiny_geometry(table), "--model", model, "--set", f"{name}={value}"]
                  for name in hs.MATERIALS[model].parameters
                  for value in [*(hs._text(b) for b in hs._bounds_of(fields.get(name))), *SWEEP_FLOATS[:10]]]
    _sweep(cases, lambda argv: simulate_property(argv, engine=False))


@long_only
def test_calibrate_each_option_at_each_extreme():
    never = ("--dry-run", "--help", "--json")
    cases = [["calibrate", "--dry-run", "--json", CAMPAIGN, flag, value] for flag, param in CALIBRATE.items()
             if flag not in never and not getattr(param, "is_flag", False) for value in _sweep_values(param)]
    cases += [["calibrate", "--dry-run", "--json", config] for config in CONFIG_TEXT]
    cases += [["--max-grains", value, "calibrate", "--dry-run", "--json", CAMPAIGN] for value in hs.INT_TEXT]
    _sweep(cases, lambda argv: calibrate_argv_property((argv, {})))


# ---------------------------------------------------------------------------------------------
# the smallest failing inputs the properties above found (they fail until rockcal is fixed)

BASE_TEXT = hs.toml_dumps(hs.base_campaign())
FOUND_CAMPAIGN_FILES = [
    # tomllib recurses per level of nesting: RecursionError (a 2 kB file)
    pytest.param(BASE_TEXT + hs._deep("array", 1000), id="array-nested-1000-deep"),
    pytest.param(BASE_TEXT + hs._deep("inline", 1000), id="inline-table-nested-1000-deep"),
    # check_numbers recurses per table: RecursionError (raw_values.py)
    pytest.param(BASE_TEXT + hs._deep("dotted", 1000), id="dotted-key-1000-deep"),
    # tomllib's time and memory grow with the square of a dotted key's parts: a 200 kB file
    # takes all the memory there is (MemoryError under the bound, the OOM killer without)
    pytest.param(BASE_TEXT + hs._deep("dotted", 100_000), id="dotted-key-100000-deep", marks=pytest.mark.slow),
    # an unknown key of white space is named by nothing: "rockcal: error: : Extra inputs are not permitted"
    pytest.param('" " = 1\n' + BASE_TEXT, id="blank-unknown-key"),
    # an empty key's nan, refused before the schema, is named by nothing: "rockcal: error: : must be a finite number"
    pytest.param('"" = nan\n' + BASE_TEXT, id="empty-key-nan"),
]


@pytest.mark.parametrize("text", FOUND_CAMPAIGN_FILES)
def test_found_campaign_files(text):
    campaign_file_property(hs.CampaignCase(text.encode()))


FOUND_CALIBRATE = [
    # a config argument longer than a file name may be: OSError (ENAMETOOLONG) from Path.exists
    pytest.param(["calibrate", "--dry-run", "--json", "a" * 300], id="config-name-too-long"),
    # click's usage errors name no field: "Got unexpected extra argument(s) (extra)"
    pytest.param(["calibrate", "--dry-run", "--json", CAMPAIGN, "extra"], id="extra-argument"),
    # "Option '--wait' does not take a value."
    pytest.param(["calibrate", "--dry-run", "--json", CAMPAIGN, "--wait=1"], id="flag-given-a-value"),
]


@pytest.mark.parametrize("argv", FOUND_CALIBRATE)
def test_found_calibrate_arguments(argv):
    calibrate_argv_property((argv, {}))


def test_found_grain_limit_below_the_speed_probe():
    """The dry run's engine-speed probe (a 40 x 40 mm lattice, 7 390 grains) is held to
    --max-grains: a limit the campaign's specimens are within is refused, naming `specimen`."""
    max_grains_property(_max_grains_of_base())


TINY_UCS = ["--max-grains", str(SIM_MAX_GRAINS), "simulate", "ucs", "--width-mm", "5", "--height-mm", "10"]
FOUND_SIMULATE = [
    # a cloud of one grain: ZeroDivisionError in the gauges (rig/gauge.py)
    pytest.param([*TINY_UCS, "--cloud-porosity", "0.9999999"], id="cloud-porosity-near-1"),
    # exit 0 and `"E_GPa": NaN` on stdout: --json that is not JSON
    pytest.param([*TINY_UCS, "--install-gap", "10", "--json"], id="install-gap-10-json-nan"),
    # values the parameters' models allow (> 0, < 1) make runs that do not end (past 60 s of CPU
    # on 5 x 10 mm): a time step of almost nothing, or no load
    *(pytest.param([*TINY_UCS, "--model", model, "--set", f"{name}={value}"], id=f"{model}-{name}={value}-never-ends",
                   marks=pytest.mark.slow)
      for model, name, value in [("parallel_bond", "density", "1e-300"), ("parallel_bond", "density", "5e-324"),
                                 ("parallel_bond", "kn_ks", "5e-324"), ("parallel_bond", "knbar_ksbar", "5e-324"),
                                 ("parallel_bond", "damping", "0.9999999999999999"),
                                 ("flatjoint", "fj_kratio", "5e-324"), ("flatjoint", "fj_rmul", "5e-324"),
                                 ("flatjoint", "lnm_krat", "5e-324"), ("flatjoint", "density", "5e-324")]),
]


@pytest.mark.parametrize("argv", FOUND_SIMULATE)
def test_found_simulate_arguments(argv):
    simulate_property(argv, engine=True)
