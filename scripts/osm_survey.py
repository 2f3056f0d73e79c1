"""Build a window of every OSM file in a folder and table what each became.

    python scripts/osm_survey.py [FOLDER] [--size 500] [--root DIR] [--markdown FILE] [--json FILE]

For each file (default folder: ``data/raw/osm``) the densest window of ``--size`` metres
(``navverse city windows``' first) is built through the shipped outdoor preset (osm_city ->
city_geometry -> populate -> storefronts -> navmesh) with the engine, in the workspace ``--root``
(default: this project; its cache makes a second run fast), and the row says:

- the window (centre lat, lon) and the build's seconds: the wall and CPU time its five stage runs
  took when they ran (read from their manifests, so a cached build reports the time it took);
- buildings kept, and dropped by reason; where their heights came from (``height`` tag, ``levels``,
  ``parts``: a ``building:part`` with its own heights, ``default``: drawn storeys);
- sidewalks mapped (km of ``footway=sidewalk`` ways) and inferred (km of road sides given one by the
  tags or the class rule); crossings mapped (nodes and ways) and added at junction arms;
- POIs and the place categories they map to, and the storefronts placed and their categories (of
  them, those of map places; the others were added where the map has few places);
- every mapped category with no storefront of a map place, with the reason its places were lost
  (the storefronts stage's ``lost`` counts: the most frequent reason, e.g. ``no facade onto a street
  or walkable ground`` for places far from any walkable surface or whose building is outside the
  window);
- navmesh islands, the largest island's share of the navigable area, and the share on islands that
  buildings, water or railway tracks wall off from it (a courtyard with no mapped passage, an
  island in a river): the disconnected part the map itself explains;
- or, for a file that cannot be built, the reason (refused: the file's fault, or the error).

Refusals are rows too; the script exits 0 unless it could not run at all.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import Counter
from collections.abc import Iterable
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
from shapely import unary_union
from shapely.geometry import LineString, Point, Polygon, box
from shapely.strtree import STRtree

from navverse.api import ApiError, build, load_scene
from navverse.city.geometry.street_plan import StreetPlan, load_street_plan
from navverse.city.map import CityMap, read_city_map
from navverse.city.precision import difference, union_of
from navverse.errors import NavverseError
from navverse.nav.pathfinder import PathFinder

PROJECT = Path(__file__).resolve().parents[1]
OSM_SUFFIXES = (".osm", ".xml", ".gz", ".bz2", ".pbf")


@dataclass
class SurveyRow:
    """What one file's window became."""

    file: str
    window: str = ""
    seconds: float = 0.0
    cpu_seconds: float = 0.0
    buildings: int = 0
    buildings_dropped: dict[str, int] = field(default_factory=dict)
    heights: dict[str, int] = field(default_factory=dict)
    sidewalks_mapped_km: float = 0.0
    sidewalks_inferred_km: float = 0.0
    crossings_mapped: int = 0
    crossings_added: int = 0
    pois: int = 0
    categories_mapped: int = 0
    storefronts: dict[str, int] = field(default_factory=dict)
    categories_from_map: int = 0
    not_placed: dict[str, str] = field(default_factory=dict)
    islands: int = 0
    largest_island: float = 0.0
    enclosed: float = 0.0
    refused: str = ""


def _osm_files(folder: Path) -> list[Path]:
    return sorted(p for p in folder.iterdir() if p.is_file() and p.name.lower().endswith(OSM_SUFFIXES))


def _window(path: Path, size: float) -> tuple[float, float]:
    """The centre (lat, lon) of the file's best window of ``size`` metres."""
    from navverse.city.osm.windows import rank_windows

    best = rank_windows(path, size_m=size, top=1).windows[0]
    return best.center


def _mapped_categories(city: CityMap) -> set[str]:
    """The storefront place categories the map's POIs map to."""
    from navverse.assets.facade.storefronts import place_category

    found = set()
    for poi in city.pois:
        key, _, value = poi.tag.partition("=")
        category = place_category({key: value})
        if category is not None:
            found.add(category)
    return found


