"""``navverse serve`` run for real on the tiny benchmark: an oracle run scored and on the leaderboard
(its page loaded in headless Chromium), every refusal with its status and message, and no goal position
in any response, page or log line."""

from __future__ import annotations

import gzip
import http.client
import json
import re
import urllib.parse
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

from navverse.eval.screenshot import find_browser, page_dom
from navverse.serve.db import open_db
from navverse.serve.teams import add_token as make_token
from tests.navverse.serve.conftest import (
    Bench,
    Client,
    Server,
    add_token,
    episodes_of,
    goal_needles,
    jsonl,
    leaks,
    oracle_body,
    oracle_lines,
)

RATE = 2
"""Submissions a team may have accepted a day, on this module's server."""


@dataclass
class Served:
    server: Server
    client: Client
    db: Path

    def token(self, team: str) -> str:
        """A new token of `team` (each test has teams of its own: the rate is per team)."""
        con = open_db(self.db)
        try:
            return make_token(con, team)[1]
        finally:
            con.close()


@pytest.fixture(scope="module")
def served(bench: Bench, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Served]:
    """The server on the tiny benchmark: bodies up to 1 MiB, 2 submissions a team a day."""
    root = tmp_path_factory.mktemp("served")
    db = root / "serve.db"
    add_token(db, "operators")  # the database made as an operator would
    server = Server(
        bench,
        db,
        root / "server.log",
        extra=["--max-body-mb", "1", "--rate-per-day", str(RATE)],
        private=True,
    )
    try:
        server.start()
        yield Served(server, Client(server.url), db)
        assert server.stop() == 0
    finally:
        server.abandon()


def _metrics_of(view: dict) -> dict:
    assert view["status"] == "done", view
    return view["metrics"]


def test_an_oracle_run_is_scored_and_shown_on_the_leaderboard(served: Served):
    client = served.client
    tokens = {team: served.token(team) for team in ("alpha", "beta")}
    accepted = client.submit(
        tokens["alpha"], oracle_body("test"), split="test", name="oracle <b>&", public=True
    )
    assert accepted.status == 202, accepted.text
    alpha_id = accepted.json()["id"]
    assert re.fullmatch(r"[A-Za-z0-9]{16}", alpha_id)
    hidden = client.submit(
        tokens["beta"], oracle_body("test", gzipped=True), split="test", name="secret run", public=False
    )
    assert hidden.status == 202, hidden.text
    beta_id = hidden.json()["id"]

    view = client.wait_done(tokens["alpha"], alpha_id)
    assert (view["name"], view["split"], view["public"]) == ("oracle <b>&", "test", True)
    assert view["track"]["name"] == "unspecified" and view["scored"].endswith("Z")
    metrics = _metrics_of(view)
    assert set(metrics) == {"overall", "task", "scene_type", "task_scene_type"}
    total = metrics["overall"]["all"]
    assert (total["episodes"], total["success"], total["success_n"], total["spl"]) == (3, 1.0, 3, 1.0)
    assert metrics["task"]["objnav"]["episodes"] == 2 and metrics["task"]["vln"]["ndtw_n"] == 1
    assert set(metrics["task_scene_type"]) == {"objnav/indoor", "vln/indoor"}
    assert view["scope"] == {"split_episodes": 3, "scored": 3, "missing": 0}
    assert "episodes" not in view and all(e.episode_id not in json.dumps(view) for e in episodes_of("test"))
    assert _metrics_of(client.wait_done(tokens["beta"], beta_id))["overall"]["all"]["success"] == 1.0

    board = client.request("GET", "/api/leaderboard?split=test").json()
    entries = {e["id"]: e for e in board["entries"]}
    assert (
        entries[alpha_id]["team"] == "alpha" and entries[alpha_id]["metrics"]["overall"]["all"]["spl"] == 1.0
    )
    assert beta_id not in entries  # not public
    assert sorted(e["rank"] for e in board["entries"]) == list(range(1, len(entries) + 1))
    assert client.request("GET", "/api/leaderboard").json() == board  # test is the default

    page = client.request("GET", f"/submissions/{alpha_id}")
    assert page.status == 200 and "oracle &lt;b&gt;&amp;" in page.text and "<b>&" not in page.text
    assert "Means per task and scene type" in page.text
    assert "content-security-policy" in {k.lower() for k in page.headers}
    assert client.request("GET", f"/submissions/{beta_id}").status == 404  # private: no page
    assert client.request("GET", "/submissions/nonexistent").status == 404
    schema = client.request("GET", "/openapi.json").json()
    assert {"/api/submissions", "/api/submissions/{submission_id}", "/api/leaderboard"} <= set(
        schema["paths"]
    )

    if find_browser() is None:
        pytest.skip("no headless Chromium on PATH (apt-get install chromium): the page's DOM is not checked")
    dom, errors = page_dom(served.server.url, timeout=60)  # test, the default
    client.seen.append(dom)
    assert errors == []
    assert 'data-sortable="ready"' in dom  # the inline script ran under the page's CSP
    assert f'data-shown="{len(entries)}"' in dom  # the filters show the overall row of each entry
    rows = re.findall(r'<tr data-task="all" data-scene="all">(.*?)</tr>', dom, re.S)
    row = next(r for r in rows if f"/submissions/{alpha_id}" in r)
    assert '<td class="text">alpha</td>' in row and "oracle &lt;b&gt;&amp;" in row and "100.0" in row
    assert "beta" not in dom and "secret run" not in dom


