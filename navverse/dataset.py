"""The episode dataset: its schema, deterministic ``.json.gz`` files, the manifest, reading and publishing.

A dataset version is a directory ``episodes/<name>/v<version>/`` (DESIGN.md §3)::

    manifest.json                  format and dataset versions, counts, checksums, scenes, splits
    <split>/<task>.json.gz         {"episodes": [...], "goals_by_category": {...},
                                    "category_to_task_category_id": {...}}
    <split>/<task>.rollouts.json.gz   {episode_id: [[t, x, y, z, qx, qy, qz, qw], ...]}: the
                                    verification rollout of every episode (10 Hz robot base poses)

Episodes follow habitat-lab's layout (``start_position``, ``start_rotation`` as ``[x, y, z, w]``,
``goals``, ``reference_path``...). Files are written with sorted keys and a zero gzip time stamp, so
the same content gives the same bytes. :class:`Dataset` reads a version and checks its format version;
:func:`publish` copies a built dataset into ``episodes/`` and refuses to change a published version.
"""

from __future__ import annotations

import gzip
import hashlib
import json
import math
import os
import shutil
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from navverse.errors import NavverseError
from navverse.files import atomic_dir, atomic_write
from navverse.scene_types import SceneType, scene_profile

__all__ = [
    "FORMAT_VERSION",
    "TASKS",
    "Dataset",
    "DatasetError",
    "DatasetManifest",
    "Episode",
    "EpisodeFile",
    "EpisodeInfo",
    "Goal",
    "Instruction",
    "Landmark",
    "Verification",
    "built_version",
    "counts_table",
    "file_sha256",
    "goal_distance",
    "publish",
    "read_json_gz",
    "success_distance",
    "write_json_gz",
]

FORMAT_VERSION = "1.0"
"""Format of the dataset files (``major.minor``); a reader takes its own major, minors up to its own."""
TASKS = ("objnav", "placenav", "vln")

Vec3 = tuple[float, float, float]
Task = Literal["objnav", "placenav", "vln"]
_CONFIG = ConfigDict(extra="forbid", frozen=True)


class DatasetError(NavverseError):
    """A dataset is missing, malformed, of another format version, or would overwrite a published one."""


class Goal(BaseModel):
    """A goal instance: an object (ObjNav, VLN) or a storefront (PlaceNav); ``object_id`` is its id."""

    model_config = _CONFIG

    object_id: int
    category: str
    position: Vec3
    radius: Annotated[float, Field(ge=0.0)]
    size: Vec3


class Landmark(BaseModel):
    """An object an instruction names, seen from the verification rollout near directive ``step``."""

    model_config = _CONFIG

    object_id: int
    category: str
    color: str | None = None
    step: int


class Instruction(BaseModel):
    """A VLN instruction: the refined text, the template it came from, and the landmarks it names."""

    model_config = _CONFIG

    instruction_text: str
    template_text: str
    instruction_type: str
    landmarks: list[Landmark] = []
    directive_times: list[float] = []
    """For each directive of the template, the rollout time (s) at which the robot carried it out."""


class Verification(BaseModel):
    """How the physics rollout of an episode went: the robot, its time, its path and when it first
    was within the success distance of a goal."""

    model_config = _CONFIG

    embodiment: str
    duration_s: float
    traveled_m: float
    oracle_success_time_s: float


class EpisodeInfo(BaseModel):
    """Derived facts of an episode."""

    model_config = _CONFIG

    geodesic_distance: float
    euclidean_distance: float
    closest_goal_object_id: int
    success_distance: float
    difficulty: Literal["easy", "medium", "hard"] | None = None
    verification: Verification | None = None


class Episode(BaseModel):
    """One navigation episode (DESIGN.md §3)."""

    model_config = _CONFIG

    episode_id: str
    scene_id: str
    scene_type: SceneType
    task: Task
    start_position: Vec3
    start_rotation: tuple[float, float, float, float]
    object_category: str | None = None
    place_category: str | None = None
    goals: list[Goal]
    instruction: Instruction | None = None
    reference_path: list[Vec3]
    info: EpisodeInfo

    @property
    def start_yaw(self) -> float:
        """Heading of the start rotation about +z (rad)."""
        x, y, z, w = self.start_rotation
        return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))

    @property
    def goal_category(self) -> str:
        """The object or place category sought."""
        return self.object_category or self.place_category or ""


class EpisodeFile(BaseModel):
    """Contents of one ``<split>/<task>.json.gz``."""

    model_config = _CONFIG

    episodes: list[Episode]
    goals_by_category: dict[str, list[Goal]] = {}
    category_to_task_category_id: dict[str, int] = {}


