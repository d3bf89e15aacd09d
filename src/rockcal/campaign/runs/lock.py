"""One writer per run store: an advisory lock (flock) on OUT/runs.lock, held for a campaign's
life. The kernel drops it when its process dies, however it dies, so the lock of a dead
process is simply taken; the file names the holder (pid, host, since) for the one who waits.
Where there is no flock (Windows), no lock is held: keeping one writer is then the user's care.
"""

from __future__ import annotations

import json
import os
import socket
import time
from contextlib import contextmanager
from pathlib import Path
from typing import Callable

from rockcal.errors import InputError

try:
    import fcntl
except ImportError:
    fcntl = None

LOCK_NAME = "runs.lock"


def holder_text(fd: int) -> str:
    """Who holds the lock, in words, from the lock file's contents."""
    try:
        data = json.loads(os.pread(fd, 4096, 0).decode())
        return f"pid {data['pid']} on {data['host']}, since {data['since']}"
    except (OSError, ValueError, KeyError, TypeError):
        return "a process that has not yet said who it is"


def _open(path: Path) -> int:
    return os.open(path, os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0), 0o644)


def _is_current(fd: int, path: Path) -> bool:
    """The locked file is still the one at `path` (its last holder may have removed it)."""
    try:
        return os.path.samestat(os.fstat(fd), os.stat(path, follow_symlinks=False))
    except FileNotFoundError:
        return False


def _claim(fd: int) -> None:
    """Say who holds the lock (a full disk leaves it unsaid: the lock holds all the same)."""
    since = time.strftime("%Y-%m-%d %H:%M:%S %Z")
    text = json.dumps({"pid": os.getpid(), "host": socket.gethostname(), "since": since})
    try:
        os.ftruncate(fd, 0)
        os.pwrite(fd, text.encode(), 0)
    except OSError:
        pass


@contextmanager
def store_lock(folder: Path, wait: bool = False, waiting: Callable[[str], None] | None = None,
               field: str = "--out", can_wait: bool = True):
    """Hold the lock of the store in `folder` (which must exist) within the block. Held
    elsewhere: an InputError naming the holder (advising --wait if the command `can_wait`),
    or with `wait` block until it is free (`waiting(holder)` is told once)."""
    if fcntl is None:
        yield
        return
    path = Path(folder) / LOCK_NAME
    told = False
    while True:
        fd = _open(path)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = holder_text(fd)
            if not wait:
                os.close(fd)
                raise in_use(folder, holder, field, can_wait) from None
            if waiting is not None and not told:
                waiting(holder)
                told = True
            fcntl.flock(fd, fcntl.LOCK_EX)
        if _is_current(fd, path):
            break
        os.close(fd)
    try:
        _claim(fd)
        yield
    finally:
        path.unlink(missing_ok=True)  # while still held: a waiter then finds it gone and retries
        os.close(fd)


def in_use(folder: Path, holder: str, field: str = "--out", can_wait: bool = True) -> InputError:
    """The refusal of a store another rockcal (`holder`) holds, naming `field`."""
    then = ", or add --wait" if can_wait else " and run again"
    return InputError(field, f"{folder} is in use by another rockcal ({holder}); wait for it to end{then}")


def holder_of(folder: Path) -> str | None:
    """Who holds the lock of the store in `folder` now, in words, or None: no one (or no
    flock). Asked read-only, so a read-only folder can be asked; the shared lock taken to ask
    is let go at once."""
    if fcntl is None:
        return None
    try:
        fd = os.open(Path(folder) / LOCK_NAME,
                     os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0))
    except OSError:
        return None  # no lock file: no holder
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
        return None
    except BlockingIOError:
        return holder_text(fd)
    finally:
        os.close(fd)
