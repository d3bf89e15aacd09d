"""Files written whole: a file written atomically has the permissions a new file gets under
the process's umask (a report is readable by whoever may read the folder), not the temporary
file's owner-only ones; a failed write leaves the old file."""

import os
import stat

import pytest

from rockcal.output_files import atomic_path, write_atomic


@pytest.mark.parametrize("umask, mode", [(0o022, 0o644), (0o077, 0o600)])
def test_a_written_file_has_the_modes_of_a_new_file(tmp_path, umask, mode):
    before = os.umask(umask)
    try:
        written = write_atomic(tmp_path / "report.html", "<html></html>")
        with atomic_path(tmp_path / "figure.png") as tmp:
            tmp.write_bytes(b"png")
    finally:
        os.umask(before)
    assert stat.S_IMODE(written.stat().st_mode) == mode
    assert stat.S_IMODE((tmp_path / "figure.png").stat().st_mode) == mode


def test_a_failed_write_leaves_the_old_file(tmp_path):
    target = write_atomic(tmp_path / "record.json", "old")
    with pytest.raises(RuntimeError), atomic_path(target) as tmp:
        tmp.write_text("half")
        raise RuntimeError("killed")
    assert target.read_text() == "old" and list(tmp_path.iterdir()) == [target]
