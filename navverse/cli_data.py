"""The data and evaluation commands of ``navverse``: show, validate dataset / submission, eval, run-agent,
export scenes.

They read datasets, submissions and built scenes, never the build engine: :mod:`navverse.cli`, the
composition root, parses the arguments and passes the commands that need built scenes a ``built_dir``
callable returning the build store (``data/built``), called only once a scene is needed, so the others
run anywhere. A dataset's scenes are looked for along the search path of
:func:`navverse.scene.locate.find_scene_dirs`: ``--scenes DIR`` (``args.scenes``), ``$NAVVERSE_SCENES``,
then that build store. Each command returns the exit code; its imports are inside it, so the command
line starts quickly.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

from rich.console import Console

__all__ = [
    "PLAIN_PROGRESS_SECONDS",
    "PlainProgress",
    "cmd_eval",
    "cmd_export_scenes",
    "cmd_run_agent",
    "cmd_show_dataset",
    "cmd_show_episode",
    "cmd_show_scene",
    "cmd_validate_dataset",
    "cmd_validate_submission",
]


PLAIN_PROGRESS_SECONDS = 10.0
"""Without a terminal, the least wall time between two progress lines (s)."""

PLAIN_PROGRESS_PARTS = 20
"""Without a terminal, the least work between two progress lines: this fraction of the total (1/20)."""


def _stderr_line(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def _duration(seconds: float) -> str:
    """A wall time for people: ``45 s``, ``9 min``, ``2.5 h``."""
    if seconds < 99.5:
        return f"{seconds:.0f} s"
    if seconds < 99.5 * 60:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


class PlainProgress:
    """Progress as plain lines, for output that is not a terminal (a log file, a pipe, a batch job).

    Called as ``progress(done, total)``. A line is written once both ``every`` more items are done and
    ``seconds`` have passed since the last line (whichever comes later), and once when the last item is
    done, e.g. ``run-agent oracle on eval: 12/157 episodes, 45 s, ~9 min left``. The time left is
    estimated from the rate since the first call, so items already done then (resumed from an
    interrupted run) do not count.

    Parameters
    ----------
    label : str
        What is going on; starts each line.
    unit : str
        What is counted (``episodes``, ``scenes``).
    write : callable, optional
        Called with each line (default: print it to stderr and flush).
    every : int, optional
        Items between lines (default: the total / :data:`PLAIN_PROGRESS_PARTS`, at least 1).
    seconds : float, optional
        Wall time between lines (default: :data:`PLAIN_PROGRESS_SECONDS`).
    clock : callable, optional
        Seconds of a monotonic clock (default: :func:`time.monotonic`).
    """

    def __init__(
        self,
        label: str,
        *,
        unit: str,
        write: Callable[[str], None] = _stderr_line,
        every: int | None = None,
        seconds: float | None = None,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.label, self.unit, self.write, self.every, self.clock = label, unit, write, every, clock
        self.seconds = PLAIN_PROGRESS_SECONDS if seconds is None else seconds
        self._start: tuple[float, int] | None = None
        self._last: tuple[float, int] = (0.0, 0)
        self._finished = False

    def __call__(self, done: int, total: int) -> None:
        """Take the count of items done of ``total``; write a line when one is due."""
        now = self.clock()
        if self._start is None:
            self._start = self._last = (now, done)
        every = self.every if self.every is not None else max(1, total // PLAIN_PROGRESS_PARTS)
        last_time, last_done = self._last
        finished = total > 0 and done >= total
        due = done - last_done >= every and now - last_time >= self.seconds
        if (finished and not self._finished) or (due and not finished):
            self.write(self.line(done, total, now))
            self._last = (now, done)
        self._finished = self._finished or finished

    def line(self, done: int, total: int, now: float) -> str:
        """The progress line for ``done`` of ``total`` items at clock time ``now``."""
        start_time, start_done = self._start if self._start is not None else (now, done)
        elapsed = now - start_time
        text = f"{self.label}: {done}/{total} {self.unit}, {_duration(elapsed)}"
        if done < total and done > start_done and elapsed > 0:
            left = (total - done) * elapsed / (done - start_done)
            text += f", ~{_duration(left)} left"
        return text


@contextmanager
def _progress(
    console: Console, label: str, *, unit: str, columns: tuple = ()
) -> Iterator[Callable[[int, int], None]]:
    """A ``progress(done, total)`` callable: a rich bar on a terminal (with ``columns``, or rich's
    default ones), plain lines on stderr otherwise (:class:`PlainProgress`), where a bar is not shown."""
    if not console.is_terminal:
        yield PlainProgress(label, unit=unit)
        return
    from rich.progress import Progress

    with Progress(*columns, console=console, transient=True) as bar:
        task = bar.add_task(label, total=None)
        yield lambda done, total: bar.update(task, completed=done, total=total)


def _warn(text: str) -> None:
    Console(stderr=True).print(
        f"warning: {text}", style="yellow", highlight=False, markup=False, soft_wrap=True
    )


def _dataset_scene_dirs(
    args: argparse.Namespace, dataset, scenes, built_dir: Callable[[], Path] | None
) -> dict[str, Path]:
    """The directories of the dataset's scenes ``scenes`` (episodes or ids), along the search path:
    ``--scenes``, ``$NAVVERSE_SCENES``, the workspace's build store. A scene must have the manifest's
    scene hash, but for one rebuilt in this workspace's store since the dataset was packaged: it is used
    with a warning, as before scenes could come from elsewhere."""
    from navverse.scene.locate import find_scene_dirs

    return find_scene_dirs(
        scenes,
        search=getattr(args, "scenes", None) or (),
        hashes=dataset.manifest.scene_hashes,
        built_dir=built_dir,
        rebuilt="warn",
        warn=_warn,
    )


def cmd_show_scene(args: argparse.Namespace, console: Console, *, built_dir: Callable[[], Path]) -> int:
    """Draw a scene's bird's-eye view, with its navmesh when it has one: a built scene's id, or a scene
    directory (one holding ``scene.json``)."""
    from navverse.nav.scene_navmesh import load_scene_navmesh, navmesh_overlay
    from navverse.scene import SceneFiles, read_scene, render_bev
    from navverse.scene.locate import built_scene_dir

    given = Path(args.scene)
    if SceneFiles(given).annotations.is_file():
        scene_dir, name = given, given.resolve().name
    else:
        scene_dir, name = built_scene_dir(built_dir(), args.scene), args.scene
    out = Path(args.output or f"{name}-bev.png")
    has_navmesh = SceneFiles(scene_dir).navmesh.is_file()
    overlays = [navmesh_overlay(load_scene_navmesh(scene_dir))] if has_navmesh else []
    render_bev(read_scene(scene_dir), out, meters_per_pixel=args.meters_per_pixel, overlays=overlays)
    console.print(f"wrote {out}")
    return 0


def cmd_show_presets(args: argparse.Namespace, console: Console) -> int:
    """Print the navmesh presets and the scene-type profiles that pick them."""
    from dataclasses import fields

    from rich.table import Table

    from navverse.nav.settings import PRESETS, NavMeshSettings
    from navverse.scene_types import PROFILES, SceneTypeProfile

    presets = Table(title="navmesh presets (navverse.nav.PRESETS)")
    profiles = Table(title="scene types (navverse.scene_types)")
    presets.add_column("setting")
    profiles.add_column("profile")
    for name in PRESETS:
        presets.add_column(name, justify="right")
    for name in PROFILES:
        profiles.add_column(name, justify="right")
    for field in NavMeshSettings.model_fields:
        presets.add_row(field, *(str(getattr(preset, field)) for preset in PRESETS.values()))
    for field in fields(SceneTypeProfile):
        if field.name != "name":
            profiles.add_row(field.name, *(str(getattr(p, field.name)) for p in PROFILES.values()))
    console.print(presets, profiles)
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


def cmd_show_episode(args: argparse.Namespace, console: Console, *, built_dir: Callable[[], Path]) -> int:
    """Draw one episode on its scene's bird's-eye view."""
    from navverse.dataset import Dataset
    from navverse.episodes.inspect import draw_episode

    dataset = Dataset(args.dataset)
    dataset.verify()
    episode = dataset.episode(args.episode_id)
    scene_dir = _dataset_scene_dirs(args, dataset, [episode.scene_id], built_dir)[episode.scene_id]
    out = draw_episode(
        scene_dir, episode, dataset.rollout(episode), Path(args.output or f"{args.episode_id}.png")
    )
    text = episode.instruction.instruction_text if episode.instruction else episode.goal_category
    console.print(f"{episode.episode_id} ({episode.task}, {episode.info.geodesic_distance:.1f} m): {text}")
    console.print(f"wrote {out}")
    return 0


def cmd_validate_dataset(args: argparse.Namespace, console: Console, *, built_dir: Callable[[], Path]) -> int:
    """Check a dataset: format, files and checksums against the manifest, counts, bounds, with --scenes
    that every scene is found with the manifest's scene hash, and (with --replay) its oracle rollouts
    under physics."""
    from navverse.dataset import Dataset
    from navverse.episodes.inspect import check_bounds

    dataset = Dataset(args.dataset)
    dataset.verify()
    episodes = list(dataset.episodes())
    violations = [(e.episode_id, r) for e in episodes if (r := check_bounds(e)) is not None]
    console.print(
        f"{dataset.root}: format {dataset.manifest.format_version}, {len(episodes)} episodes; "
        f"{len(dataset.manifest.files)} files, checksums and counts match the manifest "
        f"(manifest.json sha256 {dataset.manifest_sha256})",
        highlight=False,
    )
    console.print(
        f"distance and duration bounds: {len(episodes) - len(violations)} of {len(episodes)} keep them"
    )
    for episode_id, reason in violations[:10]:
        console.print(f"  {episode_id}: {reason}", highlight=False)
    failures = bool(violations)
    if getattr(args, "scenes", None) and not args.replay:
        scene_dirs = _dataset_scene_dirs(args, dataset, episodes, built_dir)
        console.print(f"scenes: {len(scene_dirs)} found", highlight=False)
        for scene_id, scene_dir in scene_dirs.items():
            console.print(f"  {scene_id}: {scene_dir}", highlight=False, markup=False, soft_wrap=True)
    if args.replay:
        failures = _replay(args, console, dataset, episodes, built_dir) or failures
    return 1 if failures else 0


def _replay(args: argparse.Namespace, console: Console, dataset, episodes: list, built_dir) -> bool:
    """Run the oracle rollouts of ``--replay`` N sampled episodes (or all) again; True if one fails."""
    import numpy as np

    from navverse.episodes.inspect import replay

    chosen = episodes
    if args.replay != "all":
        count = int(args.replay)
        rng = np.random.default_rng(args.seed)
        chosen = [
            episodes[i] for i in sorted(rng.choice(len(episodes), min(count, len(episodes)), replace=False))
        ]
    scene_dirs = _dataset_scene_dirs(args, dataset, chosen, built_dir)
    with _progress(console, "validate dataset: replaying", unit="scenes") as progress:
        progress(0, len(scene_dirs))
        report = replay(
            chosen, scene_dirs, embodiment=dataset.manifest.embodiment, jobs=args.jobs, progress=progress
        )
    console.print(f"replayed oracle rollouts: {report.reached} of {report.replayed} reach a goal")
    for episode_id, reason in report.failures[:10]:
        console.print(f"  {episode_id}: {reason}", highlight=False)
    return bool(report.failures)


def _split_of(dataset, split: str) -> list[str]:
    """The episode ids of a split, or a DatasetError naming the splits there are."""
    from navverse.dataset import DatasetError

    if split not in dataset.splits:
        raise DatasetError(f"{dataset.root} has no split {split!r}; it has: {', '.join(dataset.splits)}")
    return [e.episode_id for e in dataset.episodes(split=split)]


def _submission_bounds(
    args: argparse.Namespace, dataset, episodes, built_dir: Callable[[], Path] | None, console: Console
) -> dict | None:
    """The box of every episode (its scene's bounds, grown), or None with a note when the scenes are not
    found (--scenes, $NAVVERSE_SCENES, the build store): then only the absolute bound on positions is
    checked."""
    from navverse.errors import NavverseError
    from navverse.eval.submission import MAX_ABS_COORD, episode_bounds

    try:
        return episode_bounds(episodes, _dataset_scene_dirs(args, dataset, episodes, built_dir))
    except NavverseError as exc:
        why = str(exc)
    console.print(
        f"note: the scenes' bounds are not checked, positions only within ±{MAX_ABS_COORD:g} m "
        f"(the scenes are needed: {why})",
        highlight=False,
        markup=False,
    )
    return None


def cmd_validate_submission(
    args: argparse.Namespace, console: Console, *, built_dir: Callable[[], Path] | None = None
) -> int:
    """Report every problem of a submission: against a dataset split when ``--dataset`` is given (episode
    ids, and positions within the scenes' bounds when the scenes are built), else its format alone."""
    from navverse.dataset import Dataset
    from navverse.eval.submission import read_submission

    if getattr(args, "dataset", None) is None:
        submission = read_submission(args.submission)
        _print_problems(submission, console)
        console.print(
            f"{args.submission}: {len(submission.records)} valid records; {_problem_count(submission)} "
            "problems (no --dataset: episode ids and scene bounds not checked)",
            highlight=False,
            markup=False,
        )
        return 1 if submission.problems else 0
    dataset = Dataset(args.dataset)
    ids = _split_of(dataset, args.split)
    episodes = list(dataset.episodes(split=args.split))
    bounds = _submission_bounds(args, dataset, episodes, built_dir, console)
    submission = read_submission(args.submission, episode_ids=ids, bounds=bounds)
    missing = sorted(set(ids) - set(submission.records) - {p.episode_id for p in submission.problems})
    _print_problems(submission, console)
    for episode_id in missing[:20]:
        console.print(f"missing: {episode_id}", highlight=False, markup=False)
    if len(missing) > 20:
        console.print(f"missing: ... and {len(missing) - 20} more episodes")
    console.print(
        f"{args.submission}: {len(submission.records)} of {len(ids)} episodes of {args.split} valid; "
        f"{_problem_count(submission)} problems, {len(missing)} missing",
        highlight=False,
        markup=False,
    )
    return 1 if submission.problems or missing else 0


def _problem_count(submission) -> int:
    return len(submission.problems) + submission.omitted


def _print_problems(submission, console: Console) -> None:
    for problem in submission.problems:
        console.print(str(problem), highlight=False, markup=False)
    if submission.omitted:
        console.print(f"... and {submission.omitted} more problems", highlight=False, markup=False)


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

    ids = _split_of(dataset, args.split)
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


def _score_for_eval(args: argparse.Namespace, console: Console, dataset, submissions: list, scene_dirs: dict):
    """Each submission's :class:`~navverse.eval.scoring.EvalResult`, showing progress."""
    from navverse.eval.scoring import score

    results = []
    for submission in submissions:
        with _progress(console, f"eval: scoring {submission.path.name}", unit="episodes") as progress:
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
                )
            )
    return results


