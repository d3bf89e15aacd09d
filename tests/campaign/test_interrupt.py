"""Ctrl-C during a campaign on two workers (SIGINT to the whole process group, as a terminal
sends it): one line, exit 130, and no run stored as failed for the interrupt, so --resume
runs nothing the interrupt cut short twice."""

import os
import signal
import subprocess
import sys
import time

import pytest

from rockcal.campaign.runs.pool import interrupted
from rockcal.campaign.runs.store import RunStore
from test_store_lock import stored_runs
from tiny import tiny_campaign


def _terminal_sigint() -> None:
    """Ctrl-C as a terminal's process has it: a shell runs a background job (the suite's, say)
    with SIGINT ignored, and a child would inherit that."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def test_an_exception_caused_by_ctrl_c_is_the_interrupt():
    try:
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as exc:
            raise SystemError("CPUDispatcher(...) returned a result with an exception set") from exc
    except SystemError as exc:
        assert interrupted(exc)
    assert not interrupted(ValueError("a run that fails"))


@pytest.mark.slow  # a campaign in a new process, interrupted
@pytest.mark.parametrize("after_s", [0.0, 0.3, 0.6])
def test_ctrl_c_on_two_workers_is_one_line_and_stores_no_failure(after_s, tmp_path):
    config, out = tmp_path / "campaign.toml", tmp_path / "out"
    config.write_text(tiny_campaign(seed=7))
    run = subprocess.Popen([sys.executable, "-m", "rockcal", "calibrate", str(config), "--out", str(out),
                            "--workers", "2"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                           start_new_session=True, preexec_fn=_terminal_sigint)
    deadline = time.time() + 300
    while time.time() < deadline and run.poll() is None and stored_runs(out / "runs.sqlite") < 1:
        time.sleep(0.05)
    time.sleep(after_s)
    assert run.poll() is None, f"the campaign ended before it could be interrupted: {run.communicate()[1]}"
    os.killpg(run.pid, signal.SIGINT)
    _, stderr = run.communicate(timeout=120)
    assert run.returncode == 130, stderr[-2000:]
    assert "Traceback" not in stderr and stderr.rstrip().splitlines()[-1] == "rockcal: interrupted", repr(stderr[-1500:])
    store = RunStore(out, create=False, readonly=True)
    try:
        assert store.failures() == []
    finally:
        store.close()
