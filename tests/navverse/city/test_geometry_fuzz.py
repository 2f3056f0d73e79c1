"""Any window of a real extract gives a city: window centres and sizes drawn over several extracts, and
the windows that once broke the street geometry (a curb overlay's "side location conflict", a "ring
edge missing", a polygon GEOS could not triangulate, a window with no curbed road)."""

from __future__ import annotations

from itertools import pairwise
from pathlib import Path

import numpy as np
import pytest
import shapely
from shapely.geometry import box

from navverse.city.geometry.prisms import polygon_prism, triangulate
from navverse.city.geometry.scene import CityGeometry, city_scene, geometry_plan
from navverse.city.map import CityMapError
from navverse.city.osm.reader import read_osm
from navverse.city.precision import GRID

RAW = Path(__file__).parents[3] / "data" / "raw" / "osm"
GEOMETRY = CityGeometry()
# Windows (file, (lat, lon), side m) that broke the geometry before it was made on a grid.
ONCE_BROKEN = [
    ("nyc-lower-east-side.osm.pbf", (40.722118278028134, -73.98883246219755), 502.8949032319392),
    ("london-farringdon.osm.pbf", (51.5145689506425, -0.10828369728060774), 502.0740111058332),
    ("le-havre-centre.osm.xml.gz", (49.49310785241219, 0.10334585105078373), 150.27574782640528),
    ("berlin-mitte.osm.xml.gz", (52.52095003528426, 13.395707648932873), 62.26053932602442),
]
# Boxes (min_lat, min_lon, max_lat, max_lon) of dense data in extracts of four cities, for drawn windows.
FUZZED = {
    "nyc-lower-east-side.osm.pbf": (40.7165, -73.9948, 40.7244, -73.9831),
    "munich-altstadt.osm.pbf": (48.1314, 11.5657, 48.1434, 11.5861),
    "bishkek-centre.osm.xml.gz": (42.8433, 74.6248, 42.8728, 74.6484),
    "essen-south.osm.xml.gz": (51.4311, 7.0071, 51.4340, 7.0124),
}


def _check_city(name: str, center: tuple[float, float], side: float) -> None:
    try:
        city = read_osm(RAW / name, center=center, size_m=(side, side))
    except CityMapError as exc:  # an empty window is refused with a reason; nothing else may fail
        assert "no roads or buildings" in str(exc)
        return
    plan = geometry_plan(city, GEOMETRY)
    window = box(*city.window)
    classes = [g for g in plan.classes.values() if not g.is_empty]
    assert all(g.is_valid for g in classes)
    # The classes tile the window: their areas add up to it, and no two overlap by more than a seam.
    assert sum(g.area for g in classes) == pytest.approx(window.area, rel=1e-6, abs=GRID * window.length)
    union = shapely.union_all(classes, grid_size=GRID)
    assert union.area == pytest.approx(window.area, rel=1e-6, abs=GRID * window.length)
    scene = city_scene(city, scene_id="fuzz", geometry=GEOMETRY, plan=plan)
    assert scene.surfaces and all(np.isfinite(s.mesh.vertices).all() for s in scene.surfaces)


@pytest.mark.slow(seconds=30)
@pytest.mark.parametrize(("name", "center", "side"), ONCE_BROKEN, ids=[c[0] for c in ONCE_BROKEN])
def test_windows_that_once_broke_the_geometry_build(
    name: str, center: tuple[float, float], side: float
) -> None:
    _check_city(name, center, side)


@pytest.mark.slow(seconds=40)
@pytest.mark.parametrize("name", sorted(FUZZED))
def test_drawn_windows_of_real_extracts_build(name: str) -> None:
    rng = np.random.default_rng(sorted(FUZZED).index(name))
    min_lat, min_lon, max_lat, max_lon = FUZZED[name]
    for _ in range(4):
        center = (float(rng.uniform(min_lat, max_lat)), float(rng.uniform(min_lon, max_lon)))
        side = float(rng.choice([40.0, 120.0, 250.0])) + float(rng.uniform(0.0, 3.0))
        _check_city(name, center, side)


# A valid polygon of a Le Havre window with two sliver holes, on which GEOS's triangulation gives up.
SLIVER_HOLES = (
    "POLYGON ((17.944656143177085 41.66781130781387, 18.065757561938952 41.65273079333703, "
    "21.810683724879453 41.03076365742974, 21.564926162940502 39.55103286409271, "
    "21.31916860100155 38.071302070755685, 17.634486163772415 38.68326377106644, "
    "17.36968076466003 38.705346571466244, 17.86282798397713 41.674635167571836, "
    "17.944656143177085 41.66781130781387), "
    "(17.880243725711324 40.162994564403476, 17.880243725711367 40.16299456440347, "
    "21.564926162940502 39.55103286409271, 17.880243725711324 40.162994564403476), "
    "(17.850109391307978 40.16799935350901, 17.789583752124955 40.17553648880644, "
    "17.75914230694971 40.17807507888028, 17.880243725711324 40.162994564403476, "
    "17.850109391307978 40.16799935350901))"
)


def test_a_polygon_geos_cannot_triangulate_is_triangulated_on_its_own_rings() -> None:
    polygon = shapely.from_wkt(SLIVER_HOLES)
    assert polygon.is_valid
    with pytest.raises(shapely.errors.GEOSException):
        shapely.constrained_delaunay_triangles(polygon)
    points, faces = triangulate(polygon)
    a, b, c = (points[faces[:, k]] for k in range(3))
    areas = 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    assert (areas >= 0).all() and areas.sum() == pytest.approx(polygon.area, rel=1e-9)
    # Every edge of every ring is a triangle's edge, so the prism's walls meet its top.
    index = {tuple(p): i for i, p in enumerate(points)}
    sides = {
        frozenset(pair) for face in faces.tolist() for pair in zip(face, face[1:] + face[:1], strict=True)
    }
    for ring in (polygon.exterior, *polygon.interiors):
        corners = [index[c] for c in ring.coords]
        assert all(frozenset(e) in sides for e in pairwise(corners) if e[0] != e[1])
    mesh = polygon_prism(polygon, top=lambda xy: np.ones(len(xy)), bottom=0.0)
    assert mesh.num_faces == 2 * len(faces) + 2 * sum(
        len(r.coords) - 1 for r in (polygon.exterior, *polygon.interiors)
    )
