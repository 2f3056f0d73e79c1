"""Export a NavVerse dataset version for habitat-lab: ObjectNav-v1 and R2R-VLN episodes, and scenes.

:func:`export_habitat` writes, atomically (a temporary directory beside ``out``, renamed at the end)::

    out/export.json                                 source dataset, counts, categories, this layout
    out/objectnav_v1/<split>/<split>.json.gz        {"episodes": [], category maps}
    out/objectnav_v1/<split>/content/<scene>.json.gz
                                                    {"episodes", "goals_by_category", category maps}
    out/vln_r2r/<split>/<split>.json.gz             {"episodes", "instruction_vocab"}
    out/scenes/<scene>/<scene>.glb                  geometry (navverse.export.habitat_scenes)
    out/scenes/<scene>/<scene>.semantic.glb, .semantic.txt, .navmesh

With habitat-lab: ``dataset.type: ObjectNav-v1``, ``data_path:
out/objectnav_v1/{split}/{split}.json.gz``, ``scenes_dir: out/scenes`` (``R2RVLN-v1`` and
``out/vln_r2r/{split}/{split}.json.gz`` for VLN).

Frames. NavVerse is z-up (x, y on the ground, yaw about +z, 0 along +x); habitat is y-up and an
agent looks along -z of its own frame. A point maps as ``(x, y, z) -> (x, z, -y)`` (a rotation by
-90 degrees about x, so triangle winding is kept); a heading ``yaw`` becomes the rotation about
habitat +y by ``yaw - pi/2``, written ``[x, y, z, w] = [0, sin(h/2), 0, cos(h/2)]``, ``h = yaw -
pi/2`` (start rotations are yaw only; roll and pitch are not carried). Recast's own y-up frame in
navverse's navmesh tiles is the same ``(x, z, -y)``, so the ``.navmesh`` tiles are copied unchanged.

ObjectNav-v1. ObjNav and PlaceNav episodes both go here, ``object_category`` the object category or the
place category sought. Goals live in ``goals_by_category`` under ``"<scene>.glb_<category>"`` (habitat's
``goals_key``): the union of the goal instances of that scene and category over all episodes (NavVerse
keeps, per episode, only instances whose path is 5-50 m long; habitat shares one list per key). A goal
is ``position`` (the NavVerse goal position: an object's centre, a storefront's entrance), ``radius``,
``object_id`` (the object's instance id in the semantic files; for a PlaceNav goal, the id of its
storefront's object, see :mod:`navverse.export.habitat_scenes`), ``object_name``, ``object_category``
and ``view_points``: up to 16 navmesh points from which the goal counts as reached under NavVerse's
success distance (:func:`navverse.episodes.sampling.goal_regions`, spread by bearing around the goal),
each with an agent rotation facing the goal. Category ids: ``category_to_task_category_id`` numbers
every goal category of the dataset (all splits) in sorted order;
``category_to_scene_annotation_category_id`` is the 1-based index of the category in
``semantic_categories`` of ``export.json`` (-1 for a goal category no scene object carries). habitat-lab
renumbers ``episode_id`` per file; the NavVerse id is kept in ``info.navverse_episode_id``.

R2R-VLN. ``instruction.instruction_tokens`` are vocabulary indices of the lower-cased word tokens
(``[\\w'-]+``) of the text, unpadded; ``instruction_vocab`` holds ``word_list`` = ``<pad>``, ``<unk>``,
then the words of all VLN instructions of the dataset (all splits) sorted, so ``PAD_INDEX`` 0 and
``UNK_INDEX`` 1 (habitat's ``VocabDict`` rebuilds the rest from ``word_list``). ``goals`` is one
goal at the end of the reference path (on the navmesh, in the goal region) with the success distance
as its radius; the goal object is in ``info.goal_object``. ``trajectory_id`` numbers the episodes
(one instruction per path).
"""

from __future__ import annotations

import json
import re
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from navverse.dataset import Dataset, Episode, Goal, write_json_gz
from navverse.episodes.sampling import goal_regions
from navverse.errors import NavverseError
from navverse.export.habitat_scenes import (
    habitat_rotation,
    semantic_categories,
    storefront_objects,
    to_habitat,
    write_habitat_scene,
    yaw_facing,
)
from navverse.files import atomic_dir
from navverse.nav.pathfinder import PathFinder
from navverse.scene.annotations import SceneAnnotations
from navverse.scene.directory import SceneFiles, read_annotations, read_scene
from navverse.scene.locate import built_scene_dir

