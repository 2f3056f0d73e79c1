"""City benchmark: whole city builds (map -> geometry -> navmesh) and windowed reads of large files.

1. Synthetic cities of the paper's density (``synthetic_city`` grid layout, its default street
   spacing and building parameters) of 0.25, 1 and 4 km^2, each built from a recipe in a scratch
   workspace with ``navverse build`` in a child process (map, geometry, population, navmesh): the
   command's wall time, and per stage the wall time and peak RSS the build recorded in its
   manifests; the city's buildings and road km per km^2 (the paper: ~546 buildings, ~36.4 km),
   navigable area, polygons and islands. The 4 km^2 to 1 km^2 ratio of wall times says how the
   build scales.
2. The shipped real extracts (``recipes/scenes/outdoor/*.yaml`` whose map is ``osm_city``), built
   the same way.
3. Windowed reads: a 1 km^2 synthetic city written as OSM, tiled ``--tiles`` x ``--tiles`` times
   (shifted copies, fresh ids) into a large ``.osm.pbf`` and ``.osm`` file, from which ``read_osm``
   reads the 1 km^2 window at the centre of one tile in a fresh child process: wall time and peak
   RSS, and the file's size as a multiple of the window's share. Peer, in the same run: a plain
   pyosmium pass over the whole file that keeps every node location (what reading without a window
   costs), and osmnx (``graph_from_xml`` and ``features_from_xml``) reading the 1 km^2 window's own
   ``.osm`` file next to ``read_osm`` on the same file.

Run ``python bench/city.py`` (``make bench`` runs it); ``--quick`` uses 0.04, 0.16 and 0.64 km^2
cities, 3 x 3 tiles and skips the extracts. ``--json PATH`` also writes the results. Timings are
measurements, never assertions; the printed load average says whether other work shared the machine.
"""

from __future__ import annotations

import argparse
import json
import math
import multiprocessing
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

import yaml
from rich.console import Console
from rich.table import Table

REPO = Path(__file__).resolve().parents[1]
NAVVERSE = Path(sys.executable).with_name("navverse")
STAGES = ("synthetic_city", "osm_city", "city_geometry", "populate", "navmesh")
PAPER_BUILDINGS_PER_KM2 = 546
PAPER_ROAD_KM_PER_KM2 = 36.4

console = Console(width=170)


# --------------------------------------------------------------------------------------------------
# Whole builds


def make_workspace(root: Path) -> Path:
    """A scratch workspace: the project's presets and raw data, no scene recipes yet."""
    shutil.copytree(REPO / "recipes" / "presets", root / "recipes" / "presets")
    (root / "recipes" / "scenes" / "outdoor").mkdir(parents=True)
    shutil.copytree(REPO / "data" / "raw", root / "data" / "raw")
    return root


def synthetic_recipe(workspace: Path, name: str, side_m: float) -> str:
    """Write a grid synthetic city recipe of ``side_m`` x ``side_m``; returns its target name."""
    recipe = {
        "description": f"benchmark city, {side_m:.0f} m x {side_m:.0f} m",
        "extends": "outdoor-city",
        "stages": {"synthetic_city": {"layout": "grid", "size": [side_m, side_m]}},
    }
    (workspace / "recipes" / "scenes" / "outdoor" / f"{name}.yaml").write_text(yaml.safe_dump(recipe))
    return name


def build_target(workspace: Path, target: str) -> dict[str, Any]:
    """Build one target with ``navverse build`` in a child process; wall time and manifest records."""
    env = {**os.environ, "NAVVERSE_ROOT": str(workspace)}
    start = time.perf_counter()
    done = subprocess.run(
        [str(NAVVERSE), "build", target], env=env, capture_output=True, text=True, check=False
    )
    wall = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"error: navverse build {target} failed:\n{done.stderr[-2000:]}")
    stages: dict[str, dict[str, Any]] = {}
    for manifest in (workspace / "data" / "built" / "artifacts").glob("*/*/manifest.json"):
        record = json.loads(manifest.read_text())
        if record.get("target") == target:
            stages[record["stage"]] = {"run": record["run"], "stats": record.get("stats", {})}
    return {"target": target, "wall_s": wall, "stages": stages}


