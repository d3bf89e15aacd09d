"""The run store: every forward run of a campaign in one SQLite file (WAL), never run twice.

A run is keyed by what determines its result: test kind, specimen, parameters and engine
version. The driver alone writes, one transaction per finished run, so a campaign killed at
any moment loses at most the runs that were still going.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import sqlite3
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rockcal.errors import InputError

SCHEMA_VERSION = 1
STORE_NAME = "runs.sqlite"

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
class RunSpec:
    """What a forward run is: the test, its specimen settings and the full micro-parameters."""

    kind: str  # a lab test's name (`rockcal.labtests.registry`)
    specimen: tuple  # sorted (name, value) pairs
    params: tuple  # sorted (name, value) pairs, every micro-parameter
    engine: str

    @property
    def key(self) -> str:
        text = json.dumps([self.kind, self.specimen, self.params, self.engine])
        return hashlib.sha256(text.encode()).hexdigest()[:32]


@dataclass
class RunResult:
    """What a forward run gave: responses (or the error message), its curve and its cracks."""

    status: str  # "ok", "failed" or "timed out"
    responses: dict
    curve: np.ndarray | None
    wall_s: float
    message: str = ""
    cracks: np.ndarray | None = None  # rows (x m, y m, mode 1 tension / 2 shear) of broken bonds


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

    def __init__(self, folder: Path, *, create: bool = True):
        path = Path(folder) / STORE_NAME
        if not path.exists() and not create:
            raise InputError("OUT", f"{folder} holds no run store ({STORE_NAME})")
        if path.exists():
            _check_is_store(path)
        else:
            path.parent.mkdir(parents=True, exist_ok=True)
        self.path = path
        self.db = sqlite3.connect(path, timeout=30, isolation_level=None)
        self.db.execute("PRAGMA journal_mode=WAL")
        self.db.execute("PRAGMA synchronous=NORMAL")
        with self.db:
            self.db.executescript("BEGIN;" + _SCHEMA + "COMMIT;")
        version = self.db.execute("SELECT value FROM meta WHERE key='schema_version'").fetchone()
        if version is None:
            self.db.execute("INSERT INTO meta VALUES ('schema_version', ?)", (str(SCHEMA_VERSION),))

    def close(self) -> None:
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
        return RunResult(status, json.loads(responses or "{}"), from_blob(curve), wall_s,
                         message or "", from_blob(cracks))

    def run(self, key: str) -> StoredRun | None:
        """The run stored under `key`, or None when there is no such run."""
        row = self.db.execute("SELECT kind, status, specimen, params, responses, curve, cracks, "
                              "message, engine FROM runs WHERE key=?", (key,)).fetchone()
        if row is None:
            return None
        kind, status, specimen, params, responses, curve, cracks, message, engine = row
        return StoredRun(kind, status, json.loads(specimen), json.loads(params),
                         json.loads(responses or "{}"), from_blob(curve), from_blob(cracks),
                         message or "", engine)

    def put(self, spec: RunSpec, result: RunResult) -> None:
        """Store a finished run (one transaction); a run already there is left as it is."""
        now = time.time()
        with self.db:
            self.db.execute("BEGIN IMMEDIATE")
            self.db.execute(
                "INSERT OR IGNORE INTO runs VALUES (?,?,?,?,?,?,?,?,?,?,?,?)",
                (spec.key, spec.kind, json.dumps(dict(spec.specimen)), json.dumps(dict(spec.params)),
                 spec.engine, result.status, json.dumps(result.responses), to_blob(result.curve),
                 to_blob(result.cracks), result.wall_s, result.message, now))
            self.db.execute("INSERT INTO executions VALUES (?,?,?)", (spec.key, os.getpid(), now))

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
        with self.db:
            self.db.execute("BEGIN IMMEDIATE")
            self.db.execute("INSERT OR REPLACE INTO documents VALUES (?, ?)", (name, text))

    def document(self, name: str) -> str | None:
        row = self.db.execute("SELECT text FROM documents WHERE name=?", (name,)).fetchone()
        return None if row is None else row[0]


def _check_is_store(path: Path) -> None:
    with open(path, "rb") as f:
        if f.read(16) != b"SQLite format 3\x00":
            raise InputError("OUT", f"{path} is not a rockcal run store (not an SQLite file)")
    try:
        db = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
        try:
            tables = {r[0] for r in db.execute("SELECT name FROM sqlite_master WHERE type='table'")}
            version = None
            if "meta" in tables:
                version = db.execute("SELECT value FROM meta WHERE key='schema_version'").fetchone()
        finally:
            db.close()
    except sqlite3.DatabaseError as exc:
        raise InputError("OUT", f"{path} is not a readable run store: {exc}") from None
    if "runs" not in tables or "meta" not in tables:
        raise InputError("OUT", f"{path} is an SQLite file but not a rockcal run store")
    if version is not None and not str(version[0]).isdigit():
        raise InputError("OUT", f"{path} has an unknown store schema {version[0]!r}")
    if version is not None and int(version[0]) > SCHEMA_VERSION:
        raise InputError("OUT", f"{path} was written by a newer rockcal (store schema "
                                f"{version[0]} > {SCHEMA_VERSION}); upgrade rockcal")


def to_blob(curve: np.ndarray | None) -> bytes | None:
    if curve is None:
        return None
    buffer = io.BytesIO()
    np.save(buffer, np.asarray(curve, dtype=float), allow_pickle=False)
    return buffer.getvalue()


def from_blob(blob: bytes | None) -> np.ndarray | None:
    return None if blob is None else np.load(io.BytesIO(blob), allow_pickle=False)
