"""The Python API: build recipes, load scenes, make environments and generate scenes in-process.

Everything the command line does with recipes and datasets, from Python::

    import navverse.api as nv

    built = nv.build("office-s1")                               # a recipe of the workspace, by target id
    built = nv.build({"extends": "indoor-building",             # or a recipe written as a dict
                      "stages": {"indoor_layout": {"building_type": "cafe"}}}, name="my-cafe")
    scene = nv.load_scene("my-cafe")                            # geometry, annotations, navmesh
    env = nv.make_env("episodes/navverse-mini/v2.2", "office-s1-objnav-0003")
    obs, info = env.reset()

    house = nv.generate_building("apartment", seed=3)           # no engine, no files: a Scene
    town = nv.generate_city(seed=0, size=(300, 300))            # a synthetic city's map and scene

:func:`build` runs the engine on the workspace, with its cache, lock and store, through
:func:`navverse.cli.build_targets`, the code of ``navverse build``: :mod:`navverse.cli` stays the
one navverse module that imports the engine and the stages. The other functions need no
workspace. (The API is not re-exported from ``navverse`` itself: every stage's cache key covers the
package's ``__init__`` and all it imports.)
"""

from __future__ import annotations

import hashlib
import json
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import gymnasium

from navverse.errors import NavverseError

if TYPE_CHECKING:
    from navverse.city.geometry.street_plan import StreetPlan
    from navverse.city.map import CityMap
    from navverse.env import NavVerseEnv
    from navverse.nav import PathFinder
    from navverse.scene.geometry import Scene

__all__ = [
    "ApiError",
    "BuildResult",
    "EpisodeEnv",
    "GeneratedCity",
    "LoadedScene",
    "build",
    "generate_building",
    "generate_city",
    "load_scene",
    "make_env",
]

_NAME = re.compile(r"^[a-z0-9][a-z0-9._-]{0,99}$")
API_RECIPES = Path("tmp") / "api-recipes"
"""Where :func:`build` writes a recipe given as a dict, under the workspace's build store."""


class ApiError(NavverseError):
    """A call of the Python API that cannot be done as asked; the message says what to change."""


# ---------------------------------------------------------------------------------------------- build


@dataclass(frozen=True)
class BuildResult:
    """What :func:`build` built.

    Attributes
    ----------
    targets : dict
        ``{target id: {output artifact: directory}}`` of every target asked for (the artifacts of the
        build store, e.g. ``scene``, ``geometry``, ``dataset``).
    built, cached : int
        Stage runs done and taken from the cache.
    """

    targets: dict[str, dict[str, Path]]
    built: int
    cached: int

    def output(self, target: str, artifact: str | None = None) -> Path:
        """The directory of a target's output: ``artifact``, else its scene (``scene``, else
        ``geometry``) or its ``dataset``."""
        outputs = self.targets.get(target)
        if outputs is None:
            raise ApiError(f"{target!r} was not built here; built: {', '.join(self.targets)}")
        for name in (artifact,) if artifact else ("scene", "geometry", "dataset"):
            if name in outputs:
                return outputs[name]
        raise ApiError(f"target {target!r} has no output {artifact!r}; it has: {', '.join(outputs)}")


def _recipe_file(recipe: Mapping[str, Any], name: str | None, built_dir: Path) -> tuple[str, Path]:
    """Write a dict recipe where the engine reads it; its target id (``name``, the recipe's ``id``, or
    one made from its content) and the file."""
    text = json.dumps(dict(recipe), sort_keys=True, default=str)
    target = name or recipe.get("id") or f"api-{hashlib.sha256(text.encode()).hexdigest()[:10]}"
    if not isinstance(target, str) or not _NAME.match(target):
        raise ApiError(
            f"name {target!r} is not a target id: use lower-case letters, digits, '.', '_' and '-' "
            "(at most 100), starting with a letter or digit"
        )
    from navverse.files import atomic_write

    path = built_dir / API_RECIPES / f"{target}.yaml"
    path.parent.mkdir(parents=True, exist_ok=True)
    body = {k: v for k, v in dict(recipe).items() if k != "id"}
    with atomic_write(path) as handle:
        handle.write(json.dumps(body, sort_keys=True, indent=1, default=str).encode("utf-8"))  # YAML ⊃ JSON
    return target, path


