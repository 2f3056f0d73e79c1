"""Score a submission against a dataset split: per-episode metrics and their breakdowns.

:func:`score` reads the episodes of the split, takes each one's valid record from the submission (a
missing or invalid one is a failure, labelled ``invalid``), computes the measures in batches of rows
(:func:`navverse.eval.measures.measure`) and the metrics (:func:`navverse.eval.metrics.compute_metrics`),
and groups them: overall, per task, per scene type, per task × scene type, per difficulty, and per task
over the indoor-to-outdoor episodes alone (the transition analysis).

A submission is run under one PlaceNav instruction type (:func:`instruction_type_of`: the
``instruction_type`` of its valid PlaceNav records, ``category`` when they do not say); records that
disagree make it a :class:`~navverse.eval.submission.SubmissionError` naming the types and lines.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from navverse.dataset import Dataset, Episode
from navverse.eval.measures import MEASURES, TRANSITION_SCENE_TYPES, EpisodeTarget, Robot, measure, outcome
from navverse.eval.metrics import METRICS, STATISTICS, compute_metrics, termination_labels
from navverse.eval.protocol import UNSPECIFIED, describe
from navverse.eval.submission import Submission, SubmissionError
from navverse.scene.fields import SceneFields, load_scene_fields
from navverse.scene_types import SCENE_TYPES

__all__ = ["EXTRA_SURFACES", "GROUPINGS", "EvalResult", "chosen_episodes", "group_means",
           "instruction_type_of", "labelled_episodes", "metric_rows", "robot_for", "score",
           "submission_track"]  # fmt: skip

EXTRA_SURFACES = {"spot": frozenset({"curb", "green", "ground"}), "turtlebot": frozenset()}
"""Navigable classes an embodiment also counts as preferred for NSR, beyond the classes the scene marks
``preferred`` (floor, sidewalk, crosswalk): a legged robot is at home on grass, earth and curbs."""
BATCH_ROWS = 500_000
"""Rows measured at once (whole episodes; one longer episode is a batch alone): the measures hold a few
arrays per row, so this bounds scoring's working memory (about 150 MB), whatever the submission's size."""


def robot_for(embodiment: str) -> Robot:
    """The scoring view of an embodiment: r_robot, footprint, surfaces."""
    from navverse.sim.embodiments import make_embodiment

    body = make_embodiment(embodiment)
    return Robot(
        name=embodiment,
        radius=float(body.radius),
        length=float(body.size[0]),
        width=float(body.size[1]),
        extra_surfaces=EXTRA_SURFACES.get(embodiment, frozenset()),
    )


@dataclass(eq=False)
class EvalResult:
    """Per-episode values and grouped means.

    Attributes
    ----------
    episodes : list of dict
        One row per episode: ids, task, scene type, difficulty, label, every metric.
    groups : dict
        ``{grouping: {group key: {metric: mean, "episodes": n, label: share}}}`` for the groupings of
        :data:`GROUPINGS` (``i2o_task`` is empty when the split has no indoor-to-outdoor episodes).
    problems : list of str
        The submission's problems.
    difficulty_thresholds : dict
        The dataset's geodesic-length thresholds of each task's difficulties.
    instruction_type : str or None
        The PlaceNav instruction type the submission was run under (:func:`instruction_type_of`); None
        when the split has no PlaceNav episodes.
    submission : str
        The submission file scored ("" when not known).
    scope : dict
        What was scored: ``episodes`` (``all`` or ``submitted``), ``split_episodes`` (the split's
        count), ``submitted`` (episodes with a line in the submission, valid or not), ``scored`` (the
        episodes in the means) and ``missing`` (scored episodes without a valid record: failures).
    track : dict
        The sensors and privileges of the submission's agent (:func:`submission_track`).
    """

    episodes: list[dict]
    groups: dict[str, dict[str, dict[str, float]]]
    problems: list[str] = field(default_factory=list)
    difficulty_thresholds: dict[str, tuple[float, float]] = field(default_factory=dict)
    instruction_type: str | None = None
    submission: str = ""
    scope: dict = field(default_factory=dict)
    track: dict = field(default_factory=lambda: dict(UNSPECIFIED))

    @property
    def partial(self) -> bool:
        """Whether fewer episodes than the split's were scored (``--episodes submitted``)."""
        return self.scope.get("scored", 0) < self.scope.get("split_episodes", 0)


