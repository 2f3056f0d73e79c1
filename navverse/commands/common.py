"""What the command modules of ``navverse`` share when they add their parsers.

The help formatter and the helper that adds a sub-command with its examples (:func:`command`), the
option parents every command that loads recipes or reads a dataset's scenes takes
(:func:`recipe_options`, :func:`scene_options`), the help texts several commands repeat, the
``validate`` group that the build commands and the data commands both add to, ``--version``, and
:class:`Shared`, what :func:`navverse.cli.build_parser` hands each command module's ``register``.
Nothing here imports the build engine.
"""

from __future__ import annotations

import argparse
import os
import sys
import textwrap
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeAlias

__all__ = [
    "DATASET_HELP",
    "DATASET_VERSION_HELP",
    "JOBS_HELP",
    "MINI",
    "OUTDOOR",
    "SCENES_HELP",
    "HelpFormatter",
    "Shared",
    "Subparsers",
    "VersionAction",
    "command",
    "console",
    "console_table",
    "examples_epilog",
    "existing_path",
    "recipe_options",
    "scene_options",
    "validate_commands",
    "version_text",
]

Subparsers: TypeAlias = "argparse._SubParsersAction[argparse.ArgumentParser]"

PIPE_WIDTH = 100_000
"""Columns of a console writing to a pipe or a file: lines and tables are never wrapped or cut there."""


def console(*, stderr: bool = False, **options: Any):
    """A rich console on stdout (or stderr): a terminal's own width, but wide without limit when the
    stream is a pipe or a file (rich would assume 80 columns and wrap or cut tables) unless
    ``COLUMNS`` says otherwise. ``options`` go to :class:`rich.console.Console`."""
    from rich.console import Console

    stream = sys.stderr if stderr else sys.stdout
    piped = not (hasattr(stream, "isatty") and stream.isatty()) and not os.environ.get("COLUMNS")
    return Console(stderr=stderr, width=PIPE_WIDTH if piped else None, **options)


def console_table(console, **options: Any):
    """A rich table for ``console``: boxed at a terminal; a Markdown table (title on the left) in a pipe
    or a file, for logs, grep and pasting. ``options`` go to :class:`rich.table.Table`."""
    from rich import box
    from rich.table import Table

    if not console.is_terminal:
        options = {**options, "box": box.MARKDOWN, "title_justify": "left"}
    return Table(**options)


"""The sub-parsers action of a parser (``parser.add_subparsers()``), to which commands are added."""

MINI = "episodes/navverse-mini/v2.2"
"""The default dataset (``make episodes``), in the examples of ``--help``."""

OUTDOOR = "episodes/navverse-outdoor/v1.1"
"""The outdoor dataset (``navverse build navverse-outdoor``), in the examples of ``--help``."""

DATASET_HELP = "a dataset version, episodes/<name>/v<version> (or episodes/<name>: the newest)"
DATASET_VERSION_HELP = "a dataset version, episodes/<name>/v<version>"
JOBS_HELP = "processes (default: the number of cores; 0 runs in this process)"

SCENES_HELP = (
    "look for the dataset's scenes in DIR first (repeatable; searched in the order given): a scene pack "
    "written by `navverse export scenes` (DIR/<scene_id>/) or a build store (DIR/targets/<scene_id>/scene). "
    "Then in $NAVVERSE_SCENES (directories separated by '{sep}', the same two layouts), then in this "
    "workspace's data/built. A scene whose scene hash differs from the dataset manifest's is passed over "
    "(one rebuilt in this workspace since the dataset was packaged is used, with a warning, when no place "
    "has the dataset's)"
)


@dataclass
class Shared:
    """What every command module's ``register(subparsers, shared)`` is handed.

    Parameters
    ----------
    recipe_options : argparse.ArgumentParser
        The parent of the commands that load recipes (:func:`recipe_options`).
    scene_options : argparse.ArgumentParser
        The parent of the commands that read a dataset's scenes (:func:`scene_options`).
    built_dir : callable
        Returns the workspace's build store (``data/built``); given to the commands that need built
        scenes, which call it only once a scene is needed.
    groups : dict
        The sub-parsers of the command groups that several modules add to, by group name (filled by
        :func:`validate_commands`).
    """

    recipe_options: argparse.ArgumentParser
    scene_options: argparse.ArgumentParser
    built_dir: Callable[[], Path]
    groups: dict[str, Subparsers] = field(default_factory=dict)


