"""import_mesh on hostile files: named pipes and devices (refused, never waited on), USD layers and
mesh assets outside the project, non-finite and absurdly far vertices."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from navverse.cli import main
from navverse.scene.mesh_files import MeshImportError
from navverse.scene.mesh_import import read_mesh_nodes
from pipeline.dag import build_graph
from pipeline.errors import RecipeError
from pipeline.params import allow_reading
from pipeline.recipes import RecipeLoader
from pipeline.stage import discover
from pipeline.workspace import Workspace
from tests.pipeline.test_file_policy import returns_within
from tests.stages.conftest import build_all, workspace_with

STAGES = discover("stages")

FLOOR = """#usda 1.0
(
    upAxis = "Z"
    metersPerUnit = 1
)

def Mesh "Floor"
{
    int[] faceVertexCounts = [4]
    int[] faceVertexIndices = [0, 1, 2, 3]
    point3f[] points = [(0, 0, 0), (4, 0, 0), (4, 4, 0), (0, 4, 0)]
}
"""


def usd_naming(line: str) -> str:
    """A USD layer whose only content is ``line`` (layer metadata or a prim naming another file)."""
    if line.startswith("subLayers"):
        return f"#usda 1.0\n(\n    {line}\n)\n"
    return f'#usda 1.0\n\ndef Xform "Thing" (\n    {line}\n)\n{{\n}}\n'


def _project(tmp_path: Path, source: str, body: str = "") -> Workspace:
    recipe = f"stages:\n  import_mesh:\n    source: {source}\n    default: floor\n{body}"
    return workspace_with(tmp_path, [], {"scenes/hostile.yaml": recipe})


def _load(workspace: Workspace) -> list:
    return RecipeLoader(workspace, stages=STAGES).load()


def _refusal(workspace: Workspace) -> str:
    with pytest.raises(RecipeError) as caught:
        _load(workspace)
    text = str(caught.value)
    assert "scenes/hostile.yaml:3: stages.import_mesh.source:" in text, text
    return text


@pytest.fixture
def raw(tmp_path: Path) -> Path:
    folder = tmp_path / "data" / "raw"
    folder.mkdir(parents=True)
    return folder


@pytest.fixture
def elsewhere(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A folder outside the project."""
    return tmp_path_factory.mktemp("elsewhere")


# ------------------------------------------------------------------------------------- USD layers


@pytest.mark.parametrize(
    ("line", "kind"),
    [
        ("subLayers = [@./pipe.usda@]", "sublayer"),
        ("references = @./pipe.usda@", "reference"),
        ("payload = @./pipe.usda@", "payload"),
        ("clips = { dictionary c = { asset[] assetPaths = [@./pipe.usda@] } }", "reference"),
    ],
)
def test_a_usd_layer_naming_a_named_pipe_is_refused_at_validation(
    tmp_path: Path, raw: Path, line: str, kind: str
):
    os.mkfifo(raw / "pipe.usda")
    (raw / "middle.usda").write_text(usd_naming(line))
    (raw / "top.usda").write_text(usd_naming("subLayers = [@./middle.usda@]"))
    workspace = _project(tmp_path, str(raw / "top.usda"))
    text = returns_within(60, raw / "pipe.usda", lambda: _refusal(workspace))
    assert (
        f"{raw / 'middle.usda'}: {kind} @./pipe.usda@ cannot be read: "
        f"{raw / 'pipe.usda'} is a named pipe (FIFO), not a regular file"
    ) in text, text


def test_reading_a_usd_file_refuses_a_named_pipe_sublayer_without_blocking(raw: Path):
    os.mkfifo(raw / "pipe.usda")
    (raw / "top.usda").write_text(usd_naming("subLayers = [@./pipe.usda@, @./floor.usda@]"))
    (raw / "floor.usda").write_text(FLOOR)
    with pytest.raises(MeshImportError, match=r"sublayer @\./pipe\.usda@ cannot be read: .* named pipe"):
        returns_within(60, raw / "pipe.usda", lambda: read_mesh_nodes(raw / "top.usda"))


def test_a_usd_sublayer_outside_the_project_is_refused_unless_allowed(
    tmp_path: Path, raw: Path, elsewhere: Path
):
    (elsewhere / "floor.usda").write_text(FLOOR)
    (raw / "top.usda").write_text(usd_naming(f"subLayers = [@{elsewhere / 'floor.usda'}@]"))
    workspace = _project(tmp_path, str(raw / "top.usda"))
    text = _refusal(workspace)
    assert (
        f"sublayer @{elsewhere / 'floor.usda'}@ cannot be read: {elsewhere / 'floor.usda'} is outside" in text
    )
    assert f"--allow-read {elsewhere}" in text, text
    # A symbolic link in the project to the outside layer is outside too.
    (raw / "floor.usda").symlink_to(elsewhere / "floor.usda")
    (raw / "top.usda").write_text(usd_naming("subLayers = [@./floor.usda@]"))
    assert "sublayer @./floor.usda@ cannot be read: './floor.usda' resolves to" in _refusal(workspace)
    with allow_reading([elsewhere]):
        built = build_all(workspace)
    assert built.report.ok, built.report
    stats = built.manifest("hostile", "raw_geometry")["stats"]
    assert stats["nodes"] == 1 and stats["faces"] == 2