def instruction_type_of(submission: Submission, episodes: Sequence[Episode]) -> str | None:
    """The instruction type a submission's PlaceNav episodes were run under.

    Parameters
    ----------
    submission : Submission
        The submission (its valid records are read; a record without ``instruction_type`` counts as
        ``category``).
    episodes : sequence of Episode
        The split scored.

    Returns
    -------
    str or None
        ``category``, ``route`` or ``intention``; ``category`` when no PlaceNav episode has a valid
        record; None when the split has no PlaceNav episodes.

    Raises
    ------
    SubmissionError
        If its PlaceNav records name different instruction types (a submission is one run, under one).
    """
    placenav = [e.episode_id for e in episodes if e.task == "placenav"]
    if not placenav:
        return None
    first_line: dict[str, tuple[int, int]] = {}  # type -> (first line, records)
    for episode_id in placenav:
        record = submission.records.get(episode_id)
        if record is None:
            continue
        kind = record.instruction_type or "category"
        line, count = first_line.get(kind, (record.line, 0))
        first_line[kind] = (min(line, record.line), count + 1)
    if len(first_line) > 1:
        said = "; ".join(
            f"{count} say {kind!r} (first on line {line})"
            for kind, (line, count) in sorted(first_line.items())
        )
        raise SubmissionError(
            f"{submission.path}: its PlaceNav records disagree on instruction_type: {said}. A submission "
            "is one run under one instruction type (a record without it counts as 'category'); write one "
            "submission per type (`navverse run-agent --instruction-type ...`) and give each to `navverse "
            "eval --submission`"
        )
    return next(iter(first_line), "category")


def submission_track(submission: Submission) -> dict:
    """The track a submission's valid records state (:mod:`navverse.eval.protocol`), or
    :data:`~navverse.eval.protocol.UNSPECIFIED` when none does.

    Raises
    ------
    SubmissionError
        If its records state different tracks, or some state one and others do not (a submission is one
        run of one agent).
    """
    seen: dict[str, tuple[dict | None, int, int]] = {}  # key -> (track, first line, records)
    for record in submission.records.values():
        key = describe(record.track) if record.track is not None else "none"
        track, line, count = seen.get(key, (record.track, record.line, 0))
        seen[key] = (track, min(line, record.line), count + 1)
    if len(seen) > 1:
        said = "; ".join(
            f"{count} say {key} (first on line {line})" for key, (_, line, count) in sorted(seen.items())
        )
        raise SubmissionError(
            f"{submission.path}: its records disagree on the track: {said}. A submission is one run of one "
            "agent with one set of sensors; run it again with `navverse run-agent`, or write the same track "
            "on every line"
        )
    track = next(iter(seen.values()))[0] if seen else None
    return dict(track) if track is not None else dict(UNSPECIFIED)


def chosen_episodes(episodes: Sequence[Episode], submission: Submission, which: str) -> list[Episode]:
    """The episodes scored: all of the split (``all``: those without a valid record are failures), or
    those the submission has a line for, valid or not (``submitted``).

    Raises
    ------
    ValueError
        On another value of `which`.
    """
    if which == "all":
        return list(episodes)
    if which != "submitted":
        raise ValueError(f"episodes must be 'all' or 'submitted', not {which!r}")
    lines = set(submission.records) | {p.episode_id for p in submission.problems if p.episode_id}
    return [e for e in episodes if e.episode_id in lines]


