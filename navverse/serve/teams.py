"""Teams and their tokens: a token is shown once, when made; the database keeps only its SHA-256.

A token reads ``<id>.<secret>``: ``id`` (8 hex digits) names it in ``token list`` and ``token revoke
--id``, ``secret`` is :func:`secrets.token_urlsafe` of 32 bytes. A request's token is looked up by its
id and its SHA-256 compared with the stored one by :func:`hmac.compare_digest`; a revoked token is
refused as an unknown one is.
"""

from __future__ import annotations

import hashlib
import hmac
import re
import secrets
import sqlite3
import time
from dataclasses import dataclass

from navverse.serve.db import immediate
from navverse.serve.errors import ServeError

__all__ = [
    "MAX_TOKEN_CHARS",
    "TEAM_NAME",
    "TokenInfo",
    "add_token",
    "check_team_name",
    "list_tokens",
    "revoke_tokens",
    "team_of_token",
    "token_sha256",
]

TEAM_NAME = re.compile(r"[A-Za-z0-9._-]{1,64}")
"""What a team name is: 1-64 characters of letters, digits, ``.``, ``_`` and ``-``."""
_TOKEN_ID = re.compile(r"[0-9a-f]{8}")
MAX_TOKEN_CHARS = 128
"""The longest token read from a request (a real one has 52 characters)."""
_SECRET_BYTES = 32


@dataclass(frozen=True)
class TokenInfo:
    """A token as ``token list`` shows it: never the token itself."""

    id: str
    team: str
    created: float
    revoked: float | None


def check_team_name(team: str) -> str:
    """`team`, or a ServeError saying what a team name is."""
    if not TEAM_NAME.fullmatch(team):
        raise ServeError(
            f"team name {team[:80]!r}: give 1-64 characters of letters, digits, '.', '_' and '-'"
        )
    return team


def token_sha256(token: str) -> str:
    """The SHA-256 (hex) of a token, as stored."""
    return hashlib.sha256(token.encode("utf-8")).hexdigest()


def add_token(con: sqlite3.Connection, team: str, *, now: float | None = None) -> tuple[str, str]:
    """Make a token for `team` (the team is made if new).

    Returns
    -------
    tuple of str
        The token id and the token; the token is not kept anywhere: show it to its team once.

    Raises
    ------
    ServeError
        If the team name is not one.
    """
    check_team_name(team)
    now = time.time() if now is None else now
    with immediate(con):
        con.execute("INSERT OR IGNORE INTO teams (name, created) VALUES (?, ?)", (team, now))
        while True:
            token_id = secrets.token_hex(4)
            if con.execute("SELECT 1 FROM tokens WHERE id = ?", (token_id,)).fetchone() is None:
                break
        token = f"{token_id}.{secrets.token_urlsafe(_SECRET_BYTES)}"
        con.execute(
            "INSERT INTO tokens (id, team, sha256, created) VALUES (?, ?, ?, ?)",
            (token_id, team, token_sha256(token), now),
        )
    return token_id, token


def revoke_tokens(
    con: sqlite3.Connection, *, team: str | None = None, token_id: str | None = None, now: float | None = None
) -> list[str]:
    """Revoke a team's valid tokens, or one token by its id; returns the ids revoked.

    Raises
    ------
    ServeError
        If neither or both are given, or nothing matches (no such team, no valid token of it, no
        such token id, or that token was revoked already).
    """
    if (team is None) == (token_id is None):
        raise ServeError("give a team, or --id and a token id (navverse serve token list shows them)")
    now = time.time() if now is None else now
    with immediate(con):
        if team is not None:
            check_team_name(team)
            where, value, what = "team = ?", team, f"team {team!r} has no valid token"
        else:
            where, value, what = "id = ?", token_id, f"no valid token has id {token_id!r}"
        ids = [
            r[0] for r in con.execute(f"SELECT id FROM tokens WHERE {where} AND revoked IS NULL", (value,))
        ]
        if not ids:
            raise ServeError(f"{what} (navverse serve token list shows the tokens)")
        con.execute(f"UPDATE tokens SET revoked = ? WHERE {where} AND revoked IS NULL", (now, value))
    return ids


def list_tokens(con: sqlite3.Connection) -> list[TokenInfo]:
    """Every token, by team and creation time."""
    rows = con.execute("SELECT id, team, created, revoked FROM tokens ORDER BY team, created, id")
    return [TokenInfo(r["id"], r["team"], r["created"], r["revoked"]) for r in rows]


def team_of_token(con: sqlite3.Connection, token: str) -> str | None:
    """The team of a valid token, or None (unknown, malformed or revoked)."""
    if len(token) > MAX_TOKEN_CHARS:
        return None
    token_id, dot, secret = token.partition(".")
    if not dot or not secret or not _TOKEN_ID.fullmatch(token_id):
        return None
    row = con.execute("SELECT team, sha256, revoked FROM tokens WHERE id = ?", (token_id,)).fetchone()
    if row is None:
        return None
    matches = hmac.compare_digest(row["sha256"], token_sha256(token))
    return row["team"] if matches and row["revoked"] is None else None
