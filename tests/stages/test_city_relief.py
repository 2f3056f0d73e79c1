"""Cities with relief through the engine: a small synthetic city on seeded hills built end to end with
``navverse build`` (populated, storefronts, navmesh over its sidewalks, road grades within their
class's limits in the manifest), and an OSM city on a GeoTIFF DEM: built on it, refused when the DEM
does not cover the window, and refused in one line when rasterio is missing."""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

import numpy as np
import pytest
import shapely

from navverse.city.geometry.street_plan import load_street_plan
from navverse.city.geometry.terrain import GRADE_LIMITS
from navverse.nav import PathFinder
from navverse.scene.directory import read_annotations, read_scene
from navverse.scene.heights import SurfaceHeights
from pipeline.store import ArtifactStore
from pipeline.workspace import Workspace
from tests.stages.conftest import workspace_with

T_JUNCTION = Path(__file__).parents[1] / "navverse" / "city" / "data" / "t_junction.osm"
HILLS = """\
extends: outdoor-city
seeds: [3]
stages:
  synthetic_city: {size: [160, 160]}
  city_geometry: {relief_height: 10, relief_wavelength: 150}
"""
DEM_CITY = """\
stages:
  osm_city:
    source: ../../data/raw/t_junction.osm
    center: [48.0, 11.0]
    size_m: [200, 200]
  city_geometry: {{junction_crosswalks: false, dem: ../../data/raw/{dem}}}
"""


@pytest.mark.slow(seconds=20)
def test_a_hilly_city_builds_end_to_end_with_its_sidewalks_on_the_navmesh(
    tmp_path: Path, navverse_here
) -> None:
    root = tmp_path / "ws"
    workspace_with(root, [], {"scenes/hills.yaml": HILLS})
    result = navverse_here(root, "build", "hills-s3")
    assert result.returncode == 0, result.stdout + result.stderr
    store = ArtifactStore(Workspace(root).built_dir)
    street = store.target_output("hills-s3", "street_geometry")
    final = store.target_output("hills-s3", "scene")
    grades = store.read_manifest(street)["stats"]["road_grade_max"]
    assert set(grades) >= {"residential", "secondary"}
    for highway, grade in grades.items():
        assert grade <= GRADE_LIMITS[highway], (highway, grade)
    assert max(grades.values()) > 0.03  # hills, not a flat city
    scene = read_scene(final)
    annotations = read_annotations(final)
    assert annotations.storefronts and any(o.category != "storefront" for o in annotations.objects)
    plan = load_street_plan(street / "street_plan.json")
    sidewalk = plan.classes["sidewalk"].buffer(-0.4)  # off the curbs and walls
    x0, y0, x1, y1 = sidewalk.bounds
    gx, gy = (g.ravel() for g in np.meshgrid(np.arange(x0, x1, 0.5), np.arange(y0, y1, 0.5)))
    inside = shapely.contains_xy(sidewalk, gx, gy)
    xy = np.column_stack([gx[inside], gy[inside]])
    heights = SurfaceHeights(scene)(xy)
    assert np.ptp(heights[np.isfinite(heights)]) > 4.0  # the sidewalks climb the hills
    finder = PathFinder.load(final / "navmesh.bin")
    on_mesh = finder.is_navigable(np.column_stack([xy, heights]), max_y_delta=0.3)
    assert len(xy) > 300 and on_mesh.mean() > 0.9, on_mesh.mean()  # objects stand on a few points
    # and none inside the buildings, whose solids reach below the sloping ground they stand on
    inside = shapely.union_all([shapely.Polygon(b.footprint).buffer(-0.5) for b in annotations.buildings])
    middles = np.array([polygon[:, :2].mean(axis=0) for polygon in finder.polygons()])
    assert not shapely.contains_xy(inside, middles[:, 0], middles[:, 1]).any()
    shutil.rmtree(root)


def _dem(path: Path, *, covers: float = 400.0) -> None:
    """A GeoTIFF in UTM 32N around (48.0, 11.0): 420 m + 3 % east - 2 % north, ``covers`` m square."""
    import rasterio  # make setup installs the dem extra: a missing rasterio is a failure, not a skip
    from affine import Affine
    from pyproj import Transformer

    east, north = Transformer.from_crs("EPSG:4326", "EPSG:32632", always_xy=True).transform(11.0, 48.0)
    pixel = 5.0
    n = int(covers / pixel)
    x = east - covers / 2 + pixel * (np.arange(n) + 0.5) - east
    y = north + covers / 2 - pixel * (np.arange(n) + 0.5) - north
    z = 420.0 + 0.03 * x[None, :] - 0.02 * y[:, None]
    profile = {
        "driver": "GTiff", "width": n, "height": n, "count": 1, "dtype": "float32", "crs": "EPSG:32632",
        "transform": Affine(pixel, 0.0, east - covers / 2, 0.0, -pixel, north + covers / 2),
    }  # fmt: skip
    with rasterio.open(path, "w", **profile) as out:
        out.write(z.astype(np.float32), 1)


def _dem_workspace(root: Path, covers: float) -> None:
    raw = root / "data" / "raw"
    raw.mkdir(parents=True)
    shutil.copy(T_JUNCTION, raw / "t_junction.osm")
    _dem(raw / "dem.tif", covers=covers)
    workspace_with(root, [], {"scenes/city.yaml": DEM_CITY.format(dem="dem.tif")})


def test_an_osm_city_follows_its_dem(tmp_path: Path, navverse_here) -> None:
    root = tmp_path / "ws"
    _dem_workspace(root, covers=400.0)
    result = navverse_here(root, "build", "city")
    assert result.returncode == 0, result.stdout + result.stderr
    street = ArtifactStore(Workspace(root).built_dir).target_output("city", "street_geometry")
    heights = SurfaceHeights(read_scene(street))
    # sidewalk and ground points (the main street runs along y = 0 with 1.5 m sidewalks from 3.65 m)
    points = np.array([(-60.0, 4.5), (50.0, -4.5), (-70.0, -4.5), (-40.0, 30.0)])
    assert heights(points) == pytest.approx(points @ [0.03, -0.02], abs=0.01)
    assert street.joinpath("manifest.json").is_file()


def test_a_dem_short_of_the_window_is_refused(tmp_path: Path, navverse_here) -> None:
    root = tmp_path / "ws"
    _dem_workspace(root, covers=120.0)
    result = navverse_here(root, "build", "city")
    output = result.stdout + result.stderr
    assert result.returncode == 1 and "Traceback" not in output
    assert "DEM dem.tif does not cover the city's window" in output, output


def test_a_dem_without_rasterio_is_one_line_saying_how_to_install_it(
    tmp_path: Path, navverse_here, monkeypatch: pytest.MonkeyPatch
) -> None:
    root = tmp_path / "ws"
    _dem_workspace(root, covers=400.0)
    monkeypatch.setitem(sys.modules, "rasterio", None)  # `import rasterio` fails as if not installed
    result = navverse_here(root, "build", "city")
    output = result.stdout + result.stderr
    assert result.returncode == 1 and "Traceback" not in output
    lines = [line for line in output.splitlines() if "pip install 'navverse[dem]'" in line]
    assert len(lines) == 1 and "rasterio" in lines[0], output
    assert not (root / "data" / "built" / "targets" / "city").exists()
