"""The review page: a local HTTP server listing a dataset version's episodes for a person to accept or reject.

:func:`make_server` serves, on 127.0.0.1 only, one self-contained page (inline CSS and plain JavaScript,
no other site contacted; :mod:`navverse.review.page`) and what it asks for:

``GET /``
    The page. It lists the episodes (filters by split, task and decision; 25 per page), each with
    its bird's-eye view, four first-person keyframes along its verification rollout, its instruction
    texts, task, goal category, geodesic length and difficulty, a reason field and Accept / Reject.
``GET /api/episodes``
    The dataset's name, version, splits, tasks and episodes (as JSON), with the decisions so far.
``GET /bev/<episode_id>.png``
    The episode on its scene's bird's-eye view (:func:`navverse.episodes.inspect.draw_episode`: start,
    goals with their success circles, reference path, verification rollout).
``GET /keyframes/<episode_id>/<k>.png``
    Keyframe ``k`` (0..3) of the rollout, seen by the dataset embodiment's camera
    (:func:`navverse.sim.keyframes.render_keyframes`).
``POST /api/decision``
    ``{"episode_id", "decision": "accept" | "reject", "reason"}`` (JSON); the decisions file is
    rewritten atomically (:mod:`navverse.review.decisions`) and the recorded decision returned.

Pictures are drawn when first asked for, one at a time (the renderers are not thread-safe), and kept in
memory (the last :data:`CACHED_EPISODES` episodes). Requests must name the server's own host (so a web
page elsewhere cannot reach it through DNS rebinding); a decision must come as JSON, from the page's own
origin when the browser names one (a form on another site cannot post one).
"""

from __future__ import annotations

import io
import json
import re
import sys
import tempfile
import threading
from collections import OrderedDict
from collections.abc import Callable
from datetime import datetime, timezone
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any

import numpy as np
from PIL import Image

from navverse.dataset import Dataset, Episode
from navverse.review.decisions import (
    Review,
    ReviewError,
    newest_version,
    read_review,
    with_decision,
    write_review,
)
from navverse.review.page import PAGE

__all__ = ["CACHED_EPISODES", "KEYFRAMES", "KEYFRAME_SIZE", "ReviewState", "make_server"]

KEYFRAMES = 4
"""First-person keyframes per episode."""
KEYFRAME_SIZE = (240, 180)
"""Width and height of a keyframe (pixels)."""
CACHED_EPISODES = 256
"""Episodes whose pictures are kept in memory (the least recently drawn are dropped first)."""
MAX_BODY_BYTES = 64 << 10
"""Largest decision request read (bytes)."""
MAX_SCENE_RENDERERS = 4
"""Scenes whose keyframe renderer is kept (building one copies the scene's geometry)."""

_PICTURE = re.compile(r"^/(?:bev/(?P<bev>[^/]+)\.png|keyframes/(?P<kf>[^/]+)/(?P<k>\d+)\.png)$")


