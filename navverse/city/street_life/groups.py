"""Contextual object groups: small scenes of everyday street life, placed where they make sense.

A group (:data:`~navverse.city.street_life.group_catalogue.GROUPS`, 30 of them) is a few objects in a fixed
layout that tell a story together: a bench at a bus stop with a briefcase and an umbrella on its
seat (``bus_stop_wait``), a bench in a park with a notebook and a coffee cup (``park_relaxing``),
cones, a fence, a ladder and a toolbox by the road (``construction_repair``). :func:`plan_groups`
returns :class:`GroupMember` records (category, position, height, heading, size, group instance,
support), never geometry; the population stage builds the objects.

Regions
-------
Each group names the **regions** it may stand in
(:data:`~navverse.city.street_life.group_catalogue.REGIONS`). A
region is read from the street plan's surface classes, the sidewalk zones and the map's places and
furniture:

================  ===============================================  ==================================
region            anchors drawn in                                 members stand on
================  ===============================================  ==================================
``street``        furniture and frontage zones, verges             those zones and the open land
                                                                   (ground, green, plaza) beside them
``bus_stop``      the same, within 12 m of a mapped bus stop or    the same
                  of a placed bus stop sign or shelter
``construction``  frontage zones and verges (open ground by a      the same
                  road)
``cafe_front``    frontage zones and verges within 12 m of a       the same
                  cafe, restaurant, bar, pub, fast food or ice
                  cream place (:data:`CAFE_CATEGORIES`)
``shop_front``    the same, of shops (``shop=*`` places)           the same
``school``        street zones and open land within 40 m of a      the same
                  school (:data:`SCHOOL_CATEGORIES`)
``park``          green areas                                      green, ground, plaza
``plaza``         plazas and pedestrian areas                      plaza, green, ground
``sports``        green areas and plazas of at least 900 m²        green, plaza, ground
``parking``       parking lots                                     parking, ground, green
``waterside``     ground and green within 10 m of water            ground, green, plaza
================  ===============================================  ==================================

Nothing ever stands on the clear walkway, a road, a shared street, a curb, a crosswalk, in a
building or in water, nor in a junction's corner clearance; every footprint of a group lies wholly in
its region's land (footprints as :func:`~navverse.city.street_life.objects.footprint`).

Anchors and rotation
--------------------
Candidate anchors (the origin of a group's layout) are drawn uniformly over each region's anchor
area with the generator. A group is turned as a whole so that its front (local +y) faces the
nearest road (``waterside``: the nearest water; ``park`` and ``sports``: a drawn heading); its
members keep their relative layout. At each anchor the layout is also tried mirrored (x to -x) and
shifted 0.35 m along its heading, which fits it into narrow strips.

Choice and spacing
------------------
Group types are placed in a fair rotation: every round visits each type still in play once, in an
order drawn anew each round, and places at most one group of it, so a city gets many different
groups before it gets a second of any. A type leaves the rotation when none of its next ``tries``
candidate anchors fits, or when the budget has no room for its members. Two groups' anchors are at
least ``min_spacing`` (8 m) apart, and so are any two members of different groups; members keep
``gap`` from every object already placed (street objects, and whatever else is passed as ``avoid``,
such as parked cars).

Stacking
--------
A member "on" another stands on one of that member's support areas
(:class:`~navverse.assets.spec.SupportArea`, from ``supports_of(category, size)``; supports stand on
the ground): its position and heading are given in the support's local frame, its rectangle is moved
(clamped) so that it lies wholly inside the area, and its ``z`` is the area's height. Heights are
above the ground under the group (stand a member on the ground height under its support). Support
areas are computed with the size ``size_of`` gives the support, so **the support must be built at
exactly** :attr:`GroupMember.size` (which is ``size_of(category)`` for every member). On a slatted
top (a pallet's deck boards run one way or the other by design) only the centre is sure to be a
board, so an item stands there, whole over a board, not bridging a gap.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import LineString, Point, Polygon
from shapely.geometry.base import BaseGeometry
from shapely.strtree import STRtree

from navverse.assets.spec import SupportArea
from navverse.city.geometry.street_plan import StreetPlan
from navverse.city.map import CityMap
from navverse.city.shape_grid import ShapeGrid
from navverse.city.street_life.group_catalogue import (
    BUS_STOP_CATEGORIES,
    CAFE_CATEGORIES,
    GROUPS,
    REGIONS,
    SCHOOL_CATEGORIES,
    GroupSpec,
    Member,
    RegionSpec,
)
from navverse.city.street_life.objects import BASE_FOOTPRINT, Placement, footprint
from navverse.city.street_life.zones import StreetZones

__all__ = ["GroupMember", "GroupPlan", "plan_groups"]

SizeOf = Callable[[str], tuple[float, float, float]]
"""``size_of(category) -> (width, depth, height)`` of the object to build (m)."""
SupportsOf = Callable[[str, tuple[float, float, float]], list[SupportArea]]
"""``supports_of(category, size) -> [SupportArea]``: the support areas of an object of that size."""


@dataclass(frozen=True)
class GroupMember:
    """One object of a placed group.

    Attributes
    ----------
    category : str
        Object category.
    x, y : float
        Position of its centre on the ground plan (m).
    z : float
        Height of its bottom above the ground under the group (m): 0 on the ground, the support's
        ``z`` plus its support area's height when stacked.
    heading : float
        Direction its front faces (radians from +x), as in
        :class:`~navverse.city.street_life.objects.Placement`: the object's yaw is ``heading - pi / 2``.
    group : str
        Group instance (``bus_stop_wait-3``).
    zone : str
        What it stands on: a sidewalk zone (``furniture``, ``frontage``, ``verge``) or a land class
        (``ground``, ``green``, ``plaza``, ``parking``); a stacked member has its support's.
    region : str
        The region its group was placed in (:data:`REGIONS`).
    support : int or None
        Index in :attr:`GroupPlan.members` of the member it stands on, or None.
    size : tuple of float
        The exact size to build it with (``size_of(category)``). Supports **must** be built at this
        size: stacked members stand on the support areas of an object of exactly this size.
    """

    category: str
    x: float
    y: float
    z: float
    heading: float
    group: str
    zone: str
    region: str
    support: int | None
    size: tuple[float, float, float]


@dataclass(frozen=True)
class GroupPlan:
    """The placed groups.

    Attributes
    ----------
    members : tuple of GroupMember
        Every member, group by group, supports before what stands on them.
    groups : dict
        Number of groups placed, by group type.
    skipped : dict
        Group types that were not placed at all, by reason (``"<type>: <why>"``).
    anchors : dict
        ``{group instance: (x, y, heading)}``: where each group's layout origin stands and the
        direction its front faces (radians from +x).
    """

    members: tuple[GroupMember, ...]
    groups: dict[str, int]
    skipped: dict[str, int]
    anchors: dict[str, tuple[float, float, float]]


# --------------------------------------------------------------------------------------------------
# Land: the pieces of plan classes and zones a group may be anchored in and stand on.

_ZONE_ORDER = ("furniture", "frontage", "verge", "parking", "plaza", "green", "ground")


def _polygons(geometry: BaseGeometry) -> list[Polygon]:
    if geometry.is_empty:
        return []
    parts = getattr(geometry, "geoms", [geometry])
    out: list[Polygon] = []
    for part in parts:
        if part.geom_type == "Polygon" and part.area > 1e-6:
            out.append(part)
        elif part.geom_type in ("MultiPolygon", "GeometryCollection"):
            out += _polygons(part)
    return out


class _Land:
    """Labelled pieces of land with an STR tree, for coverage tests and zone look-ups."""

    def __init__(self, plan: StreetPlan, zones: StreetZones) -> None:
        classes = plan.classes
        sources = {
            "furniture": zones.furniture,
            "frontage": zones.frontage,
            "verge": zones.verge,
            "ground": classes["ground"],
            "green": classes["green"],
            "plaza": shapely.union_all([classes["plaza"], classes["pedestrian"]]),
            "parking": classes["parking"],
        }
        self.pieces: list[Polygon] = []
        self.labels: list[str] = []
        for label, geometry in sources.items():
            for piece in _polygons(geometry):
                self.pieces.append(piece)
                self.labels.append(label)
        shapely.prepare(self.pieces)
        self.tree = STRtree(self.pieces)

    def of(self, labels: frozenset[str]) -> list[Polygon]:
        return [p for p, label in zip(self.pieces, self.labels, strict=True) if label in labels]

    def covers(self, shape: Polygon, allowed: frozenset[str]) -> bool:
        """Whether ``shape`` lies wholly on pieces of the ``allowed`` labels."""
        hits = [int(i) for i in self.tree.query(shape, predicate="intersects") if self.labels[i] in allowed]
        if not hits:
            return False
        for i in hits:
            if self.pieces[i].contains(shape):
                return True
        rest: BaseGeometry = shape
        try:
            for i in hits:
                rest = rest.difference(self.pieces[i])
                if rest.is_empty:
                    return True
        except shapely.errors.GEOSException:
            return False  # a degenerate piece: not trusted to cover anything
        return rest.area < 1e-8

    def zone_at(self, x: float, y: float) -> str:
        hits = {self.labels[int(i)] for i in self.tree.query(Point(x, y), predicate="intersects")}
        return next((z for z in _ZONE_ORDER if z in hits), "open")


def _sample(polygons: list[Polygon], count: int, rng: np.random.Generator) -> np.ndarray:
    """``count`` points drawn uniformly over ``polygons`` (fewer where a thin piece resists)."""
    areas = np.array([p.area for p in polygons], dtype=np.float64)
    if count <= 0 or not len(areas) or areas.sum() <= 0:
        return np.zeros((0, 2))
    per = rng.multinomial(count, areas / areas.sum())
    out = []
    for polygon, n in zip(polygons, per, strict=True):
        if n == 0:
            continue
        x0, y0, x1, y1 = polygon.bounds
        fill = max(polygon.area / max((x1 - x0) * (y1 - y0), 1e-9), 1e-3)
        need = int(n)
        for _ in range(4):
            draw = min(int(need / fill * 1.5) + 8, 200_000)
            xs, ys = rng.uniform(x0, x1, draw), rng.uniform(y0, y1, draw)
            inside = shapely.contains_xy(polygon, xs, ys)
            points = np.column_stack([xs[inside], ys[inside]])[:need]
            out.append(points)
            need -= len(points)
            if need <= 0:
                break
    return np.concatenate(out) if out else np.zeros((0, 2))


def _facing(points: np.ndarray, targets: list[BaseGeometry]) -> np.ndarray:
    """Heading from each point to the nearest point of ``targets`` (NaN where there is none)."""
    headings = np.full(len(points), np.nan)
    if not len(points) or not targets:
        return headings
    tree = STRtree(targets)
    geoms = shapely.points(points)
    index = tree.query_nearest(geoms, all_matches=False)
    lines = shapely.shortest_line(geoms[index[0]], np.asarray(targets, dtype=object)[index[1]])
    coords = shapely.get_coordinates(lines).reshape(-1, 2, 2)
    delta = coords[:, 1] - coords[:, 0]
    ok = np.hypot(delta[:, 0], delta[:, 1]) > 1e-6
    headings[index[0][ok]] = np.arctan2(delta[ok, 1], delta[ok, 0])
    return headings


# --------------------------------------------------------------------------------------------------
# Spacing: grids of placed anchors and footprints.


@dataclass
class _Pose:
    category: str
    x: float
    y: float
    z: float
    heading: float
    size: tuple[float, float, float]
    support: int | None
    shape: Polygon


def _world(ax: float, ay: float, heading: float, x: float, y: float) -> tuple[float, float]:
    """A point of a frame at (ax, ay) whose front (+y) faces ``heading``, right (+x) to its right."""
    fx, fy = math.cos(heading), math.sin(heading)
    return ax + x * fy + y * fx, ay - x * fx + y * fy


def _half_extents(category: str, size: tuple[float, float, float], turn: float) -> tuple[float, float]:
    width, depth = BASE_FOOTPRINT.get(category, (size[0], size[1]))
    c, s = abs(math.cos(turn)), abs(math.sin(turn))
    return c * width / 2.0 + s * depth / 2.0, s * width / 2.0 + c * depth / 2.0


def _stack(
    pose: _Pose,
    member: Member,
    size: tuple[float, float, float],
    areas: list[SupportArea],
    mirror: float,
) -> _Pose | None:
    """Where ``member`` stands on ``pose``'s support areas (clamped wholly inside one), or None."""
    turn = mirror * math.radians(member.turn)
    hx, hy = _half_extents(member.category, size, turn)
    mx, my = mirror * member.x, member.y
    fits = [a for a in areas if 2 * hx <= a.width + 1e-9 and 2 * hy <= a.depth + 1e-9]
    if not fits:
        return None
    area = next((a for a in fits if a.x_min <= mx <= a.x_max and a.y_min <= my <= a.y_max), fits[0])
    cx = min(max(mx, area.x_min + hx), area.x_max - hx)
    cy = min(max(my, area.y_min + hy), area.y_max - hy)
    x, y = _world(pose.x, pose.y, pose.heading, cx, cy)
    heading = math.remainder(pose.heading + turn, math.tau)
    shape = footprint(member.category, size, x, y, heading)
    return _Pose(member.category, x, y, pose.z + area.height, heading, size, None, shape)


