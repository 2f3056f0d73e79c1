"""The server's FastAPI application: its routes, their checks and their error bodies.

Routes (JSON unless said; the schema is at ``/openapi.json``):

``POST /api/submissions?split=&name=&public=``
    A team's submission as the body (JSONL, or gzip by its magic bytes), with ``Authorization: Bearer
    <token>``. Checked in this order: the token (401), the query (422: a split that takes no
    submission or whose goals the server lacks, a name of 1-100 characters without control
    characters), the team's rate (429), the body's size (413: its ``Content-Length`` first, then the
    bytes as they come), the body itself against the split (422, :func:`navverse.serve.intake.check_upload`,
    in a thread so the server stays responsive). Accepted: the file fsynced and renamed into the store,
    its row committed (the rate checked again in that transaction), then ``202 {"id", "status"}``.
``GET /api/submissions/<id>``
    The owner's view of a submission (:func:`navverse.serve.leaderboard.submission_view`); another
    team's id is the same 404 as an unknown one.
``GET /api/leaderboard?split=``
    The best public scored submission per team and track, ranked, with its group means.
``GET /`` (HTML)
    The leaderboard page (``?split=``).
``GET /submissions/<id>`` (HTML)
    A public submission's page; a private one is 404 here (its JSON is on the API, with its token).

Every error body is ``{"error": "<what is wrong and what to change>"}``. Responses carry
``X-Content-Type-Options: nosniff``, ``Referrer-Policy: no-referrer`` and, on pages, a
Content-Security-Policy that lets only their own inline style and script run. Each request is logged
as its method, path, status and time (no query string, no client address, no body).
"""

from __future__ import annotations

import functools
import logging
import sqlite3
import time
import unicodedata
from collections.abc import AsyncIterator, Iterator
from contextlib import asynccontextmanager, contextmanager
from dataclasses import dataclass
from typing import Any

import anyio
from fastapi import Depends, FastAPI, Query, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import HTMLResponse, JSONResponse
from fastapi.security import HTTPAuthorizationCredentials, HTTPBearer
from pydantic import BaseModel
from starlette.concurrency import run_in_threadpool
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.requests import ClientDisconnect
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from navverse.serve import queue
from navverse.serve.benchmark import Benchmark
from navverse.serve.db import connect
from navverse.serve.errors import RefusedError
from navverse.serve.intake import check_upload
from navverse.serve.leaderboard import best_entries, submission_view, track_text
from navverse.serve.pages import CONTENT_SECURITY_POLICY, leaderboard_page, not_found_page, submission_page
from navverse.serve.scheduler import LOGGER, Scheduler
from navverse.serve.settings import ServeSettings
from navverse.serve.store import Store, too_large
from navverse.serve.teams import team_of_token

__all__ = ["MAX_NAME_CHARS", "ServerState", "make_app"]

MAX_NAME_CHARS = 100
"""The longest submission name."""


@dataclass(frozen=True, eq=False)
class ServerState:
    """What the routes work with.

    Attributes
    ----------
    benchmark : Benchmark
    settings : ServeSettings
    db_path : str
    store : Store
    scheduler : Scheduler
        Started and stopped with the application; woken when an upload is accepted.
    """

    benchmark: Benchmark
    settings: ServeSettings
    db_path: str
    store: Store
    scheduler: Scheduler


class Accepted(BaseModel):
    """An accepted submission: its id (for ``GET /api/submissions/<id>``) and status."""

    id: str
    status: str


class Error(BaseModel):
    """Every error's body."""

    error: str


class SubmissionOut(BaseModel):
    """A submission as its team sees it."""

    id: str
    name: str
    split: str
    public: bool
    status: str
    created: str
    scored: str | None
    track: dict[str, Any]
    instruction_type: str | None
    metrics: dict[str, Any] | None = None
    """Per grouping (overall, task, scene_type, task_scene_type) and group: each metric's mean and its
    N (``<metric>_n``), the label shares and the episodes; when done."""
    scope: dict[str, Any] | None = None
    error: str | None = None


class LeaderboardOut(BaseModel):
    """The leaderboard of a split."""

    dataset: dict[str, str]
    split: str
    splits: list[str]
    entries: list[dict[str, Any]]


_ERRORS = {401: {"model": Error}, 404: {"model": Error}, 422: {"model": Error}}
_BODY = {
    "requestBody": {
        "required": True,
        "description": "The submission file: JSONL, one record per episode, or the same gzipped",
        "content": {"application/octet-stream": {"schema": {"type": "string", "format": "binary"}}},
    }
}