__all__ = [
    "MAX_VIEW_POINTS",
    "HabitatExport",
    "HabitatExportError",
    "build_vocabulary",
    "export_habitat",
    "habitat_rotation",
    "to_habitat",
    "tokenize",
]

MAX_VIEW_POINTS = 16
PAD, UNK = "<pad>", "<unk>"
_WORD = re.compile(r"[\w'-]+")
_GOAL_TASKS = ("objnav", "placenav")
Progress = Callable[[str], None]


class HabitatExportError(NavverseError):
    """A dataset cannot be exported for habitat (a scene missing, a goal without its object...)."""


@dataclass(frozen=True)
class HabitatExport:
    """What :func:`export_habitat` wrote.

    Attributes
    ----------
    root : Path
        The export directory.
    objectnav : dict of str to int
        ObjectNav-v1 episodes (ObjNav and PlaceNav) per split.
    vln : dict of str to int
        R2R-VLN episodes per split.
    scenes : tuple of str
        The scenes written under ``scenes/``.
    vocabulary_size : int
        Words of the VLN vocabulary, ``<pad>`` and ``<unk>`` included.
    """

    root: Path
    objectnav: dict[str, int]
    vln: dict[str, int]
    scenes: tuple[str, ...]
    vocabulary_size: int

    def objectnav_file(self, split: str) -> Path:
        """The ObjectNav-v1 split file of ``split``."""
        return self.root / "objectnav_v1" / split / f"{split}.json.gz"

    def vln_file(self, split: str) -> Path:
        """The R2R-VLN split file of ``split``."""
        return self.root / "vln_r2r" / split / f"{split}.json.gz"

    def scene_dir(self, scene_id: str) -> Path:
        """The exported scene directory of ``scene_id``."""
        return self.root / "scenes" / scene_id


# ---------------------------------------------------------------------------------------------- text


def tokenize(text: str) -> list[str]:
    """Lower-cased word tokens of an instruction (runs of word characters, ``'`` and ``-``)."""
    return _WORD.findall(text.lower())


def build_vocabulary(texts: Iterable[str]) -> dict[str, Any]:
    """habitat's ``instruction_vocab`` of texts: ``<pad>`` 0, ``<unk>`` 1, then the sorted words."""
    words = sorted({w for text in texts for w in tokenize(text)} - {PAD, UNK})
    word_list = [PAD, UNK, *words]
    index = {w: i for i, w in enumerate(word_list)}
    return {
        "word_list": word_list,
        "word2idx_dict": index,
        "stoi": index,
        "itos": word_list,
        "num_vocab": len(word_list),
        "UNK_INDEX": 1,
        "PAD_INDEX": 0,
    }


# ---------------------------------------------------------------------------------------------- goals


def _round(values: np.ndarray) -> list:
    """Values as written: to the micrometre (and 1e-6 of a quaternion component), so that positions
    read back (:func:`~navverse.export.habitat_scenes.from_habitat`) within 1e-6 m."""
    return np.round(np.asarray(values, dtype=np.float64), 6).tolist()


def view_points(finder: PathFinder, goal: Goal, *, success: float) -> list[dict[str, Any]]:
    """Up to :data:`MAX_VIEW_POINTS` habitat view points of a goal: navmesh points within the success
    distance, spread by bearing around the goal, each with a rotation facing it (deterministic)."""
    regions = goal_regions(finder, [goal], success=success)
    if not regions:
        return []
    points = np.round(regions[0].points, 6)  # as written; a point rounded off the mesh is dropped
    points = points[finder.is_navigable(points)]
    if len(points) == 0:
        return []
    bearing = np.arctan2(points[:, 1] - goal.position[1], points[:, 0] - goal.position[0])
    order = np.lexsort((points[:, 2], points[:, 1], points[:, 0], np.round(bearing, 6)))
    pick = order[
        np.unique(np.linspace(0, len(order) - 1, min(MAX_VIEW_POINTS, len(order))).round().astype(int))
    ]
    chosen = points[pick]
    rotations = habitat_rotation(yaw_facing(chosen, np.asarray(goal.position)))
    return [
        {"agent_state": {"position": p, "rotation": q}, "iou": None}
        for p, q in zip(_round(to_habitat(chosen)), _round(rotations), strict=True)
    ]


