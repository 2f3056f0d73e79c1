"""The ``navverse`` command. The composition root: the only navverse module that imports
``pipeline`` and ``stages``.

It holds the argument parser, :func:`main` and the build commands (build, status, clean, validate
recipe); the data and evaluation commands are in :mod:`navverse.cli_data`, given the build store
(``data/built``) of the workspace here when they need built scenes.
"""

from __future__ import annotations

import argparse
import errno
import shutil
import signal
import sys
import textwrap
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from functools import partial
from pathlib import Path

from rich.console import Console

from navverse import cli_data, cli_list
from navverse.errors import NavverseError
from pipeline.errors import PipelineError

STAGES_PACKAGE = "stages"


def _workspace(root: Path | None = None):
    """The workspace at ``root``, else the one found from here (or ``$NAVVERSE_ROOT``)."""
    from pipeline.workspace import Workspace

    return Workspace(root=Path(root).resolve()) if root is not None else Workspace.find()


def workspace_built_dir(root: Path | None = None) -> Path:
    """The build store of the workspace (``data/built``): at ``root``, else the one found from here.

    Raises
    ------
    NavverseError
        If there is no workspace here (the engine's error, as a navverse one: the data commands then
        name it as the reason the build store was not searched).
    """
    try:
        return _workspace(root).built_dir
    except PipelineError as exc:
        raise NavverseError(str(exc)) from None


def _loader(workspace):
    from pipeline.recipes import RecipeLoader
    from pipeline.stage import discover

    return RecipeLoader(workspace, stages=discover(STAGES_PACKAGE))


def _warn(warnings: Sequence[str]) -> None:
    console = Console(stderr=True)
    for text in warnings:
        console.print(f"warning: {text}", style="yellow", highlight=False, markup=False, soft_wrap=True)


def _graph_for(
    selectors: Sequence[str],
    *,
    every_target: bool = False,
    root: Path | None = None,
    extra_files: Sequence[Path] = (),
):
    """The selected targets and their build graph (recipes of the workspace at ``root``, or found from
    here, and ``extra_files``).

    Recipe files with problems do not block a selection that does not need them: their targets are
    left out, with a warning per file (see :func:`pipeline.selection.select_loaded`).
    """
    from pipeline.selection import select_loaded
    from pipeline.store import ArtifactStore

    workspace = _workspace(root)
    loader = _loader(workspace)
    recipes = loader.load_all([*loader.recipe_files(), *extra_files] if extra_files else None)
    if every_target and recipes.broken:
        raise recipes.error()
    chosen = list(recipes.targets) if every_target else select_loaded(recipes, selectors)
    graph = _graph_over(chosen, recipes, selectors=selectors)
    return workspace, chosen, graph, ArtifactStore(workspace.built_dir)


def _graph_over(chosen, recipes, *, selectors: Sequence[str]):
    """The graph of ``chosen``, linking to the targets of ``recipes``; warns of its broken files.

    A broken file that a ``links`` glob of the graph might match is an error: the link would
    silently read fewer targets.
    """
    from pipeline.dag import build_graph
    from pipeline.errors import DagError
    from pipeline.selection import linked_broken, skipped_warnings

    try:
        graph = build_graph(chosen, universe=recipes.targets)
    except DagError as exc:
        raise DagError(f"{exc}\n{recipes.skipped_note()}" if recipes.broken else str(exc)) from None
    needed = linked_broken(recipes, (node.target for node in graph.nodes.values()))
    if needed:
        raise recipes.error(needed)
    _warn(skipped_warnings(recipes, selectors=selectors))
    return graph


def cmd_build(args: argparse.Namespace, console: Console) -> int:
    """Build targets (default: all), holding the workspace lock; exit 1 if a stage failed."""

    from pipeline.executors import make_executor
    from pipeline.runner import describe_plan, find_corrupt, plan, print_corrupt

    if args.address is not None and args.executor != "ray":
        raise PipelineError("--address names a Ray cluster: use it with --executor ray")
    _, chosen, graph, store = _graph_for(args.targets)
    force = [t.id for t in chosen] if args.force else []
    verify = "hash" if args.verify else "size"
    if args.dry_run:
        forced = {n for n, node in graph.nodes.items() if node.target.id in force}
        corrupt = find_corrupt(graph, store, level=verify, skip=forced)
        print_corrupt(corrupt, store, console, action="would rebuild")
        describe_plan(graph, plan(graph, store, force=force, corrupt=corrupt), console)
        return 0
    executor = partial(make_executor, args.jobs, kind=args.executor, address=args.address)
    report = _run_locked(graph, store, executor, force=force, verify=verify, wait=not args.no_wait,
                         console=console, then=lambda: _publish_datasets(chosen, store, console))  # fmt: skip
    return 0 if report.ok else 1


