"""Running an agent's episodes under wall-clock limits, in this process or in worker processes.

:func:`run_in_pool` hands chunks of episodes (one scene each, :class:`Chunk`) to spawned worker
processes over pipes; :func:`run_here` runs them in this process. Each episode's messages (its start
pose, its trajectory step by step, its record, or why it failed) go to :class:`Results`, the
parent's side of the run.

Time limits: each call to the agent (``reset`` or ``act``) may take ``step_timeout`` seconds of wall
time, and its calls in one episode ``episode_timeout`` seconds together (the simulator's own time does
not count). A call over its limit is interrupted by an alarm (``SIGALRM``) inside the process that
runs the agent, and an answer that comes back late anyway is not used. A worker whose agent does not
yield to the alarm (stuck in native code, or catching everything) is killed, with whatever the agent
started, by the parent :data:`KILL_GRACE` seconds past the limit, and replaced. Either way the
episode ends with the termination label :data:`~navverse.sim.terminations.AGENT_TIMEOUT`, its
trajectory as far as the robot got, no stop, and the run goes on with the episodes after it. In this
process only the alarm applies (a call stuck in native code cannot be stopped). Workers write their
standard output and error (whatever the agent prints) to a log file, never to the terminal.
"""

from __future__ import annotations

import hashlib
import json
import multiprocessing
import multiprocessing.connection
import os
import signal
import sys
import threading
import time
import traceback
from collections import deque
from collections.abc import Callable, Iterator
from contextlib import contextmanager, suppress
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from navverse.dataset import Episode
from navverse.errors import NavverseError
from navverse.processes import end_with_parent
from navverse.scene.semantics import semantic_categories
from navverse.sim.recorder import RolloutRecorder
from navverse.sim.terminations import AGENT_TIMEOUT

__all__ = [
    "EPISODE_TIMEOUT",
    "KILL_GRACE",
    "STEP_TIMEOUT",
    "Chunk",
    "Results",
    "RunError",
    "RunSettings",
    "agent_seed",
    "run_here",
    "run_in_pool",
    "task_for",
]

STEP_TIMEOUT = 30.0
"""Default wall-clock limit of one call to the agent (``reset`` or ``act``), s."""
EPISODE_TIMEOUT = 600.0
"""Default wall-clock limit of the agent's calls in one episode, together, s."""
KILL_GRACE = 2.0
"""How long past a limit the parent waits for the alarm to free a worker before it kills it, s."""
_POLL = 0.2
"""How often the parent checks the workers' deadlines, s."""

Message = tuple[Any, ...]
Emit = Callable[[Message], None]


class RunError(NavverseError):
    """An agent run that cannot start (bad arguments) or whose agent failed."""


@dataclass(frozen=True)
class RunSettings:
    """What a run is: its results can be resumed only under the same settings."""

    agent: str
    dataset: str
    """The dataset by name and manifest checksum (not by path: a run resumes wherever the version is read
    from, and not over a changed version)."""
    dataset_version: str
    split: str
    embodiment: str
    seed: int = 0
    max_steps: int | None = None
    terrain_friction: float | None = None
    step_timeout: float = STEP_TIMEOUT
    episode_timeout: float = EPISODE_TIMEOUT
    instruction_type: str = "category"
    category_ids: dict[str, dict[str, int]] = field(default_factory=dict)
    """Per task, the dataset's ``category_to_task_category_id`` of the split (the ``goal_id`` observation)."""


def agent_seed(seed: int, episode_id: str) -> int:
    """The seed an agent gets for an episode: a hash of the run's seed and the episode id."""
    digest = hashlib.sha256(f"{seed}:{episode_id}".encode()).digest()
    return int.from_bytes(digest[:4], "little")


@dataclass(frozen=True)
class Chunk:
    """Episodes (as dataset dicts) of one scene, run in order by one environment."""

    scene_dir: str
    episodes: list[dict[str, Any]]

    def after(self, episode_id: str) -> Chunk | None:
        """The episodes after ``episode_id``, or None if it was the last."""
        ids = [e["episode_id"] for e in self.episodes]
        rest = self.episodes[ids.index(episode_id) + 1 :]
        return Chunk(self.scene_dir, rest) if rest else None


