"""Terrain with relief: seeded hills, grading along roads, a hilly city's scene measured by vertical
ray casts (road grades, curb steps, crosswalk lips, sidewalks on the terrain, buildings level and
sunk into the slope), and heights read from GeoTIFF DEMs written here."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import open3d as o3d
import pytest
import shapely
import trimesh
from pydantic import ValidationError
from shapely.geometry import LineString

from navverse.city.geometry.buildings import PLINTH_DEPTH
from navverse.city.geometry.dem import DemError, rasterio_missing, read_dem
from navverse.city.geometry.draped import DRAPE_STEP, draped_prism
from navverse.city.geometry.grades import road_grades
from navverse.city.geometry.scene import CityGeometry, city_scene, geometry_plan, scene_terrain
from navverse.city.geometry.street_plan import StreetPlan
from navverse.city.geometry.terrain import (
    GRADE_LIMITS,
    GRADE_MARGIN,
    WATER_GRADE_LIMIT,
    HeightGrid,
    grade_limit,
    graded,
    hills,
)
from navverse.city.map import CityMap, Frame
from navverse.city.osm.reader import read_osm
from navverse.city.synthetic.generator import SyntheticCityParams, synthetic_city
from navverse.nav import OUTDOOR
from navverse.nav.scene_navmesh import build_scene_navmesh
from navverse.scene.geometry import Scene
from navverse.scene.heights import SurfaceHeights

T_JUNCTION = Path(__file__).parent / "data" / "t_junction.osm"
HILLY = CityGeometry(relief_height=12.0, relief_wavelength=200.0)
SEED = 7


@pytest.fixture(scope="module")
def city() -> CityMap:
    return synthetic_city(SyntheticCityParams(size=(150, 150)), seed=1)


@pytest.fixture(scope="module")
def hilly(city: CityMap) -> tuple[Scene, StreetPlan]:
    plan = geometry_plan(city, HILLY)
    return city_scene(city, scene_id="hills", geometry=HILLY, plan=plan, seed=SEED), plan


def _centre_line_grades(terrain: HeightGrid, city: CityMap) -> dict[str, float]:
    """Steepest rise over 5 m along each class's centre lines, on the height field itself."""
    worst: dict[str, float] = {}
    for road in city.roads:
        line = LineString(road.centerline.points)
        points = shapely.get_coordinates(line.interpolate(np.arange(0.0, line.length, 1.0)))
        z = terrain(points)
        if len(z) > 5:
            worst[road.highway] = max(worst.get(road.highway, 0.0), float(np.abs(z[5:] - z[:-5]).max() / 5))
    return worst


# -- the height fields


def test_hills_are_seeded_smooth_finite_and_draw_from_no_global_generator() -> None:
    window = (-100.0, -80.0, 140.0, 120.0)
    state = np.random.get_state()[1].copy()
    a = hills(window, height=12.0, wavelength=300.0, seed=5)
    assert np.array_equal(np.random.get_state()[1], state)
    assert np.array_equal(a.heights, hills(window, height=12.0, wavelength=300.0, seed=5).heights)
    assert not np.allclose(a.heights, hills(window, height=12.0, wavelength=300.0, seed=6).heights)
    assert np.all(np.isfinite(a.heights))
    inside = a(np.column_stack([np.linspace(-100, 140, 500), np.linspace(-80, 120, 500)]))
    assert np.ptp(a.heights) >= np.ptp(inside) and np.ptp(a.heights) == pytest.approx(12.0, rel=0.05)
    assert a(np.array([[20.0, 20.0]]))[0] == pytest.approx(0.0, abs=1e-9)  # 0 at the window's centre
    steepest = max(np.abs(np.diff(a.heights, axis=k)).max() for k in (0, 1)) / a.cell
    assert steepest < 2 * np.pi * 12.0 / (0.7 * 300.0)  # smooth: no steeper than its waves allow
    assert hills(window, height=0.0, wavelength=300.0, seed=5).heights.max() == 0.0


