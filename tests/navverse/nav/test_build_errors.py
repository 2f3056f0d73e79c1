"""Bad build input raises NavMeshError with a message that says what is wrong."""

from __future__ import annotations

import numpy as np
import pytest

from navverse import nav
from navverse.errors import NavverseError
from navverse.nav import NavMeshError
from tests.navverse.nav import scenes


def test_navmesh_error_is_a_navverse_error():
    assert issubclass(NavMeshError, NavverseError)


def test_only_walls_have_no_walkable_surface():
    builder = scenes.MeshBuilder()
    vertices, faces, _ = builder.box((0, 0, 0), (5, 0.2, 2.5)).arrays()
    side_faces = faces[4:]  # drop the top and bottom: vertical faces only
    with pytest.raises(
        NavMeshError, match="no walkable surface: none of the 8 walkable-type triangles faces up"
    ):
        nav.build(vertices, side_faces, nav.INDOOR)


def test_upside_down_floor_has_no_walkable_surface():
    vertices = np.array([[0, 0, 0], [5, 0, 0], [5, 5, 0], [0, 5, 0]], dtype=float)
    faces = np.array([[0, 2, 1], [0, 3, 2]])  # clockwise seen from above: facing down
    with pytest.raises(NavMeshError, match="counter-clockwise"):
        nav.build(vertices, faces, nav.INDOOR)
    nav.build(vertices, faces[:, ::-1], nav.INDOOR)  # the same floor facing up is fine


def test_never_walkable_area_types():
    vertices, faces, areas = scenes.corridor().arrays()
    with pytest.raises(NavMeshError, match="area type 0"):
        nav.build(vertices, faces, nav.INDOOR, area_types=np.zeros_like(areas))


def test_floor_smaller_than_the_agent():
    vertices, faces, _ = scenes.MeshBuilder().floor(0, 0, 1.0, 1.0).arrays()
    with pytest.raises(NavMeshError, match="no navmesh polygon remained"):
        nav.build(vertices, faces, nav.INDOOR)


@pytest.mark.parametrize(
    ("change", "match"),
    [
        (lambda v, f, a: (v[:, :2], f, a), r"vertices must have shape \(N, 3\)"),
        (lambda v, f, a: (np.where(np.arange(len(v))[:, None] == 3, np.nan, v), f, a), "NaN"),
        (lambda v, f, a: (v, f[:, :2], a), r"faces must have shape \(M, 3\)"),
        (lambda v, f, a: (v, f + 1000, a), "faces index vertices"),
        (lambda v, f, a: (v, -f, a), "faces index vertices"),
        (lambda v, f, a: (v, f.astype(float), a), "integer"),
        (lambda v, f, a: (v, f[:0], a[:0]), "no faces"),
        (lambda v, f, a: (v, f, a[:-1]), "one per face"),
        (lambda v, f, a: (v, f, np.full_like(a, 63)), r"0\.\.62"),
        (lambda v, f, a: (v, f, a.astype(float)), "integers"),
        (lambda v, f, a: ("vertices", f, a), "numbers"),
    ],
)
def test_malformed_arrays(change, match: str):
    vertices, faces, areas = change(*scenes.corridor().arrays())
    with pytest.raises(NavMeshError, match=match):
        nav.build(vertices, faces, nav.INDOOR, area_types=areas)


def test_bad_jobs_and_settings():
    vertices, faces, _ = scenes.corridor().arrays()
    with pytest.raises(NavMeshError, match="jobs"):
        nav.build(vertices, faces, nav.INDOOR, jobs=0)
    with pytest.raises(TypeError):
        nav.build(vertices, faces, {"cell_size": 0.05})  # type: ignore[arg-type]
    # model_copy skips validation; build checks again.
    unchecked = nav.OUTDOOR.model_copy(update={"tile_size": 128.5, "cell_size": -1.0})
    with pytest.raises(NavMeshError, match=r"invalid navmesh settings: .*cell_size"):
        nav.build(vertices, faces, unchecked)


def test_too_many_tiles_for_polygon_references():
    vertices, faces, _ = scenes.MeshBuilder().floor(0, 0, 2000, 2000).arrays()
    settings = nav.OUTDOOR.model_copy(update={"tile_size": 16})  # 1250 x 1250 tiles
    with pytest.raises(NavMeshError, match="increase tile_size"):
        nav.build(vertices, faces, settings)