def _target(episode: Episode) -> EpisodeTarget:
    return EpisodeTarget(
        episode_id=episode.episode_id,
        scene_id=episode.scene_id,
        task=episode.task,
        goal_centers=np.array([g.position for g in episode.goals], dtype=float).reshape(-1, 3),
        goal_radii=np.array([g.radius for g in episode.goals], dtype=float),
        geodesic=float(episode.info.geodesic_distance),
        reference_path=np.asarray(episode.reference_path, dtype=float).reshape(-1, 3),
        scene_type=episode.scene_type,
    )


def _facts(episode: Episode) -> dict[str, str]:
    """The facts of an episode's row: ids, task, scene type, difficulty."""
    return {
        "episode_id": episode.episode_id,
        "scene_id": episode.scene_id,
        "task": episode.task,
        "scene_type": episode.scene_type,
        "difficulty": episode.info.difficulty,
    }


def _preferred(fields: SceneFields, scene_dir: Path, robot: Robot) -> np.ndarray:
    from navverse.scene.directory import read_annotations

    classes = read_annotations(scene_dir).terrain_classes
    flags = [classes[n].preferred or n in robot.extra_surfaces for n in fields.class_names]
    return np.array([*flags, False], dtype=bool)


def _batches(sizes: Sequence[int], limit: int) -> list[list[int]]:
    out, current, rows = [], [], 0
    for i, size in enumerate(sizes):
        if current and rows + size > limit:
            out.append(current)
            current, rows = [], 0
        current.append(i)
        rows += size
    return [*out, current] if current else out


def score(
    dataset: Dataset,
    submission: Submission,
    *,
    split: str,
    scene_dirs: Mapping[str, Path],
    embodiment: str | None = None,
    episodes: str = "all",
    progress: Callable[[int, int], None] | None = None,
    on_fields: Callable[[str, SceneFields], None] | None = None,
) -> EvalResult:
    """Score a submission on one split of a dataset.

    Parameters
    ----------
    dataset : Dataset
        The dataset version.
    submission : Submission
        Read with the split's episode ids (:func:`~navverse.eval.submission.read_submission`).
    split : str
        The split scored; every one of its episodes is scored.
    scene_dirs : mapping
        Built scene directory by scene id (for the obstacle and surface fields).
    embodiment : str, optional
        The robot scored (r_robot, footprint); the dataset's by default.
    episodes : str
        ``all`` (every episode of the split; one without a valid record is a failure) or
        ``submitted`` (only those the submission has a line for: a partial scoring, labelled so in
        :attr:`EvalResult.scope`).
    progress : callable, optional
        Called with (episodes scored, episodes).
    on_fields : callable, optional
        Called with each scene's id and fields once its episodes are measured, while the fields are in
        memory (one scene's at a time; scenes without a valid record are not loaded): the report crops
        its pictures' backdrops there (:class:`navverse.eval.report.PictureBackdrops`), so that no
        scene's fields are read twice.

    Raises
    ------
    SubmissionError
        If the submission's PlaceNav records disagree on their instruction type or on their track.
    """
    split_episodes = list(dataset.episodes(split=split))
    which = episodes
    episodes = chosen_episodes(split_episodes, submission, which)
    instruction_type = instruction_type_of(submission, episodes)
    track = submission_track(submission)
    robot = robot_for(embodiment or dataset.manifest.embodiment)
    count = len(episodes)
    measures: dict[str, np.ndarray] = {}
    valid = np.array([e.episode_id in submission.records for e in episodes], dtype=np.float64)
    scored = [i for i in range(count) if valid[i]]
    by_scene: dict[str, list[int]] = {}
    for i in scored:
        by_scene.setdefault(episodes[i].scene_id, []).append(i)
    done = 0
    for scene, indices in sorted(by_scene.items()):  # one scene's fields in memory at a time
        fields = {scene: load_scene_fields(scene_dirs[scene])}
        preferred = {scene: _preferred(fields[scene], Path(scene_dirs[scene]), robot)}
        records = [submission.records[episodes[i].episode_id] for i in indices]
        for batch in _batches([len(r.trajectory) for r in records], BATCH_ROWS):
            chosen = [records[b] for b in batch]
            values = measure(
                [r.trajectory for r in chosen],
                [_target(episodes[indices[b]]) for b in batch],
                robot=robot,
                stops=[r.stop for r in chosen],
                collisions=[r.collisions for r in chosen],
                fields=fields,
                preferred=preferred,
            )
            for name, array in values.items():
                measures.setdefault(name, np.full(count, np.nan))[[indices[b] for b in batch]] = array
            done += len(batch)
            if progress is not None:
                progress(done, len(scored))
        if on_fields is not None:
            on_fields(scene, fields[scene])
        del fields, preferred
    inputs = {name: measures.get(name, np.full(count, np.nan)) for name in MEASURES}
    inputs["geodesic"] = np.array([e.info.geodesic_distance for e in episodes], dtype=float)
    inputs["success_distance"] = np.array([robot.success_distance(e.scene_type) for e in episodes])
    inputs["valid"] = valid
    values = compute_metrics(inputs)
    rows = metric_rows([_facts(e) for e in episodes], values)
    return EvalResult(
        episodes=rows,
        groups=group_means(rows),
        problems=[str(p) for p in submission.problems]
        + ([f"... and {submission.omitted} more problems"] if submission.omitted else []),
        difficulty_thresholds=dict(dataset.manifest.difficulty_thresholds),
        instruction_type=instruction_type,
        submission=str(submission.path),
        scope={
            "episodes": which,
            "split": split,
            "split_episodes": len(split_episodes),
            "submitted": len(chosen_episodes(split_episodes, submission, "submitted")),
            "scored": count,
            "missing": int(count - valid.sum()),
        },
        track=track,
    )


