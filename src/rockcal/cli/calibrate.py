"""`rockcal calibrate` and `rockcal report`: the whole inverse procedure, and its report."""

from __future__ import annotations

import math
import os
import sys
import tempfile
import time
from pathlib import Path
from typing import TYPE_CHECKING, Optional

import typer
from rich.console import Console
from rich.markup import escape
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn
from rich.table import Table
from rich.text import Text

from rockcal.output_files import json_text
from rockcal.campaign.runs import MAX_WORKERS
from rockcal.cli.threads import use_threads_option
from rockcal.errors import InputError

if TYPE_CHECKING:
    from rockcal.campaign.procedure.result import CalibrationResult



def calibrate(
    config: Optional[Path] = typer.Argument(None, help="Campaign file (TOML), or an embedded rock by name "
                                            "(granite, ldb); none: the embedded granite."),
    out: Optional[Path] = typer.Option(None, help="Output folder (run store, report); default runs/<rock name>, runs/<rock name>-quick with --quick."),
    workers: int = typer.Option(0, min=0, max=MAX_WORKERS, help="Parallel forward runs on this machine (0: one "
                                "per core)."),
    scheduler: Optional[str] = typer.Option(None, help="Dask scheduler: tls://HOST:PORT (with certificates), tcp://HOST:PORT, or local:N for N local workers."),
    time_limit_s: Optional[float] = typer.Option(None, help="Wall-time limit of one forward run, s; a run past it is recorded as timed out."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    resume: bool = typer.Option(False, "--resume", help="Go on with the campaign already in --out."),
    quick: bool = typer.Option(False, "--quick", help="A first look in minutes: the campaign at half "
                               "resolution (R_min doubled) with one validation beam and 50 draws for the "
                               "intervals; not the calibration."),
    wait: bool = typer.Option(False, "--wait", help="If another rockcal is using --out, wait for it to end."),
    threads: Optional[int] = typer.Option(None, min=1, help="Engine threads of a forward run, at most, free "
                                          "cores or not (default: its share of the free cores; a Dask "
                                          "worker runs one). The numbers do not depend on it."),
    dry_run: bool = typer.Option(False, "--dry-run", help="Print the plan (stages, runs, specimens, expected "
                                 "time) and exit: nothing runs, nothing is written."),
    tls_ca_file: Optional[Path] = typer.Option(None, help="tls:// scheduler: the cluster's CA certificate (PEM)."),
    tls_cert: Optional[Path] = typer.Option(None, help="tls:// scheduler: this client's certificate (PEM)."),
    tls_key: Optional[Path] = typer.Option(None, help="tls:// scheduler: this client's key (PEM; default: in --tls-cert)."),
) -> None:
    """Identify BPM micro-parameters from lab results by the inverse procedure, with a report."""
    started = time.perf_counter()
    from rockcal.campaign.job import campaign_of

    campaign, text, note, out = campaign_of(config, quick, out)
    if time_limit_s is not None and not (math.isfinite(time_limit_s) and time_limit_s > 0):
        raise InputError("--time-limit-s", f"must be a finite number > 0, got {time_limit_s}")
    tls = _cluster_options(scheduler, tls_ca_file, tls_cert, tls_key)  # before OUT gets a store
    use_threads_option(threads)
    if dry_run:
        _print_dry_run(campaign, out, workers or os.cpu_count() or 1, note, as_json, resume, wait)
        return
    result, html, bars = _run_campaign(campaign, text, note, out, as_json,
                                        dict(resume=resume, wait=wait, on_waiting=_waiting,
                                             how=dict(workers=workers, scheduler=scheduler, time_limit_s=time_limit_s,
                                                      tls=tls, threads=threads)))
    expected_s, planned_at = bars.expected
    timing = {"stage_began_s": {stage: round(t - started, 1) for stage, t in bars.began.items()},
              "expected_s": round(expected_s, 1), "planned_at_s": round(planned_at - started, 1),
              "elapsed_s": round(time.perf_counter() - started, 1)}
    _print_summary(result, html, as_json, timing)


def _run_campaign(campaign, text: str, note: str | None, out: Path, as_json: bool, options: dict):
    """Run the campaign in OUT (`campaign.job.run_in_folder` with `options`), with its first
    screen and bars; its result, its report and its bars (`_stage_progress`: when each stage
    began, the first screen's expected time and when it was made)."""
    from rockcal.campaign.job import run_in_folder
    from rockcal.campaign.plan.screen import expected_s, genesis_times, genesis_wall_s, stage_runs, stage_times
    from rockcal.campaign.procedure.points import CalibrationFailed

    bars = []

    def start(store, executor):
        if not as_json:
            _print_plan(campaign, store, executor, note)
        workers = getattr(executor, "workers", 1)
        expected = (expected_s(campaign, store, workers), time.perf_counter())
        times = stage_times(campaign, store, workers)
        genesis = (len(genesis_times(campaign)), genesis_wall_s(campaign, workers))
        bars.append(_stage_progress(as_json, stage_runs(campaign), times, genesis))
        bars[0].expected = expected
        executor.on_live, executor.on_genesis = bars[0].live, bars[0].genesis
        return bars[0]

    try:
        result, html = run_in_folder(campaign, text, out, note=note, start=start, **options)
    except CalibrationFailed as exc:
        print(f"rockcal: calibration failed: {exc}", file=sys.stderr)
        raise typer.Exit(1)
    return result, html, bars[0]


def _cluster_options(scheduler: str | None, ca_file, cert, key):
    """The --scheduler and --tls-* options checked without connecting: the TLSFiles, or None."""
    if scheduler is None and ca_file is None and cert is None and key is None:
        return None
    from rockcal.campaign.runs.dask import parse_scheduler
    from rockcal.campaign.runs.tls import security_of, tls_files

    tls = tls_files(ca_file, cert, key)
    if scheduler is None:
        raise InputError("--tls-ca-file", "the --tls-* options are for a tls://HOST:PORT --scheduler")
    kind, _ = parse_scheduler(scheduler)
    security_of(kind, tls)
    return tls


def _waiting(holder: str) -> None:
    print(f"rockcal: waiting: the output folder is in use by another rockcal ({holder})", file=sys.stderr)


def report(out: Path = typer.Argument(..., help="Output folder of a campaign.")) -> None:
    """Rebuild OUT/report.html and its figures from the campaign's run store."""
    from rockcal.campaign.files import one_line_errors
    from rockcal.campaign.job import write_record_and_report
    from rockcal.campaign.procedure.result import read_result
    from rockcal.campaign.runs.store import RunStore
    from rockcal.campaign.runs.lock import store_lock

    with one_line_errors(out, "OUT"):
        store = RunStore(out, create=False, readonly=True)
        try:
            with store_lock(out, field="OUT", can_wait=False):
                result = read_result(store)
                if result is None:
                    raise InputError("OUT", f"the campaign in {out} has not finished; run "
                                            f"`rockcal calibrate --resume --out {out}`")
                html = write_record_and_report(result, store, out)
        finally:
            store.close()
    Console(stderr=True).print(f"report: {escape(str(html))}")


def _print_plan(campaign, store, executor, note: str | None) -> None:
    from rockcal.campaign.plan.screen import describe

    console = Console(stderr=True)
    console.print(f"[bold]Calibrating {escape(campaign.rock.name)}[/]" + (" [yellow](quick look)[/]" if note else ""))
    if note:
        console.print(f"  {note}", highlight=False, markup=False)
    console.print("  measuring this machine's engine speed: a second or two (half a minute on this "
                  "install's first run, which compiles the engine)", highlight=False, markup=False)
    for line in describe(campaign, store, getattr(executor, "workers", None)):
        console.print("  " + line, highlight=False, markup=False)
    if getattr(executor, "security_source", ""):
        console.print(f"  cluster: TLS with the certificates of {executor.security_source}",
                      highlight=False, markup=False)


def _print_dry_run(campaign, out: Path, workers: int, note: str | None, as_json: bool, resume: bool,
                   wait: bool) -> None:
    """The first screen, or with `as_json` the plan as data (`plan.dry_run`), for the store in
    OUT if it holds one (read only), else for an empty store; refused as the run would be
    (`job.check_out`, `job.check_same_kind`, a store another rockcal holds without `wait`)."""
    from rockcal.campaign.files import one_line_errors
    from rockcal.campaign.job import check_out, check_same_kind
    from rockcal.campaign.plan.screen import describe, dry_run
    from rockcal.campaign.runs.lock import holder_of, in_use
    from rockcal.campaign.runs.store import STORE_NAME, RunStore

    with one_line_errors(out), tempfile.TemporaryDirectory() as empty:
        held = (out / STORE_NAME).exists()
        check_out(out, resume)
        if held and not wait and (holder := holder_of(out)) is not None:
            raise in_use(out, holder)
        store = RunStore(out if held else Path(empty), create=not held, readonly=held)
        try:
            check_same_kind(store, note is not None, out)
            if as_json:
                typer.echo(json_text(dry_run(campaign, store, workers) | {"quick_look": note}))
                return
            console = Console()
            console.print(f"[bold]Plan of {escape(campaign.rock.name)}[/] (dry run: nothing runs)"
                          + (" [yellow](quick look)[/]" if note else ""))
            if note:
                console.print(f"  {note}", highlight=False, markup=False)
            for line in describe(campaign, store, workers):
                console.print("  " + line, highlight=False, markup=False)
        finally:
            store.close()


class _Bars(Progress):
    """The bars, then a line per run in flight, each cut to the terminal's width (80 columns
    hold a bar's every column)."""

    lines: list[str] = []

    def get_renderables(self):
        yield self.make_tasks_table(self.tasks)
        for line in self.lines:
            yield Text("  " + line, no_wrap=True, overflow="ellipsis")


class _stage_progress:
    """A rich progress bar for the whole campaign and one per stage (runs done / to do, ETA), on
    stderr. The campaign's bar advances by the expected wall time of each run done
    (`plan.stage_times`: a full-size beam weighs more than a coarse sensitivity run), so its
    ETA, the rate over the last 10 minutes, holds from the first stage on; it shows the runs
    done of those planned (`plan.stage_runs`, the first screen's count).

    A stage's runs are those planned, or more when its batches have more to run (a
    verification round that verifies a second optimum, another round): the counts only grow
    while the campaign runs. A run the store held when its batch began counts toward the
    stage's planned runs, never beyond them: it may be a run of an earlier stage (the identified
    point's first packing is its verification run), so a campaign as planned ends at the count
    the first screen gave. A planned stage that never began when the campaign ends (the
    identifiability stage, where the sheet pins every parameter) leaves the count then.

    The genesis of the packings a batch needs, before its runs, has a bar of its own (packings
    made / to make), and weighs in the campaign's bar by its expected time (`genesis`: the
    packings planned and their wall time)."""

    def __init__(self, quiet: bool, planned_runs: dict[str, int], times: dict[str, tuple[int, float]],
                 genesis: tuple[int, float] = (0, 0.0)):
        self.bar = _Bars(TextColumn("{task.description:<23}"), BarColumn(bar_width=16),
                         TextColumn("{task.fields[count]:>7}"), TimeElapsedColumn(), TextColumn("ETA"),
                         TimeRemainingColumn(), console=Console(stderr=True), disable=quiet,
                         speed_estimate_period=600)
        self.planned = planned_runs  # forward runs per stage (the others count no runs)
        self.to_do = {stage: runs for stage, (runs, _) in times.items()}  # of stages not begun
        self.run_s = {stage: seconds / runs for stage, (runs, seconds) in times.items() if runs}
        self.packings_planned, genesis_s = genesis
        self.packing_s = genesis_s / self.packings_planned if self.packings_planned else 0.0
        self.packings: list[list[int]] = []  # a batch's genesis each: [made, to make]
        self.campaign = self.bar.add_task("campaign (planned runs)",
                                          total=round(genesis_s + sum(s for _, s in times.values())),
                                          count=f"0/{sum(planned_runs.values())}")
        # stage: its batches (a verification round each), each [runs held when it began, done, total]
        self.batches: dict[str, list[list[int]]] = {}
        self.tasks: dict[str, int] = {}
        self.began: dict[str, float] = {}  # when each stage began (time.perf_counter)
        self.expected = (0.0, time.perf_counter())  # the first screen's expected time (s) and when made

    def live(self, lines: list[str]) -> None:
        """Show what the running tests read now, a line each below the bars."""
        self.bar.lines = lines

    def note(self, text: str) -> None:
        """Print a step's warning above the bars (a parameter the targets barely see)."""
        self.bar.console.print(f"[yellow]warning:[/] {escape(text)}")

    def genesis(self, made: int, total: int) -> None:
        """Show the packings a batch has made of those it makes before its runs."""
        if "genesis" not in self.tasks:
            self.tasks["genesis"] = self.bar.add_task("genesis (packings)", total=total, count="")
        if not self.packings or made < self.packings[-1][0]:
            self.packings.append([made, total])
        self.packings[-1][0] = made
        made_all = sum(m for m, _ in self.packings)
        total_all = max(self.packings_planned, sum(t for _, t in self.packings))
        self.bar.update(self.tasks["genesis"], completed=made_all, total=total_all, count=f"{made_all}/{total_all}")
        self._update_campaign()

    def __enter__(self):
        self.bar.start()
        return self

    def __exit__(self, exc_type, *exc):
        if exc_type is None:
            self.planned = {stage: n for stage, n in self.planned.items() if stage in self.batches}
            self.to_do = {}
            self._update_campaign()
        self.bar.stop()

    def __call__(self, stage: str, done: int, total: int) -> None:
        if stage not in self.tasks:
            self.began[stage] = time.perf_counter()
            self.tasks[stage] = self.bar.add_task(stage, total=total, count="")
            self.to_do.pop(stage, None)
        if stage not in self.planned:  # not forward runs (the intervals' draws)
            self.bar.update(self.tasks[stage], completed=done, total=total, count=f"{done}/{total}")
            return
        batches = self.batches.setdefault(stage, [])
        # a batch counts up to its total: a count that falls back or a new total is the next one
        if not batches or done < batches[-1][1] or total != batches[-1][2]:
            batches.append([done, done, total])  # the runs done at once came from the store
        batches[-1][1] = done
        runs, left = self._runs(stage)
        self.bar.update(self.tasks[stage], completed=runs - left, total=runs, count=f"{runs - left}/{runs}")
        self._update_campaign()

    def _runs(self, stage: str) -> tuple[int, int]:
        """A begun stage's runs and those still to do: the planned runs, or its batches' runs
        to do if more."""
        to_do = sum(total - held for held, _, total in self.batches[stage])
        left = sum(total - done for _, done, total in self.batches[stage])
        return max(self.planned[stage], to_do), left

    def _update_campaign(self) -> None:
        run_s = self.run_s.get
        spent = sum((done - held) * run_s(stage, 0.0)
                    for stage, batches in self.batches.items() for held, done, _ in batches)
        left = sum((total - done) * run_s(stage, 0.0)
                   for stage, batches in self.batches.items() for _, done, total in batches) \
            + sum(runs * run_s(stage, 0.0) for stage, runs in self.to_do.items())
        made = sum(m for m, _ in self.packings)
        to_make = max(self.packings_planned, sum(t for _, t in self.packings))
        spent += made * self.packing_s
        left += (to_make - made) * self.packing_s
        counts = [self._runs(stage) for stage in self.batches]
        done = sum(runs - to_do for runs, to_do in counts)
        planned = sum(runs for runs, _ in counts) + sum(n for stage, n in self.planned.items()
                                                         if stage not in self.batches)
        # whole seconds: a new total resets the bar's rate (rich), so only a real change makes one
        self.bar.update(self.campaign, completed=spent, total=round(spent + left), count=f"{done}/{planned}")


def summary(result: CalibrationResult) -> dict:
    """What `--json` prints: identified parameters, verified responses and errors (of every
    test calibrated against, each test's named in `target_tests`), K_IC, other validation
    checks, runs."""
    v, u = result.validation, result.uncertainty

    def validation(name: str):
        return None if v is None else getattr(v, name)

    return {
        "rock": result.rock, "quick_look": result.quick_look, "accepted": result.accepted, "identified": result.identified,
        "identified_params": result.identified_params, "targets": result.targets,
        "target_tests": result.responses_by_test(), "weights": result.weights,
        "verified": {r: result.verified[r] for r in result.targets},
        "relative_errors": result.errors, "tolerance": result.tolerance,
        "objective": result.objective,
        "curve_fit": None if result.curve_fit is None else result.curve_fit.model_dump(),
        "K_IC_MPa_sqrt_m": validation("K_IC_MPa_sqrt_m"),
        "K_IC_seed_std": validation("K_IC_MPa_sqrt_m_std"),
        "K_IC_per_seed": validation("K_IC_per_seed"),
        "lab_K_IC_MPa_sqrt_m": validation("lab_K_IC_MPa_sqrt_m"),
        "K_IC_error": validation("K_IC_error"), "warning": validation("warning"),
        "dem_runs": result.dem_runs, "executed_runs": result.executed_runs,
        "failed_runs": len(result.failed_runs),
        "checks": [c.model_dump(mode="json") for c in result.checks or []],
        "intervals": None if u is None else {n: i.to_dict() for n, i in u.intervals.items()},
        "verdict": None if result.verdict is None else result.verdict.text,
        "at_bounds": result.at_bounds or [],
        "identifiability": identifiability_summary(result.identifiability),
    }


def identifiability_summary(found) -> dict | None:
    """What `--json` prints of the identifiability stage: each parameter's range and verdict,
    the tests ranked and the sentence (None: not accepted, so not judged)."""
    if found is None:
        return None
    return {"bands": found.bands, "surrogate_error": found.surrogate_error, "pinned_within": found.pinned_within,
            "pinned_share": found.pinned_share,
            "ranges": {n: r.model_dump() for n, r in found.ranges.items()},
            "end_runs": [r.model_dump() for r in found.end_runs],
            "tests": [{"test": t.test, "response": t.response, "spread": t.spread, "label": t.label}
                      for t in found.tests],
            "runs": found.runs, "text": found.text}


def _print_summary(result: CalibrationResult, html: Path, as_json: bool, timing: dict) -> None:
    """The summary table, or with `as_json` the JSON object with the report's path and
    `timing`: when each stage began and when the summary was printed, s from the command's start."""
    from rockcal.labtests.registry import PRIMARY_TEST, lab_test

    s = summary(result)
    if as_json:
        typer.echo(json_text(s | {"report": str(html)} | timing))
        return
    console = Console()
    verdict = "accepted" if s["accepted"] else "NOT accepted (closest shown)"
    kind = "Quick look at" if s["quick_look"] else "Calibration of"
    table = Table(title=f"{kind} {escape(s['rock'])}: {verdict}, {s['dem_runs']} DEM runs")
    for column in ("", "value", "target", "error"):
        table.add_column(column)
    intervals = s["intervals"] or {}
    ranges = (s["identifiability"] or {}).get("ranges", {})
    for name, value in s["identified"].items():
        i, r = intervals.get(name), ranges.get(name)
        spread = "" if i is None else f"  (5–95 %: {i['p5']:.4g}–{i['p95']:.4g}" + (
            ")" if i["pinned"] else ", not pinned down)")
        if r is not None and not r["pinned"]:
            spread += f"  (not pinned by the sheet: {r['low']:.4g}–{r['high']:.4g})"
        table.add_row(name, f"{value:.4g}{spread}", "", "")
    for test, names in s["target_tests"].items():
        for name in names:
            value, error = (s["verified"] or {}).get(name), (s["relative_errors"] or {}).get(name)
            label = name if test == PRIMARY_TEST else f"{name} ({lab_test(test).title})"
            table.add_row(label, "–" if value is None else f"{value:.4g}", f"{s['targets'][name]:.4g}",
                          "–" if error is None else f"{100 * error:+.1f} %")
    if s["K_IC_MPa_sqrt_m"] is not None:
        n = len(s["K_IC_per_seed"])
        table.add_row(f"K_IC (validation, {n} packing{'s' if n > 1 else ''})",
                      f"{s['K_IC_MPa_sqrt_m']:.3f}" + (f" ± {s['K_IC_seed_std']:.3f}" if n > 1 else ""),
                      f"{s['lab_K_IC_MPa_sqrt_m']:.3f}", f"{100 * s['K_IC_error']:+.1f} %")
    for check in s["checks"]:
        for name, lab in check["lab"].items():
            value = (check.get("responses") or {}).get(name)
            error = (check.get("errors") or {}).get(name)
            table.add_row(f"{name} (validation, {lab_test(check['test']).title})",
                          check["status"] if value is None else f"{value:.4g}", f"{lab:.4g}",
                          "–" if error is None else f"{100 * error:+.1f} %")
    console.print(table)
    if s["verdict"]:
        console.print(f"[red]verdict:[/] {escape(s['verdict'])}")
    if s["identifiability"]:
        console.print(f"identifiability: {escape(s['identifiability']['text'])}")
    if s["quick_look"]:
        console.print(f"[yellow]{escape(s['quick_look'])}[/]")
    for warning in [s["warning"], *s["at_bounds"]]:
        if warning:
            console.print(f"[yellow]warning:[/] {escape(warning)}")
    console.print(f"objective: {escape(s['objective'])}\nreport: {escape(str(html))}")
