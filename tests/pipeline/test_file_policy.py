"""The file-access policy of recipes: where a ``SourceFile`` may be, and what kind of file it must be."""

from __future__ import annotations

import contextvars
import os
import threading
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pybullet_data
import pytest

from pipeline.dag import build_graph
from pipeline.errors import RecipeError
from pipeline.params import ALLOW_READ_ENV, MAX_SOURCE_BYTES, allow_reading
from pipeline.recipes import RecipeLoader, Target
from pipeline.workspace import Workspace
from tests.pipeline.conftest import write
from tests.pipeline.example_stages import FileParams


def returns_within(seconds: float, fifo: Path, call: Callable[[], Any]) -> Any:
    """Run ``call`` and return what it returns (or raise what it raises); fail the test if it is
    still blocked after ``seconds`` (then open ``fifo`` for writing, which releases a reader)."""
    outcome: dict[str, Any] = {}
    context = contextvars.copy_context()  # the allow-list of the test's thread

    def run() -> None:
        try:
            outcome["value"] = context.run(call)
        except BaseException as exc:  # handed to the test thread
            outcome["error"] = exc

    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    thread.join(seconds)
    if thread.is_alive():
        os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))  # the blocked reader gets end-of-file
        thread.join(seconds)
        pytest.fail(f"blocked on the named pipe {fifo} for {seconds} s")
    if "error" in outcome:
        raise outcome["error"]
    return outcome["value"]


def _load(workspace: Workspace, stages: dict, source: str) -> list[Target]:
    recipe = write(
        workspace.recipes_dir / "data" / "read.yaml", f"stages:\n  ex_read_file: {{source: {source}}}\n"
    )
    return RecipeLoader(workspace, stages=stages).load([recipe])


def _refusal(workspace: Workspace, stages: dict, source: str) -> str:
    with pytest.raises(RecipeError) as caught:
        _load(workspace, stages, source)
    text = str(caught.value)
    assert "read.yaml:2: stages.ex_read_file.source:" in text, text
    return text


@pytest.fixture
def outside(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A file outside the project."""
    return write(tmp_path_factory.mktemp("elsewhere") / "values.txt", "1 2 3\n")


def test_files_inside_the_project_are_read(workspace, stages):
    values = write(workspace.root / "data" / "raw" / "values.txt", "1 2 3\n")
    (target,) = _load(workspace, stages, "../../data/raw/values.txt")
    assert target.stages[0].params.source == values.resolve()


def test_an_absolute_path_outside_the_project_is_refused_with_the_ways_to_allow_it(
    workspace, stages, outside: Path
):
    text = _refusal(workspace, stages, str(outside))
    folder = outside.parent.resolve()
    assert f"{outside.resolve()} is outside the project {workspace.root.resolve()}" in text, text
    assert f"'navverse build --allow-read {folder}' (or NAVVERSE_ALLOW_READ={folder})" in text, text
    assert "data/raw/" in text and "package_data" in text, text


def test_a_relative_path_climbing_out_of_the_project_is_refused(workspace, stages, outside: Path):
    relative = os.path.relpath(outside, workspace.recipes_dir / "data")
    assert relative.startswith("../../..")
    text = _refusal(workspace, stages, relative)
    assert f"{relative!r} resolves to {outside.resolve()}" in text, text
    assert "outside the project" in text, text


def test_a_symbolic_link_inside_the_project_to_a_file_outside_is_refused(workspace, stages, outside: Path):
    link = workspace.root / "data" / "raw" / "values.txt"
    link.parent.mkdir(parents=True)
    link.symlink_to(outside)
    text = _refusal(workspace, stages, "../../data/raw/values.txt")
    assert f"resolves to {outside.resolve()} (symbolic links followed)" in text, text
    folder_link = workspace.root / "data" / "linked"
    folder_link.symlink_to(outside.parent, target_is_directory=True)
    assert "outside the project" in _refusal(workspace, stages, "../../data/linked/values.txt")


def test_the_allow_list_from_the_option_or_the_environment_lets_a_folder_be_read(
    workspace, stages, outside: Path, monkeypatch: pytest.MonkeyPatch
):
    with allow_reading([outside.parent]):
        (target,) = _load(workspace, stages, str(outside))
    assert target.stages[0].params.source == outside.resolve()
    _refusal(workspace, stages, str(outside))  # only inside the block
    monkeypatch.setenv(ALLOW_READ_ENV, f"/nonexistent{os.pathsep}{outside.parent}")
    (target,) = _load(workspace, stages, str(outside))
    assert target.stages[0].params.source == outside.resolve()


def test_the_allow_list_does_not_change_cache_keys(
    workspace, stages, outside: Path, monkeypatch: pytest.MonkeyPatch
):
    write(workspace.root / "data" / "raw" / "values.txt", "1 2 3\n")

    def key(source: str) -> str:
        targets = _load(workspace, stages, source)
        return build_graph(targets).nodes[f"{targets[0].id}:ex_read_file"].key

    inside = key("../../data/raw/values.txt")
    with allow_reading([outside.parent]):
        assert key("../../data/raw/values.txt") == inside
        by_option = key(str(outside))
    monkeypatch.setenv(ALLOW_READ_ENV, str(outside.parent))
    assert key(str(outside)) == by_option


@pytest.mark.parametrize("kind", ["fifo", "directory", "device"])
def test_special_files_are_refused_before_they_are_opened(workspace, stages, kind: str):
    raw = workspace.root / "data" / "raw"
    raw.mkdir(parents=True)
    fifo = raw / "values.fifo"
    os.mkfifo(fifo)
    path, expected = {
        "fifo": (fifo, "is a named pipe (FIFO), not a regular file"),
        "directory": (raw, "is a directory, not a regular file"),
        "device": (Path("/dev/zero"), "/dev/zero is a character device, not a regular file"),
    }[kind]
    with allow_reading(["/dev"]):
        text = returns_within(30, fifo, lambda: _refusal(workspace, stages, str(path)))
    assert expected in text, text
    # Parameters validated again without a project (as in a worker process) are checked the same way.
    with pytest.raises(ValueError, match="not a regular file"):
        returns_within(30, fifo, lambda: FileParams.model_validate({"source": str(path)}))


def test_files_over_the_size_cap_are_refused(workspace, stages):
    big = workspace.root / "data" / "raw" / "big.txt"
    big.parent.mkdir(parents=True)
    with big.open("wb") as handle:
        handle.truncate(MAX_SOURCE_BYTES + 1)  # sparse: no disk space is used
    text = _refusal(workspace, stages, "../../data/raw/big.txt")
    assert f"{big.resolve()} is 2.00 GiB, over the 2.00 GiB limit of a source file" in text, text


def test_an_installed_package_s_data_may_be_read_and_only_inside_it(workspace, stages):
    (target,) = _load(workspace, stages, "{package_data: pybullet_data, file: cube.obj}")
    assert target.stages[0].params.source == (Path(pybullet_data.getDataPath()) / "cube.obj").resolve()
    assert "has no data file '../../../../etc/hostname'" in _refusal(
        workspace, stages, "{package_data: pybullet_data, file: ../../../../etc/hostname}"
    )
    assert "is a module, not a package with data files" in _refusal(
        workspace, stages, "{package_data: textwrap, file: x.txt}"
    )
