"""The run store: every forward run of a campaign in one SQLite file, never run twice.

A run is keyed by what determines its result: test kind, specimen, parameters and engine
version. The driver alone writes (one campaign per store: `store_lock`), one transaction per
finished run, each checkpointed into the main file, so a campaign killed at any moment loses at
most the runs that were still going and runs.sqlite alone holds the rest. A run that failed or
timed out is kept, and replaced when it is run again (`retries`).
"""

from __future__ import annotations

import io
import json
import os
import sqlite3
import time
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rockcal.campaign.runs.spec import RunResult, RunSpec
from rockcal.errors import InputError

SCHEMA_VERSION = 1
STORE_NAME = "runs.sqlite"
RUN_COLUMNS = ("key", "kind", "specimen", "params", "engine", "status", "responses", "curve", "cracks",
               "wall_s", "message", "finished_at")
DAMAGED = "restore it from a copy, or start afresh in another --out"

_SCHEMA = """
CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS runs (
    key TEXT PRIMARY KEY, kind TEXT NOT NULL, specimen TEXT NOT NULL, params TEXT NOT NULL,
    engine TEXT NOT NULL, status TEXT NOT NULL, responses TEXT, curve BLOB, cracks BLOB,
    wall_s REAL, message TEXT, finished_at REAL NOT NULL);
CREATE TABLE IF NOT EXISTS executions (run_key TEXT NOT NULL, pid INTEGER, finished_at REAL);
CREATE TABLE IF NOT EXISTS documents (name TEXT PRIMARY KEY, text TEXT NOT NULL);
"""


@dataclass(frozen=True)
class StoredRun:
    """A forward run as the store holds it (curve and cracks as arrays, or None)."""

    kind: str
    status: str
    specimen: dict
    params: dict
    responses: dict
    curve: np.ndarray | None
    cracks: np.ndarray | None
    message: str
    engine: str