def plan_groups(
    city: CityMap,
    plan: StreetPlan,
    zones: StreetZones,
    placed: Sequence[Placement],
    size_of: SizeOf,
    supports_of: SupportsOf,
    rng: np.random.Generator,
    *,
    budget: int,
    min_spacing: float = 8.0,
    excluded: frozenset[str] = frozenset(),
    selected: frozenset[str] | set[str] | None = None,
    gap: float,
    avoid: Sequence[BaseGeometry] = (),
    groups: tuple[GroupSpec, ...] = GROUPS,
    candidates: int = 3000,
    candidate_area: float = 4.0,
    tries: int = 60,
) -> GroupPlan:
    """Place contextual object groups in a city (see the module docstring).

    Parameters
    ----------
    city, plan, zones : CityMap, StreetPlan, StreetZones
        The map, its ground plan and its street zones.
    placed : sequence of Placement
        Street objects already planned (:func:`~navverse.city.street_life.objects.plan_street_objects`);
        their footprints (with ``size_of``) are kept ``gap`` clear of.
    size_of : callable
        ``size_of(category) -> (width, depth, height)``: the size every member (and every placed
        street object) is built with, e.g. the category's ``size_max``.
    supports_of : callable
        ``supports_of(category, size) -> [SupportArea]``, e.g. ``asset(category).support_areas(size)``;
        called with ``size_of(category)``, so supports must be built at exactly that size.
    rng : numpy.random.Generator
        Draws the anchors, park headings and the rotation order; the same state gives the same plan.
    budget : int
        The most member objects placed in all.
    min_spacing : float
        Least distance between two groups' anchors, and between members of different groups (m).
    excluded : frozenset of str
        Categories never placed: a group that needs one is skipped.
    selected : set of str, optional
        The group types to place (None: all).
    gap : float
        Free space kept between a member's footprint and objects already placed (m).
    avoid : sequence of BaseGeometry
        Other footprints to keep ``gap`` clear of (parked cars, objects placed by other stages).
    groups : tuple of GroupSpec
        The group table.
    candidates : int
        Most candidate anchors drawn per region.
    candidate_area : float
        One candidate anchor is drawn per this much of a region's anchor area (m²), up to
        ``candidates``.
    tries : int
        Candidate anchors tried per turn of a type before it leaves the rotation.

    Returns
    -------
    GroupPlan
        The members, groups placed by type, and types not placed by reason.

    Raises
    ------
    ValueError
        If ``selected`` names a group type not in ``groups``.
    """
    names = [g.name for g in groups]
    if selected is not None:
        unknown = sorted(set(selected) - set(names))
        if unknown:
            raise ValueError(f"unknown group types {unknown}; known: {sorted(names)}")
    skipped: Counter[str] = Counter()
    active: list[GroupSpec] = []
    for group in groups:
        if selected is not None and group.name not in selected:
            continue
        needs = sorted(group.categories & excluded)
        if needs:
            skipped[f"{group.name}: needs excluded {needs[0]}"] += 1
            continue
        active.append(group)
    if budget <= 0 or not active:
        for group in active:
            skipped[f"{group.name}: budget spent"] += 1
        return GroupPlan(members=(), groups={}, skipped=dict(sorted(skipped.items())), anchors={})

    sizes: dict[str, tuple[float, float, float]] = {}

    def size(category: str) -> tuple[float, float, float]:
        if category not in sizes:
            sizes[category] = tuple(float(v) for v in size_of(category))  # type: ignore[assignment]
        return sizes[category]

    supports: dict[str, list[SupportArea]] = {}

    def areas(category: str) -> list[SupportArea]:
        if category not in supports:
            supports[category] = list(supports_of(category, size(category)))
        return supports[category]

    land = _Land(plan, zones)
    taken = [footprint(p.category, size(p.category), p.x, p.y, p.heading) for p in placed]
    taken += [g for g in avoid if not g.is_empty]
    taken_tree = STRtree(taken) if taken else None
    keep_clear = zones.junctions
    shapely.prepare(keep_clear)

    # Candidate anchors of every region in use, in a fixed order of regions.
    region_names = sorted({r for g in active for r in g.regions})
    region_points: dict[str, np.ndarray] = {}
    region_headings: dict[str, np.ndarray] = {}
    roads = [LineString(r.centerline.points) for r in city.roads]
    water = _polygons(plan.classes["water"])
    for name in region_names:
        spec = REGIONS[name]
        seeds = [p for p in land.of(spec.seeds) if p.area >= spec.min_area]
        target = _near(city, placed, plan, spec)
        if target is not None:
            seeds = _clip(seeds, target)
        total = sum(p.area for p in seeds)
        count = min(candidates, math.ceil(total / candidate_area)) if total > 0 else 0
        points = _sample(seeds, count, rng)
        if spec.facing == "random":
            heading = rng.uniform(-math.pi, math.pi, len(points))
        else:
            heading = _facing(points, roads if spec.facing == "road" else list(water))
            missing = np.isnan(heading)
            heading[missing] = rng.uniform(-math.pi, math.pi, int(missing.sum()))
        region_points[name], region_headings[name] = points, heading

    queues: dict[str, list[tuple[str, int]]] = {}
    for group in active:
        queue = [(r, k) for r in group.regions if r in region_points for k in range(len(region_points[r]))]
        order = rng.permutation(len(queue)) if queue else []
        queues[group.name] = [queue[int(i)] for i in order]
    cursor = dict.fromkeys(queues, 0)

    anchors = ShapeGrid(max(min_spacing, 4.0))
    shapes = ShapeGrid(max(min_spacing, 4.0))
    members: list[GroupMember] = []
    counts: Counter[str] = Counter()
    placed_anchors: dict[str, tuple[float, float, float]] = {}

    def fit(
        group: GroupSpec, ax: float, ay: float, heading: float, mirror: float, allowed: frozenset[str]
    ) -> list[_Pose] | None:
        poses: list[_Pose] = []
        for k, member in enumerate(group.members):
            msize = size(member.category)
            if member.on is not None:
                pose = _stack(
                    poses[member.on], member, msize, areas(group.members[member.on].category), mirror
                )
                if pose is None:
                    return None
                pose.support = member.on
                for other in poses:
                    if other.support == member.on and other.shape.intersects(pose.shape):
                        return None
                poses.append(pose)
                continue
            x, y = _world(ax, ay, heading, mirror * member.x, member.y)
            h = math.remainder(heading + mirror * math.radians(member.turn), math.tau)
            shape = footprint(member.category, msize, x, y, h)
            if shapes.near(shape, min_spacing):
                return None
            if taken_tree is not None and len(taken_tree.query(shape, predicate="dwithin", distance=gap)):
                return None
            if keep_clear.intersects(shape) or not land.covers(shape, allowed):
                return None
            if any(p.support is None and p.shape.intersects(shape) for p in poses[:k]):
                return None
            poses.append(_Pose(member.category, x, y, 0.0, h, msize, None, shape))
        return poses

    rotation = list(active)
    while rotation:
        order = rng.permutation(len(rotation))
        keep: list[GroupSpec] = []
        for index in order:
            group = rotation[int(index)]
            if len(members) + len(group.members) > budget:
                if counts[group.name] == 0:
                    skipped[f"{group.name}: budget spent"] += 1
                continue
            queue, start = queues[group.name], cursor[group.name]
            found = None
            k = start
            while k < len(queue) and k - start < tries and found is None:
                region, c = queue[k]
                k += 1
                ax, ay = (float(v) for v in region_points[region][c])
                heading = float(region_headings[region][c])
                if anchors.near(Point(ax, ay), min_spacing - 0.35):
                    continue  # no shift gets it far enough from another group
                allowed = REGIONS[region].allowed
                for shift in (0.0, -0.35, 0.35):
                    sx, sy = ax + shift * math.cos(heading), ay + shift * math.sin(heading)
                    if anchors.near(Point(sx, sy), min_spacing):
                        continue
                    for mirror in (1.0, -1.0):
                        poses = fit(group, sx, sy, heading, mirror, allowed)
                        if poses is not None:
                            found = (region, sx, sy, heading, poses)
                            break
                    if found is not None:
                        break
            cursor[group.name] = k
            if found is None:
                if counts[group.name] == 0:
                    skipped[f"{group.name}: no free spot in {', '.join(group.regions)}"] += 1
                continue
            region, sx, sy, heading, poses = found
            counts[group.name] += 1
            instance = f"{group.name}-{counts[group.name]}"
            anchors.add(Point(sx, sy))
            placed_anchors[instance] = (sx, sy, heading)
            base = len(members)
            for pose in poses:
                if pose.support is None:
                    shapes.add(pose.shape)
            for pose in poses:
                support = None if pose.support is None else base + pose.support
                zone = land.zone_at(pose.x, pose.y) if support is None else members[support].zone
                members.append(
                    GroupMember(
                        category=pose.category,
                        x=pose.x,
                        y=pose.y,
                        z=pose.z,
                        heading=pose.heading,
                        group=instance,
                        zone=zone,
                        region=region,
                        support=support,
                        size=pose.size,
                    )
                )
            keep.append(group)
        rotation = keep
    return GroupPlan(
        members=tuple(members),
        groups=dict(sorted(counts.items())),
        skipped=dict(sorted(skipped.items())),
        anchors=placed_anchors,
    )