def _run_locked(graph, store, executor, *, force, verify, wait: bool, console: Console, then=None):
    """Run a build graph holding the workspace lock, without logging tracebacks; ``then()`` after a
    build that succeeded, still under the lock. The engine's report."""
    import logging

    from pipeline.runner import run_build

    raise_exceptions, logging.raiseExceptions = logging.raiseExceptions, False  # no logging tracebacks
    try:
        with _locked(store, wait=wait):
            report = run_build(graph, store, executor, force=force, verify=verify, console=console)
            if report.ok and then is not None:
                then()
    finally:
        logging.raiseExceptions = raise_exceptions
    return report


def build_targets(
    selectors: Sequence[str],
    *,
    root: Path | None = None,
    extra_files: Sequence[Path] = (),
    jobs: int | None = None,
    force: bool = False,
    console: Console,
) -> tuple[dict[str, dict[str, Path]], object]:
    """Build the selected targets as ``navverse build`` does, for :func:`navverse.api.build`: their
    outputs ``{target: {artifact: directory}}`` and the engine's report.

    Raises
    ------
    NavverseError
        The engine's error (a recipe problem, an unknown target), as a navverse one.
    """
    from pipeline.executors import make_executor

    try:
        _, chosen, graph, store = _graph_for(selectors, root=root, extra_files=extra_files)
        force_ids = [t.id for t in chosen] if force else []
        report = _run_locked(graph, store, partial(make_executor, jobs), force=force_ids, verify="size",
                             wait=True, console=console)  # fmt: skip
    except PipelineError as exc:
        raise NavverseError(str(exc)) from None
    outputs = {
        t.id: {out: path for call in t.stages for out in call.spec.outputs
               if (path := store.target_output(t.id, out)) is not None}
        for t in chosen
    }  # fmt: skip
    return outputs, report


@contextmanager
def _locked(store, *, wait: bool) -> Iterator[None]:
    """Hold the workspace lock (SIGTERM interrupting like Ctrl-C), saying so when another holds it."""
    from pipeline.lock import workspace_lock
    from pipeline.runner import sigterm_interrupts

    def waiting(holder: str) -> None:
        Console(stderr=True).print(
            f"{holder} holds the workspace; waiting… — Ctrl-C to stop", highlight=False
        )

    with sigterm_interrupts(), workspace_lock(store.lock_path, wait=wait, on_wait=waiting):
        yield


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
    """Print fresh / stale / missing / corrupt per target; exit 1 if an artifact is corrupt.

    The files of current artifacts are checked by size, with ``--verify`` by sha256 too. Takes no
    lock: with a build running, the statuses are those of the moment (a note says so).
    """
    from rich.table import Table

    from pipeline.lock import running_build
    from pipeline.runner import find_corrupt, print_corrupt, target_status

    _, chosen, graph, store = _graph_for(args.targets)
    corrupt = find_corrupt(graph, store, level="hash" if args.verify else "size")
    statuses = target_status(graph, store, corrupt=corrupt)
    colour = {"fresh": "green", "stale": "yellow", "missing": "red", "corrupt": "red"}
    table = Table(box=None, show_edge=False)
    for column in ("target", "status", "recipe"):
        table.add_column(column)
    recipes = {t.id: t.recipe for t in chosen}
    for target_id, status in statuses.items():
        table.add_row(target_id, f"[{colour[status]}]{status}[/]", recipes.get(target_id, "(linked)"))
    console.print(table)
    counts = {s: list(statuses.values()).count(s) for s in colour}
    console.print(", ".join(f"{n} {s}" for s, n in counts.items() if n or s != "corrupt"))
    print_corrupt(corrupt, store, console)
    if corrupt:
        console.print("run `navverse build` to rebuild the corrupt artifacts", highlight=False)
    running = running_build(store.lock_path)
    if running:
        console.print(
            f"note: {running} is running in this workspace; these statuses may change", soft_wrap=True
        )
    return 1 if corrupt else 0


def cmd_clean(args: argparse.Namespace, console: Console) -> int:
    """Remove build outputs: unused artifacts (default) or everything (--all), holding the lock."""
    from pipeline.store import ArtifactStore

    workspace = _workspace()
    store = ArtifactStore(workspace.built_dir)
    if args.all:
        with _locked(store, wait=True):
            for child in (store.artifacts_dir, store.targets_dir, store.tmp_dir, store.logs_dir):
                shutil.rmtree(child, ignore_errors=True)
        console.print(f"removed every build output in {workspace.built_dir}")
        return 0
    _, _, graph, store = _graph_for([], every_target=True)  # manual targets' artifacts are kept too
    with _locked(store, wait=True):
        return _clean_unused(graph, store, console)


