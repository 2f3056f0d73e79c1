"""A tiny benchmark for the evaluation server's tests, the real server run as ``navverse serve`` in a
process group of its own, and an HTTP client that keeps every body it reads (for the leak checks).

The benchmark: the tiny room of ``tests/navverse/scene`` as a scene pack under two ids (``tiny_room``
for split ``eval``, ``tiny_room_b`` for ``test``), three episodes per split with goals whose
coordinates are recognisable (:data:`GOALS`), and oracle submissions that follow each reference path.
With a reader that takes private files, :func:`write_benchmark` can keep ``test``'s goals private.
"""

from __future__ import annotations

import gzip
import itertools
import json
import math
import os
import re
import signal
import subprocess
import sys
import time
import urllib.error
import urllib.parse
import urllib.request
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pytest

from navverse.dataset import FORMAT_VERSION, Episode, EpisodeFile, counts_table, write_json_gz
from navverse.files import file_sha256
from navverse.scene.directory import write_scene_dir
from tests.navverse.scene.conftest import build_scene

NAVVERSE = str(Path(sys.executable).with_name("navverse"))
LEVEL = [0.0, 0.0, 0.0, 1.0]
TABLE = {"object_id": 3, "category": "table", "position": (7.0413, 4.9627, 0.3861), "radius": 0.6,
         "size": (1.2, 0.8, 0.75)}  # fmt: skip
CHAIR = {"object_id": 1, "category": "chair", "position": (3.0279, 5.0386, 0.4513), "radius": 0.25,
         "size": (0.5, 0.5, 0.9)}  # fmt: skip
GOALS = {"table": TABLE, "chair": CHAIR}
"""The goals of the episodes, at coordinates no other number on a page or in a response has."""
TO_TABLE = [(8.0, 2.0, 0.55), (8.0, 3.5, 0.55), (7.0, 4.3, 0.55)]
TO_CHAIR = [(8.0, 2.0, 0.55), (6.0, 3.0, 0.55), (3.8, 4.4, 0.55)]
SPLITS = {"eval": "tiny_room", "test": "tiny_room_b"}
# (episode id suffix, task, goal, reference path)
KINDS = [("objnav-0", "objnav", "table", TO_TABLE), ("objnav-1", "objnav", "chair", TO_CHAIR),
         ("vln-0", "vln", "chair", TO_CHAIR)]  # fmt: skip
DEADLINE = 120.0
"""Seconds a test waits for anything (a server to listen, a submission to be scored) before failing."""


def episodes_of(split: str) -> list[Episode]:
    """The episodes of a split: each kind of :data:`KINDS` in the split's scene."""
    scene = SPLITS[split]
    out = []
    for suffix, task, goal, path in KINDS:
        out.append(
            Episode.model_validate(
                {
                    "episode_id": f"{split}-{suffix}", "scene_id": scene, "scene_type": "indoor",
                    "task": task, "start_position": path[0], "start_rotation": LEVEL, "object_category": goal,
                    "goals": [GOALS[goal]], "reference_path": path,
                    "info": {
                        "geodesic_distance": sum(itertools.starmap(math.dist, itertools.pairwise(path))),
                        "euclidean_distance": math.dist(path[0], path[-1]),
                        "closest_goal_object_id": GOALS[goal]["object_id"], "success_distance": 1.6,
                        "difficulty": "easy",
                    },
                }
            )
        )  # fmt: skip
    return out


def _rows(points: Sequence[Sequence[float]]) -> list[list[float]]:
    return [[float(i), *map(float, p), *LEVEL] for i, p in enumerate(points)]


def oracle_lines(split: str, *, track: dict | None = None) -> list[dict]:
    """An oracle run of a split: every episode along its reference path, stopped at its end."""
    out = []
    for episode in episodes_of(split):
        path = [tuple(p) for p in episode.reference_path]
        record = {"episode_id": episode.episode_id, "trajectory": _rows(path), "stop": True}
        if track is not None:
            record["track"] = track
        out.append(record)
    return out


def jsonl(lines: Sequence[dict]) -> bytes:
    """JSON lines."""
    return ("\n".join(json.dumps(line) for line in lines) + "\n").encode()


def oracle_body(split: str, *, gzipped: bool = False) -> bytes:
    """An oracle submission's bytes (gzipped if asked)."""
    body = jsonl(oracle_lines(split))
    return gzip.compress(body) if gzipped else body


@dataclass(frozen=True)
class Bench:
    """A tiny benchmark on disk."""

    dataset: Path
    scenes: Path
    private: Path | None
    cache: Path


