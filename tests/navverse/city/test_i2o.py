"""Indoor-to-outdoor assembly: a procedural cafe joined to a synthetic city. The exit faces a road on
the sidewalk's side, the floor is level with the ground outside, the building covers no street and no
other building, rooms and street are one navmesh island; refusals name the constraint; the same
inputs give the same scene."""

from __future__ import annotations

import math

import numpy as np
import pytest
from shapely.geometry import LineString, Point, Polygon

from navverse.city.geometry.scene import CityGeometry, city_scene, geometry_plan
from navverse.city.i2o.assembly import AssemblyError, AssemblySettings, assemble_i2o
from navverse.city.synthetic.generator import SyntheticCityParams, synthetic_city
from navverse.indoor.building import BuildingOptions, generate_building
from navverse.nav import NavMeshSettings
from navverse.nav.scene_navmesh import build_scene_navmesh, scene_settings
from navverse.scene.heights import SurfaceHeights

GEOMETRY = CityGeometry(junction_crosswalks=True)


@pytest.fixture(scope="module")
def city():
    city_map = synthetic_city(SyntheticCityParams(size=(220.0, 220.0)), seed=4)
    plan = geometry_plan(city_map, GEOMETRY)
    return city_scene(city_map, scene_id="town", geometry=GEOMETRY, plan=plan), plan


@pytest.fixture(scope="module")
def cafe():
    return generate_building(
        "cafe", np.random.default_rng(3), scene_id="cafe", options=BuildingOptions(length=14.0)
    )


@pytest.fixture(scope="module")
def assembled(city, cafe):
    scene, plan = city
    return assemble_i2o(scene, plan, cafe, scene_id="cafe-town")


def test_the_building_joins_the_city_at_a_road_facing_facade(city, cafe, assembled) -> None:
    scene, plan = city
    ann = assembled.scene.annotations
    record = assembled.record
    assert ann.scene_type == "i2o" and record["candidates"] >= 1
    indoor = [b for b in ann.buildings if b.indoor]
    assert len(indoor) == 1 and len(indoor[0].rooms) == len(cafe.annotations.rooms)
    assert len(ann.buildings) == len(scene.annotations.buildings)  # one city building replaced by the cafe
    assert record["replaced"]["map_id"] not in {b.map_id for b in ann.buildings}
    solids = {s.name for s in assembled.scene.surfaces if s.name.startswith("building_")}
    assert solids == {f"building_{b.id:04d}" for b in ann.buildings if not b.indoor}  # names follow ids
    (exit_,) = indoor[0].exits
    facade = next(f for f in indoor[0].facades if f.id == exit_.facade)
    assert facade.road is not None  # the exit's facade faces the city's road
    assert ann.indoor_anchor == pytest.approx(exit_.center)
    normal = np.array([math.cos(exit_.facing), math.sin(exit_.facing)])
    out = LineString([exit_.center[:2], np.asarray(exit_.center[:2]) + normal * 6.6])
    assert out.intersects(plan.classes["sidewalk"])  # the sidewalk lies in front of the door
    footprint = Polygon(indoor[0].footprint).buffer(-0.1)
    for name in ("road", "curb", "crosswalk", "sidewalk", "water"):
        assert footprint.intersection(plan.classes[name]).area < 0.05, name
    for other in ann.buildings:
        if not other.indoor:
            assert footprint.intersection(Polygon(other.footprint)).area < 0.05


def _indoor_exit(scene):
    (building,) = [b for b in scene.annotations.buildings if b.indoor]
    (exit_,) = building.exits
    return exit_


def test_the_floor_is_level_with_the_ground_outside_the_exit(assembled) -> None:
    exit_ = _indoor_exit(assembled.scene)
    normal = np.array([math.cos(exit_.facing), math.sin(exit_.facing)])
    heights = SurfaceHeights(assembled.scene)  # the highest surface: the ceiling inside
    (floor,) = [s.mesh for s in assembled.scene.surfaces if s.terrain_class == "floor"]
    inside = floor.vertices[:, 2].max()
    outside = heights(np.asarray(exit_.center[:2]) + normal * 1.0)[0]
    assert abs(inside - outside) < 0.02 and abs(assembled.record["step"]) < 0.02
    assert not any(s.name == "apron" for s in assembled.scene.surfaces)


