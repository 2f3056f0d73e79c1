"""What a build cost: CPU and wall seconds of the stage runs of a graph, by stage, read from the
manifests of their current artifacts (``navverse status --cost``)."""

from __future__ import annotations

from dataclasses import dataclass

from pipeline.dag import Graph
from pipeline.store import ArtifactStore

__all__ = ["StageCost", "stage_costs"]


@dataclass
class StageCost:
    """The stage runs of one stage in a graph: how many, how many are built (current artifacts), and
    the CPU seconds, wall seconds and largest peak memory (MB) of the built ones when they ran."""

    stage: str
    runs: int = 0
    built: int = 0
    cpu_s: float = 0.0
    wall_s: float = 0.0
    peak_rss_mb: float = 0.0


def stage_costs(graph: Graph, store: ArtifactStore) -> list[StageCost]:
    """Per stage, in the order stages first run in ``graph``: the cost of its built stage runs.

    A stage run counts as built when every artifact it writes is current; its cost is the ``run``
    record of its first artifact's manifest (all of a run's artifacts carry the same one).
    """
    costs: dict[str, StageCost] = {}
    for node_id in graph.order:
        node = graph.nodes[node_id]
        cost = costs.setdefault(node.stage, StageCost(stage=node.stage))
        cost.runs += 1
        outputs = sorted(node.artifact_keys.items())
        if not outputs or not all(store.has(node.stage, out, key) for out, key in outputs):
            continue
        manifest = store.read_manifest(store.artifact_path(node.stage, *outputs[0])) or {}
        run = manifest.get("run") or {}
        cost.built += 1
        cost.cpu_s += float(run.get("cpu_s", 0.0))
        cost.wall_s += float(run.get("wall_s", 0.0))
        cost.peak_rss_mb = max(cost.peak_rss_mb, float(run.get("peak_rss_mb", 0.0)))
    return list(costs.values())