def write_benchmark(root: Path, *, private_test: bool = False) -> Bench:
    """The scene pack, the dataset version (``eval`` and ``test``) and, when `private_test`, the
    private file of ``test`` (its public episodes withheld)."""
    scenes = root / "scenes"
    for scene in SPLITS.values():
        (scenes / scene).mkdir(parents=True)
        write_scene_dir(build_scene(), scenes / scene, bev=False)
    version = root / "episodes" / "tiny" / "v1.0"
    episodes = [e for split in SPLITS for e in episodes_of(split)]
    splits = {split: [scene] for split, scene in SPLITS.items()}
    manifest: dict[str, Any] = {
        "format_version": FORMAT_VERSION, "name": "tiny", "version": "1.0", "toolkit_version": "0.1.0",
        "recipe": "recipes/datasets/tiny.yaml", "recipe_hash": "0" * 64, "embodiment": "spot",
        "scene_hashes": {}, "splits": splits, "counts": counts_table(episodes, splits),
        "difficulty_thresholds": {"objnav": [4.0, 8.0], "vln": [3.5, 7.5]}, "files": {},
    }  # fmt: skip
    private_dir = None
    if private_test:
        from navverse.dataset.private import PrivateSplit, private_file_name, withhold
        from navverse.dataset.private import private_dir as private_of

        private_dir = private_of(version)
        private_dir.mkdir(parents=True)
        full = episodes_of("test")
        tasks = sorted({e.task for e in full})
        content = PrivateSplit(
            name="tiny", version="1.0", split="test",
            files={t: EpisodeFile(episodes=[e for e in full if e.task == t]) for t in tasks},
            rollouts={t: {e.episode_id: _rows(e.reference_path) for e in full if e.task == t} for t in tasks},
        )  # fmt: skip
        path = private_dir / private_file_name("test")
        write_json_gz(content.model_dump(mode="json"), path)
        manifest["private"] = {"test": file_sha256(path)}
    for split in SPLITS:
        chosen = episodes_of(split)
        if private_test and split == "test":
            chosen = [withhold(e) for e in chosen]
        for task in sorted({e.task for e in chosen}):
            name = f"{split}/{task}.json.gz"
            write_json_gz(
                EpisodeFile(episodes=[e for e in chosen if e.task == task]).model_dump(mode="json"),
                version / name,
            )
            manifest["files"][name] = file_sha256(version / name)
    (version / "manifest.json").write_text(json.dumps(manifest))
    return Bench(version, scenes, private_dir, root / "cache")


@pytest.fixture(scope="session")
def bench(tmp_path_factory: pytest.TempPathFactory) -> Bench:
    """The tiny benchmark, its ``test`` split private (written once per test process)."""
    return write_benchmark(tmp_path_factory.mktemp("serve-bench"), private_test=True)


# ------------------------------------------------------------------------------------------ the server


def goal_needles(splits: Sequence[str] = tuple(SPLITS)) -> list[str]:
    """Every goal coordinate of the episodes of `splits`, as the JSON encoder writes it and rounded to
    2 decimals."""
    needles = set()
    for split in splits:
        for episode in episodes_of(split):
            for goal in episode.goals:
                for value in goal.position:
                    needles |= {json.dumps(float(value)), f"{value:.2f}"}
    return sorted(needles)


def leaks(texts: Sequence[str], needles: Sequence[str]) -> list[tuple[str, str]]:
    """(needle, its context) of every needle found in `texts` as a number (not inside a longer one)."""
    found = []
    for needle in needles:
        pattern = re.compile(r"(?<![\d.])" + re.escape(needle) + r"(?!\d)")
        for text in texts:
            for hit in pattern.finditer(text):
                found.append((needle, text[max(0, hit.start() - 60) : hit.end() + 60]))
    return found


@dataclass
class Response:
    status: int
    headers: Any
    """The response's headers (an :class:`email.message.Message`: names in any case)."""
    text: str

    def json(self) -> Any:
        return json.loads(self.text)


