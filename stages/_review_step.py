"""What the stages that package a dataset share: the version they publish, and applying the decisions
of ``navverse review``."""

from __future__ import annotations

from collections import Counter
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

from pydantic import Field

from pipeline import Params, SourceFile, StageContext

if TYPE_CHECKING:
    from navverse.dataset import Episode


RELEASE_SUMMARY = {
    "dataset": "dataset",
    "episodes": "counts",
    "by task": "per_task",
    "left out by review": "review.rejected",
}
"""What the build summary says a packaged dataset holds: its name and version, its episodes per split
and per task (:func:`release_stats`), and those the review left out (:func:`apply_review`)."""


def release_stats(
    name: str, version: str, counts: Mapping[str, Mapping[str, Mapping[str, int]]]
) -> dict[str, Any]:
    """The stats of :data:`RELEASE_SUMMARY` a packaging stage records besides its counts: ``dataset``
    (``<name> v<version>``) and ``per_task`` (episodes per task over every split and scene type)."""
    per_task: Counter[str] = Counter()
    for tasks in counts.values():
        for task, by_type in tasks.items():
            per_task[task] += sum(by_type.values())
    return {"dataset": f"{name} v{version}", "per_task": dict(sorted(per_task.items()))}


class ReleaseParams(Params):
    """The dataset version a packaging stage publishes (``episodes/<name>/v<version>``) and the review
    decisions applied to it."""

    version: Annotated[str, Field(pattern=r"^\d+\.\d+$")]
    """The version published, ``MAJOR.MINOR`` (the directory ``episodes/<name>/v<version>``); a published
    version never changes, so bump it when the content changes."""
    name: Annotated[str, Field(pattern=r"^[a-z0-9][a-z0-9._-]*$")] | None = None
    """The dataset's name (lowercase letters, digits, ``.``, ``_``, ``-``); null: the target id."""
    review: SourceFile | None = None
    """The decisions file of ``navverse review`` (``<name>.review.yml`` beside the recipe): the episodes
    it rejects are left out, and when any is, the minor version is bumped past the reviewed one
    (reviewed 1.1 publishes 1.2). Its content is part of the cache key; null: no review."""


def apply_review(
    ctx: StageContext, review_file: Path | None, version: str, name: str, episodes: list[Episode]
) -> tuple[list[Episode], str]:
    """The episodes the review file keeps and the version to publish; recorded in the manifest as
    ``review`` {file, sha256, reviewed_version, rejected (episodes left out), unknown (rejected ids
    this build does not have)}."""
    from navverse.review.decisions import published_version, read_review_sha256

    if review_file is None:
        return episodes, version
    review, sha256 = read_review_sha256(review_file, dataset=name)
    rejected = review.rejected
    kept = [e for e in episodes if e.episode_id not in rejected]
    unknown = sorted(rejected - {e.episode_id for e in episodes})
    if unknown:
        ctx.log.warning(
            "%d episodes rejected in %s are not in this build (e.g. %s); nothing to leave out for them",
            len(unknown), review_file.name, unknown[0],
        )  # fmt: skip
    left_out = len(episodes) - len(kept)
    published = published_version(version, review, left_out=left_out)
    ctx.record(
        review={
            "file": review_file.name,
            "sha256": sha256,
            "reviewed_version": review.reviewed_version,
            "rejected": left_out,
            "unknown": len(unknown),
        }
    )
    ctx.log.info("review %s: %d episodes left out, publishing v%s", review_file.name, left_out, published)
    return kept, published
