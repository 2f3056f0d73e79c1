"""The hand-laid T-junction (tests/navverse/city/data/t_junction.osm) as a 3-D scene, measured by
vertical ray casts, and driven over by Spot and the TurtleBot under physics.

The main street runs west-east along y = 0 (width=7, sidewalk=both, 1.5 m), the side street north
from the junction along x = 0 (untagged: 6.5 m, sidewalks on both sides by the residential rule), a
lowered crossing at x = -20 on the main street.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import open3d as o3d
import pytest
import trimesh

from navverse.city.geometry.scene import CityGeometry, city_scene
from navverse.city.osm.reader import read_osm
from navverse.scene.geometry import Scene
from navverse.sim.embodiments import make_embodiment
from navverse.sim.rollout import follow_path
from navverse.sim.simulator import Simulator
from navverse.sim.world import World

T_JUNCTION = Path(__file__).parent / "data" / "t_junction.osm"
GEOMETRY = CityGeometry(junction_crosswalks=False)


@pytest.fixture(scope="module")
def junction() -> Scene:
    city = read_osm(T_JUNCTION, center=(48.0, 11.0), size_m=(200.0, 200.0))
    return city_scene(city, scene_id="t-junction", geometry=GEOMETRY)


class Caster:
    """Vertical ray casts: the height and terrain class of the top surface at xy points."""

    def __init__(self, scene: Scene) -> None:
        labeled = scene.world_mesh(include_objects=False)
        self.classes = np.asarray(labeled.class_names)[labeled.class_index]
        self.rays = o3d.t.geometry.RaycastingScene()
        self.rays.add_triangles(
            o3d.core.Tensor(labeled.mesh.vertices.astype(np.float32)),
            o3d.core.Tensor(labeled.mesh.faces.astype(np.uint32)),
        )

    def __call__(self, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        xy = np.atleast_2d(np.asarray(xy, dtype=np.float64))
        rays = np.zeros((len(xy), 6), dtype=np.float32)
        rays[:, :2], rays[:, 2], rays[:, 5] = xy, 100.0, -1.0
        hit = self.rays.cast_rays(o3d.core.Tensor(rays))
        t = hit["t_hit"].numpy()
        return 100.0 - t, self.classes[hit["primitive_ids"].numpy().astype(np.int64) % (2**32)]


@pytest.fixture(scope="module")
def cast(junction: Scene) -> Caster:
    return Caster(junction)


def _line(start: tuple[float, float], end: tuple[float, float], step: float = 0.005) -> np.ndarray:
    n = round(np.hypot(end[0] - start[0], end[1] - start[1]) / step) + 1
    return np.linspace(start, end, n)


def _extent(points: np.ndarray, mask: np.ndarray) -> float:
    """Length of the run of ``points`` where ``mask`` holds (one run expected)."""
    inside = points[mask]
    return float(np.hypot(*(inside[-1] - inside[0])))


def test_road_widths_are_the_tagged_and_default_widths(cast: Caster) -> None:
    across_main = _line((-60.0, -8.0), (-60.0, 8.0))
    _, classes = cast(across_main)
    assert _extent(across_main, classes == "road") == pytest.approx(7.0, abs=0.05)  # width=7
    across_side = _line((-8.0, 50.0), (8.0, 50.0))
    _, classes = cast(across_side)
    assert _extent(across_side, classes == "road") == pytest.approx(6.5, abs=0.05)  # residential default


def test_sidewalks_lie_where_tags_and_rules_say(cast: Caster) -> None:
    # Main street (sidewalk=both): from the curb strip's back (3.65 m) to 5.0 m on each side.
    for sign in (1.0, -1.0):
        _, classes = cast([(-60.0, sign * y) for y in (3.6, 3.7, 4.9, 5.1)])
        assert classes.tolist() == ["curb", "sidewalk", "sidewalk", "ground"]
    # Side street (untagged residential: both sides by rule), half width 3.25 m.
    for sign in (1.0, -1.0):
        _, classes = cast([(sign * x, 50.0) for x in (3.2, 3.35, 4.6, 4.8)])
        assert classes.tolist() == ["road", "curb", "sidewalk", "ground"]
    # No sidewalk south of the side street's end: the main street's south side has its own only.
    _, classes = cast([(0.0, -5.1)])
    assert classes.tolist() == ["ground"]


def test_the_curb_is_a_20_cm_step_and_2_cm_at_the_crosswalk(cast: Caster) -> None:
    for x in (-70.0, -45.0, 50.0):
        for sign in (1.0, -1.0):
            heights, classes = cast([(x, sign * 3.49), (x, sign * 3.51)])
            assert classes.tolist() == ["road", "curb"]
            assert heights[1] - heights[0] == pytest.approx(0.20, abs=0.01)
    # At the crossing (x = -20): the crosswalk ramps up to the lowered curb; a step of at most 3 cm.
    for sign in (1.0, -1.0):
        heights, classes = cast([(-20.0, sign * 3.49), (-20.0, sign * 3.51), (-20.0, sign * 4.0)])
        assert classes.tolist() == ["crosswalk", "crosswalk", "sidewalk"]
        assert 0.0 <= heights[1] - heights[0] <= 0.03
        assert heights[2] == pytest.approx(0.0, abs=1e-4)
    # The ramp is gentle: from road level 1.5 m into the road up to the lip.
    heights, _ = cast(_line((-20.0, -3.49), (-20.0, 0.0), step=0.1))
    slopes = np.abs(np.diff(heights)) / 0.1
    assert slopes.max() < np.tan(np.radians(8.0))
    assert heights.min() == pytest.approx(-0.2, abs=1e-4)


def test_buildings_have_their_tagged_heights_and_road_facing_facades(junction: Scene, cast: Caster) -> None:
    heights, classes = cast([(25.0, -20.0), (20.0, 20.0), (-55.0, 15.0), (-40.0, 30.0)])
    assert classes.tolist() == ["building", "building", "building", "ground"]  # the courtyard is open
    assert heights[:3] == pytest.approx([12.0, 9.0, 12.0], abs=1e-4)  # height=12, 3 and 4 levels
    by_osm = {b.osm: b for b in junction.annotations.buildings}
    a = by_osm["way/110"]
    facing = [f for f in a.facades if f.road is not None]
    assert len(facing) == 1 and facing[0].normal == pytest.approx((0.0, 1.0), abs=1e-3)
    assert facing[0].road_distance == pytest.approx(10.0 - 3.5, abs=0.02)  # facade y=-10, road edge -3.5
    assert [e.facade for e in a.exits] == [facing[0].id]
    for surface in junction.surfaces:
        if surface.terrain_class == "building":
            assert trimesh.Trimesh(surface.mesh.vertices, surface.mesh.faces).is_watertight


def test_the_scene_records_the_map_frame(junction: Scene) -> None:
    geo = junction.annotations.geo
    assert (geo.epsg, geo.origin_lat, geo.origin_lon) == (32632, 48.0, 11.0)
    assert geo.map == "t_junction.osm" and "OpenStreetMap" in geo.attribution


def test_raised_kerb_keeps_the_full_curb_at_a_crossing(tmp_path: Path) -> None:
    text = T_JUNCTION.read_text(encoding="utf-8").replace('k="kerb" v="lowered"', 'k="kerb" v="raised"')
    raised = tmp_path / "raised.osm"
    raised.write_text(text, encoding="utf-8")
    city = read_osm(raised, center=(48.0, 11.0), size_m=(200.0, 200.0))
    scene = city_scene(city, scene_id="raised", geometry=GEOMETRY)
    heights, classes = Caster(scene)([(-20.0, 3.49), (-20.0, 3.51)])
    assert classes.tolist() == ["crosswalk", "curb"]
    assert heights[1] - heights[0] == pytest.approx(0.2, abs=0.01)


def test_road_depression_is_a_setting(junction: Scene) -> None:
    city = read_osm(T_JUNCTION, center=(48.0, 11.0), size_m=(200.0, 200.0))
    geometry = CityGeometry(road_depression=0.15, junction_crosswalks=False)
    heights, _ = Caster(city_scene(city, scene_id="d", geometry=geometry))([(-60.0, 3.49), (-60.0, 3.51)])
    assert heights[1] - heights[0] == pytest.approx(0.15, abs=0.01)


def _drive(scene: Scene, robot_name: str, path: list[tuple[float, float, float]], cache: Path):
    robot = make_embodiment(robot_name)
    with World(scene, collision_cache=cache) as world:
        sim = Simulator(world, robot)
        points = np.asarray(path, dtype=float)
        heading = points[1, :2] - points[0, :2]
        sim.spawn(points[0], float(np.arctan2(heading[1], heading[0])))
        outcome = follow_path(sim, points)
    return outcome, outcome.final_distance


CROSSING = [(-20.0, -6.0, 0.0), (-20.0, 6.0, 0.0)]
"""South sidewalk -> crosswalk -> north sidewalk, at the crossing."""
MID_BLOCK = [(-60.0, -6.0, 0.0), (-60.0, 6.0, 0.0)]
"""The same, 40 m west: down the curb, across the road, up the curb."""


@pytest.mark.parametrize("path", [CROSSING, MID_BLOCK], ids=["crosswalk", "mid-block"])
def test_spot_crosses_at_the_crosswalk_and_over_the_curbs(junction: Scene, path, tmp_path: Path) -> None:
    outcome, miss = _drive(junction, "spot", path, tmp_path)
    assert outcome.termination is None and miss < 0.3
    if path is MID_BLOCK:  # it really went down to the road and back up
        assert outcome.trajectory[:, 3].min() < outcome.trajectory[0, 3] - 0.15


def test_the_turtlebot_crosses_only_at_the_crosswalk(junction: Scene, tmp_path: Path) -> None:
    outcome, miss = _drive(junction, "turtlebot", CROSSING, tmp_path)
    assert outcome.termination is None and miss < 0.3
    outcome, miss = _drive(junction, "turtlebot", MID_BLOCK, tmp_path)
    assert miss > 5.0  # the 20 cm curb stops it: it never reaches the far sidewalk


def test_service_roads_are_shared_surfaces_without_curbs(tmp_path: Path) -> None:
    text = T_JUNCTION.read_text(encoding="utf-8")
    side = text.index('<way id="101">')
    text = text[:side] + text[side:].replace('v="residential"', 'v="service"', 1)
    service = tmp_path / "service.osm"
    service.write_text(text, encoding="utf-8")
    city = read_osm(service, center=(48.0, 11.0), size_m=(200.0, 200.0))
    heights, classes = Caster(city_scene(city, scene_id="s", geometry=GEOMETRY))([(0.0, 50.0), (2.5, 50.0)])
    assert classes.tolist() == ["road", "ground"]  # no sidewalk (the service rule), no curb
    assert heights == pytest.approx([0.0, 0.0], abs=1e-4)


def test_on_a_slope_every_surface_follows_the_terrain_and_curbs_keep_their_height() -> None:
    city = read_osm(T_JUNCTION, center=(48.0, 11.0), size_m=(200.0, 200.0))
    grade = np.array([0.04, -0.03])  # rise per meter east, north
    scene = city_scene(
        city, scene_id="t-slope", geometry=GEOMETRY, terrain=lambda points: points[:, :2] @ grade
    )
    cast = Caster(scene)
    for x in (-70.0, -45.0, 50.0):
        for sign in (1.0, -1.0):
            points = np.array([(x, sign * 3.49), (x, sign * 3.51), (x, sign * 4.5), (x, 0.0)])
            heights, classes = cast(points)
            assert classes.tolist() == ["road", "curb", "sidewalk", "road"]
            level = points @ grade
            assert heights[1] - heights[0] == pytest.approx(0.20 + level[1] - level[0], abs=0.01)
            assert heights[2] == pytest.approx(level[2], abs=1e-3)  # sidewalk: on the terrain
            assert heights[3] == pytest.approx(level[3] - 0.2, abs=1e-3)  # road: 0.2 m below it
    heights, classes = cast([(25.0, -20.0), (-40.0, 30.0)])
    assert classes.tolist() == ["building", "ground"]
    assert heights[1] == pytest.approx(np.array([-40.0, 30.0]) @ grade, abs=1e-3)
    for surface in scene.surfaces:
        if surface.terrain_class == "building":
            assert trimesh.Trimesh(surface.mesh.vertices, surface.mesh.faces).is_watertight