def test_editing_a_usd_sublayer_changes_the_cache_key(tmp_path: Path, raw: Path):
    (raw / "floor.usda").write_text(FLOOR)
    (raw / "top.usda").write_text(usd_naming("subLayers = [@./floor.usda@]"))
    workspace = _project(tmp_path, str(raw / "top.usda"))

    def key() -> str:
        return build_graph(_load(workspace)).nodes["hostile:import_mesh"].key

    before = key()
    assert key() == before
    (raw / "floor.usda").write_text(FLOOR.replace("(4, 4, 0)", "(5, 5, 0)"))
    assert key() != before


# ------------------------------------------------------------------------------ the mesh file itself


@pytest.mark.parametrize("kind", ["fifo", "directory", "device"])
def test_a_mesh_source_that_is_not_a_regular_file_is_refused(tmp_path: Path, raw: Path, kind: str):
    os.mkfifo(raw / "pipe.obj")
    (raw / "folder.obj").mkdir()
    source, expected = {
        "fifo": (raw / "pipe.obj", "is a named pipe (FIFO), not a regular file"),
        "directory": (raw / "folder.obj", "is a directory, not a regular file"),
        "device": (Path("/dev/zero"), "/dev/zero is a character device, not a regular file"),
    }[kind]
    workspace = _project(tmp_path, str(source), "    up_axis: z\n")
    with allow_reading(["/dev"]):
        text = returns_within(60, raw / "pipe.obj", lambda: _refusal(workspace))
    assert expected in text, text


def test_an_obj_material_library_that_is_a_named_pipe_is_refused_when_read(raw: Path):
    os.mkfifo(raw / "pipe.mtl")
    (raw / "tile.obj").write_text("mtllib pipe.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n")
    with pytest.raises(MeshImportError) as caught:
        returns_within(60, raw / "pipe.mtl", lambda: read_mesh_nodes(raw / "tile.obj"))
    assert "names files that cannot be read: 'pipe.mtl': " in str(caught.value)
    assert "is a named pipe (FIFO), not a regular file" in str(caught.value)


# ------------------------------------------------------------------------------------------ vertices


def test_non_finite_vertices_are_an_error_naming_the_file_and_their_number(raw: Path):
    obj = raw / "holes.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv nan 0 1\nv 1 inf 1\nf 1 2 3\nf 1 2 4\nf 2 3 5\n")
    with pytest.raises(MeshImportError) as caught:
        read_mesh_nodes(obj)
    assert f"{obj}: 2 vertices have non-finite coordinates (NaN or infinity)" in str(caught.value)
    usd = raw / "holes.usda"
    usd.write_text(FLOOR.replace("(4, 4, 0)", "(nan, 4, 0)"))
    with pytest.raises(MeshImportError, match=r"1 vertex has non-finite coordinates .*'/Floor': 1"):
        read_mesh_nodes(usd)


def test_the_stage_reports_bad_vertices_and_far_away_ones(tmp_path: Path, raw: Path):
    (raw / "holes.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv nan 0 1\nf 1 2 3\nf 1 2 4\n")
    (raw / "far.obj").write_text("v 0 0 0\nv 2000 0 0\nv 0 2000 0\nf 1 2 3\n")
    recipes = {
        "scenes/holes.yaml": "stages:\n  import_mesh: {source: ../../data/raw/holes.obj, up_axis: z}\n",
        "scenes/far.yaml": (
            "stages:\n  import_mesh: {source: ../../data/raw/far.obj, up_axis: z, units: 1000}\n"
        ),
    }
    built = build_all(workspace_with(tmp_path, [], recipes))
    failed = {node.split(":")[0]: result.error for node, result in built.report.failed.items()}
    assert sorted(failed) == ["far", "holes"]
    assert "1 vertex has non-finite coordinates" in failed["holes"], failed["holes"]
    assert "holes.obj" in failed["holes"]
    assert "lies 2e+06 m from the origin (at 1000 meters per unit)" in failed["far"], failed["far"]
    assert "check meters_per_unit" in failed["far"]
    assert not any("Traceback" in error for error in failed.values())


# ------------------------------------------------------------------------------------------ the CLI


def test_the_command_refuses_an_outside_mesh_then_reads_it_with_allow_read(
    tmp_path: Path, elsewhere: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
):
    (elsewhere / "tile.obj").write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n")
    _project(tmp_path, str(elsewhere / "tile.obj"), "    up_axis: z\n")
    monkeypatch.setenv("NAVVERSE_ROOT", str(tmp_path))
    monkeypatch.delenv("NAVVERSE_ALLOW_READ", raising=False)
    assert main(["validate", "recipe"]) == 1
    err = capsys.readouterr().err
    assert f"{elsewhere / 'tile.obj'} is outside the project" in err and "Traceback" not in err
    assert f"--allow-read {elsewhere}" in " ".join(err.split()), err
    assert main(["validate", "recipe", "--allow-read", str(elsewhere)]) == 0
    assert "valid" in capsys.readouterr().out
    monkeypatch.setenv("NAVVERSE_ALLOW_READ", str(elsewhere))
    assert main(["validate", "recipe"]) == 0