@dataclass(frozen=True)
class _SceneGoals:
    """A scene's goal instances by ``(task, category)``, and how to name them for habitat."""

    annotations: SceneAnnotations
    storefront_object: dict[int, int]

    def object_id(self, task: str, goal_id: int) -> int:
        """The semantic object id of a NavVerse goal id (a PlaceNav goal's id is its storefront's)."""
        if task != "placenav":
            return goal_id
        if goal_id not in self.storefront_object:
            raise HabitatExportError(f"scene {self.annotations.scene_id!r} has no storefront {goal_id}")
        return self.storefront_object[goal_id]

    def object_name(self, task: str, goal: Goal) -> str:
        """The shop's name for a storefront, else ``<category>_<id>``."""
        if task == "placenav":
            names = {s.id: s.name for s in self.annotations.storefronts}
            if names.get(goal.object_id):
                return str(names[goal.object_id])
        return f"{goal.category}_{self.object_id(task, goal.object_id)}"


def _habitat_goal(
    goal: Goal, *, task: str, finder: PathFinder, success: float, names: _SceneGoals
) -> dict[str, Any]:
    return {
        "position": _round(to_habitat(goal.position)),
        "radius": goal.radius,
        "object_id": names.object_id(task, goal.object_id),
        "object_name": names.object_name(task, goal),
        "object_category": goal.category,
        "view_points": view_points(finder, goal, success=success),
    }


# ---------------------------------------------------------------------------------------------- episodes


def _glb(scene_id: str) -> str:
    return f"{scene_id}/{scene_id}.glb"


def _start(episode: Episode) -> dict[str, Any]:
    return {
        "episode_id": episode.episode_id,
        "scene_id": _glb(episode.scene_id),
        "start_position": _round(to_habitat(episode.start_position)),
        "start_rotation": _round(habitat_rotation(episode.start_yaw)),
    }


def _info(episode: Episode) -> dict[str, Any]:
    info = episode.info
    return {
        "geodesic_distance": info.geodesic_distance,
        "euclidean_distance": info.euclidean_distance,
        "success_distance": info.success_distance,
        "difficulty": info.difficulty,
        "navverse_episode_id": episode.episode_id,
        "navverse_task": episode.task,
        "scene_type": episode.scene_type,
    }


def objectnav_episode(episode: Episode, names: _SceneGoals) -> dict[str, Any]:
    """An ObjNav or PlaceNav episode as an ObjectNav-v1 episode (its goals in ``goals_by_category``)."""
    info = _info(episode) | {
        "closest_goal_object_id": names.object_id(episode.task, episode.info.closest_goal_object_id)
    }
    if episode.instructions:
        info["instructions"] = {k: v.instruction_text for k, v in sorted(episode.instructions.items())}
    return _start(episode) | {"info": info, "goals": [], "object_category": episode.goal_category}


def vln_episode(episode: Episode, trajectory_id: int, vocabulary: Mapping[str, Any]) -> dict[str, Any]:
    """A VLN episode as an R2R-VLN episode."""
    if episode.instruction is None or not episode.reference_path:
        raise HabitatExportError(f"VLN episode {episode.episode_id} has no instruction or reference path")
    index = vocabulary["word2idx_dict"]
    text = episode.instruction.instruction_text
    goal = next((g for g in episode.goals if g.object_id == episode.info.closest_goal_object_id), None)
    info = _info(episode) | {"instruction_type": episode.instruction.instruction_type}
    if goal is not None:
        info["goal_object"] = {
            "object_id": goal.object_id,
            "category": goal.category,
            "position": _round(to_habitat(goal.position)),
        }
    return _start(episode) | {
        "trajectory_id": trajectory_id,
        "instruction": {
            "instruction_text": text,
            "instruction_tokens": [index.get(w, 1) for w in tokenize(text)],
        },
        "reference_path": _round(to_habitat(np.asarray(episode.reference_path))),
        "goals": [
            {
                "position": _round(to_habitat(episode.reference_path[-1])),
                "radius": episode.info.success_distance,
            }
        ],
        "info": info,
    }


# ---------------------------------------------------------------------------------------------- scenes


def _default_scenes(built_dir: Path) -> Callable[[str], Path]:
    def resolve(scene_id: str) -> Path:
        try:
            return built_scene_dir(built_dir, scene_id)
        except NavverseError as exc:
            raise HabitatExportError(
                f"scene {scene_id!r} not found: looked in {built_dir / 'targets' / scene_id} ({exc})"
            ) from None

    return resolve


