"""Scored exactly once: a server SIGKILLed (its whole process group) while it scores has its claim
taken up by the server started again on the same database, and two servers on one database never
score one submission twice. The database's ``scorings`` table (one row per scored submission) and
the ``attempts`` of each submission tell."""

from __future__ import annotations

import re
import sqlite3
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.navverse.serve.conftest import (
    Bench,
    Client,
    Server,
    add_token,
    group_alive,
    oracle_body,
    wait_for,
)


def _rows(db: Path, sql: str) -> list[tuple]:
    con = sqlite3.connect(db, timeout=10)
    try:
        return con.execute(sql).fetchall()
    finally:
        con.close()


def _instance(server: Server) -> str:
    found = re.findall(r"serving on \S+ \(instance (\S+)\)", server.log.read_text())
    assert found, server.log.read_text()
    return found[-1]


def _submit_all(client: Client, tokens: dict[str, str], *, splits: tuple[str, ...]) -> list[str]:
    ids = []
    for split in splits:
        for team, token in tokens.items():
            answer = client.submit(
                token, oracle_body(split, gzipped=team.endswith("1")), split=split, name=team
            )
            assert answer.status == 202, answer.text
            ids.append(answer.json()["id"])
    return ids


@pytest.mark.slow(seconds=12)
def test_a_server_killed_while_scoring_has_its_claims_taken_up_after_a_restart(
    bench: Bench, tmp_path: Path, launch: Callable[..., Server]
):
    db = tmp_path / "serve.db"
    tokens = {team: add_token(db, team) for team in ("team0", "team1", "team2")}
    first = launch(bench, db, tmp_path / "first.log", private=True)
    client = Client(first.url)
    ids = _submit_all(client, tokens, splits=("eval",))

    def scoring() -> bool:
        return bool(_rows(db, "SELECT id FROM submissions WHERE status = 'scoring'"))

    wait_for(scoring, what="a submission being scored", every=0.02)
    first.kill()
    assert first.process is not None
    wait_for(
        lambda: not group_alive(first.process.pid), deadline=10, what="the killed server's workers to end"
    )
    interrupted = _rows(db, "SELECT id, claimed_by, attempts FROM submissions WHERE status = 'scoring'")
    assert interrupted, "the kill came after the scoring ended: nothing was interrupted"
    assert {(claimed, attempts) for _, claimed, attempts in interrupted} == {(_instance(first), 1)}

    second = launch(bench, db, tmp_path / "second.log", private=True)
    client.url = second.url
    for submission_id, token in zip(ids, tokens.values(), strict=True):
        assert client.wait_done(token, submission_id)["metrics"]["overall"]["all"]["success"] == 1.0
    assert second.stop() == 0

    scorings = _rows(db, "SELECT submission_id, instance, attempt FROM scorings")
    assert sorted(s for s, _, _ in scorings) == sorted(ids)  # each accepted submission scored once
    by_id = {s: (instance, attempt) for s, instance, attempt in scorings}
    for submission_id, _, _ in interrupted:
        assert by_id[submission_id] == (_instance(second), 2)  # taken over once its lease ran out
    assert _rows(db, "SELECT status, COUNT(*) FROM submissions GROUP BY status") == [("done", len(ids))]
    assert "interrupted" not in second.log.read_text()


@pytest.mark.slow(seconds=12)
def test_two_servers_on_one_database_score_each_submission_once(
    bench: Bench, tmp_path: Path, launch: Callable[..., Server]
):
    db = tmp_path / "serve.db"
    tokens = {team: add_token(db, team) for team in ("team0", "team1", "team2")}
    servers = [launch(bench, db, tmp_path / f"server{k}.log", private=True) for k in range(2)]
    clients = [Client(server.url) for server in servers]
    ids = []
    for split in ("eval", "test"):  # each team posts to both servers, in turn
        for client in clients:
            ids += _submit_all(client, tokens, splits=(split,))
    owners = dict(_rows(db, "SELECT id, team FROM submissions"))
    for submission_id in ids:
        clients[0].wait_done(tokens[owners[submission_id]], submission_id)
    assert [server.stop() for server in servers] == [0, 0]

    scorings = _rows(db, "SELECT submission_id, instance FROM scorings")
    assert sorted(s for s, _ in scorings) == sorted(ids)
    assert {instance for _, instance in scorings} == {_instance(server) for server in servers}  # both scored
    assert _rows(db, "SELECT DISTINCT attempts FROM submissions") == [(1,)]  # no submission claimed twice
