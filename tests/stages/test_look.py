"""The look stage: the appearance layer of a scene, outside every cache key of its episodes; its USD
layer binds a textured material on every mesh, read back through pxr."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import pytest
from pxr import Usd, UsdGeom, UsdShade

from navverse.dataset import built_version
from navverse.errors import SceneError
from navverse.look.files import LOOK_JSON, find_look, load_scene_look, read_look, write_look
from navverse.look.markings import MarkedRoad
from navverse.look.scene_look import MapDetails
from navverse.look.settings import EVAL_LOOK
from navverse.look.usd_look import LOOK_USD
from navverse.scene.directory import read_scene
from pipeline.code_version import module_closure
from tests.stages.conftest import Built, build_all, copy_built


def _files(root: Path) -> dict[str, str]:
    """sha256 of every file under `root`, by relative path."""
    return {
        str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(root.rglob("*"))
        if p.is_file()
    }


def test_a_changed_look_rebuilds_only_the_look_and_the_episodes_keep_their_bytes(
    tiny_build: Built, tmp_path: Path
) -> None:
    built = copy_built(tiny_build, tmp_path / "ws")
    dataset = built_version(built.output("tiny", "dataset"))
    before = _files(dataset)
    old_look = built.output("apartment-s0", "look")
    assert read_look(old_look / LOOK_JSON)[0] == EVAL_LOOK
    recipe = built.workspace.recipes_dir / "scenes" / "indoor" / "apartment.yaml"
    recipe.write_text(recipe.read_text() + "  look: {material_variant: 7, time_of_day: 16.0}\n")
    rebuilt = build_all(built.workspace)
    assert rebuilt.report.ok, rebuilt.report
    ran = sorted(rebuilt.report.built)
    assert ran and all(node.endswith(":look") for node in ran), ran
    assert {node.split(":")[0] for node in ran} == {"apartment-s0", "apartment-s1"}
    new_look = built.output("apartment-s0", "look")
    assert new_look.resolve() != old_look.resolve()
    assert read_look(new_look / LOOK_JSON)[0].material_variant == 7
    assert _files(built_version(built.output("tiny", "dataset"))) == before


_EPISODE_STAGES = (
    "blockout", "indoor_layout", "import_mesh", "decimate", "city", "populate", "storefronts",
    "assemble_i2o", "navmesh", "sample_episodes", "verify_episodes", "package_dataset", "merge_datasets",
)  # fmt: skip


@pytest.mark.parametrize("stage_module", _EPISODE_STAGES)
def test_no_geometry_or_episode_stage_hashes_the_look_or_the_renderer(stage_module: str) -> None:
    # A stage's cache key covers its module's import closure: editing a material, the sky or the
    # shading must not move the key of a scene's geometry, its navmesh, its candidates or its
    # verified episodes. Datasets read the look's settings only (the version their manifest records).
    closure = {name for name, _ in module_closure(f"stages.{stage_module}")}
    assert closure, stage_module
    look = {name for name in closure if name.startswith("navverse.look.")}
    assert look <= {"navverse.look.settings"}, (stage_module, sorted(look))
    renderer = {"navverse.sim.render", "navverse.sim.lighting", "navverse.sim.shade_kernels"}
    assert not closure & renderer, (stage_module, sorted(closure & renderer))
    # The check can fail: the stages that draw pictures do hash them.
    assert "navverse.look.materials" in {name for name, _ in module_closure("stages.look")}


@pytest.mark.parametrize("stage_module", ["sample_episodes", "verify_episodes", "instructions"])
def test_the_stages_making_episodes_do_not_hash_the_dataset_reader(stage_module: str) -> None:
    # They read and write episode records (navverse.records); a change to the reader, the manifest,
    # publishing or private splits must not sample or verify a dataset again.
    closure = {name for name, _ in module_closure(f"stages.{stage_module}")}
    assert "navverse.records.schema" in closure, stage_module
    reader = sorted(name for name in closure if name.split(".")[:2] == ["navverse", "dataset"])
    assert not reader, (stage_module, reader)
    # The check can fail: packaging does hash the reader's package.
    assert "navverse.dataset" in {name for name, _ in module_closure("stages.package_dataset")}


def test_the_look_layer_binds_a_textured_material_on_every_mesh(tiny_build: Built) -> None:
    look_dir = tiny_build.output("apartment-s0", "look")
    stage = Usd.Stage.Open(str(look_dir / LOOK_USD))
    meshes = [prim for prim in stage.Traverse() if prim.IsA(UsdGeom.Mesh)]
    assert len(meshes) > 10
    untextured = []
    for prim in meshes:
        subsets = UsdShade.MaterialBindingAPI(prim).GetMaterialBindSubsets()
        # A mesh whose faces all lie in subsets shows their materials; otherwise its own shows too.
        covered = sum(len(s.GetIndicesAttr().Get()) for s in subsets)
        faces = len(UsdGeom.Mesh(prim).GetFaceVertexCountsAttr().Get())
        for bound in [s.GetPrim() for s in subsets] + ([prim] if covered < faces else []):
            material, _ = UsdShade.MaterialBindingAPI(bound).ComputeBoundMaterial()
            if not material or not _texture_files(material):
                untextured.append(str(bound.GetPath()))
    assert not untextured, untextured[:5]


def _texture_files(material: UsdShade.Material) -> list[Path]:
    """The existing image files the UsdUVTexture shaders of a material read."""
    files = []
    for child in material.GetPrim().GetChildren():
        shader = UsdShade.Shader(child)
        if shader and shader.GetIdAttr().Get() == "UsdUVTexture":
            asset = shader.GetInput("file").Get()
            if asset is not None and asset.resolvedPath and Path(asset.resolvedPath).is_file():
                files.append(Path(asset.resolvedPath))
    return files


def test_the_renderer_takes_the_built_look_and_a_broken_one_says_what_to_do(
    tiny_build: Built, tmp_path: Path
) -> None:
    scene_dir = tiny_build.output("apartment-s0", "scene")
    assert find_look(scene_dir).resolve() == (tiny_build.output("apartment-s0", "look") / LOOK_JSON).resolve()
    scene = read_scene(scene_dir)
    assert load_scene_look(scene, scene_dir).settings == EVAL_LOOK
    broken = tmp_path / "scene"
    broken.mkdir()
    (broken / LOOK_JSON).write_text(json.dumps({"format_version": "1.0", "settings": {"time_of_day": 99}}))
    with pytest.raises(SceneError, match="rebuild the scene's look"):
        load_scene_look(scene, broken)
    (broken / LOOK_JSON).write_text(json.dumps({"format_version": "7.0"}))
    with pytest.raises(SceneError, match=r"look format 7\.0 is not 1\.1"):
        load_scene_look(scene, broken)
    # A look made for another build of the scene is not used: the evaluation look, with a warning.
    stale = json.loads((find_look(scene_dir)).read_text())
    stale["settings"]["time_of_day"], stale["geometry_sha256"] = 17.0, "0" * 64
    for name in ("scene.json", "scene.usdc", "navmesh.bin"):
        (broken / name).write_bytes((scene_dir / name).read_bytes())
    (broken / LOOK_JSON).write_text(json.dumps(stale))
    with pytest.warns(UserWarning, match="another build of scene apartment-s0"):
        assert load_scene_look(scene, broken).settings == EVAL_LOOK


def test_look_json_keeps_the_mapped_crossings_and_reads_a_1_0_file_without_them(tmp_path: Path) -> None:
    road = MarkedRoad(((0.0, 0.0), (50.0, 0.0)), 7.0, 2, False, "residential")
    details = MapDetails(buildings={3: ("house", 2.0)}, roads=[road], crossings=[(20.0, 0.5, "lines")])
    path = tmp_path / LOOK_JSON
    write_look(path, EVAL_LOOK, details, geometry_sha256="0" * 64)
    assert json.loads(path.read_text())["map"]["crossings"] == [[20.0, 0.5, "lines"]]
    assert read_look(path) == (EVAL_LOOK, details)
    older = json.loads(path.read_text())
    del older["map"]["crossings"]
    path.write_text(json.dumps({**older, "format_version": "1.0"}))
    assert read_look(path)[1] == MapDetails(buildings={3: ("house", 2.0)}, roads=[road])
    older["map"]["crossings"] = [[20.0, 0.5, "stripes"]]
    path.write_text(json.dumps(older))
    with pytest.raises(SceneError, match="unknown crossing markings"):
        read_look(path)
