"""A stage's warnings reach the build summary: a category rule of a recipe that matches no object is
shown after the build, with the target and stage, not only in the stage's log."""

from __future__ import annotations

from pathlib import Path

from tests.stages.conftest import navverse_command, workspace_with

CAFE = """\
extends: indoor-building
stages:
  indoor_layout:
    building_type: cafe
    length: 12
    category_rules:
      - {pattern: "^chair_", category: seat}
      - {pattern: "^no_such_thing_", category: chair}
  navmesh: null
"""


def test_a_category_rule_matching_nothing_is_a_warning_in_the_build_summary(tmp_path: Path) -> None:
    workspace = workspace_with(tmp_path / "ws", [], {"scenes/cafe-rules.yaml": CAFE})
    result = navverse_command(workspace.root, "build", "cafe-rules")
    output = " ".join((result.stdout + result.stderr).split())
    assert result.returncode == 0, output
    assert "warning cafe-rules:indoor_layout: category rule '^no_such_thing_'" in output
    assert "matches no object" in output and "'^chair_'" not in output  # the chair rule did match
    log = (workspace.built_dir / "logs" / "cafe-rules" / "indoor_layout.log").read_text()
    assert "WARNING category rule '^no_such_thing_'" in log
