"""Snapshots of a long run, so that a run stopped part way (the process killed, the machine
off) goes on from its last snapshot when it is run again, to the same numbers to the bit as a
run never stopped.

A run of a store (`rockcal.campaign.runs`) keeps its snapshot beside the store,
`<out>/snapshots/<run key>.pickle`: the test's rig, readings and loading as they stood after a
reading, written at most every SNAPSHOT_EVERY_S of the run (by `output_files.atomic_path`: to a
fresh name, then renamed over the last, so a stop while writing keeps the one before and a link
planted in the folder is never followed) and removed once the run is done. The
run's key holds its test, settings, parameters and the engine's version, and a snapshot holds
the rockcal version that wrote it: a snapshot of another version, or one that cannot be read,
is left aside and the run starts afresh. A run outside a store (`rockcal.simulate`) takes none.

A snapshot is a pickle, and loading a pickle can run any code, so each is signed (HMAC-SHA256)
with a key of this user's, made once in the specimen cache's folder (readable by the user
alone): a snapshot that another user or machine wrote, or one altered since, is never unpickled
but left aside, as one of another version.

The UCS and confined compression tests, in 2D and 3D, take snapshots (the long runs: full-size
specimens of clumped or flat-jointed grains, or of spheres); the Brazilian, bending and direct
tension tests run in one go. A test builds its rig in a `start()` that `resume` calls only for a
run starting afresh, and saves what it returned (`saver`) after each reading it goes on from.
"""

from __future__ import annotations

import contextlib
import hashlib
import hmac
import io
import os
import pickle
import tempfile
import time
from pathlib import Path
from typing import Callable

import numpy as np

from rockcal.output_files import atomic_path
from rockcal.version import __version__
from rockcal.specimens.specimen import cache_dir

SNAPSHOT_EVERY_S = 300.0
FOLDER = "snapshots"
KEY_FILE = "snapshot.key"
_SIGNATURE_BYTES = hashlib.sha256().digest_size

_current: Snapshot | None = None


def _key() -> bytes:
    """This user's snapshot key, made on first use (32 random bytes, the user's alone)."""
    path = cache_dir() / KEY_FILE
    if not path.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, made = tempfile.mkstemp(prefix=f".{KEY_FILE}.", dir=path.parent)  # a fresh file, the user's alone
        with open(fd, "wb") as file:
            file.write(os.urandom(32))
        try:
            os.link(made, path)  # whole, or not at all
        except FileExistsError:  # another process made it first
            pass
        finally:
            os.unlink(made)
    return path.read_bytes()


def _signature(body: bytes) -> bytes:
    return hmac.new(_key(), body, hashlib.sha256).digest()


def _view(root: np.ndarray, offset: int, shape: tuple, strides: tuple, dtype) -> np.ndarray:
    return np.ndarray(shape, dtype, buffer=root, offset=offset, strides=strides)


class _SharingPickler(pickle.Pickler):
    """Pickles a numpy view as a view of the array that holds its memory, that array pickled
    once: the engine's arrays share memory (a particle's position is a view of its row), and
    loaded they must share it still."""

    def reducer_override(self, obj):
        if not (isinstance(obj, np.ndarray) and isinstance(obj.base, np.ndarray)):
            return NotImplemented
        root = obj.base
        while isinstance(root.base, np.ndarray):
            root = root.base
        offset = obj.__array_interface__["data"][0] - root.__array_interface__["data"][0]
        return _view, (root, offset, obj.shape, obj.strides, obj.dtype)


class Snapshot:
    """The snapshot file of one run, `path`, written at most every `every_s` seconds."""

    def __init__(self, path: Path, every_s: float = SNAPSHOT_EVERY_S):
        self.path, self.every_s = Path(path), every_s
        self.earlier_s = 0.0  # the run's time before the snapshot it went on from
        self._started_s = self._saved_s = time.perf_counter()

    def load(self) -> tuple | None:
        """The objects the run saved last (`save`), or None: no snapshot, one not signed with
        this user's key, another version's, or one that cannot be read."""
        try:
            written = self.path.read_bytes()
            signature, body = written[:_SIGNATURE_BYTES], written[_SIGNATURE_BYTES:]
            if not hmac.compare_digest(signature, _signature(body)):
                return None
            version, earlier_s, objects = pickle.loads(body)
        except Exception:  # none, cut short, or of classes since changed: start afresh
            return None
        if version != __version__:
            return None
        self.earlier_s = earlier_s
        return objects

    def save(self, objects: tuple) -> None:
        """Save `objects` (one pickle, so objects they share stay shared) if the last save is
        `every_s` old."""
        now = time.perf_counter()
        if now - self._saved_s < self.every_s:
            return
        self.path.parent.mkdir(parents=True, exist_ok=True)
        body = io.BytesIO()
        run_s = self.earlier_s + now - self._started_s
        _SharingPickler(body, protocol=pickle.HIGHEST_PROTOCOL).dump((__version__, run_s, objects))
        with atomic_path(self.path) as part, open(part, "wb") as file:  # a fresh name, never a link
            file.write(_signature(body.getbuffer()))
            file.write(body.getbuffer())
        self._saved_s = time.perf_counter()

    def remove(self) -> None:
        self.path.unlink(missing_ok=True)


@contextlib.contextmanager
def kept_in(folder: Path | None, key: str, every_s: float | None = None):
    """While the block runs, the tests' snapshot is the run `key`'s in `folder` (None: no
    snapshots), saved every `every_s` (None: SNAPSHOT_EVERY_S); removed when the block ends
    without an error."""
    global _current
    if folder is None:
        yield
        return
    _current = Snapshot(Path(folder) / FOLDER / f"{key}.pickle",
                        SNAPSHOT_EVERY_S if every_s is None else every_s)
    try:
        yield
        _current.remove()
    finally:
        _current = None


def resume(start: Callable[[], tuple]) -> tuple:
    """The objects a test's loading goes on with: its run's snapshot's, or start()'s (a run
    starting afresh, or outside a store)."""
    saved = _current.load() if _current is not None else None
    return start() if saved is None else saved


def earlier_s() -> float:
    """The run's time before the snapshot it went on from (0 for a run starting afresh)."""
    return 0.0 if _current is None else _current.earlier_s


def saver(objects: tuple) -> Callable[[], None] | None:
    """What saves `objects` after a reading the test goes on from (`load_to_failure`'s
    snapshot), or None outside a store."""
    snapshot = _current
    return None if snapshot is None else lambda: snapshot.save(objects)