def test_grading_keeps_each_road_within_its_class_and_leaves_a_gentle_relief_as_it_is(city: CityMap) -> None:
    steep = hills(city.window, height=30.0, wavelength=150.0, seed=SEED)
    before = _centre_line_grades(steep, city)
    assert any(before[h] > grade_limit(h) for h in before)  # too steep for its roads...
    after = _centre_line_grades(graded(steep, city), city)
    for highway, grade in after.items():
        assert grade <= grade_limit(highway) * GRADE_MARGIN + 0.005, (highway, grade)  # ...until graded
    gentle = hills(city.window, height=2.0, wavelength=900.0, seed=SEED)
    dry = city.model_copy(update={"areas": [a for a in city.areas if a.cls != "water"]})
    assert graded(gentle, dry).heights == pytest.approx(gentle.heights, abs=1e-9)
    # water lies level (the river falls at most 0.1 %), though the hills around it were gentle
    level = graded(gentle, city)
    water = shapely.union_all([shapely.Polygon(a.polygon.exterior) for a in city.areas if a.cls == "water"])
    wet = shapely.contains_xy(water, *level.nodes.T).reshape(level.heights.shape)
    both = wet[:, 1:] & wet[:, :-1]
    assert both.sum() > 100
    assert np.abs(np.diff(level.heights, axis=1))[both].max() <= WATER_GRADE_LIMIT * level.cell
    assert np.abs(np.diff(gentle.heights, axis=1))[both].max() > 3 * WATER_GRADE_LIMIT * level.cell


def test_grade_limits_are_one_table_by_road_class() -> None:
    assert GRADE_LIMITS["motorway"] < GRADE_LIMITS["primary"] < GRADE_LIMITS["secondary"]
    assert GRADE_LIMITS["secondary"] == GRADE_LIMITS["tertiary"] < GRADE_LIMITS["residential"]
    assert GRADE_LIMITS["residential"] < GRADE_LIMITS["service"] == GRADE_LIMITS["living_street"] <= 0.15
    assert grade_limit("no_such_class") == GRADE_LIMITS["residential"]


def test_relief_settings_are_declared_with_bounds_and_off_by_default(city: CityMap) -> None:
    assert CityGeometry().relief_height == 0.0
    assert not isinstance(scene_terrain(city, CityGeometry()), HeightGrid)  # flat, as before
    for bad in ({"relief_height": -1.0}, {"relief_height": 500.0}, {"relief_wavelength": 5.0}):
        with pytest.raises(ValidationError):
            CityGeometry(**bad)
    for name in ("relief_height", "relief_wavelength"):
        assert CityGeometry.model_fields[name].description


def test_a_draped_prism_follows_the_terrain_with_walls_only_on_its_own_boundary() -> None:
    polygon = shapely.Polygon(
        [(0, 0), (50, 0), (50, 30), (0, 30)], [[(10, 10), (20, 10), (20, 20), (10, 20)]]
    )

    def bumps(xy: np.ndarray) -> np.ndarray:
        return 3.0 * np.sin(xy[:, 0] / 7.0) + 2.0 * np.cos(xy[:, 1] / 5.0)

    mesh = draped_prism(polygon, top=bumps, depth=1.0, step=DRAPE_STEP, closed=True)
    v, f = mesh.vertices, mesh.faces
    normal_z = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])[:, 2]
    up, down, wall = f[normal_z > 1e-9], f[normal_z < -1e-9], f[np.abs(normal_z) <= 1e-9]
    tops = v[np.unique(up)]
    assert tops[:, 2] == pytest.approx(bumps(tops), abs=1e-12)
    assert shapely.contains_xy(polygon.buffer(-0.1), tops[:, 0], tops[:, 1]).any()  # inner vertices too
    foot = bumps(tops).min() - 1.0
    assert v[np.unique(down), 2] == pytest.approx(np.full(len(np.unique(down)), foot))
    walls = v[np.unique(wall)][:, :2]
    assert shapely.distance(polygon.boundary, shapely.points(walls)).max() < 1e-9  # no wall on a cut
    spans = np.ptp(v[wall][:, :, :2], axis=1)  # each wall piece spans one boundary edge
    assert np.hypot(spans[:, 0], spans[:, 1]).max() <= DRAPE_STEP + 1e-9
    # a vertical ray through the prism meets its top once and its bottom once
    rays = o3d.t.geometry.RaycastingScene()
    rays.add_triangles(o3d.core.Tensor(v.astype(np.float32)), o3d.core.Tensor(f.astype(np.uint32)))
    xy = np.random.default_rng(1).uniform((0.1, 0.1), (49.9, 29.9), (500, 2))
    origins = np.column_stack([xy, np.full(len(xy), 50.0), np.zeros((len(xy), 2)), np.full(len(xy), -1.0)])
    crossings = rays.count_intersections(o3d.core.Tensor(origins.astype(np.float32))).numpy()
    inside = shapely.contains_xy(polygon, xy[:, 0], xy[:, 1])
    assert np.array_equal(crossings, np.where(inside, 2, 0))


