"""``navverse show scene | presets | dataset | episode``, each beside its parser: draw or print what
was built. Each command returns the exit code; its imports are inside it, so the command line starts
quickly."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from functools import partial
from pathlib import Path

from rich.console import Console

from navverse.commands.common import DATASET_HELP, MINI, OUTDOOR, Shared, Subparsers, command, console_table
from navverse.commands.datasets import dataset_scene_dirs

__all__ = ["cmd_show_dataset", "cmd_show_episode", "cmd_show_presets", "cmd_show_scene", "register"]


def register(sub: Subparsers, shared: Shared) -> None:
    """Add ``navverse show WHAT`` to ``sub``."""
    show = command(
        sub, "show", summary="draw or print what was built",
        examples=("navverse show scene office-s1 -o office.png", "navverse show presets",
                  f"navverse show dataset {OUTDOOR}"),
    )  # fmt: skip
    ssub = show.add_subparsers(
        dest="what", required=True, metavar="WHAT", help="what to show (navverse show WHAT --help)"
    )
    _scene_parser(ssub, shared)
    _presets_parser(ssub)
    _dataset_parser(ssub)
    _episode_parser(ssub, shared)


def _scene_parser(ssub: Subparsers, shared: Shared) -> None:
    """``navverse show scene``."""
    scene = command(
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
    scene.set_defaults(func=partial(cmd_show_scene, built_dir=shared.built_dir))


def cmd_show_scene(args: argparse.Namespace, console: Console, *, built_dir: Callable[[], Path]) -> int:
    """Draw a scene's bird's-eye view, with its navmesh when it has one: a built scene's id, or a scene
    directory (one holding ``scene.json``)."""
    from navverse.nav.scene_navmesh import load_scene_navmesh, navmesh_overlay
    from navverse.scene.bev import render_bev
    from navverse.scene.directory import SceneFiles, read_scene
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


def _presets_parser(ssub: Subparsers) -> None:
    """``navverse show presets``."""
    presets = command(
        ssub, "presets", summary="navmesh presets and the scene-type profiles that pick them",
        examples=("navverse show presets",),
    )  # fmt: skip
    presets.set_defaults(func=cmd_show_presets)


def cmd_show_presets(args: argparse.Namespace, console: Console) -> int:
    """Print the navmesh presets and the scene-type profiles that pick them."""
    from dataclasses import fields

    from navverse.nav.settings import PRESETS, NavMeshSettings
    from navverse.scene_types import PROFILES, SceneTypeProfile

    presets = console_table(console, title="navmesh presets (navverse.nav.PRESETS)")
    profiles = console_table(console, title="scene types (navverse.scene_types)")
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


_LISTED_SCENES = 30
"""At most this many scenes, ``show dataset`` lists them by split without ``--scenes``."""


def _dataset_parser(ssub: Subparsers) -> None:
    """``navverse show dataset``."""
    dataset = command(
        ssub, "dataset", summary="episode counts and goal categories of a dataset",
        examples=(f"navverse show dataset {MINI}",
                  "navverse show dataset episodes/navverse-outdoor --top 10",
                  f"navverse show dataset {MINI} --stats --split eval --figure mini-stats.png"),
    )  # fmt: skip
    dataset.add_argument("dataset", help=DATASET_HELP)
    dataset.add_argument("--top", type=int, default=25, help="goal categories listed (default: 25)")
    dataset.add_argument(
        "--scenes", action="store_true",
        help=f"list each split's scenes (listed anyway when there are at most {_LISTED_SCENES})",
    )  # fmt: skip
    dataset.add_argument(
        "--stats", action="store_true",
        help="also per task and scene type: geodesic length and verified duration "
             "(10th percentile, median, 90th percentile) and difficulty tertiles",
    )  # fmt: skip
    dataset.add_argument("--split", default=None, help="the statistics of one split (default: all)")
    dataset.add_argument(
        "--figure", type=Path, default=None, metavar="PNG",
        help="draw the statistics (length and duration distributions, tertiles) into this PNG",
    )  # fmt: skip
    dataset.set_defaults(func=cmd_show_dataset)


def cmd_show_dataset(args: argparse.Namespace, console: Console) -> int:
    """Print a dataset's episode counts and goal categories (and with `--stats` its statistics)."""
    from navverse.dataset import local_dataset
    from navverse.episodes.inspect import category_table, counts_table, scenes_table

    dataset = local_dataset(args.dataset)
    manifest = dataset.manifest
    console.print(counts_table(dataset))
    console.print(scenes_table(dataset))
    console.print(category_table(dataset, top=args.top))
    for task, (low, high) in manifest.difficulty_thresholds.items():
        console.print(f"{task}: easy < {low:.2f} m <= medium < {high:.2f} m <= hard (geodesic length)")
    if args.scenes or sum(map(len, manifest.splits.values())) <= _LISTED_SCENES:
        splits = "; ".join(f"{name}: {', '.join(scenes)}" for name, scenes in manifest.splits.items())
        console.print(f"splits (scene-disjoint): {splits}", highlight=False)
    else:
        console.print("splits are scene-disjoint; --scenes lists each split's scenes", highlight=False)
    if args.stats or args.figure is not None:
        from navverse.episodes.statistics import dataset_statistics, statistics_figure, statistics_table

        stats = dataset_statistics(dataset, split=args.split)
        console.print(statistics_table(stats))
        if args.figure is not None:
            console.print(f"wrote {statistics_figure(stats, args.figure)}", highlight=False, soft_wrap=True)
    return 0


def _episode_parser(ssub: Subparsers, shared: Shared) -> None:
    """``navverse show episode``."""
    episode = command(
        ssub, "episode", parents=[shared.scene_options],
        summary="draw an episode on its scene's bird's-eye view",
        examples=(f"navverse show episode {MINI} office-s1-vln-0003 -o ep.png",
                  f"navverse show episode {OUTDOOR} west-oakland-vln-0000"),
    )  # fmt: skip
    episode.add_argument("dataset", help=DATASET_HELP)
    episode.add_argument("episode_id", help="the episode's id, e.g. office-s1-vln-0003 (see show dataset)")
    episode.add_argument("-o", "--output", help="PNG path (default: <episode_id>.png)")
    episode.set_defaults(func=partial(cmd_show_episode, built_dir=shared.built_dir))


def cmd_show_episode(args: argparse.Namespace, console: Console, *, built_dir: Callable[[], Path]) -> int:
    """Draw one episode on its scene's bird's-eye view."""
    from navverse.dataset import local_dataset
    from navverse.episodes.inspect import draw_episode

    dataset = local_dataset(args.dataset)
    dataset.verify()
    episode = dataset.episode(args.episode_id)
    scene_dir = dataset_scene_dirs(args, dataset, [episode.scene_id], built_dir)[episode.scene_id]
    out = draw_episode(
        scene_dir, episode, dataset.rollout(episode), Path(args.output or f"{args.episode_id}.png")
    )
    text = episode.instruction.instruction_text if episode.instruction else episode.goal_category
    length = "goals private" if episode.info is None else f"{episode.info.geodesic_distance:.1f} m"
    console.print(f"{episode.episode_id} ({episode.task}, {length}): {text}")
    console.print(f"wrote {out}")
    return 0
