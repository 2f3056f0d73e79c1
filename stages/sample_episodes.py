"""The sample_episodes stage: episode candidates drawn on the navmeshes of a dataset's scenes."""

from __future__ import annotations

import zlib
from collections import Counter
from typing import Annotated, Literal

from pydantic import AfterValidator, Field, model_validator

from navverse.episodes.sampling import SamplingSettings
from navverse.scene.categories import CATEGORY_PATTERN, CategoryRule, unmatched_rules
from pipeline import Input, Params, StageContext, stage

_TASKS_OF = {"objnav": ("objnav", "vln"), "placenav": ("placenav",)}
"""The tasks whose goals are object categories, and those whose goals are place categories."""


def _known_embodiment(name: str) -> str:
    from navverse.sim.embodiments import EMBODIMENTS

    if name not in EMBODIMENTS:
        raise ValueError(f"unknown embodiment {name!r} (known: {', '.join(sorted(EMBODIMENTS))})")
    return name


class TaskParams(Params):
    """How many candidates of a task to draw per scene."""

    episodes_per_scene: Annotated[int, Field(ge=0, le=10_000)]
    """Candidates of the task drawn in each scene (fewer where goals or attempts run out: a warning)."""


class SampleEpisodesParams(Params, SamplingSettings):
    """Parameters of :func:`sample_episodes`: those of :class:`navverse.episodes.sampling.SamplingSettings`
    and the tasks, goals and robot.

    Object goals (ObjectNav, VLN) are the objects whose category, after ``goal_rules``, is in
    ``categories``; PlaceNav goals are storefronts of ``place_categories``. Paths to a goal instance
    must be ``path_length`` long (m); the start faces the path, turned by up to ``yaw_jitter_deg``.
    ``start_region: auto`` starts indoor-to-outdoor episodes inside the building.
    """

    tasks: dict[Literal["objnav", "vln", "placenav"], TaskParams]
    """The tasks sampled (``objnav``, ``vln``, ``placenav``; at least one) and the candidates of each
    drawn per scene."""
    categories: list[Annotated[str, Field(pattern=CATEGORY_PATTERN)]] | None = None
    """Object categories (lower_snake_case) that are goals of ObjectNav and VLN episodes; null: every
    category. A category with no instance in any scene is a warning."""
    place_categories: list[str] | None = None
    """Place categories of the storefronts that are goals of PlaceNav episodes; null: every category.
    A category with no storefront in any scene is a warning."""
    goal_rules: list[CategoryRule] = []
    """Rules that rename objects before goals are chosen: tried in order on each object's prim name (or
    path), the first match gives its category (``category: null`` drops the object); unmatched objects
    keep their own. A rule that matches no object is a warning."""
    embodiment: Annotated[str, AfterValidator(_known_embodiment)] = "spot"
    """The robot (``spot`` or ``turtlebot``): its radius r_robot sets the success distance (the scene
    type's success margin + r_robot), and goal distances are measured from its standing base height;
    the verification stage uses the same robot."""

    @model_validator(mode="after")
    def _some_task(self) -> SampleEpisodesParams:
        if not self.tasks:
            raise ValueError("name at least one task under 'tasks' (objnav, vln, placenav)")
        return self