class _Headers:
    """ASGI middleware adding the security headers to every response (and the CSP to pages), and
    logging each request: its method, path (no query), status and time, nothing else."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app
        self.log = logging.getLogger(LOGGER)

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        started = time.monotonic()
        status = 500

        async def with_headers(message: Message) -> None:
            nonlocal status
            if message["type"] == "http.response.start":
                status = int(message["status"])
                headers = list(message.get("headers", []))
                headers += [
                    (b"x-content-type-options", b"nosniff"),
                    (b"referrer-policy", b"no-referrer"),
                    (b"x-frame-options", b"DENY"),
                    (b"cache-control", b"no-store"),
                ]
                kind = dict(headers).get(b"content-type", b"")
                if kind.startswith(b"text/html"):
                    headers.append((b"content-security-policy", CONTENT_SECURITY_POLICY.encode("ascii")))
                message = {**message, "headers": headers}
            await send(message)

        try:
            await self.app(scope, receive, with_headers)
        finally:
            path = scope.get("path", "")[:200]
            self.log.info(
                "%s %s %d %.3f s", scope.get("method", ""), path, status, time.monotonic() - started
            )


def _error(status: int, message: str, headers: dict[str, str] | None = None) -> JSONResponse:
    return JSONResponse({"error": message}, status_code=status, headers=headers)


def _check_name(name: str) -> None:
    if any(unicodedata.category(c).startswith("C") for c in name) or not name.strip():
        raise RefusedError(
            422, "name: give 1-100 characters of text, without control characters (it names the submission)"
        )


def make_app(state: ServerState) -> FastAPI:
    """The application serving `state`'s benchmark.

    Parameters
    ----------
    state : ServerState
        The benchmark, settings, database, store and the scheduler's wake-up.
    """
    from navverse import __version__

    benchmark: Benchmark = state.benchmark
    settings = state.settings
    log = logging.getLogger(LOGGER)
    limiter = anyio.CapacityLimiter(settings.validations)
    dataset_title = f"{benchmark.name} v{benchmark.version}"

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        state.scheduler.start()
        try:
            yield
        finally:  # before uvicorn ends: the claims go back to the queue, the workers end
            await anyio.to_thread.run_sync(state.scheduler.stop)

    app = FastAPI(
        lifespan=lifespan,
        title="NavVerse evaluation server",
        version=__version__,
        summary=f"Submissions to {dataset_title}, scored by the evaluator, and their leaderboard",
        docs_url=None,  # the interactive pages load their assets from a CDN; the schema is /openapi.json
        redoc_url=None,
    )
    app.add_middleware(_Headers)
    bearer = HTTPBearer(auto_error=False, description="a team's token (navverse serve token add TEAM)")

    @contextmanager
    def database() -> Iterator[sqlite3.Connection]:
        con = connect(state.db_path)
        try:
            yield con
        finally:
            con.close()

    def authenticated(credentials: HTTPAuthorizationCredentials | None = Depends(bearer)) -> str:  # noqa: B008
        """The team of the request's token, or a 401."""
        challenge = {"WWW-Authenticate": "Bearer"}
        if credentials is None:
            raise RefusedError(
                401, "no token: send your team's token as the header 'Authorization: Bearer <token>'",
                headers=challenge,
            )  # fmt: skip
        with database() as con:
            team = team_of_token(con, credentials.credentials)
        if team is None:
            raise RefusedError(
                401, "the token is not valid (unknown, mistyped or revoked): use the token your team was "
                "given, or ask the benchmark's operators for a new one", headers=challenge,
            )  # fmt: skip
        return team

    @app.exception_handler(RefusedError)
    async def refused(request: Request, exc: RefusedError) -> JSONResponse:
        return _error(exc.status, exc.message, exc.headers)

    @app.exception_handler(RequestValidationError)
    async def invalid(request: Request, exc: RequestValidationError) -> JSONResponse:
        parts = []
        for error in exc.errors()[:5]:
            where = " ".join(str(p) for p in error.get("loc", ()) if p != "query")
            parts.append(f"{where}: {error.get('msg', 'invalid')}")
        return _error(422, "; ".join(parts) or "the request is not valid")

    @app.exception_handler(StarletteHTTPException)
    async def http_error(request: Request, exc: StarletteHTTPException) -> Any:
        if request.url.path.startswith("/api/") or exc.status_code != 404:
            return _error(exc.status_code, str(exc.detail).lower() if exc.detail else "error")
        return HTMLResponse(not_found_page(), status_code=404)

    @app.exception_handler(Exception)
    async def crashed(request: Request, exc: Exception) -> JSONResponse:
        log.error("internal error on %s %s: %s", request.method, request.url.path, type(exc).__name__)
        return _error(500, "internal error of the server; try again later, or tell the benchmark's operators")

    def _rate_check(team: str) -> None:
        with database() as con:
            refusal = queue.rate_refusal(con, team, rate=settings.rate_per_day, now=time.time())
        if refusal is not None:
            raise refusal

    def _insert(new: queue.NewSubmission) -> None:
        with database() as con:
            queue.insert_submission(con, new, rate=settings.rate_per_day, now=time.time())

    @app.post(
        "/api/submissions", status_code=202, response_model=Accepted, openapi_extra=_BODY,
        responses={**_ERRORS, 413: {"model": Error}, 429: {"model": Error}},
        summary="submit a run (the body is the submission file)",
    )  # fmt: skip
    async def submit(
        request: Request,
        team: str = Depends(authenticated),
        split: str = Query(..., max_length=64, description="the split the run is of (e.g. test)"),
        name: str = Query(..., min_length=1, max_length=MAX_NAME_CHARS, description="the run's name"),
        public: bool = Query(False, description="show it on the leaderboard once scored"),
    ) -> dict:
        _check_name(name)
        info = benchmark.scoreable(split)
        await run_in_threadpool(_rate_check, team)
        cap = settings.max_body_bytes
        length = request.headers.get("content-length")
        if length is not None and (not length.isdigit() or int(length) > cap):
            raise RefusedError(413, too_large(cap))
        upload = state.store.upload(cap=cap)
        started = time.monotonic()
        try:
            try:
                async for chunk in request.stream():
                    upload.write(chunk)
            except ClientDisconnect:
                raise RefusedError(400, "the upload was cut off before its end: send it again") from None
            if upload.size == 0:
                raise RefusedError(422, "the request has no body: send the submission file as the body")
            await run_in_threadpool(upload.finish)
            check = functools.partial(check_upload, upload.path, info, shown=settings.problems_shown)
            checked = await anyio.to_thread.run_sync(check, limiter=limiter)
            submission_id = queue.new_id()
            file = await run_in_threadpool(state.store.place, upload, submission_id)
            new = queue.NewSubmission(
                id=submission_id, team=team, name=name, split=split, public=public, file=file,
                body_bytes=upload.size, lines=checked.lines, records=checked.records, track=checked.track,
                instruction_type=checked.instruction_type,
            )  # fmt: skip
            try:
                await run_in_threadpool(_insert, new)
            except BaseException:
                state.store.remove(file)
                raise
        finally:
            upload.discard()
        log.info(
            "submission %s of team %s: accepted (split %s, %d records, %d bytes, checked in %.1f s)",
            submission_id, team, split, checked.records, upload.size, time.monotonic() - started,
        )  # fmt: skip
        state.scheduler.wake()
        return {"id": submission_id, "status": "queued"}

    @app.get(
        "/api/submissions/{submission_id}", response_model=SubmissionOut, response_model_exclude_unset=True,
        responses=_ERRORS, summary="a submission of your team: its status, and its metrics once scored",
    )  # fmt: skip
    def submission(submission_id: str, team: str = Depends(authenticated)) -> dict:
        with database() as con:
            row = queue.submission_of(con, submission_id)
        if row is None or row["team"] != team:
            raise RefusedError(404, "no submission of your team has this id (ids are the ones POST returned)")
        return submission_view(row)

    def _board(split: str) -> list[dict]:
        with database() as con:
            return best_entries(queue.public_done(con, split))

    @app.get(
        "/api/leaderboard", response_model=LeaderboardOut, responses={422: {"model": Error}},
        summary="the best public submission per team and track",
    )  # fmt: skip
    def leaderboard(split: str | None = Query(None, max_length=64, description="default: test")) -> dict:
        split = benchmark.split(split or benchmark.default_split).name
        return {
            "dataset": {"name": benchmark.name, "version": benchmark.version},
            "split": split,
            "splits": sorted(benchmark.splits),
            "entries": _board(split),
        }

    @app.get("/", response_class=HTMLResponse, include_in_schema=False)
    def leaderboard_html(split: str | None = Query(None, max_length=64)) -> HTMLResponse:
        split = split or benchmark.default_split
        if split not in benchmark.splits:
            return HTMLResponse(not_found_page(), status_code=404)
        page = leaderboard_page(
            dataset=dataset_title, split=split, splits=sorted(benchmark.splits), entries=_board(split)
        )
        return HTMLResponse(page)

    @app.get("/submissions/{submission_id}", response_class=HTMLResponse, include_in_schema=False)
    def submission_html(submission_id: str) -> HTMLResponse:
        with database() as con:
            row = queue.submission_of(con, submission_id)
        if row is None or not row["public"]:
            return HTMLResponse(not_found_page(), status_code=404)
        view = submission_view(row)
        view["team"] = row["team"]
        view["track_text"] = track_text(view["track"])
        return HTMLResponse(submission_page(dataset=dataset_title, view=view))

    return app
