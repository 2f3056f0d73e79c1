"""The ``navverse`` command. The composition root: the only navverse module that imports
``pipeline`` and ``stages``."""

from __future__ import annotations

import argparse
import os
import shutil
import sys
from collections.abc import Sequence
from pathlib import Path

from rich.console import Console

from navverse.errors import NavverseError
from pipeline.errors import PipelineError

STAGES_PACKAGE = "stages"


def _workspace():
    from pipeline.workspace import Workspace

    return Workspace.find()


def _load_targets(workspace, files: Sequence[Path] | None = None):
    from pipeline.recipes import RecipeLoader
    from pipeline.stage import discover

    stages = discover(STAGES_PACKAGE)
    return RecipeLoader(workspace, stages=stages).load(files)


def _graph_for(selectors: Sequence[str], *, every_target: bool = False):
    from pipeline.dag import build_graph
    from pipeline.recipes import select_targets
    from pipeline.store import ArtifactStore

    workspace = _workspace()
    targets = _load_targets(workspace)
    chosen = list(targets) if every_target else select_targets(targets, selectors)
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
    if not report.ok:
        return 1
    _publish_datasets(chosen, store, console)
    return 0


def _publish_datasets(targets, store, console: Console) -> None:
    """Copy the built dataset versions into ``episodes/`` (a published version never changes)."""
    from navverse.dataset import built_version, publish

    episodes_dir = _workspace().root / "episodes"
    for target in targets:
        if not any("dataset" in call.spec.outputs for call in target.stages):
            continue
        built = store.target_output(target.id, "dataset")
        if built is None:
            continue
        path, written = publish(built_version(built), episodes_dir)
        shown = path.relative_to(episodes_dir.parent)
        console.print(f"{'published' if written else 'up to date'}: {shown}")


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
    _, _, graph, store = _graph_for([], every_target=True)  # manual targets' artifacts are kept too
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
    from navverse.scene.locate import built_scene_dir

    scene_dir = built_scene_dir(_workspace().built_dir, args.scene_id)
    out = Path(args.output or f"{args.scene_id}-bev.png")
    has_navmesh = SceneFiles(scene_dir).navmesh.is_file()
    overlays = [navmesh_overlay(load_scene_navmesh(scene_dir))] if has_navmesh else []
    render_bev(read_scene(scene_dir), out, meters_per_pixel=args.meters_per_pixel, overlays=overlays)
    console.print(f"wrote {out}")
    return 0


def cmd_show_dataset(args: argparse.Namespace, console: Console) -> int:
    """Print a dataset's episode counts and goal categories."""
    from navverse.dataset import Dataset
    from navverse.episodes.inspect import category_table, counts_table

    dataset = Dataset(args.dataset)
    manifest = dataset.manifest
    console.print(counts_table(dataset))
    console.print(category_table(dataset, top=args.top))
    for task, (low, high) in manifest.difficulty_thresholds.items():
        console.print(f"{task}: easy < {low:.2f} m <= medium < {high:.2f} m <= hard (geodesic length)")
    splits = "; ".join(f"{name}: {', '.join(scenes)}" for name, scenes in manifest.splits.items())
    console.print(f"splits (scene-disjoint): {splits}", highlight=False)
    return 0


def cmd_show_episode(args: argparse.Namespace, console: Console) -> int:
    """Draw one episode on its scene's bird's-eye view."""
    from navverse.dataset import Dataset
    from navverse.episodes.inspect import draw_episode
    from navverse.scene.locate import built_scene_dir

    dataset = Dataset(args.dataset)
    episode = dataset.episode(args.episode_id)
    scene_dir = built_scene_dir(_workspace().built_dir, episode.scene_id)
    out = draw_episode(
        scene_dir, episode, dataset.rollout(episode), Path(args.output or f"{args.episode_id}.png")
    )
    text = episode.instruction.instruction_text if episode.instruction else episode.goal_category
    console.print(f"{episode.episode_id} ({episode.task}, {episode.info.geodesic_distance:.1f} m): {text}")
    console.print(f"wrote {out}")
    return 0