def task_for(episode: Episode, *, embodiment: str, radius: float, categories: dict[int, str], seed: int,
             scene_dir: Path, instruction_type: str = "category", privileged: bool = False,
             semantic: bool = False):  # fmt: skip
    """The :class:`~navverse.eval.agents.base.AgentTask` of an episode, by the observation protocol
    (:mod:`navverse.eval.protocol`).

    Its ``goal`` is what the environment observes (:func:`navverse.env_spec.episode_goal`); its
    ``goal_category`` is "" where the protocol does not tell it (VLN; PlaceNav under ``route`` and
    ``intention``) unless the agent is privileged; ``semantic_categories`` is given only to an agent
    that uses the semantic sensor (`semantic`) or is privileged.
    """
    from navverse.env_spec import episode_goal
    from navverse.eval.agents.base import AgentTask
    from navverse.eval.protocol import is_told_category

    goal, kind = episode_goal(episode.model_dump(mode="json"), instruction_type)
    told = is_told_category(episode.task, kind, privileged=privileged)
    return AgentTask(
        episode_id=episode.episode_id,
        task=episode.task,
        goal=goal,
        goal_category=episode.goal_category if told else "",
        scene_type=episode.scene_type,
        embodiment=embodiment,
        robot_radius=radius,
        semantic_categories=dict(categories) if semantic or privileged else {},
        seed=agent_seed(seed, episode.episode_id),
        scene_dir=str(scene_dir),
        instruction_type=kind,
    )


# ---------------------------------------------------------------------------------------------- time limits


class _AgentTimeoutError(BaseException):
    """Raised into the agent's call when its time is up (a BaseException: ``except Exception`` in
    the agent does not swallow it)."""


@contextmanager
def _alarms() -> Iterator[bool]:
    """Let :class:`_AgentClock` interrupt calls with ``SIGALRM`` for the duration (restoring the
    previous handler); yields False where signals cannot be used (not the main thread)."""
    if threading.current_thread() is not threading.main_thread():
        yield False
        return
    previous = signal.getsignal(signal.SIGALRM)
    try:
        yield True
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


class _AgentClock:
    """The agent's wall-clock budget in one episode: each call gets the step limit or what is left
    of the episode's, whichever is smaller.

    Parameters
    ----------
    settings : RunSettings
        The limits.
    alarm : bool
        Whether to interrupt a call at its limit with ``SIGALRM`` (inside :func:`_alarms`).
    deadline : shared double, optional
        Where the parent reads the current call's deadline (``time.monotonic``; 0 between calls).
    """

    def __init__(self, settings: RunSettings, *, alarm: bool, deadline: Any = None) -> None:
        self._step = settings.step_timeout
        self._episode = settings.episode_timeout
        self._alarm = alarm
        self._deadline = deadline
        self.used = 0.0

    def call(self, function: Callable[..., Any], *args: Any) -> Any:
        """``function(*args)``, raising :class:`_AgentTimeoutError` if it overruns its limit: at the
        limit by the alarm, or once it returns if it swallowed the alarm (or none could be set)."""
        name = getattr(function, "__name__", "call")
        left = self._episode - self.used
        if self._step <= left:
            limit, reason = self._step, f"{name} took longer than the {self._step:g} s step limit"
        else:
            limit, reason = left, f"the agent used up the {self._episode:g} s episode limit (in {name})"
        if limit <= 0:
            raise _AgentTimeoutError(reason)
        started = time.monotonic()
        if self._deadline is not None:
            self._deadline.value = started + limit
        if self._alarm:
            signal.signal(signal.SIGALRM, _raiser(reason))
            signal.setitimer(signal.ITIMER_REAL, limit)
        try:
            result = function(*args)
        finally:
            self.release()
        elapsed = time.monotonic() - started
        self.used += elapsed
        if elapsed > limit:
            raise _AgentTimeoutError(reason)
        return result

    def release(self) -> None:
        """No call is running: disarm the alarm and clear the deadline the parent watches."""
        if self._alarm:
            signal.setitimer(signal.ITIMER_REAL, 0)
        if self._deadline is not None:
            self._deadline.value = 0.0


