"""The layer contracts of pyproject.toml (``[tool.importlinter]``) hold, and a break of each is caught."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
LINT_IMPORTS = str(Path(sys.executable).parent / "lint-imports")
PACKAGES = ("navverse", "pipeline", "stages")


def lint_imports(root: Path) -> tuple[int, str]:
    """Run lint-imports on the packages under `root` with `root`'s pyproject.toml; (exit code, output)."""
    result = subprocess.run(
        [LINT_IMPORTS, "--config", str(root / "pyproject.toml"), "--no-cache", "--no-logo"],
        cwd=root,
        env={**os.environ, "PYTHONPATH": str(root)},
        capture_output=True,
        text=True,
        timeout=120,
    )
    return result.returncode, " ".join((result.stdout + result.stderr).split())


def _not_python(directory: str, names: list[str]) -> set[str]:
    return {n for n in names if n == "__pycache__" or n.endswith((".so", ".cpp", ".h"))}


def test_the_tree_keeps_its_layers() -> None:
    code, output = lint_imports(REPO)
    assert code == 0, output
    assert "0 broken" in output


@pytest.mark.parametrize(
    ("module", "statement", "broken_import"),
    [
        (
            "pipeline/store.py",
            "from navverse.errors import NavverseError",
            "pipeline.store -> navverse.errors",
        ),
        ("pipeline/dag.py", "import stages.navmesh", "pipeline.dag -> stages.navmesh"),
        (
            "navverse/scene/fields.py",
            "from pipeline.errors import PipelineError",
            "navverse.scene.fields -> pipeline.errors",
        ),
        # Only navverse.cli is the composition root, not a module beside it.
        (
            "navverse/cli_support.py",
            "from pipeline.store import ArtifactStore",
            "navverse.cli_support -> pipeline.store",
        ),
        # The data commands beside it do not reach the engine either.
        (
            "navverse/commands/evaluate.py",
            "from pipeline.store import ArtifactStore",
            "navverse.commands.evaluate -> pipeline.store",
        ),
        (
            "navverse/sim/spot.py",
            "from navverse.sim.embodiments import make_embodiment",
            "navverse.sim.spot -> navverse.sim.embodiments",
        ),
        (
            "navverse/sim/embodiment.py",
            "from navverse.sim.turtlebot import TurtleBot",
            "navverse.sim.embodiment -> navverse.sim.turtlebot",
        ),
        # The city's subpackages: OSM reading knows no street life; the map in 3-D nothing built on it.
        (
            "navverse/city/osm/reader.py",
            "from navverse.city.street_life.populate import populate_city",
            "navverse.city.osm.reader -> navverse.city.street_life.populate",
        ),
        (
            "navverse/city/geometry/scene.py",
            "from navverse.city.street_life.zones import street_zones",
            "navverse.city.geometry.scene -> navverse.city.street_life.zones",
        ),
        # The evaluation server is handed its dataset and scenes by its command.
        (
            "navverse/serve/benchmark.py",
            "from navverse.commands.datasets import split_of",
            "navverse.serve.benchmark -> navverse.commands.datasets",
        ),
    ],
    ids=[
        "pipeline-navverse",
        "pipeline-stages",
        "navverse-pipeline",
        "beside-cli-pipeline",
        "cli-data-command-pipeline",
        "robot-registry",
        "protocol-robot",
        "osm-street-life",
        "geometry-street-life",
        "serve-commands",
    ],
)
def test_an_import_across_the_layers_breaks_a_contract(
    tmp_path: Path, module: str, statement: str, broken_import: str
) -> None:
    for package in PACKAGES:
        shutil.copytree(REPO / package, tmp_path / package, ignore=_not_python)
    shutil.copy(REPO / "pyproject.toml", tmp_path / "pyproject.toml")
    target = tmp_path / module
    source = target.read_text() if target.exists() else ""
    # Inside a function, as the lazy imports of the CLI and the stages are.
    target.write_text(f"{source}\n\ndef _injected() -> None:\n    {statement}\n")
    code, output = lint_imports(tmp_path)
    assert code == 1, output
    assert "1 broken" in output
    assert broken_import in output
