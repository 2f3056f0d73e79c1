"""What the stages that package a dataset share: the version they publish, and applying the decisions
of ``navverse review``."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

from pydantic import Field

from pipeline import Params, SourceFile, StageContext

if TYPE_CHECKING:
    from navverse.dataset import Episode


class ReleaseParams(Params):
    """The dataset version a packaging stage publishes (``episodes/<name>/v<version>``) and the review
    decisions applied to it."""

    version: Annotated[str, Field(pattern=r"^\d+\.\d+$")]
    """``MAJOR.MINOR``; a published version never changes, so bump it when the content changes."""
    name: Annotated[str, Field(pattern=r"^[a-z0-9][a-z0-9._-]*$")] | None = None
    """The dataset's name; None: the target id."""
    review: SourceFile | None = None
    """The decisions file of ``navverse review`` (``<name>.review.yml`` beside the recipe); its content
    is part of the cache key."""


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
