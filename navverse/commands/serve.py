"""``navverse serve``: the benchmark's evaluation server, and ``navverse serve token add | revoke | list``,
the teams' tokens in its database. Each beside its parser; FastAPI and uvicorn (the ``serve`` extra)
are imported only when the server runs, so ``--help`` and the token commands work without them."""

from __future__ import annotations

import argparse
import logging
import sys
from collections.abc import Callable
from functools import partial
from pathlib import Path

from rich.console import Console

from navverse.commands.common import (
    DATASET_VERSION_HELP,
    MINI,
    Shared,
    Subparsers,
    command,
    console_table,
)
from navverse.commands.common import console as terminal_console

__all__ = ["cmd_serve", "cmd_token_add", "cmd_token_list", "cmd_token_revoke", "register"]

_INSTALL = "pip install 'navverse[serve]' (in a checkout: .venv/bin/pip install -e '.[serve]')"
_DB_HELP = "the server's SQLite database (teams, tokens, submissions, results)"


def _private_of(version: str) -> str:
    """Where a dataset version's private files are built: ``<name>/private/v<version>`` beside it."""
    head, _, tail = version.rpartition("/")
    return f"{head}/private/{tail}"


def register(sub: Subparsers, shared: Shared) -> None:
    """Add ``navverse serve`` and its ``token`` commands to ``sub``."""
    from navverse.serve.settings import ServeSettings

    defaults = ServeSettings()
    serve = command(
        sub, "serve", parents=[shared.scene_options],
        summary="run the benchmark's evaluation server: submissions over HTTP, scored, on a leaderboard",
        description=(
            "Serve a dataset version's benchmark over HTTP: teams POST their submissions with their token "
            "(navverse serve token add TEAM), the server checks each against its split at once (any problem "
            "refuses it, with the problems), scores it in worker processes with the evaluator's own code and "
            "publishes its group means (never a per-episode value) to its team, and, when public, on the "
            "leaderboard at /. A private split (test) is scored with its goals from --private, which never "
            "leave the scoring processes. The server speaks plain HTTP: beyond this machine, put it behind "
            "a TLS reverse proxy (README: An evaluation server)."
        ),
        usage="navverse serve --dataset DATASET --db FILE [options]\n"
        "       navverse serve token {add,revoke,list} ...",
        examples=(f"navverse serve --dataset {MINI} --private {_private_of(MINI)} \\\n"
                  "--db serve/navverse.db --port 8000",
                  "navverse serve token add my-team --db serve/navverse.db",
                  "navverse serve token list --db serve/navverse.db"),
    )  # fmt: skip
    serve.add_argument("--dataset", default=None, help=DATASET_VERSION_HELP + " (required to serve)")
    serve.add_argument(
        "--private", metavar="DIR", default=None,
        help="the directory of the dataset's private files (episodes/<name>/private/v<version>): the goals "
        "of its private split (test); without it only splits whose goals are public are scored",
    )  # fmt: skip
    serve.add_argument("--db", metavar="FILE", default=None, help=_DB_HELP + "; made if missing (required)")
    serve.add_argument(
        "--host", default="127.0.0.1",
        help="address to listen on (default: 127.0.0.1; another one is served in plain HTTP: put a TLS "
        "reverse proxy in front)",
    )  # fmt: skip
    serve.add_argument("--port", type=int, default=8000, help="port (default: 8000; 0: any free one)")
    serve.add_argument(
        "--store", metavar="DIR", default=None,
        help="where the accepted submission files are kept (default: <db>.submissions/ beside the database)",
    )  # fmt: skip
    serve.add_argument(
        "--workers", type=int, default=defaults.workers,
        help=f"scoring processes (default: {defaults.workers})",
    )  # fmt: skip
    serve.add_argument(
        "--rate-per-day", type=int, default=defaults.rate_per_day, metavar="N",
        help=f"submissions a team may have accepted in any 24 hours (default: {defaults.rate_per_day})",
    )  # fmt: skip
    serve.add_argument(
        "--max-body-mb", type=int, default=defaults.max_body_bytes // 2**20, metavar="N",
        help=f"largest submission file taken, in MiB as sent (default: {defaults.max_body_bytes // 2**20})",
    )  # fmt: skip
    serve.add_argument(
        "--lease", type=float, default=defaults.lease_seconds, metavar="SECONDS",
        help=f"how long a claim on a submission being scored holds without a heartbeat; then another server "
        f"(or this one restarted) takes it over (default: {defaults.lease_seconds:g})",
    )  # fmt: skip
    serve.add_argument(
        "--heartbeat", type=float, default=defaults.heartbeat_seconds, metavar="SECONDS",
        help="how often the leases are renewed, at most half the lease "
        f"(default: {defaults.heartbeat_seconds:g})",
    )  # fmt: skip
    serve.set_defaults(func=partial(cmd_serve, built_dir=shared.built_dir))
    groups = serve.add_subparsers(
        dest="serve_what", metavar="token", help="the teams' tokens (navverse serve token --help)"
    )
    token = command(
        groups, "token", summary="add, revoke or list the teams' tokens in the server's database",
        examples=("navverse serve token add my-team --db serve/navverse.db",
                  "navverse serve token revoke --id 3f9c0a1b --db serve/navverse.db",
                  "navverse serve token list --db serve/navverse.db"),
    )  # fmt: skip
    tokens = token.add_subparsers(
        dest="token_what", required=True, metavar="WHAT", help="add, revoke or list"
    )
    add = command(
        tokens, "add", summary="make a token for a team (the team is added if new) and print it, once",
        description="Make a token for TEAM and print it once: the database keeps only its SHA-256, so give "
        "it to the team now. A team may hold several tokens.",
        examples=("navverse serve token add my-team --db serve/navverse.db",),
    )  # fmt: skip
    add.add_argument("team", help="1-64 characters of letters, digits, '.', '_' and '-'")
    add.add_argument("--db", metavar="FILE", required=True, help=_DB_HELP + "; made if missing")
    add.set_defaults(func=cmd_token_add)
    revoke = command(
        tokens, "revoke", summary="revoke a team's tokens, or one token by its id",
        examples=("navverse serve token revoke my-team --db serve/navverse.db",
                  "navverse serve token revoke --id 3f9c0a1b --db serve/navverse.db"),
    )  # fmt: skip
    revoke.add_argument("team", nargs="?", default=None, help="revoke every valid token of this team")
    revoke.add_argument("--id", dest="token_id", default=None, help="revoke only the token with this id")
    revoke.add_argument("--db", metavar="FILE", required=True, help=_DB_HELP)
    revoke.set_defaults(func=cmd_token_revoke)
    listing = command(
        tokens, "list", summary="list the tokens: team, token id, created, revoked (never the token)",
        examples=("navverse serve token list --db serve/navverse.db",),
    )  # fmt: skip
    listing.add_argument("--db", metavar="FILE", required=True, help=_DB_HELP)
    listing.set_defaults(func=cmd_token_list)