class HelpFormatter(argparse.HelpFormatter):
    """Help that fills the paragraphs of descriptions and epilogs but keeps indented lines (the examples)
    as they are written."""

    def _fill_text(self, text: str, width: int, indent: str) -> str:
        lines: list[str] = []
        paragraph: list[str] = []

        def flush() -> None:
            if paragraph:
                filled = textwrap.fill(
                    " ".join(paragraph), width, initial_indent=indent, subsequent_indent=indent
                )
                lines.append(filled)
                paragraph.clear()

        for line in text.strip("\n").splitlines():
            if line.strip() and not line[0].isspace():
                paragraph.append(line.strip())
                continue
            flush()
            lines.append(indent + line.rstrip() if line.strip() else "")
        flush()
        return "\n".join(lines)


def examples_epilog(*commands: str) -> str:
    """An epilog listing example commands, kept as written by :class:`HelpFormatter`: a command given as
    several lines (each but the last ending in `` \\``) has its later lines indented further."""
    lines = []
    for text in commands:
        first, *rest = text.split("\n")
        lines += [f"  {first}", *(f"      {line}" for line in rest)]
    return "examples:\n" + "\n".join(lines)


def command(
    sub: Subparsers,
    name: str,
    *,
    summary: str,
    examples: Sequence[str],
    description: str | None = None,
    **kwargs: Any,
) -> argparse.ArgumentParser:
    """Add sub-command ``name``: ``summary`` in its parent's list (and as its description unless one is
    given), ``examples`` after its options."""
    return sub.add_parser(
        name,
        help=summary,
        description=description or summary[0].upper() + summary[1:] + ".",
        epilog=examples_epilog(*examples),
        formatter_class=HelpFormatter,
        **kwargs,
    )


def validate_commands(sub: Subparsers, shared: Shared) -> Subparsers:
    """The sub-parsers of ``navverse validate WHAT``, the group being added to ``sub`` by the first call
    (the build commands add ``recipe``, the data commands ``dataset`` and ``submission``)."""
    if "validate" not in shared.groups:
        validate = command(
            sub, "validate", summary="check input files without building",
            examples=("navverse validate recipe recipes/scenes/indoor/office.yaml",
                      f"navverse validate dataset {OUTDOOR} --replay 5",
                      f"navverse validate submission run.jsonl --dataset {MINI}"),
        )  # fmt: skip
        shared.groups["validate"] = validate.add_subparsers(
            dest="what", required=True, metavar="WHAT", help="what to check (navverse validate WHAT --help)"
        )
    return shared.groups["validate"]


def existing_path(value: str) -> Path:
    """An argument naming a folder or file that exists (an argparse ``type``)."""
    path = Path(value).expanduser()
    if not path.exists():
        raise argparse.ArgumentTypeError(f"no such folder or file: {value}")
    return path


def _directory_option(flag: str, *, help_text: str) -> argparse.ArgumentParser:
    """An option parent with one repeatable option ``flag DIR`` naming a folder (or file) that exists."""
    options = argparse.ArgumentParser(add_help=False)
    options.add_argument(flag, action="append", default=[], type=existing_path, metavar="DIR", help=help_text)
    return options


def recipe_options() -> argparse.ArgumentParser:
    """Options of the commands that load recipes: the allow-list of the file-access policy."""
    return _directory_option(
        "--allow-read",
        help_text="let recipes read files in DIR too (repeatable; as $NAVVERSE_ALLOW_READ); by default they "
        "read only files inside the project and installed packages' data",
    )


def scene_options() -> argparse.ArgumentParser:
    """Options of the commands that read a dataset's scenes: where to look for them."""
    return _directory_option("--scenes", help_text=SCENES_HELP.format(sep=os.pathsep))


def version_text() -> str:
    """What ``navverse --version`` prints: the toolkit's version and the file formats it reads and writes."""
    from navverse import __version__
    from navverse.dataset import FORMAT_VERSION, PUBLIC_FORMAT_VERSION
    from navverse.scene.annotations import SCENE_FORMAT_VERSION

    dataset_major = FORMAT_VERSION.split(".")[0]
    scene_major = SCENE_FORMAT_VERSION.split(".")[0]
    return (
        f"navverse {__version__}\n"
        f"dataset format {FORMAT_VERSION} (writes {PUBLIC_FORMAT_VERSION}, {FORMAT_VERSION} with a private "
        f"split; reads {dataset_major}.0 up to {FORMAT_VERSION})\n"
        f"scene format {SCENE_FORMAT_VERSION} (writes {SCENE_FORMAT_VERSION}; reads 1.x, upgraded, and "
        f"{scene_major}.x)"
    )


class VersionAction(argparse.Action):
    """``--version``: print :func:`version_text` on stdout and exit 0."""

    def __init__(self, option_strings: Sequence[str], dest: str = argparse.SUPPRESS, **kwargs: Any) -> None:
        super().__init__(option_strings, dest=dest, default=argparse.SUPPRESS, nargs=0, **kwargs)

    def __call__(self, parser, namespace, values, option_string=None) -> None:
        sys.stdout.write(version_text() + "\n")
        parser.exit()
