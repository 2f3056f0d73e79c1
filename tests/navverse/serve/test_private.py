"""A private split (``test``, its goals in a private file apart from the dataset version): refused by a
server started without the private file, scored by one started with it, and its goals never in a
response, page or log line of either."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.navverse.serve.conftest import (
    Bench,
    Client,
    Server,
    add_token,
    goal_needles,
    jsonl,
    leaks,
    oracle_body,
    oracle_lines,
    write_benchmark,
)


@pytest.fixture(scope="module")
def private_bench(tmp_path_factory: pytest.TempPathFactory) -> Bench:
    return write_benchmark(tmp_path_factory.mktemp("private-bench"), private_test=True)


@pytest.mark.slow(seconds=14)
def test_a_private_split_is_scored_only_with_its_private_goals(
    private_bench: Bench, tmp_path: Path, launch: Callable[..., Server]
):
    from navverse.dataset import Dataset

    assert all(not e.goals for e in Dataset(private_bench.dataset).episodes(split="test"))  # withheld
    db = tmp_path / "serve.db"
    token = add_token(db, "alpha")
    client = Client()

    without = launch(private_bench, db, tmp_path / "without.log")
    client.url = without.url
    refused = client.submit(token, oracle_body("test"), split="test")
    assert refused.status == 422, refused.text
    assert "no private goals for split 'test'" in refused.json()["error"]
    assert "(eval)" in refused.json()["error"]  # the split it does score
    public = client.submit(token, oracle_body("eval"), split="eval", name="on eval")
    assert public.status == 202, public.text
    client.wait_done(token, public.json()["id"])
    assert without.stop() == 0

    with_goals = launch(private_bench, db, tmp_path / "with.log", private=True)
    client.url = with_goals.url
    # A private split takes whole submissions only: a mean over one hidden goal would give it away.
    partial = client.submit(token, jsonl(oracle_lines("test")[:1]), split="test", name="one episode")
    assert partial.status == 422, partial.text
    assert "has a line for each of its 3 episodes" in partial.json()["error"]
    assert "2 are missing, the first: test-objnav-1, test-vln-0" in partial.json()["error"]
    accepted = client.submit(token, oracle_body("test", gzipped=True), split="test", name="hidden goals")
    assert accepted.status == 202, accepted.text
    view = client.wait_done(token, accepted.json()["id"])
    total = view["metrics"]["overall"]["all"]
    assert (total["episodes"], total["success"], total["spl"]) == (3, 1.0, 1.0)
    board = client.request("GET", "/api/leaderboard?split=test").json()
    assert [e["id"] for e in board["entries"]] == [accepted.json()["id"]]
    client.request("GET", "/?split=test")
    client.request("GET", f"/submissions/{accepted.json()['id']}")
    assert with_goals.stop() == 0

    needles = goal_needles(["test"])
    logs = [without.log.read_text(), with_goals.log.read_text()]
    found = leaks([*client.seen, *logs], needles)
    assert found == [], found[:5]
    assert "hidden goals" in json.dumps(board)  # what was checked is what was shown
