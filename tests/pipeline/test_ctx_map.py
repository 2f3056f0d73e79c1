"""``ctx.map``: the same results in item order in-process, on a local pool and on Ray; errors name items."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Annotated

import numpy as np
import pytest
from pydantic import Field
from rich.console import Console

from pipeline import Params, StageContext, stage
from pipeline.context import FanOut, MapError, chunk_bounds, run_map
from pipeline.dag import build_graph
from pipeline.executors import InlineExecutor, LocalProcessExecutor
from pipeline.recipes import RecipeLoader
from pipeline.runner import run_build
from pipeline.stage import registered_stages
from pipeline.store import ArtifactStore
from pipeline.workspace import Workspace
from tests.pipeline.conftest import write

ITEMS = list(range(50))


def kernel(seed: int) -> float:
    """A small CPU-bound, order-sensitive function of one item (module level: it pickles by reference)."""
    rng = np.random.default_rng(seed)
    values = rng.random(64 + seed % 7)
    return float(np.cumsum(values * seed)[-1] - seed**0.5)


def fails_on_13(item: int) -> int:
    if item == 13 or item == 40:
        raise ValueError(f"bad item {item}")
    return item * 2


class MapParams(Params):
    count: Annotated[int, Field(ge=1, le=1000)] = 50


@stage(name="cm_map", outputs=["values"])
def cm_map(ctx: StageContext, params: MapParams) -> None:
    """Seeds drawn from the stage's generator, then ``kernel`` over them with ``ctx.map`` (``values.npy``)."""
    seeds = ctx.rng.integers(0, 2**31, size=params.count).tolist()
    np.save(ctx.output / "values.npy", np.array(ctx.map(kernel, seeds, chunksize=4)))
    ctx.record(fanout=ctx.fanout.kind)


EXPECTED = [kernel(i) for i in ITEMS]


def test_chunks_cover_the_items_in_order():
    assert chunk_bounds(50, 2) == [(s, min(s + 7, 50)) for s in range(0, 50, 7)]
    assert chunk_bounds(10, 1, chunksize=4) == [(0, 4), (4, 8), (8, 10)]
    assert chunk_bounds(0, 4) == []
    with pytest.raises(ValueError, match="chunksize"):
        chunk_bounds(5, 1, chunksize=0)


@pytest.mark.parametrize(
    "fanout", [FanOut("inline", 1), FanOut("processes", 1), FanOut("processes", 2)], ids=str
)
def test_local_results_in_item_order(fanout):
    seen: list[tuple[int, int, str]] = []
    results = run_map(kernel, ITEMS, fanout=fanout, progress=lambda d, t, s: seen.append((d, t, s)))
    assert results == EXPECTED  # exactly: floats compared bit for bit
    assert seen[-1] == (50, 50, "map kernel") and [d for d, _, _ in seen] == sorted(d for d, _, _ in seen)


def test_ray_results_equal_local(ray_instance):
    assert run_map(kernel, ITEMS, fanout=FanOut("ray", 2)) == EXPECTED
    assert run_map(kernel, ITEMS, fanout=FanOut("ray", 2), chunksize=1) == EXPECTED


@pytest.mark.parametrize("kind", ["inline", "processes", "ray"])
def test_error_names_the_lowest_failing_item(kind, request):
    if kind == "ray":
        request.getfixturevalue("ray_instance")
    with pytest.raises(
        MapError, match=r"fails_on_13 raised on item 13 of 50: ValueError: bad item 13"
    ) as info:
        run_map(fails_on_13, ITEMS, fanout=FanOut(kind, 2), chunksize=5)
    assert info.value.index == 13


CALLS: list[int] = []


def recorded(item: int) -> int:
    """``3 * item``, noting each call (inline runs only: they share this process's list)."""
    CALLS.append(item)
    return 3 * item


