"""The populate and storefronts stages through the engine: a synthetic city with its cars, street
objects and storefronts recorded in scene.json and the manifests; skipping populate leaves the street
bare; a wrong object or place category is refused."""

from __future__ import annotations

from pathlib import Path

from navverse.scene.directory import read_annotations
from tests.stages.conftest import build_all, navverse_command, workspace_with

CITY = """\
extends: outdoor-city
stages:
  synthetic_city: {{size: [160, 160]}}
  populate: {populate}
"""


def test_a_populated_city_records_its_objects_and_counts(tmp_path: Path) -> None:
    workspace = workspace_with(
        tmp_path / "ws",
        [],
        {"scenes/city.yaml": CITY.format(populate="{cars_per_km2: 800, objects_per_km2: 3000}")},
    )
    built = build_all(workspace)
    assert not built.report.failed
    scene = read_annotations(built.output("city", "scene"))
    populated = read_annotations(built.output("city", "populated_geometry"))
    stats = built.manifest("city", "populated_geometry")["stats"]
    assert sum(stats["cars"].values()) > 5 and sum(stats["objects"].values()) == len(populated.objects)
    assert all(o.zone and o.source for o in scene.objects)
    assert {o.source.split(":")[0] for o in scene.objects} >= {"parking", "map"}
    assert (built.output("city", "populated_geometry") / "street_plan.json").is_file()
    street = read_annotations(built.output("city", "street_geometry"))
    assert not street.objects  # the bare street is kept as its own artifact
    shops = built.manifest("city", "geometry")["stats"]
    assert shops["placed"] == len(scene.storefronts) >= 3
    assert shops["places"] + shops["filled"] == shops["placed"] + sum(shops["rejected"].values())
    assert all(s.name and s.design and s.building and s.facade for s in scene.storefronts)
    assert sum(o.category == "storefront" for o in scene.objects) == len(scene.storefronts)
    assert len(scene.objects) == len(populated.objects) - shops["objects_cleared"] + len(scene.storefronts)
    assert (built.output("city", "scene") / "textures").is_dir()  # the signs' images, beside scene.usdc


def test_skipping_populate_leaves_the_street_bare(tmp_path: Path) -> None:
    workspace = workspace_with(
        tmp_path / "ws", [], {"scenes/city.yaml": CITY.format(populate="{skip: true}")}
    )
    built = build_all(workspace)
    assert not built.report.failed
    scene = read_annotations(built.output("city", "scene"))
    assert all(o.category == "storefront" for o in scene.objects)  # no street life, only the shops


def test_an_unknown_category_is_refused_before_anything_is_built(tmp_path: Path) -> None:
    root = tmp_path / "ws"
    workspace_with(root, [], {"scenes/city.yaml": CITY.format(populate="{exclude: [sedan, flying_car]}")})
    result = navverse_command(root, "build", "city")
    output = result.stdout + result.stderr
    assert result.returncode == 1 and "Traceback" not in output
    assert "unknown object categories flying_car" in output and "sedan" in output
    assert not (root / "data" / "built" / "targets" / "city").exists()


def test_an_unknown_group_is_refused_with_the_known_ones(tmp_path: Path) -> None:
    root = tmp_path / "ws"
    workspace_with(root, [], {"scenes/city.yaml": CITY.format(populate="{groups: [picnic_lunch, rave]}")})
    result = navverse_command(root, "validate", "recipe", str(root / "recipes" / "scenes" / "city.yaml"))
    output = result.stdout + result.stderr
    assert result.returncode == 1 and "Traceback" not in output
    assert "unknown contextual groups rave" in output and "bus_stop_wait" in output


def test_an_unknown_place_category_is_refused_with_the_known_ones(tmp_path: Path) -> None:
    root = tmp_path / "ws"
    recipe = CITY.format(populate="{}") + "  storefronts: {categories: [bank, casino]}\n"
    workspace_with(root, [], {"scenes/city.yaml": recipe})
    result = navverse_command(root, "validate", "recipe", str(root / "recipes" / "scenes" / "city.yaml"))
    output = result.stdout + result.stderr
    assert result.returncode == 1 and "Traceback" not in output
    assert "unknown place categories casino" in output and "pharmacy" in output
