"""The submissions table: accepting within a team's rate, and scoring each submission exactly once.

Claim protocol (several servers may share one database):

1. :func:`claim_next` takes the write lock (``BEGIN IMMEDIATE``), picks the oldest submission of a
   split the instance scores that is ``queued``, or ``scoring`` under a lease that ran out (its
   server died or hangs), and sets it
   ``scoring`` with ``claimed_by`` = the claiming instance, ``lease_until`` = now + lease and
   ``attempts`` + 1. A claim is the pair (instance, attempt): no other claim can hold it while the
   lease runs, and a later claim changes the attempt.
2. While scoring, the instance renews its leases (:func:`renew`, every heartbeat), conditioned on
   still holding each claim.
3. :func:`finish` sets ``done`` and the public result with an UPDATE conditioned on the claim, and
   in the same transaction inserts the submission's row of ``scorings`` (``UNIQUE(submission_id)``):
   a claim lost to another instance (this one was too slow to renew) writes nothing, so a result is
   recorded exactly once. :func:`fail` and :func:`release` are conditioned the same way.

A submission claimed :attr:`~navverse.serve.settings.ServeSettings.max_attempts` times without a
result is marked ``failed`` by the next claim instead of being scored again.
"""

from __future__ import annotations

import json
import math
import secrets
import sqlite3
import string
import time
from collections.abc import Collection
from dataclasses import dataclass

from navverse.serve.db import immediate
from navverse.serve.errors import RefusedError
from navverse.serve.leaderboard import iso_time

__all__ = [
    "DAY",
    "Claim",
    "NewSubmission",
    "claim_next",
    "fail",
    "finish",
    "insert_submission",
    "new_id",
    "public_done",
    "rate_refusal",
    "release",
    "renew",
    "submission_of",
]

DAY = 86_400.0
"""The window of the rate limit (s)."""
_GAVE_UP = (
    "the server could not score this submission after {n} attempts (its scoring stopped without a "
    "result each time); the benchmark's operators can see why in their log"
)


@dataclass(frozen=True)
class NewSubmission:
    """An accepted upload, as its row is inserted."""

    id: str
    team: str
    name: str
    split: str
    public: bool
    file: str
    body_bytes: int
    lines: int
    records: int
    track: dict
    instruction_type: str | None


@dataclass(frozen=True)
class Claim:
    """A submission claimed by an instance: it holds while ``claimed_by`` and ``attempts`` are its own."""

    submission_id: str
    split: str
    file: str
    attempt: int
    team: str


_ID_ALPHABET = string.ascii_letters + string.digits


def new_id() -> str:
    """A submission id: 16 random letters and digits (95 bits)."""
    return "".join(secrets.choice(_ID_ALPHABET) for _ in range(16))


def _wait_text(seconds: float) -> str:
    """A wait for people: ``3 h 12 min``, ``5 min``."""
    hours, minutes = divmod(max(1, math.ceil(seconds / 60)), 60)
    return f"{hours} h {minutes} min" if hours else f"{minutes} min"


def rate_refusal(con: sqlite3.Connection, team: str, *, rate: int, now: float) -> RefusedError | None:
    """The 429 of a team that had `rate` submissions accepted in the last 24 hours, saying when the
    next is taken; None when it may submit."""
    times = [
        r[0]
        for r in con.execute(
            "SELECT created FROM submissions WHERE team = ? AND created > ? ORDER BY created",
            (team, now - DAY),
        )
    ]
    if len(times) < rate:
        return None
    opens = times[len(times) - rate] + DAY  # when enough of them are older than a day
    wait = max(1, math.ceil(opens - now))
    return RefusedError(
        429,
        f"team {team} has had {len(times)} submissions accepted in the last 24 hours, the most this server "
        f"takes ({rate} a day); the next is taken from {iso_time(opens)} (in {_wait_text(opens - now)})",
        headers={"Retry-After": str(wait)},
    )


def insert_submission(con: sqlite3.Connection, new: NewSubmission, *, rate: int, now: float) -> None:
    """Insert an accepted submission as ``queued``, if its team is within its rate (checked in the same
    transaction, so concurrent uploads of one team cannot pass it together).

    Raises
    ------
    RefusedError
        429 when the team is over its rate.
    """
    with immediate(con):
        refusal = rate_refusal(con, new.team, rate=rate, now=now)
        if refusal is not None:
            raise refusal
        con.execute(
            "INSERT INTO submissions (id, team, name, split, public, status, file, body_bytes, lines, "
            "records, track, instruction_type, created) "
            "VALUES (?, ?, ?, ?, ?, 'queued', ?, ?, ?, ?, ?, ?, ?)",
            (
                new.id, new.team, new.name, new.split, int(new.public), new.file, new.body_bytes, new.lines,
                new.records, json.dumps(new.track, sort_keys=True), new.instruction_type, now,
            ),
        )  # fmt: skip