@dataclass
class Client:
    """An HTTP client of one server (its base URL may change when it is restarted) that keeps every
    body it reads in :attr:`seen`."""

    url: str = ""
    seen: list[str] = field(default_factory=list)

    def request(
        self,
        method: str,
        path: str,
        *,
        token: str | None = None,
        body: bytes | None = None,
        headers: dict[str, str] | None = None,
    ) -> Response:
        request = urllib.request.Request(self.url.rstrip("/") + path, data=body, method=method)
        if token is not None:
            request.add_header("Authorization", f"Bearer {token}")
        if body is not None:
            request.add_header("Content-Type", "application/octet-stream")
        for key, value in (headers or {}).items():
            request.add_header(key, value)
        try:
            with urllib.request.urlopen(request, timeout=60) as answer:
                response = Response(answer.status, answer.headers, answer.read().decode())
        except urllib.error.HTTPError as error:
            response = Response(error.code, error.headers, error.read().decode())
        self.seen.append(response.text)
        return response

    def submit(
        self, token: str | None, body: bytes, *, split: str = "eval", name: str = "run", public: bool = True
    ) -> Response:
        query = urllib.parse.urlencode({"split": split, "name": name, "public": str(public).lower()})
        return self.request("POST", f"/api/submissions?{query}", token=token, body=body)

    def status(self, token: str, submission_id: str) -> dict:
        response = self.request("GET", f"/api/submissions/{submission_id}", token=token)
        assert response.status == 200, response.text
        return response.json()

    def wait_done(self, token: str, submission_id: str, *, deadline: float = DEADLINE) -> dict:
        """The submission's view once it is done (fails if it fails or the deadline passes)."""
        view: dict = {}

        def done() -> bool:
            nonlocal view
            view = self.status(token, submission_id)
            assert view["status"] != "failed", view
            return view["status"] == "done"

        wait_for(done, deadline=deadline, what=f"submission {submission_id} scored")
        return view


def wait_for(check: Callable[[], bool], *, deadline: float = DEADLINE, what: str, every: float = 0.1) -> None:
    """Poll `check` until it is true; fail after `deadline` seconds."""
    end = time.monotonic() + deadline
    while not check():
        if time.monotonic() > end:
            pytest.fail(f"gave up after {deadline:g} s waiting for: {what}")
        time.sleep(every)


_SERVING = re.compile(r"serving on (http://\S+/)")


@dataclass
class Server:
    """``navverse serve`` run in a process group of its own, its output in :attr:`log`."""

    bench: Bench
    db: Path
    log: Path
    extra: Sequence[str] = ()
    private: bool = False
    process: subprocess.Popen | None = None
    url: str = ""

    def start(self) -> Server:
        words = [NAVVERSE, "serve", "--dataset", str(self.bench.dataset), "--db", str(self.db),
                 "--port", "0", "--scenes", str(self.bench.scenes), "--lease", "2", "--heartbeat", "0.4",
                 *self.extra]  # fmt: skip
        if self.private:
            words += ["--private", str(self.bench.private)]
        env = {**os.environ, "NAVVERSE_CACHE_DIR": str(self.bench.cache), "COLUMNS": "200"}
        start = self.log.stat().st_size if self.log.exists() else 0
        with self.log.open("ab") as out:
            self.process = subprocess.Popen(
                words,
                stdout=out,
                stderr=subprocess.STDOUT,
                env=env,
                start_new_session=True,
                cwd=self.db.parent,
            )

        def listening() -> bool:
            assert self.process is not None
            text = self.log.read_text(errors="replace")[start:]
            found = _SERVING.search(text)
            if found is None and self.process.poll() is not None:
                pytest.fail(f"navverse serve exited with {self.process.returncode}:\n{text}")
            if found is not None:
                self.url = found.group(1)
            return found is not None

        wait_for(listening, what="the server to listen")
        return self

    def abandon(self) -> None:
        """Kill the server's process group if it still runs (a test that failed before stopping it)."""
        if self.process is not None and group_alive(self.process.pid):
            os.killpg(self.process.pid, signal.SIGKILL)
            self.process.wait(30)

    def kill(self) -> None:
        """SIGKILL the server's whole process group (it and its workers)."""
        assert self.process is not None
        os.killpg(self.process.pid, signal.SIGKILL)
        self.process.wait(30)

    def stop(self) -> int:
        """SIGTERM the server and wait for it to end; its exit code."""
        assert self.process is not None
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
            try:
                self.process.wait(30)
            except subprocess.TimeoutExpired:
                self.kill()
        wait_for(lambda: not group_alive(self.process.pid), deadline=15, what="the server's processes to end")
        return self.process.returncode


@pytest.fixture
def launch() -> Iterator[Callable[..., Server]]:
    """Start a :class:`Server` (the arguments of its constructor); every server still running when the
    test ends, passed or failed, is killed with its process group."""
    started: list[Server] = []

    def start(*args: Any, **kwargs: Any) -> Server:
        server = Server(*args, **kwargs)
        started.append(server)
        return server.start()

    yield start
    for server in started:
        server.abandon()


def group_alive(group: int) -> bool:
    """Whether a process of the process group is still running."""
    try:
        os.killpg(group, 0)
    except ProcessLookupError:
        return False
    return True


def add_token(db: Path, team: str) -> str:
    """A new token of `team` in the database, made by ``navverse serve token add``."""
    done = subprocess.run([NAVVERSE, "serve", "token", "add", team, "--db", str(db)], capture_output=True,
                          text=True, timeout=120)  # fmt: skip
    assert done.returncode == 0, done.stderr
    return done.stdout.strip().splitlines()[-1]