class RunStore:
    """Forward runs by key, in OUT/runs.sqlite."""

    def __init__(self, folder: Path, *, create: bool = True, readonly: bool = False):
        path = Path(folder) / STORE_NAME
        if not path.exists() and not path.is_symlink() and (not create or readonly):
            raise InputError("OUT", f"{folder} holds no run store ({STORE_NAME})")
        if path.exists() or path.is_symlink():
            _check_is_store(path)
        else:
            path.parent.mkdir(parents=True, exist_ok=True)
        self.path = path
        self.readonly = readonly
        if readonly:
            self.db = sqlite3.connect(_uri(path, "ro"), uri=True, timeout=30, isolation_level=None)
            return
        self.db = sqlite3.connect(path, timeout=30, isolation_level=None)
        self.db.execute("PRAGMA journal_mode=WAL")
        self.db.execute("PRAGMA synchronous=NORMAL")
        with self.db:
            self.db.executescript("BEGIN;" + _SCHEMA + "COMMIT;")
        version = self.db.execute("SELECT value FROM meta WHERE key='schema_version'").fetchone()
        if version is None:
            self.db.execute("INSERT INTO meta VALUES ('schema_version', ?)", (str(SCHEMA_VERSION),))

    def close(self) -> None:
        """Close, with every run in the main file and the store left in rollback mode: a copy
        of runs.sqlite alone holds them, and a read-only disk can be read."""
        if not self.readonly:
            try:
                self.db.execute("PRAGMA wal_checkpoint(TRUNCATE)")
                self.db.execute("PRAGMA journal_mode=DELETE")
            except sqlite3.Error:
                pass  # a reader still open, or the disk full: the WAL keeps the runs
        self.db.close()

    def delete(self) -> None:
        """Remove the (closed) store file and its WAL files."""
        for suffix in ("", "-wal", "-shm"):
            Path(f"{self.path}{suffix}").unlink(missing_ok=True)

    def get(self, spec: RunSpec) -> RunResult | None:
        row = self.db.execute("SELECT status, responses, curve, wall_s, message, cracks FROM runs "
                              "WHERE key=?", (spec.key,)).fetchone()
        if row is None:
            return None
        status, responses, curve, wall_s, message, cracks = row
        with self._damaged(spec.key):
            return RunResult(status, _mapping(responses), from_blob(curve), wall_s,
                             message or "", from_blob(cracks))

    def run(self, key: str) -> StoredRun | None:
        """The run stored under `key`, or None when there is no such run."""
        row = self.db.execute("SELECT kind, status, specimen, params, responses, curve, cracks, "
                              "message, engine FROM runs WHERE key=?", (key,)).fetchone()
        if row is None:
            return None
        kind, status, specimen, params, responses, curve, cracks, message, engine = row
        with self._damaged(key):
            return StoredRun(kind, status, _mapping(specimen), _mapping(params),
                             _mapping(responses), from_blob(curve), from_blob(cracks),
                             message or "", engine)

    def _damaged(self, key: str):
        return _damaged(self.path, key)

    def put(self, spec: RunSpec, result: RunResult) -> None:
        """Store a finished run (one transaction): a run done is left as it is, a failed or
        timed-out one is replaced by this try."""
        now = time.time()
        with self.db:
            self.db.execute("BEGIN IMMEDIATE")
            self.db.execute(
                "INSERT INTO runs VALUES (?,?,?,?,?,?,?,?,?,?,?,?) ON CONFLICT(key) DO UPDATE SET "
                + ", ".join(f"{c}=excluded.{c}" for c in RUN_COLUMNS[1:]) + " WHERE runs.status != 'ok'",
                (spec.key, spec.kind, json.dumps(dict(spec.specimen)), json.dumps(dict(spec.params)),
                 spec.engine, result.status, json.dumps(result.responses), to_blob(result.curve),
                 to_blob(result.cracks), result.wall_s, result.message, now))
            self.db.execute("INSERT INTO executions VALUES (?,?,?)", (spec.key, os.getpid(), now))
        self.db.execute("PRAGMA wal_checkpoint(PASSIVE)")

    def tries(self, key: str) -> int:
        """How many times the run of `key` was executed and stored."""
        return self.db.execute("SELECT COUNT(*) FROM executions WHERE run_key=?", (key,)).fetchone()[0]

    def failures(self) -> list[tuple[str, str, int]]:
        """(key, status, tries) of each stored run that failed or timed out."""
        return list(self.db.execute(
            "SELECT key, status, (SELECT COUNT(*) FROM executions WHERE run_key=runs.key) FROM runs "
            "WHERE status != 'ok' ORDER BY finished_at"))

    def wall_times(self, kind: str) -> list[tuple[dict, float]]:
        """(specimen settings, wall time s) of each finished run of a test."""
        rows = self.db.execute("SELECT specimen, wall_s FROM runs WHERE kind=? AND status='ok'", (kind,))
        return [(json.loads(specimen), wall) for specimen, wall in rows]

    def count(self) -> int:
        """How many runs the store holds."""
        return self.db.execute("SELECT COUNT(*) FROM runs").fetchone()[0]

    def executions(self) -> dict[str, int]:
        """How many times each stored run was executed (1 each, unless something is wrong)."""
        return dict(self.db.execute("SELECT run_key, COUNT(*) FROM executions GROUP BY run_key"))

    def save_document(self, name: str, text: str) -> None:
        """Store a document by name (one already so stored is not written again)."""
        if self.document(name) == text:
            return
        with self.db:
            self.db.execute("BEGIN IMMEDIATE")
            self.db.execute("INSERT OR REPLACE INTO documents VALUES (?, ?)", (name, text))

    def document(self, name: str) -> str | None:
        row = self.db.execute("SELECT text FROM documents WHERE name=?", (name,)).fetchone()
        return None if row is None else row[0]


@contextmanager
def _damaged(path: Path, key: str):
    """A stored run that cannot be read back is an InputError naming the store."""
    try:
        yield
    except (ValueError, TypeError, EOFError) as exc:
        raise InputError("OUT", f"{path}: the stored run {key[:12]} cannot be read "
                                f"({type(exc).__name__}: {exc}); the store is damaged: {DAMAGED}") from None


