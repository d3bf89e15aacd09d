"""Filesystem and SQLite errors at the CLI's edges (a read-only or full disk, a path through a
file, a damaged store) as one InputError naming the path and what to do."""

from __future__ import annotations

import errno
import sqlite3
from contextlib import contextmanager
from pathlib import Path

from rockcal.campaign.store import DAMAGED, STORE_NAME
from rockcal.errors import InputError

FULL = "free some space and run again (with --resume: the runs done are kept)"
ADVICE = {
    errno.ENOSPC: FULL, errno.EDQUOT: FULL, errno.EFBIG: FULL,
    errno.EROFS: "it is on a read-only file system",
    errno.EACCES: "it is not writable",
    errno.EPERM: "it is not writable",
    errno.ENOTDIR: "a part of the path is a file, not a folder",
    errno.EISDIR: "it is a folder, not a file",
    errno.ELOOP: "it is a symbolic link, which rockcal does not write through",
}
ELSEWHERE = "; choose another --out"  # after the advice on a path in OUT that cannot be written


def sqlite_advice(message: str) -> str:
    """What to do about an SQLite error on the store."""
    text = message.lower()
    if "full" in text:
        return FULL
    if "readonly" in text or "read-only" in text:
        return ADVICE[errno.EROFS] + ELSEWHERE
    if "locked" in text or "busy" in text:
        return "another process is using it; run again when it is done"
    if "unable to open" in text:
        return "check that the folder exists and is writable" + ELSEWHERE
    return f"the store may be damaged: {DAMAGED}"


@contextmanager
def one_line_errors(out: Path, field: str = "--out"):
    """Within it, an SQLite error or an OSError becomes an InputError naming its path: `field`
    for a path in `out`, "file" for one elsewhere (the specimen cache)."""
    store = Path(out) / STORE_NAME
    try:
        yield
    except sqlite3.Error as exc:
        raise InputError(field, f"{store}: {exc}; {sqlite_advice(str(exc))}") from None
    except OSError as exc:
        where = Path(str(exc.filename)) if exc.filename is not None else Path(out)
        inside = where.absolute().is_relative_to(Path(out).absolute())
        advice = ADVICE.get(exc.errno, "check the path and run again")
        if inside and advice != FULL:
            advice += ELSEWHERE
        raise InputError(field if inside else "file", f"{where}: {exc.strerror or exc}; {advice}") from None