def _settings(args: argparse.Namespace):
    """The server's settings from the command line, or a ServeError naming the option to change."""
    from pydantic import ValidationError

    from navverse.serve.errors import ServeError
    from navverse.serve.settings import MIB, ServeSettings

    flags = {"workers": "--workers", "rate_per_day": "--rate-per-day", "max_body_bytes": "--max-body-mb",
             "lease_seconds": "--lease", "heartbeat_seconds": "--heartbeat"}  # fmt: skip
    try:
        return ServeSettings(
            workers=args.workers,
            rate_per_day=args.rate_per_day,
            max_body_bytes=args.max_body_mb * MIB,
            lease_seconds=args.lease,
            heartbeat_seconds=args.heartbeat,
        )
    except ValidationError as exc:
        error = exc.errors()[0]
        field = str(error["loc"][0]) if error.get("loc") else ""
        message = str(error["msg"]).removeprefix("Value error, ")
        if field == "max_body_bytes":
            message = "give a whole number of MiB from 1 to 4096"
        raise ServeError(f"{flags.get(field, '--heartbeat and --lease')}: {message}") from None


def _log_to_stderr() -> None:
    """The server's log lines (and uvicorn's) on stderr, one format."""
    logging.basicConfig(
        level=logging.INFO, stream=sys.stderr, format="%(asctime)s %(levelname)s %(name)s: %(message)s"
    )