def _check_runs(db, path: Path) -> None:
    """Every stored run reads back (its JSON and arrays), before anything is written."""
    for key, specimen, params, responses, curve, cracks in db.execute(
            "SELECT key, specimen, params, responses, curve, cracks FROM runs"):
        with _damaged(path, str(key)):
            for text in (specimen, params, responses):
                _mapping(text)
            from_blob(curve), from_blob(cracks)


def _known(version) -> bool:
    """A store schema this rockcal reads (None: a store from before the meta row)."""
    return version is None or (str(version[0]).isdigit() and int(version[0]) <= SCHEMA_VERSION)


def _uri(path: Path, mode: str) -> str:
    """An SQLite URI of `path` (any characters in it quoted) opened in `mode`."""
    return f"{Path(path).absolute().as_uri()}?mode={mode}"


def _check_is_store(path: Path) -> None:
    """A run store rockcal can use: a real file, SQLite, whole (quick_check), of this schema."""
    if path.is_symlink():
        raise InputError("OUT", f"{path} is a symbolic link; rockcal writes only a store that is a "
                                "file of its own (copy the store there instead)")
    if not path.is_file():
        raise InputError("OUT", f"{path} is not a file")
    try:
        with open(path, "rb") as f:
            head = f.read(16)
    except OSError as exc:
        raise InputError("OUT", f"cannot read {path}: {exc.strerror}") from None
    if head != b"SQLite format 3\x00":
        raise InputError("OUT", f"{path} is not a rockcal run store (not an SQLite file)")
    try:
        db = sqlite3.connect(_uri(path, "ro"), uri=True)
        try:
            tables = {r[0] for r in db.execute("SELECT name FROM sqlite_master WHERE type='table'")}
            version, columns, check = None, set(), ["ok"]
            if "meta" in tables:
                version = db.execute("SELECT value FROM meta WHERE key='schema_version'").fetchone()
            if "runs" in tables:
                columns = {r[1] for r in db.execute("PRAGMA table_info(runs)")}
                check = [r[0] for r in db.execute("PRAGMA quick_check")]
            if check == ["ok"] and set(RUN_COLUMNS) <= columns and _known(version):
                _check_runs(db, path)
        finally:
            db.close()
    except sqlite3.DatabaseError as exc:
        raise InputError("OUT", f"{path} is damaged or not a run store ({exc}): {DAMAGED}") from None
    if "runs" not in tables or "meta" not in tables:
        raise InputError("OUT", f"{path} is an SQLite file but not a rockcal run store")
    if check != ["ok"]:
        raise InputError("OUT", f"{path} is damaged (SQLite quick_check: {check[0]}): {DAMAGED}")
    if version is not None and not str(version[0]).isdigit():
        raise InputError("OUT", f"{path} has an unknown store schema {version[0]!r}")
    if version is not None and int(version[0]) > SCHEMA_VERSION:
        raise InputError("OUT", f"{path} was written by a newer rockcal (store schema "
                                f"{version[0]} > {SCHEMA_VERSION}); upgrade rockcal")
    missing = [c for c in RUN_COLUMNS if c not in columns]
    if missing:
        raise InputError("OUT", f"{path} has another store schema (its runs lack {missing[0]}); "
                                "use the rockcal that wrote it, or another --out")


def _mapping(text: str | None) -> dict:
    """A JSON object stored as text (None: an empty one); ValueError for anything else."""
    value = json.loads(text or "{}")
    if not isinstance(value, dict):
        raise ValueError(f"expected a JSON object, got {type(value).__name__}")
    return value


def to_blob(curve: np.ndarray | None) -> bytes | None:
    if curve is None:
        return None
    buffer = io.BytesIO()
    np.save(buffer, np.asarray(curve, dtype=float), allow_pickle=False)
    return buffer.getvalue()


def from_blob(blob: bytes | None) -> np.ndarray | None:
    return None if blob is None else np.load(io.BytesIO(blob), allow_pickle=False)
