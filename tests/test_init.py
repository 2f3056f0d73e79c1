"""``navverse init``, the preset error of a workspace without presets, and run-agent's scoring hint."""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from navverse.commands.evaluate import eval_hint
from navverse.commands.workspace import scene_name

REPO = Path(__file__).resolve().parents[1]
VADUZ = REPO / "data" / "raw" / "osm" / "vaduz-centre.osm.pbf"


def navverse(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if not k.startswith("NAVVERSE_")}
    return subprocess.run([sys.executable, "-m", "navverse.cli", *args], cwd=cwd, env=env,
                          capture_output=True, text=True)  # fmt: skip


def test_init_writes_a_workspace_with_the_shipped_presets_and_recipes_for_a_city(tmp_path: Path):
    link = tmp_path / "any-name"
    link.symlink_to(VADUZ)  # recognised by its content, named by the link
    window = ("--center", "47.1391", "9.5217", "--size", "300", "250")
    done = navverse("init", "ws", "--city", str(link), *window, "--name", "vaduz", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    root = tmp_path / "ws"
    shipped = sorted(p.name for p in (REPO / "recipes" / "presets").glob("*.yaml"))
    assert sorted(p.name for p in (root / "recipes" / "presets").glob("*.yaml")) == shipped
    scene = yaml.safe_load((root / "recipes" / "scenes" / "vaduz.yaml").read_text())
    assert scene["extends"] == "outdoor-city"
    osm_city = {"source": "../../data/raw/osm/any-name", "center": [47.1391, 9.5217], "size_m": [300, 250]}
    assert scene["stages"]["osm_city"] == osm_city
    assert (root / "data" / "raw" / "osm" / "any-name").read_bytes() == VADUZ.read_bytes()
    assert "ODbL" in (root / "data" / "raw" / "osm" / "README.md").read_text()
    dataset = yaml.safe_load((root / "recipes" / "datasets" / "vaduz-episodes.yaml").read_text())
    assert dataset["links"] == {"scene": ["vaduz"]}
    assert dataset["stages"]["package_dataset"]["splits"] == {"eval": ["vaduz"]}
    assert "cd ws\n  navverse build\n" in done.stdout
    assert "--dataset episodes/vaduz-episodes/v1.0" in done.stdout
    checked = navverse("validate", "recipe", cwd=root)
    assert checked.returncode == 0, checked.stderr
    assert "2 targets" in checked.stdout


def test_init_without_a_city_writes_an_example_that_validates(tmp_path: Path):
    done = navverse("init", "plain", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    checked = navverse("validate", "recipe", cwd=tmp_path / "plain")
    assert checked.returncode == 0 and "1 targets" in checked.stdout, checked.stdout + checked.stderr


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--city", "README.md"], "is not an OSM file"),
        (["--city", str(VADUZ), "--center", "40", "9"], "move it onto the data"),
        (["--city", str(VADUZ), "--size", "0"], "--size: Input should be greater than 0"),
        (["--city", str(VADUZ), "--name", "Bad Name"], "--name"),
        (["--center", "47.1", "9.5"], "give its OSM file with --city"),
    ],
)
def test_init_refuses_bad_input_and_writes_nothing(tmp_path: Path, args: list[str], message: str):
    (tmp_path / "README.md").write_text("# not a map\n")
    done = navverse("init", "ws", *args, cwd=tmp_path)
    assert done.returncode == 1 and message in done.stderr and "Traceback" not in done.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["README.md"]  # no workspace, no scratch


def test_init_refuses_a_folder_that_is_not_empty(tmp_path: Path):
    (tmp_path / "ws").mkdir()
    (tmp_path / "ws" / "notes.txt").write_text("mine")
    done = navverse("init", "ws", cwd=tmp_path)
    assert done.returncode == 1 and "not an empty folder" in done.stderr
    assert [p.name for p in (tmp_path / "ws").iterdir()] == ["notes.txt"]


def test_a_workspace_without_presets_is_told_how_to_get_them(tmp_path: Path):
    (tmp_path / "recipes" / "scenes").mkdir(parents=True)
    (tmp_path / "recipes" / "scenes" / "city.yaml").write_text("extends: outdoor-city\n")
    done = navverse("validate", "recipe", cwd=tmp_path)
    assert done.returncode == 1
    assert "has no presets" in done.stderr and "navverse init" in done.stderr
    (tmp_path / "recipes" / "presets").mkdir()
    (tmp_path / "recipes" / "presets" / "dataset.yaml").write_text("stages: {}\n")
    done = navverse("validate", "recipe", cwd=tmp_path)
    assert done.returncode == 1 and "presets here: dataset" in done.stderr


@pytest.mark.parametrize(
    ("name", "expected"),
    [("vaduz-centre.osm.pbf", "vaduz-centre"), ("Berlin_Mitte.osm.xml.gz", "berlin_mitte"),
     ("map.osm.bz2", "map"), ("my city.xml", "my-city"), ("MAP.OSM", "map")],
)  # fmt: skip
def test_a_scene_is_named_after_its_file(name: str, expected: str):
    assert scene_name(Path(name)) == expected


def _run_args(**given) -> argparse.Namespace:
    defaults = {"dataset": "episodes/x/v1.0", "split": "eval", "embodiment": None, "scenes": []}
    return argparse.Namespace(**{**defaults, **given})


def test_the_scoring_hint_carries_what_the_run_used():
    whole = eval_hint(_run_args(), "run.jsonl", partial=False)
    assert whole == "navverse eval --dataset episodes/x/v1.0 --submission run.jsonl --split eval"
    part = eval_hint(
        _run_args(embodiment="turtlebot", scenes=[Path("/data/my scenes")], split="val"),
        "r.jsonl",
        partial=True,
    )
    assert part == (
        "navverse eval --dataset episodes/x/v1.0 --submission r.jsonl --split val --embodiment turtlebot "
        "--scenes '/data/my scenes' --episodes submitted"
    )