def _raw_post(url: str, path: str, *, token: str, chunks: list[bytes] | None = None,
              length: int | None = None) -> tuple[int, dict]:  # fmt: skip
    """POST with a declared Content-Length and no body, or a chunked body (no Content-Length)."""
    parts = urllib.parse.urlsplit(url)
    connection = http.client.HTTPConnection(parts.hostname, parts.port, timeout=60)
    headers = {"Authorization": f"Bearer {token}"}
    try:
        if chunks is None:
            connection.putrequest("POST", path)
            for key, value in {**headers, "Content-Length": str(length)}.items():
                connection.putheader(key, value)
            connection.endheaders()
        else:
            connection.request("POST", path, body=iter(chunks), headers=headers, encode_chunked=True)
        response = connection.getresponse()
        return response.status, json.loads(response.read())
    finally:
        connection.close()


def _bomb() -> bytes:
    """A gzip file of 257 MiB of spaces (a stream of gzip members), about 260 KiB as sent."""
    member = gzip.compress(b" " * 2**20, compresslevel=9)
    return member * 257


def test_every_refusal_has_its_status_and_message_and_counts_nothing(served: Served):
    from navverse.cli import main

    client = served.client
    tokens = {team: served.token(team) for team in ("gamma", "delta", "alpha2")}
    tokens["gamma-old"], gamma = tokens["gamma"], served.token("gamma")
    assert (
        main(["serve", "token", "revoke", "--id", tokens["gamma-old"].split(".")[0], "--db", str(served.db)])
        == 0
    )
    first = client.submit(gamma, oracle_body("eval"), name="first")
    assert first.status == 202, first.text
    gamma_id = first.json()["id"]

    def refused(response, status: int, *needles: str) -> None:
        assert response.status == status, response.text
        error = response.json()["error"]
        assert set(response.json()) == {"error"}
        for needle in needles:
            assert needle in error, error

    body = oracle_body("eval")
    refused(client.submit(None, body), 401, "no token", "Authorization: Bearer")
    refused(client.submit("0123abcd.not-a-token", body), 401, "not valid")
    refused(client.submit(tokens["gamma-old"], body), 401, "revoked")
    refused(client.request("GET", f"/api/submissions/{gamma_id}"), 401, "no token")
    refused(
        client.request("GET", f"/api/submissions/{gamma_id}", token=tokens["alpha2"]), 404, "no submission"
    )
    other = client.request("GET", f"/api/submissions/{gamma_id}", token=tokens["alpha2"]).text
    assert other == client.request("GET", "/api/submissions/Zz0000000000000", token=tokens["alpha2"]).text

    refused(client.submit(gamma, body, split="train"), 422, "split 'train' takes no submission", "eval, test")
    refused(client.submit(gamma, body, split="nope"), 422, "split 'nope'")
    refused(client.submit(gamma, body, name="x" * 101), 422, "name")
    refused(client.submit(gamma, body, name="tab\there"), 422, "control characters")
    refused(client.submit(gamma, b""), 422, "no body")

    url, path = served.server.url, "/api/submissions?split=eval&name=big"
    status, answer = _raw_post(url, path, token=gamma, length=5 * 2**20)  # told by its Content-Length
    assert status == 413 and "larger than this server takes (1 MiB as sent)" in answer["error"], answer
    status, answer = _raw_post(url, path, token=gamma, chunks=[b" " * 2**16] * 24)  # counted as it comes
    assert status == 413 and "gzip it" in answer["error"], answer
    client.seen.append(json.dumps(answer))
    refused(client.submit(gamma, _bomb()), 422, "has more than 256 MiB of text", "the submission")

    lines = oracle_lines("eval")
    broken = (
        jsonl(lines[:1]) + b'{"episode_id": "eval-objnav-1", "trajectory": [[0, 1, 2\n' + jsonl(lines[2:])
    )
    refused(client.submit(gamma, broken), 422, "1 problem", "line 2", "not accepted", "nothing was counted")
    unknown = jsonl([*lines, {**lines[0], "episode_id": "test-objnav-0"}])  # another split's episode
    refused(client.submit(gamma, unknown), 422, "line 4 (test-objnav-0): unknown episode id")
    far = jsonl([{**lines[0], "trajectory": [[0.0, 900.0, 2.0, 0.5, 0, 0, 0, 1.0]]}, *lines[1:]])
    refused(client.submit(gamma, far), 422, "line 1 (eval-objnav-0)", "outside scene tiny_room's bounds")
    mixed = jsonl(
        [{**lines[0], "track": {"name": "standard", "sensors": ["rgb"], "privileged": False}}, *lines[1:]]
    )
    refused(client.submit(gamma, mixed), 422, "disagree on the track")
    refused(client.submit(gamma, b"not json at all\n"), 422, "no line of JSON")
    said = "".join(client.seen)
    assert ".upload" not in said and str(served.db.parent) not in said  # no server path in a message

    second = client.submit(gamma, oracle_body("eval", gzipped=True), name="second")  # nothing counted yet
    assert second.status == 202, second.text
    over = client.submit(gamma, body, name="third")
    refused(
        over,
        429,
        f"team gamma has had {RATE} submissions accepted in the last 24 hours",
        "next is taken from",
    )
    assert 86_000 < int(over.headers["Retry-After"]) <= 86_400
    for submission_id in (gamma_id, second.json()["id"]):
        assert client.wait_done(gamma, submission_id)["metrics"]["overall"]["all"]["success"] == 1.0
    assert client.submit(tokens["delta"], body, name="delta's").status == 202  # other teams go on
    leftovers = list((served.db.parent / "serve.db.submissions" / "tmp").iterdir())
    assert leftovers == []  # every refused upload was removed


