"""Whether population kept a built city's sidewalks passable: its bare and populated navmeshes compared.

Usage::

    python scripts/street_passability.py [TARGET ...] [--json PATH]

For each built city target (default: every target with a ``street_geometry`` and a populated
``scene``), the populated navmesh is the target's own (``scene/navmesh.bin``); the bare one is
built here from ``street_geometry`` with the same settings. The table gives the sidewalk grid points,
those objects took off the navmesh, the sidewalk islands before and after, cut-off pieces and
pockets, crosswalks still on their island (``navverse/city/street_life/passability.py``), and the clear
walkway
width the populate stage measured (min / median).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from rich.console import Console
from rich.table import Table

from navverse.city.geometry.street_plan import STREET_PLAN_FILE, load_street_plan
from navverse.city.street_life.passability import sidewalk_passability
from navverse.nav.scene_navmesh import build_scene_navmesh, load_scene_navmesh
from navverse.scene.directory import read_scene
from navverse.scene.heights import SurfaceHeights

ROOT = Path(__file__).resolve().parents[1]
TARGETS = ROOT / "data" / "built" / "targets"


def _populated_targets() -> list[str]:
    return sorted(
        t.name
        for t in TARGETS.iterdir()
        if (t / "street_geometry").exists()
        and (t / "scene").exists()
        and json.loads((t / "geometry" / "manifest.json").read_text())["stage"] == "populate"
    )


def passability_row(target: str) -> dict[str, object]:
    """The comparison of one target's bare and populated sidewalk networks."""
    root = TARGETS / target
    street = read_scene(root / "street_geometry")
    populated = load_scene_navmesh(root / "scene")
    bare = build_scene_navmesh(street, populated.settings)
    plan = load_street_plan(root / "street_geometry" / STREET_PLAN_FILE)
    result = sidewalk_passability(bare, populated, plan, SurfaceHeights(street))
    stats = json.loads((root / "geometry" / "manifest.json").read_text())["stats"]
    clear = stats.get("walkway_clearance_m", {})
    return {
        "target": target,
        "points": result.points,
        "covered": result.covered,
        "islands_before": result.islands_before,
        "islands_after": result.islands_after,
        "cuts": result.cuts,
        "pocket_points": result.pocket_points,
        "crosswalks": result.crosswalks,
        "crosswalks_cut": result.crosswalks_cut,
        "navmesh_islands_before": bare.num_islands,
        "navmesh_islands_after": populated.num_islands,
        "clear_min": clear.get("min"),
        "clear_median": clear.get("median"),
        "passable": result.passable,
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("targets", nargs="*", help="built city targets (default: every populated one)")
    parser.add_argument("--json", type=Path, help="also write the rows here")
    args = parser.parse_args(argv)
    if not TARGETS.is_dir():
        print(f"no built targets under {TARGETS}: run `make scenes` first", file=sys.stderr)
        return 1
    targets = args.targets or _populated_targets()
    missing = [t for t in targets if not (TARGETS / t / "street_geometry").exists()]
    if missing:
        print(f"not built city targets: {', '.join(missing)}", file=sys.stderr)
        return 1
    table = Table(title="Sidewalk passability: bare vs populated navmesh")
    for column in (
        "target",
        "points",
        "covered",
        "islands before/after",
        "cuts",
        "pocket pts",
        "crosswalks cut",
        "navmesh islands before/after",
        "clear min/median m",
    ):
        table.add_column(column)
    rows = []
    for target in targets:
        row = passability_row(target)
        rows.append(row)
        table.add_row(
            target,
            str(row["points"]),
            str(row["covered"]),
            f"{row['islands_before']} / {row['islands_after']}",
            str(row["cuts"]),
            str(row["pocket_points"]),
            f"{row['crosswalks_cut']} of {row['crosswalks']}",
            f"{row['navmesh_islands_before']} / {row['navmesh_islands_after']}",
            f"{row['clear_min']} / {row['clear_median']}",
        )
    Console(width=160).print(table)
    if args.json:
        args.json.write_text(json.dumps(rows, indent=2) + "\n")
    return 0 if all(row["passable"] for row in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
