"""The build summary says what each stage run made (the figures its stage declares, from the stats
it recorded; read from the manifest of a reused artifact), and the engine's tables are never cut:
on a wide console that is not a terminal every target id and stage name is whole on its line."""

from __future__ import annotations

import io
import re

import pytest
from rich.console import Console

from pipeline import Params, StageContext, stage
from pipeline.dag import build_graph
from pipeline.executors import InlineExecutor
from pipeline.recipes import RecipeLoader
from pipeline.runner import describe_plan, plan, run_build, run_made, runs_table
from pipeline.stage import get_stage
from pipeline.store import ArtifactStore
from pipeline.summary import describe_stats
from tests.pipeline.conftest import write

LONG_STAGE = "ex_counted_populated_geometry_of_a_rather_long_name"
LONG_TARGET = "a-target-whose-id-is-far-longer-than-eighty-columns-would-allow-for-a-table-cell"
MADE = "kept 23, dropped 3 (not a closed ring 2, degenerate geometry 1), area m2 1235"
COUNTS = {"not a closed ring": 2, "degenerate geometry": 1}


class CountedParams(Params):
    pass


@stage(
    name=LONG_STAGE,
    inputs=["numbers"],
    outputs=["counted"],
    summary={"kept": "kept", "dropped": "dropped", "area m2": "area.total_m2"},
)
def ex_counted(ctx: StageContext, params: CountedParams) -> None:
    """Counts of what was kept and dropped, by reason (``counted.txt``)."""
    (ctx.output / "counted.txt").write_text("counted\n")
    ctx.record(kept=23, dropped=COUNTS, area={"total_m2": 1234.567})


def _graph(workspace, stages):
    return build_graph(RecipeLoader(workspace, stages=stages).load())


def _long_workspace(workspace, stages):
    """A target of a long id whose stages are ``ex_numbers`` and the stage of a long name."""
    recipe = f"stages: {{ex_numbers: {{count: 3}}, {LONG_STAGE}: {{}}}}\n"
    write(workspace.recipes_dir / f"{LONG_TARGET}.yaml", recipe)
    return {**stages, LONG_STAGE: get_stage(LONG_STAGE)}


def test_stats_are_shown_by_kind():
    stats = {
        "buildings": 23,
        "dropped": {"not a closed ring": 2, "degenerate geometry": 1, "invalid polygon": 3},
        "none_dropped": {},
        "road_km": 2.5854,
        "area_m2": 140643.587,
        "rate": 0.9565,
        "preset": "outdoor",
        "parts": [{"name": "a"}, {"name": "b"}],
        "counts": {
            "train": {"objnav": {"indoor": 10}, "vln": {"indoor": 5}},
            "eval": {"objnav": {"i2o": 20}},
        },
        "objects": {f"category_{i}": i + 1 for i in range(8)},
        "replaced": {"building": 227, "map_id": "building-227", "osm": None},
        "nested": {"deeper": {"placed": 6}},
    }
    fields = [(key, key) for key in stats] + [("placed", "nested.deeper.placed"), ("absent", "no.such.key")]
    line = describe_stats(stats, fields)
    assert line.split(", placed")[0] == (
        "buildings 23, dropped 6 (invalid polygon 3, not a closed ring 2, degenerate geometry 1), "
        "none_dropped 0, road_km 2.59, area_m2 140644, rate 0.957, preset outdoor, parts 2, "
        "counts 35 (eval 20, train 15), "
        "objects 36 (category_7 8, category_6 7, category_5 6, category_4 5, +4 more), "
        "replaced (building 227, map_id building-227), "
        "nested 6 (deeper 6)"
    )
    assert line.endswith(", placed 6")  # a dotted path reaches into nested stats; a missing key is left out


def test_a_summary_declaration_names_stats_keys_with_or_without_labels():
    def fn(ctx: StageContext, params: CountedParams) -> None:
        """Nothing."""

    stage(name="ex_declared_keys", outputs=["x"], summary=("kept", "dropped"))(fn)
    stage(name="ex_declared_labels", outputs=["x"], summary={"kept buildings": "kept"})(fn)
    assert get_stage("ex_declared_keys").summary == (("kept", "kept"), ("dropped", "dropped"))
    assert get_stage("ex_declared_labels").summary == (("kept buildings", "kept"),)
    for bad in ("kept", {"": "kept"}, {"kept": ""}, {"kept": "a..b"}):
        with pytest.raises(TypeError, match="summary"):
            stage(name="ex_declared_bad", outputs=["x"], summary=bad)(fn)


