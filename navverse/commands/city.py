"""``navverse city windows``: the windows of an OpenStreetMap file most worth building, as a table.

The ranking is :func:`navverse.city.osm.windows.rank_windows` (one streamed read of the file). After
the table comes the scene recipe of the best window, ready to save, and the command that builds it:
in a workspace, the recipe goes to its ``recipes/scenes/`` and names the file relative to it (or by
its absolute path, with ``--allow-read``, when the file lies outside the workspace); elsewhere, the
``navverse init`` command that makes a workspace around that window. ``--thumbnails DIR`` reads each
window's city map and draws it (:mod:`navverse.city.map_picture`): ``DIR/<rank>.png`` and the
mosaic of them all, ``DIR/windows.png``.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shlex
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

from rich.console import Console

from navverse.commands.common import Shared, Subparsers, command, console_table
from navverse.commands.progress import PLAIN_PROGRESS_SECONDS, show_progress
from navverse.commands.workspace import scene_name
from navverse.errors import NavverseError

if TYPE_CHECKING:
    from navverse.city.map import CityMap
    from navverse.city.osm.windows import WindowRank, WindowRanking

__all__ = ["RecipeAdvice", "cmd_city_windows", "recipe_advice", "register"]

THUMBNAIL_PIXELS = 600
"""The side of a window's thumbnail (px)."""
MOSAIC_TILE_PIXELS = 300
"""The side of a window's tile in the mosaic ``windows.png`` (px)."""


def register(sub: Subparsers, shared: Shared) -> None:
    """Add ``navverse city windows``."""
    city = command(
        sub, "city", summary="help author city recipes from OpenStreetMap files",
        examples=("navverse city windows data/raw/osm/munich-altstadt.osm.pbf",),
    )  # fmt: skip
    what = city.add_subparsers(
        dest="what", required=True, metavar="WHAT", help="what to do (navverse city WHAT --help)"
    )
    windows = command(
        what, "windows", summary="rank the windows of an OSM file by buildings, POIs and street length",
        description="Rank the square windows of an OSM file by buildings, POIs (shops, amenities, crafts, "
        "offices) and street length (roads and walkways), best first, none overlapping another, in one "
        "streamed read of the file; then print the scene recipe of the best window and the command that "
        "builds it. The score is the mean of a window's three measures, each as a fraction of the most "
        "any window of the file has.",
        examples=("navverse city windows data/raw/osm/munich-altstadt.osm.pbf",
                  "navverse city windows data/raw/osm/berlin-mitte.osm.xml.gz --size 300 --top 5 "
                  "--thumbnails berlin"),
    )  # fmt: skip
    windows.add_argument(
        "file", metavar="FILE", type=Path,
        help="an OpenStreetMap file (.osm, .osm.xml, .osm.gz, .osm.xml.gz, .osm.bz2, .osm.pbf)",
    )  # fmt: skip
    windows.add_argument(
        "--size", type=float, default=500.0, metavar="M",
        help="the windows' side (m; default 500, from 50 to 50000)",
    )  # fmt: skip
    windows.add_argument(
        "--top", type=int, default=10, metavar="N", help="windows to list (default 10, at most 100)"
    )
    windows.add_argument(
        "--thumbnails", type=Path, default=None, metavar="DIR",
        help=f"draw each window's map to DIR/<rank>.png ({THUMBNAIL_PIXELS} px) and all of them to "
        "DIR/windows.png (reads the file once more per window)",
    )  # fmt: skip
    windows.set_defaults(func=partial(cmd_city_windows, built_dir=shared.built_dir))


@contextmanager
def _scan_progress(console: Console, label: str) -> Iterator[Callable[[str, int], None]]:
    """``progress(phase, objects)`` of a read whose length is not known ahead: a spinner with the count
    on a terminal, else a line on stderr at most every :data:`PLAIN_PROGRESS_SECONDS` seconds."""
    if not console.is_terminal:
        start, last = time.monotonic(), [time.monotonic()]

        def line(phase: str, done: int) -> None:
            now = time.monotonic()
            if now - last[0] >= PLAIN_PROGRESS_SECONDS:
                print(f"{label}: {done:,} OSM objects read, {now - start:.0f} s", file=sys.stderr, flush=True)
                last[0] = now

        yield line
        return
    from rich.progress import Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

    columns = (
        SpinnerColumn(),
        TextColumn("{task.description}: {task.completed:,} OSM objects"),
        TimeElapsedColumn(),
    )
    with Progress(*columns, console=console, transient=True) as bar:
        task = bar.add_task(label, total=None)
        yield lambda phase, done: bar.update(task, completed=done)


def _size_text(value: float) -> str:
    """A length as a recipe writes it: no trailing ``.0``."""
    return f"{value:.0f}" if value == int(value) else repr(value)


