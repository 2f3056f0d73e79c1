"""The server's SQLite database: connections in WAL mode and the schema's migrations.

The database's schema version is its ``PRAGMA user_version``: the number of :data:`MIGRATIONS` applied.
:func:`migrate` applies the missing ones in order, each in one ``BEGIN IMMEDIATE`` transaction that
also sets the version (so two servers starting on one new file apply each migration once), and refuses
a database of a newer schema than this code knows.

Tables (migration 1):

``teams``
    ``name`` (1-64 characters of ``[A-Za-z0-9._-]``), ``created``.
``tokens``
    ``id`` (public, names the token in lists and revocations), ``team``, ``sha256`` (of the whole
    token; the token itself is never stored), ``created``, ``revoked`` (null while valid).
``submissions``
    ``id`` (random, url-safe), ``team``, ``name``, ``split``, ``public``, ``status`` (``queued``,
    ``scoring``, ``done``, ``failed``), ``file`` (relative to the store), ``body_bytes``, ``lines``,
    ``records``, ``track`` (JSON), ``instruction_type``, ``created``; the claim: ``claimed_by`` (a
    server instance's id), ``lease_until``, ``attempts``; the outcome: ``scored_at``, ``result``
    (JSON: the public group means), ``error``.
``scorings``
    One row per scored submission (``UNIQUE(submission_id)``), written in the transaction that sets
    ``done``: which instance scored it, on which attempt, when, in how many seconds.

Times are Unix seconds (REAL). Connections run in autocommit mode; writers open their own
``BEGIN IMMEDIATE`` transaction (:func:`immediate`).
"""

from __future__ import annotations

import os
import sqlite3
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path

from navverse.serve.errors import ServeError

__all__ = ["BUSY_TIMEOUT_MS", "MIGRATIONS", "SCHEMA_VERSION", "connect", "immediate", "migrate", "open_db"]

BUSY_TIMEOUT_MS = 10_000
"""How long a statement waits for another connection's write lock before it fails."""

Migration = Sequence[str] | Callable[[sqlite3.Connection], None]

_V1 = (
    """CREATE TABLE teams (
        name TEXT PRIMARY KEY,
        created REAL NOT NULL
    )""",
    """CREATE TABLE tokens (
        id TEXT PRIMARY KEY,
        team TEXT NOT NULL REFERENCES teams(name),
        sha256 TEXT NOT NULL UNIQUE,
        created REAL NOT NULL,
        revoked REAL
    )""",
    "CREATE INDEX tokens_team ON tokens(team)",
    """CREATE TABLE submissions (
        id TEXT PRIMARY KEY,
        team TEXT NOT NULL REFERENCES teams(name),
        name TEXT NOT NULL,
        split TEXT NOT NULL,
        public INTEGER NOT NULL CHECK (public IN (0, 1)),
        status TEXT NOT NULL CHECK (status IN ('queued', 'scoring', 'done', 'failed')),
        file TEXT NOT NULL,
        body_bytes INTEGER NOT NULL,
        lines INTEGER NOT NULL,
        records INTEGER NOT NULL,
        track TEXT NOT NULL,
        instruction_type TEXT,
        created REAL NOT NULL,
        claimed_by TEXT,
        lease_until REAL,
        attempts INTEGER NOT NULL DEFAULT 0,
        scored_at REAL,
        result TEXT,
        error TEXT
    )""",
    "CREATE INDEX submissions_queue ON submissions(status, created)",
    "CREATE INDEX submissions_team ON submissions(team, created)",
    "CREATE INDEX submissions_board ON submissions(split, status, public)",
    """CREATE TABLE scorings (
        submission_id TEXT NOT NULL UNIQUE REFERENCES submissions(id),
        instance TEXT NOT NULL,
        attempt INTEGER NOT NULL,
        scored_at REAL NOT NULL,
        seconds REAL NOT NULL
    )""",
)

MIGRATIONS: tuple[Migration, ...] = (_V1,)
"""The schema's migrations in order: SQL statements, or a function given the connection, each applied
in its own transaction. Append, never change one that was released."""
SCHEMA_VERSION = len(MIGRATIONS)
"""The schema version this code writes and reads."""