def _print_table(console: Console, header: list[str], rows: list[list[str]], title: str) -> None:
    from rich.table import Table

    table = Table(title=title)
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
    from navverse.dataset import Dataset
    from navverse.eval.protocol import describe
    from navverse.eval.report import write_report
    from navverse.eval.tables import (
        instruction_type_entries,
        instruction_type_table,
        scope_text,
        table_rows,
        write_outputs,
    )

    _check_out_dir(args.out)
    dataset = Dataset(args.dataset)
    dataset.verify()
    _split_of(dataset, args.split)
    scene_dirs = _dataset_scene_dirs(args, dataset, dataset.episodes(split=args.split), built_dir)
    submissions = _read_for_eval(args, dataset, scene_dirs)
    results = _score_for_eval(args, console, dataset, submissions, scene_dirs)
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
    with _progress(console, "eval: drawing the report", unit="episodes") as progress:
        progress(0, len(result.episodes))
        report = write_report(
            result,
            dataset=dataset,
            submission=submission,
            scene_dirs=scene_dirs,
            out_dir=Path(out),
            embodiment=args.embodiment,
            progress=progress,
        )
    if submission.problems:
        count = _problem_count(submission)
        console.print(f"[yellow]{count} submission problems[/] (listed in metrics.json):")
        for problem in submission.problems[:10]:
            console.print(f"  {problem}", highlight=False, markup=False)
    for other in submissions[1:]:
        if other.problems:
            console.print(
                f"{_problem_count(other)} problems in {other.path} (see `navverse validate submission`)",
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
    partial = " (PARTIAL)" if result.partial else ""
    title = f"{dataset.manifest.name} v{dataset.manifest.version} / {args.split}{partial}"
    _print_table(console, header, rows, title)
    console.print(scope_text(result), style="yellow" if result.partial else None, highlight=False)
    console.print(f"track: {describe(result.track)}", highlight=False, markup=False)
    entries = instruction_type_entries(results) if result.instruction_type is not None else []
    if entries:
        _print_table(console, *instruction_type_table(entries), "PlaceNav by instruction type (SR, SPL in %)")
    written = ", instruction_types.md" if entries else ""
    console.print(f"wrote {out}/metrics.json, tables.md, *.csv{written}, {report.name}", highlight=False)
    return 0


def cmd_run_agent(args: argparse.Namespace, console: Console, *, built_dir: Callable[[], Path]) -> int:
    """Run an agent online over a split and write its submission."""
    from rich.progress import BarColumn, MofNCompleteColumn, TextColumn, TimeRemainingColumn

    from navverse.dataset import Dataset
    from navverse.eval.runner import EPISODE_TIMEOUT, STEP_TIMEOUT, run_agent

    dataset = Dataset(args.dataset)
    dataset.verify()
    _split_of(dataset, args.split)
    embodiment = args.embodiment or dataset.manifest.embodiment
    scene_dirs = _dataset_scene_dirs(args, dataset, dataset.episodes(split=args.split), built_dir)
    jobs = args.jobs if args.jobs is not None else (os.cpu_count() or 1)
    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeRemainingColumn())
    label = f"run-agent {args.agent} on {args.split}"
    with _progress(console, label, unit="episodes", columns=columns) as progress:
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
    console.print(
        f"wrote {summary.out}; score it with: navverse eval --dataset {args.dataset} "
        f"--submission {summary.out} --split {args.split}",
        highlight=False,
        markup=False,
        soft_wrap=True,
    )
    return 0