def _raiser(reason: str) -> Callable[[int, Any], None]:
    def expire(signum: int, frame: Any) -> None:
        raise _AgentTimeoutError(reason)

    return expire


# ---------------------------------------------------------------------------------------------- worker side


class _Trail:
    """An episode's trajectory as the environment records it, handed out step by step, so that the
    parent can write the record of an episode whose agent never came back."""

    def __init__(self, sim: Any) -> None:
        self._sim = sim
        self._recorder = RolloutRecorder("trail")
        self._recorder.attach(sim)  # same rows as the environment's recorder, attached at the same time
        self._start = sim.time
        self._rows = 1
        self._collisions = len(sim.collisions)

    @property
    def first(self) -> list[float]:
        """The row at t = 0."""
        return self._recorder.rows[0]

    def news(self) -> tuple[list[list[float]], list[float], list[float]]:
        """Rows recorded since the last call, the current pose as a row, and new collision times."""
        rows = self._recorder.rows[self._rows :]
        self._rows += len(rows)
        pose = self._sim.pose()
        now = [
            round(self._sim.time - self._start, 6),
            *map(float, pose.position),
            *map(float, pose.quaternion),
        ]
        hits = self._sim.collisions[self._collisions :]
        self._collisions += len(hits)
        return rows, now, [round(c.time - self._start, 3) for c in hits]

    def close(self) -> None:
        """Stop recording."""
        self._recorder.finish(stop=False, termination=None)


def _run_episode(
    env: Any,
    agent: Any,
    task: Any,
    data: dict[str, Any],
    emit: Emit,
    clock: _AgentClock,
    *,
    category_ids: dict[str, int] | None = None,
) -> bool:
    """Run one episode, emitting ``begin``, ``step`` rows and its end (``record``, ``timeout`` or
    ``error``); False when its chunk must stop here."""
    episode_id = task.episode_id
    trail = None
    try:
        options: dict[str, Any] = {"episode": data}
        if category_ids is not None:
            options["category_ids"] = category_ids
        observation, info = env.reset(seed=task.seed, options=options)
        trail = _Trail(env.sim)
        emit(("begin", episode_id, trail.first, info.get("instruction_type")))
        clock.call(agent.reset, task)
        while "submission" not in info:
            action = clock.call(agent.act, observation, info)
            observation, _, _, _, info = env.step(action)
            if "submission" not in info:
                emit(("step", episode_id, *trail.news()))
    except _AgentTimeoutError as timeout:
        clock.release()  # the parent must not kill a worker that is free again
        emit(("timeout", episode_id, str(timeout)))
        return False
    except Exception as exc:  # the agent's (or its action's) failure, reported with its place
        frame = traceback.extract_tb(exc.__traceback__)[-1]
        where = f"{Path(frame.filename).name}:{frame.lineno} in {frame.name}"
        emit(("error", episode_id, f"{type(exc).__name__}: {exc} (at {where})"))
        return False
    finally:
        if trail is not None:
            trail.close()
    emit(("record", episode_id, info["submission"]))
    return True


