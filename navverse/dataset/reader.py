"""The reader API: :class:`Dataset`, one version of a dataset read from its directory, and its
verification against the manifest.

Opening a version reads its manifest (:func:`~navverse.dataset.manifest.read_manifest`).
:meth:`Dataset.verify` checks the version against it before it is used (the listing, regular files
only, checksums, the episode counts); an episode or rollouts file is decompressed only once its
checksum matched, and never beyond :data:`~navverse.records.files.MAX_FILE_BYTES`.
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable, Iterable, Iterator, Sequence
from pathlib import Path
from typing import Any

from pydantic import ValidationError

from navverse.dataset.manifest import read_manifest
from navverse.dataset.private import PrivateSplit, private_file_name, read_private, withheld_problem, withhold
from navverse.records.errors import REMEDY, DatasetError, first_error
from navverse.records.files import MAX_ENTRIES, describe, listing, member_state, read_checked
from navverse.records.jsongz import parse_json
from navverse.records.schema import TASKS, Episode, EpisodeFile

__all__ = ["Dataset"]


class Dataset:
    """One version of a dataset, read from its directory.

    Opening a version reads and validates its manifest only. Call :meth:`verify` before using the
    dataset for anything that counts (scoring, running agents): it checks every file against the
    manifest. Whatever the reader decompresses it checks against the manifest's checksum first.

    Parameters
    ----------
    root : path
        ``episodes/<name>/v<version>`` (or ``episodes/<name>``: its newest version).
    private : path, optional
        The directory of the version's private files (``episodes/<name>/private/v<version>``), for
        the goals of its private splits (:mod:`navverse.dataset.private`). Without it, the episodes of
        a private split are their public records (no goals, reference path or ``info``).

    Attributes
    ----------
    root : Path
        The version directory.
    manifest : DatasetManifest
        Its manifest.
    manifest_sha256 : str
        The SHA-256 of the manifest's bytes, to compare with a published value (the manifest holds
        every other file's checksum).

    Raises
    ------
    DatasetError
        If there is no manifest, it is malformed, its format version is not readable here, or
        `private` is given for a version without a private split.
    """

    def __init__(
        self, root: str | os.PathLike[str], *, private: str | os.PathLike[str] | None = None
    ) -> None:
        root = Path(root)
        if not (root / "manifest.json").is_file() and root.is_dir():
            versions = sorted(
                (p for p in root.glob("v*") if (p / "manifest.json").is_file()),
                key=lambda p: tuple(int(x) if x.isdigit() else 0 for x in p.name[1:].split(".")),
            )
            if versions:
                root = versions[-1]
        manifest_path = root / "manifest.json"
        if not manifest_path.is_file():
            raise DatasetError(_not_a_version(root))
        self.manifest, self.manifest_sha256 = read_manifest(manifest_path)
        if private is not None and not self.manifest.private:
            raise DatasetError(
                f"--private {private}: {self.manifest.name} v{self.manifest.version} has no private split "
                "(its goals are all in the version); leave --private out"
            )
        self.root = root
        self._files: dict[tuple[str, str], EpisodeFile] = {}
        self._rollouts: dict[str, dict[str, Any]] = {}  # rollout files read, by name
        self.private_dir = None if private is None else Path(private)
        self._private: dict[str, PrivateSplit] = {}  # private files read, by split

    @property
    def private_splits(self) -> frozenset[str]:
        """The splits whose goals are kept in a private file (empty for most datasets)."""
        return frozenset(self.manifest.private)

    def has_goals(self, split: str) -> bool:
        """Whether the episodes of `split` come with their goals: a public split, or a private one whose
        private directory was given."""
        return split not in self.manifest.private or self.private_dir is not None

    def require_goals(self, split: str, *, what: str) -> None:
        """Raise a DatasetError saying how to give the private file when `what` needs the goals of a
        private split that came without them."""
        if not self.has_goals(split):
            raise DatasetError(
                f"split {split!r} of {self.manifest.name} v{self.manifest.version} keeps its goals private, "
                f"and {what} needs them: pass --private DIR, the directory holding its "
                f"{private_file_name(split)} (built beside the version as "
                f"episodes/{self.manifest.name}/private/v{self.manifest.version}/), or use another split"
            )

    @property
    def splits(self) -> list[str]:
        """Split names."""
        return sorted(self.manifest.splits)

    def tasks(self, split: str) -> list[str]:
        """Tasks that have an episode file in ``split`` (as the manifest lists them)."""
        return sorted(t for t in TASKS if f"{split}/{t}.json.gz" in self.manifest.files)

    def file(self, split: str, task: str) -> EpisodeFile:
        """The episode file of a split and task (read once, after its checksum matched); of a private
        split whose private directory was given, the private file's (with the goals).

        Raises
        ------
        DatasetError
            If the manifest lists no such file, or the file is not the one it lists.
        """
        if split in self.manifest.private and self.private_dir is not None:
            self._version_file(split, task)  # the task must be one of the split's
            return self._private_split(split).files[task]
        return self._version_file(split, task)

    def _version_file(self, split: str, task: str) -> EpisodeFile:
        """The episode file of a split and task as the version directory holds it."""
        key = (split, task)
        if key not in self._files:
            name = f"{split}/{task}.json.gz"
            if name not in self.manifest.files:
                have = ", ".join(f"{s}/{t}" for s in self.splits for t in self.tasks(s)) or "none"
                raise DatasetError(f"{self.root} has no {split}/{task} episodes (it has: {have})")
            try:
                self._files[key] = EpisodeFile.model_validate(self._load(name))
            except ValidationError as exc:
                raise DatasetError(f"{self.root / name} is malformed: {first_error(exc)}") from None
        return self._files[key]

    def episodes(
        self, *, split: str | None = None, task: str | None = None, scene_type: str | None = None
    ) -> Iterator[Episode]:
        """Episodes, optionally of one split, task and scene type, in file order."""
        for s in [split] if split is not None else self.splits:
            if s not in self.manifest.splits:
                raise DatasetError(f"{self.root} has no split {s!r} (splits: {', '.join(self.splits)})")
            for t in [task] if task is not None else self.tasks(s):
                if t not in self.tasks(s):
                    continue
                for episode in self.file(s, t).episodes:
                    if scene_type is None or episode.scene_type == scene_type:
                        yield episode

    def episode(self, episode_id: str) -> Episode:
        """The episode with this id.

        Raises
        ------
        DatasetError
            If no episode has it.
        """
        for episode in self.episodes():
            if episode.episode_id == episode_id:
                return episode
        raise DatasetError(f"{self.root} has no episode {episode_id!r}")

    def scene_dir(
        self,
        episode_or_scene_id: Episode | str,
        *,
        search: Sequence[str | os.PathLike[str]] = (),
        built_dir: str | os.PathLike[str] | None = None,
    ) -> Path:
        """The directory of an episode's scene (or a scene's), with the scene hash this dataset lists.

        Looked for, in order, in ``search``, in ``$NAVVERSE_SCENES`` and in ``built_dir``: scene packs
        (``DIR/<scene_id>/``, from ``navverse export scenes``) or build stores
        (``DIR/targets/<scene_id>/scene``); a directory whose scene hash differs from the manifest's
        ``scene_hashes`` is passed over (:func:`navverse.scene.locate.find_scene_dirs`).

        Parameters
        ----------
        episode_or_scene_id : Episode or str
            An episode of this dataset, or the id of one of its scenes.
        search : sequence of path
            Scene packs or build stores searched first, in order.
        built_dir : path, optional
            A workspace's build store (``data/built``), searched last.

        Returns
        -------
        Path
            The scene directory.

        Raises
        ------
        DatasetError
            If the scene is not one of this dataset's.
        SceneError
            If it is found nowhere, or only with another scene hash (each place and why, what to do).
        """
        scene_id = (
            episode_or_scene_id if isinstance(episode_or_scene_id, str) else episode_or_scene_id.scene_id
        )
        if not any(scene_id in scenes for scenes in self.manifest.splits.values()):
            raise DatasetError(f"{self.root} has no scene {scene_id!r} in any split")
        return self.scene_dirs([scene_id], search=search, built_dir=built_dir)[scene_id]

    def scene_dirs(
        self,
        scenes: Iterable[Episode | str],
        *,
        search: Sequence[str | os.PathLike[str]] = (),
        built_dir: str | os.PathLike[str] | Callable[[], Path] | None = None,
    ) -> dict[str, Path]:
        """The directories of the scenes of `scenes` (episodes or scene ids), each with the scene
        hash this dataset lists, looked for as :meth:`scene_dir` does.

        Parameters
        ----------
        scenes : iterable of Episode or str
            Episodes of this dataset (e.g. ``episodes(split="eval")``) or ids of its scenes.
        search : sequence of path
            Scene packs or build stores searched first, in order.
        built_dir : path or callable, optional
            A workspace's build store, searched last (a callable is called only when a scene is not
            found before it).

        Returns
        -------
        dict of str to Path
            The scene directory by scene id, in sorted order.

        Raises
        ------
        SceneError
            If a scene is found nowhere, or only with another scene hash.
        """
        from navverse.scene.locate import find_scene_dirs

        return find_scene_dirs(scenes, search=search, hashes=self.manifest.scene_hashes, built_dir=built_dir)

    def rollout(self, episode: Episode) -> list[list[float]] | None:
        """The verification rollout of an episode (10 Hz ``[t, x, y, z, qx, qy, qz, qw]`` rows), if kept.

        Each rollout file is checked and read once per :class:`Dataset`, on the first episode asked
        of it, and kept.
        """
        for split in self.splits:
            if split in self.manifest.private:
                if self.private_dir is not None and episode.scene_id in self.manifest.splits[split]:
                    rows = self._private_split(split).rollouts.get(episode.task, {}).get(episode.episode_id)
                    if rows is not None:
                        return rows
                continue
            name = f"{split}/{episode.task}.rollouts.json.gz"
            if name in self.manifest.files and episode.scene_id in self.manifest.splits[split]:
                rollouts = self._rollouts.get(name)
                if rollouts is None:  # read once per file, not once per episode
                    rollouts = self._load(name)
                    if not isinstance(rollouts, dict):
                        raise DatasetError(f"{self.root / name} is malformed: not an object of rollouts")
                    self._rollouts[name] = rollouts
                rows = rollouts.get(episode.episode_id)
                if rows is not None:
                    return rows
        return None

    def verify(self) -> None:
        """Check the version against its manifest; do this before using it for results.

        The manifest must list every file of the version directory and nothing else; each listed
        path is a regular file inside the directory (no symbolic link), at most
        :data:`~navverse.records.files.MAX_FILE_BYTES` compressed and decompressed, with the listed
        SHA-256; the episode files, read only once their checksum matched, hold the episodes
        ``counts`` says, of their split's scenes and their file's task, each id once. Nothing is
        cached across processes: it hashes the whole version (a few MB) each time.

        Raises
        ------
        DatasetError
            Naming the files that do not match and what to do (re-download or rebuild).
        """
        problems = self._file_problems()
        if problems:
            raise DatasetError(f"{self.root}: {describe(problems)}. {REMEDY}")
        self._check_contents()
        if self.private_dir is not None:
            for split in sorted(self.manifest.private):
                self._check_private(split)

    def verify_checksums(self) -> list[str]:
        """Files that are missing, unlisted, not regular files, too large or not as listed (sorted).

        :meth:`verify` checks this and the episode counts, and says what to do.
        """
        return sorted({name for names in self._file_problems().values() for name in names})

    # ------------------------------------------------------------------ integrity

    def _load(self, name: str) -> Any:
        """A listed ``.json.gz`` file's content, decompressed only once its checksum matched."""
        path = self.root / name
        problem = member_state(self.root, name)
        data = b""
        if problem is None:
            problem, data = read_checked(path, self.manifest.files[name], keep=True)
        if problem is not None:
            raise DatasetError(f"{self.root}: {describe({problem: [name]})}. {REMEDY}")
        return parse_json(data, path)

    def _private_split(self, split: str) -> PrivateSplit:
        """A private split's file, read once (after its checksum matched the manifest's)."""
        if split not in self._private:
            assert self.private_dir is not None
            self._private[split] = read_private(
                self.private_dir,
                split=split,
                sha256=self.manifest.private[split],
                name=self.manifest.name,
                version=self.manifest.version,
            )
        return self._private[split]

    def _check_private(self, split: str) -> None:
        """A private split's file against its public episode files: the same tasks and episodes, each
        public record its full episode withheld, and a rollout for every episode."""
        content = self._private_split(split)
        problems = []
        if sorted(content.files) != self.tasks(split):
            problems.append(f"it has the tasks {sorted(content.files)}, the version {self.tasks(split)}")
        for task in sorted(set(content.files) & set(self.tasks(split))):
            public = self._version_file(split, task).episodes
            full = content.files[task].episodes
            if [e.episode_id for e in full] != [e.episode_id for e in public]:
                problems.append(f"its {task} episodes are not those of {split}/{task}.json.gz")
                continue
            changed = [f.episode_id for f, p in zip(full, public, strict=True) if withhold(f) != p]
            if changed:
                problems.append(
                    f"{len(changed)} {task} episodes differ from their public record ({changed[0]}...)"
                )
            missing = [e.episode_id for e in full if e.episode_id not in content.rollouts.get(task, {})]
            if missing:
                problems.append(f"{len(missing)} {task} episodes have no rollout ({missing[0]}...)")
        if problems:
            raise DatasetError(
                f"{self.private_dir}: the private file of split {split!r} does not match {self.root}: "
                + "; ".join(problems)
                + f". Use the private files built with {self.manifest.name} v{self.manifest.version}"
            )

    def _file_problems(self) -> dict[str, list[str]]:
        """Problem kind -> files, over the listing and every listed file (empty: all sound)."""
        problems: dict[str, list[str]] = {}
        try:
            present, overflow = listing(self.root)
        except OSError as exc:
            return {"unreadable": [f"a folder of the version directory ({exc.strerror})"]}
        if overflow:
            problems["crowded"] = [f"more than {MAX_ENTRIES} entries"]
        for name in sorted(present - set(self.manifest.files)):
            problems.setdefault("unlisted", []).append(name)
        for name, expected in sorted(self.manifest.files.items()):
            problem = member_state(self.root, name) or read_checked(self.root / name, expected)[0]
            if problem is not None:
                problems.setdefault(problem, []).append(name)
        return problems

    def _check_contents(self) -> None:
        """The episode files against ``counts``, the splits' scenes and their own task."""
        found: dict[tuple[str, str, str], int] = {}
        problems: list[str] = []
        seen: set[str] = set()
        for split in self.splits:
            scenes = set(self.manifest.splits[split])
            private = split in self.manifest.private
            for task in self.tasks(split):
                for episode in self._version_file(split, task).episodes:
                    where = f"{split}/{task}.json.gz: {episode.episode_id}"
                    revealed = withheld_problem(episode) if private else None
                    if revealed is not None:
                        problems.append(f"{where}, of the private split {split}, {revealed}")
                    elif not private and episode.info is None:
                        problems.append(f"{where} has no info (only a private split's episodes go without)")
                    if episode.task != task:
                        problems.append(f"{where} is an episode of task {episode.task}")
                    if episode.scene_id not in scenes:
                        problems.append(f"{where} is in scene {episode.scene_id}, not one of split {split}")
                    if episode.episode_id in seen:
                        problems.append(f"{where} appears twice")
                    seen.add(episode.episode_id)
                    key = (split, episode.task, episode.scene_type)
                    found[key] = found.get(key, 0) + 1
        listed = {
            (s, t, k): n
            for s, tasks in self.manifest.counts.items()
            for t, c in tasks.items()
            for k, n in c.items()
        }
        for key in sorted(set(found) | set(listed)):
            if found.get(key, 0) != listed.get(key, 0):
                problems.append(
                    f"counts {'/'.join(key)} is {listed.get(key, 0)} in manifest.json but the episode files "
                    f"hold {found.get(key, 0)}"
                )
        if problems:
            shown = "; ".join(problems[:5]) + (
                f"; ... ({len(problems) - 5} more)" if len(problems) > 5 else ""
            )
            raise DatasetError(
                f"{self.root}: the episode files do not match manifest.json: {shown}. {REMEDY}"
            )


def _not_a_version(root: Path) -> str:
    """Why ``root`` is not a dataset version, with the published versions beside it and how to build it."""
    versioned = re.fullmatch(r"v[0-9][0-9.]*", root.name) is not None
    name = root.parent.name if versioned else root.name
    episodes = root.parent.parent if versioned else root.parent
    published = sorted(p.parent for p in episodes.glob("*/v*/manifest.json"))
    text = f"{root} is not a dataset version (no manifest.json)"
    if published:
        text += f"; published in {episodes}: " + ", ".join(str(p) for p in published)
    return (
        f"{text}; build it in its workspace with `navverse build {name or '<dataset>'}` (the dataset "
        "recipe's id; `navverse status` lists the targets) and pass episodes/<name>/v<version>"
    )