def build(
    recipe: str | Sequence[str] | Mapping[str, Any],
    *,
    name: str | None = None,
    root: str | os.PathLike[str] | None = None,
    jobs: int | None = None,
    force: bool = False,
    quiet: bool = True,
) -> BuildResult:
    """Build recipes with the engine, as ``navverse build`` does (cache, lock, store of the workspace).

    Parameters
    ----------
    recipe : str, sequence of str, or mapping
        Target ids or selectors of the workspace's recipes (``"office-s1"``, ``"scenes/indoor"``), or
        one recipe as a dict (the keys of a recipe file: ``extends``, ``stages``, ``seeds``...), built
        as target ``name``.
    name : str, optional
        Target id of a dict recipe (default: its ``id``, else one made from its content); a recipe of
        the workspace with this id is an error.
    root : path, optional
        The workspace (default: found from the current directory, or ``$NAVVERSE_ROOT``).
    jobs : int, optional
        Stage runs at once (default: the number of CPUs).
    force : bool
        Rebuild the asked targets' stages even if cached.
    quiet : bool
        No progress bars or summary on the terminal.

    Returns
    -------
    BuildResult

    Raises
    ------
    NavverseError
        A recipe problem, a target that does not exist, or a failed stage (with the engine's message).
    """
    from rich.console import Console

    from navverse.cli import build_targets, workspace_built_dir

    root = Path(root) if root is not None else None
    extra: list[Path] = []
    if isinstance(recipe, Mapping):
        target, path = _recipe_file(recipe, name, workspace_built_dir(root))
        selectors, extra = [target], [path]
    else:
        selectors = [recipe] if isinstance(recipe, str) else list(recipe)
    try:
        outputs, report = build_targets(
            selectors, root=root, extra_files=extra, jobs=jobs, force=force, console=Console(quiet=quiet)
        )
    except NavverseError as exc:
        raise ApiError(str(exc)) from None
    if not report.ok:
        failed = "; ".join(f"{node}: {result.error}" for node, result in list(report.failed.items())[:5])
        raise ApiError(
            f"the build failed ({len(report.failed)} stage runs failed, {len(report.skipped)} skipped): "
            + failed
        )
    return BuildResult(targets=outputs, built=len(report.built), cached=len(report.cached))


# ---------------------------------------------------------------------------------------------- scenes


@dataclass(frozen=True)
class LoadedScene:
    """A built scene: its directory, geometry and annotations, and its navmesh (None if not built)."""

    directory: Path
    scene: Scene
    pathfinder: PathFinder | None

    @property
    def annotations(self):
        """The scene's annotations (``scene.json``)."""
        return self.scene.annotations


def load_scene(
    scene: str | os.PathLike[str], *, scenes: Sequence[str | os.PathLike[str]] = ()
) -> LoadedScene:
    """A built scene, by directory (one holding ``scene.json``) or by id.

    An id is looked for along the scene search path (:func:`navverse.scene.locate.find_scene_dirs`):
    ``scenes``, then ``$NAVVERSE_SCENES``, then the workspace's build store.
    """
    from navverse.nav.scene_navmesh import load_scene_navmesh
    from navverse.scene.directory import SceneFiles, read_scene
    from navverse.scene.locate import find_scene_dirs

    given = Path(scene)
    if (given / "scene.json").is_file():
        directory = given
    else:
        directory = find_scene_dirs([str(scene)], search=scenes, built_dir=_workspace_built_dir)[str(scene)]
    has_navmesh = SceneFiles(directory).navmesh.is_file()
    return LoadedScene(
        directory, read_scene(directory), load_scene_navmesh(directory) if has_navmesh else None
    )


def _workspace_built_dir() -> Path:
    """The build store of the workspace here (the last place of the scene search path)."""
    from navverse.cli import workspace_built_dir

    return workspace_built_dir()


# ---------------------------------------------------------------------------------------------- env


class EpisodeEnv(gymnasium.Wrapper):
    """A :class:`~navverse.env.NavVerseEnv` that starts the episodes of a dataset, in turn.

    ``reset()`` starts the next of its episodes (the first after construction, cycling), with the
    dataset's category ids for the ``goal_id`` observation; ``reset(options={"episode": ...})`` still
    starts any episode. :attr:`episode` is the episode running.
    """

    def __init__(
        self, env: NavVerseEnv, episodes: Sequence[Any], category_ids: Mapping[str, Mapping[str, int]]
    ):
        super().__init__(env)
        self._episodes = list(episodes)
        self._category_ids = category_ids
        self._next = 0
        self.episode = self._episodes[0]

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        """Start the next episode (or the one in ``options``)."""
        options = dict(options or {})
        if "episode" not in options:
            self.episode = self._episodes[self._next % len(self._episodes)]
            self._next += 1
            options["episode"] = self.episode.model_dump(mode="json")
            options.setdefault("category_ids", dict(self._category_ids.get(self.episode.task, {})))
        return self.env.reset(seed=seed, options=options)


