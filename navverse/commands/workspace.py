"""``navverse init``: a workspace of one's own, with the shipped presets and, for a city file, recipes.

A workspace is a folder with ``recipes/`` (its targets, and ``recipes/presets/`` that they extend by
name), ``data/raw/`` (its input files) and, once built, ``data/built/`` and ``episodes/``. The
command writes the new workspace in a temporary folder beside ``DIR`` and renames it into place, so
an interrupted or failed ``init`` leaves nothing behind.
"""

from __future__ import annotations

import argparse
import re
import shlex
import shutil
import tempfile
from dataclasses import dataclass
from pathlib import Path

from pydantic import ValidationError
from rich.console import Console

from navverse.commands.common import Shared, Subparsers, command
from navverse.errors import NavverseError

__all__ = [
    "OSM_SUFFIXES",
    "CityWindow",
    "cmd_init",
    "register",
    "shipped_presets_dir",
    "write_workspace",
]

OSM_SUFFIXES = (".osm", ".xml", ".gz", ".bz2", ".pbf")
"""Suffixes dropped from an OSM file's name to name its scene (``vaduz.osm.xml.gz`` gives ``vaduz``)."""

_GOAL_CATEGORIES = (
    "sedan", "hatchback", "suv", "fire_hydrant", "street_lamp", "post_box", "waste_bin", "stop_sign",
    "bus_shelter", "park_bench", "bollard", "traffic_light", "utility_box", "recycling_bin", "dumpster",
    "picnic_table", "deciduous_tree", "birch_tree",
)  # fmt: skip
"""The ObjNav goal categories of a city's dataset recipe: street objects and parked cars."""


def shipped_presets_dir() -> Path:
    """The presets shipped with navverse: ``recipes/presets`` of the project it is installed from.

    Raises
    ------
    NavverseError
        If navverse is not installed from its repository (the presets are not beside it).
    """
    import navverse

    presets = Path(navverse.__file__).resolve().parent.parent / "recipes" / "presets"
    if not any(presets.glob("*.yaml")):
        raise NavverseError(
            f"the shipped presets are not beside the installed navverse (looked in {presets}): install "
            "navverse from its repository (`make setup` there), or copy its recipes/presets/ by hand"
        )
    return presets


@dataclass(frozen=True)
class CityWindow:
    """A window of an OSM file that a new workspace builds as a scene.

    Attributes
    ----------
    source : Path
        The OSM file (any name: recognised by its content).
    center : tuple of float or None
        ``(lat, lon)`` of the window's centre; None: the centre of the file's declared bounds.
    size_m : tuple of float
        ``(east-west, north-south)`` sides (m).
    name : str
        The scene's target id; the dataset's is ``NAME-episodes``.
    """

    source: Path
    center: tuple[float, float] | None
    size_m: tuple[float, float]
    name: str

    @property
    def dataset(self) -> str:
        """The target id of the dataset recipe."""
        return f"{self.name}-episodes"


def scene_name(path: Path) -> str:
    """A target id from an OSM file's name: lower case, its OSM suffixes dropped, other characters as -."""
    name = path.name.lower()
    while (suffix := Path(name).suffix) in OSM_SUFFIXES and suffix:
        name = name[: -len(suffix)]
    name = re.sub(r"[^a-z0-9._-]+", "-", name).strip("-._")
    return name or "city"


def city_window(
    source: Path, *, center: tuple[float, float] | None, size: tuple[float, ...], name: str | None
) -> CityWindow:
    """Check an OSM file and a window of it (the bounds of the ``osm_city`` stage), as ``init`` uses them.

    Raises
    ------
    NavverseError
        If the file is not OSM data, the window is out of bounds or off the file's data, or the name
        is not a valid target id.
    """
    from navverse.city.map import CityMapError
    from navverse.city.osm.files import check_osm_file
    from navverse.city.osm.reader import check_window
    from navverse.city.osm.window import OsmWindow

    size_m = (size[0], size[0]) if len(size) == 1 else (size[0], size[1])
    try:
        window = OsmWindow(center=center, size_m=size_m)
    except ValidationError as exc:
        flags = {"size_m": "--size", "center": "--center"}
        problems = {f"{flags.get(str(e['loc'][0]), e['loc'][0])}: {e['msg']}" for e in exc.errors()}
        raise NavverseError("; ".join(sorted(problems))) from None
    try:
        check_osm_file(source)
        check_window(source, center=window.center, size_m=window.size_m)
    except CityMapError as exc:
        raise NavverseError(str(exc)) from None
    chosen = name or scene_name(source)
    if re.fullmatch(r"[a-z0-9][a-z0-9._-]*", chosen) is None:
        raise NavverseError(f"--name {chosen!r}: use lower-case letters, digits, '.', '_' and '-'")
    center = None if window.center is None else (float(window.center[0]), float(window.center[1]))
    return CityWindow(source, center, (float(window.size_m[0]), float(window.size_m[1])), chosen)


