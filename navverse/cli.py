"""The ``navverse`` command: the composition root, the one navverse module that imports ``pipeline``
and ``stages``.

:func:`build_parser` assembles the parser from :data:`COMMANDS`, the ``register`` of each command
group in the order of ``navverse --help``: the build commands here (build, status, clean, validate
recipe: the ones that reach into the engine), the data commands in :mod:`navverse.commands`, each
declaring its commands' arguments beside their handlers. The data commands are handed the build
store (:func:`workspace_built_dir`, through :class:`~navverse.commands.common.Shared`) so they never
import the engine. :func:`build_targets` is ``navverse build`` for :func:`navverse.api.build`.
:func:`main` runs the chosen command's ``func``. The engine is imported inside the functions that use
it, so the command line starts quickly and the data commands never load it; a stage's module is
imported when a recipe names the stage (:func:`pipeline.stage.stage_index`).
"""

from __future__ import annotations

import argparse
import contextlib
import errno
import shutil
import signal
import sys
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from functools import partial
from pathlib import Path

from rich.console import Console

from navverse.commands import city, evaluate, export, listing, serve, show, validate, workspace
from navverse.commands.common import (
    MINI,
    HelpFormatter,
    Shared,
    Subparsers,
    VersionAction,
    command,
    examples_epilog,
    recipe_options,
    scene_options,
    validate_commands,
)
from navverse.commands.common import (
    console as terminal_console,
)
from navverse.errors import NavverseError
from navverse.review import cli as review

__all__ = [
    "COMMANDS",
    "STAGES_PACKAGE",
    "build_parser",
    "build_targets",
    "cmd_build",
    "cmd_clean",
    "cmd_status",
    "cmd_validate_recipe",
    "main",
    "register",
    "workspace_built_dir",
]

STAGES_PACKAGE = "stages"
"""The package whose modules register the stages (the tests point it at toy stages)."""


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
    from pipeline.errors import PipelineError

    try:
        return _workspace(root).built_dir
    except PipelineError as exc:
        raise NavverseError(str(exc)) from None


def _loader(workspace):
    """The workspace's recipe loader; a stage's module is imported when a recipe names the stage."""
    from pipeline.recipes import RecipeLoader
    from pipeline.stage import stage_index

    return RecipeLoader(workspace, stages=stage_index(STAGES_PACKAGE))


def _warn(warnings: Sequence[str]) -> None:
    console = terminal_console(stderr=True)
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


def register(sub: Subparsers, shared: Shared) -> None:
    """Add ``navverse build``, ``status``, ``clean`` and ``validate recipe`` to ``sub``."""
    _build_parser(sub, shared)
    _status_parser(sub, shared)
    _clean_parser(sub, shared)
    _validate_recipe_parser(sub, shared)


