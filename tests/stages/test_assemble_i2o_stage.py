"""The assemble_i2o stage through the engine: a cafe joined to a synthetic city is an i2o scene with
its navmesh and a record of the facade chosen; a building that fits no facade is refused with the
constraint named, exit 1, no traceback, and nothing written for that target."""

from __future__ import annotations

import pytest

from navverse.scene.directory import read_annotations
from tests.stages.conftest import Built, build_all, navverse_command, workspace_with

CITY = """\
extends: outdoor-city
stages:
  synthetic_city: {size: [200, 200]}
"""
CAFE = """\
extends: indoor-building
stages:
  indoor_layout: {building_type: cafe, length: 14}
"""
I2O = """\
extends: i2o
stages:
  assemble_i2o: {options}
links:
  city: {{artifact: geometry, targets: [{city}]}}
  building: {{artifact: geometry, targets: [cafe]}}
"""
RULED_CITY = """\
extends: outdoor-city
stages:
  synthetic_city: {size: [200, 200], sidewalk: 3.5}
  populate: {exclude: [street_lamp, sedan, suv], clear_width: 2.0}
  storefronts: {categories: [bank, pharmacy]}
"""
EXCLUDED = {"street_lamp", "sedan", "suv"}


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> Built:
    """The cafe joined to a city of default settings (``cafe-city``) and to a city of its own rules
    (``ruled-cafe-city``, over ``ruled-city``)."""
    workspace = workspace_with(
        tmp_path_factory.mktemp("i2o") / "ws",
        [],
        {
            "scenes/city.yaml": CITY,
            "scenes/ruled-city.yaml": RULED_CITY,
            "scenes/cafe.yaml": CAFE,
            "scenes/cafe-city.yaml": I2O.format(options="{}", city="city"),
            "scenes/ruled-cafe-city.yaml": I2O.format(options="{storefronts_nearby: 6}", city="ruled-city"),
        },
    )
    return build_all(workspace)


@pytest.mark.slow(seconds=40)  # the module's build
def test_a_cafe_joined_to_a_city_is_an_i2o_scene(built: Built) -> None:
    assert not built.report.failed
    scene = read_annotations(built.output("cafe-city", "scene"))
    assert scene.scene_type == "i2o" and scene.indoor_anchor is not None
    (cafe,) = [b for b in scene.buildings if b.indoor]
    assert cafe.rooms and cafe.exits
    stats = built.manifest("cafe-city", "geometry")["stats"]
    assert stats["city"] == "city" and stats["building"] == "cafe" and stats["candidates"] >= 1
    facades = {f.id for b in read_annotations(built.output("city", "geometry")).buildings for f in b.facades}
    assert stats["facade"] in facades and abs(stats["step"]) < 0.02
    assert (built.output("cafe-city", "scene") / "navmesh.bin").is_file()


def test_the_neighbourhood_of_the_exit_is_densified(built: Built) -> None:
    city = read_annotations(built.output("city", "geometry"))
    scene = read_annotations(built.output("cafe-city", "scene"))
    added = built.manifest("cafe-city", "geometry")["stats"]["densified"]
    cars, objects = sum(added["cars"].values()), sum(added["objects"].values())
    assert 0 < cars <= 8 and 0 < objects <= 30  # the defaults: 8 cars, 30 street objects
    anchor = scene.indoor_anchor
    new = [o for o in scene.objects if o.source in ("parking", "grammar")]
    near = [o for o in new if (o.center[0] - anchor[0]) ** 2 + (o.center[1] - anchor[1]) ** 2 <= 50.0**2]
    old = [o for o in city.objects if o.source in ("parking", "grammar")]
    old_near = [o for o in old if (o.center[0] - anchor[0]) ** 2 + (o.center[1] - anchor[1]) ** 2 <= 50.0**2]
    assert len(near) >= len(old_near) + cars + objects - 3  # a few of the city's own were cut with the block
    assert (built.output("city", "geometry") / "city_map.json").is_file()  # the map travels with the city


def test_a_building_that_fits_no_facade_is_refused_and_nothing_is_written(built: Built) -> None:
    root = built.workspace.root
    recipe = I2O.format(options="{max_road_distance: 0.5}", city="city")  # no facade faces a road that near
    (root / "recipes" / "scenes" / "cafe-wide.yaml").write_text(recipe)
    result = navverse_command(root, "build", "cafe-wide")
    output = result.stdout + result.stderr
    assert result.returncode == 1 and "Traceback" not in output, output
    assert "no road-facing facade of city holds cafe" in output and "the facade faces no road" in output
    assert not (root / "data" / "built" / "targets" / "cafe-wide").exists()


