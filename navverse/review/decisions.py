"""The review decisions file: a person's accept / reject decisions on a dataset's episodes.

``recipes/datasets/<name>.review.yml`` sits next to the dataset recipe, written by the review page
(``navverse review``) and read by the ``package_dataset`` stage when the recipe names it
(``package_dataset: {review: <name>.review.yml}``)::

    dataset: navverse-mini
    decisions:
      apartment-s0-objnav-0003: {at: '2025-01-01T10:00:00+00:00', decision: reject, reason: goal behind glass}
    reviewed_version: '1.1'

``reviewed_version`` is the newest version of the dataset when its set of rejected episodes last
changed; the next build publishes ``MAJOR.(MINOR + 1)`` of it when it leaves episodes out
(:func:`published_version`). The file is YAML with sorted keys, written whole and atomically, so the
same decisions give the same bytes. Reading is bounded: a regular file of at most
:data:`MAX_REVIEW_BYTES`, no YAML aliases, every field checked; a malformed file is a
:class:`ReviewError` naming the file, the entry and what to do.

The name ends in ``.review.yml``, not ``.yaml``: the recipe loader reads every ``*.yaml`` under
``recipes/`` as a recipe.
"""

from __future__ import annotations

import hashlib
import os
import re
import stat
from collections.abc import Mapping
from datetime import datetime
from pathlib import Path
from typing import Annotated, Any, Literal

import yaml
from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, ValidationError, model_validator

from navverse.errors import NavverseError
from navverse.files import atomic_write

__all__ = [
    "MAX_REASON_CHARS",
    "MAX_REVIEW_BYTES",
    "REVIEW_SUFFIX",
    "Decision",
    "Review",
    "ReviewError",
    "newest_version",
    "published_version",
    "read_review",
    "read_review_sha256",
    "review_bytes",
    "review_path",
    "version_key",
    "with_decision",
    "write_review",
]

REVIEW_SUFFIX = ".review.yml"
"""Ending of a decisions file's name: ``<dataset name>.review.yml`` beside the recipe."""
MAX_REVIEW_BYTES = 16 << 20
"""Largest decisions file read (bytes): about 100,000 decisions with long reasons."""
MAX_REASON_CHARS = 2000
"""Longest reason kept with a decision (characters)."""

_VERSION = r"^\d+\.\d+$"
_NAME = r"^[A-Za-z0-9][A-Za-z0-9._-]*$"
_CONFIG = ConfigDict(extra="forbid", frozen=True)


class ReviewError(NavverseError):
    """A decisions file is missing, malformed, or does not fit the dataset it is applied to."""


def _iso_text(value: Any) -> Any:
    """A YAML timestamp left unquoted by hand is taken as its ISO text; text must be an ISO time."""
    if isinstance(value, datetime):
        return value.isoformat()
    if isinstance(value, str):
        try:
            datetime.fromisoformat(value)
        except ValueError:
            raise ValueError(f"{value!r} is not an ISO 8601 time (e.g. 2025-01-31T09:30:00+00:00)") from None
    return value


class Decision(BaseModel):
    """One episode's decision: ``accept`` or ``reject``, why, and when (ISO 8601 text)."""

    model_config = _CONFIG

    decision: Literal["accept", "reject"]
    reason: Annotated[str, Field(max_length=MAX_REASON_CHARS)] = ""
    at: Annotated[str, BeforeValidator(_iso_text)]

    @model_validator(mode="after")
    def _reason_for_reject(self) -> Decision:
        if self.decision == "reject" and not self.reason.strip():
            raise ValueError("a rejection needs a reason (what is wrong with the episode)")
        return self


class Review(BaseModel):
    """A decisions file: the dataset, the version the rejections apply past, and the decisions by episode."""

    model_config = _CONFIG

    dataset: Annotated[str, Field(pattern=_NAME, max_length=200)]
    reviewed_version: Annotated[str, Field(pattern=_VERSION)]
    decisions: dict[Annotated[str, Field(pattern=_NAME, max_length=200)], Decision] = {}

    @property
    def rejected(self) -> frozenset[str]:
        """Ids of the rejected episodes."""
        return frozenset(k for k, v in self.decisions.items() if v.decision == "reject")


# ---------------------------------------------------------------------------------------------- versions


def version_key(version: str) -> tuple[int, int]:
    """``MAJOR.MINOR`` as a pair of integers, for comparing versions."""
    major, minor = version.split(".")
    return int(major), int(minor)


def newest_version(*versions: str | None) -> str:
    """The highest of the versions given (None entries ignored)."""
    return max((v for v in versions if v is not None), key=version_key)


def published_version(recipe_version: str, review: Review, *, left_out: int) -> str:
    """The version a build with this review publishes.

    No episode left out: the recipe's version (the content is the unreviewed build's). Otherwise the
    recipe's major with its minor bumped past the reviewed version: reviewed ``1.1`` publishes ``1.2``
    (a recipe already at ``1.5`` stays ``1.5``), so the new content never lands on a published version.

    Raises
    ------
    ReviewError
        If the reviewed version has another major than the recipe's (the review was of another
        generation of the dataset).
    """
    if left_out == 0:
        return recipe_version
    major, minor = version_key(recipe_version)
    reviewed_major, reviewed_minor = version_key(review.reviewed_version)
    if reviewed_major != major:
        raise ReviewError(
            f"the review of {review.dataset} is of version {review.reviewed_version} but the recipe builds "
            f"{recipe_version}: review the {major}.x dataset (navverse review) or remove package_dataset: "
            "review from the recipe"
        )
    return f"{major}.{max(minor, reviewed_minor + 1)}"


