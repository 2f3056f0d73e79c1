"""Two furnished procedural buildings written as scene directories with their navmeshes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from navverse import nav
from navverse.indoor import generate_building
from navverse.nav.scene_navmesh import build_scene_navmesh
from navverse.scene.directory import SceneFiles, write_scene_dir
from navverse.scene.geometry import Scene


def write_building(root: Path, building_type: str, seed: int) -> Path:
    """A procedural building of a type and seed, as a scene directory with its navmesh."""
    scene_id = f"{building_type}-s{seed}"
    scene = generate_building(building_type, np.random.default_rng(seed), scene_id=scene_id)
    out = root / scene_id
    out.mkdir(parents=True)
    write_scene_dir(scene, out, bev=False)
    build_scene_navmesh(scene, nav.INDOOR, jobs=1).save(SceneFiles(out).navmesh)
    return out


@pytest.fixture(scope="session")
def scene_dirs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    root = tmp_path_factory.mktemp("buildings")
    return {d.name: d for d in (write_building(root, "apartment", 0), write_building(root, "cafe", 1))}


@pytest.fixture(scope="session")
def apartment(scene_dirs: dict[str, Path]) -> Scene:
    from navverse.scene.directory import read_scene

    return read_scene(scene_dirs["apartment-s0"])


VLN_CATEGORIES = ["bed", "sofa", "toilet", "fridge", "oven", "bathtub", "bench", "desk", "wardrobe"]


@pytest.fixture(scope="session")
def verified_vln(apartment: Scene, scene_dirs: dict[str, Path]):
    """VLN candidates of apartment-s0 and their Spot verification rollouts: ``(episodes, results)``."""
    from navverse.episodes.sampling import object_goals, sample_scene_episodes
    from navverse.episodes.verification import verify_episodes
    from navverse.nav.scene_navmesh import load_scene_navmesh

    finder = load_scene_navmesh(scene_dirs["apartment-s0"])
    goals = object_goals(apartment.annotations, categories=VLN_CATEGORIES)
    sample = sample_scene_episodes(
        finder, apartment.annotations, goals, task="vln", count=14, rng=np.random.default_rng(11),
        robot_radius=0.6, base_height=0.55,
    )  # fmt: skip
    results = verify_episodes(sample.episodes, scene_dirs, embodiment="spot", jobs=1)
    return sample.episodes, results
