"""Navmeshes of the test scenes, built once per session."""

from __future__ import annotations

import pytest

from navverse import nav
from navverse.nav import NavMeshSettings, PathFinder
from tests.navverse.nav import scenes


def build_scene(
    builder: scenes.MeshBuilder, base: NavMeshSettings = nav.INDOOR, **overrides: object
) -> PathFinder:
    """Build a navmesh of a test scene with its per-triangle area types."""
    vertices, faces, areas = builder.arrays()
    settings = base.model_copy(update=overrides) if overrides else base
    return nav.build(vertices, faces, settings, area_types=areas)


@pytest.fixture(scope="session")
def corridor_nav() -> PathFinder:
    return build_scene(scenes.corridor())


@pytest.fixture(scope="session")
def l_nav() -> PathFinder:
    return build_scene(scenes.l_corridor())


@pytest.fixture(scope="session")
def box_nav() -> PathFinder:
    return build_scene(scenes.box_room())


@pytest.fixture(scope="session")
def rooms_nav() -> PathFinder:
    return build_scene(scenes.two_rooms())
