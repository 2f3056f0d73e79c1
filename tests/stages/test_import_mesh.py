"""The import_mesh stage on small synthetic OBJ, GLB, PLY and USDA files: rules, frames, colours, errors."""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
import pybullet_data
import pytest
import trimesh
import yaml
from PIL import Image

from navverse.scene.directory import read_annotations, read_scene
from navverse.scene.geometry import Scene
from navverse.scene.mesh_parts import split_components, subdivide
from pipeline.errors import RecipeError
from pipeline.recipes import RecipeLoader
from pipeline.stage import discover
from tests.stages.conftest import REPO, Built, build_all, workspace_with

RED, BLUE, GREEN = (255, 0, 0), (0, 0, 255), (0, 160, 0)


# ------------------------------------------------------------------------------------ fixture files


def _box(lo, hi) -> trimesh.Trimesh:
    return trimesh.creation.box(bounds=np.array([lo, hi], dtype=float))


def _obj_block(mesh: trimesh.Trimesh, group: str, material: str, offset: int) -> tuple[str, int]:
    lines = [f"g {group}", f"usemtl {material}"]
    lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in mesh.vertices]
    lines += [f"f {a + offset + 1} {b + offset + 1} {c + offset + 1}" for a, b, c in mesh.faces]
    return "\n".join(lines), offset + len(mesh.vertices)


def write_obj(folder: Path) -> None:
    """A y-up OBJ in centimeters: groups floor_main (red), lanterns (three lanterns of two stacked
    boxes each, blue), chair_big (a known box, green), chair_on_floor and clutter (red)."""
    (folder / "hall.mtl").write_text(
        "newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\nnewmtl green\nKd 0 0.627 0\n"
    )
    blocks, offset = [], 0
    parts = [
        ("floor_main", "red", [_box((0, -10, -1000), (1000, 0, 0))]),
        (
            "lanterns",
            "blue",
            [
                box
                for x in (600, 700, 800)
                for box in (
                    _box((x, 0, -120), (x + 40, 40, -80)),
                    _box((x + 5, 40, -115), (x + 35, 100, -85)),
                )
            ],
        ),
        ("chair_big", "green", [_box((100, 0, -400), (300, 50, -200))]),
        ("chair_on_floor", "red", [_box((400, 0, -600), (450, 90, -550))]),
        ("clutter", "red", [_box((900, 0, -900), (950, 20, -850))]),
    ]
    for group, material, boxes in parts:
        block, offset = _obj_block(trimesh.util.concatenate(boxes), group, material, offset)
        blocks.append(block)
    (folder / "hall.obj").write_text("mtllib hall.mtl\n" + "\n".join(blocks) + "\n")


def write_glb(folder: Path) -> None:
    """A glTF scene (y-up, meters): ground; /furniture (moved by -1 along z) holding a green table and
    a lamp without colours."""
    scene = trimesh.Scene()
    ground = _box((-5, -0.1, -5), (5, 0, 5))
    scene.add_geometry(ground, node_name="ground", geom_name="ground_mesh")
    scene.graph.update(
        frame_from="world",
        frame_to="furniture",
        matrix=trimesh.transformations.translation_matrix([0, 0, -1]),
    )
    table = _box((-0.5, 0, -0.25), (0.5, 0.8, 0.25))
    table.visual.vertex_colors = np.tile([*GREEN, 255], (len(table.vertices), 1))
    scene.add_geometry(
        table,
        node_name="table",
        geom_name="table_mesh",
        parent_node_name="furniture",
        transform=trimesh.transformations.translation_matrix([1, 0, -2]),
    )
    scene.add_geometry(
        _box((-0.1, 0, -0.1), (0.1, 1.5, 0.1)),
        node_name="lamp",
        geom_name="lamp_mesh",
        parent_node_name="furniture",
    )
    scene.export(folder / "room.glb")


def write_ply(folder: Path) -> None:
    """A z-up PLY in millimeters: a 1 m x 2 m x 0.1 m slab with blue vertex colours."""
    slab = _box((0, 0, -100), (1000, 2000, 0))
    slab.visual.vertex_colors = np.tile([*BLUE, 255], (len(slab.vertices), 1))
    slab.export(folder / "slab.ply")


