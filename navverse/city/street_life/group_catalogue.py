"""The catalogue of contextual object groups: 30 small scenes of everyday street life, and the
regions they may stand in.

Each group (:data:`GROUPS`) is a few objects in a fixed layout (:class:`Member`: category, offset
and turn in the group's frame, the member it stands on) that tell a story together; each names the
regions (:data:`REGIONS`) it may stand in. The table is checked when the module loads (unique
names, known regions, supports before what they carry). Placing groups in a city is
:mod:`navverse.city.street_life.groups`; this module is data and imports nothing of the placement.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "BUS_STOP_CATEGORIES",
    "CAFE_CATEGORIES",
    "GROUPS",
    "REGIONS",
    "SCHOOL_CATEGORIES",
    "GroupSpec",
    "Member",
    "RegionSpec",
]


@dataclass(frozen=True)
class Member:
    """One object of a group's layout.

    Attributes
    ----------
    category : str
        Object category.
    x, y : float
        Position of its centre (m). On the ground: in the group's frame (front = +y, right = +x).
        Stacked (``on`` set): in the support's local frame, from the support's centre.
    turn : float
        Heading of its front relative to the group's front (or the support's front), degrees
        counter-clockwise.
    on : int or None
        Index of the member it stands on (an earlier member with a support area), or None for the
        ground.
    """

    category: str
    x: float = 0.0
    y: float = 0.0
    turn: float = 0.0
    on: int | None = None


@dataclass(frozen=True)
class GroupSpec:
    """A contextual group: its name, the regions it may stand in, and its members' layout."""

    name: str
    regions: tuple[str, ...]
    members: tuple[Member, ...]

    @property
    def categories(self) -> frozenset[str]:
        """Every category the group needs."""
        return frozenset(m.category for m in self.members)


@dataclass(frozen=True)
class RegionSpec:
    """Where a region's groups are anchored and what their members may stand on.

    Attributes
    ----------
    seeds : frozenset of str
        Land the anchors are drawn in: ``furniture``, ``frontage``, ``verge`` (sidewalk zones),
        ``ground``, ``green``, ``plaza`` (plazas and pedestrian areas), ``parking`` (lots).
    allowed : frozenset of str
        Land every member footprint must lie on (the same names).
    near : str or None
        Anchors lie within ``radius`` of these: ``bus_stop``, ``cafe``, ``shop``, ``school`` (POIs
        or furniture) or ``water``.
    radius : float
        See ``near`` (m).
    facing : {"road", "water", "random"}
        What the group's front faces.
    min_area : float
        Smallest seed area a group is anchored in (m²): sports need a field.
    """

    seeds: frozenset[str]
    allowed: frozenset[str]
    near: str | None = None
    radius: float = 0.0
    facing: str = "road"
    min_area: float = 0.0


_STREET_LAND = frozenset({"furniture", "frontage", "ground", "green", "plaza"})
_ZONES = frozenset({"furniture", "frontage", "verge"})
_FRONTS = frozenset({"frontage", "verge"})

REGIONS: dict[str, RegionSpec] = {
    "street": RegionSpec(_ZONES, _STREET_LAND),
    "bus_stop": RegionSpec(_ZONES, _STREET_LAND, near="bus_stop", radius=12.0),
    "construction": RegionSpec(_FRONTS, _STREET_LAND),
    "cafe_front": RegionSpec(_FRONTS, _STREET_LAND, near="cafe", radius=12.0),
    "shop_front": RegionSpec(_FRONTS, _STREET_LAND, near="shop", radius=12.0),
    "school": RegionSpec(_ZONES | {"ground", "green", "plaza"}, _STREET_LAND, near="school", radius=40.0),
    "park": RegionSpec(frozenset({"green"}), frozenset({"green", "ground", "plaza"}), facing="random"),
    "plaza": RegionSpec(frozenset({"plaza"}), frozenset({"plaza", "green", "ground"})),
    "sports": RegionSpec(
        frozenset({"green", "plaza"}),
        frozenset({"green", "plaza", "ground"}),
        facing="random",
        min_area=900.0,
    ),
    "parking": RegionSpec(frozenset({"parking"}), frozenset({"parking", "ground", "green"})),
    "waterside": RegionSpec(
        frozenset({"ground", "green"}),
        frozenset({"ground", "green", "plaza"}),
        near="water",
        radius=10.0,
        facing="water",
    ),
}
"""The regions groups stand in (see the module docstring)."""

