"""The ``--help`` of ``navverse`` and of every command and sub-command is the text recorded in
``tests/data/cli_help.txt``, and no command is lost or added unnoticed.

The texts are made by walking the argument parser (every sub-parsers action, depth first) with the
terminal width fixed at :data:`COLUMNS` columns, which argparse reads from ``$COLUMNS``; the
snapshot starts with the list of commands, then the help of each.

To record a change of the help on purpose, rewrite the snapshot and review its diff::

    NAVVERSE_UPDATE_SNAPSHOT=1 .venv/bin/python -m pytest tests/test_cli_help.py -q -n 0

(or ``.venv/bin/python -m tests.test_cli_help``, which calls :func:`write_snapshot`).
"""

from __future__ import annotations

import argparse
import difflib
import os
import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

from navverse.cli import build_parser

SNAPSHOT = Path(__file__).resolve().parent / "data" / "cli_help.txt"
UPDATE_ENV = "NAVVERSE_UPDATE_SNAPSHOT"
COLUMNS = 100
"""The terminal width the help is formatted for."""

NAVVERSE = str(Path(sys.executable).parent / "navverse")
HEADER = "=" * 20 + " "
"""Starts the line naming a command in the snapshot (no help text has such a line)."""


@contextmanager
def _columns(columns: int) -> Iterator[None]:
    """``$COLUMNS`` set to ``columns`` (the width argparse formats for), restored after."""
    before = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = str(columns)
    try:
        yield
    finally:
        if before is None:
            del os.environ["COLUMNS"]
        else:
            os.environ["COLUMNS"] = before


def _walk(parser: argparse.ArgumentParser, words: tuple[str, ...]) -> Iterator[tuple[str, str]]:
    """(command, help text) of ``parser`` and of every sub-command under it, depth first."""
    yield " ".join(words), parser.format_help()
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, child in action.choices.items():
                yield from _walk(child, (*words, name))


def help_texts(*, columns: int = COLUMNS) -> dict[str, str]:
    """The ``--help`` text of ``navverse`` and of each command, by command (``navverse export scenes``),
    in the order of the parser, formatted for ``columns`` columns."""
    with _columns(columns):
        return dict(_walk(build_parser(), ("navverse",)))


def render(texts: dict[str, str]) -> str:
    """The snapshot of ``texts``: the list of commands, then each command's help under a header."""
    parts = ["commands:\n", *(f"  {command}\n" for command in texts)]
    for command, text in texts.items():
        parts += ["\n", f"{HEADER}{command} --help\n", text]
    return "".join(parts)


def parse(snapshot: str) -> tuple[list[str], dict[str, str]]:
    """The command list and the help texts of a snapshot written by :func:`render`."""
    listing, _, body = snapshot.partition(f"\n{HEADER}")
    commands = [line.strip() for line in listing.splitlines()[1:] if line.strip()]
    texts = {}
    for block in f"{HEADER}{body}".split(f"\n{HEADER}"):
        title, _, text = block.removeprefix(HEADER).partition("\n")
        texts[title.removesuffix(" --help")] = text
    return commands, texts


def write_snapshot(path: Path = SNAPSHOT) -> Path:
    """Record the help of every command as the code has it now (review the diff before committing)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(render(help_texts()), encoding="utf-8")
    return path


def test_the_help_of_every_command_is_the_recorded_one() -> None:
    if os.environ.get(UPDATE_ENV) == "1":
        pytest.skip(f"{UPDATE_ENV}=1: wrote {write_snapshot()}")
    assert SNAPSHOT.is_file(), f"no {SNAPSHOT}: write it with {UPDATE_ENV}=1 (see this module's docstring)"
    assert SNAPSHOT.stat().st_size < 5_000_000
    commands, recorded = parse(SNAPSHOT.read_text(encoding="utf-8"))
    texts = help_texts()
    how = f"if the change is meant, rewrite the snapshot with {UPDATE_ENV}=1 (see {Path(__file__).name})"
    assert list(texts) == commands, (
        f"the commands differ from {SNAPSHOT.name}: lost {sorted(set(commands) - set(texts))}, "
        f"new {sorted(set(texts) - set(commands))} (or a new order); {how}"
    )
    differing = [command for command in commands if texts[command] != recorded.get(command)]
    diffs = [
        "".join(
            difflib.unified_diff(
                recorded.get(command, "").splitlines(keepends=True),
                texts[command].splitlines(keepends=True),
                fromfile=f"{command} --help (recorded)",
                tofile=f"{command} --help (now)",
            )
        )
        for command in differing
    ]
    assert not differing, f"the help of {', '.join(differing)} changed; {how}:\n" + "\n".join(diffs)


def test_the_snapshot_round_trips() -> None:
    texts = help_texts()
    assert parse(render(texts)) == (list(texts), texts)


def test_the_command_prints_the_help_the_parser_formats() -> None:
    env = {**os.environ, "COLUMNS": str(COLUMNS)}
    texts = help_texts()
    for command in ("navverse", "navverse export scenes"):
        words = command.split()[1:]
        result = subprocess.run(
            [NAVVERSE, *words, "--help"], capture_output=True, text=True, env=env, timeout=120
        )
        assert result.returncode == 0, result.stderr
        assert result.stdout == texts[command]


if __name__ == "__main__":
    print(f"wrote {write_snapshot()}")
