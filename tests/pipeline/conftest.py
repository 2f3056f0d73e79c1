"""Fixtures: a throw-away workspace with recipes for the example stages."""

from __future__ import annotations

import textwrap
from collections.abc import Iterator
from pathlib import Path

import pytest

import tests.pipeline.example_stages  # noqa: F401  (registers the example stages)
from pipeline.stage import registered_stages
from pipeline.workspace import Workspace
from tests.pipeline.cli_helpers import end_leftovers

EXAMPLE_STAGES = (
    *("ex_numbers", "ex_sum", "ex_gather", "ex_slow", "ex_read_file"),
    *("ex_block", "ex_annex", "ex_decorate", "ex_publish"),
)


def write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(textwrap.dedent(text).lstrip())
    return path


@pytest.fixture(autouse=True)
def no_build_left_running() -> Iterator[None]:
    """After each test, end the builds it started that still run (it failed midway), so that no later
    test of the worker shares the machine with them."""
    yield
    end_leftovers()


@pytest.fixture
def stages():
    registry = registered_stages()
    return {name: registry[name] for name in EXAMPLE_STAGES}


@pytest.fixture
def workspace(tmp_path: Path) -> Workspace:
    ws = Workspace(tmp_path)
    write(
        ws.presets_dir / "base.yaml",
        """
        stages:
          ex_numbers: {count: 4}
          ex_sum: {offset: 1.0}
    """,
    )
    write(
        ws.recipes_dir / "group" / "alpha.yaml",
        """
        description: two seeds of numbers and their sums
        extends: base
        seeds: [0, 1]
    """,
    )
    write(
        ws.recipes_dir / "group" / "beta.yaml",
        """
        extends: base
        seed: 7
        stages:
          ex_sum: {offset: 2.5}
    """,
    )
    write(
        ws.recipes_dir / "all.yaml",
        """
        stages:
          ex_gather: {}
        links:
          total: ["alpha-*", "beta"]
    """,
    )
    return ws


@pytest.fixture(scope="module")
def ray_instance():
    """A local Ray with 2 worker CPUs for the module (executors use it and leave it running); shut down
    after the module if it started it."""
    import ray

    started = not ray.is_initialized()
    if started:
        ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False, configure_logging=False)
    yield ray
    if started:
        ray.shutdown()