def _number(value: float) -> str:
    """A number as a recipe writes it: no trailing ``.0``."""
    return f"{value:g}" if value == int(value) else repr(value)


def _scene_recipe(city: CityWindow, file_name: str) -> str:
    width, height = (_number(v) for v in city.size_m)
    where = "its centre" if city.center is None else f"{city.center[0]}, {city.center[1]}"
    center = "" if city.center is None else f"    center: [{city.center[0]}, {city.center[1]}]\n"
    return (
        "description: >\n"
        f"  {city.name}: a {width} m x {height} m window of {file_name} (OpenStreetMap, ODbL) around\n"
        f"  {where}: streets, buildings, street life and storefronts from the map.\n"
        "extends: outdoor-city  # recipes/presets/outdoor-city.yaml: city_geometry, populate, storefronts, "
        "navmesh\n"
        "stages:\n"
        "  osm_city:\n"
        f"    source: ../../data/raw/osm/{file_name}\n"
        f"{center}"
        f"    size_m: [{width}, {height}]\n"
    )


def _dataset_recipe(city: CityWindow) -> str:
    categories = ", ".join(_GOAL_CATEGORIES)
    return (
        "description: >\n"
        f"  ObjNav and PlaceNav episodes in {city.name}, verified with Spot; one split, eval.\n"
        "extends: dataset  # recipes/presets/dataset.yaml: sample, verify, instructions, package\n"
        "seed: 0\n"
        "links:\n"
        f"  scene: [{city.name}]\n"
        "stages:\n"
        "  sample_episodes:\n"
        "    tasks:\n"
        "      objnav: {episodes_per_scene: 6}\n"
        "      placenav: {episodes_per_scene: 6}  # goals are the storefronts of the map's shops\n"
        f"    categories: [{categories}]\n"
        "  instructions:\n"
        "    max_landmark_distance: 8.0\n"
        "    min_landmarks: 1\n"
        "  package_dataset:\n"
        '    version: "1.0"\n'
        "    splits:\n"
        f"      eval: [{city.name}]\n"
    )


_INDOOR_EXAMPLE = """\
description: >
  An example: a small cafe (change building_type to apartment, office, grocery, school or
  hospital_ward, or the size), built with `navverse build my-cafe`.
id: my-cafe
extends: indoor-building  # recipes/presets/indoor-building.yaml: decimate, navmesh after the layout
stages:
  indoor_layout:
    building_type: cafe
    length: 12
"""


def _readme(root_shown: str, city: CityWindow | None) -> str:
    lines = [
        f"# {Path(root_shown).name or 'workspace'}: a NavVerse workspace",
        "",
        "- `recipes/scenes/`, `recipes/datasets/`: the targets (`navverse status` lists them).",
        "- `recipes/presets/`: the presets the recipes extend by name (copied from navverse by",
        "  `navverse init`; edit them here, or copy newer ones from navverse's `recipes/presets/`).",
        "- `data/raw/`: input files (keep each file's attribution beside it).",
        "- `data/built/`: what builds produce (a cache: safe to delete); `episodes/`: published datasets.",
        "",
        "Commands find the workspace from the current folder (the nearest one holding `recipes/`), or",
        "from `NAVVERSE_ROOT`. To build everything:",
        "",
        "```bash",
        "navverse build",
        "```",
    ]
    if city is not None:
        dataset = f"episodes/{city.dataset}/v1.0"
        lines += [
            "",
            f"It builds the scene `{city.name}` and the dataset `{city.dataset}` (published to `{dataset}`).",
            "Then run an agent on five of its episodes and score them with the command it prints:",
            "",
            "```bash",
            f"navverse run-agent --dataset {dataset} --agent oracle --limit 5 --out oracle.jsonl",
            f"navverse eval --dataset {dataset} --submission oracle.jsonl --split eval --episodes submitted",
            "```",
        ]
    return "\n".join(lines) + "\n"


def _osm_attribution(file_name: str, source: Path) -> str:
    return (
        "# OpenStreetMap data\n\n"
        f"`{file_name}` (copied from `{source.name}`): data © OpenStreetMap contributors, available under\n"
        "the Open Database License (ODbL) 1.0, https://www.openstreetmap.org/copyright. Whatever copies\n"
        "this file must keep this attribution beside it.\n"
    )


