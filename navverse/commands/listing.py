"""``navverse list WHAT``: what the toolkit knows, as tables (or JSON for scripts).

Each kind of listing is a function returning :class:`Listing` tables: rows of plain JSON values, and
columns that say how a row is shown in a table. :func:`cmd_list` prints them as rich tables or, with
``--json``, the rows of every table as one JSON list. The navmesh presets and scene-type profiles are
printed by ``navverse show presets`` and are not listed here. The registries are imported inside the
functions, so the command line starts quickly and listing one kind does not load the others (PyBullet,
the object library). :func:`register` adds the command's parser.
"""

from __future__ import annotations

import argparse
import json
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from rich.console import Console

from navverse.commands.common import Shared, Subparsers, command, console_table

__all__ = ["CATEGORY_KINDS", "LIST_KINDS", "Column", "Listing", "cmd_list", "listings", "register"]

Row = dict[str, Any]

CATEGORY_KINDS: tuple[str, ...] = ("objects", "places")
"""What ``navverse list categories --kind`` chooses: object categories or place categories."""

_RST_ROLE = re.compile(r":[a-z]+:`(~?)([^`]+)`")


@dataclass(frozen=True)
class Column:
    """A table column: its heading and the text of a row's cell."""

    heading: str
    cell: Callable[[Row], str]


@dataclass(frozen=True)
class Listing:
    """One table of a listing.

    Parameters
    ----------
    title : str
        The table's title.
    columns : tuple of Column
        How a row is shown, in column order.
    rows : list of dict
        One JSON-serialisable dict per line (the ``--json`` output).
    """

    title: str
    columns: tuple[Column, ...]
    rows: list[Row]


def _text(value: Any) -> str:
    """A JSON value as table text: yes/no, comma-separated lists, empty for None."""
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (list, tuple)):
        return ", ".join(str(v) for v in value)
    return "" if value is None else str(value)


def _field(heading: str, key: str) -> Column:
    """A column showing the row's ``key`` as it is."""
    return Column(heading, lambda row: _text(row[key]))


def _span(low: float, high: float, *, digits: int = 1) -> str:
    """``low–high`` (one number when they are equal)."""
    return f"{low:.{digits}f}" if low == high else f"{low:.{digits}f}–{high:.{digits}f}"


def _first_line(obj: object) -> str:
    """The first line of an object's docstring, reStructuredText roles and literals made plain."""
    doc = (getattr(obj, "__doc__", None) or "").strip()
    line = doc.splitlines()[0] if doc else ""
    plain = _RST_ROLE.sub(lambda m: m.group(2).rsplit(".", 1)[-1] if m.group(1) else m.group(2), line)
    return plain.replace("``", "")


def _building_types() -> list[Listing]:
    from navverse.indoor.programs import PROGRAMS

    rows = []
    for name, program in PROGRAMS.items():
        sides = 2 if program.spine.sides == "both" else 1
        depth = [round(program.spine.width[i] + sides * program.side_depth[i], 3) for i in (0, 1)]
        rows.append(
            {
                "name": name,
                "description": program.description,
                "length_m": list(program.length),
                "depth_m": depth,
                "spine": program.spine.room_type,
                "rooms": [spec.room_type for spec in program.rooms],
                "exits": program.exits,
                "ceiling_height_m": list(program.ceiling_height),
            }
        )
    columns = (
        _field("building type", "name"),
        Column("footprint (m)", lambda r: f"{_span(*r['length_m'], digits=0)} × {_span(*r['depth_m'])}"),
        _field("spine", "spine"),
        _field("exits", "exits"),
        _field("description", "description"),
    )
    return [Listing("building types (indoor_layout: building_type)", columns, rows)]


