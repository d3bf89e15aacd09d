"""The run store and OUT under faults: a damaged store, one of another schema, a full or read-only
disk, a path through a file, a symbolic link in OUT, a writer killed with runs in its WAL. Each is
one line naming the path with exit code 2, and leaves the store as it was."""

import hashlib
import os
import shutil
import sqlite3
import subprocess
import sys

import pytest

from rockcal.campaign.input.config import parse_campaign
from rockcal.campaign.plan.planned import planned
from rockcal.campaign.job import QUICK_LOOK
from rockcal.campaign.runs.pool import Executor
from rockcal.campaign.procedure.steps import calibrate
from rockcal.campaign.procedure.result import save_result
from rockcal.campaign.runs.store import STORE_NAME, RunStore
from tiny import tiny_campaign
from one_line import ERROR, assert_one_line

CAMPAIGN = tiny_campaign(samples=4, iterations=10, max_dem_runs=5)


@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    """A finished tiny campaign's OUT (store, record, report) and its campaign file."""
    folder = tmp_path_factory.mktemp("finished")
    config = folder / "campaign.toml"
    config.write_text(CAMPAIGN)
    out = folder / "out"
    store = RunStore(out)
    result = calibrate(planned(parse_campaign(CAMPAIGN, folder)), Executor(store, workers=1))
    store.save_document("campaign.toml", CAMPAIGN)
    store.save_document(QUICK_LOOK, "")  # as `rockcal calibrate` saves them
    save_result(store, result)
    store.close()
    (out / "report.html").write_text("<p>the report</p>")
    return config, out, result.final_ucs_run_key


@pytest.fixture
def out(finished, tmp_path):
    config, folder, _ = finished
    shutil.copy(config, tmp_path / "campaign.toml")
    shutil.copytree(folder, tmp_path / "out")
    return tmp_path / "out"


@pytest.fixture
def rockcal(cli):
    """`rockcal ARGS` in this process: its exit code and stderr."""
    def run(*args):
        done = cli(*args)
        return done.returncode, done.stderr
    return run


def commands(out):
    config = out.parent / "campaign.toml"
    return {"resume": ["calibrate", config, "--out", out, "--resume", "--workers", "1", "--json"],
            "report": ["report", out], "export": ["export", out, "--format", "json"]}


