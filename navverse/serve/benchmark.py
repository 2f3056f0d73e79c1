"""The dataset as the server holds it: per split its public episodes, their ids, scenes and bounds.

The server process keeps the *public* records only (:class:`SplitInfo`): what a submission is checked
against at intake (episode ids, the tasks for the instruction type, positions within the scenes'
bounds). The goals of a private split are read by the scoring processes alone, from the private
directory (``--private``); :func:`open_benchmark` checks that directory once at start.

Submissions are taken for every split of the dataset but ``train`` (the one agents learn from); a
private split is scoreable only when the server was given its private file.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from navverse.serve.errors import RefusedError, ServeError

if TYPE_CHECKING:
    from navverse.dataset import Dataset, Episode
    from navverse.eval.submission import Box

__all__ = ["NOT_SUBMITTED", "Benchmark", "SplitInfo", "open_benchmark", "open_dataset"]

NOT_SUBMITTED = frozenset({"train"})
"""Splits that take no submission."""


@dataclass(frozen=True, eq=False)
class SplitInfo:
    """One split that takes submissions.

    Attributes
    ----------
    name : str
    private : bool
        Whether its goals are kept in a private file.
    scoreable : bool
        Whether this server has its goals (a public split, or a private one with ``--private``).
    episodes : tuple of Episode
        Its public records (of a private split: without goals, reference path or info).
    episode_ids : frozenset of str
    scene_dirs : mapping
        Scene directory by scene id (empty when not scoreable).
    bounds : mapping
        Where each episode's positions may be (:func:`navverse.eval.submission.episode_bounds`;
        empty when not scoreable).
    """

    name: str
    private: bool
    scoreable: bool
    episodes: tuple[Episode, ...]
    episode_ids: frozenset[str]
    scene_dirs: Mapping[str, Path]
    bounds: Mapping[str, Box]


@dataclass(frozen=True, eq=False)
class Benchmark:
    """The dataset version the server scores against.

    Attributes
    ----------
    root : Path
        The dataset version directory.
    private_dir : Path or None
        The directory of its private files (``--private``).
    name, version, embodiment : str
        From its manifest.
    splits : mapping
        :class:`SplitInfo` by split name.
    """

    root: Path
    private_dir: Path | None
    name: str
    version: str
    embodiment: str
    splits: Mapping[str, SplitInfo]

    @property
    def default_split(self) -> str:
        """The split the leaderboard shows unless asked: ``test`` when there is one, else the first."""
        return "test" if "test" in self.splits else sorted(self.splits)[0]

    def split(self, name: str) -> SplitInfo:
        """The split named in a request.

        Raises
        ------
        RefusedError
            422 naming the splits there are.
        """
        info = self.splits.get(name)
        if info is None:
            shown = name if len(name) <= 40 else name[:40] + "..."
            raise RefusedError(
                422,
                f"split {shown!r} takes no submission here; give split= one of: "
                f"{', '.join(sorted(self.splits))}",
            )
        return info

    def scoreable(self, name: str) -> SplitInfo:
        """The split named in a submission, if this server can score it.

        Raises
        ------
        RefusedError
            422: an unknown split, or a private split whose goals this server was not given.
        """
        info = self.split(name)
        if not info.scoreable:
            others = ", ".join(sorted(s for s, i in self.splits.items() if i.scoreable)) or "none"
            raise RefusedError(
                422,
                f"this server has no private goals for split {name!r} (it was started without its private "
                f"file), so it cannot score it; submit to a split it scores ({others}) or ask the "
                "benchmark's operators",
            )
        return info


def open_dataset(root: str | os.PathLike[str], *, private: str | os.PathLike[str] | None = None) -> Dataset:
    """The dataset version at `root`, verified; with its private files from `private` when given.

    Raises
    ------
    DatasetError
        If `private` is given but the dataset has no private split, or the version (or its private
        files) does not match its manifest.
    """
    from navverse.dataset import Dataset

    dataset = Dataset(root, private=private)
    dataset.verify()
    return dataset


def open_benchmark(
    root: str | os.PathLike[str],
    *,
    private: str | os.PathLike[str] | None = None,
    scenes: Sequence[str | os.PathLike[str]] = (),
    built_dir: str | os.PathLike[str] | Callable[[], Path] | None = None,
) -> Benchmark:
    """Open the dataset the server scores against and find the scenes of the splits it can score.

    Parameters
    ----------
    root : path
        The dataset version.
    private : path, optional
        The directory of its private files (the goals of its private splits).
    scenes : sequence of path
        Scene packs or build stores searched first (``--scenes``), then ``$NAVVERSE_SCENES``.
    built_dir : path or callable, optional
        A workspace's build store, searched last.

    Raises
    ------
    ServeError
        If the dataset has no split that takes submissions, or `private` cannot be used.
    NavverseError
        If the dataset does not verify, or a scene of a scoreable split is not found.
    """
    from navverse.dataset import Dataset
    from navverse.eval.submission import episode_bounds

    verified = open_dataset(root, private=private)
    public = Dataset(verified.root) if private is not None else verified  # no goal kept in this process
    private_splits = public.private_splits
    splits = {}
    for name in public.splits:
        if name in NOT_SUBMITTED:
            continue
        episodes = tuple(public.episodes(split=name))
        scoreable = name not in private_splits or private is not None
        scene_dirs = public.scene_dirs(episodes, search=scenes, built_dir=built_dir) if scoreable else {}
        splits[name] = SplitInfo(
            name=name,
            private=name in private_splits,
            scoreable=scoreable,
            episodes=episodes,
            episode_ids=frozenset(e.episode_id for e in episodes),
            scene_dirs=scene_dirs,
            bounds=episode_bounds(episodes, scene_dirs) if scoreable else {},
        )
    if not splits:
        raise ServeError(
            f"{public.root} has no split that takes submissions (it has: {', '.join(public.splits)}; "
            f"{', '.join(sorted(NOT_SUBMITTED))} takes none)"
        )
    manifest = public.manifest
    return Benchmark(
        root=Path(public.root).resolve(),
        private_dir=None if private is None else Path(private).resolve(),
        name=manifest.name,
        version=manifest.version,
        embodiment=manifest.embodiment,
        splits=splits,
    )
