"""The habitat-lab export of a toy dataset over the tiny room scene: schemas, frames, scene files."""

from __future__ import annotations

import gzip
import json
import math
import struct
from pathlib import Path

import numpy as np
import pytest

from navverse import nav
from navverse.dataset import Dataset, Episode, EpisodeInfo, Goal, Instruction, goal_distance
from navverse.export import HabitatExportError, export_habitat
from navverse.export.habitat import build_vocabulary, habitat_rotation, to_habitat, tokenize
from navverse.export.habitat_navmesh import POLYFLAGS_WALK, tiles_from_mset
from navverse.export.habitat_scenes import (
    SEMANTIC_HEADER,
    STOREFRONT_ID_BASE,
    from_habitat,
    habitat_yaw,
    id_colors,
    scene_triangles,
)
from navverse.nav.fileformat import read_navmesh, write_navmesh
from navverse.nav.pathfinder import PathFinder
from navverse.nav.scene_navmesh import build_scene_navmesh
from navverse.scene.directory import SceneFiles, read_scene, write_scene_dir
from tests.navverse.eval.toy_dataset import write_toy_dataset
from tests.navverse.scene.conftest import build_scene

SCENE = "tiny_room"
START = (8.0, 2.0, 0.0)
CHAIRS = [Goal(object_id=i, category="chair", position=p, radius=0.25, size=(0.5, 0.5, 0.9))
          for i, p in ((1, (3.0, 5.0, 0.45)), (2, (4.0, 6.0, 0.45)))]  # fmt: skip
CAFE = Goal(object_id=1, category="cafe", position=(5.0, -1.0, 0.0), radius=1.5, size=(3.0, 0.2, 2.5))
TABLE = Goal(object_id=3, category="table", position=(7.0, 5.0, 0.375), radius=0.6, size=(1.2, 0.8, 0.75))
TEXT = "Turn left, walk past the chair's back and stop at the table."


def _rotation(yaw: float) -> tuple[float, float, float, float]:
    return (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))


def _info(goal: Goal) -> EpisodeInfo:
    return EpisodeInfo(
        geodesic_distance=5.0, euclidean_distance=4.0, closest_goal_object_id=goal.object_id,
        success_distance=1.6, difficulty="easy",
    )  # fmt: skip


def _episodes() -> list[Episode]:
    common = {"scene_id": SCENE, "scene_type": "i2o", "start_position": START}
    return [
        Episode(episode_id=f"{SCENE}-objnav-0000", task="objnav", start_rotation=_rotation(0.5),
                object_category="chair", goals=CHAIRS, reference_path=[START, (3.5, 4.5, 0.0)],
                info=_info(CHAIRS[0]), **common),
        Episode(episode_id=f"{SCENE}-placenav-0000", task="placenav", start_rotation=_rotation(-1.0),
                place_category="cafe", goals=[CAFE], reference_path=[START, (5.0, -1.5, 0.0)],
                info=_info(CAFE), **common),
        Episode(episode_id=f"{SCENE}-vln-0000", task="vln", start_rotation=_rotation(2.0),
                object_category="table", goals=[TABLE], reference_path=[START, (7.0, 3.8, 0.0)],
                instruction=Instruction(instruction_text=TEXT, template_text=TEXT,
                                        instruction_type="landmark"),
                info=_info(TABLE), **common),
    ]  # fmt: skip


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    root = tmp_path_factory.mktemp("habitat")
    scene = build_scene()
    scene_dir = root / "scenes" / SCENE
    scene_dir.mkdir(parents=True)
    write_scene_dir(scene, scene_dir, bev=False)
    build_scene_navmesh(scene, nav.INDOOR, jobs=1).save(SceneFiles(scene_dir).navmesh)
    dataset = root / "dataset"
    dataset.mkdir()
    write_toy_dataset(dataset, _episodes())
    out = root / "export"
    lines: list[str] = []
    result = export_habitat(dataset, out, scenes=lambda s: root / "scenes" / s, progress=lines.append)
    assert result.objectnav == {"eval": 2} and result.vln == {"eval": 1} and lines
    return {"root": root, "dataset": dataset, "out": out, "scene_dir": scene_dir}


def _json(path: Path):
    with gzip.open(path, "rt") as handle:
        return json.load(handle)


def _rotate(q, v) -> np.ndarray:
    """Rotate ``v`` by the ``[x, y, z, w]`` quaternion ``q``."""
    u, w = np.asarray(q[:3], float), float(q[3])
    t = 2.0 * np.cross(u, v)
    return np.asarray(v, float) + w * t + np.cross(u, t)


def test_frame_maps_points_and_the_agent_forward():
    np.testing.assert_allclose(to_habitat([1.0, 2.0, 3.0]), [1.0, 3.0, -2.0])
    for yaw in (0.0, 0.5, math.pi / 2, 2.0, -2.7):
        forward = _rotate(habitat_rotation(yaw), [0.0, 0.0, -1.0])  # habitat agents look along -z
        np.testing.assert_allclose(forward, to_habitat([math.cos(yaw), math.sin(yaw), 0.0]), atol=1e-12)
        np.testing.assert_allclose(
            _rotate(habitat_rotation(yaw), [0.0, 1.0, 0.0]), [0.0, 1.0, 0.0], atol=1e-12
        )