def connect(path: str | os.PathLike[str]) -> sqlite3.Connection:
    """A connection to the database at `path` (created if missing): WAL mode, foreign keys, a busy
    timeout of :data:`BUSY_TIMEOUT_MS`, rows as :class:`sqlite3.Row`, autocommit (writers use
    :func:`immediate`).

    Raises
    ------
    ServeError
        If the file cannot be opened as a database.
    """
    try:
        con = sqlite3.connect(os.fspath(path), timeout=BUSY_TIMEOUT_MS / 1000, isolation_level=None)
        con.row_factory = sqlite3.Row
        con.execute(f"PRAGMA busy_timeout = {BUSY_TIMEOUT_MS}")
        mode = con.execute("PRAGMA journal_mode = WAL").fetchone()[0]
        con.execute("PRAGMA synchronous = FULL")
        con.execute("PRAGMA foreign_keys = ON")
    except sqlite3.DatabaseError as exc:
        raise ServeError(f"--db {path}: cannot open it as an SQLite database ({exc})") from None
    if str(mode).lower() != "wal":
        con.close()
        raise ServeError(
            f"--db {path}: SQLite cannot use WAL mode there (journal mode {mode!r}); put the database on a "
            "local file system"
        )
    return con


@contextmanager
def immediate(con: sqlite3.Connection) -> Iterator[sqlite3.Connection]:
    """A write transaction (``BEGIN IMMEDIATE``: the write lock is taken at once, so what the block
    reads is not changed by another writer before it commits); rolled back if the block raises."""
    con.execute("BEGIN IMMEDIATE")
    try:
        yield con
    except BaseException:
        con.execute("ROLLBACK")
        raise
    con.execute("COMMIT")


def _version(con: sqlite3.Connection) -> int:
    return int(con.execute("PRAGMA user_version").fetchone()[0])


def _newer(path: str | os.PathLike[str], version: int) -> ServeError:
    return ServeError(
        f"--db {path} has schema version {version}, newer than this toolkit's {SCHEMA_VERSION}: run the "
        "server of the toolkit version that wrote it (or a newer one)"
    )


def migrate(con: sqlite3.Connection, *, path: str | os.PathLike[str] = "the database") -> int:
    """Apply the migrations the database lacks, each in its own transaction; returns the schema version.

    Raises
    ------
    ServeError
        If the database's schema is newer than :data:`SCHEMA_VERSION`.
    """
    while True:
        with immediate(con):
            version = _version(con)
            if version > SCHEMA_VERSION:
                raise _newer(path, version)
            if version == SCHEMA_VERSION:
                return version
            step = MIGRATIONS[version]
            if callable(step):
                step(con)
            else:
                for statement in step:
                    con.execute(statement)
            con.execute(f"PRAGMA user_version = {version + 1}")


def open_db(path: str | os.PathLike[str], *, create: bool = True) -> sqlite3.Connection:
    """A connection to the server's database, migrated to :data:`SCHEMA_VERSION`.

    Parameters
    ----------
    path : path
        The database file.
    create : bool
        Whether a missing file is created (the server and ``token add`` create it; ``token list`` and
        ``revoke`` do not).

    Raises
    ------
    ServeError
        If the file is missing (and not to be created), is not a database, or is of a newer schema.
    """
    path = Path(path)
    if not path.exists() and not create:
        raise ServeError(f"--db {path} does not exist: give the database the server was started with")
    if path.exists() and not path.is_file():
        raise ServeError(f"--db {path} is not a file: give the server's database file")
    if not path.parent.is_dir():
        raise ServeError(f"--db {path}: its folder {path.parent} does not exist; create it first")
    if not path.exists():
        try:  # readable by its owner only: it holds the tokens' hashes and every result
            os.close(os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600))
        except FileExistsError:
            pass  # another server made it just now
        except OSError as exc:
            raise ServeError(f"--db {path}: cannot create it ({exc.strerror or exc})") from None
    con = connect(path)
    try:
        migrate(con, path=path)
    except ServeError:
        con.close()
        raise
    except sqlite3.DatabaseError as exc:
        con.close()
        raise ServeError(f"--db {path}: not a database of this server ({exc})") from None
    return con