def test_the_summary_says_what_each_run_made_built_or_reused(workspace, stages):
    stages = _long_workspace(workspace, stages)
    graph = _graph(workspace, stages)
    store = ArtifactStore(workspace.built_dir)
    first = run_build(graph, store, InlineExecutor, console=Console(quiet=True))
    assert first.ok
    long_run = f"{LONG_TARGET}:{LONG_STAGE}"
    assert run_made(graph.nodes[long_run], store, first.built[long_run]) == MADE
    assert run_made(graph.nodes["beta:ex_sum"], store, first.built["beta:ex_sum"]) == ""  # declares nothing

    beta = "extends: base\nseed: 7\nstages: {ex_sum: {offset: 9}}\n"
    write(workspace.recipes_dir / "group" / "beta.yaml", beta)
    graph = _graph(workspace, stages)
    console = Console(file=io.StringIO(), width=1000, force_terminal=False)
    second = run_build(graph, store, InlineExecutor, console=console)
    assert sorted(second.built) == ["all:ex_gather", "beta:ex_sum"]
    output = console.file.getvalue()
    # the reused runs are described from their artifacts' manifests
    assert re.search(rf"^{LONG_TARGET} +{LONG_STAGE} +cached +{re.escape(MADE)} *$", output, re.M)
    assert re.search(rf"^{LONG_TARGET} +ex_numbers +cached +numbers 3 *$", output, re.M)
    assert re.search(r"^beta +ex_numbers +cached +numbers 4 *$", output, re.M)
    assert re.search(r"^beta +ex_sum +\d+\.\d s *$", output, re.M)
    table = output[output.index(_header(output)) :].splitlines()[1 : 1 + len(graph.nodes)]
    assert [line.split()[:2] for line in table] == [  # by target, then in execution order
        [LONG_TARGET, "ex_numbers"],
        [LONG_TARGET, LONG_STAGE],
        ["all", "ex_gather"],
        *([target, name] for target in ("alpha-s0", "alpha-s1", "beta") for name in ("ex_numbers", "ex_sum")),
    ]


def _header(output: str) -> str:
    return next(line for line in output.splitlines() if re.match(r"^target +stage +time +made", line))


def test_the_plan_and_the_summary_are_whole_on_a_wide_console_that_is_not_a_terminal(workspace, stages):
    stages = _long_workspace(workspace, stages)
    graph = _graph(workspace, stages)
    store = ArtifactStore(workspace.built_dir)
    console = Console(file=io.StringIO(), width=1000, force_terminal=False)
    describe_plan(graph, plan(graph, store), console)
    run_build(graph, store, InlineExecutor, console=console)
    output = console.file.getvalue()
    assert "…" not in output
    plan_rows = [line for line in output.splitlines() if re.match(r"^\d+ ", line)]
    assert len(plan_rows) == len(graph.nodes)  # one line each: nothing wrapped
    row = rf"^\d+ +{LONG_TARGET} +{LONG_STAGE} +numbers<-self +counted +build "
    assert any(re.match(row, line) for line in plan_rows)
    summary_rows = [line for line in output.splitlines() if line.startswith(LONG_TARGET)]
    assert [row.split()[1] for row in summary_rows] == ["ex_numbers", LONG_STAGE]
    assert summary_rows[1].rstrip().endswith(MADE)


def test_on_a_narrow_terminal_the_tables_fold_rather_than_cut(workspace, stages):
    stages = _long_workspace(workspace, stages)
    graph = _graph(workspace, stages)
    store = ArtifactStore(workspace.built_dir)
    report = run_build(graph, store, InlineExecutor, console=Console(quiet=True))
    for table in ("plan", "summary"):
        console = Console(file=io.StringIO(), width=60, force_terminal=True, color_system=None)
        if table == "plan":
            describe_plan(graph, plan(graph, store), console)
        else:
            console.print(runs_table(graph, store, report))
        lines = console.file.getvalue().splitlines()
        assert "…" not in "".join(lines)
        header = next(i for i, line in enumerate(lines) if re.search(r"target +stage", line))
        following = "reads" if table == "plan" else "time"
        assert "".join(_column(lines, header, "target", "stage")).count(LONG_TARGET) == 2
        assert LONG_STAGE in "".join(_column(lines, header, "stage", following))


def _column(lines: list[str], header: int, name: str, following: str) -> list[str]:
    """The cells of the column ``name`` of the table whose header is ``lines[header]``, line by line."""
    start, end = lines[header].index(name), lines[header].index(following)
    return [line[start:end].strip() for line in lines[header + 1 :]]


def test_a_failed_run_and_those_it_stops_are_in_the_summary_without_figures(workspace, stages):
    write(
        workspace.recipes_dir / "group" / "beta.yaml",
        "extends: base\nseed: 7\nstages: {ex_sum: {fail: true}}\n",
    )
    graph = _graph(workspace, stages)
    console = Console(file=io.StringIO(), width=1000, force_terminal=False)
    report = run_build(graph, ArtifactStore(workspace.built_dir), InlineExecutor, console=console)
    assert list(report.failed) == ["beta:ex_sum"] and list(report.skipped) == ["all:ex_gather"]
    output = console.file.getvalue()
    assert re.search(r"^beta +ex_sum +failed *$", output, re.M)
    assert re.search(r"^all +ex_gather +skipped *$", output, re.M)
    assert re.search(r"^beta +ex_numbers +\d+\.\d s +numbers 4 *$", output, re.M)
    assert "FAILED beta:ex_sum: ValueError: asked to fail" in output
