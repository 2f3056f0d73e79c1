"""The server's database without a server: migrations, tokens, the rate, and the claim protocol that
scores each submission exactly once, step by step on a clock the test sets."""

from __future__ import annotations

import sqlite3
from pathlib import Path

import pytest

from navverse.serve import queue
from navverse.serve.db import SCHEMA_VERSION, open_db
from navverse.serve.errors import RefusedError, ServeError
from navverse.serve.teams import add_token, list_tokens, revoke_tokens, team_of_token


@pytest.fixture
def con(tmp_path: Path) -> sqlite3.Connection:
    connection = open_db(tmp_path / "serve.db")
    yield connection
    connection.close()


def test_a_new_database_is_migrated_in_wal_mode_and_a_newer_one_refused(tmp_path: Path):
    path = tmp_path / "serve.db"
    with pytest.raises(ServeError, match="does not exist"):
        open_db(path, create=False)
    con = open_db(path)
    assert con.execute("PRAGMA user_version").fetchone()[0] == SCHEMA_VERSION
    assert con.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
    tables = {r[0] for r in con.execute("SELECT name FROM sqlite_master WHERE type = 'table'")}
    assert {"teams", "tokens", "submissions", "scorings"} <= tables
    con.execute(f"PRAGMA user_version = {SCHEMA_VERSION + 1}")
    con.close()
    with pytest.raises(ServeError, match=f"schema version {SCHEMA_VERSION + 1}, newer than"):
        open_db(path)
    other = tmp_path / "notes.txt"
    other.write_text("not a database, " * 100)
    with pytest.raises(ServeError, match=r"notes\.txt"):
        open_db(other)


def test_tokens_are_checked_by_their_hash_and_revoked(con: sqlite3.Connection):
    first_id, first = add_token(con, "team-a")
    second_id, second = add_token(con, "team-a")
    _, other = add_token(con, "team.b")
    assert first.startswith(f"{first_id}.") and len(first) > 40
    stored = [r[0] for r in con.execute("SELECT sha256 FROM tokens")]
    assert first not in stored and all(len(s) == 64 for s in stored)
    assert (team_of_token(con, first), team_of_token(con, other)) == ("team-a", "team.b")
    assert team_of_token(con, first[:-1] + ("A" if first[-1] != "A" else "B")) is None
    assert team_of_token(con, "no-dot") is None and team_of_token(con, "x" * 500) is None
    assert revoke_tokens(con, token_id=first_id) == [first_id]
    assert (team_of_token(con, first), team_of_token(con, second)) == (None, "team-a")
    assert revoke_tokens(con, team="team-a") == [second_id]
    assert team_of_token(con, second) is None
    with pytest.raises(ServeError, match="no valid token"):
        revoke_tokens(con, team="team-a")
    with pytest.raises(ServeError, match="team name"):
        add_token(con, "bad name!")
    listed = list_tokens(con)
    assert [(t.team, t.revoked is not None) for t in listed] == [
        ("team-a", True),
        ("team-a", True),
        ("team.b", False),
    ]


def _new(submission_id: str, team: str = "team-a", split: str = "eval") -> queue.NewSubmission:
    return queue.NewSubmission(
        id=submission_id, team=team, name="run", split=split, public=True, file=f"{submission_id}.jsonl",
        body_bytes=10, lines=1, records=1, track={"name": "unspecified"}, instruction_type=None,
    )  # fmt: skip


def test_the_rate_counts_the_accepted_submissions_of_the_last_day(con: sqlite3.Connection):
    add_token(con, "team-a")
    for k, at in enumerate((1000.0, 2000.0)):
        queue.insert_submission(con, _new(f"s{k}"), rate=2, now=at)
    with pytest.raises(RefusedError) as refused:
        queue.insert_submission(con, _new("s2"), rate=2, now=3000.0)
    assert refused.value.status == 429 and refused.value.headers["Retry-After"] == str(1000 + 86_400 - 3000)
    assert "next is taken from 1970-01-02T00:16:40Z (in 23 h 27 min)" in refused.value.message
    assert queue.rate_refusal(con, "team-a", rate=2, now=1000.0 + 86_400.5) is None  # s0 is a day old


