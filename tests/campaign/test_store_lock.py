"""One writer per run store: a second rockcal on the same OUT says who holds it and exits 2, or
waits with --wait; a campaign killed (SIGKILL, SIGTERM, SIGINT) while another waits leaves its
lock to the waiter, which resumes to the uninterrupted result with nothing run twice."""

import json
import os
import signal
import socket
import sqlite3
import subprocess
import sys
import threading
import time

import pytest

from rockcal.campaign.runs.store import RunStore
from rockcal.campaign.runs.lock import LOCK_NAME, store_lock
from rockcal.errors import InputError
from tiny import tiny_campaign

CAMPAIGN = tiny_campaign(seed=5)


def test_a_held_lock_names_its_holder_and_a_stale_one_is_taken(tmp_path):
    with store_lock(tmp_path):
        with pytest.raises(InputError) as refused:
            with store_lock(tmp_path):
                pass
    message = str(refused.value)
    assert message.startswith(f"--out: {tmp_path} is in use by another rockcal (pid {os.getpid()} on "
                              f"{socket.gethostname()}, since ")
    assert message.endswith("wait for it to end, or add --wait")
    assert not (tmp_path / LOCK_NAME).exists()
    (tmp_path / LOCK_NAME).write_text(json.dumps({"pid": 999999999, "host": "gone", "since": "then"}))
    with store_lock(tmp_path):  # the lock of a dead process: its file is there, its flock is not
        assert json.loads((tmp_path / LOCK_NAME).read_text())["pid"] == os.getpid()


def test_wait_blocks_until_the_holder_is_done(tmp_path):
    told, order = [], []
    held = threading.Event()

    def holder():
        with store_lock(tmp_path):
            held.set()
            time.sleep(0.5)
            order.append("first done")

    thread = threading.Thread(target=holder)
    thread.start()
    held.wait(10)
    with store_lock(tmp_path, wait=True, waiting=told.append):
        order.append("second in")
    thread.join()
    assert order == ["first done", "second in"]
    assert len(told) == 1 and told[0].startswith(f"pid {os.getpid()} on ")


def calibrate(config, out, *args, stderr=subprocess.PIPE):
    return subprocess.Popen([sys.executable, "-m", "rockcal", "calibrate", str(config), "--out", str(out),
                             "--workers", "1", *args], stdout=subprocess.PIPE, stderr=stderr, text=True)


def test_a_second_rockcal_on_a_held_store_is_refused_in_one_line(tmp_path, cli):
    config = tmp_path / "campaign.toml"
    config.write_text(CAMPAIGN)
    out = tmp_path / "out"
    out.mkdir()
    RunStore(out).close()
    before = (out / "runs.sqlite").read_bytes()
    with store_lock(out):  # a lock is an open file's: the command's own open of it is refused too
        for command in (["calibrate", config, "--out", out, "--resume"],
                        ["calibrate", config, "--out", out, "--resume", "--dry-run"], ["report", out]):
            run = cli(*command)
            assert run.returncode == 2, run.stderr
            assert len(run.stderr.splitlines()) == 1 and "Traceback" not in run.stderr
            field = "--out" if command[0] == "calibrate" else "OUT"
            assert run.stderr.startswith(f"rockcal: error: {field}: {out} is in use by another rockcal "
                                         f"(pid {os.getpid()} on {socket.gethostname()}, since "), run.stderr
    assert (out / "runs.sqlite").read_bytes() == before


@pytest.fixture(scope="module")
def uninterrupted(tmp_path_factory):
    """Two campaigns started together on one new OUT: one runs it, the other is refused; the
    JSON of the one that ran."""
    folder = tmp_path_factory.mktemp("race")
    config = folder / "campaign.toml"
    config.write_text(CAMPAIGN)
    runs = [calibrate(config, folder / "out", "--json") for _ in range(2)]
    done = [run.communicate(timeout=600) for run in runs]
    codes = sorted(run.returncode for run in runs)
    assert codes == [0, 2], done
    (stdout, _), = [d for d, run in zip(done, runs) if run.returncode == 0]
    (_, refused), = [d for d, run in zip(done, runs) if run.returncode == 2]
    assert len(refused.splitlines()) == 1
    assert "is in use by another rockcal" in refused or "already holds a campaign's runs" in refused
    assert set(RunStore(folder / "out").executions().values()) == {1}
    return config, json.loads(stdout)


def stored_runs(store) -> int:
    """The runs in the store, read only: a plain connect would create an empty file where the
    campaign is about to make its store, and the campaign would take it for another's."""
    try:
        db = sqlite3.connect(f"file:{store}?mode=ro", uri=True, timeout=30)
        try:
            return db.execute("SELECT COUNT(*) FROM runs").fetchone()[0]
        finally:
            db.close()
    except sqlite3.OperationalError:
        return 0


@pytest.mark.slow  # campaigns in new processes, killed
@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM, signal.SIGINT], ids=["KILL", "TERM", "INT"])
def test_a_killed_holder_leaves_its_store_to_the_waiter(sig, uninterrupted, tmp_path):
    config, expected = uninterrupted
    out = tmp_path / "out"
    first = calibrate(config, out)
    deadline = time.time() + 300
    while time.time() < deadline and first.poll() is None and stored_runs(out / "runs.sqlite") < 3:
        time.sleep(0.05)
    log = tmp_path / "waiter.err"
    with open(log, "w") as err:
        waiter = calibrate(config, out, "--resume", "--wait", "--json", stderr=err)
        while time.time() < deadline and "waiting" not in log.read_text():
            time.sleep(0.05)
    assert first.poll() is None, f"the campaign ended before it could be killed: {first.communicate()[1]}"
    first.send_signal(sig)
    first.communicate(timeout=300)
    stdout, _ = waiter.communicate(timeout=600)
    assert waiter.returncode == 0, log.read_text()
    result = json.loads(stdout)
    assert result["identified"] == expected["identified"] and result["verified"] == expected["verified"]
    assert set(RunStore(out).executions().values()) == {1}  # nothing run twice
    assert not (out / LOCK_NAME).exists()