def _scene_dirs(scene_ids: Iterable[str], resolve: Callable[[str], Path]) -> dict[str, Path]:
    """Each scene's built directory, checked to hold its annotations, USD file and navmesh."""
    found = {}
    for scene_id in sorted(set(scene_ids)):
        try:
            scene_dir = Path(resolve(scene_id))
        except HabitatExportError:
            raise
        except (NavverseError, OSError) as exc:
            raise HabitatExportError(f"scene {scene_id!r} not found: {exc}") from None
        files = SceneFiles(scene_dir)
        missing = [p.name for p in (files.annotations, files.usd, files.navmesh) if not p.is_file()]
        if missing:
            raise HabitatExportError(
                f"scene {scene_id!r} not found: looked in {scene_dir}, which has no {', '.join(missing)}; "
                f"build it with `navverse build {scene_id}`"
            )
        found[scene_id] = scene_dir
    return found


# ---------------------------------------------------------------------------------------------- export


def _exported(dataset: Dataset) -> list[str]:
    """The splits exported: all but the private ones (whose goals the version does not hold)."""
    return [s for s in dataset.splits if s not in dataset.private_splits]


def _goal_instances(dataset: Dataset, split: str, scene_id: str) -> dict[tuple[str, str], dict[int, Goal]]:
    """``(task, category) -> {goal id: goal}`` of a scene's ObjNav and PlaceNav episodes in a split."""
    found: dict[tuple[str, str], dict[int, Goal]] = {}
    for task in _GOAL_TASKS:
        if task not in dataset.tasks(split):
            continue
        file = dataset.file(split, task)
        for episode in file.episodes:
            if episode.scene_id == scene_id:
                bucket = found.setdefault((task, episode.goal_category), {})
                bucket.update({g.object_id: g for g in episode.goals})
        for (t, category), bucket in list(found.items()):
            if t == task:
                bucket.update(
                    {g.object_id: g for g in file.goals_by_category.get(f"{scene_id}_{category}", [])}
                )
    return found


def _success(dataset: Dataset, split: str, scene_id: str) -> float:
    episodes = (e for e in dataset.episodes(split=split) if e.scene_id == scene_id)
    return max((e.info.success_distance for e in episodes), default=1.6)


def _content_file(
    dataset: Dataset, split: str, scene_id: str, scene_dir: Path, maps: Mapping[str, Any]
) -> dict[str, Any] | None:
    """The ObjectNav-v1 content of one scene of a split (None: the scene has no such episodes)."""
    episodes = [
        e for t in _GOAL_TASKS if t in dataset.tasks(split) for e in dataset.file(split, t).episodes
        if e.scene_id == scene_id
    ]  # fmt: skip
    if not episodes:
        return None
    annotations = read_annotations(scene_dir)
    names = _SceneGoals(annotations, storefront_objects(annotations))
    finder = PathFinder.load(SceneFiles(scene_dir).navmesh)
    success = _success(dataset, split, scene_id)
    goals = {
        f"{scene_id}.glb_{category}": [
            _habitat_goal(g, task=task, finder=finder, success=success, names=names)
            for _, g in sorted(instances.items())
        ]
        for (task, category), instances in sorted(_goal_instances(dataset, split, scene_id).items())
    }
    return dict(maps) | {
        "episodes": [objectnav_episode(e, names) for e in episodes],
        "goals_by_category": goals,
    }


def _category_maps(dataset: Dataset, scene_dirs: Mapping[str, Path]) -> tuple[dict[str, Any], list[str]]:
    """The ObjectNav-v1 category maps (dataset-wide) and the semantic category list."""
    goal_categories = sorted(
        {e.goal_category for s in _exported(dataset) for t in _GOAL_TASKS if t in dataset.tasks(s)
         for e in dataset.file(s, t).episodes}
    )  # fmt: skip
    semantic = sorted(
        {c for d in scene_dirs.values() for c in semantic_categories(read_annotations(d)).values()}
    )
    index = {c: i + 1 for i, c in enumerate(semantic)}
    maps = {
        "category_to_task_category_id": {c: i for i, c in enumerate(goal_categories)},
        "category_to_scene_annotation_category_id": {c: index.get(c, -1) for c in goal_categories},
    }
    return maps, semantic


def _write_objectnav(
    dataset: Dataset, root: Path, scene_dirs: Mapping[str, Path], maps: Mapping[str, Any], progress: Progress
) -> dict[str, int]:
    counts = {}
    for split in _exported(dataset):
        if not any(t in dataset.tasks(split) for t in _GOAL_TASKS):
            continue
        counts[split] = 0
        for scene_id in dataset.manifest.splits[split]:
            if scene_id not in scene_dirs:
                continue
            progress(f"objectnav {split}: goals and view points of {scene_id}")
            content = _content_file(dataset, split, scene_id, scene_dirs[scene_id], maps)
            if content is not None:
                write_json_gz(content, root / "objectnav_v1" / split / "content" / f"{scene_id}.json.gz")
                counts[split] += len(content["episodes"])
        write_json_gz(dict(maps) | {"episodes": []}, root / "objectnav_v1" / split / f"{split}.json.gz")
    return counts