def _clean_unused(graph, store, console: Console) -> int:
    """Remove the artifacts no target of ``graph`` uses now, and stale work directories."""
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
    """Validate recipe files (all of them when none is given).

    Every problem of the files named is the error; other files with problems are warned about
    (the named files' links may have needed them).
    """
    from pipeline.dag import build_graph

    workspace = _workspace()
    loader = _loader(workspace)
    if not args.files:
        targets = loader.load()
        build_graph(targets, universe=targets)
        console.print(f"[green]valid[/]: all recipe file(s), {len(targets)} targets")
        return 0
    files = [_recipe_path(workspace, name) for name in args.files]
    targets = loader.load(files)
    _graph_over(targets, loader.load_all(), selectors=[])
    console.print(f"[green]valid[/]: {len(files)} recipe file(s), {len(targets)} targets")
    return 0


def _recipe_path(workspace, name: str) -> Path:
    """A recipe file named on the command line: as given, else under the project or recipes folder."""
    import os

    for path in (Path(name), workspace.root / name, workspace.recipes_dir / name):
        if os.path.lexists(path):
            return path
    return Path(name)


def _existing_path(value: str) -> Path:
    path = Path(value).expanduser()
    if not path.exists():
        raise argparse.ArgumentTypeError(f"no such folder or file: {value}")
    return path


class HelpFormatter(argparse.HelpFormatter):
    """Help that fills the paragraphs of descriptions and epilogs but keeps indented lines (the examples)
    as they are written."""

    def _fill_text(self, text: str, width: int, indent: str) -> str:
        lines: list[str] = []
        paragraph: list[str] = []

        def flush() -> None:
            if paragraph:
                filled = textwrap.fill(
                    " ".join(paragraph), width, initial_indent=indent, subsequent_indent=indent
                )
                lines.append(filled)
                paragraph.clear()

        for line in text.strip("\n").splitlines():
            if line.strip() and not line[0].isspace():
                paragraph.append(line.strip())
                continue
            flush()
            lines.append(indent + line.rstrip() if line.strip() else "")
        flush()
        return "\n".join(lines)


def _examples(*commands: str) -> str:
    """An epilog listing example commands, kept as written by :class:`HelpFormatter`: a command given as
    several lines (each but the last ending in `` \\``) has its later lines indented further."""
    lines = []
    for command in commands:
        first, *rest = command.split("\n")
        lines += [f"  {first}", *(f"      {line}" for line in rest)]
    return "examples:\n" + "\n".join(lines)


def _command(
    sub, name: str, *, summary: str, examples: Sequence[str], description: str | None = None, **kwargs
) -> argparse.ArgumentParser:
    """Add sub-command ``name``: ``summary`` in its parent's list (and as its description unless one is
    given), ``examples`` after its options."""
    return sub.add_parser(
        name,
        help=summary,
        description=description or summary[0].upper() + summary[1:] + ".",
        epilog=_examples(*examples),
        formatter_class=HelpFormatter,
        **kwargs,
    )


def version_text() -> str:
    """What ``navverse --version`` prints: the toolkit's version and the file formats it reads and writes."""
    from navverse import __version__
    from navverse.dataset import FORMAT_VERSION
    from navverse.scene.annotations import SCENE_FORMAT_VERSION

    dataset_major = FORMAT_VERSION.split(".")[0]
    scene_major = SCENE_FORMAT_VERSION.split(".")[0]
    return (
        f"navverse {__version__}\n"
        f"dataset format {FORMAT_VERSION} (writes {FORMAT_VERSION}; reads {dataset_major}.0 up to "
        f"{FORMAT_VERSION})\n"
        f"scene format {SCENE_FORMAT_VERSION} (writes {SCENE_FORMAT_VERSION}; reads 1.x, upgraded, and "
        f"{scene_major}.x)"
    )


class _VersionAction(argparse.Action):
    """``--version``: print :func:`version_text` on stdout and exit 0."""

    def __init__(self, option_strings: Sequence[str], dest: str = argparse.SUPPRESS, **kwargs) -> None:
        super().__init__(option_strings, dest=dest, default=argparse.SUPPRESS, nargs=0, **kwargs)

    def __call__(self, parser, namespace, values, option_string=None) -> None:
        sys.stdout.write(version_text() + "\n")
        parser.exit()