def claim_next(
    con: sqlite3.Connection,
    *,
    instance: str,
    lease: float,
    max_attempts: int,
    splits: Collection[str],
    now: float | None = None,
) -> Claim | None:
    """Claim the oldest submission of `splits` waiting to be scored (``queued``, or ``scoring`` under a
    lease that ran out); None when there is none. One given up after `max_attempts` claims is marked
    failed. Submissions of other splits are left to a server that scores them (one given the private
    goals of their split)."""
    now = time.time() if now is None else now
    chosen = sorted(splits)
    if not chosen:
        return None
    marks = ", ".join("?" * len(chosen))
    with immediate(con):
        while True:
            row = con.execute(
                "SELECT id, split, file, attempts, team FROM submissions "
                "WHERE (status = 'queued' OR (status = 'scoring' AND lease_until < ?)) "
                f"AND split IN ({marks}) ORDER BY created, id LIMIT 1",
                (now, *chosen),
            ).fetchone()
            if row is None:
                return None
            if row["attempts"] >= max_attempts:
                con.execute(
                    "UPDATE submissions SET status = 'failed', error = ?, claimed_by = NULL, "
                    "lease_until = NULL WHERE id = ?",
                    (_GAVE_UP.format(n=row["attempts"]), row["id"]),
                )
                continue
            con.execute(
                "UPDATE submissions SET status = 'scoring', claimed_by = ?, lease_until = ?, "
                "attempts = attempts + 1 WHERE id = ?",
                (instance, now + lease, row["id"]),
            )
            return Claim(row["id"], row["split"], row["file"], row["attempts"] + 1, row["team"])


_HELD = "id = ? AND claimed_by = ? AND attempts = ? AND status = 'scoring'"
"""The condition of holding a claim."""


def renew(
    con: sqlite3.Connection, claims: list[Claim], *, instance: str, lease: float, now: float | None = None
) -> list[Claim]:
    """Extend the leases of `claims` to now + `lease`; returns the claims no longer held."""
    now = time.time() if now is None else now
    lost = []
    with immediate(con):
        for claim in claims:
            cursor = con.execute(
                f"UPDATE submissions SET lease_until = ? WHERE {_HELD}",
                (now + lease, claim.submission_id, instance, claim.attempt),
            )
            if cursor.rowcount != 1:
                lost.append(claim)
    return lost


def finish(
    con: sqlite3.Connection,
    claim: Claim,
    *,
    instance: str,
    result: dict,
    seconds: float,
    now: float | None = None,
) -> bool:
    """Record the result of a claimed submission and its scoring, if the claim still holds.

    Returns
    -------
    bool
        Whether it was recorded (False: the claim was lost, another instance scores it).
    """
    now = time.time() if now is None else now
    with immediate(con):
        cursor = con.execute(
            "UPDATE submissions SET status = 'done', result = ?, scored_at = ?, error = NULL, "
            f"claimed_by = NULL, lease_until = NULL WHERE {_HELD}",
            (json.dumps(result, sort_keys=True), now, claim.submission_id, instance, claim.attempt),
        )
        if cursor.rowcount != 1:
            return False
        con.execute(
            "INSERT INTO scorings (submission_id, instance, attempt, scored_at, seconds) "
            "VALUES (?, ?, ?, ?, ?)",
            (claim.submission_id, instance, claim.attempt, now, seconds),
        )
    return True


def fail(
    con: sqlite3.Connection, claim: Claim, *, instance: str, error: str, now: float | None = None
) -> bool:
    """Mark a claimed submission failed with `error` (shown to its team), if the claim still holds."""
    now = time.time() if now is None else now
    with immediate(con):
        cursor = con.execute(
            "UPDATE submissions SET status = 'failed', error = ?, scored_at = ?, claimed_by = NULL, "
            f"lease_until = NULL WHERE {_HELD}",
            (error, now, claim.submission_id, instance, claim.attempt),
        )
    return cursor.rowcount == 1


def release(con: sqlite3.Connection, claim: Claim, *, instance: str, counted: bool) -> bool:
    """Put a claimed submission back in the queue, if the claim still holds.

    Parameters
    ----------
    counted : bool
        Whether this attempt counts towards ``max_attempts`` (a worker that died while scoring it);
        a server that stops releases its claims uncounted.
    """
    with immediate(con):
        cursor = con.execute(
            "UPDATE submissions SET status = 'queued', claimed_by = NULL, lease_until = NULL, "
            f"attempts = attempts - ? WHERE {_HELD}",
            (0 if counted else 1, claim.submission_id, instance, claim.attempt),
        )
    return cursor.rowcount == 1


def submission_of(con: sqlite3.Connection, submission_id: str) -> sqlite3.Row | None:
    """A submission's row, or None."""
    if len(submission_id) > 64:
        return None
    return con.execute("SELECT * FROM submissions WHERE id = ?", (submission_id,)).fetchone()


def public_done(con: sqlite3.Connection, split: str) -> list[sqlite3.Row]:
    """The public submissions of a split that are scored, oldest first."""
    return list(
        con.execute(
            "SELECT * FROM submissions WHERE split = ? AND status = 'done' AND public = 1 "
            "ORDER BY created, id",
            (split,),
        )
    )