def test_objectnav_files_follow_habitat_schema(built):
    split = _json(built["out"] / "objectnav_v1" / "eval" / "eval.json.gz")
    assert split["episodes"] == []
    assert split["category_to_task_category_id"] == {"cafe": 0, "chair": 1}
    assert set(split["category_to_scene_annotation_category_id"]) == {"cafe", "chair"}
    content = _json(built["out"] / "objectnav_v1" / "eval" / "content" / f"{SCENE}.json.gz")
    assert content["category_to_task_category_id"] == split["category_to_task_category_id"]
    assert set(content["goals_by_category"]) == {f"{SCENE}.glb_chair", f"{SCENE}.glb_cafe"}
    objnav, placenav = content["episodes"]
    assert set(objnav) == {"episode_id", "scene_id", "start_position", "start_rotation", "info", "goals",
                           "object_category"}  # fmt: skip
    assert objnav["scene_id"] == f"{SCENE}/{SCENE}.glb" and objnav["goals"] == []
    assert (objnav["object_category"], placenav["object_category"]) == ("chair", "cafe")
    assert objnav["start_position"] == [8.0, 0.0, -2.0]
    np.testing.assert_allclose(objnav["start_rotation"], habitat_rotation(0.5), atol=1e-4)
    assert objnav["info"]["geodesic_distance"] == 5.0 and objnav["info"]["navverse_episode_id"].endswith(
        "0000"
    )
    chairs = content["goals_by_category"][f"{SCENE}.glb_chair"]
    assert [g["object_id"] for g in chairs] == [1, 2]
    for goal in chairs:
        assert set(goal) == {
            "position",
            "radius",
            "object_id",
            "object_name",
            "object_category",
            "view_points",
        }
        assert goal["object_category"] == "chair" and isinstance(goal["radius"], float)
    np.testing.assert_allclose(chairs[0]["position"], [3.0, 0.45, -5.0])
    (cafe,) = content["goals_by_category"][f"{SCENE}.glb_cafe"]
    assert cafe["object_id"] == STOREFRONT_ID_BASE + 1  # the tiny room's storefront has no object of its own
    assert placenav["info"]["closest_goal_object_id"] == STOREFRONT_ID_BASE + 1


def test_view_points_are_navigable_within_success_and_face_the_goal(built):
    content = _json(built["out"] / "objectnav_v1" / "eval" / "content" / f"{SCENE}.json.gz")
    finder = PathFinder.load(SceneFiles(built["scene_dir"]).navmesh)
    goals = {g.object_id: g for g in CHAIRS}
    for goal in content["goals_by_category"][f"{SCENE}.glb_chair"]:
        views = goal["view_points"]
        assert 4 <= len(views) <= 16
        points = from_habitat([v["agent_state"]["position"] for v in views])
        assert finder.is_navigable(points).all()
        source = goals[goal["object_id"]]
        assert all(goal_distance(p + np.array([0.0, 0.0, 0.55]), source) <= 1.6 for p in points)
        for view, point in zip(views, points, strict=True):
            forward = from_habitat(_rotate(view["agent_state"]["rotation"], [0.0, 0.0, -1.0]))
            towards = np.subtract(source.position[:2], point[:2])
            assert forward[:2] @ (towards / np.linalg.norm(towards)) > 0.999


def test_vln_file_and_vocabulary_round_trip(built):
    data = _json(built["out"] / "vln_r2r" / "eval" / "eval.json.gz")
    vocab = data["instruction_vocab"]
    assert vocab["word_list"][:2] == ["<pad>", "<unk>"] and (vocab["PAD_INDEX"], vocab["UNK_INDEX"]) == (0, 1)
    assert vocab["stoi"] == vocab["word2idx_dict"] and vocab["itos"] == vocab["word_list"]
    assert vocab["num_vocab"] == len(vocab["word_list"])
    (episode,) = data["episodes"]
    assert set(episode) == {"episode_id", "trajectory_id", "scene_id", "start_position", "start_rotation",
                            "instruction", "reference_path", "goals", "info"}  # fmt: skip
    assert isinstance(episode["trajectory_id"], int)
    tokens = episode["instruction"]["instruction_tokens"]
    words = ["turn", "left", "walk", "past", "the", "chair's", "back", "and", "stop", "at", "the", "table"]
    assert [vocab["itos"][t] for t in tokens] == tokenize(TEXT) == words
    assert episode["reference_path"] == [[8.0, 0.0, -2.0], [7.0, 0.0, -3.8]]
    assert episode["goals"] == [{"position": [7.0, 0.0, -3.8], "radius": 1.6}]
    assert build_vocabulary(["B a", "a"])["word_list"] == ["<pad>", "<unk>", "a", "b"]


