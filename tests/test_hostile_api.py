"""The notebook call under hostile arguments: `rockcal.calibrate` and `rockcal.simulate` either
run or raise one InputError naming an argument (or a key of the campaign), before anything is
written; no DEM runs here (the run is replaced by a stand-in that says it was reached)."""

import dataclasses
import math
import os
import sys
import tomllib
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

import rockcal
from rockcal.errors import InputError

sys.path.insert(0, str(Path(__file__).parent / "campaign"))
from tiny import tiny_campaign  # noqa: E402

TINY = tomllib.loads(tiny_campaign())
CALIBRATE_ARGUMENTS = {"campaign", "out", "quick", "resume", "wait", "workers", "scheduler", "threads"}
SIMULATE_ARGUMENTS = {"test", "params", "model", "packing"}
HOSTILE = [None, True, False, 0, -1, 1.5, math.nan, math.inf, 10**30, "", "two", "a\0b", b"x", [1], {"a": 1},
           object()]


class Reached(Exception):
    """The call got past its checks to the run."""


def _reached(*args, **kwargs):
    raise Reached


def _deep(depth: int) -> dict:
    deep = {}
    for _ in range(depth):
        deep = {"a": deep}
    return deep


@pytest.fixture
def no_runs(monkeypatch, tmp_path):
    """Work in an empty folder; `calibrate`'s run and `simulate`'s genesis and run are stand-ins."""
    import rockcal.campaign.job as job
    import rockcal.labtests.registry as registry

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(job, "run_in_folder", _reached)
    lab_test = registry.lab_test
    monkeypatch.setattr(registry, "lab_test", lambda name: dataclasses.replace(
        lab_test(name), make=_reached, hexagonal=_reached, run=_reached))
    return tmp_path


def _outcome(call, names: set[str], folder: Path) -> None:
    """`call` reached the run or raised an InputError naming one of `names` (or a campaign's
    key), and wrote nothing."""
    try:
        call()
    except Reached:
        pass
    except InputError as exc:
        assert exc.field and "\n" not in str(exc), exc
        assert exc.field in names or exc.field.split(".")[0] not in names | {"--out", "--threads"}, exc
    assert list(folder.iterdir()) == []


def _any(valid: list) -> st.SearchStrategy:
    return st.sampled_from(valid + HOSTILE)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(campaign=_any([TINY]), out=_any([None, "out", Path("out")]), quick=_any([False]),
       resume=_any([False, True]), wait=_any([False, True]), workers=_any([0, 1, 2]),
       scheduler=_any([None, "local:1"]), threads=_any([None, 1]))
def test_calibrate_runs_or_names_its_argument(no_runs, campaign, out, quick, resume, wait, workers, scheduler,
                                              threads):
    _outcome(lambda: rockcal.calibrate(campaign, out=out, quick=quick, resume=resume, wait=wait, workers=workers,
                                       scheduler=scheduler, threads=threads), CALIBRATE_ARGUMENTS, no_runs)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(test=_any(["ucs", "direct-tension", "brazilian"]), params=_any([None, {"E_c": 25.0}]),
       model=_any([None, "parallel_bond"]), packing=_any(["random", "hexagonal"]),
       setting=st.sampled_from(["rmin_mm", "seed", "confinement_mpa", "width_mm"]), value=_any([0.5, 1]))
def test_simulate_runs_or_names_its_argument(no_runs, test, params, model, packing, setting, value):
    _outcome(lambda: rockcal.simulate(test, params, model=model, packing=packing, **{setting: value}),
             SIMULATE_ARGUMENTS | {setting}, no_runs)


@pytest.mark.parametrize("argument, value, field", [
    ("threads", "two", "threads"), ("threads", 0, "threads"), ("threads", True, "threads"),
    ("workers", 1.5, "workers"), ("workers", None, "workers"), ("workers", True, "workers"),
    ("out", 5, "out"), ("out", "", "out"), ("quick", "yes", "quick"), ("resume", 1, "resume"),
    ("scheduler", 5, "scheduler"), ("scheduler", "nope", "scheduler"),
    ("campaign", _deep(5000), "a." * 20 + "..."),
])
def test_a_bad_argument_is_named_before_anything_is_written(no_runs, argument, value, field):
    arguments = {"campaign": TINY, argument: value}
    with pytest.raises(InputError) as refused:
        rockcal.calibrate(arguments.pop("campaign"), **arguments)
    assert refused.value.field == field
    assert list(no_runs.iterdir()) == []


def test_a_dict_that_holds_itself_is_refused():
    tables = {"rock": {}}
    tables["rock"]["again"] = tables
    with pytest.raises(InputError, match="nested more than"):
        rockcal.calibrate(tables)


@pytest.mark.parametrize("call, field", [
    (lambda: rockcal.simulate(None), "test"), (lambda: rockcal.simulate("ucs", 5), "params"),
    (lambda: rockcal.simulate("ucs", model=5), "model"), (lambda: rockcal.simulate("ucs", packing="hex"), "packing"),
    (lambda: rockcal.simulate("ucs", rmin_mm=True), "rmin_mm"), (lambda: rockcal.simulate("ucs", seed=False), "seed"),
])
def test_simulate_names_a_bad_argument(no_runs, call, field):
    with pytest.raises(InputError) as refused:
        call()
    assert refused.value.field == field


def test_a_3d_calibration_exports_pfc3d_s_file_by_default():
    from rockcal.api import _export_file

    assert _export_file("pfc-fish", True) == "mpParams.p3dat"
    assert _export_file("pfc-fish", False) == "mpParams.p2dat"
    assert _export_file("json", True) == "mpParams.json"


def _cli(args, monkeypatch, capsys) -> tuple[int, str]:
    from rockcal.cli.app import main

    monkeypatch.setattr(sys, "argv", ["rockcal", *map(str, args)])
    with pytest.raises(SystemExit) as done:
        main()
    return done.value.code, capsys.readouterr().err


@pytest.mark.parametrize("out", ["a_file", "a_file/sub"])
def test_simulate_refuses_an_out_through_a_file_before_the_run(out, tmp_path, monkeypatch, capsys):
    import rockcal.cli.simulate as simulate

    monkeypatch.chdir(tmp_path)
    (tmp_path / "a_file").write_text("")
    monkeypatch.setattr(simulate, "_on_packings", _reached)
    code, err = _cli(["simulate", "ucs", "--out", out], monkeypatch, capsys)
    assert code == 2 and err == "rockcal: error: --out: a_file is a file, not a folder\n"


@pytest.mark.parametrize("held, args, field", [
    ("", [], "--out"),  # a calibration's store without --resume
    ("a quick look", ["--resume"], "--quick"),  # a quick look's store resumed as a calibration
    (None, [], "--out"),  # OUT is a file
])
def test_the_dry_run_refuses_what_the_run_refuses(held, args, field, tmp_path, monkeypatch, capsys):
    from rockcal.campaign.job import QUICK_LOOK
    from rockcal.campaign.runs.store import RunStore

    config, out = tmp_path / "campaign.toml", tmp_path / "out"
    config.write_text(tiny_campaign())
    if held is None:
        out.write_text("")
    else:
        store = RunStore(out)
        store.save_document(QUICK_LOOK, held)
        store.close()
    before = sorted(tmp_path.rglob("*"))
    for dry in (["--dry-run"], ["--dry-run", "--json"]):
        code, err = _cli(["calibrate", config, "--out", out, *args, *dry], monkeypatch, capsys)
        assert code == 2 and err.startswith(f"rockcal: error: {field}: ") and err.count("\n") == 1, err
    assert sorted(tmp_path.rglob("*")) == before
