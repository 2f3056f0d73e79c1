"""The ``navverse`` command. The composition root: the only navverse module that imports
``pipeline`` and ``stages``."""

from __future__ import annotations

import argparse
import shutil
import sys
from collections.abc import Sequence
from pathlib import Path

from rich.console import Console

from navverse.errors import NavverseError, SceneError
from pipeline.errors import PipelineError

STAGES_PACKAGE = "stages"
SCENE_ARTIFACTS = ("scene", "geometry")
"""Artifacts that are scene directories, most complete first: a scene with its navmesh, or the
geometry a scene stage produced before the navmesh is built."""


def _workspace():
    from pipeline.workspace import Workspace

    return Workspace.find()


def _load_targets(workspace, files: Sequence[Path] | None = None):
    from pipeline.recipes import RecipeLoader
    from pipeline.stage import discover

    stages = discover(STAGES_PACKAGE)
    return RecipeLoader(workspace, stages=stages).load(files)


def _graph_for(selectors: Sequence[str]):
    from pipeline.dag import build_graph
    from pipeline.recipes import select_targets
    from pipeline.store import ArtifactStore

    workspace = _workspace()
    targets = _load_targets(workspace)
    chosen = select_targets(targets, selectors)
    graph = build_graph(chosen, universe=targets)
    return workspace, chosen, graph, ArtifactStore(workspace.built_dir)


def cmd_build(args: argparse.Namespace, console: Console) -> int:
    """Build targets (default: all)."""
    from pipeline.executors import make_executor
    from pipeline.runner import describe_plan, plan, run_build

    _, chosen, graph, store = _graph_for(args.targets)
    force = [t.id for t in chosen] if args.force else []
    if args.dry_run:
        describe_plan(graph, plan(graph, store, force=force), console)
        return 0
    report = run_build(graph, store, lambda: make_executor(args.jobs), force=force, console=console)
    return 0 if report.ok else 1


def cmd_status(args: argparse.Namespace, console: Console) -> int:
    """Print fresh / stale / missing per target."""
    from rich.table import Table

    from pipeline.runner import target_status

    _, chosen, graph, store = _graph_for(args.targets)
    statuses = target_status(graph, store)
    colour = {"fresh": "green", "stale": "yellow", "missing": "red"}
    table = Table(box=None, show_edge=False)
    for column in ("target", "status", "recipe"):
        table.add_column(column)
    recipes = {t.id: t.recipe for t in chosen}
    for target_id, status in statuses.items():
        table.add_row(target_id, f"[{colour[status]}]{status}[/]", recipes.get(target_id, "(linked)"))
    console.print(table)
    counts = {s: list(statuses.values()).count(s) for s in colour}
    console.print(", ".join(f"{n} {s}" for s, n in counts.items()))
    return 0


def cmd_clean(args: argparse.Namespace, console: Console) -> int:
    """Remove build outputs: unused artifacts (default) or everything (--all)."""
    from pipeline.store import ArtifactStore

    workspace = _workspace()
    store = ArtifactStore(workspace.built_dir)
    if args.all:
        for child in (store.artifacts_dir, store.targets_dir, store.tmp_dir, store.logs_dir):
            shutil.rmtree(child, ignore_errors=True)
        console.print(f"removed every build output in {workspace.built_dir}")
        return 0
    _, _, graph, store = _graph_for([])
    keep = {
        store.artifact_path(node.stage, out, key)
        for node in graph.nodes.values()
        for out, key in node.artifact_keys.items()
    }
    removed = 0
    if store.artifacts_dir.is_dir():
        for path in sorted(store.artifacts_dir.glob("*/*")):
            if path not in keep:
                shutil.rmtree(path, ignore_errors=True)
                removed += 1
    removed += store.clean_stale_tmp()
    console.print(f"removed {removed} unused artifacts; kept {len(keep)} current ones")
    return 0


