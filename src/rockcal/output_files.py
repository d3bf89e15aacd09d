"""Every file rockcal writes (JSON, CSV, HTML, figures), written whole or not at all and never
through a link: to a fresh hidden name beside it, `.NAME.<pid>.<host>.<random>.tmp.SUFFIX`,
then renamed over NAME. A kill or a full disk leaves the old file or none; a symbolic link at
NAME is replaced, never followed. A killed write leaves its temporary file behind: the next
write of NAME removes it once the pid in its name no longer runs on this machine (the host
part keeps another machine's writes on a shared disk out of it)."""

from __future__ import annotations

import csv
import json
import math
import os
import re
import socket
import tempfile
import zlib
from contextlib import contextmanager
from pathlib import Path

HOST = f"{zlib.crc32(socket.gethostname().encode()):08x}"  # this machine, in a temporary file's name


@contextmanager
def atomic_path(path: Path):
    """A fresh temporary path beside `path` (same suffix) to write to; renamed to `path` when
    the block ends without an error, with the permissions a new file gets (not the temporary
    file's owner-only ones), removed otherwise (a block that removes it leaves `path` as it
    was)."""
    path = Path(path)
    _remove_stale(path)
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.{os.getpid()}.{HOST}.", suffix=f".tmp{path.suffix}",
                                   dir=path.parent)
    except OSError as exc:
        exc.filename = str(path)  # name the file asked for, not a temporary name
        raise
    os.close(fd)
    try:
        yield Path(tmp)
        if not os.path.exists(tmp):
            return
        os.chmod(tmp, 0o666 & ~_umask())
        with open(tmp, "rb+") as f:
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _remove_stale(path: Path) -> None:
    """Remove the temporary files of `path` that killed writes left: our pattern alone, made on
    this machine by a process that no longer runs."""
    ours = re.compile(rf"\.{re.escape(path.name)}\.(\d+)\.{HOST}\.[^.]+\.tmp{re.escape(path.suffix)}")
    try:
        names = os.listdir(path.parent)
    except OSError:
        return  # the write itself reports a folder it cannot use
    for name in names:
        found = ours.fullmatch(name)
        if found and not _running(int(found[1])):
            try:
                (path.parent / name).unlink()
            except OSError:
                pass  # another writer removed it first, or it cannot be: it stays, harmless


def _running(pid: int) -> bool:
    """Process `pid` runs on this machine, or may (another user's; Windows, where signal 0
    would end it)."""
    if os.name == "nt":
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (OSError, OverflowError):  # another user's process (EPERM), or not a pid at all
        pass
    return True


def _umask() -> int:
    """This process's umask (read by setting it and setting it back)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def write_atomic(path: Path, data: str | bytes) -> Path:
    """Write `data` (text as UTF-8) to `path` atomically; returns `path`."""
    with atomic_path(path) as tmp:
        tmp.write_bytes(data.encode("utf-8") if isinstance(data, str) else data)
    return Path(path)


def write_csv(path: Path, header: list[str], rows) -> Path:
    """Write a CSV file, `header` then `rows`, atomically; returns `path`."""
    with atomic_path(path) as tmp, open(tmp, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(header)
        writer.writerows(rows)
    return Path(path)


def save_figure(fig, path: Path, **options) -> Path:
    """Save a matplotlib figure to `path` atomically, in the format its suffix names (given
    explicitly: the temporary name must not choose it); `options` go to `savefig`."""
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format=path.suffix.lstrip(".") or "png", **options)
    return path


def json_text(data, indent: int | None = None) -> str:
    """`data` as JSON, a number that is not finite (a response a run could not read) as null:
    JSON has no NaN, and a reader of strict JSON would refuse the file."""
    return json.dumps(_finite(data), indent=indent, allow_nan=False)


def _finite(value):
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(v) for v in value]
    return value
