"""A file a user names (the campaign file, a measured curve), read as UTF-8 text of bounded
size: a binary file, a FIFO or device, or one that cannot be read is one error naming
the field, before any store or run."""

from __future__ import annotations

import os
import stat
from pathlib import Path

from rockcal.errors import InputError

MAX_BYTES = 16 * 2**20  # a campaign file or a measured curve is far smaller


def read_user_text(path: Path, field: str, limit: int = MAX_BYTES) -> str:
    """The UTF-8 text of `path`, read up to `limit` bytes; InputError naming `field` otherwise."""
    try:
        mode = os.stat(path).st_mode
        if stat.S_ISDIR(mode):
            raise InputError(field, f"{path} is a folder, not a file")
        if not stat.S_ISREG(mode):  # a FIFO or a device could block or never end
            raise InputError(field, f"{path} is not a regular file (a device or a pipe)")
        with open(path, "rb") as f:
            data = f.read(limit + 1)
    except OSError as exc:
        raise InputError(field, f"cannot read {path}: {exc.strerror or exc}") from None
    if len(data) > limit:
        raise InputError(field, f"{path} is larger than {limit // 2**20} MiB; not a file rockcal reads")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(field, f"{path} is not UTF-8 text (byte {data[exc.start]:#04x} at "
                                f"offset {exc.start})") from None