class ReviewState:
    """What the review server serves: a dataset version, its scenes, the decisions file, the pictures.

    Parameters
    ----------
    dataset : Dataset
        The version reviewed (verified by the caller).
    scene_dirs : dict
        ``{scene_id: scene directory}`` of every scene of the dataset.
    decisions : Path
        The decisions file (``<name>.review.yml`` beside the recipe); read if present, written on
        every decision.
    recipe : Path, optional
        The dataset's recipe (shown in hints).
    clock : callable, optional
        The time of a decision, ISO 8601 (default: now, UTC, to the second).

    Raises
    ------
    ReviewError
        If the decisions file exists but is malformed or about another dataset.
    """

    def __init__(
        self,
        dataset: Dataset,
        scene_dirs: dict[str, Path],
        decisions: Path,
        *,
        recipe: Path | None = None,
        clock: Callable[[], str] | None = None,
    ) -> None:
        self.dataset = dataset
        self.recipe = recipe
        self.scene_dirs = scene_dirs
        self.decisions_path = Path(decisions)
        self._clock = clock or (lambda: datetime.now(timezone.utc).isoformat(timespec="seconds"))
        name, version = dataset.manifest.name, dataset.manifest.version
        if self.decisions_path.exists():
            self.review = read_review(self.decisions_path, dataset=name)
        else:
            self.review = Review(dataset=name, reviewed_version=version)
        split_of = {scene: s for s, scenes in dataset.manifest.splits.items() for scene in scenes}
        self.episodes: dict[str, tuple[str, Episode]] = {
            e.episode_id: (split_of[e.scene_id], e) for e in dataset.episodes()
        }
        self._lock = threading.Lock()  # the review and its file
        self._render_lock = threading.Lock()  # the renderers (matplotlib, ray casting)
        self._pictures: OrderedDict[str, dict[str, bytes]] = OrderedDict()
        self._renderers: OrderedDict[str, Any] = OrderedDict()
        self._camera: np.ndarray | None = None

    # ------------------------------------------------------------------ listing and deciding

    def listing(self) -> dict[str, Any]:
        """The page's data: the dataset, its splits and tasks, and every episode with its decision."""
        manifest = self.dataset.manifest
        with self._lock:
            decisions = {k: v.model_dump() for k, v in self.review.decisions.items()}
        return {
            "dataset": manifest.name,
            "version": manifest.version,
            "embodiment": manifest.embodiment,
            "decisions_file": self.decisions_path.name,
            "splits": self.dataset.splits,
            "tasks": sorted({e.task for _, e in self.episodes.values()}),
            "episodes": [_summary(split, e, decisions.get(i)) for i, (split, e) in self.episodes.items()],
        }

    def decide(self, episode_id: str, decision: str, reason: str) -> dict[str, str]:
        """Record a decision and rewrite the decisions file; the decision as recorded.

        Raises
        ------
        ReviewError
            If the episode is not one of the dataset's or the decision is malformed.
        """
        if episode_id not in self.episodes:
            raise ReviewError(f"{self.dataset.manifest.name} has no episode {episode_id!r}")
        with self._lock:
            review = with_decision(
                self.review, episode_id, decision=decision, reason=reason, at=self._clock(),
                newest=self._newest_published(),
            )  # fmt: skip
            write_review(self.decisions_path, review)
            self.review = review
            return review.decisions[episode_id].model_dump()

    def _newest_published(self) -> str:
        """The newest version of this dataset beside the reviewed one (``episodes/<name>/v*``)."""
        found = [self.dataset.manifest.version]
        for path in self.dataset.root.parent.glob("v*/manifest.json"):
            if re.fullmatch(r"v\d+\.\d+", path.parent.name):
                found.append(path.parent.name[1:])
        return newest_version(*found)

    # ------------------------------------------------------------------ pictures

    def picture(self, episode_id: str, name: str) -> bytes:
        """A picture of an episode: ``bev`` or ``keyframe-<k>`` (PNG bytes), drawn once and kept.

        Raises
        ------
        KeyError
            If there is no such episode or picture.
        """
        if episode_id not in self.episodes:
            raise KeyError(episode_id)
        kind = "bev" if name == "bev" else "keyframes"
        with self._render_lock:
            cached = self._pictures.setdefault(episode_id, {})
            self._pictures.move_to_end(episode_id)
            if name not in cached:
                cached.update(self._draw(episode_id, kind))
            while len(self._pictures) > CACHED_EPISODES:
                self._pictures.popitem(last=False)
        return cached[name]

    def _draw(self, episode_id: str, kind: str) -> dict[str, bytes]:
        from navverse.episodes.inspect import draw_episode

        _, episode = self.episodes[episode_id]
        rollout = self.dataset.rollout(episode)
        scene_dir = self.scene_dirs[episode.scene_id]
        if kind == "bev":
            with tempfile.TemporaryDirectory(prefix="navverse-review-") as tmp:
                out = draw_episode(scene_dir, episode, rollout, Path(tmp) / "bev.png")
                return {"bev": out.read_bytes()}
        if not rollout:
            return {}
        frames = self._keyframes(episode.scene_id, scene_dir, np.asarray(rollout, dtype=float))
        return {f"keyframe-{k}": _png(frame) for k, frame in enumerate(frames)}

    def _keyframes(self, scene_id: str, scene_dir: Path, rollout: np.ndarray) -> list[np.ndarray]:
        from navverse.look.files import load_scene_look
        from navverse.scene.directory import read_scene
        from navverse.sim.camera import CameraIntrinsics
        from navverse.sim.embodiments import make_embodiment
        from navverse.sim.keyframes import render_keyframes
        from navverse.sim.render import SceneRenderer

        if self._camera is None:
            embodiment = make_embodiment(self.dataset.manifest.embodiment)
            self._camera = np.asarray(embodiment.camera_to_base, dtype=float)
        if scene_id not in self._renderers:
            intrinsics = CameraIntrinsics.from_hfov(*KEYFRAME_SIZE, 90.0)
            shown = read_scene(scene_dir)
            look = load_scene_look(shown, scene_dir)
            self._renderers[scene_id] = SceneRenderer(shown, intrinsics=intrinsics, look=look)
            while len(self._renderers) > MAX_SCENE_RENDERERS:
                self._renderers.popitem(last=False)
        self._renderers.move_to_end(scene_id)
        return render_keyframes(self._renderers[scene_id], rollout, self._camera, KEYFRAMES)