def _not_placed(categories: set[str], manifest: Path) -> dict[str, str]:
    """Why each of these mapped categories has no storefront of a map place: the most frequent reason
    its places were lost (the storefronts stage's counts in its manifest)."""
    stats = json.loads(manifest.read_text(encoding="utf-8")).get("stats", {})
    lost = stats.get("lost", {})
    why = {}
    for category in sorted(categories):
        reasons = lost.get(category, {})
        why[category] = max(sorted(reasons), key=reasons.get) if reasons else "not placed"
    return why


def _build_seconds(outputs: Iterable[Path]) -> tuple[float, float]:
    """Wall and CPU seconds the stage runs of these outputs took when they ran (their manifests)."""
    wall = cpu = 0.0
    for output in outputs:
        run = json.loads((output / "manifest.json").read_text(encoding="utf-8")).get("run", {})
        wall += float(run.get("wall_s", 0.0))
        cpu += float(run.get("cpu_s", 0.0))
    return round(wall, 1), round(cpu, 1)


def _heights(city: CityMap) -> dict[str, int]:
    names = {"height": "tag", "levels": "levels", "drawn": "default", "synthetic": "synthetic"}
    found = Counter("parts" if b.outline else names[b.height_source] for b in city.buildings)
    return dict(sorted(found.items()))


def _sidewalk_km(city: CityMap) -> tuple[float, float]:
    mapped = sum(LineString(w.centerline.points).length for w in city.walkways if w.kind == "sidewalk")
    inferred = sum(
        LineString(r.centerline.points).length
        * ((r.sidewalk_left is not None) + (r.sidewalk_right is not None))
        for r in city.roads
    )
    return round(mapped / 1000.0, 2), round(inferred / 1000.0, 2)


def survey_file(path: Path, *, size: float, root: Path) -> SurveyRow:
    """Build the best window of ``path`` and describe it (a refusal is described too)."""
    row = SurveyRow(file=path.name)
    try:
        lat, lon = _window(path, size)
    except NavverseError as exc:
        row.refused = str(exc)
        return row
    row.window = f"{lat:.5f}, {lon:.5f}"
    recipe = {
        "extends": "outdoor-city",
        "stages": {"osm_city": {"source": str(path.resolve()), "center": [lat, lon], "size_m": [size, size]}},
    }
    name = "survey-" + "".join(c if c.isalnum() else "-" for c in path.name.lower()).strip("-")
    try:
        result = build(recipe, name=name, root=root, jobs=1)
    except (ApiError, NavverseError) as exc:
        row.refused = " ".join(line.strip() for line in str(exc).splitlines())
        return row
    row.seconds, row.cpu_seconds = _build_seconds(result.targets[name].values())
    loaded = load_scene(result.output(name))
    geometry = result.output(name, "geometry")  # the storefronts stage's: the map and plan beside it
    city = read_city_map(geometry / "city_map.json")
    row.buildings = len(city.buildings)
    row.buildings_dropped = {k: v for k, v in city.dropped.items() if "building" in k}
    row.heights = _heights(city)
    row.sidewalks_mapped_km, row.sidewalks_inferred_km = _sidewalk_km(city)
    row.crossings_mapped = len(city.crossings) + sum(1 for w in city.walkways if w.kind == "crossing")
    plan = json.loads((geometry / "street_plan.json").read_text())
    row.crossings_added = max(0, len(plan.get("crossings", [])) - len(city.crossings))
    row.pois = len(city.pois)
    row.categories_mapped = len(_mapped_categories(city))
    stores = Counter(s.place_category for s in loaded.annotations.storefronts)
    row.storefronts = dict(sorted(stores.items(), key=lambda item: (-item[1], item[0])))
    from_map = {s.place_category for s in loaded.annotations.storefronts if s.poi is not None}
    row.categories_from_map = len(from_map)
    row.not_placed = _not_placed(_mapped_categories(city) - from_map, geometry / "manifest.json")
    if loaded.pathfinder is not None and len(loaded.pathfinder.island_areas):
        areas = loaded.pathfinder.island_areas
        row.islands = len(areas)
        row.largest_island = round(float(areas[0] / areas.sum()), 3)
        row.enclosed = round(
            _enclosed_share(loaded.pathfinder, load_street_plan(geometry / "street_plan.json")), 3
        )
    return row


