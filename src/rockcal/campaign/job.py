"""A campaign run in its output folder, start to end: the folder held by one rockcal, the run
store made or resumed, the procedure run on an executor, then the record and the report
written. `rockcal calibrate` runs it with its screen and bars; `rockcal.calibrate` without."""

from __future__ import annotations

from contextlib import nullcontext
from pathlib import Path
from typing import Callable

from rockcal.errors import InputError

DEFAULT_OUT = Path("runs")
QUICK_LOOK = "quick look"  # the store's document naming what the quick look was ("": not one)


def default_out(rock: str, quick: bool) -> Path:
    """runs/<rock>, or runs/<rock>-quick for a quick look: never the calibration's folder; only
    when the rock name is a plain folder name."""
    from rockcal.campaign.files import is_plain_name

    name = f"{rock}-quick" if quick else rock
    if not is_plain_name(name):
        raise InputError("rock.name", f"{rock!r} is not a plain folder name, so it cannot name the "
                                      "output folder runs/<rock name>; give --out")
    return DEFAULT_OUT / name


def campaign_of(config, quick: bool, out: Path | None):
    """The campaign of a file or an embedded rock (`config`), on its route or as a quick look if
    `quick`, its specimens within the grain limit: (campaign, its file's text, the quick look's
    note or None, the output folder: `out` or the default)."""
    from rockcal.campaign.input.config import load_campaign

    return as_run(*load_campaign(config), quick, out)


def as_run(campaign, text: str, quick: bool, out: Path | None):
    """`campaign_of` for a campaign read from its file's `text` (`parse_campaign`'s: not yet on
    its route)."""
    from rockcal.campaign.plan.planned import planned
    from rockcal.campaign.plan.quick_look import quick_look, quick_look_note
    from rockcal.campaign.plan.sizes import check_campaign_sizes

    note = None
    if quick:  # a quick look takes a route of its own
        campaign = quick_look(campaign)
        note = quick_look_note(campaign)
    else:
        campaign = planned(campaign)
    check_campaign_sizes(campaign)
    return campaign, text, note, out if out is not None else default_out(campaign.rock.name, quick)


def run_in_folder(campaign, text: str, out: Path, *, note: str | None = None, resume: bool = False,
                  wait: bool = False, on_waiting: Callable[[str], None] | None = None, how: dict | None = None,
                  start: Callable | None = None):
    """Run `campaign` (its file's `text`; `note`: a quick look's) with the store in `out`,
    going on with the runs it holds only if `resume`; `how`: the executor's settings
    (`runs.executors.make_executor`); `start(store, executor)`: a context manager giving the
    procedure's progress callback (none: no progress shown). Returns the result and the
    report's path; `procedure.points.CalibrationFailed` when the campaign cannot go on."""
    from rockcal.campaign.files import no_empty_store, one_line_errors, out_folder
    from rockcal.campaign.procedure.result import save_result
    from rockcal.campaign.procedure.steps import calibrate
    from rockcal.campaign.runs.executors import make_executor
    from rockcal.campaign.runs.lock import store_lock
    from rockcal.campaign.runs.store import STORE_NAME, RunStore

    with one_line_errors(out), out_folder(out), store_lock(out, wait, on_waiting):
        check_out(out, resume)
        with no_empty_store(out, not (out / STORE_NAME).exists()):
            store = RunStore(out)
            try:
                check_same_kind(store, note is not None, out)
                executor = make_executor(store, **(how or {}))
                try:
                    store.save_document("campaign.toml", text)
                    store.save_document(QUICK_LOOK, note or "")
                    with start(store, executor) if start else nullcontext(None) as progress:
                        result = calibrate(campaign, executor, progress)
                finally:
                    executor.close()
                result = result.model_copy(update={"executed_runs": executor.executed, "quick_look": note})
                save_result(store, result)
                html = write_record_and_report(result, store, out)
            finally:
                store.close()
    return result, html


def check_out(out: Path, resume: bool) -> None:
    """What a run refuses of OUT before it writes (`--dry-run` asks the same): a file or a path
    through one, or a campaign's store without `resume`."""
    from rockcal.campaign.runs.store import STORE_NAME

    existing = next((p for p in (out, *out.parents) if p.exists()), None)
    if existing is not None and not existing.is_dir():
        raise InputError("--out", f"{existing} is a file, not a folder")
    if (out / STORE_NAME).exists() and not resume:
        raise InputError("--out", f"{out} already holds a campaign's runs; add --resume to go on "
                                  "with it, or choose another folder")


def check_same_kind(store, quick: bool, out: Path) -> None:
    """A quick look and a calibration never share a run store."""
    stored = store.document(QUICK_LOOK)
    if stored is not None and bool(stored) != quick:
        was = "a quick look (--quick)" if stored else "a full-resolution calibration"
        raise InputError("--quick", f"the campaign in {out} is {was}; "
                                    f"{'add' if stored else 'leave out'} --quick, or choose another --out")


def write_record_and_report(result, store, out: Path) -> Path:
    """OUT/record.json and OUT/report.html (with its figures); the report's path."""
    from rockcal.campaign.outputs.report import write_report
    from rockcal.campaign.procedure.result import RECORD_NAME
    from rockcal.output_files import write_atomic

    write_atomic(out / RECORD_NAME, result.to_json(indent=1))
    return write_report(result, store, out)