def cmd_validate_dataset(args: argparse.Namespace, console: Console) -> int:
    """Check a dataset: format, checksums, bounds, and (with --replay) its oracle rollouts under physics."""
    import numpy as np
    from rich.progress import Progress

    from navverse.dataset import Dataset, DatasetError
    from navverse.episodes.inspect import check_bounds, replay
    from navverse.scene.directory import scene_hash
    from navverse.scene.locate import built_scene_dirs

    dataset = Dataset(args.dataset)
    bad = dataset.verify_checksums()
    if bad:
        raise DatasetError(f"{dataset.root}: files differ from the manifest's checksums: {', '.join(bad)}")
    episodes = list(dataset.episodes())
    violations = [(e.episode_id, r) for e in episodes if (r := check_bounds(e)) is not None]
    console.print(
        f"{dataset.root}: format {dataset.manifest.format_version}, {len(episodes)} episodes, checksums ok"
    )
    console.print(
        f"distance and duration bounds: {len(episodes) - len(violations)} of {len(episodes)} keep them"
    )
    for episode_id, reason in violations[:10]:
        console.print(f"  {episode_id}: {reason}", highlight=False)
    failures = bool(violations)
    if args.replay:
        chosen = episodes
        if args.replay != "all":
            count = int(args.replay)
            rng = np.random.default_rng(args.seed)
            chosen = [
                episodes[i]
                for i in sorted(rng.choice(len(episodes), min(count, len(episodes)), replace=False))
            ]
        scene_dirs = built_scene_dirs(chosen, built_dir=_workspace().built_dir)
        changed = [s for s, d in scene_dirs.items() if scene_hash(d) != dataset.manifest.scene_hashes.get(s)]
        if changed:
            console.print(
                f"[yellow]warning:[/] built scenes differ from the dataset's: {', '.join(changed)} "
                "(rebuilt since packaging?); replaying in the scenes as built now"
            )
        with Progress(console=console, transient=True) as bar:
            task = bar.add_task("replaying (scenes)", total=len(scene_dirs))
            report = replay(
                chosen,
                scene_dirs,
                embodiment=dataset.manifest.embodiment,
                jobs=args.jobs,
                progress=lambda done, total: bar.update(task, completed=done),
            )
        console.print(f"replayed oracle rollouts: {report.reached} of {report.replayed} reach a goal")
        for episode_id, reason in report.failures[:10]:
            console.print(f"  {episode_id}: {reason}", highlight=False)
        failures = failures or bool(report.failures)
    return 1 if failures else 0


def _split_of(dataset, split: str) -> list[str]:
    """The episode ids of a split, or a DatasetError naming the splits there are."""
    from navverse.dataset import DatasetError

    if split not in dataset.splits:
        raise DatasetError(f"{dataset.root} has no split {split!r}; it has: {', '.join(dataset.splits)}")
    return [e.episode_id for e in dataset.episodes(split=split)]


def cmd_validate_submission(args: argparse.Namespace, console: Console) -> int:
    """Report every problem of a submission against a dataset split."""
    from navverse.dataset import Dataset
    from navverse.eval.submission import read_submission

    dataset = Dataset(args.dataset)
    ids = _split_of(dataset, args.split)
    submission = read_submission(args.submission, episode_ids=ids)
    missing = sorted(set(ids) - set(submission.records) - {p.episode_id for p in submission.problems})
    for problem in submission.problems:
        console.print(str(problem), highlight=False, markup=False)
    for episode_id in missing[:20]:
        console.print(f"missing: {episode_id}", highlight=False, markup=False)
    if len(missing) > 20:
        console.print(f"missing: ... and {len(missing) - 20} more episodes")
    console.print(
        f"{args.submission}: {len(submission.records)} of {len(ids)} episodes of {args.split} valid; "
        f"{len(submission.problems)} problems, {len(missing)} missing"
    )
    return 1 if submission.problems or missing else 0