def _recipe_options() -> argparse.ArgumentParser:
    """Options of the commands that load recipes: the allow-list of the file-access policy."""
    options = argparse.ArgumentParser(add_help=False)
    options.add_argument(
        "--allow-read",
        action="append",
        default=[],
        type=_existing_path,
        metavar="DIR",
        help="let recipes read files in DIR too (repeatable; as $NAVVERSE_ALLOW_READ); by default they "
        "read only files inside the project and installed packages' data",
    )
    return options


SCENES_HELP = (
    "look for the dataset's scenes in DIR first (repeatable; searched in the order given): a scene pack "
    "written by `navverse export scenes` (DIR/<scene_id>/) or a build store (DIR/targets/<scene_id>/scene). "
    "Then in $NAVVERSE_SCENES (directories separated by '{sep}', the same two layouts), then in this "
    "workspace's data/built. A scene whose scene hash differs from the dataset manifest's is passed over "
    "(one rebuilt in this workspace since the dataset was packaged is used, with a warning, when no place "
    "has the dataset's)"
)


EXPORT_SCENES_DESCRIPTION = (
    "Copy the scenes a dataset version (or one split) needs into OUT/<scene_id>/ (scene.json, scene.usdc, "
    "navmesh.bin, navmesh.json, textures/), with OUT/scenes.json listing each scene's hash and file "
    "checksums; each copy is checked against the dataset manifest's scene hash. The scenes are looked "
    "for as --scenes says and must have the dataset's scene hashes, in data/built too. Ship OUT with the "
    "dataset and pass --scenes OUT (or put OUT in $NAVVERSE_SCENES) to show episode, validate dataset, "
    "run-agent and eval."
)


EXPORT_HABITAT_DESCRIPTION = (
    "Write OUT/objectnav_v1/<split>/ (ObjectNav-v1: the ObjNav and PlaceNav episodes, goals with view points "
    "on the navmesh), OUT/vln_r2r/<split>/ (R2R-VLN: instructions with tokens and vocabulary) and "
    "OUT/scenes/<scene>/ (the scene as GLB, HM3D-style semantic files, the navmesh as habitat-sim's "
    ".navmesh), in habitat's y-up frame: a NavVerse point (x, y, z) is (x, z, -y) there. Load it with "
    "habitat-lab's dataset types ObjectNav-v1 / R2RVLN-v1 "
    "(data_path OUT/objectnav_v1/{split}/{split}.json.gz, scenes_dir OUT/scenes); "
    "scripts/habitat_check.py does so in a separate environment."
)

MINI = "episodes/navverse-mini/v2.0"
"""The default dataset (``make episodes``), in the examples of ``--help``."""

OUTDOOR = "episodes/navverse-outdoor/v1.0"
"""The outdoor dataset (``navverse build navverse-outdoor``), in the examples of ``--help``."""

DATASET_HELP = "a dataset version, episodes/<name>/v<version> (or episodes/<name>: the newest)"
DATASET_VERSION_HELP = "a dataset version, episodes/<name>/v<version>"
JOBS_HELP = "processes (default: the number of cores; 0 runs in this process)"


def _scene_options() -> argparse.ArgumentParser:
    """Options of the commands that read a dataset's scenes: where to look for them."""
    import os

    options = argparse.ArgumentParser(add_help=False)
    options.add_argument(
        "--scenes",
        action="append",
        default=[],
        type=_existing_path,
        metavar="DIR",
        help=SCENES_HELP.format(sep=os.pathsep),
    )
    return options