def write_textured_obj(folder: Path) -> None:
    """A triangle with a texture of one red and one blue pixel (white Kd)."""
    Image.fromarray(np.array([[RED, BLUE]], dtype=np.uint8)).save(folder / "tiles.png")
    (folder / "tiles.mtl").write_text("newmtl tiles\nKd 1 1 1\nmap_Kd tiles.png\n")
    (folder / "tiles.obj").write_text(
        "mtllib tiles.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nusemtl tiles\nf 1/1 2/2 3/3\n"
    )


USDA = """#usda 1.0
(
    upAxis = "Y"
    metersPerUnit = 0.01
)

def Xform "Root"
{
    def Mesh "Floor"
    {
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(-500, 0, -500), (-500, 0, 500), (500, 0, 500), (500, 0, -500)]
        color3f[] primvars:displayColor = [(1, 0, 0)] (interpolation = "constant")
    }

    def Xform "Shelf"
    {
        double3 xformOp:translate = (100, 0, -200)
        uniform token[] xformOpOrder = ["xformOp:translate"]

        def Mesh "shelf_mesh"
        {
            int[] faceVertexCounts = [4, 4, 4, 4, 4, 4]
            int[] faceVertexIndices = [0, 1, 2, 3, 4, 7, 6, 5, 0, 4, 5, 1, 2, 6, 7, 3, 1, 5, 6, 2, 0, 3, 7, 4]
            point3f[] points = [(-25, 0, -25), (25, 0, -25), (25, 0, 25), (-25, 0, 25),
                                (-25, 50, -25), (25, 50, -25), (25, 50, 25), (-25, 50, 25)]
            color3f[] primvars:displayColor = [(0, 0, 1)] (interpolation = "constant")
        }
    }
}
"""


