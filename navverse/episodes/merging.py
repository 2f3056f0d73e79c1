"""A dataset made of datasets: the episodes of several built dataset versions, packaged as one.

Each part keeps what made it good for its scene type (its own sampling counts, goal categories and
instruction settings: an indoor, an outdoor and an indoor-to-outdoor dataset recipe), and the merged
version is one benchmark over all of them, as the paper's is. :func:`merge_parts` checks the parts
against one another and returns what :func:`~navverse.episodes.packaging.write_dataset` packages:

- the parts must be verified with the same robot (the success distance is the robot's);
- a scene may belong to one part only, so the union of scene-disjoint splits stays scene-disjoint,
  and every scene keeps the split its part gave it (a part's ``train`` scenes train);
- an episode id may appear once;
- difficulties are relabelled over the merged episodes, by task (the tertiles of the whole benchmark).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from navverse.dataset import Dataset, DatasetError, Episode

__all__ = ["MergedParts", "merge_parts"]


@dataclass(frozen=True)
class MergedParts:
    """The merged parts, ready to package.

    Attributes
    ----------
    episodes : list of Episode
        Every part's episodes (with their instructions), in part order.
    rollouts : dict
        Verification rollout of every episode, by id.
    splits : dict
        Scenes of each split (the union of the parts').
    embodiment : str
        The robot all parts were verified with.
    scene_hashes : dict
        The parts' scene hashes.
    parts : list of dict
        Per part: ``name``, ``version`` and its episode count (recorded in the merged stage's manifest).
    """

    episodes: list[Episode]
    rollouts: dict[str, list[list[float]]]
    splits: dict[str, list[str]]
    embodiment: str
    scene_hashes: dict[str, str]
    parts: list[dict]


def merge_parts(parts: Sequence[Dataset]) -> MergedParts:
    """Check and join the episodes of dataset versions (see the module docstring).

    Raises
    ------
    DatasetError
        With no part, parts verified with different robots, a scene in two parts, or an episode id twice.
    """
    if not parts:
        raise DatasetError(
            "a merged dataset needs at least one dataset to merge: link their 'dataset' outputs"
        )
    robots = {p.manifest.embodiment for p in parts}
    if len(robots) > 1:
        named = ", ".join(f"{p.manifest.name} v{p.manifest.version}: {p.manifest.embodiment}" for p in parts)
        raise DatasetError(
            f"the datasets to merge were verified with different robots ({named}): merge one robot's"
        )
    owner: dict[str, str] = {}
    episodes: list[Episode] = []
    rollouts: dict[str, list[list[float]]] = {}
    splits: dict[str, list[str]] = {}
    hashes: dict[str, str] = {}
    records = []
    for part in parts:
        label = f"{part.manifest.name} v{part.manifest.version}"
        for split, scenes in part.manifest.splits.items():
            for scene in scenes:
                if scene in owner:
                    raise DatasetError(
                        f"scene {scene!r} is in both {owner[scene]} and {label}: the merged splits would not "
                        "be scene-disjoint; link datasets over different scenes"
                    )
                owner[scene] = label
                splits.setdefault(split, []).append(scene)
        hashes.update(part.manifest.scene_hashes)
        count = 0
        for episode in part.episodes():
            if episode.episode_id in rollouts:
                raise DatasetError(f"episode {episode.episode_id!r} is in two of the datasets to merge")
            rollout = part.rollout(episode)
            if rollout is None:
                raise DatasetError(f"{label} has no rollout of episode {episode.episode_id}: rebuild it")
            rollouts[episode.episode_id] = rollout
            episodes.append(episode)
            count += 1
        records.append({"name": part.manifest.name, "version": part.manifest.version, "episodes": count})
    return MergedParts(
        episodes=episodes,
        rollouts=rollouts,
        splits={k: sorted(v) for k, v in sorted(splits.items())},
        embodiment=robots.pop(),
        scene_hashes=dict(sorted(hashes.items())),
        parts=records,
    )