class DatasetManifest(BaseModel):
    """``manifest.json`` of a dataset version."""

    model_config = _CONFIG

    format_version: str
    name: str
    version: str
    toolkit_version: str
    recipe: str
    recipe_hash: str
    embodiment: str
    scene_hashes: dict[str, str]
    splits: dict[str, list[str]]
    counts: dict[str, dict[str, dict[str, int]]]
    difficulty_thresholds: dict[str, tuple[float, float]]
    files: dict[str, str]


# ---------------------------------------------------------------------------------------------- geometry


def success_distance(robot_radius: float, *, scene_type: str) -> float:
    """Largest goal distance that counts as success in a scene of ``scene_type``: the profile's
    success margin plus ``r_robot`` (:mod:`navverse.scene_types`; 1.6 m for Spot)."""
    return scene_profile(scene_type).success_distance(robot_radius)


def goal_distance(position: Sequence[float], goal: Goal) -> float:
    """Distance to a goal (paper Appendix A.5): ``max(0, ||p - p_goal||_2 - r_goal)`` in 3-D (m).

    ``p`` is the robot's base position (x, y, z), ``p_goal`` the goal's centre and ``r_goal`` its radius,
    half its larger horizontal extent.
    """
    d = math.dist((float(position[0]), float(position[1]), float(position[2])), goal.position)
    return max(0.0, d - goal.radius)


# ---------------------------------------------------------------------------------------------- files


def write_json_gz(data: Any, path: str | os.PathLike[str]) -> Path:
    """Write JSON (sorted keys, compact) gzipped with a zero time stamp: same data, same bytes."""
    path = Path(path)
    text = json.dumps(data, sort_keys=True, separators=(",", ":"), allow_nan=False)
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_write(path) as handle:
        handle.write(gzip.compress(text.encode(), compresslevel=9, mtime=0))
    return path


def read_json_gz(path: str | os.PathLike[str]) -> Any:
    """Read a gzipped JSON file.

    Raises
    ------
    DatasetError
        If the file is missing, not gzip or not JSON.
    """
    path = Path(path)
    try:
        return json.loads(gzip.decompress(path.read_bytes()))
    except FileNotFoundError:
        raise DatasetError(f"{path} does not exist") from None
    except (OSError, EOFError, ValueError) as exc:
        raise DatasetError(f"{path} is not a gzipped JSON file ({exc})") from None


def file_sha256(path: str | os.PathLike[str]) -> str:
    """Hex SHA-256 of a file's bytes."""
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _check_format(version: str, source: Path) -> None:
    try:
        major, minor = (int(part) for part in version.split("."))
        own_major, own_minor = (int(part) for part in FORMAT_VERSION.split("."))
    except ValueError:
        raise DatasetError(f"{source}: format_version {version!r} is not 'major.minor'") from None
    if major != own_major or minor > own_minor:
        raise DatasetError(
            f"{source} has dataset format {version}; this toolkit ({_toolkit_version()}) reads format "
            f"{own_major}.x up to {FORMAT_VERSION}. "
            + ("Update the toolkit." if (major, minor) > (own_major, own_minor) else "Rebuild the dataset.")
        )


def _toolkit_version() -> str:
    from navverse import __version__

    return __version__


# ---------------------------------------------------------------------------------------------- reading


