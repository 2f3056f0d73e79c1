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

Integrity: the manifest is read with a size cap and validated strictly (a ``files`` entry is a plain
``<split>/<task>[.rollouts].json.gz`` inside the version directory, checksums are SHA-256 hex).
:meth:`Dataset.verify` checks a version against its manifest before it is used (the listing, regular
files only, checksums, the episode counts); an episode or rollouts file is decompressed only once its
checksum matched, and never beyond :data:`MAX_FILE_BYTES`.
"""

from __future__ import annotations

import errno
import gzip
import hashlib
import json
import math
import os
import re
import shutil
import zlib
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    NonNegativeInt,
    ValidationError,
    field_validator,
    model_validator,
)

from navverse.dataset_files import (
    MAX_ENTRIES,
    MAX_FILE_BYTES,
    TooLargeError,
    describe,
    gunzip,
    listing,
    member_state,
    mib,
    open_regular,
    read_checked,
    sha256_of,
)
from navverse.errors import NavverseError
from navverse.files import atomic_dir, atomic_write
from navverse.scene_types import SceneType, scene_profile

__all__ = [
    "FORMAT_VERSION",
    "INSTRUCTION_TYPES",
    "MAX_FILE_BYTES",
    "MAX_MANIFEST_BYTES",
    "TASKS",
    "Dataset",
    "DatasetError",
    "DatasetManifest",
    "Episode",
    "EpisodeFile",
    "EpisodeInfo",
    "Goal",
    "Instruction",
    "InstructionType",
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

FORMAT_VERSION = "1.1"
"""Format of the dataset files (``major.minor``); a reader takes its own major, minors up to its own.
1.1 added the PlaceNav episodes' ``instructions`` by instruction type."""
TASKS = ("objnav", "placenav", "vln")
MAX_MANIFEST_BYTES = 4 << 20
"""Largest ``manifest.json`` read (bytes)."""
_MEMBER = re.compile(
    r"(?P<split>[a-z][a-z0-9_]*)/(?P<task>objnav|placenav|vln)(?P<rollouts>\.rollouts)?\.json\.gz"
)
"""A ``files`` entry: ``<split>/<task>.json.gz`` or ``<split>/<task>.rollouts.json.gz``."""
_REMEDY = (
    "This dataset version is not as it was packaged: re-download it, or rebuild it with `make episodes` "
    "(`navverse build <dataset>`); never edit a published version"
)

Vec3 = tuple[float, float, float]
Task = Literal["objnav", "placenav", "vln"]
InstructionType = Literal["category", "route", "intention"]
INSTRUCTION_TYPES: tuple[InstructionType, ...] = ("category", "route", "intention")
"""The instruction types of a PlaceNav episode (the paper's Store Category, VLN Instruction and
Intention Driven): ``category`` names the place ("Find a bank."), ``route`` describes the way along
the reference path, naming landmarks and roads, and ``intention`` states a need the place meets ("I
need to withdraw some cash.")."""
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
    """An instruction: the final text, the template it came from, and the landmarks it names.

    A VLN episode's ``instruction_type`` is ``landmark`` or ``refined``; the instructions of a
    PlaceNav episode are ``category``, ``route`` or ``intention`` (:data:`INSTRUCTION_TYPES`)."""

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
    instructions: dict[InstructionType, Instruction] = {}
    """PlaceNav: the episode's instruction of each type (:data:`INSTRUCTION_TYPES`), all three."""
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


Sha256 = Annotated[str, Field(pattern=r"^[0-9a-f]{64}$")]
SplitName = Annotated[str, Field(pattern=r"^[a-z][a-z0-9_]*$")]
Name = Annotated[str, Field(pattern=r"^[A-Za-z0-9][A-Za-z0-9._-]*$", max_length=200)]
"""A dataset or scene name: one path component, never ``.`` or ``..``."""