def test_a_claim_holds_until_its_lease_runs_out_and_only_its_holder_records_a_result(con: sqlite3.Connection):
    add_token(con, "team-a")
    for k in range(3):
        queue.insert_submission(
            con, _new(f"s{k}", split="test" if k == 2 else "eval"), rate=10, now=100.0 + k
        )
    claim = {"lease": 10.0, "max_attempts": 3, "splits": ["eval"]}
    a = queue.claim_next(con, instance="A", now=1000.0, **claim)
    b = queue.claim_next(con, instance="B", now=1001.0, **claim)
    assert (a.submission_id, a.attempt, b.submission_id) == ("s0", 1, "s1")
    assert queue.claim_next(con, instance="B", now=1002.0, **claim) is None  # s2's split is not B's
    assert queue.renew(con, [a], instance="A", lease=10.0, now=1005.0) == []  # A renews: to 1015
    assert queue.renew(con, [b], instance="B", lease=10.0, now=1005.0) == []
    assert queue.claim_next(con, instance="C", now=1012.0, **claim) is None
    taken = queue.claim_next(con, instance="C", now=1016.0, **claim)  # A stopped renewing
    assert (taken.submission_id, taken.attempt) == ("s0", 2)
    assert queue.renew(con, [a], instance="A", lease=10.0, now=1017.0) == [a]  # A learns it lost s0
    assert not queue.finish(con, a, instance="A", result={"groups": {}}, seconds=1.0)
    assert queue.finish(con, taken, instance="C", result={"groups": {"overall": {}}}, seconds=1.0)
    assert not queue.finish(con, taken, instance="C", result={"groups": {}}, seconds=1.0)  # once
    assert not queue.fail(con, a, instance="A", error="late")
    scorings = con.execute("SELECT submission_id, instance, attempt FROM scorings").fetchall()
    assert [tuple(row) for row in scorings] == [("s0", "C", 2)]
    assert queue.release(con, b, instance="B", counted=False)  # a stopping server: not an attempt
    assert tuple(con.execute("SELECT status, attempts FROM submissions WHERE id = 's1'").fetchone()) == (
        "queued",
        0,
    )


def test_a_submission_whose_scoring_keeps_dying_is_failed_after_its_attempts(con: sqlite3.Connection):
    add_token(con, "team-a")
    queue.insert_submission(con, _new("s0"), rate=10, now=0.0)
    claim = {"lease": 10.0, "max_attempts": 2, "splits": ["eval"]}
    first = queue.claim_next(con, instance="A", now=100.0, **claim)
    assert queue.release(con, first, instance="A", counted=True)  # its worker died
    second = queue.claim_next(con, instance="A", now=101.0, **claim)
    assert second.attempt == 2
    assert queue.claim_next(con, instance="B", now=200.0, **claim) is None  # A died too: given up
    status, error = con.execute("SELECT status, error FROM submissions").fetchone()
    assert status == "failed" and "after 2 attempts" in error


def test_the_token_commands(tmp_path: Path, capsys: pytest.CaptureFixture[str]):
    from navverse.cli import main

    db = str(tmp_path / "serve.db")
    assert main(["serve", "token", "list", "--db", db]) == 1
    assert "does not exist" in capsys.readouterr().err
    assert main(["serve", "token", "add", "no good", "--db", db]) == 1
    assert "team name 'no good'" in capsys.readouterr().err
    assert main(["serve", "token", "add", "team-a", "--db", db]) == 0
    token = capsys.readouterr().out.strip().splitlines()[-1]
    assert main(["serve", "token", "list", "--db", db]) == 0
    listed = capsys.readouterr().out
    assert "team-a" in listed and token.split(".")[0] in listed and token.split(".")[1] not in listed
    assert main(["serve", "token", "revoke", "team-a", "--db", db]) == 0
    assert main(["serve", "token", "revoke", "team-a", "--db", db]) == 1
    assert "has no valid token" in capsys.readouterr().err
    assert main(["serve", "--db", db]) == 1
    assert "give --dataset" in capsys.readouterr().err
