"""How many place categories a real city window gets as storefronts, and where the others are lost.

Usage::

    python scripts/storefront_categories.py [--window FILE@LAT,LON ...] [--size 500] [--seed 0]
        [--fill-per-km2 150] [--jobs 2] [--json PATH]

For each window (default: the dense parts of eight extracts of ``data/raw/osm``, see
:data:`WINDOWS`) the map is read (``read_osm``), its geometry built (``geometry_plan`` +
``city_scene`` with the default :class:`CityGeometry`), populated (``populate_city``) and given
storefronts (``place_storefronts``) with the outdoor preset's settings (``fill_per_km2: 150``), the
stages' sequence. Printed per window: the map's POIs, those with a place category, the distinct
categories they map to, the storefronts placed (of them from map places) and their distinct
categories, the rejections by reason, every mapped category that got no storefront of a map place
with the reasons its places were lost, and the most frequent POI tags that map to no category.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import Counter
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from navverse.assets.facade.storefronts import place_category
from navverse.city.geometry.scene import CityGeometry, city_scene, geometry_plan
from navverse.city.map import CityMap, Poi
from navverse.city.osm.reader import read_osm
from navverse.city.places.storefronts import StorefrontSettings, place_storefronts
from navverse.city.street_life.populate import PopulateSettings, populate_city
from navverse.processes import end_with_parent
from navverse.scene.geometry import Scene

ROOT = Path(__file__).resolve().parents[1]
OSM = ROOT / "data" / "raw" / "osm"
WINDOWS: tuple[tuple[str, float, float], ...] = (
    ("munich-altstadt.osm.pbf", 48.1363, 11.5747),
    ("berlin-mitte.osm.xml.gz", 52.5253, 13.4048),
    ("london-farringdon.osm.pbf", 51.5199, -0.1097),
    ("nyc-lower-east-side.osm.pbf", 40.7208, -73.9879),
    ("porto-downtown.osm.pbf", 41.1482, -8.6076),
    ("ho-chi-minh-tan-dinh.osm", 10.7882, 106.6913),
    ("vaduz-centre.osm.pbf", 47.1398, 9.5219),
    ("chiang-mai-nimman.osm.xml.gz", 18.7971, 98.9677),
)
"""Default windows: the file, and the centre (lat, lon) of its densest 500 m square of POI nodes."""
TARGET = 17
"""The issue's target: at least min(TARGET, mapped categories) categories placed."""


def _tags(poi: Poi) -> dict[str, str]:
    key, _, value = poi.tag.partition("=")
    return {key: value}


def map_categories(city: CityMap) -> tuple[Counter[str], Counter[str]]:
    """POIs per place category, and POI tags without a category, of a city map."""
    mapped: Counter[str] = Counter()
    unmapped: Counter[str] = Counter()
    for poi in city.pois:
        category = place_category(_tags(poi))
        if category is None:
            unmapped[poi.tag] += 1
        else:
            mapped[category] += 1
    return mapped, unmapped


def measure(path: Path, center: tuple[float, float], *, size: float, seed: int, fill: float) -> dict:
    """The storefront category counts of one window (see the module docstring)."""
    city = read_osm(path, center=center, size_m=(size, size), seed=seed)
    geometry = CityGeometry()
    plan = geometry_plan(city, geometry)
    scene = city_scene(city, scene_id=path.name.split(".")[0], geometry=geometry, plan=plan)
    populated = populate_city(scene, city, plan, np.random.default_rng(seed), PopulateSettings()).scene
    settings = StorefrontSettings(fill_per_km2=fill)
    result = place_storefronts(populated, city, plan, np.random.default_rng(seed), settings)
    mapped, unmapped = map_categories(city)
    stores = result.scene.annotations.storefronts
    from_map = Counter(s.place_category for s in stores if s.poi is not None)
    everything = Counter(s.place_category for s in stores)
    lost = result.counts.get("lost", {})
    distances, elsewhere = _distances(city, result.scene)
    return {
        "window": f"{path.name}@{center[0]:.4f},{center[1]:.4f}",
        "pois": len(city.pois),
        "mapped_pois": sum(mapped.values()),
        "mapped": dict(sorted(mapped.items())),
        "placed": len(stores),
        "placed_from_map": sum(from_map.values()),
        "categories_from_map": dict(sorted(from_map.items())),
        "categories_placed": dict(sorted(everything.items())),
        "rejected": result.counts["rejected"],
        "distance_m": {
            "median": round(float(np.median(distances)), 1) if distances else None,
            "p90": round(float(np.percentile(distances, 90)), 1) if distances else None,
            "max": round(max(distances), 1) if distances else None,
        },
        "other_building": elsewhere,
        "missing": {c: lost.get(c, {}) for c in sorted(set(mapped) - set(from_map))},
        "lost": lost,
        "unmapped": dict(unmapped.most_common(25)),
    }