# ---------------------------------------------------------------------------------------------- files


def review_path(recipe: str | os.PathLike[str], name: str) -> Path:
    """The decisions file of dataset ``name`` built by ``recipe``: ``<recipe folder>/<name>.review.yml``."""
    return Path(recipe).parent / f"{name}{REVIEW_SUFFIX}"


class _NoAliases(yaml.SafeLoader):
    """Safe YAML without aliases: a decisions file is flat data, never worth an alias's expansion."""

    def compose_node(self, parent: Any, index: Any) -> Any:
        if self.check_event(yaml.AliasEvent):
            mark = self.peek_event().start_mark
            raise yaml.YAMLError(f"line {mark.line + 1}: aliases (*name) are not allowed here")
        return super().compose_node(parent, index)


def _problem(exc: ValidationError) -> str:
    error = exc.errors()[0]
    where = ".".join(str(p) for p in error["loc"]) or "top level"
    more = f" (and {exc.error_count() - 1} more problems)" if exc.error_count() > 1 else ""
    return f"{where}: {error['msg'].removeprefix('Value error, ')}{more}"


def _read_bytes(path: Path) -> bytes:
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise ReviewError(f"no decisions file {path}: review the dataset with `navverse review`") from None
    if not stat.S_ISREG(info.st_mode):
        raise ReviewError(f"{path} is not a regular file; a decisions file is YAML text")
    if info.st_size > MAX_REVIEW_BYTES:
        raise ReviewError(f"{path} is {info.st_size} bytes, over the {MAX_REVIEW_BYTES}-byte limit")
    with open(path, "rb") as handle:
        return handle.read(MAX_REVIEW_BYTES + 1)[:MAX_REVIEW_BYTES]


def read_review(path: str | os.PathLike[str], *, dataset: str | None = None) -> Review:
    """Read and validate a decisions file.

    Parameters
    ----------
    path : path
        The ``<name>.review.yml`` file.
    dataset : str, optional
        The dataset it must be about.

    Returns
    -------
    Review

    Raises
    ------
    ReviewError
        If it is missing, not a regular file, too large, not YAML, malformed (naming the entry), or
        about another dataset.
    """
    return read_review_sha256(path, dataset=dataset)[0]


def read_review_sha256(path: str | os.PathLike[str], *, dataset: str | None = None) -> tuple[Review, str]:
    """:func:`read_review`, with the SHA-256 of the very bytes read (hex)."""
    path = Path(path)
    data = _read_bytes(path)
    try:
        loaded = yaml.load(data.decode("utf-8"), Loader=_NoAliases)
    except (UnicodeDecodeError, yaml.YAMLError) as exc:
        raise ReviewError(f"{path} is not readable YAML: {exc}") from None
    if not isinstance(loaded, Mapping):
        raise ReviewError(f"{path} must be a mapping {{dataset, reviewed_version, decisions}}")
    try:
        review = Review.model_validate(dict(loaded))
    except ValidationError as exc:
        raise ReviewError(
            f"{path} is malformed: {_problem(exc)}. Fix it, or record the decisions again with "
            "`navverse review`"
        ) from None
    if dataset is not None and review.dataset != dataset:
        raise ReviewError(f"{path} reviews dataset {review.dataset!r}, not {dataset!r}")
    return review, hashlib.sha256(data).hexdigest()


def review_bytes(review: Review) -> bytes:
    """The file's bytes: YAML with sorted keys, block style; the same review, the same bytes."""
    text = yaml.safe_dump(
        review.model_dump(mode="json"), sort_keys=True, allow_unicode=True, default_flow_style=False
    )
    return text.encode("utf-8")


def write_review(path: str | os.PathLike[str], review: Review) -> None:
    """Write a decisions file atomically (a reader sees the old file or the new one, never half)."""
    with atomic_write(path) as handle:
        handle.write(review_bytes(review))


def with_decision(
    review: Review, episode_id: str, *, decision: str, reason: str, at: str, newest: str
) -> Review:
    """The review with one episode's decision recorded (replacing an earlier one).

    Parameters
    ----------
    review : Review
        The decisions so far.
    episode_id : str
        The episode decided on.
    decision : {"accept", "reject"}
    reason : str
        Why (required for a rejection); surrounding white space is dropped.
    at : str
        When, ISO 8601.
    newest : str
        The newest published version of the dataset. When the set of rejected episodes changes,
        ``reviewed_version`` moves up to it, so the next build publishes past every published version.

    Raises
    ------
    ReviewError
        If the decision is malformed (unknown decision, a rejection without reason, a reason too long).
    """
    try:
        entry = Decision(decision=decision, reason=re.sub(r"\s+", " ", reason).strip(), at=at)
    except ValidationError as exc:
        raise ReviewError(f"decision on {episode_id}: {_problem(exc)}") from None
    decisions = {**review.decisions, episode_id: entry}
    update: dict[str, Any] = {"decisions": dict(sorted(decisions.items()))}
    was_rejected = episode_id in review.rejected
    if was_rejected != (entry.decision == "reject"):
        update["reviewed_version"] = newest_version(review.reviewed_version, newest)
    try:
        return Review.model_validate({**review.model_dump(), **update})
    except ValidationError as exc:
        raise ReviewError(f"decision on {episode_id}: {_problem(exc)}") from None