def sha(path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def corrupt_pages(path, last_only: bool = False):
    """Scribble on the header of every b-tree page but the first (the schema stays readable),
    or of the last page only."""
    data = bytearray(path.read_bytes())
    size = int.from_bytes(data[16:18], "big")
    for start in range(len(data) - size if last_only else size, len(data), size):
        data[start:start + 8] = b"\xff" * 8
    path.write_bytes(bytes(data))


def spoil_run(column: str, value):
    def spoil(path, key):
        db = sqlite3.connect(path)
        db.execute(f"UPDATE runs SET {column}=? WHERE key=?", (value, key))
        db.commit()
        db.close()
    return spoil


def other_schema(path, key):
    db = sqlite3.connect(path)
    db.executescript("CREATE TABLE runs2 AS SELECT key, kind, specimen, params, engine, status, responses, "
                     "curve, wall_s, message, finished_at FROM runs; DROP TABLE runs; "
                     "ALTER TABLE runs2 RENAME TO runs;")
    db.close()


SPOILS = {
    "damaged pages": (lambda path, key: corrupt_pages(path), "is damaged"),
    "one damaged page": (lambda path, key: corrupt_pages(path, last_only=True), "is damaged"),
    "bad curve blob": (spoil_run("curve", b"\x93NUMPY garbage"), "the stored run"),
    "bad responses JSON": (spoil_run("responses", "{not json"), "the stored run"),
    "responses not an object": (spoil_run("responses", "[1, 2]"), "the stored run"),
    "another schema": (other_schema, "has another store schema"),
}


@pytest.mark.parametrize("command", ["resume", "report", "export"])
@pytest.mark.parametrize("spoil, says", SPOILS.values(), ids=SPOILS.keys())
def test_a_damaged_store_is_one_line_and_left_as_it_was(spoil, says, command, out, finished, rockcal):
    store = out / STORE_NAME
    spoil(store, finished[2])
    before = sha(store)
    code, stderr = rockcal(*commands(out)[command])
    assert_one_line(code, stderr, ERROR + f"OUT: {store}")
    assert says in stderr
    assert sha(store) == before


def test_a_stored_run_without_a_targeted_response_is_one_line_on_resume(out, finished, rockcal):
    spoil_run("responses", '{"E_GPa": 20.0}')(out / STORE_NAME, finished[2])
    code, stderr = rockcal(*commands(out)["resume"])
    assert_one_line(code, stderr, ERROR + "--out: a stored UCS run lacks its response ucs_MPa, a target of this campaign")


def test_out_below_a_file_is_one_line(tmp_path, rockcal):
    (tmp_path / "campaign.toml").write_text(CAMPAIGN)
    (tmp_path / "file").write_text("not a folder")
    code, stderr = rockcal("calibrate", tmp_path / "campaign.toml", "--out", tmp_path / "file" / "out")
    assert_one_line(code, stderr, ERROR + f"--out: {tmp_path / 'file' / 'out'}")
    assert "a part of the path is a file, not a folder" in stderr


def test_copying_runs_sqlite_alone_after_a_kill_keeps_the_runs(tmp_path):
    """A writer killed after storing runs (no close, no checkpoint at exit): the main file alone
    holds them."""
    killed = tmp_path / "killed"
    code = ("import os, sys\nfrom rockcal.campaign.runs.store import RunStore\nfrom rockcal.campaign.runs.spec import RunSpec, RunResult\n"
            f"store = RunStore({str(killed)!r})\n"
            "for i in range(3):\n"
            "    store.put(RunSpec('ucs', (('i', i),), (), 'e'), RunResult('ok', {'E_GPa': i}, None, 0.1))\n"
            "os._exit(0)\n")
    subprocess.run([sys.executable, "-c", code], check=True, timeout=120)
    copy = tmp_path / "copy"
    copy.mkdir()
    shutil.copy(killed / STORE_NAME, copy / STORE_NAME)
    store = RunStore(copy, create=False)
    assert store.count() == 3
    store.close()


def test_a_symbolic_link_in_out_is_replaced_not_followed(out, tmp_path, rockcal):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    for name in ("report.html", "record.json", "range_analysis.png"):
        (out / name).unlink(missing_ok=True)
        (out / name).symlink_to(victim)
    code, stderr = rockcal("report", out)
    assert code == 0, stderr
    assert victim.read_text() == "precious"
    assert not (out / "report.html").is_symlink() and "<html" in (out / "report.html").read_text()
    assert not (out / "record.json").is_symlink()


def test_a_symbolic_link_as_the_store_is_refused(out, tmp_path, rockcal):
    real = tmp_path / "elsewhere.sqlite"
    shutil.move(out / STORE_NAME, real)
    (out / STORE_NAME).symlink_to(real)
    assert_one_line(*rockcal(*commands(out)["resume"]), ERROR + f"OUT: {out / STORE_NAME} is a symbolic link")


@pytest.fixture
def small_disk(tmp_path):
    """A 1 MiB tmpfs (root only): a disk that fills up."""
    mount = tmp_path / "disk"
    mount.mkdir()
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m", "tmpfs", str(mount)],
                      capture_output=True).returncode != 0:
        pytest.skip("cannot mount a tmpfs here (needs root)")
    yield mount
    subprocess.run(["umount", "-l", str(mount)], check=True)


def fill(disk, leave: int) -> None:
    """Fill the disk but for about `leave` bytes."""
    free = shutil.disk_usage(disk).free
    with open(disk / "filler", "wb") as f:
        f.write(b"\0" * max(0, free - leave))