def _distances(city: CityMap, scene: Scene) -> tuple[list[float], int]:
    """How far each map place's storefront stands from the place (m), and how many stand on another
    building than the one the place is mapped in."""
    pois = {p.id: p for p in city.pois}
    map_ids = {b.id: b.map_id for b in scene.annotations.buildings}
    distances, elsewhere = [], 0
    for store in scene.annotations.storefronts:
        poi = pois.get(store.poi) if store.poi is not None else None
        if poi is None:
            continue
        distances.append(float(np.hypot(*(np.asarray(store.center[:2]) - poi.position))))
        elsewhere += poi.building is not None and map_ids.get(store.building) != poi.building
    return distances, elsewhere


def _report(row: dict) -> str:
    mapped, placed = len(row["mapped"]), len(row["categories_from_map"])
    goal = min(TARGET, mapped)
    lines = [
        f"== {row['window']}",
        f"POIs {row['pois']}, with a place category {row['mapped_pois']}, "
        f"categories mapped {mapped}: {_counts(row['mapped'])}",
        f"storefronts {row['placed']} ({row['placed_from_map']} of map places), categories placed "
        f"{len(row['categories_placed'])} ({placed} of map places; goal {goal}: "
        f"{'met' if placed >= goal else 'SHORT'}): {_counts(row['categories_placed'])}",
        f"rejected: {_counts(row['rejected'])}",
        f"distance from place to storefront (m): {_counts(row['distance_m'])}; "
        f"on another building than the place's: {row['other_building']}",
    ]
    for category, reasons in row["missing"].items():
        lines.append(f"  no storefront for {category} ({row['mapped'][category]}): {_counts(reasons)}")
    lines.append(f"unmapped POI tags: {_counts(row['unmapped'])}")
    return "\n".join(lines)


def _counts(counts: dict) -> str:
    return ", ".join(f"{k} {v}" for k, v in counts.items()) or "-"


def _window(text: str) -> tuple[Path, tuple[float, float]]:
    name, _, centre = text.partition("@")
    lat, _, lon = centre.partition(",")
    path = Path(name) if Path(name).exists() else OSM / name
    return path, (float(lat), float(lon))


def _run(args: tuple[Path, tuple[float, float], float, int, float]) -> dict:
    path, center, size, seed, fill = args
    return measure(path, center, size=size, seed=seed, fill=fill)


def main(argv: list[str] | None = None) -> int:
    """Measure the windows and print (or write as JSON) one report per window."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--window", action="append", help="FILE@LAT,LON (FILE in data/raw/osm or a path)")
    parser.add_argument("--size", type=float, default=500.0, help="window side (m)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--fill-per-km2", type=float, default=150.0)
    parser.add_argument("--jobs", type=int, default=1, help="windows measured at once")
    parser.add_argument("--json", type=Path, help="also write the rows here")
    args = parser.parse_args(argv)
    windows = [_window(w) for w in args.window] if args.window else [(OSM / f, (a, b)) for f, a, b in WINDOWS]
    work = [(path, center, args.size, args.seed, args.fill_per_km2) for path, center in windows]
    if args.jobs > 1:
        with ProcessPoolExecutor(args.jobs, initializer=end_with_parent) as pool:
            rows = list(pool.map(_run, work))
    else:
        rows = [_run(item) for item in work]
    for row in rows:
        print(_report(row), "\n")
    print("| window | POIs | mapped POIs | categories mapped | storefronts (map) | categories placed (map) |")
    print("|---|---|---|---|---|---|")
    for row in rows:
        print(
            f"| {row['window']} | {row['pois']} | {row['mapped_pois']} | {len(row['mapped'])} | "
            f"{row['placed']} ({row['placed_from_map']}) | "
            f"{len(row['categories_placed'])} ({len(row['categories_from_map'])}) |"
        )
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1, sort_keys=True))
    return 0


if __name__ == "__main__":
    sys.exit(main())
