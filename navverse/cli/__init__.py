"""The ``navverse`` command. The composition root: with :mod:`navverse.cli.build`, the only navverse
modules that import ``pipeline`` and ``stages``.

:func:`build_parser` assembles the parser from :data:`COMMANDS`, the command modules in the order of
``navverse --help``: each declares its commands' arguments beside their handlers and adds them with
``register(subparsers, shared)`` (:class:`~navverse.cli.common.Shared`: the option parents and the
build store, :func:`~navverse.cli.build.workspace_built_dir`, which the data commands are handed so
they never import the engine). :func:`main` runs the chosen command's ``func``.
"""

from __future__ import annotations

import argparse
import errno
import signal
from collections.abc import Sequence
from types import ModuleType

from rich.console import Console

from navverse.cli import build, evaluate, export, listing, show, validate
from navverse.cli.common import (
    MINI,
    HelpFormatter,
    Shared,
    VersionAction,
    examples_epilog,
    recipe_options,
    scene_options,
)
from navverse.errors import NavverseError
from navverse.review import cli as review
from pipeline.errors import PipelineError

__all__ = ["COMMANDS", "build_parser", "main"]

COMMANDS: tuple[ModuleType, ...] = (build, validate, evaluate, show, export, review, listing)
"""The command modules, in the order their commands are listed by ``navverse --help``."""


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every sub-command."""
    parser = argparse.ArgumentParser(
        prog="navverse",
        description="Build navigation scenes and episode datasets from recipes, and evaluate agents.",
        epilog=examples_epilog(
            "navverse build office-s1",
            f"navverse run-agent --dataset {MINI} --agent oracle --out run.jsonl",
            f"navverse eval --dataset {MINI} --submission run.jsonl",
        ),
        formatter_class=HelpFormatter,
    )
    parser.add_argument(
        "--version",
        action=VersionAction,
        help="print the version and the dataset and scene formats, and exit",
    )
    sub = parser.add_subparsers(
        dest="command", required=True, metavar="COMMAND", help="what to do (navverse COMMAND --help)"
    )
    shared = Shared(
        recipe_options=recipe_options(), scene_options=scene_options(), built_dir=build.workspace_built_dir
    )
    for module in COMMANDS:
        module.register(sub, shared)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``navverse`` command; returns the exit code.

    Exit codes: 0 success; 1 an error (a message, never a traceback; for ``build`` a failed stage,
    for ``status`` a corrupt artifact); 2 bad arguments; 130 interrupted by Ctrl-C (SIGINT), 143
    by SIGTERM (a build ends its workers first and says how many stage runs are left).
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    console = Console(stderr=False)
    errors = Console(stderr=True, highlight=False, soft_wrap=True)
    from pipeline.params import allow_reading

    try:
        with allow_reading(args.allow_read if "allow_read" in args else ()):
            return int(args.func(args, console))
    except (NavverseError, PipelineError) as exc:
        errors.print(f"error: {exc}", style="red", markup=False)
        return 1
    except KeyboardInterrupt as exc:  # a build's BuildInterrupted says how many stage runs are left
        errors.print(str(exc) if hasattr(exc, "unfinished") else "interrupted", markup=False)
        return 128 + int(getattr(exc, "signum", signal.SIGINT))
    except OSError as exc:
        if exc.errno not in (errno.ENOSPC, errno.EDQUOT):
            raise
        where = exc.filename or "the workspace"
        errors.print(
            f"error: no space left on device while writing {where}; free space and run the same "
            "command to resume",
            style="red",
            markup=False,
        )
        return 1