def _enclosed_share(finder: PathFinder, plan: StreetPlan) -> float:
    """Share of the navigable area on islands other than the largest that buildings, water or railway
    tracks wall off from it: ground with no way out on the map (a courtyard with no mapped passage, an
    island in a river), not a gap the geometry made."""
    walls = union_of(plan.classes.get(name, Polygon()) for name in ("building", "water", "rail"))
    ground = difference(box(*unary_union(list(plan.classes.values())).bounds), walls)
    parts = [part.buffer(0.3) for part in getattr(ground, "geoms", [ground])]  # a point on a wall's edge
    tree = STRtree(parts)
    rng = np.random.default_rng(0)

    def part_of(island: int) -> int | None:
        for _ in range(3):
            x, y = finder.get_random_navigable_point(rng, island=island)[:2]
            hits = tree.query(Point(x, y), predicate="within")
            if len(hits):
                return int(min(hits))
        return None

    main = part_of(0)
    areas = finder.island_areas
    walled = sum(float(areas[i]) for i in range(1, len(areas)) if part_of(i) != main)
    return walled / float(areas.sum())


def _short(reasons: dict[str, int]) -> str:
    return "; ".join(f"{reason.split(' (')[0]} {n}" for reason, n in reasons.items()) or "-"


def markdown(rows: list[SurveyRow]) -> str:
    """The survey as a Markdown table."""
    head = (
        "| file | window (lat, lon) | s (CPU s) | buildings | dropped | heights "
        "| sidewalks mapped / inferred km | crossings mapped / added | POIs (categories) "
        "| storefronts (categories; of map places) | mapped categories not placed (why) "
        "| islands | largest | walled off |"
    )
    lines = [head, "|" + "---|" * 14]
    for r in rows:
        if r.refused:
            lines.append(f"| {r.file} | refused: {r.refused} |" + " |" * 12)
            continue
        heights = ", ".join(f"{k} {v}" for k, v in r.heights.items())
        stores = sum(r.storefronts.values())
        cells = [
            r.file,
            r.window,
            f"{r.seconds:g} ({r.cpu_seconds:g})",
            str(r.buildings),
            _short(r.buildings_dropped),
            heights,
            f"{r.sidewalks_mapped_km:g} / {r.sidewalks_inferred_km:g}",
            f"{r.crossings_mapped} / {r.crossings_added}",
            f"{r.pois} ({r.categories_mapped})",
            f"{stores} ({len(r.storefronts)}; {r.categories_from_map})",
            "; ".join(f"{c}: {why}" for c, why in r.not_placed.items()) or "-",
            str(r.islands),
            f"{r.largest_island:.0%}",
            f"{r.enclosed:.0%}",
        ]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("folder", nargs="?", type=Path, default=PROJECT / "data" / "raw" / "osm")
    parser.add_argument("--size", type=float, default=500.0, help="the window's side (m)")
    parser.add_argument("--root", type=Path, default=PROJECT, help="the workspace to build in")
    parser.add_argument("--markdown", type=Path, help="also write the table here")
    parser.add_argument("--json", type=Path, help="write the rows as JSON here")
    parser.add_argument("--only", nargs="*", default=None, help="survey only these file names")
    args = parser.parse_args()
    if not args.folder.is_dir():
        print(f"error: {args.folder} is not a folder of OSM files", file=sys.stderr)
        return 1
    files = [p for p in _osm_files(args.folder) if args.only is None or p.name in args.only]
    from pipeline.params import allow_reading

    rows = []
    with allow_reading([args.folder.resolve()]):
        for n, path in enumerate(files, 1):
            print(f"[{n}/{len(files)}] {path.name}", file=sys.stderr, flush=True)
            rows.append(survey_file(path, size=args.size, root=args.root))
    table = markdown(rows)
    sys.stdout.write(table)
    if args.markdown:
        args.markdown.write_text(table, encoding="utf-8")
    if args.json:
        args.json.write_text(json.dumps([asdict(r) for r in rows], indent=1), encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
