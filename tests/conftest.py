"""Suite-wide settings: SIGINT at its default, the hypothesis profile that keeps property tests bounded
and reproducible; the order of the test modules (the long ones first); the build several test modules
read, made once per run."""

from __future__ import annotations

import fcntl
import os
import pickle
import signal
from pathlib import Path
from typing import TYPE_CHECKING

import pytest
from hypothesis import HealthCheck, settings

if TYPE_CHECKING:
    from tests.stages.conftest import Built

# A run started in the background by a script (`make test &`: a shell without job control starts
# background commands with SIGINT ignored) would pass SIGINT ignored on to every process the tests
# start, and a build then ignores the Ctrl-C the interrupt tests send it (tests/pipeline/test_shutdown.py,
# test_ray_abort.py, the adversarial script's ctrl-c case), and they fail. The tests run as
# from a terminal, where a command starts with SIGINT at its default. Set here, before xdist starts its
# workers, so they and everything they start inherit it.
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)

# Property tests run a bounded number of examples with a fixed derivation (no example database, no
# wall-clock deadline on a shared 2-core machine), so `make test` stays fast and gives the same result
# on every run. NAVVERSE_HYPOTHESIS=thorough runs many more examples when hunting for a bug.
settings.register_profile(
    "navverse",
    max_examples=60,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile("thorough", parent=settings.get_profile("navverse"), max_examples=2000)
settings.load_profile("thorough" if os.environ.get("NAVVERSE_HYPOTHESIS") == "thorough" else "navverse")


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Put the modules that hold tests marked ``slow`` first, the longest first, keeping every
    module's tests together and in their order.

    ``make test`` gives each of its workers whole modules, one after the other (``--dist loadfile``
    in ``pyproject.toml``): started first, the long modules leave the short ones to even out the
    workers at the end, where one long module started last would keep one worker busy alone. A
    module's length is the sum of the ``seconds`` of its ``slow`` marks (about how long each test
    takes on its own on a 2-core machine, its fixtures included).
    """
    seconds: dict[Path, float] = {}
    for item in items:
        for mark in item.iter_markers("slow"):
            seconds[item.path] = seconds.get(item.path, 0.0) + mark.kwargs.get("seconds", SLOW_SECONDS)
    items.sort(key=lambda item: -seconds.get(item.path, 0.0))  # a stable sort: collection order otherwise


SLOW_SECONDS = 30.0
"""The length of a test marked ``slow`` without its ``seconds``."""


@pytest.fixture(scope="session")
def tiny_build(tmp_path_factory: pytest.TempPathFactory) -> Built:
    """The apartment scenes and the tiny dataset of ``tests/stages/conftest.py``, built once per run:
    in this process, or under ``pytest -n`` by the first worker that needs it (the others wait for it
    and read it where that worker built it).

    Never changed: the fixtures that use it give their tests a copy
    (:func:`tests.stages.conftest.copy_built`), so a module that rebuilds or publishes sees only its
    own changes.
    """
    from pipeline.store import ArtifactStore
    from pipeline.workspace import Workspace
    from tests.stages.conftest import Built, build_tiny

    if "PYTEST_XDIST_WORKER" not in os.environ:
        return build_tiny(tmp_path_factory.mktemp("tiny") / "ws")
    run_dir = tmp_path_factory.getbasetemp().parent  # this run's folder, holding every worker's own
    with open(run_dir / "tiny-build.lock", "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # released when the file closes
        made = run_dir / "tiny-build.pickle"  # (workspace root, build report) of the worker that built it
        if not made.is_file():
            built = build_tiny(tmp_path_factory.mktemp("tiny") / "ws")
            made.write_bytes(pickle.dumps((str(built.workspace.root), built.report)))
            return built
        root, report = pickle.loads(made.read_bytes())
    workspace = Workspace(Path(root))
    return Built(workspace, ArtifactStore(workspace.built_dir), report)