def cmd_eval(args: argparse.Namespace, console: Console) -> int:
    """Score a submission: metrics.json, tables (md, csv), report.html, and the headline table."""
    from rich.progress import Progress
    from rich.table import Table

    from navverse import __version__
    from navverse.dataset import Dataset
    from navverse.eval.report import write_report
    from navverse.eval.scoring import score
    from navverse.eval.submission import read_submission
    from navverse.eval.tables import table_rows, write_outputs
    from navverse.scene.locate import built_scene_dirs

    dataset = Dataset(args.dataset)
    ids = _split_of(dataset, args.split)
    submission = read_submission(args.submission, episode_ids=ids)
    scene_dirs = built_scene_dirs(dataset.episodes(split=args.split), built_dir=_workspace().built_dir)
    with Progress(console=console, transient=True) as bar:
        task = bar.add_task("scoring", total=len(submission.records) or 1)
        result = score(
            dataset,
            submission,
            split=args.split,
            scene_dirs=scene_dirs,
            embodiment=args.embodiment,
            progress=lambda done, total: bar.update(task, completed=done),
        )
    meta = {
        "dataset": str(dataset.root),
        "dataset_version": dataset.manifest.version,
        "split": args.split,
        "submission": str(args.submission),
        "embodiment": args.embodiment or dataset.manifest.embodiment,
        "toolkit_version": __version__,
    }
    out = write_outputs(result, args.out, meta=meta)
    with Progress(console=console, transient=True) as bar:
        task = bar.add_task("report", total=len(result.episodes) or 1)
        report = write_report(
            result,
            dataset=dataset,
            submission=submission,
            scene_dirs=scene_dirs,
            out_dir=Path(out),
            embodiment=args.embodiment,
            progress=lambda done, total: bar.update(task, completed=done),
        )
    if submission.problems:
        console.print(f"[yellow]{len(submission.problems)} submission problems[/] (listed in metrics.json):")
        for problem in submission.problems[:10]:
            console.print(f"  {problem}", highlight=False, markup=False)
    invalid = [row["episode_id"] for row in result.episodes if row["label"] == "invalid"]
    if invalid:
        console.print(
            f"[yellow]{len(invalid)} episodes have no valid trajectory, scored as failures:[/] "
            + ", ".join(invalid[:10])
            + (f" ... ({len(invalid) - 10} more)" if len(invalid) > 10 else ""),
            highlight=False,
        )
    header, rows = table_rows(result, "task_scene")
    table = Table(title=f"{dataset.manifest.name} v{dataset.manifest.version} / {args.split}")
    for column in header:
        table.add_column(column, justify="left" if column == header[0] else "right")
    for row in rows:
        table.add_row(*row)
    console.print(table)
    console.print(f"wrote {out}/metrics.json, tables.md, *.csv, {report.name}", highlight=False)
    return 0


