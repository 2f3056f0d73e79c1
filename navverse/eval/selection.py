"""Which episodes an evaluation report draws as cards: a bounded, deterministic choice showing every outcome.

A report of thousands of episodes with a picture each is neither fast to draw nor readable, so
``report.html`` draws at most :data:`PICTURES` cards (``navverse eval --pictures``) and lists every other
episode as a row of metrics. :func:`pictured_episodes` chooses them; :func:`selection_text` is what the
page says of the choice. This module imports nothing heavy: the command line reads its default.
"""

from __future__ import annotations

import hashlib
import itertools
from collections import deque
from collections.abc import Iterable, Iterator, Mapping, Sequence
from typing import TypeVar

__all__ = ["CARD_ORDER", "NO_TRAJECTORY", "PICTURES", "pictured_episodes", "selection_text"]

CARD_ORDER = ("invalid", "fall", "timeout", "wrong_goal", "success")
"""Order of the episode groups of a report: failures first."""
NO_TRAJECTORY = "invalid"
"""The label of an episode without a valid record (:data:`navverse.eval.metrics.LABELS`): nothing to
picture, so it takes no card unless every episode has one."""
PICTURES = 60
"""Episode cards a report draws by default; the other episodes are rows of metrics."""


_T = TypeVar("_T")
_END = object()


def _turns(queues: Iterable[Iterator[_T]]) -> Iterator[_T]:
    """The items of the queues taking turns, one each a turn, until every queue has run out."""
    active = deque(queues)
    while active:
        queue = active.popleft()
        item = next(queue, _END)
        if item is not _END:
            yield item
            active.append(queue)


def _id_order(episode_id: str) -> bytes:
    """A fixed order of episode ids unrelated to how they are numbered: their SHA-256."""
    return hashlib.sha256(episode_id.encode("utf-8")).digest()


def pictured_episodes(rows: Sequence[Mapping[str, object]], count: int) -> list[str]:
    """The episodes a report pictures: at most `count`, every outcome shown, failures first.

    Every episode when there are at most `count`. Otherwise they are chosen among the episodes with a
    valid trajectory (those labelled :data:`NO_TRAJECTORY` have nothing to picture): the termination
    labels take turns in the order of :data:`CARD_ORDER` (fall, timeout, wrong goal, success; a label
    added later after them), each giving one episode a turn until `count` are chosen or its episodes
    run out; a label's turns go round its groups of task × scene type, a group's round its scenes, and
    a scene gives its episodes in the order of the SHA-256 of their ids (fixed, and unrelated to their
    numbering). The choice depends only on the rows' ids, labels, tasks, scene types and scenes: the
    same submission gives the same choice.

    Parameters
    ----------
    rows : sequence of mapping
        One per episode: ``episode_id``, ``label``, ``task``, ``scene_type``, ``scene_id`` (the rows of
        :attr:`EvalResult.episodes <navverse.eval.scoring.EvalResult>`, or of
        :func:`~navverse.eval.scoring.labelled_episodes`).
    count : int
        The most episodes pictured (0: none).

    Returns
    -------
    list of str
        The chosen episode ids, in the order they were chosen.
    """
    if count >= len(rows):
        return [str(row["episode_id"]) for row in rows]
    tree: dict[str, dict[tuple[str, str], dict[str, list[str]]]] = {}
    for row in rows:
        if row["label"] == NO_TRAJECTORY:
            continue
        label, group = str(row["label"]), (str(row["task"]), str(row["scene_type"]))
        tree.setdefault(label, {}).setdefault(group, {}).setdefault(str(row["scene_id"]), []).append(
            str(row["episode_id"])
        )
    order = [*CARD_ORDER, *sorted(set(tree) - set(CARD_ORDER))]
    labels = []
    for label in (label for label in order if label in tree):
        groups = []
        for _, scenes in sorted(tree[label].items()):
            groups.append(_turns([iter(sorted(ids, key=_id_order)) for _, ids in sorted(scenes.items())]))
        labels.append(_turns(groups))
    return list(itertools.islice(_turns(labels), max(0, count)))


def selection_text(shown: int, total: int, count: int) -> str:
    """What the page says of the episode cards (HTML): how many there are, and how they were chosen.

    Parameters
    ----------
    shown : int
        The episodes with a card (:func:`pictured_episodes`).
    total : int
        The episodes scored.
    count : int
        The most cards asked for (``--pictures``).

    Returns
    -------
    str
        One paragraph's HTML.
    """
    option = f"a report draws at most {count}: <code>navverse eval</code>'s <code>--pictures</code> option"
    if shown >= total:
        return f"Every episode has a card ({option})."
    order = ", ".join(label.replace("_", " ") for label in CARD_ORDER if label != NO_TRAJECTORY)
    return (
        f"{shown} of the {total} episodes {'has' if shown == 1 else 'have'} a card ({option}), chosen "
        "among those with a valid trajectory to show every outcome, failures first: the termination "
        "labels take turns "
        f"({order}), each giving one episode a turn until {count} are chosen or its episodes run out; a "
        "label's turns go round its groups of task × scene type, a group's round its scenes, and a scene "
        "gives its episodes in a fixed order (by the SHA-256 of their ids). Every other episode is a row "
        "of the table under its label, with the metrics a card shows (one without a valid record, with "
        "its first problem)."
    )
