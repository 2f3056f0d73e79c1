"""``navverse eval`` and ``run-agent``, each beside its parser: score a submission against a dataset
split, and run an agent online over a split to write its submission. Each command returns the exit code;
its imports are inside it, so the command line starts quickly."""

from __future__ import annotations

import argparse
import gc
import os
from collections.abc import Callable, Iterator
from contextlib import contextmanager, suppress
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

from rich.console import Console

from navverse.commands.common import (
    DATASET_VERSION_HELP,
    MINI,
    OUTDOOR,
    Shared,
    Subparsers,
    command,
    console_table,
)
from navverse.commands.datasets import dataset_scene_dirs, problem_count, split_of
from navverse.commands.progress import show_progress
from navverse.eval.selection import PICTURES

if TYPE_CHECKING:
    from navverse.scene.fields import SceneFields

__all__ = ["PRIVATE_HELP", "cmd_eval", "cmd_run_agent", "open_dataset", "register"]

PRIVATE_HELP = (
    "the directory of the dataset version's private files (episodes/<name>/private/v<version>): the "
    "goals of a private split such as test (default: that directory beside the version, when it is there)"
)


def open_dataset(args: argparse.Namespace):
    """The ``--dataset`` version, verified, with its private files: ``--private`` when given, else those
    beside it when they are there (a NavverseError when ``--private`` is given for a dataset without a
    private split)."""
    from navverse.dataset import local_dataset

    dataset = local_dataset(args.dataset, private=args.private)
    dataset.verify()
    return dataset


def register(sub: Subparsers, shared: Shared) -> None:
    """Add ``navverse eval`` and ``run-agent`` to ``sub``."""
    _eval_parser(sub, shared)
    _run_parser(sub, shared)


