"""Cut a small sample out of a real OSM extract: the test files of the OSM reader come from here.

    python scripts/cut_osm_sample.py data/raw/osm/berlin-grosser-stern.osm.gz OUT.osm \\
        --center 52.5145 13.3501 --radius 80 [--clip] [--no-bounds]

Keeps the ways and multipolygon relations that have a node within ``--radius`` metres of the centre
and every node they name (so buildings and roads stay whole), or, with ``--clip``, only the nodes
inside the box (ways then name nodes the file lacks, as in an extract cut at its edge). The output
declares the box as its bounds unless ``--no-bounds`` (as Overpass exports do not). The format follows
the output's name (``.osm``, ``.osm.gz``, ``.osm.bz2``, ``.osm.pbf``). Data © OpenStreetMap
contributors, ODbL 1.0: keep the attribution beside what you cut.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import osmium
import osmium.io
import osmium.osm

from navverse.city.osm.files import check_osm_file, osmium_file


def _box(lat: float, lon: float, radius: float) -> tuple[float, float, float, float]:
    dlat = radius / 111_320.0
    dlon = radius / (111_320.0 * math.cos(math.radians(lat)))
    return lon - dlon, lat - dlat, lon + dlon, lat + dlat


def cut(
    source: Path, target: Path, *, center: tuple[float, float], radius: float, clip: bool, bounds: bool
) -> None:
    """Write the sample of ``source`` around ``center`` to ``target`` (see the module docstring)."""
    fmt = check_osm_file(source).format
    west, south, east, north = _box(*center, radius)

    def inside(location: osmium.osm.Location) -> bool:
        return location.valid() and west <= location.lon <= east and south <= location.lat <= north

    near_nodes = {
        n.id for n in osmium.FileProcessor(osmium_file(source, fmt), osmium.osm.NODE) if inside(n.location)
    }
    ways, way_nodes = set(), set()
    for way in osmium.FileProcessor(osmium_file(source, fmt), osmium.osm.WAY):
        refs = [n.ref for n in way.nodes]
        if any(ref in near_nodes for ref in refs):
            ways.add(way.id)
            way_nodes.update(refs)
    relations = set()
    for relation in osmium.FileProcessor(osmium_file(source, fmt), osmium.osm.RELATION):
        if relation.tags.get("type") == "multipolygon" and any(
            m.type == "w" and m.ref in ways for m in relation.members
        ):
            relations.add(relation.id)
    member_ways = set()
    for relation in osmium.FileProcessor(osmium_file(source, fmt), osmium.osm.RELATION):
        if relation.id in relations:
            member_ways.update(m.ref for m in relation.members if m.type == "w")
    for way in osmium.FileProcessor(osmium_file(source, fmt), osmium.osm.WAY):
        if way.id in member_ways:
            ways.add(way.id)
            way_nodes.update(n.ref for n in way.nodes)
    keep_nodes = near_nodes if clip else way_nodes | near_nodes
    header = osmium.io.Header()
    if bounds:
        header.add_box(osmium.osm.Box(osmium.osm.Location(west, south), osmium.osm.Location(east, north)))
    header.set("generator", "navverse scripts/cut_osm_sample.py")
    target.unlink(missing_ok=True)
    writer = osmium.SimpleWriter(str(target), header=header)
    try:
        for obj in osmium.FileProcessor(osmium_file(source, fmt)):
            kind = obj.type_str()
            if (
                (kind == "n" and obj.id in keep_nodes)
                or (kind == "w" and obj.id in ways)
                or (kind == "r" and obj.id in relations)
            ):
                writer.add(obj)
    finally:
        writer.close()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("source", type=Path)
    parser.add_argument("target", type=Path)
    parser.add_argument("--center", type=float, nargs=2, required=True, metavar=("LAT", "LON"))
    parser.add_argument("--radius", type=float, default=80.0, help="half the box's side (m)")
    parser.add_argument("--clip", action="store_true", help="keep only the nodes inside the box")
    parser.add_argument("--no-bounds", action="store_true", help="declare no bounds")
    args = parser.parse_args()
    cut(
        args.source,
        args.target,
        center=(args.center[0], args.center[1]),
        radius=args.radius,
        clip=args.clip,
        bounds=not args.no_bounds,
    )
    print(f"wrote {args.target} ({args.target.stat().st_size / 1024:.0f} KiB)")


if __name__ == "__main__":
    main()