def _build_parser(sub: Subparsers, shared: Shared) -> None:
    """``navverse build``."""
    build = command(
        sub, "build", parents=[shared.recipe_options], summary="build targets from recipes (default: all)",
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


def cmd_build(args: argparse.Namespace, console: Console) -> int:
    """Build targets (default: all), holding the workspace lock; exit 1 if a stage failed."""
    from pipeline.errors import PipelineError
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
    from pipeline.errors import PipelineError
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
        terminal_console(stderr=True).print(
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


def _status_parser(sub: Subparsers, shared: Shared) -> None:
    """``navverse status``."""
    status = command(
        sub, "status", parents=[shared.recipe_options],
        summary="fresh / stale / missing / corrupt per target",
        examples=("navverse status", "navverse status 'office-*' --verify",
                  "navverse status navverse-full --cost"),
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
    status.add_argument(
        "--cost",
        action="store_true",
        help="also per stage: stage runs built of all, and the CPU and wall hours the built ones took",
    )
    status.set_defaults(func=cmd_status)


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
    if args.cost:
        console.print(_cost_table(graph, store))
    if corrupt:
        console.print("run `navverse build` to rebuild the corrupt artifacts", highlight=False)
    running = running_build(store.lock_path)
    if running:
        console.print(
            f"note: {running} is running in this workspace; these statuses may change", soft_wrap=True
        )
    return 1 if corrupt else 0


def _cost_table(graph, store):
    """Per stage: stage runs built / in the graph, CPU hours (the stage's processes and the pools they
    waited for), wall hours and largest peak memory of the built runs; and the total."""
    from rich.table import Table

    from pipeline.costs import stage_costs

    costs = stage_costs(graph, store)
    table = Table(title="cost of the built stage runs (as they ran)")
    for column in ("stage", "built / runs", "CPU h", "wall h", "peak MB"):
        table.add_column(column, justify="left" if column == "stage" else "right")
    for cost in costs:
        table.add_row(cost.stage, f"{cost.built} / {cost.runs}", f"{cost.cpu_s / 3600:.2f}",
                      f"{cost.wall_s / 3600:.2f}", f"{cost.peak_rss_mb:.0f}")  # fmt: skip
    built, runs = sum(c.built for c in costs), sum(c.runs for c in costs)
    cpu, wall = sum(c.cpu_s for c in costs) / 3600, sum(c.wall_s for c in costs) / 3600
    table.add_row("all", f"{built} / {runs}", f"{cpu:.2f}", f"{wall:.2f}", "", style="bold")
    return table


def _clean_parser(sub: Subparsers, shared: Shared) -> None:
    """``navverse clean``."""
    clean = command(
        sub, "clean", parents=[shared.recipe_options],
        summary="remove unused build outputs (or all with --all)",
        examples=("navverse clean", "navverse clean --all"),
    )  # fmt: skip
    clean.add_argument("--all", action="store_true", help="remove every build output")
    clean.set_defaults(func=cmd_clean)


def cmd_clean(args: argparse.Namespace, console: Console) -> int:
    """Remove build outputs: unused artifacts (default) or everything (--all), holding the lock."""
    from pipeline.store import ArtifactStore

    workspace = _workspace()
    store = ArtifactStore(workspace.built_dir)
    if args.all:
        with _locked(store, wait=True):
            for child in (store.artifacts_dir, store.targets_dir, store.tmp_dir, store.logs_dir,
                          store.checkpoints_dir):  # fmt: skip
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
    runs = {node.key for node in graph.nodes.values()}
    if store.checkpoints_dir.is_dir():  # the saved map results of stage runs no target makes now
        for path in sorted(store.checkpoints_dir.iterdir()):
            if path.name not in runs:
                shutil.rmtree(path, ignore_errors=True)
                removed += 1
    console.print(f"removed {removed} unused artifacts; kept {len(keep)} current ones")
    return 0


def _validate_recipe_parser(sub: Subparsers, shared: Shared) -> None:
    """``navverse validate recipe``."""
    recipe = command(
        validate_commands(sub, shared), "recipe", parents=[shared.recipe_options],
        summary="validate recipe files (all when none given)",
        examples=("navverse validate recipe", "navverse validate recipe recipes/scenes/indoor/office.yaml"),
    )  # fmt: skip
    recipe.add_argument(
        "files", nargs="*", metavar="FILE",
        help="recipe files (as given, or relative to the project or to recipes/); default: every recipe",
    )  # fmt: skip
    recipe.set_defaults(func=cmd_validate_recipe)


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


COMMANDS: tuple[Callable[[Subparsers, Shared], None], ...] = (
    workspace.register,
    city.register,
    register,
    validate.register,
    evaluate.register,
    serve.register,
    show.register,
    export.register,
    review.register,
    listing.register,
)
"""The ``register`` of every command group, in the order ``navverse --help`` lists their commands."""


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every sub-command."""
    parser = argparse.ArgumentParser(
        prog="navverse",
        description="Build navigation scenes and episode datasets from recipes, and evaluate agents.",
        epilog=examples_epilog(
            "navverse build office-s1",
            f"navverse run-agent --dataset {MINI} --agent oracle --out run.jsonl",
            f"navverse eval --dataset {MINI} --submission run.jsonl",
        ),
        formatter_class=HelpFormatter,
    )
    parser.add_argument(
        "--version",
        action=VersionAction,
        help="print the version and the dataset and scene formats, and exit",
    )
    sub = parser.add_subparsers(
        dest="command", required=True, metavar="COMMAND", help="what to do (navverse COMMAND --help)"
    )
    shared = Shared(
        recipe_options=recipe_options(), scene_options=scene_options(), built_dir=workspace_built_dir
    )
    for add in COMMANDS:
        add(sub, shared)
    return parser


def _reading(args: argparse.Namespace) -> contextlib.AbstractContextManager[None]:
    """``--allow-read`` of a command that reads recipes; the other commands load no engine."""
    if "allow_read" not in args:
        return contextlib.nullcontext()
    from pipeline.params import allow_reading

    return allow_reading(args.allow_read)


def _one_line_errors() -> tuple[type[Exception], ...]:
    """The errors :func:`main` prints as one line: navverse's, and the engine's once a command has
    loaded the engine (a command that never imports it cannot raise its errors)."""
    engine = sys.modules.get("pipeline.errors")
    return (NavverseError,) if engine is None else (NavverseError, engine.PipelineError)


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``navverse`` command; returns the exit code.

    Exit codes: 0 success; 1 an error (a message, never a traceback; for ``build`` a failed stage,
    for ``status`` a corrupt artifact); 2 bad arguments; 130 interrupted by Ctrl-C (SIGINT), 143
    by SIGTERM (a build ends its workers first and says how many stage runs are left).
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    console = terminal_console()
    errors = terminal_console(stderr=True, highlight=False, soft_wrap=True)
    try:
        with _reading(args):
            return int(args.func(args, console))
    except _one_line_errors() as exc:
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


if __name__ == "__main__":  # python -m navverse.cli
    sys.exit(main())