def _room_types() -> list[Listing]:
    from navverse.indoor.programs import PROGRAMS, ROOM_FURNITURE

    buildings: dict[str, list[str]] = {}
    areas: dict[str, list[tuple[float, float]]] = {}
    spines = {program.spine.room_type for program in PROGRAMS.values()}
    for name, program in PROGRAMS.items():
        buildings.setdefault(program.spine.room_type, []).append(name)
        for spec in program.rooms:
            buildings.setdefault(spec.room_type, []).append(name)
            areas.setdefault(spec.room_type, []).append(spec.area)
    rows = []
    for room_type in sorted(buildings):
        spans = areas.get(room_type, [])
        rows.append(
            {
                "name": room_type,
                "role": "spine" if room_type in spines else "room",
                "building_types": sorted(set(buildings[room_type])),
                "area_m2": [min(a[0] for a in spans), max(a[1] for a in spans)] if spans else None,
                "furniture": sorted({rule.category for rule in ROOM_FURNITURE.get(room_type, ())}),
            }
        )
    columns = (
        _field("room type", "name"),
        _field("role", "role"),
        Column("area (m²)", lambda r: _span(*r["area_m2"], digits=0) if r["area_m2"] else "(spine)"),
        _field("building types", "building_types"),
        _field("furniture", "furniture"),
    )
    return [Listing("room types (indoor_layout: extra_furniture room_type)", columns, rows)]


def _size_text(row: Row) -> str:
    spans = zip(row["size_min_m"], row["size_max_m"], strict=True)
    return " × ".join(_span(low, high, digits=2) for low, high in spans)


def _object_categories() -> Listing:
    from navverse.assets.library import asset, categories

    rows = []
    for name in categories():
        spec = asset(name)
        rows.append(
            {
                "name": name,
                "kind": "object",
                "size_min_m": list(spec.size_min),
                "size_max_m": list(spec.size_max),
                "placement": spec.placement,
                "contexts": list(spec.contexts),
            }
        )
    columns = (
        _field("object category", "name"),
        Column("size (m, width × depth × height)", _size_text),
        _field("placement", "placement"),
        _field("contexts", "contexts"),
    )
    return Listing("object categories (navverse.assets)", columns, rows)


def _place_categories() -> Listing:
    from navverse.assets.facade.storefronts import DESIGNS_PER_CATEGORY, PLACE_CATEGORIES

    rows = [
        {"name": name, "kind": "place", "designs": DESIGNS_PER_CATEGORY, "fallback": name == "shop"}
        for name in PLACE_CATEGORIES
    ]
    columns = (
        _field("place category", "name"),
        _field("storefront designs", "designs"),
        Column("note", lambda r: "any other OSM shop=*" if r["fallback"] else ""),
    )
    return Listing("place categories (PlaceNav goals, storefronts)", columns, rows)


def _categories(kind: str | None) -> list[Listing]:
    makers = {"objects": _object_categories, "places": _place_categories}
    return [makers[name]() for name in (CATEGORY_KINDS if kind is None else (kind,))]


def _agents() -> list[Listing]:
    from navverse.eval.agents import BUILTIN_AGENTS, agent_factory

    rows = []
    for name, source in BUILTIN_AGENTS.items():
        agent = agent_factory(name)
        rows.append(
            {
                "name": name,
                "privileged": bool(getattr(agent, "privileged", False)),
                "action_mode": getattr(agent, "action_mode", None),
                "sensors": list(getattr(agent, "sensors", ("rgb", "depth"))),
                "description": _first_line(agent),
                "source": source,
            }
        )
    columns = (
        _field("agent", "name"),
        _field("privileged", "privileged"),
        _field("action mode", "action_mode"),
        Column("sensors", lambda r: _text(r["sensors"]) or "(no images)"),
        _field("description", "description"),
    )
    return [Listing("built-in agents (run-agent --agent NAME)", columns, rows)]


def _speed_text(row: Row) -> str:
    forward, sideways, turn = row["max_velocity"]
    return f"{forward:g} m/s, {sideways:g} m/s, {turn:g} rad/s"