def summarize(build: dict[str, Any], area_km2: float) -> dict[str, Any]:
    """One row: stage times and memory, city and navmesh figures per km^2."""
    stages = build["stages"]
    geometry = stages["city_geometry"]["stats"]
    navmesh = stages["navmesh"]["stats"]
    return {
        "target": build["target"],
        "area_km2": area_km2,
        "wall_s": build["wall_s"],
        "stage_wall_s": {name: stages[name]["run"]["wall_s"] for name in STAGES if name in stages},
        "stage_peak_rss_mb": {name: stages[name]["run"]["peak_rss_mb"] for name in STAGES if name in stages},
        "peak_rss_mb": max(stage["run"]["peak_rss_mb"] for stage in stages.values()),
        "buildings": geometry["buildings"],
        "road_km": geometry["road_km"],
        "buildings_per_km2": geometry["buildings"] / area_km2,
        "road_km_per_km2": geometry["road_km"] / area_km2,
        "navigable_m2": navmesh["navigable_area_m2"],
        "largest_island_share": navmesh["largest_island_m2"] / max(navmesh["navigable_area_m2"], 1e-9),
        "islands": navmesh["islands"],
        "polygons": navmesh["polygons"],
        "dropped": geometry.get("dropped", {}),
    }


def shipped_extracts() -> list[tuple[str, float]]:
    """(target, window area in km^2) of the shipped ``osm_city`` recipes."""
    found = []
    for path in sorted((REPO / "recipes" / "scenes" / "outdoor").glob("*.yaml")):
        recipe = yaml.safe_load(path.read_text())
        params = (recipe.get("stages") or {}).get("osm_city")
        if params is None:
            continue
        width, height = params.get("size", [1000.0, 1000.0])
        found.append((path.stem, width * height / 1e6))
    return found


# --------------------------------------------------------------------------------------------------
# Windowed reads


def _child_peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _read_window(path: str, center: tuple[float, float], size_m: float) -> dict[str, Any]:
    from navverse.city.osm.reader import read_osm

    start = time.perf_counter()
    city = read_osm(path, center=center, size_m=(size_m, size_m))
    return {
        "wall_s": time.perf_counter() - start,
        "peak_rss_mb": _child_peak_mb(),
        "roads": len(city.roads),
        "buildings": len(city.buildings),
    }


def _full_pass(path: str) -> dict[str, Any]:
    import osmium

    start = time.perf_counter()
    nodes = ways = 0
    for obj in osmium.FileProcessor(path).with_locations("flex_mem"):
        if obj.is_node():
            nodes += 1
        elif obj.is_way():
            ways += 1
    return {
        "wall_s": time.perf_counter() - start,
        "peak_rss_mb": _child_peak_mb(),
        "nodes": nodes,
        "ways": ways,
    }


def _osmnx_read(path: str) -> dict[str, Any]:
    import osmnx

    start = time.perf_counter()
    graph = osmnx.graph_from_xml(path, simplify=False, retain_all=True)
    buildings = osmnx.features_from_xml(path, tags={"building": True})
    return {
        "wall_s": time.perf_counter() - start,
        "peak_rss_mb": _child_peak_mb(),
        "edges": graph.number_of_edges(),
        "buildings": len(buildings),
    }


def in_child(fn: Callable[..., dict[str, Any]], *args: Any) -> dict[str, Any]:
    """Run ``fn(*args)`` in a fresh ``spawn`` process, so its peak RSS is its own."""
    with ProcessPoolExecutor(max_workers=1, mp_context=multiprocessing.get_context("spawn")) as pool:
        return pool.submit(fn, *args).result()


def synthetic_osm(path: Path, side_m: float, seed: int) -> Path:
    """Write a synthetic city of ``side_m`` x ``side_m`` as OSM XML."""
    from navverse.city.osm.writer import write_osm
    from navverse.city.synthetic.generator import synthetic_city
    from navverse.city.synthetic.params import SyntheticCityParams

    return write_osm(synthetic_city(SyntheticCityParams(size=(side_m, side_m)), seed=seed), path)