def _build_parsers(sub, recipe_options: argparse.ArgumentParser) -> None:
    """``navverse build``, ``status`` and ``clean``: the commands of the build engine."""
    build = _command(
        sub, "build", parents=[recipe_options], summary="build targets from recipes (default: all)",
        examples=("navverse build office-s1", "navverse build scenes/indoor --jobs 2",
                  "navverse build navverse-mini --dry-run"),
    )  # fmt: skip
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
        help="parallel processes (default: number of cores; 0 runs in this process); with --executor ray, "
        "the CPUs of the Ray instance started here, or a cap on the tasks sent to a cluster",
    )
    build.add_argument(
        "--executor",
        choices=("local", "ray"),
        default="local",
        help="where stages run: local processes (default) or Ray tasks (needs navverse[cluster]; the "
        "build store must be on a filesystem every Ray node mounts at the same path)",
    )
    build.add_argument(
        "--address",
        default=None,
        metavar="ADDR",
        help="with --executor ray: the cluster to use ('auto', host:port or ray://host:port; "
        "default: start Ray on this machine)",
    )
    build.add_argument(
        "--force", action="store_true", help="rebuild the selected targets even if cached (replacing them)"
    )
    build.add_argument("--dry-run", action="store_true", help="print the build graph and what would run")
    build.add_argument(
        "--verify",
        action="store_true",
        help="check the sha256 of every file reused (default: sizes only) and rebuild what differs",
    )
    build.add_argument(
        "--no-wait",
        action="store_true",
        help="exit 1 at once if another build holds the workspace (default: wait for it)",
    )
    build.set_defaults(func=cmd_build)

    status = _command(
        sub, "status", parents=[recipe_options], summary="fresh / stale / missing / corrupt per target",
        examples=("navverse status", "navverse status 'office-*' --verify"),
    )  # fmt: skip
    status.add_argument(
        "targets", nargs="*", metavar="TARGET",
        help="target ids (globs allowed) or recipe paths/folders (default: every target)",
    )  # fmt: skip
    status.add_argument(
        "--verify",
        action="store_true",
        help="check the sha256 of every built file (default: sizes only); exit 1 if one differs",
    )
    status.set_defaults(func=cmd_status)

    clean = _command(
        sub, "clean", parents=[recipe_options], summary="remove unused build outputs (or all with --all)",
        examples=("navverse clean", "navverse clean --all"),
    )  # fmt: skip
    clean.add_argument("--all", action="store_true", help="remove every build output")
    clean.set_defaults(func=cmd_clean)


def _validate_parser(sub, recipe_options: argparse.ArgumentParser, scene_options: argparse.ArgumentParser):
    """``navverse validate recipe | dataset | submission``."""
    validate = _command(
        sub, "validate", summary="check input files without building",
        examples=("navverse validate recipe recipes/scenes/indoor/office.yaml",
                  f"navverse validate dataset {OUTDOOR} --replay 5",
                  f"navverse validate submission run.jsonl --dataset {MINI}"),
    )  # fmt: skip
    vsub = validate.add_subparsers(
        dest="what", required=True, metavar="WHAT", help="what to check (navverse validate WHAT --help)"
    )
    recipe = _command(
        vsub, "recipe", parents=[recipe_options], summary="validate recipe files (all when none given)",
        examples=("navverse validate recipe", "navverse validate recipe recipes/scenes/indoor/office.yaml"),
    )  # fmt: skip
    recipe.add_argument(
        "files", nargs="*", metavar="FILE",
        help="recipe files (as given, or relative to the project or to recipes/); default: every recipe",
    )  # fmt: skip
    recipe.set_defaults(func=cmd_validate_recipe)
    vdataset = _command(
        vsub, "dataset", parents=[scene_options],
        summary="check a dataset version (format, checksums, bounds, rollouts; with --scenes, its scenes)",
        examples=(f"navverse validate dataset {MINI}", f"navverse validate dataset {MINI} --replay all",
                  f"navverse validate dataset {OUTDOOR} --replay 5 --seed 1"),
    )  # fmt: skip
    vdataset.add_argument("dataset", help=DATASET_HELP)
    vdataset.add_argument(
        "--replay", metavar="N|all", help="run the oracle rollouts of N sampled episodes (or all) again"
    )
    vdataset.add_argument("--seed", type=int, default=0, help="which episodes --replay N samples")
    vdataset.add_argument("--jobs", "-j", type=int, default=None, help=f"{JOBS_HELP}, for --replay")
    vdataset.set_defaults(func=partial(cli_data.cmd_validate_dataset, built_dir=workspace_built_dir))
    vsubmission = _command(
        vsub, "submission", parents=[scene_options],
        summary="report every problem of a submission, with line numbers",
        examples=("navverse validate submission run.jsonl",
                  f"navverse validate submission run.jsonl.gz --dataset {MINI} --split eval"),
    )  # fmt: skip
    vsubmission.add_argument("submission", help="JSONL file (optionally .gz), one episode per line")
    vsubmission.add_argument(
        "--dataset", default=None, help="episodes/<name>/v<version> (without it: the format alone)"
    )
    vsubmission.add_argument("--split", default="eval", help="the split it answers (default: eval)")
    vsubmission.set_defaults(func=partial(cli_data.cmd_validate_submission, built_dir=workspace_built_dir))