# -- a hilly city's scene, measured by vertical ray casts


def _across(plan: StreetPlan, high: str, low: str, offset: float, spacing: float) -> np.ndarray:
    """Pairs of points ``offset`` either side of the boundary between plan classes ``high`` and
    ``low``, ``spacing`` apart along it: shape (N, 2, 2), the ``high`` side first."""
    a, b = plan.classes[high], plan.classes[low]
    shared = shapely.line_merge(shapely.intersection(a.boundary, b.boundary))
    pairs = []
    for line in shapely.get_parts(shared):
        if not isinstance(line, LineString):
            continue
        for d in np.arange(0.3, line.length - 0.3, spacing):
            p, q = (np.asarray(line.interpolate(d + e).coords[0]) for e in (-0.05, 0.05))
            tangent = (q - p) / np.linalg.norm(q - p)
            normal = np.array([-tangent[1], tangent[0]]) * offset
            middle = (p + q) / 2.0
            for one, other in ((middle + normal, middle - normal), (middle - normal, middle + normal)):
                if shapely.contains_xy(a, *one) and shapely.contains_xy(b, *other):
                    pairs.append((one, other))
    return np.asarray(pairs).reshape(-1, 2, 2)


def test_a_hilly_city_keeps_its_roads_within_their_grades(hilly, city: CityMap) -> None:
    scene, plan = hilly
    grades = road_grades(scene, city, plan, road_depression=HILLY.road_depression)
    assert set(grades) == {r.highway for r in city.roads}
    for highway, grade in grades.items():
        assert grade <= grade_limit(highway), (highway, grade)
    assert max(grades.values()) > 0.05  # and the hills are there


def test_curbs_keep_their_height_along_the_slope(hilly) -> None:
    scene, plan = hilly
    heights = SurfaceHeights(scene)
    pairs = _across(plan, "curb", "road", 0.01, 1.0)
    assert len(pairs) > 300
    step = heights(pairs[:, 0]) - heights(pairs[:, 1])
    assert np.ptp(heights(pairs[:, 0])) > 5.0  # the curbs run up and down hills
    assert step == pytest.approx(np.full(len(step), HILLY.road_depression), abs=0.01)


def test_crosswalk_ramps_rise_to_the_lowered_curb_on_the_slope(hilly) -> None:
    scene, plan = hilly
    heights = SurfaceHeights(scene)
    pairs = _across(plan, "lowered_curb", "crosswalk", 0.005, 0.5)
    assert len(pairs) > 50
    lip = heights(pairs[:, 0]) - heights(pairs[:, 1])
    assert lip == pytest.approx(np.full(len(lip), HILLY.lowered_curb_height), abs=0.003)


def test_sidewalks_lie_on_the_terrain(hilly, city: CityMap) -> None:
    scene, plan = hilly
    terrain = scene_terrain(city, HILLY, seed=SEED)
    sidewalk = plan.classes["sidewalk"]
    x0, y0, x1, y1 = sidewalk.bounds
    points = np.random.default_rng(0).uniform((x0, y0), (x1, y1), (4000, 2))
    points = points[shapely.contains_xy(sidewalk, points[:, 0], points[:, 1])]
    assert len(points) > 200
    assert SurfaceHeights(scene)(points) == pytest.approx(terrain(points), abs=0.05)


