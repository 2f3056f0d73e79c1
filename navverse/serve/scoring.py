"""What a scoring process runs: the evaluator's scoring of one stored submission, reduced to the group
means the server publishes.

:func:`score_job` is what ``navverse eval`` does for a split (:func:`navverse.eval.submission.read_submission`
against the split's episodes and scene bounds, :func:`navverse.eval.scoring.score` over every episode of
the split, those without a valid record counted as failures), in a worker process of the server's pool:
the goals of a private split are read there, from the private directory, and only
:func:`public_result` leaves the process: per grouping of :data:`PUBLISHED` the means of every
metric with its N (``<metric>_n``), the label shares and the episode counts. Never a per-episode row: a
per-episode final distance would let a team triangulate hidden goals.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from navverse.dataset import Dataset
    from navverse.eval.scoring import EvalResult

__all__ = ["PUBLISHED", "SCOPE", "ScoringJob", "public_result", "score_job"]

PUBLISHED = ("overall", "task", "scene_type", "task_scene_type")
"""The groupings of :attr:`navverse.eval.scoring.EvalResult.groups` a result publishes."""
SCOPE = ("split_episodes", "scored", "missing")
"""The counts of :attr:`navverse.eval.scoring.EvalResult.scope` a result publishes."""


@dataclass(frozen=True)
class ScoringJob:
    """One submission to score, as a worker process is handed it (plain values, picklable).

    Attributes
    ----------
    submission_id : str
    path : str
        Its stored file.
    split : str
    dataset : str
        The dataset version directory.
    private : str or None
        The directory of its private files.
    scene_dirs : tuple of (str, str)
        Scene directory by scene id, for the split's scenes.
    """

    submission_id: str
    path: str
    split: str
    dataset: str
    private: str | None
    scene_dirs: tuple[tuple[str, str], ...]


@lru_cache(maxsize=4)
def _dataset(root: str, private: str | None) -> Dataset:
    """The dataset of a job, opened once per process (the server verified it at start; every episode
    file is checked against the manifest's checksum as it is read)."""
    from navverse.dataset import Dataset

    return Dataset(root) if private is None else Dataset(root, private=private)


def public_result(result: EvalResult) -> dict:
    """What the server publishes of a scoring: ``groups`` (the groupings of :data:`PUBLISHED`, each
    ``{group: {metric: mean, "<metric>_n": n, "episodes": n, <statistic>: value}}``) and ``scope``
    (the counts of :data:`SCOPE`). Nothing per episode."""
    return {
        "groups": {grouping: result.groups.get(grouping, {}) for grouping in PUBLISHED},
        "scope": {key: result.scope.get(key) for key in SCOPE},
    }


def score_job(job: ScoringJob) -> dict:
    """Score a stored submission on its split; returns its :func:`public_result`.

    Raises
    ------
    ServeError
        If the split's goals are private and the job names no private directory.
    SubmissionError
        If the submission cannot be read (it was checked when accepted: the file changed since).
    """
    from navverse.eval.scoring import score
    from navverse.eval.submission import episode_bounds, read_submission
    from navverse.serve.errors import ServeError

    dataset = _dataset(job.dataset, job.private)
    has_goals = getattr(dataset, "has_goals", None)
    if has_goals is not None and not has_goals(job.split):
        raise ServeError(f"split {job.split!r} keeps its goals private and this server has no private file")
    episodes = list(dataset.episodes(split=job.split))
    scene_dirs = {scene: Path(folder) for scene, folder in job.scene_dirs}
    submission = read_submission(
        job.path,
        episode_ids=[e.episode_id for e in episodes],
        bounds=episode_bounds(episodes, scene_dirs),
    )
    result = score(dataset, submission, split=job.split, scene_dirs=scene_dirs, episodes="all")
    return public_result(result)