def cmd_serve(args: argparse.Namespace, console: Console, *, built_dir: Callable[[], Path]) -> int:
    """Run the evaluation server until Ctrl-C or SIGTERM."""
    from navverse.serve.errors import ServeError

    missing = [flag for flag, value in (("--dataset", args.dataset), ("--db", args.db)) if value is None]
    if missing:
        raise ServeError(
            f"give {' and '.join(missing)} to run the server (the token commands are `navverse serve token "
            "add | revoke | list`)"
        )
    try:
        import fastapi  # noqa: F401
        import uvicorn  # noqa: F401
    except ImportError as exc:
        raise ServeError(
            f"the server needs FastAPI and uvicorn ({exc.name} is missing): {_INSTALL}"
        ) from None
    from navverse.serve.benchmark import open_benchmark
    from navverse.serve.db import open_db
    from navverse.serve.server import LOCAL_HOSTS, run_server

    settings = _settings(args)
    open_db(args.db).close()  # before the dataset is read: a database that cannot be used fails at once
    warn = terminal_console(stderr=True)
    if args.host not in LOCAL_HOSTS:
        warn.print(
            f"warning: listening on {args.host}: the server speaks plain HTTP (tokens and submissions in "
            "clear); serve it beyond this machine only behind a TLS reverse proxy (README: An evaluation "
            "server)",
            style="yellow", highlight=False, markup=False, soft_wrap=True,
        )  # fmt: skip
    benchmark = open_benchmark(
        args.dataset, private=args.private, scenes=args.scenes or (), built_dir=built_dir
    )
    scored = sorted(s for s, info in benchmark.splits.items() if info.scoreable)
    withheld = sorted(s for s, info in benchmark.splits.items() if not info.scoreable)
    unscored = f"; not scored (private goals, no --private): {', '.join(withheld)}" if withheld else ""
    console.print(
        f"{benchmark.name} v{benchmark.version}: scoring split {', '.join(scored)}{unscored}",
        highlight=False, markup=False, soft_wrap=True,
    )  # fmt: skip

    def ready(url: str, instance: str) -> None:
        console.print(
            f"serving on {url} (instance {instance}); Ctrl-C to stop",
            highlight=False,
            markup=False,
            soft_wrap=True,
        )
        sys.stdout.flush()

    _log_to_stderr()
    run_server(
        benchmark, db_path=args.db, store=args.store, settings=settings, host=args.host, port=args.port,
        on_ready=ready,
    )  # fmt: skip
    console.print("stopped", highlight=False)
    return 0


def cmd_token_add(args: argparse.Namespace, console: Console) -> int:
    """Make a token for a team and print it once."""
    from navverse.serve.db import open_db
    from navverse.serve.teams import add_token, check_team_name

    check_team_name(args.team)
    con = open_db(args.db, create=True)
    try:
        token_id, token = add_token(con, args.team)
    finally:
        con.close()
    console.print(
        f"token {token_id} of team {args.team}; it is shown only now (the database keeps its hash), give it "
        "to the team:",
        highlight=False, markup=False, soft_wrap=True,
    )  # fmt: skip
    console.print(token, highlight=False, markup=False, soft_wrap=True)
    return 0


def cmd_token_revoke(args: argparse.Namespace, console: Console) -> int:
    """Revoke a team's tokens, or one token by its id."""
    from navverse.serve.db import open_db
    from navverse.serve.teams import revoke_tokens

    con = open_db(args.db, create=False)
    try:
        ids = revoke_tokens(con, team=args.team, token_id=args.token_id)
    finally:
        con.close()
    whose = f" of team {args.team}" if args.team is not None else ""
    console.print(f"revoked {len(ids)} token(s){whose}: {', '.join(ids)}", highlight=False, markup=False)
    return 0


def cmd_token_list(args: argparse.Namespace, console: Console) -> int:
    """List the tokens: team, id, created, revoked (never the token itself)."""
    from navverse.serve.db import open_db
    from navverse.serve.leaderboard import iso_time
    from navverse.serve.teams import list_tokens

    con = open_db(args.db, create=False)
    try:
        tokens = list_tokens(con)
    finally:
        con.close()
    table = console_table(console, title=f"tokens in {args.db}")
    for column in ("team", "token id", "created", "revoked"):
        table.add_column(column)
    for info in tokens:
        table.add_row(info.team, info.id, iso_time(info.created) or "", iso_time(info.revoked) or "–")
    console.print(table)
    if not tokens:
        console.print("no token yet: navverse serve token add TEAM --db ...", highlight=False, markup=False)
    return 0
