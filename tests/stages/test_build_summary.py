"""The build summary of a city says what each stage made: the map's buildings and what was dropped by
reason, the objects placed, the storefronts, the navmesh's area and islands; a rebuild that reuses
them says the same from their manifests."""

from __future__ import annotations

import io
import re
from pathlib import Path

from rich.console import Console

from pipeline.dag import build_graph
from pipeline.executors import make_executor
from pipeline.recipes import RecipeLoader
from pipeline.runner import run_build, run_made
from pipeline.stage import discover
from pipeline.store import ArtifactStore
from tests.stages.conftest import workspace_with

T_JUNCTION = Path(__file__).parents[1] / "navverse" / "city" / "data" / "t_junction.osm"
CITY = """\
extends: outdoor-city
stages:
  osm_city:
    source: ../../data/raw/broken.osm
    center: [48.0, 11.0]
    size_m: [200, 200]
  city_geometry: {junction_crosswalks: false}
  storefronts: {fill_per_km2: 400}
"""


def _build(workspace, console: Console):
    graph = build_graph(RecipeLoader(workspace, stages=discover("stages")).load())
    store = ArtifactStore(workspace.built_dir)
    return graph, store, run_build(graph, store, lambda: make_executor(0), console=console)


def test_a_city_build_says_what_each_stage_made_and_a_rebuild_says_it_again(tmp_path: Path) -> None:
    raw = tmp_path / "ws" / "data" / "raw"
    raw.mkdir(parents=True)
    broken = T_JUNCTION.read_text(encoding="utf-8").replace('<nd ref="43"/>', '<nd ref="999"/>')
    (raw / "broken.osm").write_text(broken, encoding="utf-8")
    workspace = workspace_with(tmp_path / "ws", [], {"scenes/city.yaml": CITY})
    graph, store, report = _build(workspace, Console(quiet=True))
    assert report.ok, report.failed
    made = {
        node_id.split(":")[1]: run_made(graph.nodes[node_id], store, report.built[node_id])
        for node_id in graph.order
    }
    stats = {n.split(":")[1]: r.stats for n, r in report.built.items()}
    dropped = stats["osm_city"]["dropped"]
    assert dropped  # the broken building, by reason
    reasons = ", ".join(f"{reason} {n}" for reason, n in sorted(dropped.items(), key=lambda kv: -kv[1]))
    assert made["osm_city"].startswith(f"buildings {stats['osm_city']['buildings']}, roads ")
    assert f"dropped {sum(dropped.values())} ({reasons})" in made["osm_city"]
    kept = stats["city_geometry"]["buildings"]
    assert made["city_geometry"].startswith(
        f"buildings {kept}, dropped {sum(dropped.values())} ({reasons}), "
    )
    placed = sum(stats["populate"]["objects"].values())
    assert made["populate"].startswith(f"objects {placed} (") and ", by source " in made["populate"]
    assert made["storefronts"].startswith(f"storefronts {stats['storefronts']['placed']}")
    assert ", map places " in made["storefronts"] and ", rejected " in made["storefronts"]
    assert re.match(r"navigable m2 \d+, islands \d+, largest island m2 \d+, polygons \d+, preset outdoor$",
                    made["navmesh"])  # fmt: skip

    # A rebuild of the navmesh alone: the reused runs say the same, read from their manifests.
    (workspace.recipes_dir / "scenes" / "city.yaml").write_text(
        CITY + "  navmesh: {area_costs: {road: 4.0}}\n"
    )
    console = Console(file=io.StringIO(), width=1000, force_terminal=False)
    _, _, again = _build(workspace, console)
    assert sorted(again.built) == ["city:navmesh"]
    output = console.file.getvalue()
    for stage in ("osm_city", "city_geometry", "populate", "storefronts"):
        assert re.search(rf"^city +{stage} +cached +{re.escape(made[stage])} *$", output, re.M), output
    assert re.search(r"^city +navmesh +\d+\.\d s +navigable m2 \d+, islands ", output, re.M), output