def labelled_episodes(
    dataset: Dataset,
    submission: Submission,
    *,
    split: str,
    embodiment: str | None = None,
    episodes: str = "all",
) -> list[dict]:
    """The episodes :func:`score` scores, each with its termination label, from the trajectories alone.

    The labels are those :func:`score` gives (the same measures, :func:`~navverse.eval.measures.outcome`,
    and the same rule, :func:`~navverse.eval.metrics.termination_labels`), but no scene's fields are read,
    so they are known before scoring: the report chooses the episodes it pictures by them, and takes
    their backdrops while scoring holds each scene's fields.

    Parameters
    ----------
    dataset, submission, split, embodiment, episodes
        As given to :func:`score`.

    Returns
    -------
    list of dict
        In the order of :attr:`EvalResult.episodes`: ``episode_id``, ``scene_id``, ``task``,
        ``scene_type``, ``difficulty`` and ``label``.
    """
    chosen = chosen_episodes(list(dataset.episodes(split=split)), submission, episodes)
    robot = robot_for(embodiment or dataset.manifest.embodiment)
    count = len(chosen)
    inputs = {name: np.full(count, np.nan) for name in ("dtg", "fell", "stopped")}
    scored = [i for i, e in enumerate(chosen) if e.episode_id in submission.records]
    records = [submission.records[chosen[i].episode_id] for i in scored]
    for batch in _batches([len(r.trajectory) for r in records], BATCH_ROWS):
        values = outcome(
            [records[b].trajectory for b in batch],
            [_target(chosen[scored[b]]) for b in batch],
            stops=[records[b].stop for b in batch],
        )
        for name, array in inputs.items():
            array[[scored[b] for b in batch]] = values[name]
    inputs["success_distance"] = np.array([robot.success_distance(e.scene_type) for e in chosen])
    inputs["valid"] = np.array([e.episode_id in submission.records for e in chosen], dtype=np.float64)
    labels = termination_labels(inputs)
    return [{**_facts(e), "label": str(labels[i])} for i, e in enumerate(chosen)]


