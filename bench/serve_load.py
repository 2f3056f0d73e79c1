"""Evaluation server under load: many teams submitting at once, on loopback.

1. A submission of ``--episodes`` episodes (default 900, navverse-full's eval split) is made from the
   dataset's own verification rollouts (``{"episode_id", "trajectory": rollout, "stop": true}`` per
   line, gzipped): an oracle run, without running an agent.
2. ``navverse serve`` is started on a free port of 127.0.0.1 with a fresh database and store,
   ``--workers`` scoring processes and a rate that lets every client submit once; ``--clients`` teams
   (default 50) get a token each.
3. The clients submit at once, one thread each (``POST /api/submissions``); each upload's latency
   from its first byte to its ``202`` is kept.
4. The run then watches the scoring for at most ``--score-seconds`` (0: until every submission is
   done), polling each submission's status with its owner's token, sampling the resident memory of the
   server and of its worker processes every half second.
5. Printed: accepted and refused uploads, the p50 / p95 / max upload latency, submissions scored per
   minute (from the first upload, and between the first and the last scoring: the pace once the
   scenes' fields are cached, which a fresh cache spends its first scorings on), the peak RSS of
   the server, of its largest worker and of all together; then the checks: every accepted
   submission has its row and its file in the store (``lost``), and no submission was scored more
   than once (``scored twice``: rows of the database's ``scorings`` table per submission, and claims
   of it by a scoring worker, ``attempts``).
6. The peer, in the same run on the same submission: ``navverse eval`` scoring it once from the
   command line (``--pictures 0``, the fields cached by the server's scorings), in submissions per
   minute; printed beside the server's pace, and their ratio.

Run ``python bench/serve_load.py --dataset episodes/navverse-full/v1.0 --scenes DIR`` (``--scenes``
where its scenes are built, or ``$NAVVERSE_SCENES``). Timings are measurements, never assertions;
the printed load average shows whether other work shared the machine.
"""

from __future__ import annotations

import argparse
import gzip
import json
import os
import platform
import socket
import sqlite3
import statistics
import subprocess
import sys
import tempfile
import threading
import time
import urllib.error
import urllib.request
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import psutil
from rich.console import Console
from rich.table import Table

from navverse.dataset import local_dataset
from navverse.serve.db import open_db
from navverse.serve.teams import add_token

POLL_SECONDS = 2.0
SAMPLE_SECONDS = 0.5


def make_submission(dataset_dir: str, split: str, episodes: int, out: Path) -> int:
    """Write a gzipped oracle submission of the first `episodes` episodes of `split` that have a
    rollout; return how many lines it has."""
    dataset = local_dataset(dataset_dir)
    dataset.verify()
    lines = []
    for episode in dataset.episodes(split=split):
        rollout = dataset.rollout(episode)
        if rollout is None:
            continue
        lines.append(json.dumps({"episode_id": episode.episode_id, "trajectory": rollout, "stop": True}))
        if len(lines) == episodes:
            break
    out.write_bytes(gzip.compress(("\n".join(lines) + "\n").encode(), mtime=0))
    return len(lines)


def free_port() -> int:
    """A free TCP port of 127.0.0.1."""
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def wait_until_up(url: str, server: subprocess.Popen, *, timeout: float = 120.0) -> None:
    """Wait for the server's leaderboard to answer (or fail if the server ended)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if server.poll() is not None:
            raise SystemExit(f"the server ended with code {server.returncode} before answering")
        try:
            with urllib.request.urlopen(url + "/api/leaderboard?split=eval", timeout=2):
                return
        except (urllib.error.URLError, OSError):
            time.sleep(0.25)
    raise SystemExit(f"the server did not answer within {timeout:.0f} s")


def submit(url: str, token: str, body: bytes, *, split: str, name: str) -> tuple[int, float, str]:
    """POST one submission; its status code, latency (s) and answer."""
    request = urllib.request.Request(
        f"{url}/api/submissions?split={split}&name={name}&public=true",
        data=body,
        method="POST",
        headers={"Authorization": f"Bearer {token}", "Content-Type": "application/octet-stream"},
    )
    started = time.perf_counter()
    try:
        with urllib.request.urlopen(request, timeout=600) as answer:
            return answer.status, time.perf_counter() - started, answer.read().decode()
    except urllib.error.HTTPError as exc:
        return exc.code, time.perf_counter() - started, exc.read().decode()


def status(url: str, token: str, submission_id: str) -> str:
    """The status of a submission, asked with its owner's token."""
    request = urllib.request.Request(
        f"{url}/api/submissions/{submission_id}", headers={"Authorization": f"Bearer {token}"}
    )
    with urllib.request.urlopen(request, timeout=60) as answer:
        return json.loads(answer.read())["status"]