CAFE_CATEGORIES = frozenset({"cafe", "restaurant", "fast_food", "bar", "pub", "ice_cream", "biergarten"})
"""POI categories whose fronts are ``cafe_front``."""
SCHOOL_CATEGORIES = frozenset({"school", "kindergarten", "childcare", "college", "university"})
"""POI categories that make a ``school`` region."""
BUS_STOP_CATEGORIES = frozenset({"bus_stop_sign", "bus_shelter"})
"""Placed objects that mark a bus stop (besides mapped ``bus_stop`` furniture)."""


def _m(category: str, x: float = 0.0, y: float = 0.0, turn: float = 0.0) -> Member:
    return Member(category, x, y, turn)


def _on(support: int, category: str, x: float = 0.0, y: float = 0.0, turn: float = 0.0) -> Member:
    return Member(category, x, y, turn, on=support)


def _g(name: str, regions: tuple[str, ...], *members: Member) -> GroupSpec:
    return GroupSpec(name, regions, tuple(members))


# Layouts are drawn at each category's largest size (size_max); a bench's seat is its front half
# (y from -0.09 to 0.39 m), a picnic table's top +-1.15 x +-0.4 m, a bistro table's +-0.26 m.
GROUPS: tuple[GroupSpec, ...] = (
    _g(
        "bus_stop_wait",
        ("bus_stop",),
        _m("park_bench"),
        _m("bus_stop_sign", -2.0, 0.2),
        _on(0, "briefcase", 0.55, 0.15),
        _on(0, "umbrella", -0.5, 0.15),
    ),
    _g(
        "park_relaxing",
        ("park",),
        _m("park_bench"),
        _on(0, "notebook", 0.4, 0.15),
        _on(0, "coffee_cup", 0.75, 0.2),
    ),
    _g(
        "feeding_cat",
        ("park", "plaza"),
        _m("park_bench"),
        _on(0, "takeaway_box", -0.5, 0.15),
        _m("cat", 0.3, 1.0, 180.0),
        _m("cat", -0.6, 1.1, 150.0),
    ),
    _g(
        "construction_repair",
        ("construction",),
        _m("construction_fence"),
        _m("traffic_cone", -2.3, 0.0),
        _m("toolbox", 2.3, 0.0),
        _m("ladder", 3.5, 0.0, 90.0),
        _on(2, "coffee_cup", 0.15, 0.0),
    ),
    _g(
        "sports_gear",
        ("sports",),
        _m("park_bench"),
        _on(0, "backpack", -0.5, 0.15),
        _on(0, "water_bottle", 0.1, 0.2),
        _m("soccer_ball", 0.8, 1.0),
    ),
    _g(
        "picnic_lunch",
        ("park",),
        _m("picnic_table"),
        _on(0, "takeaway_box", -0.5, 0.0),
        _on(0, "water_bottle", 0.2, 0.1),
        _on(0, "coffee_cup", 0.6, -0.1),
        _m("backpack", 1.6, 0.6),
    ),
    _g(
        "dog_walk",
        ("park", "street"),
        _m("park_bench"),
        _on(0, "handbag", 0.6, 0.15),
        _m("dog", -0.3, 1.0, 90.0),
        _m("waste_bin", 1.75, 0.0),
    ),
    _g(
        "cafe_terrace",
        ("cafe_front",),
        _m("bistro_table"),
        _m("bistro_chair", -0.75, 0.0, -90.0),
        _m("bistro_chair", 0.75, 0.0, 90.0),
        _on(0, "coffee_cup", -0.19, 0.18),
        _on(0, "newspaper", 0.05, -0.05),
    ),
    _g(
        "delivery_drop",
        ("shop_front", "cafe_front"),
        _m("cargo_pallet"),
        _on(0, "shopping_bag"),
        _m("shopping_bag", -1.1, 0.0),
        _m("motor_scooter", 1.7, 0.0, 90.0),
    ),
    _g(
        "moving_day",
        ("street", "parking"),
        _m("armchair"),
        _m("cargo_pallet", 1.25, 0.0),
        _on(1, "lamp"),
        _m("suitcase", 2.35, 0.0),
        _m("floor_lamp", -0.85, 0.0),
    ),
    _g(
        "street_cleaning",
        ("street", "plaza"),
        _m("wheelbarrow", 0.0, 0.0, 90.0),
        _m("waste_bin", 1.3, 0.0),
        _m("traffic_cone", -1.35, 0.0),
    ),
    _g(
        "bike_parking",
        ("street", "plaza"),
        _m("bicycle", -1.0, 0.0, 90.0),
        _m("bicycle", 1.0, 0.0, 90.0),
        _m("kick_scooter", 2.6, 0.0, 90.0),
    ),
    _g(
        "school_pickup",
        ("school",),
        _m("park_bench"),
        _on(0, "backpack", -0.6, 0.15),
        _on(0, "book_stack", 0.2, 0.15),
        _m("kick_scooter", 1.9, 0.3, 90.0),
        _m("stroller", -1.8, 0.1),
    ),
    _g(
        "newspaper_stand",
        ("street", "bus_stop", "plaza"),
        _m("newspaper_box", -0.35, 0.0),
        _m("newspaper_box", 0.35, 0.0),
        _m("waste_bin", 1.15, 0.0),
    ),
    _g(
        "market_stall",
        ("plaza", "parking"),
        _m("picnic_table"),
        _on(0, "takeaway_box", -0.6, 0.0),
        _on(0, "takeaway_box", -0.25, 0.05),
        _on(0, "shopping_bag", 0.5, 0.0),
        _m("patio_umbrella", 1.75, 0.0),
        _m("shopping_bag", 0.0, 1.3),
    ),
    _g(
        "roadworks_barrier",
        ("construction",),
        _m("traffic_barrier", -1.1, 0.0),
        _m("traffic_barrier", 1.1, 0.0),
        _m("traffic_cone", -2.75, 0.0),
        _m("traffic_cone", 2.75, 0.0),
    ),
    _g(
        "lost_luggage",
        ("bus_stop", "plaza", "street"),
        _m("suitcase"),
        _m("backpack", 0.55, 0.05),
        _m("handbag", -0.55, 0.0),
        _m("umbrella", 0.0, 0.45),
    ),
    _g(
        "shopping_break",
        ("shop_front", "plaza"),
        _m("park_bench"),
        _on(0, "handbag", -0.6, 0.15),
        _on(0, "coffee_cup", 0.1, 0.25),
        _m("shopping_bag", 1.5, 0.1),
        _m("shopping_bag", -1.5, 0.1),
    ),
    _g(
        "soccer_practice",
        ("sports",),
        _m("traffic_cone", -3.0, 2.0),
        _m("traffic_cone", -1.0, 2.0),
        _m("traffic_cone", 1.0, 2.0),
        _m("traffic_cone", 3.0, 2.0),
        _m("soccer_ball", 0.0, 0.5),
        _m("soccer_ball", 2.0, 3.5),
        _m("backpack", -3.5, -1.0),
        _m("water_bottle", -3.0, -1.0),
    ),
    _g(
        "basketball_court",
        ("sports",),
        _m("basketball_hoop"),
        _m("park_bench", 3.0, -0.5, 90.0),
        _on(1, "backpack", -0.5, 0.15),
        _on(1, "water_bottle", 0.3, 0.2),
    ),
    _g(
        "pram_stop",
        ("park", "street"),
        _m("park_bench"),
        _m("stroller", 1.85, 0.3),
        _on(0, "handbag", -0.4, 0.15),
        _on(0, "water_bottle", 0.6, 0.2),
    ),
    _g(
        "recycling_point",
        ("street", "parking"),
        _m("recycling_bin", -0.85, 0.0),
        _m("recycling_bin", 0.85, 0.0),
        _m("waste_bin", 2.1, 0.0),
        _m("shopping_bag", -2.0, 0.05),
    ),
    _g(
        "skate_spot",
        ("plaza", "sports"),
        _m("skateboard", 0.0, 0.0, 30.0),
        _m("skateboard", 1.2, 0.5, -60.0),
        _m("kick_scooter", -1.2, 0.3, 90.0),
        _m("backpack", -0.5, -1.0),
        _m("water_bottle", -0.1, -1.0),
    ),
    _g(
        "park_gardening",
        ("park",),
        _m("flower_bed"),
        _m("wheelbarrow", 0.0, 1.4, 90.0),
        _m("toolbox", 1.5, 1.3),
    ),
    _g(
        "outdoor_work",
        ("park", "plaza"),
        _m("picnic_table"),
        _on(0, "laptop", -0.4, 0.0),
        _on(0, "coffee_cup", 0.05, 0.15),
        _on(0, "notebook", 0.45, 0.0),
        _m("backpack", 1.6, 0.5),
    ),
    _g(
        "flood_defence",
        ("waterside", "construction"),
        _m("sandbag_stack", -1.15, 0.0),
        _m("sandbag_stack", 1.15, 0.0),
        _m("wheelbarrow", 3.2, 0.0, 90.0),
    ),
    _g(
        "renovation_skip",
        ("construction", "parking"),
        _m("dumpster"),
        _m("cargo_pallet", 1.8, -0.2),
        _on(1, "toolbox"),
        _m("armchair", -1.7, 0.1),
    ),
    _g(
        "street_food",
        ("cafe_front", "plaza"),
        _m("bistro_table"),
        _on(0, "takeaway_box", -0.1, 0.05),
        _on(0, "water_bottle", 0.15, -0.1),
        _m("bistro_chair", 0.75, 0.0, 90.0),
        _m("waste_bin", -1.0, 0.0),
    ),
    _g(
        "shopfront_repair",
        ("shop_front",),
        _m("ladder", 0.0, 0.0, 90.0),
        _m("toolbox", 1.1, 0.0),
        _m("traffic_cone", -1.2, 0.0),
        _m("a_frame_sign", 2.1, 0.0),
    ),
    _g(
        "homework_break",
        ("school", "park"),
        _m("park_bench"),
        _on(0, "book_stack", -0.55, 0.15),
        _on(0, "laptop", 0.1, 0.15),
        _on(0, "water_bottle", 0.7, 0.2),
        _m("backpack", 1.6, 0.0),
    ),
)
"""The 30 contextual groups, in table order (see :class:`Member` for the layout frame)."""


def _check_table() -> None:
    names = [g.name for g in GROUPS]
    if len(set(names)) != len(names):
        raise ValueError("GROUPS: group names repeat")
    for group in GROUPS:
        if not group.regions or not set(group.regions) <= set(REGIONS):
            raise ValueError(f"GROUPS: {group.name} names unknown regions {group.regions}")
        for k, member in enumerate(group.members):
            if member.on is not None and not (0 <= member.on < k and group.members[member.on].on is None):
                raise ValueError(f"GROUPS: {group.name} member {k} stands on {member.on}, not an earlier one")


_check_table()