def _yaml_path(path: str) -> str:
    """A path as a YAML scalar: as it is when plain, else quoted (JSON strings are YAML)."""
    return path if re.fullmatch(r"[A-Za-z0-9_./~-]+", path) else json.dumps(path)


@dataclass(frozen=True)
class RecipeAdvice:
    """The recipe of a window and how to build it.

    Attributes
    ----------
    name : str
        The target id (the recipe file's stem).
    text : str
        The recipe.
    save_as : Path or None
        Where to save it in this workspace; None without a workspace.
    commands : tuple of str
        The commands to run then, each runnable as printed.
    """

    name: str
    text: str
    save_as: Path | None
    commands: tuple[str, ...]


def _shown(path: Path) -> str:
    """A path as the user reaches it from here: relative below the current folder, else absolute."""
    here = Path.cwd().resolve()
    return str(path.relative_to(here)) if path.is_relative_to(here) else str(path)


def _free_folder(name: str) -> str:
    """``name``, or ``name-2``, ``name-3``... the first that is not a non-empty folder or a file here."""
    candidate, n = name, 1
    while Path(candidate).exists() and not (Path(candidate).is_dir() and not any(Path(candidate).iterdir())):
        n += 1
        candidate = f"{name}-{n}"
    return candidate


def recipe_advice(ranking: WindowRanking, window: WindowRank, *, workspace_root: Path | None) -> RecipeAdvice:
    """The scene recipe of ``window`` (extending the ``outdoor-city`` preset) and the commands that build it.

    Parameters
    ----------
    ranking : WindowRanking
        What the window was ranked in (the file, its name).
    window : WindowRank
        The window.
    workspace_root : Path or None
        The workspace the recipe is for: it goes to ``recipes/scenes/NAME.yaml`` there and names the
        file relative to that folder when the file lies inside the workspace (recipes may read only
        files inside it, or in a folder allowed with ``--allow-read``). None: no workspace here; the
        commands make one with ``navverse init``.
    """
    source = ranking.path.resolve()
    width, height = (_size_text(v) for v in window.size_m)
    name = f"{scene_name(ranking.path)}-{_size_text(ranking.size_m)}m"  # named as the user names the file
    scenes = workspace_root.resolve() / "recipes" / "scenes" if workspace_root is not None else None
    inside = workspace_root is not None and source.is_relative_to(workspace_root.resolve())
    written = os.path.relpath(source, scenes) if scenes is not None and inside else str(source)
    lat, lon = window.center
    text = (
        "description: >\n"
        f"  {name}: a {width} m x {height} m window of {ranking.path.name} (OpenStreetMap, ODbL) with\n"
        f"  {window.buildings} buildings, {window.pois} POIs and {window.street_km:.1f} km of streets "
        "(navverse city windows).\n"
        "extends: outdoor-city\n"
        "stages:\n"
        "  osm_city:\n"
        f"    source: {_yaml_path(written)}\n"
        f"    center: [{lat:.6f}, {lon:.6f}]\n"
        f"    size_m: [{width}, {height}]\n"
    )
    if scenes is None:
        folder = _free_folder(name)
        size = width if width == height else f"{width} {height}"
        init = (
            f"navverse init {shlex.quote(folder)} --city {shlex.quote(str(source))} "
            f"--center {lat:.6f} {lon:.6f} --size {size} --name {name}"
        )
        return RecipeAdvice(name, text, None, (init, f"cd {shlex.quote(folder)}", f"navverse build {name}"))
    build = f"navverse build {name}"
    if not inside:
        build += f" --allow-read {shlex.quote(str(source.parent))}"
    return RecipeAdvice(name, text, scenes / f"{name}.yaml", (build,))


def _workspace_root(built_dir: Callable[[], Path]) -> Path | None:
    """The workspace found from here (the folder holding ``data/built``), or None."""
    try:
        return built_dir().parent.parent
    except NavverseError:
        return None


def _print_table(console: Console, ranking: WindowRanking) -> None:
    east, north = ranking.extent_m
    console.print(
        f"{ranking.path.name}: {ranking.buildings:,} buildings, {ranking.pois:,} POIs and "
        f"{ranking.street_m / 1000.0:,.1f} km of streets over "
        f"{east / 1000.0:.1f} km x {north / 1000.0:.1f} km",
        highlight=False,
        markup=False,
        soft_wrap=True,
    )
    size = _size_text(ranking.size_m)
    title = f"windows of {size} m x {size} m, best first"
    first = ranking.windows[0]
    if first.size_m != (ranking.size_m, ranking.size_m):
        width, height = (_size_text(v) for v in first.size_m)
        title = f"the data fits in a window of {size} m: one window, its extent ({width} m x {height} m)"
    table = console_table(console, title=title)
    for heading in ("rank", "centre (lat, lon)", "buildings", "POIs", "streets (km)", "score"):
        table.add_column(heading, justify="left" if heading.startswith("centre") else "right")
    for window in ranking.windows:
        lat, lon = window.center
        table.add_row(
            str(window.rank), f"{lat:.6f}, {lon:.6f}", f"{window.buildings:,}", f"{window.pois:,}",
            f"{window.street_km:.2f}", f"{window.score:.3f}",
        )  # fmt: skip
    console.print(table)


