"""``navverse review DATASET``: serve the review page of a dataset version until Ctrl-C.

:func:`cmd_review` is the command, :func:`register` adds its parser (called by
:func:`navverse.cli.build_parser`); :func:`open_review` does its work short of serving, so tests and
other tools can start the same server in a thread.
"""

from __future__ import annotations

import argparse
import os
import webbrowser
from collections.abc import Callable, Sequence
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

from rich.console import Console

from navverse.errors import NavverseError

if TYPE_CHECKING:
    from navverse.commands.common import Shared, Subparsers

__all__ = ["cmd_review", "open_review", "register"]


def _warn(text: str) -> None:
    from navverse.commands.common import console as terminal_console

    terminal_console(stderr=True).print(
        f"warning: {text}", style="yellow", highlight=False, markup=False, soft_wrap=True
    )


def _workspace_root(built_dir: Callable[[], Path]) -> Path:
    """The workspace's root: the folder holding ``data/built``."""
    return built_dir().parent.parent


def _dataset_path(given: str, built_dir: Callable[[], Path]) -> Path:
    """A dataset version or folder as given, else ``episodes/<given>`` of the workspace (a bare name)."""
    path = Path(given)
    if path.exists() or os.sep in given or "/" in given:
        return path
    return _workspace_root(built_dir) / "episodes" / given


def open_review(
    dataset_path: str | os.PathLike[str],
    *,
    built_dir: Callable[[], Path],
    recipe: str | os.PathLike[str] | None = None,
    scenes: Sequence[str | os.PathLike[str]] = (),
    port: int = 0,
):
    """The review server of a dataset version, bound and ready to serve (not started).

    Parameters
    ----------
    dataset_path : path
        A dataset version (``episodes/<name>/v<version>``) or its folder (the newest version is taken).
    built_dir : callable
        Returns the workspace's build store (``data/built``); its workspace holds the recipe and the
        scenes when they are not found elsewhere.
    recipe : path, optional
        The dataset's recipe; by default the manifest's ``recipe`` in the workspace. The decisions
        file is ``<name>.review.yml`` beside it.
    scenes : sequence of path
        Scene packs or build stores searched before ``$NAVVERSE_SCENES`` and the workspace's store.
    port : int
        Port on 127.0.0.1; 0 picks a free one.

    Returns
    -------
    ThreadingHTTPServer
        With ``.state`` (:class:`navverse.review.server.ReviewState`).

    Raises
    ------
    NavverseError
        If the dataset is malformed, its recipe or scenes are not found, or the decisions file is
        malformed.
    """
    from navverse.dataset import local_dataset
    from navverse.review.decisions import review_path
    from navverse.review.server import ReviewState, make_server
    from navverse.scene.locate import find_scene_dirs

    dataset = local_dataset(dataset_path)
    dataset.verify()
    manifest = dataset.manifest
    recipe_file = Path(recipe) if recipe is not None else _workspace_root(built_dir) / manifest.recipe
    if not recipe_file.is_file():
        raise NavverseError(
            f"the recipe of {manifest.name} v{manifest.version}, {recipe_file}, is not here: run from its "
            "workspace or pass --recipe recipes/datasets/<name>.yaml (the decisions file goes beside it)"
        )
    scene_ids = sorted({s for members in manifest.splits.values() for s in members})
    scene_dirs = find_scene_dirs(
        scene_ids,
        search=scenes,
        hashes=manifest.scene_hashes,
        built_dir=built_dir,
        rebuilt="warn",
        warn=_warn,
    )
    state = ReviewState(dataset, scene_dirs, review_path(recipe_file, manifest.name), recipe=recipe_file)
    try:
        return make_server(state, port=port)
    except OSError as exc:
        raise NavverseError(f"cannot listen on 127.0.0.1 port {port}: {exc.strerror or exc}") from None


def register(sub: Subparsers, shared: Shared) -> None:
    """Add ``navverse review DATASET`` to ``sub``: the local page where a person accepts or rejects
    episodes. (:mod:`navverse.cli` is imported here, so the review server does not load it.)"""
    from navverse.commands.common import MINI, command

    review = command(
        sub, "review", parents=[shared.scene_options],
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
    review.set_defaults(func=partial(cmd_review, built_dir=shared.built_dir))


def cmd_review(args: argparse.Namespace, console: Console, *, built_dir: Callable[[], Path]) -> int:
    """Serve the review page of ``args.dataset`` on 127.0.0.1 until Ctrl-C; decisions are saved as made.

    Arguments read: ``dataset`` (a version, its folder, or a name under the workspace's ``episodes/``),
    ``port`` (0: any free one), ``no_browser``, ``recipe`` (optional) and ``scenes`` (optional list).
    Returns 0 when stopped with Ctrl-C (every decision is already saved).
    """
    server = open_review(
        _dataset_path(args.dataset, built_dir),
        built_dir=built_dir,
        recipe=getattr(args, "recipe", None),
        scenes=getattr(args, "scenes", None) or (),
        port=getattr(args, "port", 0) or 0,
    )
    state = server.state
    url = f"http://127.0.0.1:{server.server_address[1]}/"
    manifest = state.dataset.manifest
    console.print(
        f"reviewing {manifest.name} v{manifest.version} ({len(state.episodes)} episodes)", highlight=False
    )
    console.print(f"decisions are saved to {state.decisions_path}", highlight=False, soft_wrap=True)
    if not _names_review(state.recipe, state.decisions_path.name):
        console.print(
            f"to leave the rejected episodes out of the next build, add to {state.recipe}:\n"
            f"  stages: {{package_dataset: {{review: {state.decisions_path.name}}}}}",
            highlight=False,
            markup=False,
        )
    console.print(f"open {url} — Ctrl-C to stop", highlight=False, soft_wrap=True)
    if not getattr(args, "no_browser", False):
        webbrowser.open(url)
    try:
        server.serve_forever()
    except KeyboardInterrupt:
        console.print(
            f"stopped; {len(state.review.decisions)} decisions in {state.decisions_path}", highlight=False
        )
    finally:
        server.server_close()
    return 0


def _names_review(recipe: Path, file_name: str) -> bool:
    """Whether the recipe text names the decisions file (a hint only: the build validates the recipe)."""
    try:
        return file_name in recipe.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return False
