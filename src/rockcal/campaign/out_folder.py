"""The output folder of a campaign: made when needed and removed again if the command fails
before writing into it; a store this call made and that holds no run is not left behind; a rock
name picks the folder only when it is a plain folder name."""

from __future__ import annotations

import re
import sqlite3
from contextlib import contextmanager
from pathlib import Path

from rockcal.campaign.store import STORE_NAME
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