def _eval_parser(sub: Subparsers, shared: Shared) -> None:
    """``navverse eval``."""
    evaluate = command(
        sub, "eval", parents=[shared.scene_options], summary="score a submission against a dataset split",
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
    evaluate.add_argument(
        "--private", metavar="DIR", default=None, help=PRIVATE_HELP + " (needed to score one)"
    )
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
    evaluate.add_argument(
        "--pictures", default=PICTURES, metavar="N",
        help=f"episodes report.html draws as cards, with a bird's-eye view and keyframes (a whole number, "
        f"default: {PICTURES}): every outcome shown, failures first, spread over tasks, scene types and "
        "scenes; the others are rows of metrics. When at most N episodes are scored, each gets a card",
    )  # fmt: skip
    evaluate.set_defaults(func=partial(cmd_eval, built_dir=shared.built_dir))


def _pictures(value: str | int) -> int:
    """``--pictures`` as a count of cards (a whole number, 0 or more), or a NavverseError saying what to
    give (checked by the command, so that a bad value exits 1 with the message, as other bad values do)."""
    from navverse.errors import NavverseError

    count = None
    if isinstance(value, str):
        with suppress(ValueError):
            count = int(value)
    elif isinstance(value, int) and not isinstance(value, bool):
        count = value
    if count is None or count < 0:
        raise NavverseError(
            f"--pictures {value}: give the number of episode cards report.html draws, a whole number, 0 or "
            f"more (default {PICTURES})"
        )
    return count


@contextmanager
def _long_lived() -> Iterator[Callable[[], None]]:
    """A block in which the function given marks the objects alive as long-lived (:func:`gc.freeze`):
    the garbage collector's full passes leave them out until the block ends (:func:`gc.unfreeze`).

    ``eval`` reads the dataset's episodes and the submissions' records first and keeps them to the end:
    at 10,000 episodes they are about a million objects, which every full pass would walk again (some
    2 s of a 30 s eval). Nothing is frozen when the collector is off or something else froze objects.
    """
    own = gc.isenabled() and gc.get_freeze_count() == 0
    try:
        yield gc.freeze if own else lambda: None
    finally:
        if own:
            gc.unfreeze()


def _check_out_dir(out: str | os.PathLike[str]) -> Path:
    """`out` as a directory the outputs can be written into (made later), or a NavverseError saying what
    to change: it is a file, a parent is a file, or the place is not writable."""
    import tempfile

    from navverse.errors import NavverseError

    out = Path(out)
    if out.exists() and not out.is_dir():
        raise NavverseError(f"--out {out} is a file: give a directory (it gets metrics.json, report.html)")
    existing = next(p for p in (out, *out.absolute().parents) if p.exists())
    if not existing.is_dir():
        raise NavverseError(f"--out {out}: {existing} is a file, not a directory; choose another --out")
    try:
        with tempfile.TemporaryFile(dir=existing):
            pass
    except OSError as exc:
        raise NavverseError(
            f"--out {out}: cannot write into {existing} ({exc.strerror or exc}); choose a writable --out"
        ) from None
    return out


def _submission_paths(args: argparse.Namespace) -> list[str]:
    """The ``--submission`` files of ``eval`` (a list from the parser; one path is taken too)."""
    given = args.submission
    return [os.fspath(given)] if isinstance(given, (str, os.PathLike)) else [os.fspath(p) for p in given]


def _read_for_eval(args: argparse.Namespace, dataset, scene_dirs: dict) -> list:
    """The submissions given to ``eval`` (read against the split), each under its own instruction type
    when there are several, or a NavverseError saying what to change."""
    from navverse.errors import NavverseError
    from navverse.eval.scoring import instruction_type_of
    from navverse.eval.submission import episode_bounds, read_submission

    ids = split_of(dataset, args.split)
    episodes = list(dataset.episodes(split=args.split))
    bounds = episode_bounds(episodes, scene_dirs)
    paths = _submission_paths(args)
    submissions, kinds = [], {}
    for path in paths:
        submission = read_submission(path, episode_ids=ids, bounds=bounds)
        kind = instruction_type_of(submission, episodes)
        if len(paths) > 1 and kind is None:
            raise NavverseError(
                f"several --submission are scored to compare PlaceNav instruction types, but split "
                f"{args.split!r} has no PlaceNav episodes: give one --submission"
            )
        if kind in kinds:
            raise NavverseError(
                f"--submission {kinds[kind]} and {path} were both run under instruction type {kind!r}: give "
                "one submission per instruction type (`navverse run-agent --instruction-type ...`)"
            )
        kinds[kind] = path
        submissions.append(submission)
    return submissions


def _score_for_eval(
    args: argparse.Namespace,
    console: Console,
    dataset,
    submissions: list,
    scene_dirs: dict,
    *,
    on_fields: Callable[[str, SceneFields], None] | None = None,
):
    """Each submission's :class:`~navverse.eval.scoring.EvalResult`, showing progress; `on_fields` sees
    the first one's scenes' fields (:func:`~navverse.eval.scoring.score`)."""
    from navverse.eval.scoring import score

    results = []
    for index, submission in enumerate(submissions):
        with show_progress(console, f"eval: scoring {submission.path.name}", unit="episodes") as progress:
            progress(0, len(submission.records))
            results.append(
                score(
                    dataset,
                    submission,
                    split=args.split,
                    scene_dirs=scene_dirs,
                    embodiment=args.embodiment,
                    episodes=args.episodes,
                    progress=progress,
                    on_fields=on_fields if index == 0 else None,
                )
            )
    return results


def _print_table(console: Console, header: list[str], rows: list[list[str]], title: str) -> None:
    table = console_table(console, title=title)
    for column in header:
        table.add_column(column, justify="left" if column == header[0] else "right")
    for row in rows:
        table.add_row(*row)
    console.print(table)


def cmd_eval(args: argparse.Namespace, console: Console, *, built_dir: Callable[[], Path]) -> int:
    """Score a submission: metrics.json, tables (md, csv), report.html, and the headline table. Several
    submissions (one per PlaceNav instruction type) add rows to the instruction-type table; the other
    outputs are the first one's."""
    from navverse import __version__
    from navverse.eval.protocol import describe
    from navverse.eval.report import PictureBackdrops, write_report
    from navverse.eval.tables import (
        instruction_type_entries,
        instruction_type_table,
        scope_text,
        table_rows,
        write_outputs,
    )

    pictures = _pictures(args.pictures)
    _check_out_dir(args.out)
    with _long_lived() as settle:
        dataset = open_dataset(args)
        split_of(dataset, args.split)
        dataset.require_goals(args.split, what="scoring")
        scene_dirs = dataset_scene_dirs(args, dataset, dataset.episodes(split=args.split), built_dir)
        submissions = _read_for_eval(args, dataset, scene_dirs)
        settle()  # the episodes and the records, kept to the end
        backdrops = PictureBackdrops(
            dataset, submissions[0], split=args.split, scene_dirs=scene_dirs, embodiment=args.embodiment,
            episodes=args.episodes, pictures=pictures,
        )  # fmt: skip
        results = _score_for_eval(args, console, dataset, submissions, scene_dirs, on_fields=backdrops.take)
        submission, result = submissions[0], results[0]
        meta = {
            "dataset": str(dataset.root),
            "dataset_version": dataset.manifest.version,
            "split": args.split,
            "submission": _submission_paths(args)[0],
            "embodiment": args.embodiment or dataset.manifest.embodiment,
            "episodes": args.episodes,
            "toolkit_version": __version__,
        }
        out = write_outputs(result, args.out, meta=meta, others=results[1:])
        with show_progress(console, "eval: drawing the report", unit="cards") as progress:
            report = write_report(
                result,
                dataset=dataset,
                submission=submission,
                scene_dirs=scene_dirs,
                out_dir=Path(out),
                embodiment=args.embodiment,
                pictures=pictures,
                backdrops=backdrops,
                progress=progress,
            )
    if submission.problems:
        count = problem_count(submission)
        console.print(f"[yellow]{count} submission problems[/] (listed in metrics.json):")
        for problem in submission.problems[:10]:
            console.print(f"  {problem}", highlight=False, markup=False)
    for other in submissions[1:]:
        if other.problems:
            console.print(
                f"{problem_count(other)} problems in {other.path} (see `navverse validate submission`)",
                style="yellow",
                highlight=False,
                markup=False,
            )
    invalid = [row["episode_id"] for row in result.episodes if row["label"] == "invalid"]
    if invalid:
        console.print(
            f"[yellow]{len(invalid)} episodes have no valid trajectory, scored as failures:[/] "
            + ", ".join(invalid[:10])
            + (f" ... ({len(invalid) - 10} more)" if len(invalid) > 10 else ""),
            highlight=False,
        )
    header, rows = table_rows(result, "task_scene")
    marked = " (PARTIAL)" if result.partial else ""
    title = f"{dataset.manifest.name} v{dataset.manifest.version} / {args.split}{marked}"
    _print_table(console, header, rows, title)
    console.print(scope_text(result), style="yellow" if result.partial else None, highlight=False)
    console.print(f"track: {describe(result.track)}", highlight=False, markup=False)
    entries = instruction_type_entries(results) if result.instruction_type is not None else []
    if entries:
        _print_table(console, *instruction_type_table(entries), "PlaceNav by instruction type (SR, SPL in %)")
    written = ", instruction_types.md" if entries else ""
    console.print(f"wrote {out}/metrics.json, tables.md, *.csv{written}, {report.name}", highlight=False)
    return 0


def _run_parser(sub: Subparsers, shared: Shared) -> None:
    """``navverse run-agent``."""
    from navverse.dataset import INSTRUCTION_TYPES, TASKS

    run = command(
        sub, "run-agent", parents=[shared.scene_options],
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
        "--private", metavar="DIR", default=None,
        help=PRIVATE_HELP + " (without it, a private split's public episodes are run: no goals, so no "
        "privileged agent)",
    )  # fmt: skip
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
    run.set_defaults(func=partial(cmd_run_agent, built_dir=shared.built_dir))


def cmd_run_agent(args: argparse.Namespace, console: Console, *, built_dir: Callable[[], Path]) -> int:
    """Run an agent online over a split and write its submission."""
    from rich.progress import BarColumn, MofNCompleteColumn, TextColumn, TimeRemainingColumn

    from navverse.eval.runner import EPISODE_TIMEOUT, STEP_TIMEOUT, run_agent

    dataset = open_dataset(args)
    split_ids = split_of(dataset, args.split)
    embodiment = args.embodiment or dataset.manifest.embodiment
    scene_dirs = dataset_scene_dirs(args, dataset, dataset.episodes(split=args.split), built_dir)
    jobs = args.jobs if args.jobs is not None else (os.cpu_count() or 1)
    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeRemainingColumn())
    label = f"run-agent {args.agent} on {args.split}"
    with show_progress(console, label, unit="episodes", columns=columns) as progress:
        summary = run_agent(
            dataset,
            agent=args.agent,
            split=args.split,
            embodiment=embodiment,
            scene_dirs=scene_dirs,
            out=args.out,
            jobs=jobs,
            limit=args.limit,
            task=args.task,
            seed=args.seed,
            max_steps=args.max_steps,
            terrain_friction=args.friction,
            step_timeout=STEP_TIMEOUT if args.step_timeout is None else args.step_timeout,
            episode_timeout=EPISODE_TIMEOUT if args.episode_timeout is None else args.episode_timeout,
            instruction_type=args.instruction_type,
            progress=progress,
        )
    for episode_id, reason in summary.timeouts[:10]:
        console.print(
            f"agent_timeout: {episode_id}: {reason}",
            style="yellow",
            highlight=False,
            markup=False,
            soft_wrap=True,
        )
    if len(summary.timeouts) > 10:
        console.print(f"agent_timeout: ... and {len(summary.timeouts) - 10} more episodes", style="yellow")
    if summary.log is not None:
        console.print(
            f"the agent's output is in {summary.log}", highlight=False, markup=False, soft_wrap=True
        )
    ended = ", ".join(f"{label} {count}" for label, count in sorted(summary.terminations.items()))
    resumed = f" ({summary.resumed} resumed from an interrupted run)" if summary.resumed else ""
    kind = f", PlaceNav: {args.instruction_type}" if args.instruction_type != "category" else ""
    console.print(
        f"{args.agent} ({embodiment}{kind}): {summary.episodes} episodes{resumed} in "
        f"{summary.seconds:.0f} s; ended: {ended}",
        highlight=False,
        markup=False,
        soft_wrap=True,
    )
    if dataset.has_goals(args.split):
        hint = eval_hint(args, summary.out, partial=summary.episodes < len(split_ids))
        then = f"score it with: {hint}"
    else:
        then = (
            f"the goals of split {args.split!r} are private: submit it to the benchmark's evaluation server "
            f"(POST /api/submissions?split={args.split}; README: An evaluation server)"
        )
    console.print(f"wrote {summary.out}; {then}", highlight=False, markup=False, soft_wrap=True)
    return 0


def eval_hint(args: argparse.Namespace, submission: str | os.PathLike[str], *, partial: bool) -> str:
    """The ``navverse eval`` command that scores what ``run-agent`` (run with ``args``) wrote, runnable as
    printed: the same dataset, split, robot and scene folders, and ``--episodes submitted`` when the run
    covered only part of the split (``--limit``, ``--task``), so that it is not scored as failures."""
    import shlex

    words = ["navverse", "eval", "--dataset", str(args.dataset), "--submission", os.fspath(submission)]
    words += ["--split", args.split]
    if getattr(args, "private", None) is not None:
        words += ["--private", os.fspath(args.private)]
    if args.embodiment is not None:
        words += ["--embodiment", args.embodiment]
    for folder in getattr(args, "scenes", None) or ():
        words += ["--scenes", os.fspath(folder)]
    if partial:
        words += ["--episodes", "submitted"]
    return shlex.join(words)