def cmd_export_scenes(args: argparse.Namespace, console: Console, *, built_dir: Callable[[], Path]) -> int:
    """Copy the scenes a dataset (or one split) needs into a scene pack, checked against the manifest's
    scene hashes, for ``--scenes`` on a machine without the workspace."""
    from rich.progress import BarColumn, DownloadColumn, Progress, TextColumn, TimeRemainingColumn

    from navverse.export.scene_pack import export_scene_pack

    columns = (TextColumn("{task.description}"), BarColumn(), DownloadColumn(), TimeRemainingColumn())
    with Progress(*columns, console=console, transient=True) as bar:
        task = bar.add_task("copying scenes", total=None)
        pack = export_scene_pack(
            args.dataset,
            args.out,
            split=args.split,
            search=getattr(args, "scenes", None) or (),
            built_dir=built_dir,
            progress=lambda done, total: bar.update(task, completed=done, total=total),
        )
    size = pack.bytes / 1e6
    console.print(
        f"wrote {pack.root}: {len(pack.scenes)} scenes, {pack.files} files, {size:.1f} MB, scene hashes "
        f"checked against the dataset's; use it with: --scenes {pack.root} (or {_env_hint(pack.root)})",
        highlight=False,
        markup=False,
        soft_wrap=True,
    )
    return 0


