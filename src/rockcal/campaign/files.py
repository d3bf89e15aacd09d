"""File safety at the edges of a campaign (its files are written whole by
`rockcal.output_files`): the output folder, made when needed and removed again if the command
fails before writing into it, with no empty store left behind; and filesystem and SQLite errors
(a read-only or full disk, a path through a file, a damaged store) as one InputError naming the
path and what to do, advising only the options of the command at hand."""

from __future__ import annotations

import errno
import re
import sqlite3
from contextlib import contextmanager
from pathlib import Path

from rockcal.campaign.runs.store import DAMAGED, STORE_NAME
from rockcal.errors import InputError


PLAIN_NAME = re.compile(r"[^/\\\x00]+")


def is_plain_name(name: str) -> bool:
    """One folder name: no separator, not hidden, not . or .., at most 255 bytes."""
    return bool(PLAIN_NAME.fullmatch(name)) and not name.startswith(".") and len(name.encode()) <= 255


class out_folder:
    """OUT made if need be (InputError if it or a folder above it is a file); a folder made
    here is removed again if the command fails before writing anything into it."""

    def __init__(self, out: Path):
        self.out = Path(out)
        self.made = False

    def __enter__(self):
        if self.out.exists() and not self.out.is_dir():
            raise InputError("--out", f"{self.out} is a file, not a folder")
        if not self.out.exists():
            self.out.mkdir(parents=True)
            self.made = True
        return self

    def __exit__(self, kind, exc, tb):
        if exc is not None and self.made:
            try:
                self.out.rmdir()  # only if empty
            except OSError:
                pass
        return False


@contextmanager
def no_empty_store(out: Path, new: bool):
    """A store made within the block and holding no run is removed if the block fails (an
    unreachable scheduler, a disk full from the start)."""
    try:
        yield
    except BaseException:
        if new and _holds_no_run(out / STORE_NAME):
            for suffix in ("", "-wal", "-shm", "-journal"):
                Path(f"{out / STORE_NAME}{suffix}").unlink(missing_ok=True)
        raise


def _holds_no_run(path: Path) -> bool:
    """The store at `path` surely holds no run (none, or no runs table yet)."""
    try:
        db = sqlite3.connect(f"{path.absolute().as_uri()}?mode=ro", uri=True)
        try:
            return db.execute("SELECT COUNT(*) FROM runs").fetchone()[0] == 0
        finally:
            db.close()
    except sqlite3.Error as exc:
        return "no such table" in str(exc) or not path.exists()


FULL = "free some space and run again"
RESUMES = "--out"  # the field of calibrate, the one command that goes on with the runs done
ADVICE = {
    errno.ENOSPC: FULL, errno.EDQUOT: FULL, errno.EFBIG: FULL,
    errno.EROFS: "it is on a read-only file system",
    errno.EACCES: "it is not writable",
    errno.EPERM: "it is not writable",
    errno.ENOTDIR: "a part of the path is a file, not a folder",
    errno.EISDIR: "it is a folder, not a file",
    errno.ELOOP: "it is a symbolic link, which rockcal does not write through",
}


def full_advice(field: str) -> str:
    """What to do about a full disk; with --resume for calibrate's --out."""
    return FULL + (" (with --resume: the runs done are kept)" if field == RESUMES else "")


def elsewhere(field: str) -> str:
    """After the advice on a path in `field` that cannot be written: choose another, when
    `field` is an option (a positional OUT is a campaign's own folder: no other will do)."""
    return f"; choose another {field}" if field.startswith("-") else ""


def sqlite_advice(message: str, field: str = "--out") -> str:
    """What to do about an SQLite error on the store in `field`."""
    text = message.lower()
    if "full" in text:
        return full_advice(field)
    if "readonly" in text or "read-only" in text:
        return ADVICE[errno.EROFS] + elsewhere(field)
    if "locked" in text or "busy" in text:
        return "another process is using it; run again when it is done"
    if "unable to open" in text:
        return "check that the folder exists and is writable" + elsewhere(field)
    return f"the store may be damaged: {DAMAGED}"


@contextmanager
def one_line_errors(out: Path, field: str = "--out"):
    """Within it, an SQLite error or an OSError becomes an InputError naming its path: `field`
    for a path in `out`, "file" for one elsewhere (the specimen cache)."""
    store = Path(out) / STORE_NAME
    try:
        yield
    except sqlite3.Error as exc:
        raise InputError(field, f"{store}: {exc}; {sqlite_advice(str(exc), field)}") from None
    except OSError as exc:
        where = Path(str(exc.filename)) if exc.filename is not None else Path(out)
        inside = where.absolute().is_relative_to(Path(out).absolute())
        advice = ADVICE.get(exc.errno, "check the path and run again")
        if advice == FULL:
            advice = full_advice(field)
        elif inside:
            advice += elsewhere(field)
        raise InputError(field if inside else "file", f"{where}: {exc.strerror or exc}; {advice}") from None