def metric_rows(facts: Sequence[Mapping[str, str]], values: Mapping[str, np.ndarray]) -> list[dict]:
    """One row per episode: its facts, label and every public metric (None where undefined).

    Parameters
    ----------
    facts : sequence of mapping
        Per episode: ``episode_id``, ``scene_id``, ``task``, ``scene_type``, ``difficulty``.
    values : mapping
        The output of :func:`~navverse.eval.metrics.compute_metrics` for these episodes, in order.

    Returns
    -------
    list of dict
        A metric is None when it is NaN or does not apply to the episode's task or scene type.
    """
    public = [(name, spec) for name, spec in METRICS.items() if not name.startswith("_")]
    columns = [np.asarray(values[name], dtype=np.float64).tolist() for name, _ in public]  # Python floats
    labels = [str(label) for label in values["label"]]
    applying: dict[tuple[str, str], list[bool]] = {}  # per task and scene type: which metrics apply
    rows = []
    for i, fact in enumerate(facts):
        kind = (fact["task"], fact["scene_type"])
        if kind not in applying:
            applying[kind] = [spec.applies(*kind) for _, spec in public]
        row = {**fact, "label": labels[i]}
        for (name, _), column, applies in zip(public, columns, applying[kind], strict=True):
            v = column[i]
            row[name] = round(v, 6) if applies and math.isfinite(v) else None
        rows.append(row)
    return rows


GROUPINGS: dict[str, Callable[[Mapping], str | None]] = {
    "overall": lambda r: "all",
    "task": lambda r: r["task"],
    "scene_type": lambda r: r["scene_type"],
    "task_scene_type": lambda r: f"{r['task']}/{r['scene_type']}",
    "task_difficulty": lambda r: f"{r['task']}/{r['difficulty']}",
    "i2o_task": lambda r: r["task"] if r["scene_type"] in TRANSITION_SCENE_TYPES else None,
}
"""Group key of an episode row per grouping; None leaves the episode out of that grouping."""


_ORDER = {**{name: k for k, name in enumerate(SCENE_TYPES)}, "easy": 0, "medium": 1, "hard": 2}
"""Rank of a group key's parts: scene types in the profile table's order, difficulties easy to hard."""


def _group_order(key: str) -> tuple:
    """Sort key of a group: task, scene type and difficulty in their natural order (easy before hard)."""
    return tuple((_ORDER.get(part, -1), part) for part in key.split("/"))


def group_means(rows: Sequence[dict]) -> dict[str, dict[str, dict[str, float]]]:
    """Means of every metric (over the episodes where it is defined; ``<metric>_n`` is how many) and
    the group statistics, per grouping.

    The statistics are those of :data:`~navverse.eval.metrics.STATISTICS`: the share of each label, the
    ``failures`` and the ``post_exit_failures`` (failed episodes that reached outdoors: the episodes the
    ``post_exit_*`` shares are over), each over all the group's episodes.
    """
    out: dict[str, dict[str, dict[str, float]]] = {}
    names = [n for n in METRICS if not n.startswith("_")]
    for grouping, key in GROUPINGS.items():
        groups: dict[str, list[dict]] = {}
        for row in rows:
            group = key(row)
            if group is not None:
                groups.setdefault(group, []).append(row)
        table = {}
        for group, members in sorted(groups.items(), key=lambda item: _group_order(item[0])):
            entry: dict[str, float] = {"episodes": len(members)}
            for name in names:
                defined = [m[name] for m in members if m[name] is not None]
                entry[name] = round(float(np.mean(defined)), 6) if defined else None
                entry[f"{name}_n"] = len(defined)
            for name, spec in STATISTICS.items():
                entry[name] = round(spec.function(members), 6)
            table[group] = entry
        out[grouping] = table
    return out