def cmd_validate_recipe(args: argparse.Namespace, console: Console) -> int:
    """Validate recipe files (all of them when none is given)."""
    workspace = _workspace()
    files = [Path(f) for f in args.files] or None
    targets = _load_targets(workspace, files)
    from pipeline.dag import build_graph

    build_graph(targets, universe=_load_targets(workspace) if files else targets)
    console.print(f"[green]valid[/]: {len(files) if files else 'all'} recipe file(s), {len(targets)} targets")
    return 0


def cmd_show_scene(args: argparse.Namespace, console: Console) -> int:
    """Draw a built scene's bird's-eye view, with its navmesh when it has one."""
    from navverse.nav.scene_navmesh import load_scene_navmesh, navmesh_overlay
    from navverse.scene import SceneFiles, read_scene, render_bev
    from pipeline.store import ArtifactStore

    workspace = _workspace()
    store = ArtifactStore(workspace.built_dir)
    found = (store.target_output(args.scene_id, artifact) for artifact in SCENE_ARTIFACTS)
    scene_dir = next((path for path in found if path is not None), None)
    if scene_dir is None:
        raise SceneError(
            f"scene {args.scene_id!r} is not built: run 'navverse build {args.scene_id}' "
            "('navverse status' lists the scenes)"
        )
    out = Path(args.output or f"{args.scene_id}-bev.png")
    has_navmesh = SceneFiles(scene_dir).navmesh.is_file()
    overlays = [navmesh_overlay(load_scene_navmesh(scene_dir))] if has_navmesh else []
    render_bev(read_scene(scene_dir), out, meters_per_pixel=args.meters_per_pixel, overlays=overlays)
    console.print(f"wrote {out}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every sub-command."""
    parser = argparse.ArgumentParser(
        prog="navverse",
        description="Build navigation scenes and episode datasets from recipes, and evaluate agents.",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    build = sub.add_parser("build", help="build targets from recipes (default: all)")
    build.add_argument(
        "targets",
        nargs="*",
        metavar="TARGET",
        help="target ids (globs allowed) or recipe paths/folders such as 'scenes/indoor'",
    )
    build.add_argument(
        "--jobs",
        "-j",
        type=int,
        default=None,
        help="parallel processes (default: number of cores; 0 runs in this process)",
    )
    build.add_argument("--force", action="store_true", help="rebuild the selected targets even if cached")
    build.add_argument("--dry-run", action="store_true", help="print the build graph and what would run")
    build.set_defaults(func=cmd_build)

    status = sub.add_parser("status", help="fresh / stale / missing per target")
    status.add_argument("targets", nargs="*", metavar="TARGET")
    status.set_defaults(func=cmd_status)

    clean = sub.add_parser("clean", help="remove unused build outputs (or all with --all)")
    clean.add_argument("--all", action="store_true", help="remove every build output")
    clean.set_defaults(func=cmd_clean)

    validate = sub.add_parser("validate", help="check input files without building")
    vsub = validate.add_subparsers(dest="what", required=True, metavar="WHAT")
    recipe = vsub.add_parser("recipe", help="validate recipe files (all when none given)")
    recipe.add_argument("files", nargs="*", metavar="FILE")
    recipe.set_defaults(func=cmd_validate_recipe)

    show = sub.add_parser("show", help="draw or print what was built")
    ssub = show.add_subparsers(dest="what", required=True, metavar="WHAT")
    scene = ssub.add_parser("scene", help="bird's-eye-view picture of a built scene")
    scene.add_argument("scene_id")
    scene.add_argument("-o", "--output", help="PNG path (default: <scene_id>-bev.png)")
    scene.add_argument("--meters-per-pixel", type=float, default=None)
    scene.set_defaults(func=cmd_show_scene)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``navverse`` command; returns the exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    console = Console(stderr=False)
    try:
        return int(args.func(args, console))
    except (NavverseError, PipelineError) as exc:
        Console(stderr=True).print(
            f"error: {exc}", style="red", highlight=False, markup=False, soft_wrap=True
        )
        return 1
    except KeyboardInterrupt:
        Console(stderr=True).print("interrupted")
        return 130


if __name__ == "__main__":
    sys.exit(main())