def _eval_parser(sub, scene_options: argparse.ArgumentParser) -> None:
    """``navverse eval``."""
    evaluate = _command(
        sub, "eval", parents=[scene_options], summary="score a submission against a dataset split",
        examples=(f"navverse eval --dataset {MINI} --submission run.jsonl --out eval-out",
                  f"navverse eval --dataset {MINI} --submission run.jsonl --episodes submitted",
                  f"navverse eval --dataset {OUTDOOR} --submission oracle-category.jsonl \\\n"
                  "--submission oracle-route.jsonl --submission oracle-intention.jsonl"),
    )  # fmt: skip
    evaluate.add_argument("--dataset", required=True, help=DATASET_VERSION_HELP)
    evaluate.add_argument(
        "--submission", required=True, action="append",
        help="JSONL file (optionally .gz). Repeatable: the same agent's runs under different PlaceNav "
        "instruction types (one each) fill the instruction-type table (instruction_types.md); every "
        "other output (metrics.json, tables, report) is the first submission's",
    )  # fmt: skip
    evaluate.add_argument("--split", default="eval", help="split scored (default: eval)")
    evaluate.add_argument("--embodiment", default=None, help="robot scored (default: the dataset's)")
    evaluate.add_argument("--out", default="eval-out", help="output folder (default: eval-out)")
    evaluate.add_argument(
        "--episodes",
        choices=("all", "submitted"),
        default="all",
        help="all: every episode of the split, one without a valid record scored as a failure (the "
        "benchmark's number; default); submitted: only the episodes the submission has a line for "
        "(a partial scoring, labelled PARTIAL in every output)",
    )
    evaluate.set_defaults(func=partial(cli_data.cmd_eval, built_dir=workspace_built_dir))


def _run_parser(sub, scene_options: argparse.ArgumentParser) -> None:
    """``navverse run-agent``."""
    from navverse.dataset import INSTRUCTION_TYPES, TASKS

    run = _command(
        sub, "run-agent", parents=[scene_options],
        summary="run an agent over a dataset split and write its submission",
        examples=(f"navverse run-agent --dataset {MINI} --agent oracle --out oracle.jsonl.gz",
                  f"navverse run-agent --dataset {MINI} --agent examples/my_agent.py:GoalSeekingAgent \\\n"
                  "--limit 10 --out mine.jsonl",
                  f"navverse run-agent --dataset {OUTDOOR} --agent frontier --embodiment turtlebot \\\n"
                  "--instruction-type route --out frontier-route.jsonl.gz"),
    )  # fmt: skip
    run.add_argument("--dataset", required=True, help=DATASET_VERSION_HELP)
    run.add_argument("--split", default="eval", help="split run (default: eval)")
    run.add_argument(
        "--agent",
        required=True,
        help="oracle, gt_goal, random, frontier (navverse list agents), or your own 'module:Class' / "
        "'path/to/file.py:Class'",
    )
    run.add_argument("--embodiment", default=None, help="spot or turtlebot (default: the dataset's)")
    run.add_argument("--out", required=True, help="submission to write (.jsonl or .jsonl.gz)")
    run.add_argument("--jobs", "-j", type=int, default=None, help="processes (default: cores; 0: in process)")
    run.add_argument("--limit", type=int, default=None, help="run only K episodes, spread over the split")
    run.add_argument("--task", choices=TASKS, default=None, help="run only this task's episodes")
    run.add_argument("--seed", type=int, default=0, help="seed of the agent's per-episode seeds")
    run.add_argument(
        "--instruction-type", choices=INSTRUCTION_TYPES, default="category",
        help="the instruction PlaceNav episodes give the agent: the place category, a route description "
        "or an intention (default: category); under route and intention an agent that is not privileged "
        "is not told the category",
    )  # fmt: skip
    run.add_argument("--max-steps", type=int, default=None, help="cut an episode after this many actions")
    run.add_argument(
        "--friction", type=float, default=None, help="friction of every terrain class (a diagnostic)"
    )
    run.add_argument(
        "--step-timeout", type=float, default=None, metavar="SECONDS",
        help="wall-clock limit of one agent call (reset or act); over it the episode ends as "
        "agent_timeout (default: 30)",
    )  # fmt: skip
    run.add_argument(
        "--episode-timeout", type=float, default=None, metavar="SECONDS",
        help="wall-clock limit of the agent's calls in one episode, together (default: 600)",
    )  # fmt: skip
    run.set_defaults(func=partial(cli_data.cmd_run_agent, built_dir=workspace_built_dir))