def cmd_run_agent(args: argparse.Namespace, console: Console) -> int:
    """Run an agent online over a split and write its submission."""
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

    from navverse.dataset import Dataset
    from navverse.eval.runner import run_agent
    from navverse.scene.locate import built_scene_dirs

    dataset = Dataset(args.dataset)
    _split_of(dataset, args.split)
    embodiment = args.embodiment or dataset.manifest.embodiment
    scene_dirs = built_scene_dirs(dataset.episodes(split=args.split), built_dir=_workspace().built_dir)
    jobs = args.jobs if args.jobs is not None else (os.cpu_count() or 1)
    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeRemainingColumn())
    with Progress(*columns, console=console, transient=True) as bar:
        task = bar.add_task(f"{args.agent} on {args.split}", total=None)
        summary = run_agent(
            dataset,
            agent=args.agent,
            split=args.split,
            embodiment=embodiment,
            scene_dirs=scene_dirs,
            out=args.out,
            jobs=jobs,
            limit=args.limit,
            seed=args.seed,
            max_steps=args.max_steps,
            terrain_friction=args.friction,
            progress=lambda done, total: bar.update(task, completed=done, total=total),
        )
    ended = ", ".join(f"{label} {count}" for label, count in sorted(summary.terminations.items()))
    resumed = f" ({summary.resumed} resumed from an interrupted run)" if summary.resumed else ""
    console.print(
        f"{args.agent} ({embodiment}): {summary.episodes} episodes{resumed} in {summary.seconds:.0f} s; "
        f"ended: {ended}",
        highlight=False,
        markup=False,
    )
    console.print(
        f"wrote {summary.out}; score it with: navverse eval --dataset {args.dataset} "
        f"--submission {summary.out} --split {args.split}",
        highlight=False,
        markup=False,
    )
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
    vdataset = vsub.add_parser(
        "dataset", help="check a dataset version (format, checksums, bounds, rollouts)"
    )
    vdataset.add_argument("dataset", help="episodes/<name>/v<version> (or episodes/<name>: the newest)")
    vdataset.add_argument(
        "--replay", metavar="N|all", help="run the oracle rollouts of N sampled episodes (or all) again"
    )
    vdataset.add_argument("--seed", type=int, default=0, help="which episodes --replay N samples")
    vdataset.add_argument("--jobs", "-j", type=int, default=None, help="processes for --replay")
    vdataset.set_defaults(func=cmd_validate_dataset)
    vsubmission = vsub.add_parser(
        "submission", help="report every problem of a submission, with line numbers"
    )
    vsubmission.add_argument("submission", help="JSONL file (optionally .gz), one episode per line")
    vsubmission.add_argument("--dataset", required=True, help="episodes/<name>/v<version>")
    vsubmission.add_argument("--split", default="eval", help="the split it answers (default: eval)")
    vsubmission.set_defaults(func=cmd_validate_submission)

    evaluate = sub.add_parser("eval", help="score a submission against a dataset split")
    evaluate.add_argument("--dataset", required=True, help="episodes/<name>/v<version>")
    evaluate.add_argument("--submission", required=True, help="JSONL file (optionally .gz)")
    evaluate.add_argument("--split", default="eval", help="split scored (default: eval)")
    evaluate.add_argument("--embodiment", default=None, help="robot scored (default: the dataset's)")
    evaluate.add_argument("--out", default="eval-out", help="output folder (default: eval-out)")
    evaluate.set_defaults(func=cmd_eval)

    run = sub.add_parser("run-agent", help="run an agent over a dataset split and write its submission")
    run.add_argument("--dataset", required=True, help="episodes/<name>/v<version>")
    run.add_argument("--split", default="eval", help="split run (default: eval)")
    run.add_argument(
        "--agent",
        required=True,
        help="oracle, gt_goal, random, frontier, or your own 'module:Class' / 'path/to/file.py:Class'",
    )
    run.add_argument("--embodiment", default=None, help="spot or turtlebot (default: the dataset's)")
    run.add_argument("--out", required=True, help="submission to write (.jsonl or .jsonl.gz)")
    run.add_argument("--jobs", "-j", type=int, default=None, help="processes (default: cores; 0: in process)")
    run.add_argument("--limit", type=int, default=None, help="run only K episodes, spread over the split")
    run.add_argument("--seed", type=int, default=0, help="seed of the agent's per-episode seeds")
    run.add_argument("--max-steps", type=int, default=None, help="cut an episode after this many actions")
    run.add_argument(
        "--friction", type=float, default=None, help="friction of every terrain class (a diagnostic)"
    )
    run.set_defaults(func=cmd_run_agent)

    show = sub.add_parser("show", help="draw or print what was built")
    ssub = show.add_subparsers(dest="what", required=True, metavar="WHAT")
    scene = ssub.add_parser("scene", help="bird's-eye-view picture of a built scene")
    scene.add_argument("scene_id")
    scene.add_argument("-o", "--output", help="PNG path (default: <scene_id>-bev.png)")
    scene.add_argument("--meters-per-pixel", type=float, default=None)
    scene.set_defaults(func=cmd_show_scene)
    dataset = ssub.add_parser("dataset", help="episode counts and goal categories of a dataset")
    dataset.add_argument("dataset", help="episodes/<name>/v<version> (or episodes/<name>: the newest)")
    dataset.add_argument("--top", type=int, default=25, help="goal categories listed")
    dataset.set_defaults(func=cmd_show_dataset)
    episode = ssub.add_parser("episode", help="draw an episode on its scene's bird's-eye view")
    episode.add_argument("dataset")
    episode.add_argument("episode_id")
    episode.add_argument("-o", "--output", help="PNG path (default: <episode_id>.png)")
    episode.set_defaults(func=cmd_show_episode)
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