def test_no_goal_position_in_any_response_page_or_log_line(served: Served):
    """The goals of the scored splits never leave the scoring processes: not in the JSON of submissions
    and leaderboards, nor on the pages, nor in the refusals, nor in the server's log."""
    client = served.client
    tokens = {"eval": served.token("epsilon"), "test": served.token("zeta")}
    needles = goal_needles()
    dataset_text = "".join(
        gzip.decompress(p.read_bytes()).decode()
        for p in sorted(served.server.bench.dataset.rglob("*.json.gz"))
    )
    assert leaks([dataset_text], needles)  # the needles are written as they would leak
    runs = []
    for split, token in tokens.items():
        for public in (True, False):
            answer = client.submit(
                token, oracle_body(split), split=split, name=f"{split}-{public}", public=public
            )
            assert answer.status == 202, answer.text
            runs.append((split, answer.json()["id"], token))
    for _split, submission_id, token in runs:
        client.wait_done(token, submission_id)
        client.request("GET", f"/submissions/{submission_id}")
    for split in ("eval", "test"):
        client.request("GET", f"/api/leaderboard?split={split}")
        client.request("GET", f"/?split={split}")
    near = [
        {**oracle_lines("test")[0], "trajectory": [[0.0, 7.0, 4.9, 0.4, 0, 0, 0, 1.0]], "episode_id": "x"}
    ]
    client.submit(tokens["test"], jsonl(near), split="test")  # a refusal about a run at the goal
    log = served.server.log.read_text()
    assert "accepted" in log and "done in" in log
    found = leaks([*client.seen, log], needles)
    assert found == [], found[:5]