def tile_osm(source: Path, tiles: int, targets: list[Path]) -> tuple[float, float, float, float]:
    """Write ``tiles`` x ``tiles`` shifted copies of ``source`` into each of ``targets``.

    Copies are shifted by the source's extent in latitude and longitude, with ids offset so that no
    two copies share one. Returns the (west, south, east, north) of the whole.
    """
    import osmium

    nodes, ways, relations = [], [], []
    for obj in osmium.FileProcessor(str(source)):
        tags = dict(obj.tags)
        if obj.is_node():
            nodes.append((obj.id, obj.location.lon, obj.location.lat, tags))
        elif obj.is_way():
            ways.append((obj.id, [ref.ref for ref in obj.nodes], tags))
        elif obj.is_relation():
            relations.append((obj.id, [(m.type, m.ref, m.role) for m in obj.members], tags))
    west, east = min(n[1] for n in nodes), max(n[1] for n in nodes)
    south, north = min(n[2] for n in nodes), max(n[2] for n in nodes)
    dlon, dlat = (east - west) * 1.02, (north - south) * 1.02
    stride = 10 ** (len(str(max(o[0] for o in nodes + ways + relations))) + 1)
    bounds = (west, south, west + tiles * dlon, south + tiles * dlat)
    header = osmium.io.Header()
    header.add_box(
        osmium.osm.Box(osmium.osm.Location(bounds[0], bounds[1]), osmium.osm.Location(bounds[2], bounds[3]))
    )
    copies = [(k * stride, (k % tiles) * dlon, (k // tiles) * dlat) for k in range(tiles * tiles)]
    for target in targets:
        writer = osmium.SimpleWriter(str(target), header=header, overwrite=True)
        try:
            for offset, shift_lon, shift_lat in copies:
                for node_id, lon, lat, tags in nodes:
                    location = (lon + shift_lon, lat + shift_lat)
                    writer.add_node(
                        osmium.osm.mutable.Node(id=node_id + offset, location=location, tags=tags)
                    )
            for offset, _, _ in copies:
                for way_id, refs, tags in ways:
                    refs_shifted = [ref + offset for ref in refs]
                    writer.add_way(osmium.osm.mutable.Way(id=way_id + offset, nodes=refs_shifted, tags=tags))
            for offset, _, _ in copies:
                for relation_id, members, tags in relations:
                    shifted = [(kind, ref + offset, role) for kind, ref, role in members]
                    writer.add_relation(
                        osmium.osm.mutable.Relation(id=relation_id + offset, members=shifted, tags=tags)
                    )
        finally:
            writer.close()
    return bounds


# --------------------------------------------------------------------------------------------------
# Tables


def build_table(title: str, rows: list[dict[str, Any]]) -> Table:
    table = Table(title=title)
    for column in (
        "city",
        "km²",
        "wall s",
        "map s",
        "geometry s",
        "populate s",
        "navmesh s",
        "peak RSS MB",
        "buildings/km²",
        "road km/km²",
        "navigable m²",
        "islands",
        "largest",
    ):
        table.add_column(column, justify="left" if column == "city" else "right")
    for row in rows:
        walls = row["stage_wall_s"]
        map_s = walls.get("synthetic_city", walls.get("osm_city", float("nan")))
        table.add_row(
            row["target"],
            f"{row['area_km2']:.2f}",
            f"{row['wall_s']:.1f}",
            f"{map_s:.1f}",
            f"{walls['city_geometry']:.1f}",
            f"{walls.get('populate', float('nan')):.1f}",
            f"{walls['navmesh']:.1f}",
            f"{row['peak_rss_mb']:.0f}",
            f"{row['buildings_per_km2']:.0f}",
            f"{row['road_km_per_km2']:.1f}",
            f"{row['navigable_m2']:.0f}",
            str(row["islands"]),
            f"{row['largest_island_share']:.1%}",
        )
    return table


def window_table(rows: list[dict[str, Any]], side: float) -> Table:
    table = Table(title=f"Reading a {side:.0f} m x {side:.0f} m window (a fresh child process each)")
    for column in ("file", "size MB", "file/window", "reader", "wall s", "peak RSS MB", "what it read"):
        table.add_column(column, justify="left" if column in ("file", "reader", "what it read") else "right")
    for row in rows:
        table.add_row(
            row["file"],
            f"{row['size_mb']:.0f}",
            f"{row['factor']:.0f}x",
            row["reader"],
            f"{row['wall_s']:.1f}",
            f"{row['peak_rss_mb']:.0f}",
            row["read"],
        )
    return table


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="small cities, 3 x 3 tiles, no extracts")
    parser.add_argument(
        "--sizes", type=float, nargs="+", help="synthetic city areas in km² (default 0.25 1 4)"
    )
    parser.add_argument("--tiles", type=int, help="tiles per side of the large file (default 8: 64 km²)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the synthetic cities")
    parser.add_argument("--no-extracts", action="store_true", help="skip the shipped real extracts")
    parser.add_argument("--no-window", action="store_true", help="skip the windowed reads")
    parser.add_argument("--json", type=Path, help="also write the results here")
    args = parser.parse_args(argv)
    sizes = args.sizes or ([0.04, 0.16, 0.64] if args.quick else [0.25, 1.0, 4.0])
    tiles = args.tiles or (3 if args.quick else 8)
    window_side = 200.0 if args.quick else 1000.0
    console.print(f"load average before: {os.getloadavg()[0]:.2f}, {os.cpu_count()} CPUs")
    results: dict[str, Any] = {"sizes_km2": sizes, "synthetic": [], "extracts": [], "window": []}

    with tempfile.TemporaryDirectory(prefix="navverse-bench-city-") as scratch:
        workspace = make_workspace(Path(scratch) / "workspace")
        for area in sizes:
            side = math.sqrt(area) * 1000.0
            target = synthetic_recipe(workspace, f"bench-{area:g}km2".replace(".", "_"), side)
            console.print(f"building {target} ({side:.0f} m x {side:.0f} m) ...")
            results["synthetic"].append(summarize(build_target(workspace, target), area))
        console.print(build_table("Synthetic grid cities (map -> geometry -> navmesh)", results["synthetic"]))
        walls = {row["area_km2"]: row["wall_s"] for row in results["synthetic"]}
        if len(sizes) >= 2:
            small, large = sorted(sizes)[-2:]
            ratio = walls[large] / walls[small]
            results["scaling"] = {"small_km2": small, "large_km2": large, "wall_ratio": ratio}
            console.print(f"{large:g} km² / {small:g} km² wall: {ratio:.2f}x for {large / small:g}x the area")

        if not (args.quick or args.no_extracts):
            for name, area in shipped_extracts():
                shutil.copy(
                    REPO / "recipes" / "scenes" / "outdoor" / f"{name}.yaml",
                    workspace / "recipes" / "scenes" / "outdoor" / f"{name}.yaml",
                )
                console.print(f"building {name} ...")
                results["extracts"].append(summarize(build_target(workspace, name), area))
            console.print(build_table("Shipped OpenStreetMap extracts", results["extracts"]))

        if not args.no_window:
            results["window"] = window_reads(Path(scratch), window_side, tiles, args.seed)
            console.print(window_table(results["window"], window_side))
    console.print(f"load average after: {os.getloadavg()[0]:.2f}")
    if args.json:
        args.json.write_text(json.dumps(results, indent=1))
    return 0


def window_reads(scratch: Path, side: float, tiles: int, seed: int) -> list[dict[str, Any]]:
    """Build the tiled files and time the window reads and their peers."""
    window = synthetic_osm(scratch / "window.osm", side, seed)
    console.print(f"tiling the {side:.0f} m city {tiles} x {tiles} times ...")
    pbf, xml = scratch / "large.osm.pbf", scratch / "large.osm"
    west, south, east, north = tile_osm(window, tiles, [pbf, xml])
    # The centre of the middle tile.
    k = tiles // 2
    center = (south + (k + 0.5) * (north - south) / tiles, west + (k + 0.5) * (east - west) / tiles)
    rows = []
    for path, factor in ((pbf, tiles * tiles), (xml, tiles * tiles), (window, 1)):
        size_mb = path.stat().st_size / 1e6
        console.print(f"reading {path.name} ({size_mb:.0f} MB) ...")
        ours = in_child(_read_window, str(path), center if factor > 1 else None, side)
        runs = [("read_osm (window)", ours, f"{ours['roads']} roads, {ours['buildings']} buildings")]
        if factor > 1:
            peer = in_child(_full_pass, str(path))
            runs.append(("pyosmium, all + locations", peer, f"{peer['nodes']} nodes, {peer['ways']} ways"))
        else:
            peer = in_child(_osmnx_read, str(path))
            runs.append(
                ("osmnx graph + buildings", peer, f"{peer['edges']} edges, {peer['buildings']} buildings")
            )
        for reader, run, read in runs:
            rows.append(
                {
                    "file": path.name,
                    "size_mb": size_mb,
                    "factor": factor,
                    "reader": reader,
                    "wall_s": run["wall_s"],
                    "peak_rss_mb": run["peak_rss_mb"],
                    "read": read,
                }
            )
    return rows


if __name__ == "__main__":
    sys.exit(main())