class MemoryWatch:
    """Samples the RSS of a process and of its children in a thread; keeps the peaks."""

    def __init__(self, pid: int) -> None:
        self.process = psutil.Process(pid)
        self.server = self.worker = self.total = 0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while not self._stop.is_set():
            try:
                server = self.process.memory_info().rss
                workers = [c.memory_info().rss for c in self.process.children(recursive=True)]
            except psutil.Error:
                break
            self.server = max(self.server, server)
            self.worker = max([self.worker, *workers])
            self.total = max(self.total, server + sum(workers))
            self._stop.wait(SAMPLE_SECONDS)

    def stop(self) -> None:
        self._stop.set()
        self._thread.join()


def percentile(values: Sequence[float], q: float) -> float:
    """The `q` quantile (0-1) of `values`, by the nearest rank."""
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, max(0, round(q * (len(ordered) - 1))))]


def check_store(db: Path, store: Path, accepted: Sequence[str]) -> dict[str, Any]:
    """Lost and scored-twice counts, read from the database (read-only) and the store."""
    con = sqlite3.connect(f"file:{db}?mode=ro", uri=True)
    rows = {r[0]: r for r in con.execute("SELECT id, file, status, attempts FROM submissions")}
    times = sorted(t for (t,) in con.execute("SELECT scored_at FROM scorings"))
    scorings: dict[str, int] = {}
    for (submission_id,) in con.execute("SELECT submission_id FROM scorings"):
        scorings[submission_id] = scorings.get(submission_id, 0) + 1
    con.close()
    lost = [i for i in accepted if i not in rows or not (store / rows[i][1]).is_file()]
    return {
        "lost": len(lost),
        "scored_twice": sum(1 for n in scorings.values() if n > 1),
        "claimed_more_than_once": sum(1 for r in rows.values() if (r[3] or 0) > 1),
        "done": sum(1 for r in rows.values() if r[2] == "done"),
        "failed": sum(1 for r in rows.values() if r[2] == "failed"),
        # Between the first and the last scoring: the pace once the scenes' fields are cached.
        "steady_per_minute": 60.0 * (len(times) - 1) / (times[-1] - times[0]) if len(times) > 2 else None,
    }


def time_eval(args: argparse.Namespace, submission: Path, out: Path) -> float:
    """Seconds ``navverse eval`` takes to score `submission` once (no pictures)."""
    command = [
        str(Path(sys.executable).with_name("navverse")), "eval", "--dataset", args.dataset, "--split",
        args.split, "--submission", str(submission), "--out", str(out), "--pictures", "0",
    ]  # fmt: skip
    for folder in args.scenes:
        command += ["--scenes", folder]
    started = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - started


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dataset", default="episodes/navverse-full/v1.0", help="dataset version served")
    parser.add_argument("--split", default="eval", help="split submitted (default eval)")
    parser.add_argument("--scenes", action="append", default=[], help="where its scenes are built")
    parser.add_argument("--clients", type=int, default=50, help="concurrent clients, a team each (50)")
    parser.add_argument("--episodes", type=int, default=900, help="episodes per submission (900)")
    parser.add_argument("--workers", type=int, default=2, help="scoring processes of the server (2)")
    parser.add_argument(
        "--score-seconds", type=float, default=600.0,
        help="how long to watch the scoring after the uploads (default 600; 0: until all are done)",
    )  # fmt: skip
    parser.add_argument("--json", help="also write the results as JSON here")
    return parser.parse_args(argv)


