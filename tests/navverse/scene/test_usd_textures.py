"""Textured meshes in the scene USD file: UVs, texture subsets, shader network, PNG files."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from pxr import Sdf, Usd, UsdGeom, UsdShade

from navverse.errors import SceneError
from navverse.scene.compose import ObjectPart, assemble_scene
from navverse.scene.directory import SceneFiles, read_scene, scene_hash, write_scene_dir
from navverse.scene.geometry import MeshData, Scene, Surface, Texture
from navverse.scene.terrain import terrain_classes
from navverse.scene.usd import export_usd, read_usd, scene_from_usd
from tests.scenes import quad

CHECKER_UVS = np.array([[[0, 0], [2, 0], [2, 2]], [[0, 0], [2, 2], [0, 2]]], dtype=np.float32)
WALL_FACES_STRIPES = (2, 3)  # the wall's front (-y) faces show "stripes", its left (-x) faces "checker"
WALL_FACES_CHECKER = (8, 9)


def _checkerboard() -> np.ndarray:
    """4x4 pixels: 2x2 blocks of red and blue, red at the top left."""
    cells = ((np.arange(4)[:, None] // 2) + (np.arange(4)[None, :] // 2)) % 2
    return np.where(cells[..., None] == 0, np.uint8([255, 0, 0]), np.uint8([0, 0, 255])).astype(np.uint8)


def _stripes() -> np.ndarray:
    image = np.zeros((2, 6, 3), np.uint8)
    image[:, ::2] = (250, 240, 10)
    image[1] = (7, 8, 9)
    return image


def _wall() -> MeshData:
    """A box with two textured face pairs; textures listed out of name order."""
    box = MeshData.box((4.0, 0.2, 2.0), center=(2.0, 6.0, 1.0))
    rng = np.random.default_rng(7)
    uvs = rng.uniform(-1.0, 3.0, size=(box.num_faces, 3, 2)).astype(np.float32)
    index = np.full(box.num_faces, -1, np.int16)
    index[list(WALL_FACES_STRIPES)] = 0
    index[list(WALL_FACES_CHECKER)] = 1
    colors = np.tile(np.uint8([[90, 80, 70]]), (box.num_faces, 1))
    textures = (Texture("stripes", _stripes()), Texture("checker", _checkerboard()))
    return MeshData(box.vertices, box.faces, colors, uvs, index, textures)


def _textured_scene() -> Scene:
    floor = quad(0.0, 0.0, 4.0, 4.0, 0.0)
    floor = MeshData(
        floor.vertices,
        floor.faces,
        None,
        CHECKER_UVS,
        np.zeros(2, np.int16),
        (Texture("checker", _checkerboard()),),
    )
    return assemble_scene(
        scene_id="textured",
        scene_type="indoor",
        surfaces=(Surface("floor", "floor", floor), Surface("wall_north", "wall", _wall())),
        objects=[ObjectPart("chair", MeshData.box((0.5, 0.5, 0.9)), (1.0, 1.0, 0.45), 0.4)],
        terrain_classes=terrain_classes(["floor", "wall"]),
    )


@pytest.fixture(scope="module")
def scene() -> Scene:
    return _textured_scene()


@pytest.fixture(scope="module")
def usd_path(scene: Scene, tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("textured") / "scene.usdc"
    export_usd(scene, path)
    return path


def test_png_files_hold_the_images(usd_path: Path) -> None:
    assert sorted(p.name for p in (usd_path.parent / "textures").iterdir()) == ["checker.png", "stripes.png"]
    with Image.open(usd_path.parent / "textures" / "checker.png") as image:
        assert image.mode == "RGB"
        pixels = np.asarray(image)
    np.testing.assert_array_equal(pixels, _checkerboard())
    assert tuple(pixels[0, 0]) == (255, 0, 0) and tuple(pixels[0, 2]) == (0, 0, 255)


def test_shader_network_and_subset_binding(usd_path: Path) -> None:
    stage = Usd.Stage.Open(str(usd_path))
    floor = stage.GetPrimAtPath("/World/Terrain/floor")
    subsets = UsdShade.MaterialBindingAPI(floor).GetMaterialBindSubsets()
    assert [s.GetPrim().GetName() for s in subsets] == ["texture_checker"]
    subset = subsets[0]
    assert subset.GetElementTypeAttr().Get() == "face"
    assert subset.GetFamilyNameAttr().Get() == "materialBind"
    assert list(subset.GetIndicesAttr().Get()) == [0, 1]
    material, _ = UsdShade.MaterialBindingAPI(subset.GetPrim()).ComputeBoundMaterial()
    assert str(material.GetPath()) == "/World/Looks/Textures/checker"
    surface = material.ComputeSurfaceSource()[0]
    assert surface.GetIdAttr().Get() == "UsdPreviewSurface"
    texture = UsdShade.Shader(surface.GetInput("diffuseColor").GetConnectedSources()[0][0].source.GetPrim())
    assert texture.GetIdAttr().Get() == "UsdUVTexture"
    assert texture.GetInput("file").Get().path == "./textures/checker.png"
    assert Path(texture.GetInput("file").Get().resolvedPath) == usd_path.parent / "textures" / "checker.png"
    assert texture.GetInput("wrapS").Get() == "repeat" and texture.GetInput("wrapT").Get() == "repeat"
    assert texture.GetInput("sourceColorSpace").Get() == "sRGB"
    reader = UsdShade.Shader(texture.GetInput("st").GetConnectedSources()[0][0].source.GetPrim())
    assert reader.GetIdAttr().Get() == "UsdPrimvarReader_float2"
    assert reader.GetInput("varname").Get() == "st"
    st = UsdGeom.PrimvarsAPI(floor).GetPrimvar("st")
    assert st.GetInterpolation() == "faceVarying"
    assert st.GetTypeName() == Sdf.ValueTypeNames.TexCoord2fArray
    np.testing.assert_array_equal(np.asarray(st.Get()), CHECKER_UVS.reshape(-1, 2))
    # The floor itself keeps its class look and physics material; the subset resolves the same physics.
    assert str(UsdShade.MaterialBindingAPI(floor).ComputeBoundMaterial()[0].GetPath()) == "/World/Looks/floor"
    for prim in (floor, subset.GetPrim()):
        bound, _ = UsdShade.MaterialBindingAPI(prim).ComputeBoundMaterial("physics")
        assert str(bound.GetPath()) == "/World/Physics/floor"


def test_mixed_mesh_shares_the_material_and_keeps_untextured_faces(usd_path: Path) -> None:
    stage = Usd.Stage.Open(str(usd_path))
    wall = stage.GetPrimAtPath("/World/Terrain/wall_north")
    binding = UsdShade.MaterialBindingAPI(wall)
    assert binding.GetMaterialBindSubsetsFamilyType() == "nonOverlapping"
    bound = {
        s.GetPrim().GetName(): (
            list(s.GetIndicesAttr().Get()),
            str(UsdShade.MaterialBindingAPI(s.GetPrim()).ComputeBoundMaterial()[0].GetPath()),
        )
        for s in binding.GetMaterialBindSubsets()
    }
    assert bound == {
        "texture_checker": (list(WALL_FACES_CHECKER), "/World/Looks/Textures/checker"),
        "texture_stripes": (list(WALL_FACES_STRIPES), "/World/Looks/Textures/stripes"),
    }
    assert str(binding.ComputeBoundMaterial()[0].GetPath()) == "/World/Looks/wall"
    assert UsdGeom.PrimvarsAPI(wall).GetPrimvar("displayColor").GetInterpolation() == "uniform"
    chair_mesh = stage.GetPrimAtPath("/World/Objects/chair_0001/mesh")
    assert not UsdGeom.PrimvarsAPI(chair_mesh).HasPrimvar("st")
    assert not UsdShade.MaterialBindingAPI(chair_mesh).GetMaterialBindSubsets()
    looks = [p.GetName() for p in stage.GetPrimAtPath("/World/Looks/Textures").GetChildren()]
    assert looks == ["checker", "stripes"]


def test_reader_returns_what_was_written(scene: Scene, usd_path: Path) -> None:
    usd = read_usd(usd_path)
    floor, wall = usd.surfaces
    written_floor = scene.surfaces[0].mesh
    np.testing.assert_array_equal(floor.mesh.face_uvs, written_floor.face_uvs)
    np.testing.assert_array_equal(floor.mesh.face_texture, written_floor.face_texture)
    assert [t.name for t in floor.mesh.textures] == ["checker"]
    np.testing.assert_array_equal(floor.mesh.textures[0].image, _checkerboard())
    written_wall = scene.surfaces[1].mesh
    np.testing.assert_array_equal(wall.mesh.face_uvs, written_wall.face_uvs)
    np.testing.assert_array_equal(wall.mesh.face_colors, written_wall.face_colors)
    assert [t.name for t in wall.mesh.textures] == ["checker", "stripes"]  # ordered by name
    names = np.array(["-", *(t.name for t in wall.mesh.textures)])[wall.mesh.face_texture + 1]
    written = np.array(["-", *(t.name for t in written_wall.textures)])[written_wall.face_texture + 1]
    np.testing.assert_array_equal(names, written)
    np.testing.assert_array_equal(wall.mesh.textures[1].image, _stripes())
    assert wall.mesh.textures[0] is floor.mesh.textures[0]  # one file, read once
    (chair,) = usd.objects
    assert not chair.mesh.textured and chair.mesh.face_uvs is None and chair.mesh.textures == ()


def test_scene_from_usd_keeps_textures(scene: Scene, usd_path: Path) -> None:
    rebuilt = scene_from_usd(usd_path, scene.annotations)
    assert rebuilt.surfaces[0].mesh.textured
    np.testing.assert_array_equal(rebuilt.surfaces[0].mesh.face_uvs, CHECKER_UVS)
    assert not rebuilt.objects[0].mesh.textured


def test_textured_object_mesh_round_trips(tmp_path: Path) -> None:
    box = MeshData.box((0.5, 0.5, 0.9))
    uvs = np.tile(np.float32([[0, 0], [1, 0], [1, 1]]), (box.num_faces, 1, 1))
    index = np.where(np.arange(box.num_faces) < 2, 0, -1).astype(np.int16)
    mesh = MeshData(box.vertices, box.faces, None, uvs, index, (Texture("seat", _stripes()),))
    scene = assemble_scene(
        scene_id="textured_object",
        scene_type="indoor",
        surfaces=(Surface("floor", "floor", quad(0.0, 0.0, 4.0, 4.0, 0.0)),),
        objects=[ObjectPart("chair", mesh, (1.0, 1.0, 0.45), 0.0)],
        terrain_classes=terrain_classes(["floor"]),
    )
    export_usd(scene, tmp_path / "scene.usdc")
    (chair,) = read_usd(tmp_path / "scene.usdc").objects
    np.testing.assert_array_equal(chair.mesh.face_texture, index)
    np.testing.assert_array_equal(chair.mesh.face_uvs, uvs)
    np.testing.assert_array_equal(chair.mesh.textures[0].image, _stripes())
    assert chair.physics_material == "/World/Physics/objects"
    assert not read_usd(tmp_path / "scene.usdc").surfaces[0].mesh.textured


def test_export_is_byte_identical(scene: Scene, tmp_path: Path) -> None:
    first, second = tmp_path / "a", tmp_path / "b"
    first.mkdir()
    second.mkdir()
    export_usd(scene, first / "scene.usdc")
    export_usd(_textured_scene(), second / "scene.usdc")
    export_usd(scene, first / "scene.usdc")  # overwriting gives the same bytes too
    for name in ("scene.usdc", "textures/checker.png", "textures/stripes.png"):
        assert (first / name).read_bytes() == (second / name).read_bytes(), name
    assert sorted(p.name for p in (first / "textures").iterdir()) == ["checker.png", "stripes.png"]


def test_missing_png_is_a_scene_error(scene: Scene, tmp_path: Path) -> None:
    export_usd(scene, tmp_path / "scene.usdc")
    (tmp_path / "textures" / "stripes.png").unlink()
    with pytest.raises(SceneError, match=r"texture file .*textures/stripes\.png .* is missing") as info:
        read_usd(tmp_path / "scene.usdc")
    assert "Traceback" not in str(info.value)
    with pytest.raises(SceneError, match=r"stripes\.png"):
        scene_from_usd(tmp_path / "scene.usdc", scene.annotations)


def test_conflicting_texture_names_are_rejected(scene: Scene, tmp_path: Path) -> None:
    floor = scene.surfaces[0].mesh
    other = MeshData(
        floor.vertices,
        floor.faces,
        None,
        floor.face_uvs,
        floor.face_texture,
        (Texture("stripes", _checkerboard()),),
    )
    clash = Scene(scene.annotations, (scene.surfaces[1], Surface("floor", "floor", other)), scene.objects)
    with pytest.raises(ValueError, match="stripes"):
        export_usd(clash, tmp_path / "scene.usdc")


def test_scene_directory_reads_textures_and_hashes_them(scene: Scene, tmp_path: Path) -> None:
    files = write_scene_dir(scene, tmp_path, bev=False)
    assert files.textures == SceneFiles(tmp_path).textures == tmp_path / "textures"
    rebuilt = read_scene(tmp_path)
    np.testing.assert_array_equal(rebuilt.surfaces[1].mesh.textures[1].image, _stripes())
    before = scene_hash(tmp_path)
    (tmp_path / "textures" / ".stripes.png.1.abc.tmp.png").write_bytes(b"partial")  # ignored
    assert scene_hash(tmp_path) == before
    Image.fromarray(_stripes()[::-1].copy()).save(files.textures / "stripes.png")
    assert scene_hash(tmp_path) != before