@pytest.fixture(scope="module")
def files(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The mesh files, in ``data/raw/meshes`` of the project :func:`built` builds them in."""
    folder = tmp_path_factory.mktemp("import-mesh") / "data" / "raw" / "meshes"
    folder.mkdir(parents=True)
    write_obj(folder)
    write_glb(folder)
    write_ply(folder)
    (folder / "store.usda").write_text(USDA)
    write_textured_obj(folder)
    (folder / "broken.glb").write_bytes(b"glTF this is not a binary glTF file at all")
    (folder / "empty.obj").write_text("# nothing here\nv 0 0 0\n")
    (folder / "broken.usda").write_text("#usda 1.0\ndef Mesh {{{ nonsense\n")
    return folder


def _recipe(source: str, body: str = "") -> str:
    return f"stages:\n  import_mesh:\n    source: {source}\n" + textwrap.indent(textwrap.dedent(body), "    ")


RECIPES = {
    "hall": _recipe(
        "{folder}/hall.obj",
        """\
        units: centimeters
        up_axis: y
        rules:
          - {pattern: "^lanterns", object: stone_lantern, split: components}
          - {pattern: "chair", object: chair}
          - {pattern: "floor", surface: floor}
        default: drop
        friction: {floor: 0.5}
        """,
    ),
    "hall-nodes": _recipe(
        "{folder}/hall.obj",
        """\
        units: 0.01
        up_axis: y
        rules:
          - {pattern: "^lanterns", object: stone_lantern}
          - {pattern: "^clutter", drop: true}
        """,
    ),
    "room": _recipe(
        "{folder}/room.glb",
        """\
        rules:
          - {pattern: "^/furniture/", on: path, object: furniture}
          - {pattern: "ground", surface: ground}
        """,
    ),
    "slab": _recipe("{folder}/slab.ply", "units: millimeters\nup_axis: z\ndefault: floor\nsubdivide: 1\n"),
    "store": _recipe(
        "{folder}/store.usda",
        """\
        rules:
          - {pattern: "^/Root/Shelf", on: path, object: shelf}
          - {pattern: "^Floor$", surface: floor}
        """,
    ),
    "store-raw": _recipe(
        "{folder}/store.usda",
        "units: meters\nup_axis: z\nrules: [{pattern: Shelf, on: path, object: shelf}]\ndefault: floor\n",
    ),
    "tiles": _recipe("{folder}/tiles.obj", "up_axis: z\ndefault: floor\n"),
    "cube": _recipe("{package_data: pybullet_data, file: cube.obj}", "up_axis: z\ndefault: floor\n"),
    "broken": _recipe("{folder}/broken.glb"),
    "empty": _recipe("{folder}/empty.obj", "up_axis: z\n"),
    "broken-usd": _recipe("{folder}/broken.usda"),
    "all-dropped": _recipe("{folder}/slab.ply", "up_axis: z\ndefault: drop\n"),
}


@pytest.fixture(scope="module")
def built(files: Path) -> Built:
    root = files.parents[2]
    extra = {f"scenes/{name}.yaml": text.replace("{folder}", str(files)) for name, text in RECIPES.items()}
    return build_all(workspace_with(root, [], extra))


def scene_of(built: Built, target: str) -> Scene:
    return read_scene(built.output(target, "raw_geometry"))


def bounds(mesh) -> np.ndarray:
    return np.array(mesh.bounds())


# ------------------------------------------------------------------------------------------ rules


def test_rules_make_objects_and_surfaces(built: Built):
    scene = scene_of(built, "hall")
    assert [s.name for s in scene.surfaces] == ["floor_main_red"]
    assert scene.surfaces[0].terrain_class == "floor"
    categories = [o.annotation.category for o in scene.objects]
    # Nodes go by path. split: components -> one lantern per instance (its two stacked boxes joined);
    # first match wins: 'chair_on_floor' is a chair, not floor; 'clutter' matches nothing: dropped.
    assert categories == ["chair", "chair"] + ["stone_lantern"] * 3
    annotations = read_annotations(built.output("hall", "raw_geometry"))
    assert annotations.statistics.objects_per_category == {"chair": 2, "stone_lantern": 3}
    assert list(annotations.terrain_classes) == ["floor"]
    assert annotations.terrain_classes["floor"].friction == 0.5
    assert [o.prim_path for o in annotations.objects] == [
        "/World/Objects/chair_0001",
        "/World/Objects/chair_0002",
        "/World/Objects/stone_lantern_0003",
        "/World/Objects/stone_lantern_0004",
        "/World/Objects/stone_lantern_0005",
    ]
    for lantern, x in zip(scene.objects[2:], (6.2, 7.2, 8.2), strict=True):
        assert lantern.annotation.size == pytest.approx((0.4, 0.4, 1.0))
        assert lantern.annotation.center == pytest.approx((x, 1.0, 0.5))
        assert lantern.annotation.yaw == 0.0
        lo, hi = bounds(lantern.mesh)
        np.testing.assert_allclose(lo + hi, 0.0, atol=1e-9)  # local frame centred on the box
    stats = built.manifest("hall", "raw_geometry")["stats"]
    assert stats["rule_matches"] == [1, 2, 1]
    assert (stats["nodes"], stats["dropped_nodes"], stats["objects"], stats["surfaces"]) == (5, 1, 5, 1)
    assert stats["faces"] == annotations.statistics.faces == 12 * (1 + 6 + 2)


def test_without_split_one_object_per_node_drop_rules_and_the_obstacle_default(built: Built):
    scene = scene_of(built, "hall-nodes")
    assert [o.annotation.category for o in scene.objects] == ["stone_lantern"]
    assert scene.objects[0].annotation.size == pytest.approx((2.4, 0.4, 1.0))
    assert {s.terrain_class for s in scene.surfaces} == {"obstacle"}
    assert [s.name for s in scene.surfaces] == ["chair_big_green", "chair_on_floor_red", "floor_main_red"]
    assert built.manifest("hall-nodes", "raw_geometry")["stats"]["dropped_nodes"] == 1  # the clutter


def test_path_rules_and_node_transforms_in_a_gltf_scene(built: Built):
    scene = scene_of(built, "room")
    by_center = sorted(scene.objects, key=lambda o: o.annotation.size[2])
    table, lamp = by_center
    # glTF is y-up: file (x, y, z) -> (x, -z, y); the table sits at (1, 0, -2) under /furniture (z - 1).
    assert table.annotation.center == pytest.approx((1.0, 3.0, 0.4))
    assert table.annotation.size == pytest.approx((1.0, 0.5, 0.8))
    assert lamp.annotation.center == pytest.approx((0.0, 1.0, 0.75))
    assert {o.annotation.category for o in scene.objects} == {"furniture"}
    (ground,) = scene.surfaces
    assert ground.terrain_class == "ground"
    np.testing.assert_allclose(bounds(ground.mesh), [[-5, -5, -0.1], [5, 5, 0]], atol=1e-6)


def test_units_and_up_axis_put_a_known_box_where_expected(built: Built):
    chair = next(o for o in scene_of(built, "hall").objects if o.annotation.size[2] == pytest.approx(0.5))
    # cm, y-up: x 100..300, y 0..50, z -400..-200  ->  m, z-up: x 1..3, y 2..4, z 0..0.5
    assert chair.annotation.center == pytest.approx((2.0, 3.0, 0.25))
    assert chair.annotation.size == pytest.approx((2.0, 2.0, 0.5))
    (slab,) = scene_of(built, "slab").surfaces
    np.testing.assert_allclose(bounds(slab.mesh), [[0, 0, -0.1], [1, 2, 0]], atol=1e-6)


def test_winding_stays_outward_after_the_axis_change(built: Built):
    chair = next(o for o in scene_of(built, "hall").objects if o.annotation.category == "chair")
    mesh = trimesh.Trimesh(chair.mesh.vertices, chair.mesh.faces, process=False)
    assert mesh.is_volume and mesh.volume > 0  # outward normals: positive volume


def test_usd_stage_metadata_and_transforms(built: Built):
    scene = scene_of(built, "store")
    (shelf,) = scene.objects
    # upAxis Y, metersPerUnit 0.01; translate (100, 0, -200) cm; cube of 50 cm from y = 0.
    assert shelf.annotation.category == "shelf"
    assert shelf.annotation.center == pytest.approx((1.0, 2.0, 0.25))
    assert shelf.annotation.size == pytest.approx((0.5, 0.5, 0.5))
    (floor,) = scene.surfaces
    assert floor.mesh.num_faces == 2  # the quad, triangulated
    normal = np.cross(
        *(floor.mesh.vertices[floor.mesh.faces[0, 1:]] - floor.mesh.vertices[floor.mesh.faces[0, 0]])
    )
    assert normal[2] > 0  # faces up in z-up
    np.testing.assert_allclose(bounds(floor.mesh), [[-5, -5, 0], [5, 5, 0]], atol=1e-6)
    shelf_mesh = trimesh.Trimesh(shelf.mesh.vertices, shelf.mesh.faces, process=False)
    assert shelf_mesh.volume == pytest.approx(0.125, rel=1e-5)


def test_recipe_units_and_axis_override_the_usd_stage(built: Built):
    (shelf,) = scene_of(built, "store-raw").objects
    assert shelf.annotation.center == pytest.approx((100.0, 25.0, -200.0))
    assert shelf.annotation.size == pytest.approx((50.0, 50.0, 50.0))
    stats = built.manifest("store-raw", "raw_geometry")["stats"]
    assert (stats["up_axis"], stats["meters_per_unit"]) == ("z", 1.0)


# ---------------------------------------------------------------------------------------- colours


def _colors(mesh) -> set[tuple[int, ...]]:
    assert mesh.face_colors is not None
    return {tuple(int(c) for c in row) for row in np.unique(mesh.face_colors, axis=0)}


def _close(colors: set[tuple[int, ...]], expected: tuple[int, int, int]) -> bool:
    return len(colors) == 1 and np.abs(np.subtract(next(iter(colors)), expected)).max() <= 1


def test_colours_come_from_materials_vertex_colours_and_display_colours(built: Built):
    hall = scene_of(built, "hall")
    assert _close(_colors(hall.surfaces[0].mesh), RED)  # OBJ material Kd
    assert _close(_colors(hall.objects[-1].mesh), BLUE)
    chair = next(o for o in hall.objects if o.annotation.size[2] == pytest.approx(0.5))
    assert _close(_colors(chair.mesh), GREEN)
    room = scene_of(built, "room")
    table = max(room.objects, key=lambda o: o.annotation.size[0])
    assert _close(_colors(table.mesh), GREEN)  # glTF vertex colours
    assert _close(_colors(scene_of(built, "slab").surfaces[0].mesh), BLUE)  # PLY vertex colours
    assert _close(_colors(scene_of(built, "tiles").surfaces[0].mesh), (128, 0, 128))  # texture mean
    store = scene_of(built, "store")
    assert _close(_colors(store.surfaces[0].mesh), RED)  # USD displayColor
    assert _close(_colors(store.objects[0].mesh), BLUE)


def test_nodes_without_colours_get_a_stable_colour_of_their_name(built: Built):
    from navverse.scene.colors import default_color

    room = scene_of(built, "room")
    lamp = min(room.objects, key=lambda o: o.annotation.size[0])
    assert _close(_colors(lamp.mesh), default_color("lamp"))


# ----------------------------------------------------------------------------- subdivision, helpers


def test_subdivide_multiplies_faces_and_keeps_the_shape(built: Built):
    (slab,) = scene_of(built, "slab").surfaces
    assert slab.mesh.num_faces == 12 * 4
    mesh = trimesh.Trimesh(slab.mesh.vertices, slab.mesh.faces, process=False)
    assert mesh.volume == pytest.approx(0.2, rel=1e-6)
    assert mesh.is_watertight  # midpoints are shared between neighbouring triangles


def test_subdivided_faces_keep_the_colour_of_their_parent():
    from navverse.scene.geometry import MeshData

    box = MeshData.box((1.0, 1.0, 1.0))
    colors = np.zeros((12, 3), dtype=np.uint8)
    colors[:, 0] = np.arange(12)
    fine = subdivide(MeshData(box.vertices, box.faces, colors), 2)
    assert fine.num_faces == 12 * 16
    parent_normals = np.array(trimesh.Trimesh(box.vertices, box.faces, process=False).face_normals)
    child_normals = np.array(trimesh.Trimesh(fine.vertices, fine.faces, process=False).face_normals)
    np.testing.assert_allclose(child_normals, parent_normals[fine.face_colors[:, 0]], atol=1e-9)


def test_split_components_joins_pieces_within_the_gap():
    from navverse.scene.geometry import MeshData

    a = MeshData.box((1, 1, 1), center=(0, 0, 0))
    b = MeshData.box((1, 1, 1), center=(0, 0, 1.05))  # 5 cm above a
    c = MeshData.box((1, 1, 1), center=(5, 0, 0))
    mesh = MeshData.concatenate([a, b, c])
    assert [p.num_faces for p in split_components(mesh, join_gap=0.1)] == [24, 12]
    assert [p.num_faces for p in split_components(mesh, join_gap=0.0)] == [12, 12, 12]


# ------------------------------------------------------------------------------------ package data


def test_package_data_resolves_to_the_package_file(built: Built):
    params = built.manifest("cube", "raw_geometry")["params"]
    assert Path(params["source"]) == (Path(pybullet_data.getDataPath()) / "cube.obj").resolve()
    (surface,) = scene_of(built, "cube").surfaces
    assert surface.terrain_class == "floor" and surface.mesh.num_faces == 12


# ----------------------------------------------------------------------------------------- errors


def test_unreadable_files_fail_the_stage_with_a_clear_message(built: Built):
    failed = {node.split(":")[0]: result.error for node, result in built.report.failed.items()}
    assert sorted(failed) == ["all-dropped", "broken", "broken-usd", "empty"]
    assert failed["broken"].startswith("MeshImportError: cannot read") and "broken.glb" in failed["broken"]
    assert (
        failed["broken-usd"].startswith("MeshImportError: cannot read") and "as USD" in failed["broken-usd"]
    )
    assert "holds no triangle meshes" in failed["empty"]
    assert "every one of its 1 nodes is dropped" in failed["all-dropped"]
    assert not any("Traceback" in error for error in failed.values())


@pytest.mark.parametrize(
    ("source", "body", "message"),
    [
        ("nothere.obj", "up_axis: y", "file not found"),
        ("model.fbx", "", "unsupported mesh format '.fbx'"),
        ("{package_data: no_such_package_xyz, file: a.obj}", "", "unknown package 'no_such_package_xyz'"),
        ("{package_data: pybullet_data, file: nope.obj}", "", "package 'pybullet_data' has no data file"),
        ("{package_data: pybullet_data, path: cube.obj}", "", "exactly the keys 'package_data' and 'file'"),
        ("hall.obj", "", "do not say which axis is up"),
        ("hall.obj", "up_axis: x", "'y' or 'z'"),
        ("hall.obj", "up_axis: y\nunits: parsecs", "unknown unit 'parsecs'"),
        ("hall.obj", "up_axis: y\nrules: [{pattern: '([', surface: floor}]", "invalid regular expression"),
        ("hall.obj", "up_axis: y\nrules: [{pattern: a, surface: lava}]", "unknown terrain class 'lava'"),
        ("hall.obj", "up_axis: y\ndefault: lava", "unknown terrain class 'lava'"),
        ("hall.obj", "up_axis: y\nrules: [{pattern: a, object: Chair}]", "must be lower_snake_case"),
        ("hall.obj", "up_axis: y\nrules: [{pattern: a, object: chair, surface: floor}]", "exactly one of"),
        (
            "hall.obj",
            "up_axis: y\nrules: [{pattern: a, surface: floor, colour: red}]",
            "unknown key 'colour'",
        ),
        ("hall.obj", "up_axis: y\nfriction: {road: 0.3}", "no rule (nor 'default') uses: road"),
        ("hall.obj", "up_axis: y\nsubdivide: 9", "less than or equal to 3"),
    ],
)
def test_recipe_mistakes_are_reported_with_their_line(
    files: Path, tmp_path: Path, source: str, body: str, message: str
):
    (tmp_path / "recipes" / "scenes").mkdir(parents=True)
    (tmp_path / "recipes" / "scenes" / "model.fbx").write_text("not a mesh")
    (tmp_path / "recipes" / "scenes" / "hall.obj").write_bytes((files / "hall.obj").read_bytes())
    workspace = workspace_with(tmp_path, [], {"scenes/bad.yaml": _recipe(source, body)})
    with pytest.raises(RecipeError) as caught:
        RecipeLoader(workspace, stages=discover("stages")).load()
    text = str(caught.value)
    assert message in text, text
    assert "scenes/bad.yaml:" in text and "stages.import_mesh" in text, text


# ------------------------------------------------------------------------------- shipped monastery


def test_shipped_monastery_rules_find_every_lantern_and_pagoda(tmp_path: Path):
    shipped = yaml.safe_load((REPO / "recipes/scenes/indoor/samurai-monastery.yaml").read_text())
    only_import = {"stages": {"import_mesh": shipped["stages"]["import_mesh"]}}  # skip the slower stages
    workspace = workspace_with(tmp_path, [], {"scenes/monastery-import.yaml": yaml.safe_dump(only_import)})
    built = build_all(workspace)
    assert not built.report.failed
    annotations = read_annotations(built.output("monastery-import", "raw_geometry"))
    assert annotations.statistics.objects_per_category == {
        "pagoda": 4,
        "paper_lantern": 72,
        "stone_lantern": 4,
    }
    assert list(annotations.terrain_classes) == ["building", "floor", "ground", "wall"]
    # y-up file turned z-up: the ground lies at z = 0 and the pagodas reach about 30 m up.
    assert annotations.bounds.min[2] == pytest.approx(0.0, abs=0.05)
    assert annotations.bounds.max[2] == pytest.approx(30.3, abs=0.1)
    pagodas = [o for o in annotations.objects if o.category == "pagoda"]
    assert all(o.size[2] == pytest.approx(27.6, abs=0.1) for o in pagodas)
    stats = built.manifest("monastery-import", "raw_geometry")["stats"]
    assert stats["nodes"] == 81 and stats["dropped_nodes"] == 0
    assert 124_000 < stats["faces"] <= 124_789