def _embodiments() -> list[Listing]:
    from navverse.sim.embodiments import EMBODIMENTS, make_embodiment

    rows = []
    for name in EMBODIMENTS:
        robot = make_embodiment(name)
        rows.append(
            {
                "name": name,
                "radius_m": float(robot.radius),
                "size_m": [round(float(v), 3) for v in robot.size],
                "max_velocity": [float(v) for v in robot.max_velocity],
                "description": _first_line(type(robot)),
            }
        )
    columns = (
        _field("embodiment", "name"),
        _field("radius (m)", "radius_m"),
        Column("size (m)", lambda r: " × ".join(f"{v:.2f}" for v in r["size_m"])),
        Column("max forward, sideways, turn", _speed_text),
        _field("description", "description"),
    )
    return [Listing("embodiments (--embodiment NAME)", columns, rows)]


LISTERS: dict[str, Callable[[str | None], list[Listing]]] = {
    "building-types": lambda kind: _building_types(),
    "room-types": lambda kind: _room_types(),
    "categories": _categories,
    "agents": lambda kind: _agents(),
    "embodiments": lambda kind: _embodiments(),
}
"""The listings by name; each is given ``--kind`` (used by ``categories`` alone)."""

LIST_KINDS: tuple[str, ...] = tuple(LISTERS)
"""What ``navverse list`` lists."""


def listings(what: str, *, kind: str | None = None) -> list[Listing]:
    """The tables of one kind of listing.

    Parameters
    ----------
    what : str
        One of :data:`LIST_KINDS`.
    kind : str, optional
        For ``categories``: one of :data:`CATEGORY_KINDS` (default: both).

    Returns
    -------
    list of Listing
        Its tables, in print order.
    """
    return LISTERS[what](kind)


def _print_tables(console: Console, tables: Sequence[Listing]) -> None:
    from rich.text import Text

    for listing in tables:
        table = console_table(console, title=listing.title, title_justify="left")
        for column in listing.columns:
            table.add_column(column.heading, overflow="fold")
        for row in listing.rows:
            table.add_row(*(Text(column.cell(row)) for column in listing.columns))
        console.print(table)


def cmd_list(args: argparse.Namespace, console: Console) -> int:
    """Print the building types, room types, categories, agents or embodiments (``--json``: as JSON).

    Raises
    ------
    NavverseError
        If ``--kind`` is given for a listing other than ``categories``.
    """
    from navverse.errors import NavverseError

    kind = getattr(args, "kind", None)
    if kind is not None and args.what != "categories":
        raise NavverseError(f"--kind chooses among categories; `navverse list {args.what}` takes no --kind")
    tables = listings(args.what, kind=kind)
    if args.json:
        rows = [row for table in tables for row in table.rows]
        console.out(json.dumps(rows, indent=2, ensure_ascii=False), highlight=False)
    else:
        _print_tables(console, tables)
    return 0


def register(sub: Subparsers, shared: Shared) -> None:
    """Add ``navverse list WHAT`` to ``sub``."""
    listing = command(
        sub, "list", summary="list building types, room types, categories, agents or embodiments",
        examples=("navverse list building-types", "navverse list categories --kind places",
                  "navverse list agents --json"),
    )  # fmt: skip
    listing.add_argument(
        "what", choices=LIST_KINDS, metavar="WHAT",
        help=f"one of: {', '.join(LIST_KINDS)} (navmesh presets: navverse show presets)",
    )  # fmt: skip
    listing.add_argument(
        "--kind", choices=CATEGORY_KINDS, default=None,
        help="for categories: only object categories (goal objects, furniture, street objects) or only "
        "place categories (PlaceNav goals); default: both",
    )  # fmt: skip
    listing.add_argument(
        "--json", action="store_true", help="print the rows as one JSON list (for scripts) instead of tables"
    )
    listing.set_defaults(func=cmd_list)