@stage(
    name="sample_episodes",
    inputs=[Input("scene", many=True)],
    outputs=["candidates"],
    summary={"candidates": "per_task", "scenes": "scenes"},
)
def sample_episodes(ctx: StageContext, params: SampleEpisodesParams) -> None:
    """candidates.json.gz: episode candidates of every task in every linked scene, with their statistics."""
    from navverse.episodes import files
    from navverse.records.jsongz import write_json_gz
    from navverse.scene.directory import read_annotations
    from navverse.sim.embodiments import make_embodiment

    robot = make_embodiment(params.embodiment)
    scenes = sorted((read_annotations(path).scene_id, path) for path in ctx.inputs["scene"])
    body = (robot.radius, robot.standing_height)
    jobs = [(scene_id, path, ctx.seed, params, body) for scene_id, path in scenes]
    ctx.progress(0, len(scenes), "sampling")
    episodes = []
    per_scene: dict[str, dict[str, int]] = {}
    hits = [0] * len(params.goal_rules)
    found: dict[str, set[str]] = {"objnav": set(), "placenav": set()}  # goal categories with an instance
    for scene_id, sampled in zip(
        (s for s, _ in scenes), ctx.map(_sample_scene, jobs, chunksize=1), strict=True
    ):
        episodes.extend(sampled["episodes"])
        per_scene[scene_id] = sampled["counts"]
        hits = [a + b for a, b in zip(hits, sampled["hits"], strict=True)]
        for key, names in sampled["found"].items():
            found[key].update(names)
        for message in sampled["short"]:
            ctx.log.warning("%s", message)
    for warning in unmatched_rules(params.goal_rules, hits):
        ctx.log.warning("%s", warning)
    for kind, asked, key in (("categories", params.categories, "objnav"),
                             ("place_categories", params.place_categories, "placenav")):  # fmt: skip
        absent = sorted(set(asked or ()) - found[key])
        if asked is not None and absent and any(t in params.tasks for t in _TASKS_OF[key]):
            ctx.log.warning(
                "%s %s: no instance in any of the %d scenes; check the names (navverse list categories)",
                kind, ", ".join(absent), len(scenes),
            )  # fmt: skip
    ctx.progress(len(scenes), len(scenes), "written")
    write_json_gz(
        {
            "embodiment": params.embodiment,
            "robot_radius": robot.radius,
            "episodes": [e.model_dump(mode="json") for e in episodes],
        },
        ctx.output / files.CANDIDATES,
    )
    per_task = Counter(e.task for e in episodes)
    ctx.record(
        candidates=len(episodes),
        scenes=len(scenes),
        per_scene=per_scene,
        per_task=dict(sorted(per_task.items())),
    )
    ctx.log.info("%d candidates in %d scenes", len(episodes), len(scenes))


def _sample_scene(job: tuple) -> dict:
    """The candidates of one scene (a ``ctx.map`` job): per task, drawn with a generator seeded from
    (stage seed, scene id, task), so the result does not depend on where or in which order it runs."""
    import numpy as np

    from navverse.episodes.sampling import object_goals, place_goals, sample_scene_episodes
    from navverse.nav.scene_navmesh import load_scene_navmesh
    from navverse.scene.directory import read_annotations

    scene_id, path, seed, params, (robot_radius, base_height) = job
    settings = SamplingSettings.of(params)
    annotations = read_annotations(path)
    finder = load_scene_navmesh(path)
    out: dict = {"episodes": [], "counts": {}, "hits": [0] * len(params.goal_rules), "short": []}
    out["found"] = {"objnav": set(), "placenav": set()}
    for task_index, (task, spec) in enumerate(sorted(params.tasks.items())):
        if task == "placenav":
            goals = place_goals(annotations, categories=params.place_categories)
        else:
            goals = object_goals(
                annotations, rules=params.goal_rules, categories=params.categories, hits=out["hits"]
            )
        out["found"]["placenav" if task == "placenav" else "objnav"].update(goals)
        rng = np.random.default_rng([seed, zlib.crc32(scene_id.encode()), task_index])
        sample = sample_scene_episodes(
            finder, annotations, goals, task=task, count=spec.episodes_per_scene, rng=rng,
            robot_radius=robot_radius, base_height=base_height, settings=settings,
        )  # fmt: skip
        out["episodes"].extend(sample.episodes)
        out["counts"][task] = len(sample.episodes)
        if len(sample.episodes) < spec.episodes_per_scene:
            why = "no reachable goal category" if not sample.categories else "attempts used up"
            out["short"].append(
                f"{scene_id}: {len(sample.episodes)} of {spec.episodes_per_scene} {task} candidates ({why})"
            )
    return out
