"""The scheduler: a thread of the server that claims submissions from the database, scores them in a
process pool and renews their leases while they are scored.

The pool's processes are spawned by this thread and start with
:func:`navverse.processes.end_with_parent`: they end when it does (the server stops, or is killed,
with SIGKILL too). Its loop, until stopped:

1. settle the scorings that ended: the result recorded (:func:`navverse.serve.queue.finish`), or the
   submission failed (a submission the reader refuses) or put back in the queue (a worker that died,
   an error of the server's: counted towards the submission's attempts);
2. every heartbeat, renew the leases of the submissions being scored (:func:`~navverse.serve.queue.renew`);
3. while a worker is free, claim the oldest waiting submission (:func:`~navverse.serve.queue.claim_next`)
   and hand it to the pool;
4. wait for a scoring to end, an accepted upload (:meth:`Scheduler.wake`), the next heartbeat or the
   poll interval.

A stopped scheduler puts the submissions it was scoring back in the queue (uncounted), so that the
next server takes them at once; a killed one leaves its claims to run out (``lease_seconds``).
Log lines name submission ids, teams, statuses and timings only.
"""

from __future__ import annotations

import concurrent.futures as cf
import logging
import multiprocessing
import sqlite3
import threading
import time
from concurrent.futures.process import BrokenProcessPool

from navverse.processes import end_with_parent
from navverse.serve import queue
from navverse.serve.benchmark import Benchmark
from navverse.serve.db import connect
from navverse.serve.errors import ServeError
from navverse.serve.scoring import ScoringJob, score_job
from navverse.serve.settings import ServeSettings
from navverse.serve.store import Store

__all__ = ["LOGGER", "Scheduler"]

LOGGER = "navverse.serve"
"""The name of the server's logger."""
_LOST = "the server lost this submission's file; tell the benchmark's operators"
_REFUSED = (
    "the scorer could not read the submission: {reason}. Check it with `navverse validate submission` "
    "and send it again"
)


