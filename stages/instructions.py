"""The instructions stage: landmark-grounded VLN instructions, and PlaceNav's three instruction types."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field

from navverse.episodes.instructions.settings import InstructionSettings
from pipeline import Input, Params, StageContext, stage


class InstructionsParams(Params, InstructionSettings):
    """Parameters of :func:`instructions` (Appendix D.3): those of
    :class:`navverse.episodes.instructions.settings.InstructionSettings`, and the refiner.

    Each verified VLN episode gets a template (turns and distances along the simplified reference path,
    aligned to its rollout) and a rewrite naming landmarks, objects seen by the robot's camera near each
    turn, by colour and category, without distances. Episodes naming fewer than ``min_landmarks``
    landmarks are dropped. ``max_landmark_distance`` bounds how far (m) a landmark may be from the
    camera and from its turn. An optional ``refiner`` (for instance wrapping a vision-language model)
    writes the final text.

    Each verified PlaceNav episode gets its three instruction types: ``category`` ("Find a bank."),
    ``route`` (the same machinery along its reference path, naming the place, and telling the
    stretches along a road as following the street) and ``intention`` ("I need to withdraw some
    cash."); one whose route instruction is dropped is dropped.
    """

    refiner: Annotated[str, Field(pattern=r"^[A-Za-z_][\w.]*:[A-Za-z_][\w.]*$")] | None = None
    """A callable named ``"package.module:function"`` (the attribute may be dotted) that receives the
    keyframes (camera images at each directive), the template text, the landmark text and the episode,
    and returns the final instruction text, or None to drop the episode. Null: the landmark text is kept."""


@stage(
    name="instructions",
    inputs=["verified", Input("scene", many=True)],
    outputs=["instructions"],
    summary={"episodes": "episodes", "written": "written", "dropped": "dropped_by_reason"},
)
def instructions(ctx: StageContext, params: InstructionsParams) -> None:
    """instructions.json.gz (per VLN episode id its instruction, per PlaceNav one {type: instruction}) and
    dropped.json.gz (episode id -> reason)."""
    from collections import Counter

    import numpy as np

    from navverse.episodes import files
    from navverse.episodes.instructions.writer import load_refiner
    from navverse.records.jsongz import read_json_gz, write_json_gz
    from navverse.records.schema import Episode
    from navverse.scene.directory import read_annotations

    if params.refiner:
        load_refiner(params.refiner)  # a wrong name fails here, before any scene is read
    verified = read_json_gz(ctx.input("verified") / files.EPISODES)
    rollouts = read_json_gz(ctx.input("verified") / files.ROLLOUTS)
    by_scene: dict[str, list[Episode]] = {}
    for raw in verified["episodes"]:
        episode = Episode.model_validate(raw)
        if episode.task in ("vln", "placenav"):
            by_scene.setdefault(episode.scene_id, []).append(episode)
    scene_dirs = {read_annotations(path).scene_id: path for path in ctx.inputs["scene"]}
    missing = sorted(set(by_scene) - set(scene_dirs))
    if missing:
        raise RuntimeError(f"VLN or PlaceNav episodes of scenes that are not linked: {', '.join(missing)}")
    settings = InstructionSettings.of(params)
    total = sum(map(len, by_scene.values()))
    ctx.progress(0, total, "writing")
    jobs = [
        (
            scene_dirs[scene_id],
            episodes,
            {e.episode_id: rollouts[e.episode_id] for e in episodes},
            verified["embodiment"],
            settings,
            params.refiner,
            ctx.seed,
        )
        for scene_id, episodes in sorted(by_scene.items())
    ]
    written, dropped = {}, {}
    for scene_written, scene_dropped in ctx.map(_write_scene, jobs, chunksize=1):  # a scene per job
        written.update(scene_written)
        dropped.update(scene_dropped)
    ctx.progress(total, total, "written")
    write_json_gz(written, ctx.output / files.INSTRUCTIONS)
    write_json_gz(dropped, ctx.output / files.DROPPED)
    why = Counter(reason.split(":")[0] for reason in dropped.values())
    ctx.record(
        episodes=total,
        written=len(written),
        dropped=len(dropped),
        dropped_by_reason=dict(sorted(why.items())),
        landmarks_per_instruction=round(
            float(np.mean([len(_route(i)["landmarks"]) for i in written.values()])) if written else 0.0, 3
        ),
    )
    ctx.log.info(
        "%d of %d VLN and PlaceNav episodes have instructions; %d dropped", len(written), total, len(dropped)
    )


def _route(written: dict) -> dict:
    """The landmark-bearing instruction of a written record (a VLN one, or a PlaceNav one's route)."""
    return written.get("route", written)


def _write_scene(job: tuple) -> tuple[dict[str, dict], dict[str, str]]:
    """The instructions of one scene's episodes (a ``ctx.map`` job: its renderer and landmark views
    are this process's own); each episode draws from a generator seeded from (stage seed, episode id),
    so the texts do not depend on where or in which order scenes are written."""
    import zlib

    import numpy as np

    from navverse.episodes.instructions import (
        PLACE_NAMES,
        RoadFollowing,
        category_instruction,
        intention_instruction,
    )
    from navverse.episodes.instructions.writer import InstructionWriter, load_refiner
    from navverse.records.schema import Instruction
    from navverse.scene.directory import read_scene
    from navverse.sim.embodiments import make_embodiment

    scene_dir, episodes, rollouts, embodiment, settings, refiner_name, seed = job
    refiner = load_refiner(refiner_name) if refiner_name else None
    scene = read_scene(scene_dir)
    camera_to_base = make_embodiment(embodiment).camera_to_base
    writer = InstructionWriter(scene, camera_to_base=camera_to_base, settings=settings, refiner=refiner)
    roads = RoadFollowing(scene)
    written: dict[str, dict] = {}
    dropped: dict[str, str] = {}
    for episode in episodes:
        rng = np.random.default_rng([seed, zlib.crc32(episode.episode_id.encode())])
        rollout = np.asarray(rollouts[episode.episode_id])
        if episode.task == "vln":
            instruction, reason = writer.write(episode, rollout, rng, roads=roads)
            if instruction is None:
                dropped[episode.episode_id] = reason
            else:
                written[episode.episode_id] = instruction.model_dump(mode="json")
            continue
        category = episode.goal_category
        route, reason = writer.write(episode, rollout, rng, goal=PLACE_NAMES[category], roads=roads)
        if route is None:
            dropped[episode.episode_id] = reason
            continue
        texts = {
            "category": category_instruction(category, rng),
            "intention": intention_instruction(category, rng),
        }
        written[episode.episode_id] = {
            "category": Instruction(
                instruction_text=texts["category"],
                template_text=texts["category"],
                instruction_type="category",
            ).model_dump(mode="json"),
            "route": route.model_copy(update={"instruction_type": "route"}).model_dump(mode="json"),
            "intention": Instruction(
                instruction_text=texts["intention"],
                template_text=texts["intention"],
                instruction_type="intention",
            ).model_dump(mode="json"),
        }
    return written, dropped
