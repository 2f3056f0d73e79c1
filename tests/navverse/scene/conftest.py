"""A tiny hand-built scene: a room (floor, two walls, ceiling), a road, three objects, a storefront."""

from __future__ import annotations

import math

import numpy as np
import pytest

from navverse.scene.annotations import (
    BuildingAnnotation,
    ExitAnnotation,
    SceneSource,
    StorefrontAnnotation,
    footprint_facades,
)
from navverse.scene.compose import ObjectPart, assemble_scene
from navverse.scene.geometry import MeshData, Scene, Surface
from navverse.scene.terrain import terrain_classes
from tests.scenes import quad

ROAD_FRICTION = 0.7
FLOOR_POINT = (8.0, 2.0)  # on the floor, away from walls and objects
WALL_POINT = (5.0, 0.15)  # middle of the south wall's top
ROAD_POINT = (5.0, -2.5)


OBJECTS = (
    # (id, category, center, size, yaw)
    (1, "chair", (3.0, 5.0, 0.45), (0.5, 0.5, 0.9), 0.3),
    (2, "chair", (4.0, 6.0, 0.45), (0.5, 0.5, 0.9), -1.2),
    (3, "table", (7.0, 5.0, 0.375), (1.2, 0.8, 0.75), 2.5),
)


def build_scene() -> Scene:
    objects = []
    for _, category, center, size, yaw in OBJECTS:
        mesh = MeshData.box(size)
        if category == "table":
            colors = np.tile(np.array([[140, 90, 40]], dtype=np.uint8), (mesh.num_faces, 1))
            colors[::2] = (10, 200, 30)
            mesh = MeshData(mesh.vertices, mesh.faces, colors)
        objects.append(ObjectPart(category, mesh, center, yaw))
    road = quad(-2.0, -4.0, 12.0, -1.0, -0.1)
    road = MeshData(road.vertices, road.faces, np.array([[50, 50, 60], [70, 60, 50]], dtype=np.uint8))
    surfaces = (
        Surface("floor", "floor", quad(0.0, 0.0, 10.0, 8.0, 0.0)),
        Surface("wall_south", "wall", MeshData.box((10.0, 0.3, 2.5), center=(5.0, 0.15, 1.25))),
        Surface("wall_west", "wall", MeshData.box((0.3, 8.0, 2.5), center=(0.15, 4.0, 1.25))),
        Surface("ceiling", "ceiling", quad(0.0, 0.0, 10.0, 8.0, 2.5)),
        Surface("road_0", "road", road),
    )
    footprint = [(0.0, 0.0), (10.0, 0.0), (10.0, 8.0), (0.0, 8.0)]
    room = BuildingAnnotation(
        id=1,
        footprint=footprint,
        height=2.5,
        indoor=True,
        exits=[ExitAnnotation(id=1, center=(5.0, 0.0, 0.0), width=1.2, facing=-math.pi / 2, facade=1)],
        facades=footprint_facades(footprint, height=2.5),
    )
    return assemble_scene(
        scene_id="tiny_room",
        scene_type="i2o",
        surfaces=surfaces,
        objects=objects,
        buildings=[room],
        storefronts=[
            StorefrontAnnotation(
                id=1,
                place_category="cafe",
                center=(5.0, -0.6, 1.5),
                facing=-math.pi / 2,
                size=(3.0, 0.2, 2.5),
                entrance=(5.0, -1.0, 0.0),
                building=1,
                facade=1,
            )
        ],
        indoor_anchor=(5.0, 4.0, 0.0),
        terrain_classes=terrain_classes(
            ["floor", "wall", "ceiling", "road"], overrides={"road": ROAD_FRICTION}
        ),
        source=SceneSource(
            recipe="recipes/scenes/i2o/tiny.yaml", recipe_hash="abc123", toolkit_version="0.1.0"
        ),
    )


@pytest.fixture(scope="session")
def tiny_scene() -> Scene:
    return build_scene()