def _write_vln(dataset: Dataset, root: Path) -> tuple[dict[str, int], int]:
    splits = [s for s in _exported(dataset) if "vln" in dataset.tasks(s)]
    episodes = {s: list(dataset.episodes(split=s, task="vln")) for s in splits}
    vocabulary = build_vocabulary(
        e.instruction.instruction_text for es in episodes.values() for e in es if e.instruction is not None
    )
    counts, trajectory = {}, 0
    for split in splits:
        out = []
        for episode in episodes[split]:
            out.append(vln_episode(episode, trajectory, vocabulary))
            trajectory += 1
        write_json_gz(
            {"episodes": out, "instruction_vocab": vocabulary}, root / "vln_r2r" / split / f"{split}.json.gz"
        )
        counts[split] = len(out)
    return counts, int(vocabulary["num_vocab"]) if splits else 0


def _write_scenes(
    scene_dirs: Mapping[str, Path], root: Path, progress: Progress
) -> dict[str, dict[str, int]]:
    stats = {}
    for i, (scene_id, scene_dir) in enumerate(sorted(scene_dirs.items()), start=1):
        progress(f"scene {scene_id} ({i}/{len(scene_dirs)}): GLB, semantics, navmesh")
        out = root / "scenes" / scene_id
        out.mkdir(parents=True)
        stats[scene_id] = write_habitat_scene(read_scene(scene_dir), SceneFiles(scene_dir).navmesh, out)
    return stats


def export_habitat(
    dataset_dir: Path,
    out: Path,
    *,
    scenes: Callable[[str], Path] | None = None,
    progress: Progress | None = None,
) -> HabitatExport:
    """Export a dataset version and its scenes in habitat-lab's layouts (see the module docstring).

    Parameters
    ----------
    dataset_dir : Path
        ``episodes/<name>/v<version>`` (verified before use).
    out : Path
        The export directory to create; it must not exist (or be empty). Nothing is left there on
        failure.
    scenes : callable, optional
        ``scene_id -> built scene directory``; by default the scene's build in ``data/built`` of the
        current directory (:func:`navverse.scene.locate.built_scene_dir`).
    progress : callable, optional
        Called with a line of text as each scene is written.

    Returns
    -------
    HabitatExport
        Counts and paths of what was written.

    Raises
    ------
    HabitatExportError
        If ``out`` is not empty, a scene is missing (naming it and where it was looked for), or a goal
        cannot be given an object id.
    DatasetError
        If the dataset does not verify.
    """
    out, say = Path(out), progress or (lambda _line: None)
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        raise HabitatExportError(f"{out} already exists and is not empty: choose a new directory")
    dataset = Dataset(dataset_dir)
    dataset.verify()
    resolve = scenes if scenes is not None else _default_scenes(Path("data") / "built")
    scene_dirs = _scene_dirs(
        (e.scene_id for s in _exported(dataset) for e in dataset.episodes(split=s)), resolve
    )
    maps, semantic = _category_maps(dataset, scene_dirs)
    out.parent.mkdir(parents=True, exist_ok=True)
    with atomic_dir(out) as tmp:
        stats = _write_scenes(scene_dirs, tmp, say)
        objectnav = _write_objectnav(dataset, tmp, scene_dirs, maps, say)
        vln, vocabulary_size = _write_vln(dataset, tmp)
        summary = {
            "source": {
                "name": dataset.manifest.name,
                "version": dataset.manifest.version,
                "manifest_sha256": dataset.manifest_sha256,
                "embodiment": dataset.manifest.embodiment,
            },
            "frame": "habitat y-up: (x, y, z) z-up -> (x, z, -y); yaw -> rotation about +y by yaw - pi/2",
            "objectnav_v1": objectnav,
            "vln_r2r": vln,
            "scenes": stats,
            "semantic_categories": semantic,
            "navmesh": "Detour MSET version 1 (habitat-sim PathFinder.load_nav_mesh)",
            "left_out": {split: "its goals are private" for split in sorted(dataset.private_splits)},
        }
        (tmp / "export.json").write_text(
            json.dumps(summary, indent=2, sort_keys=True) + "\n", encoding="utf-8"
        )
    return HabitatExport(
        root=out,
        objectnav=objectnav,
        vln=vln,
        scenes=tuple(sorted(scene_dirs)),
        vocabulary_size=vocabulary_size,
    )
