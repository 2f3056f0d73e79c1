"""The package_dataset stage: the versioned dataset of verified episodes, with scene-disjoint splits."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, field_validator

from pipeline import Input, StageContext, stage
from stages._review_step import RELEASE_SUMMARY, ReleaseParams, apply_review, release_stats


class PackageDatasetParams(ReleaseParams):
    """Parameters of :func:`package_dataset`: the version published and the review applied
    (:class:`~stages._review_step.ReleaseParams`), the scene-disjoint ``splits`` and the ``quota``.

    A recipe samples more candidates than it needs, from measured acceptance rates, and the quota
    keeps that many (:func:`~navverse.episodes.packaging.apply_quota`).
    """

    splits: dict[Annotated[str, Field(pattern=r"^[a-z][a-z0-9_]*$")], list[str]]
    """Glob patterns over scene ids (``fnmatch``, case-sensitive) by split name (lower_snake_case),
    e.g. ``{train: ['*-s0'], eval: ['*-s1']}``; every scene must fall in exactly one split, and every
    split get a scene."""
    quota: (
        dict[
            Annotated[str, Field(pattern=r"^[a-z][a-z0-9_]*$")],
            dict[Literal["objnav", "placenav", "vln"], Annotated[int, Field(ge=1, le=1_000_000)]],
        ]
        | None
    ) = None
    """Most episodes kept per split and task, e.g. ``{train: {objnav: 2200}, eval: {objnav: 150}}``,
    spread evenly over the split's scenes; a split and task left short of its quota is a warning.
    Null, or a split or task left out: every episode is kept."""

    @field_validator("splits")
    @classmethod
    def _some(cls, value: dict[str, list[str]]) -> dict[str, list[str]]:
        if not value or any(not globs for globs in value.values()):
            raise ValueError(
                "give every split a list of scene id patterns, e.g. {train: ['*-s0'], eval: ['*-s1']}"
            )
        return value


@stage(
    name="package_dataset",
    inputs=["verified", "instructions", Input("scene", many=True)],
    outputs=["dataset"],
    summary=RELEASE_SUMMARY,
)
def package_dataset(ctx: StageContext, params: PackageDatasetParams) -> None:
    """<name>/v<version>/: <split>/<task>.json.gz, the rollouts beside them, and manifest.json."""
    from navverse import __version__
    from navverse.dataset import Episode, Instruction, read_json_gz
    from navverse.episodes import files
    from navverse.episodes.packaging import apply_quota, assign_splits, write_dataset
    from navverse.scene.directory import read_annotations, scene_hash

    verified = read_json_gz(ctx.input("verified") / files.EPISODES)
    rollouts = read_json_gz(ctx.input("verified") / files.ROLLOUTS)
    instructions = read_json_gz(ctx.input("instructions") / files.INSTRUCTIONS)
    episodes = []
    for raw in verified["episodes"]:
        episode = Episode.model_validate(raw)
        if episode.task == "vln":
            if episode.episode_id not in instructions:
                continue  # dropped for want of landmarks
            instruction = Instruction.model_validate(instructions[episode.episode_id])
            episode = episode.model_copy(update={"instruction": instruction})
        elif episode.task == "placenav":
            if episode.episode_id not in instructions:
                continue  # its route instruction was dropped
            by_type = {k: Instruction.model_validate(v) for k, v in instructions[episode.episode_id].items()}
            episode = episode.model_copy(update={"instructions": by_type})
        episodes.append(episode)
    scene_dirs = {read_annotations(path).scene_id: path for path in ctx.inputs["scene"]}
    splits = assign_splits(sorted(scene_dirs), params.splits)
    name = params.name or ctx.target
    quota_report = {}
    if params.quota:
        episodes, quota_report = apply_quota(episodes, splits, params.quota, seed=ctx.seed)
        for split, tasks in quota_report.items():
            for task, cell in tasks.items():
                if cell["kept"] < cell["quota"]:
                    ctx.log.warning(
                        "%s %s: %d episodes, short of its quota of %d: sample more candidates per scene",
                        split, task, cell["kept"], cell["quota"],
                    )  # fmt: skip
    episodes, version = apply_review(ctx, params.review, params.version, name, episodes)
    manifest = write_dataset(
        ctx.output / name / f"v{version}",  # laid out as published under episodes/
        episodes,
        rollouts,
        name=name,
        version=version,
        splits=splits,
        embodiment=verified["embodiment"],
        recipe=f"recipes/{ctx.recipe}",
        recipe_hash=ctx.recipe_hash,
        scene_hashes={scene: scene_hash(path) for scene, path in scene_dirs.items()},
        toolkit_version=__version__,
    )
    ctx.record(
        episodes=len(episodes),
        counts=manifest.counts,
        quota=quota_report,
        difficulty_thresholds={k: list(v) for k, v in manifest.difficulty_thresholds.items()},
        **release_stats(manifest.name, manifest.version, manifest.counts),
    )
    ctx.log.info(
        "dataset %s v%s: %d episodes in %s", manifest.name, manifest.version, len(episodes), ", ".join(splits)
    )