class DatasetManifest(BaseModel):
    """``manifest.json`` of a dataset version.

    ``files`` lists every file of the version but the manifest, by its path relative to the version
    directory (``<split>/<task>.json.gz`` or ``<split>/<task>.rollouts.json.gz``), with its SHA-256;
    ``counts`` holds the episodes per split, task and scene type.
    """

    model_config = _CONFIG

    format_version: str
    name: Name
    version: Annotated[str, Field(pattern=r"^\d+\.\d+$")]
    toolkit_version: str
    recipe: str
    recipe_hash: str
    embodiment: str
    scene_hashes: dict[Name, str]
    splits: dict[SplitName, list[Name]]
    counts: dict[SplitName, dict[Task, dict[SceneType, NonNegativeInt]]]
    difficulty_thresholds: dict[Task, tuple[float, float]]
    files: dict[str, Sha256]

    @field_validator("files")
    @classmethod
    def _plain_paths(cls, files: dict[str, str]) -> dict[str, str]:
        for name in files:
            problem = _member_problem(name)
            if problem is not None:
                raise ValueError(
                    f"files entry {name!r} {problem}: every entry is <split>/<task>.json.gz or "
                    "<split>/<task>.rollouts.json.gz inside the version directory"
                )
        return files

    @model_validator(mode="after")
    def _known_splits(self) -> DatasetManifest:
        named = [n.split("/")[0] for n in self.files] + list(self.counts)
        unknown = sorted(set(named) - set(self.splits))
        if unknown:
            raise ValueError(f"files or counts name splits that splits does not list: {', '.join(unknown)}")
        scenes = [scene for members in self.splits.values() for scene in members]
        shared = sorted({scene for scene in scenes if scenes.count(scene) > 1})
        if shared:
            raise ValueError(f"splits must be scene-disjoint; in several splits: {', '.join(shared)}")
        return self


def _member_problem(name: str) -> str | None:
    """What is wrong with a ``files`` entry, or None for a plain ``<split>/<task>...json.gz``."""
    if name.startswith("/") or re.match(r"^[A-Za-z]:", name):
        return "is an absolute path"
    if any(part in ("..", ".") for part in re.split(r"[/\\]", name)):
        return "leaves the version directory"
    if _MEMBER.fullmatch(name) is None:
        return "is not a dataset file name"
    return None


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


def read_json_gz(path: str | os.PathLike[str], *, max_bytes: int = MAX_FILE_BYTES) -> Any:
    """Read a gzipped JSON file, decompressing it in chunks up to ``max_bytes``.

    Raises
    ------
    DatasetError
        If the file is missing, not gzip, not JSON, or decompresses to more than ``max_bytes``.
    """
    path = Path(path)
    try:
        with open(path, "rb") as handle:
            _, data = gunzip(handle, limit=max_bytes, keep=True)
    except FileNotFoundError:
        raise DatasetError(f"{path} does not exist") from None
    except TooLargeError:
        raise DatasetError(f"{path} decompresses to more than {mib(max_bytes)}: refused") from None
    except (OSError, EOFError, zlib.error) as exc:
        raise DatasetError(f"{path} is not a gzipped JSON file ({exc})") from None
    return _parse_json(data, path)


def file_sha256(path: str | os.PathLike[str]) -> str:
    """Hex SHA-256 of a file's bytes (read in chunks)."""
    with open(path, "rb") as handle:
        return sha256_of(handle)


def _parse_json(data: bytes, source: Path) -> Any:
    try:
        return json.loads(data)
    except (ValueError, RecursionError) as exc:
        raise DatasetError(f"{source} is not a gzipped JSON file ({type(exc).__name__}: {exc})") from None