def test_rooms_and_street_are_one_island(assembled) -> None:
    scene = assembled.scene
    settings = scene_settings(NavMeshSettings.preset("i2o"), scene.annotations)
    assert settings.fine_region is not None
    finder = build_scene_navmesh(scene, settings)
    exit_ = _indoor_exit(scene)
    rooms = [r for b in scene.annotations.buildings if b.indoor for r in b.rooms]
    normal = np.array([math.cos(exit_.facing), math.sin(exit_.facing)])
    inside = [(*Polygon(r.polygon).representative_point().coords[0], exit_.center[2]) for r in rooms]
    street = (*(np.asarray(exit_.center[:2]) + normal * 4.0), exit_.center[2])
    islands = finder.island_of(np.array([*inside, street]))
    assert (islands >= 0).all() and len(set(islands.tolist())) == 1
    assert np.isfinite(finder.geodesic_distance(inside[0], street))


def test_a_named_facade_too_narrow_for_the_exit_is_refused(city, cafe) -> None:
    scene, plan = city
    (exit_,) = cafe.annotations.exits
    narrow = min(
        (f for b in scene.annotations.buildings for f in b.facades if f.road is not None),
        key=lambda f: f.width,
    )
    margin = (narrow.width - exit_.width) / 2 + 0.5  # the exit and its margins need 1 m more than it has
    settings = AssemblySettings(facade=narrow.id, exit_margin=margin)
    with pytest.raises(
        AssemblyError, match=rf"facade {narrow.id} of town is .* m wide; the exit of cafe needs"
    ):
        assemble_i2o(scene, plan, cafe, scene_id="x", settings=settings)


def test_a_building_that_fits_nowhere_is_refused_with_the_reasons(city) -> None:
    scene, plan = city
    huge = generate_building(
        "office", np.random.default_rng(0), scene_id="office", options=BuildingOptions(length=34.0)
    )
    with pytest.raises(AssemblyError, match="no road-facing facade of town holds office") as caught:
        assemble_i2o(scene, plan, huge, scene_id="x", settings=AssemblySettings(exit_margin=40.0))
    facing = [f for b in scene.annotations.buildings for f in b.facades if f.road and f.road_distance <= 30.0]
    assert f"the facade is too narrow for the exit: {len(facing)}" in str(caught.value)  # every one of them


def test_the_same_inputs_give_the_same_scene(city, cafe, assembled) -> None:
    scene, plan = city
    again = assemble_i2o(scene, plan, cafe, scene_id="cafe-town")
    assert again.record == assembled.record
    assert again.scene.annotations.model_dump() == assembled.scene.annotations.model_dump()
    for a, b in zip(again.scene.surfaces, assembled.scene.surfaces, strict=True):
        assert a.name == b.name and np.array_equal(a.mesh.vertices, b.mesh.vertices)


def test_the_same_inputs_give_byte_identical_scene_files(city, cafe, assembled, tmp_path) -> None:
    from navverse.scene.directory import write_scene_dir

    scene, plan = city
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    write_scene_dir(assembled.scene, tmp_path / "a")
    write_scene_dir(assemble_i2o(scene, plan, cafe, scene_id="cafe-town").scene, tmp_path / "b")
    names = sorted(p.relative_to(tmp_path / "a") for p in (tmp_path / "a").rglob("*") if p.is_file())
    assert names and names == sorted(
        p.relative_to(tmp_path / "b") for p in (tmp_path / "b").rglob("*") if p.is_file()
    )
    for name in names:
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes(), name