def test_a_full_disk_is_one_line_and_leaves_the_old_report_whole(out, small_disk, rockcal):
    target = small_disk / "out"
    shutil.copytree(out, target)
    shutil.copy(out.parent / "campaign.toml", small_disk / "campaign.toml")
    before = (target / "report.html").read_bytes()
    fill(small_disk, 4096)
    code, stderr = rockcal("report", target)
    assert_one_line(code, stderr, ERROR + "OUT: ")
    assert "No space left on device; free some space" in stderr
    assert (target / "report.html").read_bytes() == before
    assert sorted(p.name for p in target.iterdir()) == sorted(p.name for p in out.iterdir())  # no temp files


def test_a_disk_that_fills_mid_campaign_is_one_line_and_the_store_stays_whole(small_disk, rockcal):
    (small_disk / "campaign.toml").write_text(CAMPAIGN)
    fill(small_disk, 300 * 1024)
    out = small_disk / "out"
    code, stderr = rockcal("calibrate", small_disk / "campaign.toml", "--out", out, "--workers", "1", "--json")
    assert_one_line(code, stderr, ERROR + "--out: ")
    assert "free some space and run again (with --resume" in stderr
    assert (out / STORE_NAME).exists()
    os.remove(small_disk / "filler")
    store = RunStore(out)  # quick_check passes: whole, with the runs done before the disk filled
    assert store.count() >= 1
    store.close()


@pytest.fixture
def read_only_disk(out, tmp_path):
    """A read-only tmpfs holding a copy of a finished OUT (root only)."""
    mount = tmp_path / "ro"
    mount.mkdir()
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=8m", "tmpfs", str(mount)],
                      capture_output=True).returncode != 0:
        pytest.skip("cannot mount a tmpfs here (needs root)")
    shutil.copytree(out, mount / "out")
    shutil.copy(out.parent / "campaign.toml", mount / "campaign.toml")
    subprocess.run(["mount", "-o", "remount,ro", str(mount)], check=True)
    yield mount
    subprocess.run(["umount", "-l", str(mount)], check=True)


def test_a_read_only_out_is_one_line(read_only_disk, rockcal):
    out = read_only_disk / "out"
    for args, start in ((commands(out)["resume"], "--out: "), (["report", out], "OUT: "),
                        (["calibrate", read_only_disk / "campaign.toml", "--out", read_only_disk / "new"], "--out: ")):
        code, stderr = rockcal(*args)
        assert_one_line(code, stderr, ERROR + start)
        assert "read-only" in stderr
    code, stderr = rockcal("export", out, "--format", "json")  # reading needs no writing
    assert code == 0, stderr


def test_a_kill_while_writing_the_record_leaves_the_old_one_whole(finished, out, monkeypatch):
    """Writing record.json and report.html cut short half way (a kill): the files in OUT are the
    old ones, whole, and no temporary file is left."""
    import pathlib

    from rockcal.campaign.procedure.result import CalibrationResult
    from rockcal.campaign.job import write_record_and_report as _write_report

    store = RunStore(out, create=False)
    result = CalibrationResult.from_json(store.document("record.json"))
    (out / "record.json").write_text(result.to_json(indent=1))
    before = {name: (out / name).read_bytes() for name in ("record.json", "report.html")}

    def half_then_die(self, data, *args, **kwargs):
        with open(self, "wb") as f:
            f.write((data.encode() if isinstance(data, str) else data)[:len(data) // 2])
        raise KeyboardInterrupt

    monkeypatch.setattr(pathlib.Path, "write_text", half_then_die)
    monkeypatch.setattr(pathlib.Path, "write_bytes", half_then_die)
    try:
        with pytest.raises(KeyboardInterrupt):
            _write_report(result, store, out)
    finally:
        store.close()
    assert {name: (out / name).read_bytes() for name in before} == before
    assert not [p.name for p in out.iterdir() if ".tmp" in p.name]
