"""scripts/kinodynamics.py keeps each dataset's runs apart and tables only what ran."""

from __future__ import annotations

from types import SimpleNamespace

from tests.script_module import load_script

kinodynamics = load_script("kinodynamics")


def _dataset(name: str, sha: str) -> SimpleNamespace:
    return SimpleNamespace(manifest=SimpleNamespace(name=name, version="1.0"), manifest_sha256=sha)


def test_runs_of_other_datasets_splits_limits_or_contents_are_never_reused() -> None:
    folder = kinodynamics._runs_folder
    hills, turtle = _dataset("navverse-hills", "a" * 64), _dataset("navverse-hills-turtlebot", "a" * 64)
    rebuilt = _dataset("navverse-hills", "b" * 64)  # the same version rebuilt with other episodes
    names = {
        folder(hills, split="eval", limit=None),
        folder(hills, split="train", limit=None),
        folder(hills, split="eval", limit=80),
        folder(turtle, split="eval", limit=None),
        folder(rebuilt, split="eval", limit=None),
    }
    assert len(names) == 5
    assert folder(hills, split="eval", limit=None) == folder(hills, split="eval", limit=None)


def test_a_run_without_valid_trajectories_gives_no_rows() -> None:
    invalid = [{"episode_id": "e1", "label": "invalid", "scene_type": "outdoor", "speed": 0.0}]
    assert kinodynamics._rows("spot", 0.5, invalid, invalid) == []
    ran = [{"episode_id": "e1", "label": "success", "scene_type": "outdoor", "speed": 1.4}]
    rows = kinodynamics._rows("spot", 0.5, ran, ran)
    assert [r["scene_type"] for r in rows] == ["outdoor", "all"] and rows[1]["sr_own_tolerance"] == 1.0