def test_buildings_stand_level_and_reach_below_the_ground_around_them(hilly, city: CityMap) -> None:
    scene, _ = hilly
    terrain = scene_terrain(city, HILLY, seed=SEED)
    solids = {s.name: s.mesh for s in scene.surfaces if s.terrain_class == "building"}
    assert len(solids) == len(scene.annotations.buildings) > 10
    sunk = 0
    for building in scene.annotations.buildings:
        mesh = solids[f"building_{building.id:04d}"]
        levels = np.unique(mesh.vertices[:, 2])
        assert len(levels) == 2  # a level floor and a level roof
        assert trimesh.Trimesh(mesh.vertices, mesh.faces).is_watertight
        outline = shapely.Polygon(building.footprint)
        around = shapely.get_coordinates(shapely.segmentize(outline, 0.5))
        ground = terrain(around)
        assert levels[0] == pytest.approx(building.base_height - PLINTH_DEPTH)
        assert building.base_height <= ground.min() + 0.02  # its floor at the lowest ground...
        assert levels[0] < ground.min() - 0.3  # ...its solid below it
        sunk += np.ptp(ground) > 0.5
    assert sunk > 5  # many stand on a slope


@pytest.mark.parametrize("geometry", [HILLY, CityGeometry(slope=(0.05, 0.03))], ids=["hills", "slope"])
def test_no_navmesh_is_left_inside_buildings_sunk_into_a_slope(city: CityMap, geometry: CityGeometry) -> None:
    scene = city_scene(city, scene_id="sunk", geometry=geometry, seed=SEED)
    finder = build_scene_navmesh(scene, OUTDOOR, jobs=2)
    inside = shapely.union_all(
        [shapely.Polygon(b.footprint).buffer(-0.5) for b in scene.annotations.buildings]
    )
    middles = np.array([polygon[:, :2].mean(axis=0) for polygon in finder.polygons()])
    assert len(middles) > 100
    assert not shapely.contains_xy(inside, middles[:, 0], middles[:, 1]).any()


def test_the_same_seed_gives_the_same_city_and_another_seed_other_hills(hilly, city: CityMap) -> None:
    scene, plan = hilly
    again = city_scene(city, scene_id="hills", geometry=HILLY, plan=plan, seed=SEED)
    other = city_scene(city, scene_id="hills", geometry=HILLY, plan=plan, seed=SEED + 1)
    for a, b in zip(scene.surfaces, again.surfaces, strict=True):
        assert np.array_equal(a.mesh.vertices, b.mesh.vertices) and np.array_equal(a.mesh.faces, b.mesh.faces)
    sidewalk = lambda s: next(x.mesh.vertices for x in s.surfaces if x.name == "sidewalk")  # noqa: E731
    assert not np.array_equal(sidewalk(scene), sidewalk(other))


# -- DEMs


@pytest.fixture(scope="module")
def junction() -> CityMap:
    return read_osm(T_JUNCTION, center=(48.0, 11.0), size_m=(200.0, 200.0))


def _write_dem(
    path: Path, height, *, crs: str, bounds: tuple[float, float, float, float], pixels: int
) -> None:
    """A GeoTIFF of ``height(x, y)`` (x, y in UTM 32N metres) at the centres of ``pixels`` x ``pixels``
    pixels over ``bounds`` (west, south, east, north) in ``crs``."""
    import rasterio  # make setup installs the dem extra: a missing rasterio is a failure, not a skip
    from affine import Affine
    from pyproj import Transformer

    west, south, east, north = bounds
    sx, sy = (east - west) / pixels, (north - south) / pixels
    cx = west + sx * (np.arange(pixels) + 0.5)
    cy = north - sy * (np.arange(pixels) + 0.5)
    gx, gy = np.meshgrid(cx, cy)
    ux, uy = Transformer.from_crs(crs, "EPSG:32632", always_xy=True).transform(gx, gy)
    profile = {
        "driver": "GTiff",
        "width": pixels,
        "height": pixels,
        "count": 1,
        "dtype": "float64",
        "crs": crs,
    }
    with rasterio.open(path, "w", **profile, transform=Affine(sx, 0.0, west, 0.0, -sy, north)) as out:
        out.write(height(ux, uy), 1)


