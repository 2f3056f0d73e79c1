"""Running agents and scoring on a private split: run-agent runs the public episodes, eval needs the
private file, and what each prints to do next runs as printed."""

from __future__ import annotations

import gzip
import json
import shutil
from pathlib import Path

import pytest

from navverse import cli
from tests.navverse.serve.conftest import Bench, oracle_body, write_benchmark


@pytest.fixture(scope="module")
def bench(tmp_path_factory: pytest.TempPathFactory) -> Bench:
    return write_benchmark(tmp_path_factory.mktemp("private-runs"), private_test=True)


@pytest.fixture()
def public_only(bench: Bench, tmp_path: Path) -> Path:
    """The version as a team downloads it: without the private directory beside it."""
    copy = tmp_path / "download" / "tiny" / "v1.0"
    shutil.copytree(bench.dataset, copy)
    return copy


def _lines(path: Path) -> list[dict]:
    return [json.loads(line) for line in gzip.decompress(path.read_bytes()).decode().splitlines()]


@pytest.mark.slow(seconds=20)
def test_an_agent_runs_the_public_test_episodes_and_is_pointed_to_the_server(
    bench: Bench, public_only: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch
):
    monkeypatch.setenv("NAVVERSE_CACHE_DIR", str(bench.cache))
    out = tmp_path / "random-test.jsonl.gz"
    words = ["run-agent", "--dataset", str(public_only), "--split", "test", "--agent", "random"]
    words += ["--scenes", str(bench.scenes), "--out", str(out), "--jobs", "0", "--max-steps", "5"]
    assert cli.main(words) == 0, capsys.readouterr().err
    printed = capsys.readouterr().out
    assert "the goals of split 'test' are private: submit it to the benchmark's evaluation server" in printed
    assert "navverse eval" not in printed  # no command that could not run here
    assert sorted(r["episode_id"] for r in _lines(out)) == ["test-objnav-0", "test-objnav-1", "test-vln-0"]

    # A privileged agent is given the goals, which this copy does not have; neither can eval score it.
    oracle = ["run-agent", "--dataset", str(public_only), "--split", "test", "--agent", "oracle"]
    assert cli.main([*oracle, "--scenes", str(bench.scenes), "--out", str(tmp_path / "o.jsonl")]) == 1
    assert "keeps its goals private, and the privileged agent 'oracle'" in capsys.readouterr().err
    score = ["eval", "--dataset", str(public_only), "--split", "test", "--submission", str(out)]
    assert cli.main([*score, "--scenes", str(bench.scenes), "--out", str(tmp_path / "e")]) == 1
    assert "keeps its goals private, and scoring needs them: pass --private DIR" in capsys.readouterr().err


@pytest.mark.slow(seconds=30)
def test_with_the_private_file_the_test_split_is_scored_and_the_printed_eval_command_runs(
    bench: Bench, public_only: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch
):
    monkeypatch.setenv("NAVVERSE_CACHE_DIR", str(bench.cache))
    assert bench.private is not None
    out = tmp_path / "random-test.jsonl"
    words = ["run-agent", "--dataset", str(public_only), "--private", str(bench.private), "--split", "test"]
    words += ["--agent", "random", "--scenes", str(bench.scenes), "--out", str(out), "--jobs", "0"]
    assert cli.main([*words, "--max-steps", "5"]) == 0, capsys.readouterr().err
    hint = capsys.readouterr().out.split("score it with: ")[1].strip()
    assert f"--private {bench.private}" in hint  # the eval command it prints runs as printed
    command = [*hint.split()[1:], "--out", str(tmp_path / "random-eval"), "--pictures", "0"]
    assert cli.main(command) == 0, capsys.readouterr().err
    metrics = json.loads((tmp_path / "random-eval" / "metrics.json").read_text())
    assert metrics["overall"]["episodes"] == 3

    oracle = tmp_path / "oracle-test.jsonl.gz"
    oracle.write_bytes(oracle_body("test", gzipped=True))
    score = ["eval", "--dataset", str(public_only), "--private", str(bench.private), "--split", "test"]
    score += ["--submission", str(oracle), "--scenes", str(bench.scenes), "--out", str(tmp_path / "o")]
    assert cli.main([*score, "--pictures", "0"]) == 0, capsys.readouterr().err
    metrics = json.loads((tmp_path / "o" / "metrics.json").read_text())
    assert metrics["overall"]["success"] == 1.0