def _png(frame: np.ndarray) -> bytes:
    buffer = io.BytesIO()
    Image.fromarray(np.ascontiguousarray(frame, dtype=np.uint8)).save(buffer, format="PNG")
    return buffer.getvalue()


def _summary(split: str, episode: Episode, decision: dict[str, str] | None) -> dict[str, Any]:
    """An episode as the page shows it."""
    instructions = []
    if episode.instruction is not None:
        instructions.append(
            {"type": episode.instruction.instruction_type, "text": episode.instruction.instruction_text}
        )
    for kind, instruction in sorted(episode.instructions.items()):
        instructions.append({"type": kind, "text": instruction.instruction_text})
    return {
        "id": episode.episode_id,
        "split": split,
        "task": episode.task,
        "scene": episode.scene_id,
        "scene_type": episode.scene_type,
        "category": episode.goal_category,
        "geodesic": None if episode.info is None else round(episode.info.geodesic_distance, 2),
        "difficulty": None if episode.info is None else episode.info.difficulty,
        "instructions": instructions,
        "decision": decision,
    }


# ---------------------------------------------------------------------------------------------- HTTP


class _Handler(BaseHTTPRequestHandler):
    """The routes of the review page; ``server.state`` is the :class:`ReviewState`."""

    server: _ReviewServer
    protocol_version = "HTTP/1.1"

    def log_message(self, format: str, *args: Any) -> None:
        """Quiet: the console shows the URL only."""

    def do_GET(self) -> None:
        """The page, the listing, or a picture."""
        if not self._host_ok():
            return
        path = self.path.split("?", 1)[0]
        if path in ("/", "/index.html"):
            self._send(HTTPStatus.OK, PAGE.encode("utf-8"), "text/html; charset=utf-8")
        elif path == "/api/episodes":
            self._json(HTTPStatus.OK, self.server.state.listing())
        elif (match := _PICTURE.match(path)) is not None:
            self._picture(match)
        else:
            self._json(HTTPStatus.NOT_FOUND, {"error": f"no such page: {path}"})

    def do_POST(self) -> None:
        """A decision."""
        if not self._host_ok():
            return
        if self.path != "/api/decision":
            self._json(HTTPStatus.NOT_FOUND, {"error": f"no such page: {self.path}"})
            return
        problem, body = self._read_json()
        if problem is not None:
            self._json(HTTPStatus.BAD_REQUEST, {"error": problem})
            return
        try:
            saved = self.server.state.decide(
                str(body.get("episode_id", "")), str(body.get("decision", "")), str(body.get("reason", ""))
            )
        except ReviewError as exc:
            self._json(HTTPStatus.BAD_REQUEST, {"error": str(exc)})
            return
        except OSError as exc:
            self._json(HTTPStatus.INTERNAL_SERVER_ERROR, {"error": f"cannot write the decisions: {exc}"})
            return
        self._json(HTTPStatus.OK, {"episode_id": body["episode_id"], **saved})

    # ------------------------------------------------------------------ helpers

    def _hosts(self) -> set[str]:
        port = self.server.server_address[1]
        return {f"127.0.0.1:{port}", f"localhost:{port}"}

    def _host_ok(self) -> bool:
        if self.headers.get("Host", "") in self._hosts():
            return True
        self._json(HTTPStatus.FORBIDDEN, {"error": "open the page at the address navverse review printed"})
        return False

    def _read_json(self) -> tuple[str | None, dict[str, Any]]:
        origin = self.headers.get("Origin")
        if origin is not None and origin.removeprefix("http://") not in self._hosts():
            return f"decisions come from the review page, not from {origin}", {}
        if self.headers.get("Content-Type", "").split(";")[0].strip() != "application/json":
            return "a decision is sent as application/json", {}
        try:
            length = int(self.headers.get("Content-Length", ""))
        except ValueError:
            return "a decision needs a Content-Length", {}
        if not 0 < length <= MAX_BODY_BYTES:
            return f"a decision is 1 to {MAX_BODY_BYTES} bytes", {}
        try:
            body = json.loads(self.rfile.read(length))
        except (UnicodeDecodeError, json.JSONDecodeError):
            return "a decision is a JSON object", {}
        if not isinstance(body, dict):
            return "a decision is a JSON object {episode_id, decision, reason}", {}
        return None, body

    def _picture(self, match: re.Match[str]) -> None:
        episode_id = match["bev"] or match["kf"]
        name = "bev" if match["bev"] else f"keyframe-{int(match['k'])}"
        if match["k"] is not None and int(match["k"]) >= KEYFRAMES:
            self._json(HTTPStatus.NOT_FOUND, {"error": f"keyframes are 0 to {KEYFRAMES - 1}"})
            return
        try:
            data = self.server.state.picture(episode_id, name)
        except KeyError:
            self._json(HTTPStatus.NOT_FOUND, {"error": f"no picture {name} of {episode_id}"})
            return
        self._send(HTTPStatus.OK, data, "image/png", cache=True)

    def _json(self, status: HTTPStatus, data: Any) -> None:
        self._send(status, json.dumps(data).encode("utf-8"), "application/json")

    def _send(self, status: HTTPStatus, body: bytes, content_type: str, *, cache: bool = False) -> None:
        self.send_response(status)
        self.send_header("Content-Type", content_type)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "private, max-age=3600" if cache else "no-store")
        self.send_header("X-Content-Type-Options", "nosniff")
        self.end_headers()
        self.wfile.write(body)


class _ReviewServer(ThreadingHTTPServer):
    daemon_threads = True

    def __init__(self, address: tuple[str, int], state: ReviewState) -> None:
        super().__init__(address, _Handler)
        self.state = state

    def handle_error(self, request: Any, client_address: Any) -> None:
        """A browser that left before its answer was sent is no error; anything else is printed."""
        if isinstance(sys.exc_info()[1], ConnectionError):
            return
        super().handle_error(request, client_address)


def make_server(state: ReviewState, *, port: int = 0) -> ThreadingHTTPServer:
    """A review server on 127.0.0.1 (not started: call ``serve_forever``).

    Parameters
    ----------
    state : ReviewState
        What it serves.
    port : int
        The port; 0 picks a free one (read it from ``server.server_address[1]``).

    Returns
    -------
    ThreadingHTTPServer
        The bound server; ``server.state`` is ``state``.
    """
    return _ReviewServer(("127.0.0.1", int(port)), state)