def test_densification_follows_the_city_s_own_settings(built: Built) -> None:
    """The settings travel: the neighbourhood of the exit is densified by the linked city's
    population and storefront settings (carried in its city_settings.json), not by defaults."""
    from navverse.city.city_settings import load_city_settings
    from navverse.city.geometry.street_plan import load_street_plan
    from navverse.city.i2o.densify import base_footprint
    from navverse.city.map import read_city_map
    from navverse.city.street_life.zones import street_zones

    assert not built.report.failed
    city_dir = built.output("ruled-city", "geometry")
    carried = load_city_settings(city_dir / "city_settings.json")
    assert set(carried.populate.exclude) == EXCLUDED and carried.populate.clear_width == 2.0
    assert carried.storefronts.categories == ["bank", "pharmacy"]

    city = read_annotations(city_dir)
    scene = read_annotations(built.output("ruled-cafe-city", "scene"))
    added = built.manifest("ruled-cafe-city", "geometry")["stats"]["densified"]
    assert sum(added["objects"].values()) > 0 and sum(added["cars"].values()) > 0
    assert not EXCLUDED & set(added["objects"]) and not EXCLUDED & set(added["cars"])
    assert not EXCLUDED & {o.category for o in scene.objects}
    new_stores = {s.name for s in scene.storefronts} - {s.name for s in city.storefronts}
    assert added["storefronts"]["placed"] > 0 and new_stores
    assert {s.place_category for s in scene.storefronts} <= {"bank", "pharmacy"}

    # no new street object stands in the walkway kept clear at the city's 2.0 m
    plan = load_street_plan(city_dir / "street_plan.json")
    walkway = street_zones(read_city_map(city_dir / "city_map.json"), plan, carried.populate).walkway
    old = {(o.category, *o.center) for o in city.objects}
    new = [o for o in scene.objects if o.source == "grammar" and (o.category, *o.center) not in old]
    assert new
    assert all(base_footprint(o).intersection(walkway).area < 0.01 for o in new)


PARK_CITY = """\
extends: outdoor-city
stages:
  synthetic_city: {size: [200, 200], park_share: 1.0, river_width: 0}
"""


def _seed_drawing(target: str, stage_name: str, index: int, count: int) -> int:
    """A recipe seed whose stage rng first draws `index` of `count` (the linked city tried first)."""
    from pipeline.seeds import derive_seed, make_rng

    return next(
        seed
        for seed in range(1000)
        if int(make_rng(derive_seed(seed, target, stage_name)).integers(count)) == index
    )


@pytest.mark.slow(seconds=20)  # the park city's build
def test_a_city_without_room_passes_the_building_to_the_next_linked_city(built: Built) -> None:
    """A city of parks only has no facade: drawn first, it refuses and the next linked city takes the
    cafe; the record says which city refused and why. Linked alone, it fails the build with that
    reason, exit 1, no traceback."""
    root = built.workspace.root
    (root / "recipes" / "scenes" / "park-city.yaml").write_text(PARK_CITY)
    seed = _seed_drawing("cafe-fallback", "assemble_i2o", 1, 2)  # by scene id: city, park-city
    recipe = I2O.format(options="{}", city="city, park-city") + f"seed: {seed}\n"
    (root / "recipes" / "scenes" / "cafe-fallback.yaml").write_text(recipe)
    result = navverse_command(root, "build", "cafe-fallback")
    assert result.returncode == 0, result.stdout + result.stderr
    stats = built.manifest("cafe-fallback", "geometry")["stats"]
    assert stats["city"] == "city" and list(stats["cities_refused"]) == ["park-city"]
    assert "road-facing facade" in stats["cities_refused"]["park-city"]

    (root / "recipes" / "scenes" / "cafe-in-parks.yaml").write_text(
        I2O.format(options="{}", city="park-city")
    )
    result = navverse_command(root, "build", "cafe-in-parks")
    output = result.stdout + result.stderr
    assert result.returncode == 1 and "Traceback" not in output, output
    assert "park-city" in output and "road-facing facade" in output
    assert not (root / "data" / "built" / "targets" / "cafe-in-parks").exists()