def _run_chunk(settings: RunSettings, chunk: Chunk, emit: Emit, *, alarm: bool, deadline: Any = None) -> None:
    """Run a chunk's episodes in one environment, emitting messages as they go (see :class:`Results`);
    it stops at the first episode that fails or runs out of time."""
    from navverse.env import NavVerseEnv
    from navverse.eval.agents import load_agent
    from navverse.eval.protocol import agent_sensors

    agent = load_agent(settings.agent)
    privileged = bool(getattr(agent, "privileged", False))
    sensors = agent_sensors(agent)
    env = NavVerseEnv(
        chunk.scene_dir,
        embodiment=settings.embodiment,
        action_mode=agent.action_mode,
        privileged=privileged,
        sensors=sensors,
        max_steps=settings.max_steps,
        terrain_friction=settings.terrain_friction,
        instruction_type=settings.instruction_type,
    )
    try:
        categories = {i: c for i, c in semantic_categories(env.scene.annotations).items() if c}
        radius = float(env.sim.robot.radius)
        for data in chunk.episodes:
            episode = Episode.model_validate(data)
            task = task_for(episode, embodiment=settings.embodiment, radius=radius, categories=categories,
                            seed=settings.seed, scene_dir=Path(chunk.scene_dir),
                            instruction_type=settings.instruction_type, privileged=privileged,
                            semantic="semantic" in sensors)  # fmt: skip
            clock = _AgentClock(settings, alarm=alarm, deadline=deadline)
            ids = settings.category_ids.get(episode.task)
            if not _run_episode(env, agent, task, data, emit, clock, category_ids=ids):
                return
    finally:
        env.close()


def _worker_main(conn: Any, settings: RunSettings, deadline: Any, log: str) -> None:
    """A worker process: run the chunks the parent sends until it sends None."""
    os.setpgrp()  # its own process group: the parent can stop whatever the agent started with it
    end_with_parent()  # and a killed run-agent leaves no worker behind
    _send_output_to(log)
    with _alarms() as alarm:
        while True:
            try:
                work = conn.recv()
            except EOFError:
                return
            if work is None:
                return
            try:
                _run_chunk(settings, Chunk(*work), conn.send, alarm=alarm, deadline=deadline)
            except Exception as exc:  # the agent or the environment could not even start
                conn.send(("failed", f"{type(exc).__name__}: {exc}"))
            deadline.value = 0.0
            conn.send(("end",))


