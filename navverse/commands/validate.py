"""``navverse validate dataset`` and ``validate submission``, each beside its parser: check a dataset
version or a submission without building (``validate recipe`` is a build command,
:mod:`navverse.cli`). Each command returns the exit code; its imports are inside it, so the
command line starts quickly."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from functools import partial
from pathlib import Path

from rich.console import Console

from navverse.commands.common import (
    DATASET_HELP,
    JOBS_HELP,
    MINI,
    OUTDOOR,
    Shared,
    Subparsers,
    command,
    validate_commands,
)
from navverse.commands.datasets import dataset_scene_dirs, print_problems, problem_count, split_of
from navverse.commands.progress import show_progress

__all__ = ["cmd_validate_dataset", "cmd_validate_submission", "register"]


def register(sub: Subparsers, shared: Shared) -> None:
    """Add ``navverse validate dataset`` and ``validate submission`` to the ``validate`` group of ``sub``."""
    vsub = validate_commands(sub, shared)
    _dataset_parser(vsub, shared)
    _submission_parser(vsub, shared)


def _dataset_parser(vsub: Subparsers, shared: Shared) -> None:
    """``navverse validate dataset``."""
    vdataset = command(
        vsub, "dataset", parents=[shared.scene_options],
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
    vdataset.set_defaults(func=partial(cmd_validate_dataset, built_dir=shared.built_dir))


def cmd_validate_dataset(args: argparse.Namespace, console: Console, *, built_dir: Callable[[], Path]) -> int:
    """Check a dataset: format, files and checksums against the manifest, counts, bounds, with --scenes
    that every scene is found with the manifest's scene hash, and (with --replay) its oracle rollouts
    under physics."""
    from navverse.dataset import local_dataset
    from navverse.episodes.inspect import check_bounds

    dataset = local_dataset(args.dataset)
    dataset.verify()
    episodes = [e for e in dataset.episodes() if not e.withheld]
    violations = [(e.episode_id, r) for e in episodes if (r := check_bounds(e)) is not None]
    for split in sorted(dataset.private_splits):
        checked = "checked against its private file" if dataset.has_goals(split) else "not here, not checked"
        console.print(f"split {split}: goals private ({checked})", highlight=False)
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
        scene_dirs = dataset_scene_dirs(args, dataset, episodes, built_dir)
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
    scene_dirs = dataset_scene_dirs(args, dataset, chosen, built_dir)
    with show_progress(console, "validate dataset: replaying", unit="scenes") as progress:
        progress(0, len(scene_dirs))
        report = replay(
            chosen, scene_dirs, embodiment=dataset.manifest.embodiment, jobs=args.jobs, progress=progress
        )
    console.print(f"replayed oracle rollouts: {report.reached} of {report.replayed} reach a goal")
    for episode_id, reason in report.failures[:10]:
        console.print(f"  {episode_id}: {reason}", highlight=False)
    return bool(report.failures)


def _submission_parser(vsub: Subparsers, shared: Shared) -> None:
    """``navverse validate submission``."""
    vsubmission = command(
        vsub, "submission", parents=[shared.scene_options],
        summary="report every problem of a submission, with line numbers",
        examples=("navverse validate submission run.jsonl",
                  f"navverse validate submission run.jsonl.gz --dataset {MINI} --split eval"),
    )  # fmt: skip
    vsubmission.add_argument("submission", help="JSONL file (optionally .gz), one episode per line")
    vsubmission.add_argument(
        "--dataset", default=None, help="episodes/<name>/v<version> (without it: the format alone)"
    )
    vsubmission.add_argument("--split", default="eval", help="the split it answers (default: eval)")
    vsubmission.set_defaults(func=partial(cmd_validate_submission, built_dir=shared.built_dir))


def _submission_bounds(
    args: argparse.Namespace, dataset, episodes, built_dir: Callable[[], Path] | None, console: Console
) -> dict | None:
    """The box of every episode (its scene's bounds, grown), or None with a note when the scenes are not
    found (--scenes, $NAVVERSE_SCENES, the build store): then only the absolute bound on positions is
    checked."""
    from navverse.errors import NavverseError
    from navverse.eval.submission import MAX_ABS_COORD, episode_bounds

    try:
        return episode_bounds(episodes, dataset_scene_dirs(args, dataset, episodes, built_dir))
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
        print_problems(submission, console)
        console.print(
            f"{args.submission}: {len(submission.records)} valid records; {problem_count(submission)} "
            "problems (no --dataset: episode ids and scene bounds not checked)",
            highlight=False,
            markup=False,
        )
        return 1 if submission.problems else 0
    dataset = Dataset(args.dataset)
    ids = split_of(dataset, args.split)
    episodes = list(dataset.episodes(split=args.split))
    bounds = _submission_bounds(args, dataset, episodes, built_dir, console)
    submission = read_submission(args.submission, episode_ids=ids, bounds=bounds)
    missing = sorted(set(ids) - set(submission.records) - {p.episode_id for p in submission.problems})
    print_problems(submission, console)
    for episode_id in missing[:20]:
        console.print(f"missing: {episode_id}", highlight=False, markup=False)
    if len(missing) > 20:
        console.print(f"missing: ... and {len(missing) - 20} more episodes")
    console.print(
        f"{args.submission}: {len(submission.records)} of {len(ids)} episodes of {args.split} valid; "
        f"{problem_count(submission)} problems, {len(missing)} missing",
        highlight=False,
        markup=False,
    )
    return 1 if submission.problems or missing else 0
