"""What the data commands share: a dataset's scenes along the search path, its splits, and the problems
of a submission.

The data commands read datasets, submissions and built scenes, never the build engine: those that need
built scenes are handed a ``built_dir`` callable returning the build store (``data/built``), called only
once a scene is needed, so the others run anywhere. A dataset's scenes are looked for along the search
path of :func:`navverse.scene.locate.find_scene_dirs`: ``--scenes DIR`` (``args.scenes``),
``$NAVVERSE_SCENES``, then that build store.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path

from rich.console import Console

from navverse.commands.common import console as terminal_console

__all__ = ["dataset_scene_dirs", "print_problems", "problem_count", "split_of"]


def _warn(text: str) -> None:
    """Print a warning on stderr."""
    terminal_console(stderr=True).print(
        f"warning: {text}", style="yellow", highlight=False, markup=False, soft_wrap=True
    )


def dataset_scene_dirs(
    args: argparse.Namespace, dataset, scenes, built_dir: Callable[[], Path] | None
) -> dict[str, Path]:
    """The directories of the dataset's scenes ``scenes`` (episodes or ids), along the search path:
    ``--scenes``, ``$NAVVERSE_SCENES``, the workspace's build store. A scene must have the manifest's
    scene hash, but for one rebuilt in this workspace's store since the dataset was packaged: it is used
    with a warning, as before scenes could come from elsewhere."""
    from navverse.scene.locate import find_scene_dirs

    return find_scene_dirs(
        scenes,
        search=getattr(args, "scenes", None) or (),
        hashes=dataset.manifest.scene_hashes,
        built_dir=built_dir,
        rebuilt="warn",
        warn=_warn,
    )


def split_of(dataset, split: str) -> list[str]:
    """The episode ids of a split, or a DatasetError naming the splits there are."""
    from navverse.dataset import DatasetError

    if split not in dataset.splits:
        raise DatasetError(f"{dataset.root} has no split {split!r}; it has: {', '.join(dataset.splits)}")
    return [e.episode_id for e in dataset.episodes(split=split)]


def problem_count(submission) -> int:
    """How many problems a submission has: those listed and those left out of the list."""
    return len(submission.problems) + submission.omitted


def print_problems(submission, console: Console) -> None:
    """Print each listed problem of a submission on a line, then how many more there are."""
    for problem in submission.problems:
        console.print(str(problem), highlight=False, markup=False)
    if submission.omitted:
        console.print(f"... and {submission.omitted} more problems", highlight=False, markup=False)