def _show_parser(sub, scene_options: argparse.ArgumentParser) -> None:
    """``navverse show scene | presets | dataset | episode``."""
    show = _command(
        sub, "show", summary="draw or print what was built",
        examples=("navverse show scene office-s1 -o office.png", "navverse show presets",
                  f"navverse show dataset {OUTDOOR}"),
    )  # fmt: skip
    ssub = show.add_subparsers(
        dest="what", required=True, metavar="WHAT", help="what to show (navverse show WHAT --help)"
    )
    scene = _command(
        ssub, "scene", summary="bird's-eye-view picture of a built scene (or a scene directory)",
        examples=("navverse show scene office-s1 -o office.png",
                  "navverse show scene data/built/targets/corridor/scene --meters-per-pixel 0.02"),
    )  # fmt: skip
    scene.add_argument("scene", help="a built scene's id, or a directory holding scene.json")
    scene.add_argument("-o", "--output", help="PNG path (default: <scene>-bev.png)")
    scene.add_argument(
        "--meters-per-pixel", type=float, default=None, metavar="M",
        help="the picture's scale (default: chosen from the scene's size)",
    )  # fmt: skip
    scene.set_defaults(func=partial(cli_data.cmd_show_scene, built_dir=workspace_built_dir))
    presets = _command(
        ssub, "presets", summary="navmesh presets and the scene-type profiles that pick them",
        examples=("navverse show presets",),
    )  # fmt: skip
    presets.set_defaults(func=cli_data.cmd_show_presets)
    dataset = _command(
        ssub, "dataset", summary="episode counts and goal categories of a dataset",
        examples=(f"navverse show dataset {MINI}",
                  "navverse show dataset episodes/navverse-outdoor --top 10"),
    )  # fmt: skip
    dataset.add_argument("dataset", help=DATASET_HELP)
    dataset.add_argument("--top", type=int, default=25, help="goal categories listed (default: 25)")
    dataset.set_defaults(func=cli_data.cmd_show_dataset)
    episode = _command(
        ssub, "episode", parents=[scene_options], summary="draw an episode on its scene's bird's-eye view",
        examples=(f"navverse show episode {MINI} office-s1-vln-0003 -o ep.png",
                  f"navverse show episode {OUTDOOR} west-oakland-vln-0000"),
    )  # fmt: skip
    episode.add_argument("dataset", help=DATASET_HELP)
    episode.add_argument("episode_id", help="the episode's id, e.g. office-s1-vln-0003 (see show dataset)")
    episode.add_argument("-o", "--output", help="PNG path (default: <episode_id>.png)")
    episode.set_defaults(func=partial(cli_data.cmd_show_episode, built_dir=workspace_built_dir))


def _review_parser(sub, scene_options: argparse.ArgumentParser) -> None:
    """``navverse review DATASET``: the local page where a person accepts or rejects episodes."""
    from navverse.review.cli import cmd_review

    review = _command(
        sub, "review", parents=[scene_options],
        summary="serve a local page to accept or reject a dataset's episodes (manual quality control)",
        description=(
            "List a dataset version's episodes with their bird's-eye view, keyframes along the verification "
            "rollout and instruction texts, on a page served at 127.0.0.1; each Accept or Reject (with a "
            "reason) is saved at once to recipes/datasets/<name>.review.yml. Name that file in the "
            "recipe (package_dataset or merge_datasets: {review: <name>.review.yml}) and build again: a "
            "new minor version is published without the rejected episodes; the reviewed one is untouched."
        ),
        examples=(f"navverse review {MINI}",
                  "navverse review episodes/navverse-outdoor --port 8765 --no-browser"),
    )  # fmt: skip
    review.add_argument(
        "dataset", help="episodes/<name>[/v<version>], or a name under episodes/ (newest version)"
    )
    review.add_argument("--port", type=int, default=0, help="port on 127.0.0.1 (default: any free one)")
    review.add_argument("--no-browser", action="store_true", help="only print the URL, do not open a browser")
    review.add_argument(
        "--recipe", help="the dataset recipe (default: the manifest's recipe in this workspace)"
    )
    review.set_defaults(func=partial(cmd_review, built_dir=workspace_built_dir))