def write_workspace(root: Path, *, city: CityWindow | None = None, presets: Path | None = None) -> list[Path]:
    """Write a new workspace at ``root`` (which must not exist, or be an empty folder).

    Parameters
    ----------
    root : Path
        The new workspace.
    city : CityWindow, optional
        An OSM window: the file is copied to ``data/raw/osm/`` with its attribution, and a scene recipe
        and a dataset recipe are written for it. Without one, an example indoor recipe is written.
    presets : Path, optional
        The presets to copy (default: :func:`shipped_presets_dir`).

    Returns
    -------
    list of Path
        The files written, relative to ``root``.

    Raises
    ------
    NavverseError
        If ``root`` exists and is not an empty folder, or the presets are not found.
    """
    root = Path(root)
    if root.exists() and (not root.is_dir() or any(root.iterdir())):
        raise NavverseError(f"{root} already exists and is not an empty folder: give a new folder")
    presets = presets or shipped_presets_dir()
    root.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix=f".{root.name}-", dir=root.parent) as scratch:
        staging = Path(scratch) / "workspace"
        recipes = staging / "recipes"
        shutil.copytree(presets, recipes / "presets", ignore=shutil.ignore_patterns("*.pyc", "__pycache__"))
        for folder in ("scenes", "datasets"):
            (recipes / folder).mkdir(parents=True)
        (staging / "data" / "raw").mkdir(parents=True)
        if city is not None:
            osm = staging / "data" / "raw" / "osm"
            osm.mkdir()
            file_name = city.source.name  # as the user named it (a link keeps its own name)
            shutil.copyfile(city.source, osm / file_name)
            (osm / "README.md").write_text(_osm_attribution(file_name, city.source))
            (recipes / "scenes" / f"{city.name}.yaml").write_text(_scene_recipe(city, file_name))
            (recipes / "datasets" / f"{city.dataset}.yaml").write_text(_dataset_recipe(city))
        else:
            (recipes / "scenes" / "my-cafe.yaml").write_text(_INDOOR_EXAMPLE)
        (staging / "README.md").write_text(_readme(str(root), city))
        (staging / ".gitignore").write_text("data/built/\n")
        written = sorted(p.relative_to(staging) for p in staging.rglob("*") if p.is_file())
        if root.exists():
            root.rmdir()  # empty, checked above
        staging.rename(root)
    return written


def register(sub: Subparsers, shared: Shared) -> None:
    """Add ``navverse init``."""
    init = command(
        sub, "init", summary="make a workspace of one's own: the shipped presets, and recipes for a city",
        description="Make a workspace: recipes/presets/ (the shipped presets), recipes/scenes/, "
        "recipes/datasets/, data/raw/ and a README. With --city, the OSM file is copied to data/raw/osm/ "
        "and a scene recipe (a window of the file) and a dataset recipe (ObjNav and PlaceNav episodes in "
        "it, split eval) are written; without, an example indoor recipe.",
        examples=("navverse init my-workspace",
                  "navverse init my-city --city vaduz.osm.pbf --center 47.1391 9.5217 --size 300"),
    )  # fmt: skip
    init.add_argument("directory", metavar="DIR", type=Path, help="the new workspace (a new or empty folder)")
    init.add_argument(
        "--city", metavar="FILE", type=Path, default=None,
        help="an OpenStreetMap file (.osm, .osm.xml, .osm.gz, .osm.xml.gz, .osm.bz2, .osm.pbf)",
    )  # fmt: skip
    init.add_argument(
        "--center", nargs=2, type=float, metavar=("LAT", "LON"), default=None,
        help="with --city: the window's centre (default: the centre of the file's declared bounds)",
    )  # fmt: skip
    init.add_argument(
        "--size", nargs="+", type=float, metavar="M", default=(400.0,),
        help="with --city: the window's side, or its east-west and north-south sides (m; default 400)",
    )  # fmt: skip
    init.add_argument(
        "--name", default=None, help="with --city: the scene's id (default: the file's name without suffixes)"
    )
    init.set_defaults(func=cmd_init)


def cmd_init(args: argparse.Namespace, console: Console) -> int:
    """Write the workspace and print the commands to run next."""
    if args.city is None and (args.center is not None or args.name is not None):
        raise NavverseError("--center and --name describe a city: give its OSM file with --city FILE")
    if len(args.size) > 2:
        raise NavverseError("--size takes one side, or the east-west and north-south sides (m)")
    city = None
    if args.city is not None:
        center = tuple(args.center) if args.center is not None else None
        city = city_window(args.city, center=center, size=tuple(args.size), name=args.name)
    written = write_workspace(args.directory, city=city)
    shown = shlex.quote(str(args.directory))
    console.print(f"created {shown}: {len(written)} files", highlight=False)
    for path in written:
        if not path.is_relative_to("recipes/presets"):
            console.print(f"  {path}", highlight=False)
    presets = sorted(p.stem for p in written if p.is_relative_to("recipes/presets"))
    console.print(f"  recipes/presets/: {', '.join(presets)}", highlight=False)
    console.print("next:", highlight=False)
    console.print(f"  cd {shown}", highlight=False)
    console.print("  navverse build", highlight=False)
    if city is not None:
        dataset = f"episodes/{city.dataset}/v1.0"
        console.print(
            f"  navverse run-agent --dataset {dataset} --agent oracle --limit 5 --out oracle.jsonl",
            highlight=False,
            soft_wrap=True,
        )
    return 0