class Scheduler:
    """Claims and scores submissions in a process pool, in a thread of its own.

    Parameters
    ----------
    db_path : path
        The database.
    store : Store
        The submission files.
    benchmark : Benchmark
        The dataset and its splits' scenes.
    settings : ServeSettings
        Workers, lease, heartbeat, poll interval, attempts.
    instance : str
        This server's id in claims (random per start).
    """

    def __init__(
        self, *, db_path: str, store: Store, benchmark: Benchmark, settings: ServeSettings, instance: str
    ) -> None:
        self.db_path = db_path
        self.store = store
        self.benchmark = benchmark
        self.settings = settings
        self.instance = instance
        self.log = logging.getLogger(LOGGER)
        self._wake = threading.Event()
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._pool: cf.ProcessPoolExecutor | None = None
        self._running: dict[cf.Future, tuple[queue.Claim, float, cf.ProcessPoolExecutor]] = {}

    def start(self) -> None:
        """Start the scheduler's thread (once)."""
        if self._thread is not None:
            return
        self._thread = threading.Thread(target=self._run, name="navverse-serve-scheduler", daemon=True)
        self._thread.start()

    def wake(self) -> None:
        """Look for work now (an upload was accepted)."""
        self._wake.set()

    def stop(self, *, timeout: float = 30.0) -> None:
        """Stop claiming, put the submissions being scored back in the queue, end the pool's processes
        (nothing when it is not running)."""
        self._stop.set()
        self._wake.set()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout)

    # ------------------------------------------------------------------ the loop

    def _run(self) -> None:
        try:
            con = connect(self.db_path)
        except ServeError as exc:
            self.log.error("the scheduler cannot open the database, nothing is scored: %s", exc)
            return
        next_beat = 0.0
        try:
            while not self._stop.is_set():
                try:
                    self._settle(con)
                    now = time.time()
                    if self._running and now >= next_beat:
                        self._renew(con)
                        next_beat = now + self.settings.heartbeat_seconds
                    self._claim(con)
                except sqlite3.Error as exc:  # a busy or full disk: try again at the next turn
                    self.log.warning("database error in the scheduler: %s", type(exc).__name__)
                except Exception as exc:  # keep scoring the others; the operators see the kind of error
                    self.log.error("error in the scheduler: %s", type(exc).__name__)
                wait = self.settings.poll_seconds
                if self._running:
                    wait = min(wait, max(0.0, next_beat - time.time()))
                self._wake.wait(wait)
                self._wake.clear()
        finally:
            self._shutdown(con)
            con.close()

    def _job(self, claim: queue.Claim) -> ScoringJob:
        split = self.benchmark.splits[claim.split]
        return ScoringJob(
            submission_id=claim.submission_id,
            path=str(self.store.path(claim.file)),
            split=claim.split,
            dataset=str(self.benchmark.root),
            private=None if self.benchmark.private_dir is None else str(self.benchmark.private_dir),
            scene_dirs=tuple((scene, str(folder)) for scene, folder in sorted(split.scene_dirs.items())),
        )

    def _claim(self, con: sqlite3.Connection) -> None:
        settings = self.settings
        scored = [name for name, split in self.benchmark.splits.items() if split.scoreable]
        while len(self._running) < settings.workers and not self._stop.is_set():
            claim = queue.claim_next(
                con, instance=self.instance, lease=settings.lease_seconds, max_attempts=settings.max_attempts,
                splits=scored,
            )  # fmt: skip
            if claim is None:
                return
            try:
                job = self._job(claim)
            except ServeError:  # the database names a file this store does not make
                queue.fail(con, claim, instance=self.instance, error=_LOST)
                self.log.error("submission %s: failed, its file is not in the store", claim.submission_id)
                continue
            if self._pool is None:
                self._pool = cf.ProcessPoolExecutor(
                    max_workers=settings.workers,
                    mp_context=multiprocessing.get_context("spawn"),
                    initializer=end_with_parent,
                )
            future = self._pool.submit(score_job, job)
            future.add_done_callback(lambda _: self._wake.set())
            self._running[future] = (claim, time.monotonic(), self._pool)
            self.log.info(
                "submission %s of team %s: scoring (attempt %d)",
                claim.submission_id,
                claim.team,
                claim.attempt,
            )

    def _renew(self, con: sqlite3.Connection) -> None:
        claims = [claim for claim, _, _ in self._running.values()]
        for claim in queue.renew(con, claims, instance=self.instance, lease=self.settings.lease_seconds):
            self.log.warning("submission %s: lease lost to another server", claim.submission_id)

    def _settle(self, con: sqlite3.Connection) -> None:
        for future in [f for f in self._running if f.done()]:
            claim, started, pool = self._running[future]
            seconds = time.monotonic() - started
            self._settle_one(con, future, claim, seconds)
            if isinstance(future.exception(), BrokenProcessPool) and pool is self._pool:
                self._drop_pool()  # its processes are gone: the next claim makes a new pool
            del self._running[future]  # only once its outcome is written (a database error retries it)

    def _settle_one(
        self, con: sqlite3.Connection, future: cf.Future, claim: queue.Claim, seconds: float
    ) -> None:
        from navverse.eval.submission import SubmissionError

        exc = future.exception()
        name = claim.submission_id
        if exc is None:
            done = queue.finish(con, claim, instance=self.instance, result=future.result(), seconds=seconds)
            if done:
                self.log.info("submission %s of team %s: done in %.1f s", name, claim.team, seconds)
            else:
                self.log.warning("submission %s: scored, but its claim was lost; result dropped", name)
        elif isinstance(exc, SubmissionError):
            reason = str(exc).replace(str(self.store.path(claim.file)), "the submission")
            queue.fail(con, claim, instance=self.instance, error=_REFUSED.format(reason=reason))
            self.log.info("submission %s of team %s: failed (SubmissionError)", name, claim.team)
        else:
            queue.release(con, claim, instance=self.instance, counted=True)
            self.log.warning(
                "submission %s: scoring stopped with %s after %.1f s (attempt %d); queued again",
                name, type(exc).__name__, seconds, claim.attempt,
            )  # fmt: skip

    def _drop_pool(self) -> None:
        """Let a broken pool go."""
        pool, self._pool = self._pool, None
        if pool is not None:
            pool.shutdown(wait=False, cancel_futures=True)

    def _shutdown(self, con: sqlite3.Connection) -> None:
        """Put the claims back in the queue (uncounted) and end the pool's processes."""
        for claim, _, _ in list(self._running.values()):
            try:
                if queue.release(con, claim, instance=self.instance, counted=False):
                    self.log.info("submission %s: queued again (server stopping)", claim.submission_id)
            except sqlite3.Error:
                pass  # its lease runs out: another server takes it then
        self._running.clear()
        pool, self._pool = self._pool, None
        if pool is not None:
            processes = list(getattr(pool, "_processes", {}).values())
            pool.shutdown(wait=False, cancel_futures=True)
            for process in processes:
                process.kill()
            for process in processes:
                process.join(5)
