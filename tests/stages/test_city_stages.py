"""The city stages through the engine: osm_city / synthetic_city -> city_geometry -> navmesh.

Bad OSM input is refused with a clear message, exit 1 and nothing built; the same recipe builds the
same bytes; different synthetic seeds build different cities; the synthetic map's OSM file loads
in osmnx.
"""

from __future__ import annotations

import gzip
import hashlib
import shutil
from pathlib import Path

import osmnx
import pytest

from navverse.city.map import read_city_map
from navverse.scene.directory import read_annotations
from tests.stages.conftest import build_all, navverse_command, workspace_with

T_JUNCTION = Path(__file__).parents[1] / "navverse" / "city" / "data" / "t_junction.osm"
CITY = """\
extends: outdoor-city
stages:
  osm_city:
    source: ../../data/raw/{name}
    center: [48.0, 11.0]
    size_m: [200, 200]
  city_geometry: {{junction_crosswalks: false}}
"""
SYNTHETIC = """\
extends: outdoor-city
seeds: [1, 2]
stages:
  synthetic_city: {size: [150, 150], write_osm: true}
"""


def _workspace(root: Path, files: dict[str, bytes | str], recipes: dict[str, str]):
    raw = root / "data" / "raw"
    raw.mkdir(parents=True)
    for name, content in files.items():
        (raw / name).write_bytes(content if isinstance(content, bytes) else content.encode())
    return workspace_with(root, [], recipes)


def _built_files(root: Path) -> list[Path]:
    artifacts = root / "data" / "built" / "artifacts"
    return sorted(p for p in artifacts.rglob("*") if p.is_file()) if artifacts.exists() else []


JUNCTION = T_JUNCTION.read_text(encoding="utf-8")
BOMB = (
    '<?xml version="1.0"?>\n<!DOCTYPE osm [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;">]>\n'
    '<osm version="0.6"><node id="1" lat="48" lon="11"><tag k="name" v="&b;"/></node></osm>\n'
)
EMPTY_OF_FEATURES = (
    '<?xml version="1.0"?>\n<osm version="0.6">\n'
    '  <bounds minlat="47.999" minlon="10.998" maxlat="48.001" maxlon="11.002"/>\n'
    '  <node id="1" lat="48.0" lon="11.0"><tag k="natural" v="tree"/></node>\n</osm>\n'
)


@pytest.mark.parametrize(
    ("name", "content", "center", "message"),
    [
        ("truncated.osm", JUNCTION[: len(JUNCTION) // 2], None, "truncated"),
        ("bomb.osm", BOMB, None, "DOCTYPE"),
        ("nothing.osm", EMPTY_OF_FEATURES, None, "no roads or buildings"),
        ("t_junction.osm", JUNCTION, "[40.0, 11.0]", "move it onto the data"),
        ("notes.osm", "some words, not a map\n", None, "is not an OSM file"),
        ("words.osm.gz", gzip.compress(b"some words", mtime=0), None, "does not hold OSM XML"),
    ],
    ids=[
        "truncated",
        "entity-bomb",
        "no-roads-or-buildings",
        "centre-outside",
        "not-osm",
        "gzip-not-holding-osm",
    ],
)
def test_bad_osm_input_is_a_clear_error_and_builds_nothing(
    tmp_path: Path, name: str, content: str | bytes, center: str | None, message: str
) -> None:
    recipe = CITY.format(name=name)
    if center is not None:
        recipe = recipe.replace("[48.0, 11.0]", center)
    root = tmp_path / "ws"
    _workspace(root, {name: content}, {"scenes/city.yaml": recipe})
    result = navverse_command(root, "build", "city")
    assert result.returncode == 1, result.stdout + result.stderr
    output = result.stdout + result.stderr
    assert message in output and "Traceback" not in output
    assert not [p for p in _built_files(root) if p.name != "stage.log"]
    assert not (root / "data" / "built" / "targets" / "city").exists()


def test_a_file_with_broken_features_builds_the_rest_and_counts_them(tmp_path: Path) -> None:
    broken = JUNCTION.replace('<nd ref="43"/>', '<nd ref="999"/>')  # building B loses a corner
    broken = broken.replace('<tag k="width" v="7"/>', '<tag k="width" v="variable"/>')
    root = tmp_path / "ws"
    workspace = _workspace(root, {"broken.osm": broken}, {"scenes/city.yaml": CITY.format(name="broken.osm")})
    built = build_all(workspace)
    assert not built.report.failed
    city = read_city_map(built.output("city", "city_map") / "city_map.json")
    assert city.dropped  # counted by reason
    assert built.manifest("city", "street_geometry")["stats"]["dropped"] == city.dropped
    assert read_annotations(built.output("city", "scene")).statistics.buildings >= 2


def _digest(directory: Path) -> dict[str, str]:
    return {
        p.name: hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(directory.iterdir())
        if p.is_file() and p.name not in ("manifest.json", "stage.log")
    }


@pytest.mark.slow(seconds=25)
def test_the_same_recipe_builds_the_same_bytes_and_seeds_differ(tmp_path: Path) -> None:
    scenes = []
    for run, targets in (("a", ("city", "synthetic-s1", "synthetic-s2")), ("b", ("city", "synthetic-s1"))):
        root = tmp_path / run
        workspace = _workspace(
            root,
            {"t_junction.osm": JUNCTION},
            {"scenes/city.yaml": CITY.format(name="t_junction.osm"), "scenes/synthetic.yaml": SYNTHETIC},
        )
        built = build_all(workspace, only=targets)  # built again: the OSM city and one synthetic seed
        assert built.report.ok, built.report
        scenes.append(
            {
                (t, out): _digest(built.output(t, out))
                for t in targets
                for out in ("street_geometry", "geometry", "scene")
            }
        )
    assert {key: scenes[0][key] for key in scenes[1]} == scenes[1]  # the same bytes, built twice
    assert "street_plan.json" in scenes[0][("city", "street_geometry")]
    assert set(scenes[0][("city", "scene")]) >= {
        "scene.usdc",
        "scene.json",
        "navmesh.bin",
        "navmesh.json",
        "bev.png",
    }
    assert (
        scenes[0][("synthetic-s1", "scene")]["scene.json"]
        != scenes[0][("synthetic-s2", "scene")]["scene.json"]
    )
    osm = built.output("synthetic-s1", "city_map") / "city.osm"
    graph = osmnx.graph_from_xml(osm, simplify=False, retain_all=True)
    assert graph.number_of_edges() > 10
    shutil.rmtree(tmp_path)