def _send_output_to(log: str) -> None:
    """Point this process's standard output and error (Python's and C's) at the end of ``log``."""
    fd = os.open(log, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
    for target in (1, 2):
        os.dup2(fd, target)
    os.close(fd)
    for stream in (sys.stdout, sys.stderr):
        with suppress(AttributeError, ValueError):
            stream.reconfigure(line_buffering=True)


# ---------------------------------------------------------------------------------------------- parent side


@dataclass
class _Open:
    """What the parent knows of an episode in progress: its trajectory so far (and, for PlaceNav, the
    instruction type its record names)."""

    rows: list[list[float]]
    now: list[float]
    collisions: list[float] = field(default_factory=list)
    instruction_type: str | None = None

    def record(self, episode_id: str) -> dict[str, Any]:
        """The submission record of the episode ended here by the agent's time limit."""
        rows = list(self.rows)
        if self.now[0] > rows[-1][0] + 1e-9:
            rows.append(self.now)
        record = {
            "episode_id": episode_id,
            "trajectory": rows,
            "stop": False,
            "collisions": sorted(set(self.collisions)),
            "termination": AGENT_TIMEOUT,
        }
        if self.instruction_type is not None:
            record["instruction_type"] = self.instruction_type
        return record


class Results:
    """The parent's side of a run: takes the workers' messages, keeps the records (appending each
    to the partial file) and the failures.

    Parameters
    ----------
    records : dict
        Episode id -> submission record; filled in as episodes end.
    sink : text file
        Where each new record is appended as a JSON line (the partial file).
    progress : callable
        Called after each new record.

    Messages: ``("begin", id, row, instruction_type)`` (None but for PlaceNav), ``("step", id, rows,
    now, collisions)``, ``("record", id, record)``, ``("timeout", id, reason)``, ``("error", id,
    message)``; the pool adds ``("end",)`` and ``("failed", message)``.
    """

    def __init__(self, records: dict[str, dict[str, Any]], sink: Any, progress: Callable[[], None]) -> None:
        self.records = records
        self.errors: list[tuple[str, str]] = []
        self.timeouts: list[tuple[str, str]] = []
        self._sink = sink
        self._progress = progress
        self._open: dict[str, _Open] = {}

    def handle(self, message: Message) -> None:
        """Take one message from the episode runner."""
        kind, episode_id = message[0], message[1]
        if kind == "begin":
            kind = message[3] if len(message) > 3 else None
            self._open[episode_id] = _Open([message[2]], message[2], instruction_type=kind)
        elif kind == "step":
            trail = self._open[episode_id]
            trail.rows.extend(message[2])
            trail.now = message[3]
            trail.collisions.extend(message[4])
        elif kind == "record":
            self._finish(episode_id, message[2])
        elif kind == "timeout":
            self.time_out(episode_id, message[2])
        elif kind == "error":
            self._open.pop(episode_id, None)
            self.errors.append((episode_id, message[2]))

    def ended(self, episode_id: str) -> bool:
        """Whether the episode has its record or failed."""
        return episode_id in self.records or any(e == episode_id for e, _ in self.errors)

    def time_out(self, episode_id: str, reason: str) -> None:
        """End an episode by the agent's time limit, with the trajectory streamed so far."""
        trail = self._open.get(episode_id)
        if trail is None:
            raise RunError(f"episode {episode_id} timed out before it began")  # never: begin comes first
        self.timeouts.append((episode_id, reason))
        self._finish(episode_id, trail.record(episode_id))

    def _finish(self, episode_id: str, record: dict[str, Any]) -> None:
        self._open.pop(episode_id, None)
        self.records[episode_id] = record
        self._sink.write(json.dumps(record, separators=(",", ":")) + "\n")
        self._sink.flush()
        self._progress()


def run_here(settings: RunSettings, chunks: list[Chunk], results: Results) -> None:
    """Run the chunks in this process, one after the other: time limits by alarm only (in the main
    thread; elsewhere none), and the agent's output goes where this process's goes.

    Parameters
    ----------
    settings : RunSettings
        The run.
    chunks : list of Chunk
        The episodes to run, by scene.
    results : Results
        Where the episodes' messages go.
    """
    pending = deque(chunks)
    with _alarms() as alarm:
        while pending:
            chunk = pending.popleft()

            def emit(message: Message, chunk: Chunk = chunk) -> None:
                results.handle(message)
                if message[0] == "timeout" and (rest := chunk.after(message[1])) is not None:
                    pending.appendleft(rest)

            _run_chunk(settings, chunk, emit, alarm=alarm)


class _Worker:
    """A worker process, its pipe, the deadline it shares, and the chunk it runs."""

    def __init__(self, context: Any, settings: RunSettings, log: Path) -> None:
        self.conn, child = context.Pipe()
        self.deadline = context.RawValue("d", 0.0)
        self.process = context.Process(
            target=_worker_main, args=(child, settings, self.deadline, str(log)), name="navverse-agent"
        )
        self.process.start()
        child.close()
        self.chunk: Chunk | None = None
        self.current: str | None = None

    def give(self, chunk: Chunk) -> bool:
        """Start a chunk; False if the process is gone."""
        self.deadline.value = 0.0
        try:
            self.conn.send((chunk.scene_dir, chunk.episodes))
        except OSError:
            return False
        self.chunk, self.current = chunk, None
        return True

    def overdue(self) -> bool:
        """Whether the agent's current call is past its deadline and the grace."""
        deadline = self.deadline.value
        return self.chunk is not None and deadline > 0.0 and time.monotonic() > deadline + KILL_GRACE

    def receive(self, results: Results, pending: deque[Chunk]) -> None:
        """Handle every message that has arrived (all of them once the process is gone)."""
        while self.chunk is not None:
            try:
                if not self.conn.poll():
                    return
                message = self.conn.recv()
            except (EOFError, OSError):
                return
            if message[0] == "end":
                self.chunk = None
            elif message[0] == "failed":
                raise RunError(f"a worker failed: {message[1]}")
            else:
                results.handle(message)
                if message[0] == "begin":
                    self.current = message[1]
                elif message[0] == "timeout" and (rest := self.chunk.after(message[1])) is not None:
                    pending.appendleft(rest)

    def kill(self) -> None:
        """Stop the process and whatever it started, at once."""
        with suppress(ProcessLookupError, PermissionError):
            os.killpg(self.process.pid, signal.SIGKILL)
        with suppress(ProcessLookupError):
            self.process.kill()
        self.process.join()

    def stop(self) -> None:
        """Ask an idle process to exit (killing it if it does not, or is busy)."""
        if self.chunk is None and self.process.is_alive():
            with suppress(OSError):
                self.conn.send(None)
            self.process.join(timeout=5.0)
        if self.process.is_alive():
            self.kill()
        self.conn.close()


def run_in_pool(settings: RunSettings, chunks: list[Chunk], jobs: int, results: Results, log: Path) -> None:
    """Run the chunks in up to ``jobs`` spawned processes, enforcing the agent's time limits.

    A worker whose agent overruns its limit by :data:`KILL_GRACE` is killed with its process group
    and its episode ended as ``agent_timeout``; the rest of its chunk goes to another worker. One that
    exits on its own fails its current episode.

    Parameters
    ----------
    settings : RunSettings
        The run.
    chunks : list of Chunk
        The episodes to run, by scene.
    jobs : int
        Most worker processes at once (at least 1).
    results : Results
        Where the episodes' messages go.
    log : Path
        The file the workers' standard output and error are appended to.

    Raises
    ------
    RunError
        If a worker cannot start, or cannot load the agent or open the scene.
    """
    context = multiprocessing.get_context("spawn")
    pending = deque(chunks)
    workers: list[_Worker] = []
    try:
        while pending or any(w.chunk is not None for w in workers):
            for worker in [w for w in workers if w.chunk is None and pending]:
                if not worker.give(pending[0]):
                    workers.remove(worker)
                    worker.stop()
                    continue
                pending.popleft()
            while pending and len(workers) < jobs:
                workers.append(_Worker(context, settings, log))
                if not workers[-1].give(pending[0]):
                    code = workers[-1].process.exitcode
                    raise RunError(f"a worker process could not start (exit code {code})")
                pending.popleft()
            busy = [w for w in workers if w.chunk is not None]
            multiprocessing.connection.wait(
                [w.conn for w in busy] + [w.process.sentinel for w in busy], _POLL
            )
            for worker in busy:
                worker.receive(results, pending)
                if worker.chunk is not None and worker.overdue():
                    _kill_overdue(worker, settings, results, pending)
                elif worker.chunk is not None and not worker.process.is_alive():
                    worker.receive(results, pending)
                    _report_death(worker, results)
                else:
                    continue
                workers.remove(worker)
                worker.stop()
    finally:
        for worker in workers:
            worker.stop()


def _kill_overdue(worker: _Worker, settings: RunSettings, results: Results, pending: deque[Chunk]) -> None:
    """Kill a worker whose agent did not yield to the alarm; its episode ends by the time limit."""
    worker.kill()
    worker.receive(results, pending)  # what it sent before it died
    episode_id = worker.current
    if worker.chunk is None or episode_id is None or results.ended(episode_id):
        return
    results.time_out(
        episode_id,
        f"the agent did not return within its limit (step {settings.step_timeout:g} s, episode "
        f"{settings.episode_timeout:g} s) nor yield to the alarm: its worker process was killed",
    )
    rest = worker.chunk.after(episode_id)
    if rest is not None:
        pending.appendleft(rest)


def _report_death(worker: _Worker, results: Results) -> None:
    """A worker that exited on its own in the middle of a chunk: a failure of its current episode."""
    assert worker.chunk is not None
    episode_id = worker.current or worker.chunk.episodes[0]["episode_id"]
    if not results.ended(episode_id):
        code = worker.process.exitcode
        results.errors.append(
            (episode_id, f"the process running the agent exited unexpectedly (exit code {code})")
        )