@pytest.mark.parametrize("fanout", [FanOut("inline", 1), FanOut("processes", 2)], ids=str)
def test_saved_results_are_taken_instead_of_made_again(tmp_path, fanout):
    """A map killed part way resumes: each item's result is saved as it is made, and a later run takes
    the saved ones, makes the missing (and unreadable) ones, and returns the same list."""
    saved = tmp_path / "map-1"
    assert run_map(kernel, ITEMS, fanout=fanout, chunksize=4, checkpoints=saved) == EXPECTED
    files = sorted(saved.glob("*.pkl"))
    assert len(files) == len(ITEMS) and not list(saved.glob(".*"))  # no partial file left
    for path in files[:5]:  # as if these items were in flight when the run was killed
        path.unlink()
    files[5].write_bytes(b"torn")
    assert run_map(kernel, ITEMS, fanout=fanout, chunksize=4, checkpoints=saved) == EXPECTED
    assert len(list(saved.glob("*.pkl"))) == len(ITEMS)


def test_only_missing_items_are_made_on_resume(tmp_path):
    saved = tmp_path / "map-1"
    CALLS.clear()
    assert run_map(recorded, list(range(20)), fanout=FanOut("inline", 1), checkpoints=saved) == [
        3 * i for i in range(20)
    ]
    assert sorted(CALLS) == list(range(20))
    for path in sorted(saved.glob("*.pkl"))[:3]:
        path.unlink()
    CALLS.clear()
    assert run_map(recorded, list(range(20)), fanout=FanOut("inline", 1), checkpoints=saved) == [
        3 * i for i in range(20)
    ]
    assert len(CALLS) == 3  # the other 17 were taken from their files
    # another function over the same items, in the same place, gets its own results, not recorded's
    assert run_map(kernel, list(range(20)), fanout=FanOut("inline", 1), checkpoints=saved) == EXPECTED[:20]


def test_a_lambda_is_refused_on_every_executor():
    with pytest.raises(TypeError, match="module-level function"):
        run_map(lambda x: x, ITEMS, fanout=FanOut("inline", 1))


def _build_values(root: Path, factory) -> tuple[np.ndarray, dict]:
    workspace = Workspace(root)
    write(workspace.recipes_dir / "mapped.yaml", "seed: 11\nstages:\n  cm_map: {count: 50}\n")
    targets = RecipeLoader(workspace, stages={"cm_map": registered_stages()["cm_map"]}).load()
    store = ArtifactStore(workspace.built_dir)
    report = run_build(build_graph(targets), store, factory, console=Console(quiet=True))
    assert report.ok, {n: r.error for n, r in report.failed.items()}
    values = store.targets_dir / "mapped" / "values"
    stats = ArtifactStore.read_manifest(values.resolve())["stats"]
    return np.load(values / "values.npy"), stats


def test_stage_map_is_the_same_on_every_executor(tmp_path, ray_instance):
    from pipeline.ray_executor import RayExecutor

    inline, stats_inline = _build_values(tmp_path / "inline", InlineExecutor)
    assert not list((tmp_path / "inline" / "data" / "built").glob("checkpoints/*"))  # removed on commit
    pooled, stats_pool = _build_values(tmp_path / "pool", lambda: LocalProcessExecutor(1, map_workers=2))
    on_ray, stats_ray = _build_values(tmp_path / "ray", lambda: RayExecutor(None, 2))
    assert (stats_inline["fanout"], stats_pool["fanout"], stats_ray["fanout"]) == (
        "inline",
        "processes",
        "ray",
    )
    seeds = np.random.default_rng(0).integers(0, 2**31, size=3)  # sanity: the kernel varies with the seed
    assert len({kernel(int(s)) for s in seeds}) == 3
    assert inline.shape == (50,) and np.unique(inline).size == 50
    assert inline.tobytes() == pooled.tobytes() == on_ray.tobytes()


def test_local_executor_gives_stages_their_share_of_cores():
    for map_workers, expected in ((1, FanOut("inline", 1)), (3, FanOut("processes", 3))):
        executor = LocalProcessExecutor(2, map_workers=map_workers)
        try:
            assert executor.fanout == expected
        finally:
            executor.close()
    executor = LocalProcessExecutor(os.cpu_count() or 1)
    try:
        assert executor.fanout == FanOut("inline", 1)  # one core per stage: no pool
    finally:
        executor.close()