def _export_parser(sub, scene_options: argparse.ArgumentParser) -> None:
    """``navverse export WHAT``: a dataset's parts for use elsewhere (one sub-command per format)."""
    export = _command(
        sub, "export", summary="write a dataset's scenes (or the dataset) for use elsewhere",
        examples=(f"navverse export scenes {MINI} mini-scenes",
                  f"navverse export habitat {MINI} mini-habitat"),
    )  # fmt: skip
    esub = export.add_subparsers(
        dest="what", required=True, metavar="WHAT", help="what to write (navverse export WHAT --help)"
    )
    scenes = _command(
        esub, "scenes", parents=[scene_options],
        summary="copy the scenes a dataset needs into a scene pack, to use it where the scenes are not built",
        description=EXPORT_SCENES_DESCRIPTION,
        examples=(f"navverse export scenes {MINI} mini-scenes",
                  f"navverse export scenes {OUTDOOR} outdoor-eval-scenes --split eval",
                  f"navverse eval --dataset {MINI} --submission run.jsonl --scenes mini-scenes"),
    )  # fmt: skip
    scenes.add_argument("dataset", help=DATASET_HELP)
    scenes.add_argument("out", help="the pack directory to create (must not exist, or be empty)")
    scenes.add_argument("--split", default=None, help="only the scenes of this split (default: every split)")
    scenes.set_defaults(func=partial(cli_data.cmd_export_scenes, built_dir=workspace_built_dir))
    habitat = _command(
        esub, "habitat", parents=[scene_options],
        summary="write a dataset and its scenes in habitat-lab's layouts (ObjectNav-v1, R2R-VLN, GLB)",
        description=EXPORT_HABITAT_DESCRIPTION,
        examples=(f"navverse export habitat {MINI} mini-habitat",
                  f"navverse export habitat {OUTDOOR} outdoor-habitat --scenes outdoor-scenes"),
    )  # fmt: skip
    habitat.add_argument("dataset", help=DATASET_VERSION_HELP)
    habitat.add_argument("out", help="the export directory to create (must not exist, or be empty)")
    habitat.set_defaults(func=partial(cli_data.cmd_export_habitat, built_dir=workspace_built_dir))


def _list_parser(sub) -> None:
    """``navverse list WHAT``."""
    listing = _command(
        sub, "list", summary="list building types, room types, categories, agents or embodiments",
        examples=("navverse list building-types", "navverse list categories --kind places",
                  "navverse list agents --json"),
    )  # fmt: skip
    listing.add_argument(
        "what", choices=cli_list.LIST_KINDS, metavar="WHAT",
        help=f"one of: {', '.join(cli_list.LIST_KINDS)} (navmesh presets: navverse show presets)",
    )  # fmt: skip
    listing.add_argument(
        "--kind", choices=cli_list.CATEGORY_KINDS, default=None,
        help="for categories: only object categories (goal objects, furniture, street objects) or only "
        "place categories (PlaceNav goals); default: both",
    )  # fmt: skip
    listing.add_argument(
        "--json", action="store_true", help="print the rows as one JSON list (for scripts) instead of tables"
    )
    listing.set_defaults(func=cli_list.cmd_list)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every sub-command."""
    parser = argparse.ArgumentParser(
        prog="navverse",
        description="Build navigation scenes and episode datasets from recipes, and evaluate agents.",
        epilog=_examples(
            "navverse build office-s1",
            f"navverse run-agent --dataset {MINI} --agent oracle --out run.jsonl",
            f"navverse eval --dataset {MINI} --submission run.jsonl",
        ),
        formatter_class=HelpFormatter,
    )
    parser.add_argument(
        "--version",
        action=_VersionAction,
        help="print the version and the dataset and scene formats, and exit",
    )
    sub = parser.add_subparsers(
        dest="command", required=True, metavar="COMMAND", help="what to do (navverse COMMAND --help)"
    )
    recipe_options = _recipe_options()
    scene_options = _scene_options()
    _build_parsers(sub, recipe_options)
    _validate_parser(sub, recipe_options, scene_options)
    _eval_parser(sub, scene_options)
    _run_parser(sub, scene_options)
    _show_parser(sub, scene_options)
    _export_parser(sub, scene_options)
    _review_parser(sub, scene_options)
    _list_parser(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``navverse`` command; returns the exit code.

    Exit codes: 0 success; 1 an error (a message, never a traceback; for ``build`` a failed stage,
    for ``status`` a corrupt artifact); 2 bad arguments; 130 interrupted by Ctrl-C (SIGINT), 143
    by SIGTERM (a build ends its workers first and says how many stage runs are left).
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    console = Console(stderr=False)
    errors = Console(stderr=True, highlight=False, soft_wrap=True)
    from pipeline.params import allow_reading

    try:
        with allow_reading(args.allow_read if "allow_read" in args else ()):
            return int(args.func(args, console))
    except (NavverseError, PipelineError) as exc:
        errors.print(f"error: {exc}", style="red", markup=False)
        return 1
    except KeyboardInterrupt as exc:  # a build's BuildInterrupted says how many stage runs are left
        errors.print(str(exc) if hasattr(exc, "unfinished") else "interrupted", markup=False)
        return 128 + int(getattr(exc, "signum", signal.SIGINT))
    except OSError as exc:
        if exc.errno not in (errno.ENOSPC, errno.EDQUOT):
            raise
        where = exc.filename or "the workspace"
        errors.print(
            f"error: no space left on device while writing {where}; free space and run the same "
            "command to resume",
            style="red",
            markup=False,
        )
        return 1


if __name__ == "__main__":
    sys.exit(main())