def _near(
    city: CityMap, placed: Sequence[Placement], plan: StreetPlan, spec: RegionSpec
) -> BaseGeometry | None:
    """The area within ``spec.radius`` of what a region must be near (None: no such condition)."""
    if spec.near is None:
        return None
    if spec.near == "water":
        return plan.classes["water"].buffer(spec.radius, quad_segs=2)
    if spec.near == "bus_stop":
        points = [f.position for f in city.furniture if f.kind == "bus_stop"]
        points += [(p.x, p.y) for p in placed if p.category in BUS_STOP_CATEGORIES]
    elif spec.near == "cafe":
        points = [p.position for p in city.pois if p.category in CAFE_CATEGORIES]
    elif spec.near == "shop":
        points = [p.position for p in city.pois if p.tag.startswith("shop=")]
    elif spec.near == "school":
        points = [p.position for p in city.pois if p.category in SCHOOL_CATEGORIES]
    else:
        raise ValueError(f"unknown region condition near={spec.near!r}")
    if not points:
        return Polygon()
    return shapely.union_all(
        shapely.buffer(shapely.points(np.asarray(points, dtype=np.float64)), spec.radius)
    )


def _clip(seeds: list[Polygon], target: BaseGeometry) -> list[Polygon]:
    """The parts of ``seeds`` inside ``target``."""
    if target.is_empty or not seeds:
        return []
    tree = STRtree(seeds)
    shapely.prepare(target)
    out: list[Polygon] = []
    for i in tree.query(target, predicate="intersects"):
        seed = seeds[int(i)]
        out += _polygons(seed if target.contains(seed) else seed.intersection(target))
    return out
