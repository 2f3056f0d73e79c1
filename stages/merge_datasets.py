"""The merge_datasets stage: one versioned dataset made of the built versions of several dataset recipes."""

from __future__ import annotations

from pipeline import Input, StageContext, stage
from stages._review_step import RELEASE_SUMMARY, ReleaseParams, apply_review, release_stats


class MergeDatasetsParams(ReleaseParams):
    """Parameters of :func:`merge_datasets`.

    The recipe links the parts (``links: {parts: {artifact: dataset, targets: [...]}}``): built dataset
    versions over different scenes, verified with the same robot. Each scene keeps the split its part
    gave it; difficulties are relabelled over all the episodes. ``version``, ``name`` and ``review``
    (the decisions file of ``navverse review``) are as for ``package_dataset``.
    """


@stage(
    name="merge_datasets",
    inputs=[Input("parts", artifact="dataset", many=True)],
    outputs=["dataset"],
    summary=RELEASE_SUMMARY,
)
def merge_datasets(ctx: StageContext, params: MergeDatasetsParams) -> None:
    """<name>/v<version>/: the linked datasets' episodes and rollouts packaged as one dataset."""
    from navverse import __version__
    from navverse.dataset import built_version, local_dataset
    from navverse.episodes.merging import merge_parts
    from navverse.episodes.packaging import write_dataset

    parts = sorted(
        (local_dataset(built_version(path)) for path in ctx.inputs["parts"]), key=lambda d: d.manifest.name
    )
    ctx.progress(0, 2, "merging")
    merged = merge_parts(parts)
    ctx.progress(1, 2, "writing")
    name = params.name or ctx.target
    episodes, version = apply_review(ctx, params.review, params.version, name, merged.episodes)
    manifest = write_dataset(
        ctx.output / name / f"v{version}",
        episodes,
        merged.rollouts,
        name=name,
        version=version,
        splits=merged.splits,
        embodiment=merged.embodiment,
        recipe=f"recipes/{ctx.recipe}",
        recipe_hash=ctx.recipe_hash,
        scene_hashes=merged.scene_hashes,
        toolkit_version=__version__,
    )
    ctx.progress(2, 2, "done")
    ctx.record(
        parts=merged.parts,
        episodes=len(episodes),
        counts=manifest.counts,
        difficulty_thresholds={k: list(v) for k, v in manifest.difficulty_thresholds.items()},
        **release_stats(manifest.name, manifest.version, manifest.counts),
    )
    ctx.log.info(
        "dataset %s v%s: %d episodes from %s",
        manifest.name, manifest.version, len(episodes), ", ".join(p["name"] for p in merged.parts),
    )  # fmt: skip