class Dataset:
    """One version of a dataset, read from its directory.

    Parameters
    ----------
    root : path
        ``episodes/<name>/v<version>`` (or ``episodes/<name>``: its newest version).

    Raises
    ------
    DatasetError
        If there is no manifest, it is malformed, or its format version is not readable here.
    """

    def __init__(self, root: str | os.PathLike[str]) -> None:
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
            raise DatasetError(
                f"{root} is not a dataset version (no manifest.json); build one with `make episodes` "
                "and pass episodes/<name>/v<version>"
            )
        try:
            raw = json.loads(manifest_path.read_text())
        except ValueError as exc:
            raise DatasetError(f"{manifest_path} is not JSON ({exc})") from None
        _check_format(str(raw.get("format_version", "?")) if isinstance(raw, dict) else "?", manifest_path)
        try:
            self.manifest = DatasetManifest.model_validate(raw)
        except ValidationError as exc:
            raise DatasetError(f"{manifest_path} is malformed: {_first_error(exc)}") from None
        self.root = root
        self._files: dict[tuple[str, str], EpisodeFile] = {}

    @property
    def splits(self) -> list[str]:
        """Split names."""
        return sorted(self.manifest.splits)

    def tasks(self, split: str) -> list[str]:
        """Tasks that have a file in ``split``."""
        return sorted(t for t in TASKS if (self.root / split / f"{t}.json.gz").is_file())

    def file(self, split: str, task: str) -> EpisodeFile:
        """The episode file of a split and task (read once)."""
        key = (split, task)
        if key not in self._files:
            path = self.root / split / f"{task}.json.gz"
            if not path.is_file():
                have = ", ".join(f"{s}/{t}" for s in self.splits for t in self.tasks(s)) or "none"
                raise DatasetError(f"{self.root} has no {split}/{task} episodes (it has: {have})")
            try:
                self._files[key] = EpisodeFile.model_validate(read_json_gz(path))
            except ValidationError as exc:
                raise DatasetError(f"{path} is malformed: {_first_error(exc)}") from None
        return self._files[key]

    def episodes(
        self, *, split: str | None = None, task: str | None = None, scene_type: str | None = None
    ) -> Iterator[Episode]:
        """Episodes, optionally of one split, task and scene type, in file order."""
        for s in [split] if split is not None else self.splits:
            if s not in self.manifest.splits:
                raise DatasetError(f"{self.root} has no split {s!r} (splits: {', '.join(self.splits)})")
            for t in [task] if task is not None else self.tasks(s):
                if task is not None and not (self.root / s / f"{t}.json.gz").is_file():
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

    def rollout(self, episode: Episode) -> list[list[float]] | None:
        """The verification rollout of an episode (10 Hz ``[t, x, y, z, qx, qy, qz, qw]`` rows), if kept."""
        for split in self.splits:
            path = self.root / split / f"{episode.task}.rollouts.json.gz"
            if path.is_file():
                rows = read_json_gz(path).get(episode.episode_id)
                if rows is not None:
                    return rows
        return None

    def verify_checksums(self) -> list[str]:
        """Files whose SHA-256 differs from the manifest's (or that are missing)."""
        bad = []
        for name, digest in sorted(self.manifest.files.items()):
            path = self.root / name
            if not path.is_file() or file_sha256(path) != digest:
                bad.append(name)
        return bad


def _first_error(exc: ValidationError) -> str:
    error = exc.errors()[0]
    where = ".".join(str(p) for p in error["loc"]) or "top level"
    return f"{where}: {error['msg']}"


# ---------------------------------------------------------------------------------------------- publishing


def built_version(artifact: str | os.PathLike[str]) -> Path:
    """The ``<name>/v<version>`` directory inside a built ``dataset`` artifact (laid out as published).

    Raises
    ------
    DatasetError
        If the artifact holds no dataset version, or more than one.
    """
    found = sorted(p.parent for p in Path(artifact).glob("*/v*/manifest.json"))
    if len(found) != 1:
        raise DatasetError(f"{artifact} holds {len(found)} dataset versions, not one: rebuild it")
    return found[0]


def publish(built: str | os.PathLike[str], episodes_dir: str | os.PathLike[str]) -> tuple[Path, bool]:
    """Copy a built dataset version into ``<episodes_dir>/<name>/v<version>``.

    A published version is immutable: publishing the same content again does nothing; different
    content under the same version is refused.

    Parameters
    ----------
    built : path
        A dataset version directory with ``manifest.json`` (:func:`built_version` of the artifact).
    episodes_dir : path
        The ``episodes/`` folder.

    Returns
    -------
    tuple of (Path, bool)
        The published directory, and whether it was written now (False: it was already there).

    Raises
    ------
    DatasetError
        If that version exists with other content.
    """
    dataset = Dataset(built)
    manifest = dataset.manifest
    target = Path(episodes_dir) / manifest.name / f"v{manifest.version}"
    if (target / "manifest.json").is_file():
        try:
            existing = DatasetManifest.model_validate_json((target / "manifest.json").read_text())
        except ValidationError:
            existing = None
        if existing is not None and existing.files == manifest.files:
            return target, False
        raise DatasetError(
            f"{target} is already published with different content, and a published version is "
            f"immutable: bump the dataset version in {manifest.recipe} (package_dataset: version) or "
            f"delete {target} if it was never shared"
        )
    target.parent.mkdir(parents=True, exist_ok=True)
    with atomic_dir(target) as staging:
        shutil.copytree(dataset.root, staging, dirs_exist_ok=True)
    return target, True


def counts_table(
    episodes: Sequence[Episode], splits: Mapping[str, Sequence[str]]
) -> dict[str, dict[str, dict[str, int]]]:
    """``{split: {task: {scene_type: count}}}`` of episodes, their split given by their scene."""
    split_of = {scene: split for split, scenes in splits.items() for scene in scenes}
    table: dict[str, dict[str, dict[str, int]]] = {}
    for episode in episodes:
        split = split_of[episode.scene_id]
        by_task = table.setdefault(split, {}).setdefault(episode.task, {})
        by_task[episode.scene_type] = by_task.get(episode.scene_type, 0) + 1
    return {
        s: {t: dict(sorted(c.items())) for t, c in sorted(tasks.items())}
        for s, tasks in sorted(table.items())
    }