def cmd_export_habitat(args: argparse.Namespace, console: Console, *, built_dir: Callable[[], Path]) -> int:
    """Write a dataset version and its scenes in habitat-lab's layouts (ObjectNav-v1, R2R-VLN, GLB scenes
    with semantic files and navmeshes)."""
    from navverse.dataset import Dataset
    from navverse.export.habitat import export_habitat

    dataset = Dataset(args.dataset)
    dataset.verify()
    scene_dirs = _dataset_scene_dirs(args, dataset, dataset.episodes(), built_dir)
    with console.status("exporting for habitat-lab") as status:
        done = export_habitat(
            Path(args.dataset),
            Path(args.out),
            scenes=scene_dirs.__getitem__,
            progress=lambda line: status.update(f"exporting for habitat-lab: {line}"),
        )
    objectnav, vln = sum(done.objectnav.values()), sum(done.vln.values())
    console.print(
        f"wrote {done.root}: {objectnav} ObjectNav-v1 and {vln} R2R-VLN episodes over {len(done.scenes)} "
        f"scenes; in habitat-lab set dataset.data_path to "
        f"{done.root}/objectnav_v1/{{split}}/{{split}}.json.gz (or vln_r2r/...) and dataset.scenes_dir to "
        f"{done.root}/scenes",
        highlight=False,
        markup=False,
        soft_wrap=True,
    )
    return 0


def _env_hint(root: Path) -> str:
    from navverse.scene.locate import SCENES_ENV

    return f"{SCENES_ENV}={root.resolve()}"