def _utm_origin() -> tuple[float, float]:
    from pyproj import Transformer

    return Transformer.from_crs("EPSG:4326", "EPSG:32632", always_xy=True).transform(11.0, 48.0)


def test_a_dem_is_read_in_the_map_frame_relative_to_the_window_centre(
    tmp_path: Path, junction: CityMap
) -> None:
    e0, n0 = _utm_origin()
    plane = tmp_path / "plane.tif"
    _write_dem(
        plane,
        lambda x, y: 300.0 + 0.03 * (x - e0) - 0.02 * (y - n0),
        crs="EPSG:32632",
        bounds=(e0 - 150, n0 - 150, e0 + 150, n0 + 150),
        pixels=60,
    )
    grid = read_dem(plane, frame=junction.frame, window=junction.window)
    assert grid.heights.ravel() == pytest.approx(grid.nodes @ [0.03, -0.02], abs=1e-6)
    # a hill written in longitude and latitude, read back in the map's UTM frame
    hill = lambda x, y: 500.0 + 8.0 * np.exp(-(((x - e0 - 30) ** 2 + (y - n0 + 20) ** 2) / 60.0**2))  # noqa: E731
    lonlat = tmp_path / "hill.tif"
    _write_dem(lonlat, hill, crs="EPSG:4326", bounds=(10.997, 47.998, 11.003, 48.002), pixels=300)
    grid = read_dem(lonlat, frame=junction.frame, window=junction.window)
    nodes = grid.nodes
    expected = hill(nodes[:, 0] + e0, nodes[:, 1] + n0) - hill(e0, n0)
    assert grid.heights.ravel() == pytest.approx(expected, abs=0.02)


def test_a_steep_dem_is_graded_along_the_roads(tmp_path: Path, junction: CityMap) -> None:
    e0, n0 = _utm_origin()
    steep = tmp_path / "steep.tif"
    _write_dem(
        steep,
        lambda x, y: 0.25 * (x - e0) + 0.1 * (y - n0),
        crs="EPSG:32632",
        bounds=(e0 - 150, n0 - 150, e0 + 150, n0 + 150),
        pixels=100,
    )
    geometry = CityGeometry(junction_crosswalks=False)
    dem = read_dem(steep, frame=junction.frame, window=junction.window)
    plan = geometry_plan(junction, geometry)
    scene = city_scene(junction, scene_id="steep", geometry=geometry, plan=plan, dem=dem)
    grades = road_grades(scene, junction, plan, road_depression=geometry.road_depression)
    assert grades["residential"] <= GRADE_LIMITS["residential"]
    assert grades["residential"] > 0.08  # graded down to its limit, not flattened
    heights = SurfaceHeights(scene)(np.array([[-40.0, 30.0], [90.0, 90.0]]))
    assert heights[1] - heights[0] > 10.0  # the land away from the roads keeps climbing


def test_a_dem_that_does_not_cover_the_window_or_a_map_without_a_frame_is_refused(
    tmp_path: Path, junction: CityMap
) -> None:
    e0, n0 = _utm_origin()
    small = tmp_path / "small.tif"
    _write_dem(
        small, lambda x, y: x * 0.0, crs="EPSG:32632", bounds=(e0 - 50, n0 - 50, e0 + 50, n0 + 50), pixels=10
    )
    with pytest.raises(DemError, match=r"DEM small\.tif does not cover the city's window"):
        read_dem(small, frame=junction.frame, window=junction.window)
    with pytest.raises(DemError, match="no geographic frame"):
        read_dem(
            small, frame=Frame(epsg=0, origin_lat=0.0, origin_lon=0.0), window=(-10.0, -10.0, 10.0, 10.0)
        )


def test_without_rasterio_a_dem_says_how_to_install_it(
    monkeypatch: pytest.MonkeyPatch, junction: CityMap
) -> None:
    monkeypatch.setitem(sys.modules, "rasterio", None)
    assert rasterio_missing() == (
        "reading a DEM needs rasterio, which is not installed: pip install 'navverse[dem]'"
    )
    with pytest.raises(DemError, match=r"pip install 'navverse\[dem\]'"):
        read_dem("any.tif", frame=junction.frame, window=junction.window)
