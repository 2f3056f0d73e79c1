"""``navverse export scenes | habitat``, each beside its parser: a dataset's parts for use elsewhere
(a scene pack; habitat-lab's layouts). Each command returns the exit code; its imports are inside it, so
the command line starts quickly."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from functools import partial
from pathlib import Path

from rich.console import Console

from navverse.commands.common import (
    DATASET_HELP,
    DATASET_VERSION_HELP,
    MINI,
    OUTDOOR,
    Shared,
    Subparsers,
    command,
)
from navverse.commands.datasets import dataset_scene_dirs

__all__ = ["cmd_export_habitat", "cmd_export_scenes", "register"]


def register(sub: Subparsers, shared: Shared) -> None:
    """Add ``navverse export WHAT`` to ``sub``: one sub-command per format."""
    export = command(
        sub, "export", summary="write a dataset's scenes (or the dataset) for use elsewhere",
        examples=(f"navverse export scenes {MINI} mini-scenes",
                  f"navverse export habitat {MINI} mini-habitat"),
    )  # fmt: skip
    esub = export.add_subparsers(
        dest="what", required=True, metavar="WHAT", help="what to write (navverse export WHAT --help)"
    )
    _scenes_parser(esub, shared)
    _habitat_parser(esub, shared)


EXPORT_SCENES_DESCRIPTION = (
    "Copy the scenes a dataset version (or one split) needs into OUT/<scene_id>/ (scene.json, scene.usdc, "
    "navmesh.bin, navmesh.json, textures/), with OUT/scenes.json listing each scene's hash and file "
    "checksums; each copy is checked against the dataset manifest's scene hash. The scenes are looked "
    "for as --scenes says and must have the dataset's scene hashes, in data/built too. Ship OUT with the "
    "dataset and pass --scenes OUT (or put OUT in $NAVVERSE_SCENES) to show episode, validate dataset, "
    "run-agent and eval."
)


def _scenes_parser(esub: Subparsers, shared: Shared) -> None:
    """``navverse export scenes``."""
    scenes = command(
        esub, "scenes", parents=[shared.scene_options],
        summary="copy the scenes a dataset needs into a scene pack, to use it where the scenes are not built",
        description=EXPORT_SCENES_DESCRIPTION,
        examples=(f"navverse export scenes {MINI} mini-scenes",
                  f"navverse export scenes {OUTDOOR} outdoor-eval-scenes --split eval",
                  f"navverse eval --dataset {MINI} --submission run.jsonl --scenes mini-scenes"),
    )  # fmt: skip
    scenes.add_argument("dataset", help=DATASET_HELP)
    scenes.add_argument("out", help="the pack directory to create (must not exist, or be empty)")
    scenes.add_argument("--split", default=None, help="only the scenes of this split (default: every split)")
    scenes.set_defaults(func=partial(cmd_export_scenes, built_dir=shared.built_dir))


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


def _env_hint(root: Path) -> str:
    from navverse.scene.locate import SCENES_ENV

    return f"{SCENES_ENV}={root.resolve()}"


EXPORT_HABITAT_DESCRIPTION = (
    "Write OUT/objectnav_v1/<split>/ (ObjectNav-v1: the ObjNav and PlaceNav episodes, goals with view points "
    "on the navmesh), OUT/vln_r2r/<split>/ (R2R-VLN: instructions with tokens and vocabulary) and "
    "OUT/scenes/<scene>/ (the scene as GLB, HM3D-style semantic files, the navmesh as habitat-sim's "
    ".navmesh), in habitat's y-up frame: a NavVerse point (x, y, z) is (x, z, -y) there. Load it with "
    "habitat-lab's dataset types ObjectNav-v1 / R2RVLN-v1 "
    "(data_path OUT/objectnav_v1/{split}/{split}.json.gz, scenes_dir OUT/scenes); "
    "scripts/habitat_check.py does so in a separate environment."
)


def _habitat_parser(esub: Subparsers, shared: Shared) -> None:
    """``navverse export habitat``."""
    habitat = command(
        esub, "habitat", parents=[shared.scene_options],
        summary="write a dataset and its scenes in habitat-lab's layouts (ObjectNav-v1, R2R-VLN, GLB)",
        description=EXPORT_HABITAT_DESCRIPTION,
        examples=(f"navverse export habitat {MINI} mini-habitat",
                  f"navverse export habitat {OUTDOOR} outdoor-habitat --scenes outdoor-scenes"),
    )  # fmt: skip
    habitat.add_argument("dataset", help=DATASET_VERSION_HELP)
    habitat.add_argument("out", help="the export directory to create (must not exist, or be empty)")
    habitat.set_defaults(func=partial(cmd_export_habitat, built_dir=shared.built_dir))


def cmd_export_habitat(args: argparse.Namespace, console: Console, *, built_dir: Callable[[], Path]) -> int:
    """Write a dataset version and its scenes in habitat-lab's layouts (ObjectNav-v1, R2R-VLN, GLB scenes
    with semantic files and navmeshes)."""
    from navverse.dataset import Dataset
    from navverse.export.habitat import export_habitat

    dataset = Dataset(args.dataset)
    dataset.verify()
    scene_dirs = dataset_scene_dirs(args, dataset, dataset.episodes(), built_dir)
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
