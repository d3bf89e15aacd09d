import faulthandler
import os
import sys
from types import SimpleNamespace

import numba
import pytest

import rockcal  # noqa: F401 (before any test compiles a function: it sets the vector width)


@pytest.fixture(autouse=True, scope="session")
def _specimen_cache(tmp_path_factory):
    """Keep test specimens out of the user's cache; pytest-xdist's workers share one cache, so
    a specimen is made once per session."""
    root = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        root = root.parent
    mp = pytest.MonkeyPatch()
    mp.setenv("ROCKCAL_CACHE", str(root / "specimens"))
    yield
    mp.undo()


TEST_LIMIT_S = 900  # no test takes two minutes with its fixtures; one past this is stuck


@pytest.hookimpl(wrapper=True)
def pytest_runtest_protocol(item):
    """A test stuck past TEST_LIMIT_S (its fixtures' setup included) prints every thread's stack
    and ends its process (under pytest-xdist, its worker: the test is reported as crashed and
    the run goes on). faulthandler's watchdog is a C thread, so it ends a test stuck in compiled
    code too, where a Python timer (a signal handler, pytest-timeout) never gets the interpreter
    back. The stacks go where pytest's own faulthandler writes (stderr before pytest captured it)."""
    from _pytest.faulthandler import fault_handler_stderr_fd_key

    stderr = item.config.stash.get(fault_handler_stderr_fd_key, None)
    faulthandler.dump_traceback_later(TEST_LIMIT_S, exit=True, file=sys.stderr if stderr is None else stderr)
    try:
        return (yield)
    finally:
        faulthandler.cancel_dump_traceback_later()


@pytest.fixture(autouse=True, scope="session")
def _one_thread_per_worker():
    """With one pytest-xdist worker per core, the engine runs one thread per worker: two
    threads per worker would oversubscribe the cores."""
    if not os.environ.get("PYTEST_XDIST_WORKER"):
        yield
        return
    cap = numba.get_num_threads()
    numba.set_num_threads(1)
    yield
    numba.set_num_threads(cap)


@pytest.fixture
def cli(monkeypatch, capsys):
    """`rockcal ARGS` in this process (optionally from the folder `cwd`): its exit code, stdout
    and stderr. Quicker than a new process by the interpreter's and the engine's start."""
    from rockcal.cli.app import main

    def run(*args, cwd=None):
        with monkeypatch.context() as m:
            if cwd is not None:
                m.chdir(cwd)
            m.setattr(sys, "argv", ["rockcal", *map(str, args)])
            capsys.readouterr()
            with pytest.raises(SystemExit) as done:
                main()
        out = capsys.readouterr()
        return SimpleNamespace(returncode=done.value.code or 0, stdout=out.out, stderr=out.err)
    return run


@pytest.fixture(scope="session")
def save_finished():
    """`save_finished(folder, campaign_text, params, identified)`: a store in `folder` holding
    a finished campaign's documents (what `calibrate` writes at its end) of `campaign_text`, its
    identified `params` (`identified`: the searched ones by name), verified within 0.5 % of
    E_GPa 41.5; the folder."""
    from rockcal.campaign.input.config import parse_campaign
    from rockcal.campaign.procedure.result import CalibrationResult, save_result
    from rockcal.campaign.runs.store import RunStore

    def save(folder, campaign_text: str, params, identified: dict, **fields):
        nothing = {"samples": {"x": [], "responses": []}, "iterations": [], "dem_run_keys": [],
                   "surrogate_check": {"x": [], "dem": [], "predicted": [], "max_relative_error": None,
                                       "trusted": None, "tolerance": 0.05, "epsilon": {}},
                   "failed_runs": [], "ucs_specimen": {}, "fixed": {}}
        result = CalibrationResult.model_validate(nothing | {
            "rock": "twin", "accepted": True, "dem_runs": 12, "targets": {"E_GPa": 41.5},
            "specimen": parse_campaign(campaign_text, folder).specimen, "parameters": list(identified),
            "bounds": {"E_c": [10, 30]}, "verified": {"E_GPa": 41.3}, "errors": {"E_GPa": -0.005},
            "identified": identified, "identified_params": params.key(), "tolerance": 0.05,
            "objective": "F", "best_iteration": 0, "final_ucs_run_key": "not run"} | fields)
        store = RunStore(folder)
        store.save_document("campaign.toml", campaign_text)
        save_result(store, result)
        store.close()
        return folder
    return save