def test_scene_glbs_load_back_with_their_triangles(built):
    import trimesh

    scene_out = built["out"] / "scenes" / SCENE
    corners, _, ids = scene_triangles(read_scene(built["scene_dir"]))
    mesh = trimesh.load(scene_out / f"{SCENE}.glb", force="mesh", process=False)
    assert len(mesh.vertices) == 3 * len(corners) and len(mesh.faces) == len(corners)
    np.testing.assert_allclose(mesh.vertices, to_habitat(corners.reshape(-1, 3)), atol=1e-5)
    semantic = trimesh.load(scene_out / f"{SCENE}.semantic.glb", force="mesh", process=False)
    colors = np.asarray(semantic.visual.vertex_colors)[::3, :3]
    np.testing.assert_array_equal(colors, id_colors(ids))
    assert (colors[ids == 3] == [0, 0, 3]).all() and (colors[ids == 0] == 0).all()
    lines = (scene_out / f"{SCENE}.semantic.txt").read_text().splitlines()
    assert lines[0] == SEMANTIC_HEADER and '3,000003,"table",0' in lines
    assert f'{STOREFRONT_ID_BASE + 1},800001,"cafe",0' in lines


def test_navmesh_file_reads_back_as_the_same_detour_navmesh(built):
    original_bytes = SceneFiles(built["scene_dir"]).navmesh.read_bytes()
    meta, _ = read_navmesh(original_bytes)
    params, tiles = tiles_from_mset((built["out"] / "scenes" / SCENE / f"{SCENE}.navmesh").read_bytes())
    for _, tile in tiles:
        poly_count, vert_count = struct.unpack_from("<ii", tile, 24)
        start = 100 + 12 * vert_count
        flags = np.frombuffer(tile, np.uint8, 32 * poly_count, start).reshape(-1, 32)[:, 28:30].copy()
        assert (flags.view("<u2") == POLYFLAGS_WALK).all()
    payload = struct.pack("<4sIii3fffii", b"NVDT", 1, 7, 4, *params) + struct.pack("<i", len(tiles))
    payload += b"".join(struct.pack("<Qi", ref, len(tile)) + tile for ref, tile in tiles)
    copy = PathFinder.from_bytes(write_navmesh(payload, settings=meta["settings"]))
    original = PathFinder.from_bytes(original_bytes)
    a, b = [8.0, 2.0, 0.0], [2.0, 6.5, 0.0]
    assert copy.geodesic_distance(a, b) == pytest.approx(original.geodesic_distance(a, b))
    assert copy.navigable_area == pytest.approx(original.navigable_area)


def test_missing_scene_names_it_and_writes_nothing(built, tmp_path):
    out = tmp_path / "nested" / "export"
    nowhere = tmp_path / "no-scenes"
    with pytest.raises(HabitatExportError, match=rf"{SCENE}.*{nowhere}"):
        export_habitat(built["dataset"], out, scenes=lambda s: nowhere / s)
    assert not out.exists() and not out.parent.exists()
    with pytest.raises(HabitatExportError, match="not empty"):
        export_habitat(built["dataset"], built["out"], scenes=lambda s: nowhere / s)


def test_positions_and_headings_round_trip_from_the_export(built):
    """Everything exported maps back to the NavVerse episode it came from: positions within 1e-6 m,
    start headings within 1e-5 rad."""
    episodes = {e.episode_id: e for e in Dataset(built["dataset"]).episodes()}
    content = _json(built["out"] / "objectnav_v1" / "eval" / "content" / f"{SCENE}.json.gz")
    vln = _json(built["out"] / "vln_r2r" / "eval" / "eval.json.gz")["episodes"]
    exported = content["episodes"] + vln
    assert len(exported) == len(episodes)
    for habitat in exported:
        episode = episodes[habitat["info"]["navverse_episode_id"]]
        np.testing.assert_allclose(from_habitat(habitat["start_position"]), episode.start_position, atol=1e-6)
        turn = habitat_yaw(habitat["start_rotation"]) - episode.start_yaw
        assert abs(math.remainder(float(turn), math.tau)) < 1e-5
        if "reference_path" in habitat:
            np.testing.assert_allclose(
                from_habitat(habitat["reference_path"]), episode.reference_path, atol=1e-6
            )
    goals = [g for key in content["goals_by_category"] for g in content["goals_by_category"][key]]
    for goal in goals:  # a place's object id is its storefront's semantic id: matched by category
        sources = [
            g.position for e in episodes.values() for g in e.goals if g.category == goal["object_category"]
        ]
        gaps = np.abs(np.asarray(sources) - from_habitat(goal["position"])).max(axis=1)
        assert gaps.min() < 1e-6, goal
    for yaw in np.linspace(-3.1, 3.1, 13):  # the heading's inverse, all round
        assert abs(math.remainder(float(habitat_yaw(habitat_rotation(yaw))) - yaw, math.tau)) < 1e-12
