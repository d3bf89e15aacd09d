"""An error's advice names only options of the command at hand: `export-specimen --to` a folder
that cannot be written says to choose another --to; `report` on a campaign folder in use has no
--wait to offer; `export` of a campaign still running says to wait for its end, not to resume
it; only calibrate's --out is advised --resume on a full disk."""

import errno
import os
import subprocess

import pytest

from rockcal.campaign.files import one_line_errors
from rockcal.campaign.runs.lock import store_lock
from rockcal.campaign.runs.store import RunStore
from rockcal.errors import InputError
import test_cli
import test_export

finished = test_export.finished  # the fixtures: a finished campaign's store,
rockcal = test_cli.rockcal  # and `rockcal ARGS` in this process


def error_line(run) -> str:
    """The one line a command that failed on its input wrote (exit code 2)."""
    assert run.returncode == 2 and len(run.stderr.splitlines()) == 1, run.stderr
    return run.stderr.strip()


@pytest.fixture
def read_only(tmp_path):
    """A folder that cannot be written: mode 555, or for root a read-only tmpfs."""
    folder = tmp_path / "read-only"
    folder.mkdir()
    if os.geteuid() != 0:
        folder.chmod(0o555)
        yield folder
        folder.chmod(0o755)
        return
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "ro,size=64k", "tmpfs", str(folder)],
                      capture_output=True).returncode != 0:
        pytest.skip("cannot mount a tmpfs here")
    yield folder
    subprocess.run(["umount", "-l", str(folder)], check=True)


def test_export_specimen_to_a_folder_that_cannot_be_written(finished, read_only, rockcal):
    line = error_line(rockcal("export-specimen", str(finished), "--to", str(read_only)))
    assert line.startswith(f"rockcal: error: --to: {read_only / 'balls.csv'}: ") and line.endswith(
        "; choose another --to"), line


def test_report_on_a_folder_in_use_offers_no_wait(finished, rockcal):
    with store_lock(finished):
        line = error_line(rockcal("report", str(finished)))
    assert line.startswith(f"rockcal: error: OUT: {finished} is in use by another rockcal (pid {os.getpid()} ")
    assert line.endswith("; wait for it to end and run again") and "--wait" not in line, line


@pytest.mark.parametrize("command", [["export", "--format", "json"], ["export-specimen", "--to", "specimen"]])
def test_export_of_a_running_campaign_says_to_wait(command, tmp_path, rockcal):
    out = tmp_path / "out"
    store = RunStore(out)  # a campaign begun, with no result yet
    store.save_document("campaign.toml", test_export.CAMPAIGN)
    store.close()
    args = [command[0], str(out), *command[1:]]
    with store_lock(out):
        line = error_line(rockcal(*args))
    assert line.startswith(f"rockcal: error: OUT: the campaign in {out} is running (pid {os.getpid()} ")
    assert line.endswith("wait for it to end, then export again") and "--resume" not in line, line
    line = error_line(rockcal(*args))  # stopped, not running: calibrate goes on with it
    assert line.endswith(f"run `rockcal calibrate --resume --out {out}`"), line


@pytest.mark.parametrize("field, code, advice", [
    ("--out", errno.ENOSPC, "free some space and run again (with --resume: the runs done are kept)"),
    ("--to", errno.ENOSPC, "free some space and run again"),
    ("--to", errno.EACCES, "it is not writable; choose another --to"),
    ("OUT", errno.EROFS, "it is on a read-only file system"),
])
def test_the_advice_on_a_file_names_the_commands_own_field(field, code, advice, tmp_path):
    with pytest.raises(InputError) as failed, one_line_errors(tmp_path, field):
        raise OSError(code, os.strerror(code), str(tmp_path / "balls.csv"))
    assert str(failed.value) == f"{field}: {tmp_path / 'balls.csv'}: {os.strerror(code)}; {advice}"