def test_storefronts_are_added_near_the_exit_and_never_on_the_building(city, assembled) -> None:
    from navverse.city.places.storefronts import StorefrontSettings, densify_storefronts

    _, plan = city
    anchor = np.asarray(assembled.scene.annotations.indoor_anchor[:2])
    region = Point(*anchor).buffer(50.0)
    first = densify_storefronts(
        assembled.scene, plan, np.random.default_rng(0), StorefrontSettings(), region=region, count=3
    )
    stores = first.scene.annotations.storefronts
    counts = first.counts
    assert stores, "the neighbourhood of the exit has room for a storefront"
    assert len(stores) <= 3 and counts["placed"] == len(stores)  # never more than asked
    assert counts["filled"] == counts["placed"] + sum(counts["rejected"].values())  # every try accounted
    (indoor,) = [b.id for b in first.scene.annotations.buildings if b.indoor]
    for store in stores:
        assert store.building != indoor
        assert (
            np.hypot(*(np.asarray(store.center[:2]) - anchor)) < 50.0 + 10.0
        )  # its facade's middle is inside
    # a second pass keeps them, numbers the new ones after them and never overlaps them
    second = densify_storefronts(
        first.scene, plan, np.random.default_rng(1), StorefrontSettings(), region=region, count=3
    )
    again = second.scene.annotations.storefronts
    assert again[: len(stores)] == stores and len({s.id for s in again}) == len(again)
    boxes = [Polygon(_corners(s)) for s in again]
    for i, a in enumerate(boxes):
        for b in boxes[i + 1 :]:
            assert a.intersection(b).area < 1e-6


def _corners(store) -> list[tuple[float, float]]:
    normal = np.array([math.cos(store.facing), math.sin(store.facing)])
    along = np.array([-normal[1], normal[0]])
    c = np.asarray(store.center[:2])
    w, d = store.size[0] / 2, store.size[1] / 2
    return [tuple(c + along * a * w + normal * b * d) for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1))]


def test_a_building_generated_to_fit_joins_the_city(city) -> None:
    from navverse.city.i2o.assembly import generated_fits
    from navverse.indoor.floorplan import depth_range
    from navverse.indoor.programs import PROGRAMS

    scene, plan = city
    result = next(generated_fits(scene, plan, "apartment", np.random.default_rng(0), scene_id="apt-town"))
    generated = result.record["generated"]
    program = PROGRAMS["apartment"]
    assert program.length[0] <= generated["length"] <= program.length[1]
    lo, hi = depth_range(program)
    assert lo <= generated["depth"] <= hi
    (building,) = [b for b in result.scene.annotations.buildings if b.indoor]
    sides = sorted(
        [
            math.dist(building.footprint[0], building.footprint[1]),
            math.dist(building.footprint[1], building.footprint[2]),
        ]
    )
    assert sides == pytest.approx(sorted([generated["length"], generated["depth"]]), abs=0.06)
    assert building.rooms and abs(result.record["step"]) < 0.02
    with pytest.raises(AssemblyError, match="unknown building type 'castle'"):
        next(generated_fits(scene, plan, "castle", np.random.default_rng(0), scene_id="x"))


def test_a_depth_outside_the_program_is_refused() -> None:
    from navverse.errors import SceneError

    with pytest.raises(SceneError, match=r"a cafe footprint is .* m deep; 40.00 m was asked"):
        generate_building("cafe", np.random.default_rng(0), scene_id="x", options=BuildingOptions(depth=40.0))


def test_generated_joins_come_lazily_best_facade_first(city) -> None:
    from navverse.city.i2o.assembly import generated_fits

    scene, plan = city
    rng = np.random.default_rng(0)
    joins = generated_fits(scene, plan, "apartment", rng, scene_id="apt-town")
    first = next(joins)
    after_first = rng.bit_generator.state
    # The first join is the same whatever follows, and the next facade's building is drawn only when
    # asked for.
    alone = np.random.default_rng(0)
    assert next(generated_fits(scene, plan, "apartment", alone, scene_id="apt-town")).record == first.record
    assert alone.bit_generator.state == after_first
    second = next(joins)
    assert second.record["facade"] != first.record["facade"]
    assert rng.bit_generator.state != after_first


def test_things_near_an_exit_are_counted_outside_the_building(assembled) -> None:
    from navverse.city.i2o.densify import things_near

    annotations = assembled.scene.annotations
    x, y = annotations.indoor_anchor[0], annotations.indoor_anchor[1]
    indoor = [Polygon(p) for p in annotations.indoor_polygons]
    inside = [any(p.contains(Point(o.center[:2])) for p in indoor) for o in annotations.objects]
    assert any(inside), "the cafe is furnished"
    outside = [
        o for o, within in zip(annotations.objects, inside, strict=True)
        if not within and math.dist(o.center[:2], (x, y)) <= 30.0
    ]  # fmt: skip
    assert things_near(assembled.scene, x, y, 30.0) == len(outside)
    assert things_near(assembled.scene, x, y, 1e-3) == 0
