"""A server run: the database migrated, the store opened, the application and its scheduler served by
uvicorn on a socket bound here (so that a port in use is a clear error and port 0 gets a free one).

The server speaks plain HTTP; put it behind a TLS reverse proxy (nginx, Caddy) to serve it beyond
this machine. Each run has a random instance id, the ``claimed_by`` of its claims: a server started
again on the same database takes over the claims of a killed one once their leases run out.
"""

from __future__ import annotations

import os
import secrets
import signal
import socket
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

from navverse.serve.benchmark import Benchmark
from navverse.serve.db import open_db
from navverse.serve.errors import ServeError
from navverse.serve.settings import ServeSettings
from navverse.serve.store import Store

__all__ = ["LOCAL_HOSTS", "bind", "default_store", "run_server"]

LOCAL_HOSTS = frozenset({"127.0.0.1", "localhost", "::1"})
"""Hosts that bind this machine only."""


def default_store(db_path: str | os.PathLike[str]) -> Path:
    """The store beside a database: ``<db>.submissions/``."""
    db_path = Path(db_path)
    return db_path.with_name(db_path.name + ".submissions")


def bind(host: str, port: int) -> socket.socket:
    """A listening TCP socket on `host`:`port` (0: a free port).

    Raises
    ------
    ServeError
        If the address cannot be bound (in use, not this machine's, no permission).
    """
    if not 0 <= port <= 65535:
        raise ServeError(f"--port {port}: give a port from 1 to 65535 (0: any free one)")
    try:
        family = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)[0][0]
        return socket.create_server((host, port), family=family, backlog=128)
    except OSError as exc:
        raise ServeError(
            f"cannot listen on {host} port {port}: {exc.strerror or exc}; choose another --port or --host"
        ) from None


def run_server(
    benchmark: Benchmark,
    *,
    db_path: str | os.PathLike[str],
    store: str | os.PathLike[str] | None = None,
    settings: ServeSettings | None = None,
    host: str = "127.0.0.1",
    port: int = 8000,
    on_ready: Callable[[str, str], None] | None = None,
) -> None:
    """Serve `benchmark` until stopped by SIGINT or SIGTERM (then the submissions being scored go back to
    the queue, the workers end, and this returns).

    Parameters
    ----------
    benchmark : Benchmark
        :func:`navverse.serve.benchmark.open_benchmark`.
    db_path : path
        The database (created and migrated if needed).
    store : path, optional
        The folder of submission files (default :func:`default_store`).
    settings : ServeSettings, optional
    host : str
        The address to listen on.
    port : int
        The port (0: any free one).
    on_ready : callable, optional
        Called with the URL served and the instance id once the socket listens.

    Raises
    ------
    ServeError
        If the database, the store or the address cannot be used.
    """
    import uvicorn

    from navverse.serve.app import ServerState, make_app
    from navverse.serve.scheduler import Scheduler

    settings = settings or ServeSettings()
    db_path = Path(db_path)
    open_db(db_path).close()
    files = Store(store if store is not None else default_store(db_path)).open()
    instance = secrets.token_urlsafe(9)
    scheduler = Scheduler(
        db_path=str(db_path), store=files, benchmark=benchmark, settings=settings, instance=instance
    )
    app = make_app(ServerState(benchmark, settings, str(db_path), files, scheduler))
    sock = bind(host, port)
    name, bound = sock.getsockname()[:2]
    shown = f"[{name}]" if ":" in name else name
    config = uvicorn.Config(
        app,
        log_config=None,  # the command's logging: one format for the server's and uvicorn's lines
        access_log=False,  # the application logs each request without its query (user input)
        limit_concurrency=settings.max_connections,
        server_header=False,
        timeout_graceful_shutdown=10,
    )
    server = uvicorn.Server(config)
    if on_ready is not None:
        on_ready(f"http://{shown}:{bound}/", instance)
    with _stopped_by_signals():
        try:
            server.run(sockets=[sock])
        finally:
            scheduler.stop()
            sock.close()


@contextmanager
def _stopped_by_signals() -> Iterator[None]:
    """A block that ends normally when SIGINT or SIGTERM stops the server: uvicorn shuts down on either,
    then raises it again for its caller, here caught."""

    def stop(signum: int, frame: object) -> None:  # SIGTERM, raised again once uvicorn has shut down
        raise KeyboardInterrupt

    in_main = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGTERM, stop) if in_main else None
    try:
        yield
    except KeyboardInterrupt:
        pass
    finally:
        if in_main:
            signal.signal(signal.SIGTERM, previous)