def _unique_keys(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    """A JSON object's dict, refusing a key given twice (JSON would keep the last one silently)."""
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise ValueError(f"the key {key!r} appears twice in one object")
        out[key] = value
    return out


def _no_constant(name: str) -> Any:
    raise ValueError(f"{name} is not a JSON number")


def _read_manifest(path: Path) -> tuple[DatasetManifest, str]:
    """Read and strictly validate ``manifest.json`` (at most :data:`MAX_MANIFEST_BYTES`); with its SHA-256."""
    try:
        with open_regular(path) as handle:
            text = handle.read(MAX_MANIFEST_BYTES + 1)
    except OSError as exc:
        what = "is a symbolic link" if exc.errno == errno.ELOOP else f"cannot be read ({exc.strerror})"
        raise DatasetError(f"{path} {what}: a dataset manifest is a regular file. {_REMEDY}") from None
    if len(text) > MAX_MANIFEST_BYTES:
        raise DatasetError(
            f"{path} is larger than {mib(MAX_MANIFEST_BYTES)}: not a dataset manifest. {_REMEDY}"
        )
    try:
        raw = json.loads(text, object_pairs_hook=_unique_keys, parse_constant=_no_constant)
    except (ValueError, RecursionError) as exc:
        raise DatasetError(f"{path} is not JSON ({exc}). {_REMEDY}") from None
    _check_format(str(raw.get("format_version", "?")) if isinstance(raw, dict) else "?", path)
    try:
        manifest = DatasetManifest.model_validate_json(text, strict=True)
    except ValidationError as exc:
        raise DatasetError(f"{path} is malformed: {_first_error(exc)}. {_REMEDY}") from None
    return manifest, hashlib.sha256(text).hexdigest()


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

    Opening a version reads and validates its manifest only. Call :meth:`verify` before using the
    dataset for anything that counts (scoring, running agents): it checks every file against the
    manifest. Whatever the reader decompresses it checks against the manifest's checksum first.

    Parameters
    ----------
    root : path
        ``episodes/<name>/v<version>`` (or ``episodes/<name>``: its newest version).

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
        self.manifest, self.manifest_sha256 = _read_manifest(manifest_path)
        self.root = root
        self._files: dict[tuple[str, str], EpisodeFile] = {}

    @property
    def splits(self) -> list[str]:
        """Split names."""
        return sorted(self.manifest.splits)

    def tasks(self, split: str) -> list[str]:
        """Tasks that have an episode file in ``split`` (as the manifest lists them)."""
        return sorted(t for t in TASKS if f"{split}/{t}.json.gz" in self.manifest.files)

    def file(self, split: str, task: str) -> EpisodeFile:
        """The episode file of a split and task (read once, after its checksum matched).

        Raises
        ------
        DatasetError
            If the manifest lists no such file, or the file is not the one it lists.
        """
        key = (split, task)
        if key not in self._files:
            name = f"{split}/{task}.json.gz"
            if name not in self.manifest.files:
                have = ", ".join(f"{s}/{t}" for s in self.splits for t in self.tasks(s)) or "none"
                raise DatasetError(f"{self.root} has no {split}/{task} episodes (it has: {have})")
            try:
                self._files[key] = EpisodeFile.model_validate(self._load(name))
            except ValidationError as exc:
                raise DatasetError(f"{self.root / name} is malformed: {_first_error(exc)}") from None
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
        from navverse.scene.locate import find_scene_dirs

        scene_id = (
            episode_or_scene_id if isinstance(episode_or_scene_id, str) else episode_or_scene_id.scene_id
        )
        if not any(scene_id in scenes for scenes in self.manifest.splits.values()):
            raise DatasetError(f"{self.root} has no scene {scene_id!r} in any split")
        found = find_scene_dirs(
            [scene_id], search=search, hashes=self.manifest.scene_hashes, built_dir=built_dir
        )
        return found[scene_id]

    def rollout(self, episode: Episode) -> list[list[float]] | None:
        """The verification rollout of an episode (10 Hz ``[t, x, y, z, qx, qy, qz, qw]`` rows), if kept."""
        for split in self.splits:
            name = f"{split}/{episode.task}.rollouts.json.gz"
            if name in self.manifest.files and episode.scene_id in self.manifest.splits[split]:
                rollouts = self._load(name)
                if not isinstance(rollouts, dict):
                    raise DatasetError(f"{self.root / name} is malformed: not an object of rollouts")
                rows = rollouts.get(episode.episode_id)
                if rows is not None:
                    return rows
        return None

    def verify(self) -> None:
        """Check the version against its manifest; do this before using it for results.

        The manifest must list every file of the version directory and nothing else; each listed
        path is a regular file inside the directory (no symbolic link), at most
        :data:`MAX_FILE_BYTES` compressed and decompressed, with the listed SHA-256; the episode
        files, read only once their checksum matched, hold the episodes ``counts`` says, of their
        split's scenes and their file's task, each id once. Nothing is cached across processes: it
        hashes the whole version (a few MB) each time.

        Raises
        ------
        DatasetError
            Naming the files that do not match and what to do (re-download or rebuild).
        """
        problems = self._file_problems()
        if problems:
            raise DatasetError(f"{self.root}: {describe(problems)}. {_REMEDY}")
        self._check_contents()

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
            raise DatasetError(f"{self.root}: {describe({problem: [name]})}. {_REMEDY}")
        return _parse_json(data, path)

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
            for task in self.tasks(split):
                for episode in self.file(split, task).episodes:
                    where = f"{split}/{task}.json.gz: {episode.episode_id}"
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
                f"{self.root}: the episode files do not match manifest.json: {shown}. {_REMEDY}"
            )


def _first_error(exc: ValidationError) -> str:
    error = exc.errors()[0]
    where = ".".join(str(p) for p in error["loc"]) or "top level"
    return f"{where}: {error['msg'].removeprefix('Value error, ')}"


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
        If the built version does not match its manifest, or that version exists with other content.
    """
    dataset = Dataset(built)
    dataset.verify()
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
