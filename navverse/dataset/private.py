"""Private splits: a test split whose goals only the scorer knows.

A split named in :data:`PRIVATE_SPLITS` is published in two parts:

- its public episode files ``<split>/<task>.json.gz`` in the version directory, with what an agent
  may know of each episode (scene, start, task, category, instruction texts): :func:`withhold` takes
  out the goals, the reference path, ``info`` (path lengths, difficulty, the verification) and the
  landmarks and directive times of its instructions; no rollouts file;
- its private file ``<split>.private.json.gz`` in a directory apart
  (``episodes/<name>/private/v<version>/``, never part of the published version): the full
  episodes and their verification rollouts by task (:class:`PrivateSplit`). The manifest records its
  SHA-256 only (``private`` {split: sha256}).

Scoring a private split needs its private file (``navverse eval --private DIR``, ``navverse serve
--private DIR``); running agents does not (``navverse run-agent`` runs the public episodes).
"""

from __future__ import annotations

import os
from pathlib import Path

from pydantic import BaseModel, ValidationError

from navverse.records.errors import DatasetError, first_error
from navverse.records.files import describe, read_checked
from navverse.records.jsongz import parse_json
from navverse.records.schema import RECORD_CONFIG, Episode, EpisodeFile, Instruction, Task

__all__ = [
    "PRIVATE_SPLITS",
    "PrivateSplit",
    "private_dir",
    "private_file_name",
    "read_private",
    "withheld_problem",
    "withhold",
]

PRIVATE_SPLITS = ("test",)
"""Splits whose goals are kept private: packaging publishes their episodes withheld and writes the
full ones to their private file."""


def private_file_name(split: str) -> str:
    """The name of a private split's file: ``<split>.private.json.gz``."""
    return f"{split}.private.json.gz"


def private_dir(version_dir: str | os.PathLike[str]) -> Path:
    """Where the private files of a version ``<name>/v<version>`` are kept: ``<name>/private/v<version>``
    (beside the published versions, outside every one of them)."""
    version_dir = Path(version_dir)
    return version_dir.parent / "private" / version_dir.name


class PrivateSplit(BaseModel):
    """Content of ``<split>.private.json.gz``: a private split's full episodes and rollouts by task."""

    model_config = RECORD_CONFIG

    name: str
    version: str
    split: str
    files: dict[Task, EpisodeFile]
    """The episode files as a public split's would be (goals, reference paths, info)."""
    rollouts: dict[Task, dict[str, list[list[float]]]]
    """The verification rollouts by task and episode id (10 Hz ``[t, x, y, z, qx, qy, qz, qw]``)."""


def _public_instruction(instruction: Instruction) -> Instruction:
    """An instruction's text, type and template, without its landmarks or directive times."""
    return instruction.model_copy(update={"landmarks": [], "directive_times": []})


def withhold(episode: Episode) -> Episode:
    """The public record of an episode of a private split: without goals, reference path, ``info``,
    and its instructions without landmarks or directive times."""
    return episode.model_copy(
        update={
            "goals": [],
            "reference_path": [],
            "info": None,
            "instruction": None if episode.instruction is None else _public_instruction(episode.instruction),
            "instructions": {k: _public_instruction(v) for k, v in episode.instructions.items()},
        }
    )


def withheld_problem(episode: Episode) -> str | None:
    """What the public record of a private split's episode gives away, or None when it is withheld."""
    shown = [
        name
        for name, given in (
            ("goals", bool(episode.goals)),
            ("reference_path", bool(episode.reference_path)),
            ("info", episode.info is not None),
            (
                "instruction landmarks or directive times",
                any(
                    i.landmarks or i.directive_times
                    for i in [episode.instruction, *episode.instructions.values()]
                    if i is not None
                ),
            ),
        )
        if given
    ]
    return f"gives away its {', '.join(shown)}" if shown else None


def read_private(
    directory: str | os.PathLike[str], *, split: str, sha256: str, name: str, version: str
) -> PrivateSplit:
    """Read a private split's file from `directory` after its checksum matched the manifest's.

    Parameters
    ----------
    directory : path
        The directory holding ``<split>.private.json.gz`` (or that file itself).
    split, name, version : str
        The split, and the dataset name and version it must belong to.
    sha256 : str
        Its SHA-256 as the manifest records it.

    Raises
    ------
    DatasetError
        If the file is missing, not the one the manifest records, malformed or of another dataset.
    """
    path = Path(directory)
    if path.is_dir() or not path.name.endswith(".private.json.gz"):
        path = path / private_file_name(split)
    problem, data = read_checked(path, sha256, keep=True)
    if problem is not None:
        raise DatasetError(
            f"{path}: {describe({problem: [path.name]})}: it must be the private file of split {split!r} "
            f"of {name} v{version}, as built (episodes/{name}/private/v{version}/)"
        )
    try:
        content = PrivateSplit.model_validate(parse_json(data, path))
    except ValidationError as exc:
        raise DatasetError(f"{path} is malformed: {first_error(exc)}") from None
    if (content.name, content.version, content.split) != (name, version, split):
        raise DatasetError(
            f"{path} is the private file of split {content.split!r} of {content.name} v{content.version}, "
            f"not of split {split!r} of {name} v{version}"
        )
    return content