def _print_advice(console: Console, advice: RecipeAdvice, *, several: bool) -> None:
    other = " (for another window, put its centre in center:)" if several else ""
    if advice.save_as is not None:
        console.print(
            f"\nThe best window as a scene recipe{other}: save it as {_shown(advice.save_as)}\n",
            highlight=False, markup=False, soft_wrap=True,
        )  # fmt: skip
    else:
        console.print(
            f"\nThe best window as a scene recipe{other}:\n", highlight=False, markup=False, soft_wrap=True
        )
    console.print(advice.text, highlight=False, markup=False, soft_wrap=True, end="")
    if advice.save_as is not None:
        console.print("\nthen build it with:", highlight=False, markup=False)
    else:
        console.print(
            "\nNo workspace here (no recipes/ folder in this folder or its parents): make one with a copy "
            "of the file and this window's recipe (and a dataset recipe), and build the scene, with:",
            highlight=False, markup=False, soft_wrap=True,
        )  # fmt: skip
    for line in advice.commands:
        console.print(f"  {line}", highlight=False, markup=False, soft_wrap=True)


def _draw_thumbnails(console: Console, ranking: WindowRanking, folder: Path) -> list[Path]:
    """Read each window's map and draw it to ``folder/<rank>.png``, then all to ``folder/windows.png``."""
    from navverse.city.map import CityMapError
    from navverse.city.map_picture import draw_city_map, draw_city_mosaic
    from navverse.city.osm.reader import read_osm

    folder.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []
    tiles: list[tuple[str, CityMap]] = []
    with show_progress(console, "city windows: thumbnails", unit="windows") as progress:
        for done, window in enumerate(ranking.windows):
            progress(done, len(ranking.windows))
            label = f"{window.rank}: {window.center[0]:.6f}, {window.center[1]:.6f}"
            try:
                city = read_osm(ranking.path, center=window.center, size_m=window.size_m)
            except CityMapError as exc:
                console.print(f"window {window.rank}: no thumbnail ({exc})", highlight=False, markup=False)
                continue
            written.append(
                draw_city_map(city, folder / f"{window.rank}.png", pixels=THUMBNAIL_PIXELS, label=label)
            )
            tiles.append((label, city))
        progress(len(ranking.windows), len(ranking.windows))
    if tiles:
        written.append(draw_city_mosaic(tiles, folder / "windows.png", tile_pixels=MOSAIC_TILE_PIXELS))
    return written


def cmd_city_windows(args: argparse.Namespace, console: Console, *, built_dir: Callable[[], Path]) -> int:
    """Print the ranked windows of an OSM file, the best one's recipe and how to build it."""
    from navverse.city.osm.window import MAX_WINDOW_SIDE
    from navverse.city.osm.windows import MAX_TOP, MIN_WINDOW_SIDE, rank_windows

    if not MIN_WINDOW_SIDE <= args.size <= MAX_WINDOW_SIDE:
        raise NavverseError(
            f"--size {args.size:g}: give the windows' side in meters, from {MIN_WINDOW_SIDE:g} to "
            f"{MAX_WINDOW_SIDE:g}"
        )
    if not 1 <= args.top <= MAX_TOP:
        raise NavverseError(f"--top {args.top}: give how many windows to list, from 1 to {MAX_TOP}")
    if args.thumbnails is not None and args.thumbnails.exists() and not args.thumbnails.is_dir():
        raise NavverseError(
            f"--thumbnails {args.thumbnails}: that is a file; give a folder (made if missing)"
        )
    if not args.file.exists():
        raise NavverseError(f"{args.file} does not exist: give the path of an OpenStreetMap file")
    with _scan_progress(console, f"city windows: reading {args.file.name}") as progress:
        ranking = rank_windows(args.file, size_m=args.size, top=args.top, progress=progress)
    _print_table(console, ranking)
    advice = recipe_advice(ranking, ranking.windows[0], workspace_root=_workspace_root(built_dir))
    _print_advice(console, advice, several=len(ranking.windows) > 1)
    if args.thumbnails is not None:
        written = _draw_thumbnails(console, ranking, args.thumbnails)
        console.print(
            f"\nthumbnails: {len(written)} pictures in {args.thumbnails}",
            highlight=False,
            markup=False,
            soft_wrap=True,
        )
    return 0
