"""The ``navverse`` command end to end, on a copy of the shipped recipes."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import yaml

from pipeline.workspace import Workspace
from tests.stages.conftest import build_all

REPO = Path(__file__).resolve().parents[1]
NAVVERSE = str(Path(sys.executable).parent / "navverse")


def run(root: Path, *args: str, timeout: float = 600) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "NAVVERSE_ROOT": str(root)}
    env.pop("COLUMNS", None)  # as a user's pipe: pytest-xdist workers set 80
    return subprocess.run(
        [NAVVERSE, *args], env=env, capture_output=True, text=True, timeout=timeout, cwd=root
    )


def copy_recipes(root: Path, *, only: str | None = None) -> Path:
    """The shipped recipes and raw data in a workspace at ``root``; with ``only`` (a glob, or globs
    joined by ``|``), only the scene recipes it matches, and no dataset (its scenes are gone)."""
    shutil.copytree(REPO / "recipes", root / "recipes")
    shutil.copytree(REPO / "data" / "raw", root / "data" / "raw")  # the files recipes read
    for manifest in (REPO / "episodes").glob("*/v*/manifest.json"):  # a published release recipes check
        target = root / manifest.relative_to(REPO)
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(manifest, target)
    if only is not None:
        for path in (root / "recipes" / "scenes").rglob("*.yaml"):
            if not any(path.match(pattern) for pattern in only.split("|")):
                path.unlink()
        shutil.rmtree(root / "recipes" / "datasets")
    return root


def built_files(root: Path) -> dict[str, dict]:
    """{artifact dir name: manifest 'files'} of every committed artifact."""
    found = {}
    for manifest in sorted((root / "data" / "built" / "artifacts").glob("*/*/manifest.json")):
        found[manifest.parent.name] = json.loads(manifest.read_text())["files"]
    return found


def test_help_everywhere():
    for args in ([], ["build"], ["status"], ["clean"], ["validate", "recipe"], ["show", "scene"]):
        result = subprocess.run([NAVVERSE, *args, "--help"], capture_output=True, text=True)
        assert result.returncode == 0 and "usage: navverse" in result.stdout


def test_dry_run_prints_the_graph_of_shipped_recipes():
    result = run(REPO, "build", "--dry-run")
    assert result.returncode == 0, result.stderr
    assert "Build graph" in result.stdout
    for recipe in (REPO / "recipes" / "scenes").rglob("*.yaml"):
        if yaml.safe_load(recipe.read_text()).get("manual"):
            continue  # built only by name, not in the default graph (test_shipped_recipes plans it)
        assert recipe.stem in result.stdout


def test_recipe_with_three_mistakes(tmp_path):
    copy_recipes(tmp_path)
    bad = tmp_path / "recipes" / "scenes" / "bad.yaml"
    bad.write_text(
        "description: three mistakes\n"
        "stages:\n"
        "  blockout:\n"
        "    scene_type: indoor\n"
        "    colour: red\n"
        "    surfaces:\n"
        "      - {name: floor, terrain: floor, center: [0, 0, 0], box: [-4, 4, 0.1]}\n"
        "      - {name: wall, terrain: wall, center: [zero, 0, 1], box: [4, 0.2, 2]}\n"
    )
    for command in (["build"], ["validate", "recipe", str(bad)]):
        result = run(tmp_path, *command)
        assert result.returncode == 1
        assert "Traceback" not in result.stderr + result.stdout
        assert "bad.yaml:5: stages.blockout.colour: unknown key 'colour'" in result.stderr
        assert "bad.yaml:7: stages.blockout.surfaces.0.box.0:" in result.stderr
        assert "bad.yaml:8: stages.blockout.surfaces.1.center.0:" in result.stderr
        assert "3 problems" in result.stderr
    assert not (tmp_path / "data" / "built").exists()


def test_unknown_target_and_missing_scene_are_clean_errors(tmp_path):
    copy_recipes(tmp_path)
    result = run(tmp_path, "build", "no-such-target")
    assert result.returncode == 1 and "no target or recipe matches 'no-such-target'" in result.stderr
    result = run(tmp_path, "show", "scene", "corridor")
    assert result.returncode == 1 and "navverse build corridor" in result.stderr
    assert "Traceback" not in result.stderr


@pytest.mark.slow(seconds=15)
def test_build_twice_then_edit_one_recipe(tmp_path):
    # The stages run in the command's process (--jobs 0): what is built is this test's concern, the
    # workers are test_sigkill_mid_build_then_resume_matches_clean_build's.
    copy_recipes(tmp_path, only="*corridor.yaml")
    first = run(tmp_path, "build", "--jobs", "0")
    assert first.returncode == 0, first.stderr + first.stdout
    assert "4 built" in first.stdout  # blockout and navmesh of each corridor
    second = run(tmp_path, "build")
    assert second.returncode == 0 and "Nothing to do" in second.stdout
    status = run(tmp_path, "status")
    assert "2 fresh" in status.stdout
    recipe = tmp_path / "recipes" / "scenes" / "blockout" / "corridor.yaml"
    recipe.write_text(recipe.read_text().replace("radius: 0.25", "radius: 0.3"))
    assert "1 stale" in run(tmp_path, "status").stdout
    third = run(tmp_path, "build", "--jobs", "0")
    assert third.returncode == 0
    assert (
        "built corridor:blockout" in third.stdout
        and "l-corridor:blockout" not in third.stdout.split("Build finished")[0]
    )
    assert "2 built, 2 cached" in third.stdout  # the corridor's blockout and navmesh
    scene_dir = tmp_path / "data/built/targets/corridor/scene"
    scene = json.loads((scene_dir / "scene.json").read_text())
    assert scene["scene_id"] == "corridor" and scene["objects"][0]["size"][0] == pytest.approx(0.6)
    assert scene["statistics"]["navigable_area_m2"] > 15.0 and (scene_dir / "navmesh.bin").is_file()
    out = tmp_path / "corridor.png"
    shown = run(tmp_path, "show", "scene", "corridor", "-o", str(out))
    assert shown.returncode == 0 and out.stat().st_size > 10_000


@pytest.mark.slow(seconds=35)
def test_sigkill_mid_build_then_resume_matches_clean_build(tmp_path):
    # Three blockout scenes (blockout and navmesh stages): six stage runs, each in a worker of its own,
    # so the kill lands mid-build. The clean build, what the resumed one must match, is made in this
    # process.
    scenes = "*/box-room.yaml|*/corridor.yaml|*/two-rooms.yaml"
    clean = copy_recipes(tmp_path / "clean", only=scenes)
    killed = copy_recipes(tmp_path / "killed", only=scenes)
    assert build_all(Workspace(clean)).report.ok
    env = {**os.environ, "NAVVERSE_ROOT": str(killed)}
    process = subprocess.Popen(
        [NAVVERSE, "build", "--jobs", "2"],
        env=env,
        cwd=killed,
        start_new_session=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    artifacts = killed / "data" / "built" / "artifacts"
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and len(list(artifacts.glob("*/*/manifest.json"))) < 1:
        time.sleep(0.05)
    os.killpg(process.pid, signal.SIGKILL)
    process.wait()
    gone_by = time.monotonic() + 10
    while time.monotonic() < gone_by:  # until every process of the build (workers included) is gone
        try:
            os.killpg(process.pid, 0)
        except ProcessLookupError:
            break
        time.sleep(0.05)
    partial = built_files(killed)
    assert 0 < len(partial) < len(built_files(clean)), "the kill should land mid-build"
    resumed = run(killed, "build", "--jobs", "2")
    assert resumed.returncode == 0, resumed.stderr + resumed.stdout
    assert built_files(killed) == built_files(clean)
    assert not list((killed / "data" / "built" / "tmp").iterdir())


def test_show_presets_prints_every_preset_and_profile(tmp_path):
    result = run(copy_recipes(tmp_path), "show", "presets")
    assert result.returncode == 0, result.stderr
    for word in ("cell_size", "indoor", "outdoor", "i2o", "discrete_step_m", "start_region"):
        assert word in result.stdout, word


def test_show_scene_draws_a_scene_directory_of_two_buildings(tmp_path):
    import math

    import numpy as np

    from navverse.indoor import generate_building
    from navverse.scene.compose import merge_scenes, transform_scene
    from navverse.scene.directory import write_scene_dir

    cafe = generate_building("cafe", np.random.default_rng(1), scene_id="cafe")
    flat = generate_building("apartment", np.random.default_rng(2), scene_id="flat")
    flat = transform_scene(flat, translation=(35.0, 0.0, 0.0), yaw=math.pi / 2)
    scene_dir = tmp_path / "two"
    scene_dir.mkdir()
    write_scene_dir(merge_scenes([cafe, flat], scene_id="two", scene_type="indoor"), scene_dir, bev=False)
    result = run(
        copy_recipes(tmp_path / "ws"), "show", "scene", str(scene_dir), "-o", str(tmp_path / "two.png")
    )
    assert result.returncode == 0, result.stderr
    assert (tmp_path / "two.png").stat().st_size > 20_000
    missing = run(tmp_path / "ws", "show", "scene", str(tmp_path / "nowhere"))
    assert missing.returncode == 1 and "Traceback" not in missing.stderr