def make_env(
    dataset: str | os.PathLike[str],
    episode_id: str | None = None,
    *,
    split: str | None = None,
    scenes: Sequence[str | os.PathLike[str]] = (),
    **env_options: Any,
) -> EpisodeEnv:
    """An environment on a dataset episode's scene that starts that episode at ``reset()``.

    Parameters
    ----------
    dataset : path
        ``episodes/<name>/v<version>``.
    episode_id : str, optional
        The episode; without one, every episode of the first scene of ``split`` (default: the first
        split), in turn.
    split : str, optional
        The split the episodes are taken from when no ``episode_id`` is given.
    scenes : sequence of path
        Where to look for the scene first (scene packs or build stores; then ``$NAVVERSE_SCENES``, then
        the workspace).
    **env_options
        :class:`~navverse.env.NavVerseEnv` options (``embodiment``, ``action_mode``, ``sensors``,
        ``reward``, ``instruction_type``...).
    """
    from navverse.dataset import Dataset
    from navverse.env import NavVerseEnv

    data = Dataset(dataset)
    if episode_id is not None:
        episodes = [data.episode(episode_id)]
        split = next(
            s for s in data.splits if any(e.episode_id == episode_id for e in data.episodes(split=s))
        )
    else:
        split = split or data.splits[0]
        every = list(data.episodes(split=split))
        if not every:
            raise ApiError(f"split {split!r} of {data.root} has no episodes")
        episodes = [e for e in every if e.scene_id == every[0].scene_id]
    directory = data.scene_dir(episodes[0], search=scenes, built_dir=_workspace_built_dir)
    env_options.setdefault("embodiment", data.manifest.embodiment)
    env = NavVerseEnv(directory, **env_options)
    ids = {task: data.file(split, task).category_to_task_category_id for task in data.tasks(split)}
    return EpisodeEnv(env, episodes, ids)


# ---------------------------------------------------------------------------------------------- generate


def generate_building(
    building_type: str, *, seed: int = 0, scene_id: str | None = None, **options: Any
) -> Scene:
    """A furnished procedural building as a scene, in-process (no engine, no files).

    ``options`` are those of :class:`~navverse.indoor.building.BuildingOptions` (``length``,
    ``depth``, ``density``, ``exclude_categories``...), the ``indoor_layout`` stage's recipe keys,
    checked as a recipe's are; the same type, seed and options give the same scene.
    Write it with :func:`navverse.scene.write_scene_dir`, or build its navmesh with
    :func:`navverse.nav.scene_navmesh.build_scene_navmesh`.
    """
    import numpy as np
    from pydantic import ValidationError

    from navverse.indoor.building import BuildingOptions, BuildingSettings
    from navverse.indoor.building import generate_building as generate
    from navverse.indoor.programs import PROGRAMS

    if building_type not in PROGRAMS:
        raise ApiError(f"unknown building type {building_type!r}; choose from: {', '.join(PROGRAMS)}")
    unknown = sorted(set(options) - set(BuildingOptions.model_fields))
    if unknown:
        known = ", ".join(BuildingOptions.model_fields)
        raise ApiError(f"unknown building options {unknown}; the building options are: {known}")
    try:
        chosen = BuildingSettings(building_type=building_type, **options)
    except ValidationError as exc:
        raise ApiError(f"building options: {exc}") from None
    return generate(
        building_type,
        np.random.default_rng(seed),
        scene_id=scene_id or f"{building_type}-s{seed}",
        options=BuildingOptions.of(chosen),
    )


@dataclass(frozen=True)
class GeneratedCity:
    """A synthetic city: its map (the records of a real one), street plan and scene (unpopulated)."""

    map: CityMap
    plan: StreetPlan
    scene: Scene


def generate_city(
    *, seed: int = 0, scene_id: str | None = None, geometry: Mapping[str, Any] | None = None, **params: Any
) -> GeneratedCity:
    """A synthetic city drawn from a seed, in-process: its map, street plan and 3-D scene.

    ``params`` are those of :class:`~navverse.city.synthetic.params.SyntheticCityParams` (``size``,
    ``layout``...), ``geometry`` those of :class:`~navverse.city.geometry.scene.CityGeometry` (as the
    ``city_geometry`` stage's: ``relief_height``, ``road_depression``...); the same seed and parameters
    give the same city (its hills too).
    """
    from pydantic import ValidationError

    from navverse.city.geometry.scene import CityGeometry, city_scene, geometry_plan
    from navverse.city.synthetic.generator import SyntheticCityParams, synthetic_city

    try:
        chosen = SyntheticCityParams(**params)
    except ValidationError as exc:
        raise ApiError(f"synthetic city parameters: {exc}") from None
    try:
        settings = CityGeometry(**dict(geometry or {}))
    except ValidationError as exc:
        raise ApiError(f"city geometry parameters: {exc}") from None
    city_map = synthetic_city(chosen, seed=seed)
    plan = geometry_plan(city_map, settings)
    scene = city_scene(
        city_map, scene_id=scene_id or f"synthetic-s{seed}", geometry=settings, plan=plan, seed=seed
    )
    return GeneratedCity(map=city_map, plan=plan, scene=scene)