def main(argv: Sequence[str] | None = None) -> int:
    args = parse_args(argv)
    console = Console()
    with tempfile.TemporaryDirectory(prefix="serve-load-") as tmp:
        work = Path(tmp)
        body_path = work / "run.jsonl.gz"
        lines = make_submission(args.dataset, args.split, args.episodes, body_path)
        body = body_path.read_bytes()
        db, store = work / "serve.db", work / "store"
        con = open_db(db)
        tokens = [add_token(con, f"team-{i:03d}")[1] for i in range(args.clients)]
        con.close()
        port = free_port()
        url = f"http://127.0.0.1:{port}"
        command = [
            str(Path(sys.executable).with_name("navverse")), "serve", "--dataset", args.dataset,
            "--db", str(db),
            "--store", str(store), "--port", str(port), "--workers", str(args.workers),
            "--rate-per-day", str(args.clients + 1),
        ]  # fmt: skip
        for folder in args.scenes:
            command += ["--scenes", folder]
        log = (work / "server.log").open("w")
        server = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
        try:
            wait_until_up(url, server)
            memory = MemoryWatch(server.pid)
            console.print(
                f"{args.clients} clients, each a {lines}-episode submission of {len(body) / 1e6:.1f} MB "
                f"(gzip) to {args.dataset} / {args.split}; {args.workers} scoring workers",
                highlight=False,
            )
            started = time.monotonic()
            with ThreadPoolExecutor(max_workers=args.clients) as pool:
                answers = list(
                    pool.map(
                        lambda i: submit(url, tokens[i], body, split=args.split, name=f"load-{i:03d}"),
                        range(args.clients),
                    )
                )
            uploaded = time.monotonic() - started
            accepted = {i: json.loads(text)["id"] for i, (code, _, text) in enumerate(answers) if code == 202}
            latencies = [seconds for code, seconds, _ in answers if code == 202]
            refused = [(code, text[:200]) for code, _, text in answers if code != 202]
            pending = dict(accepted)
            deadline = None if args.score_seconds <= 0 else time.monotonic() + args.score_seconds
            while pending and (deadline is None or time.monotonic() < deadline):
                for i, submission_id in list(pending.items()):
                    if status(url, tokens[i], submission_id) in ("done", "failed"):
                        del pending[i]
                time.sleep(POLL_SECONDS)
            watched = time.monotonic() - started
            memory.stop()
        finally:
            os.killpg(server.pid, 15)
            server.wait(timeout=60)
            log.close()
        checks = check_store(db, store, list(accepted.values()))
        peer_seconds = time_eval(args, body_path, work / "eval-out")
    scored = checks["done"] + checks["failed"]
    result = {
        "machine": {"cpus": os.cpu_count(), "load": os.getloadavg(), "python": platform.python_version()},
        "clients": args.clients,
        "episodes": lines,
        "body_bytes": len(body),
        "accepted": len(accepted),
        "refused": refused,
        "upload_seconds": uploaded,
        "latency_p50_s": statistics.median(latencies) if latencies else None,
        "latency_p95_s": percentile(latencies, 0.95) if latencies else None,
        "latency_max_s": max(latencies) if latencies else None,
        "scored": scored,
        "watched_seconds": watched,
        "scored_per_minute": 60.0 * scored / watched if watched else None,
        "peer_eval_seconds": peer_seconds,
        "peer_per_minute": 60.0 / peer_seconds,
        "peak_rss_mb": {
            "server": memory.server / 2**20,
            "worker": memory.worker / 2**20,
            "all": memory.total / 2**20,
        },
        **checks,
    }
    table = Table(title="evaluation server under load (loopback)")
    table.add_column("measure")
    table.add_column("value", justify="right")
    rows = [
        ("accepted / refused", f"{len(accepted)} / {len(refused)}"),
        ("upload latency p50 / p95 / max", "-" if not latencies else
         f"{result['latency_p50_s']:.2f} / {result['latency_p95_s']:.2f} / {result['latency_max_s']:.2f} s"),
        ("all uploads answered in", f"{uploaded:.1f} s"),
        ("scored (done or failed)", f"{scored} of {len(accepted)} in {watched:.0f} s"),
        ("scored per minute (from the first upload)", f"{result['scored_per_minute']:.2f}"),
        ("scored per minute (first to last scoring)", "-" if checks["steady_per_minute"] is None
         else f"{checks['steady_per_minute']:.2f}"),
        ("peer: navverse eval, one at a time, per minute", f"{60.0 / peer_seconds:.2f}"),
        ("server (first to last scoring) / peer", "-" if checks["steady_per_minute"] is None
         else f"{checks['steady_per_minute'] * peer_seconds / 60.0:.2f}x"),
        ("peak RSS server / largest worker / all", "{server:.0f} / {worker:.0f} / {all:.0f} MB".format(
            **result["peak_rss_mb"])),
        ("lost", str(checks["lost"])),
        ("scored twice (scorings rows)", str(checks["scored_twice"])),
        ("claimed more than once (attempts)", str(checks["claimed_more_than_once"])),
        ("load average", " ".join(f"{x:.2f}" for x in os.getloadavg())),
    ]  # fmt: skip
    for row in rows:
        table.add_row(*row)
    console.print(table)
    for code, text in refused[:5]:
        console.print(f"refused {code}: {text}", highlight=False, markup=False)
    if args.json:
        Path(args.json).write_text(json.dumps(result, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
