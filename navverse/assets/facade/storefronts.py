"""Procedural storefronts: the ground-floor shop front set into a building facade.

A storefront is a shallow facade panel with a door and display windows (glass a separate, slightly
recessed part; frames, mullions and a dark shop interior behind), window contents that fit the place
(shelves of goods, tables and chairs, counters, clothes rails, flowers, a salon chair, blinds), an
optional awning (flat canopy or sloped, plain or striped) and a sign board above the openings whose
front face is textured with an image of the shop name and a category icon
(:mod:`navverse.assets.facade.storefront_signs`).

Place categories
----------------
The categories are among the most frequent ``amenity=*`` and ``shop=*`` values of OpenStreetMap
(taginfo); :func:`place_category` maps tags to them, checking ``amenity``, then ``shop``, ``craft``
and ``office`` (the order of the OSM reader's places). A value joins a category when a person asking
for that category would take the place for one (a greengrocer is a grocery, a watchmaker a jeweller,
a tailor a clothes shop); values of other trades keep the generic ``shop`` or none:

============  ===================================================================================
category      OSM tags
============  ===================================================================================
restaurant    amenity=restaurant
cafe          amenity=cafe
fast_food     amenity=fast_food|food_court
bar           amenity=bar|pub|biergarten|nightclub
bank          amenity=bank|bureau_de_change|money_transfer|payment_centre
pharmacy      amenity=pharmacy; shop=chemist|drugstore
supermarket   shop=supermarket|wholesale
convenience   shop=convenience|kiosk|newsagent|grocery|general|food|greengrocer|deli|health_food|
              frozen_food|dairy|tobacco
bakery        shop=bakery|pastry|confectionery|chocolate; craft=bakery|confectionery|pastry
clothes       shop=clothes|shoes|boutique|fashion|fashion_accessories|bag|leather|tailor;
              craft=tailor|dressmaker|shoemaker
hairdresser   shop=hairdresser|beauty|barber
books         shop=books|stationery
florist       shop=florist|garden_centre
hardware      shop=hardware|doityourself|paint|trade|tools|electrical|locksmith;
              craft=locksmith|key_cutter
electronics   shop=electronics|mobile_phone|computer|hifi|telecommunication|appliance|camera|
              video_games|radiotechnics; craft=electronics_repair
post_office   amenity=post_office
clinic        amenity=doctors|dentist|clinic; office=physician
ice_cream     amenity=ice_cream; shop=ice_cream|frozen_yogurt
butcher       shop=butcher; craft=butcher
optician      shop=optician; craft=optician
jewelry       shop=jewelry|jewellery|watches; craft=jeweller|goldsmith|watchmaker
shop          any other ``shop`` value except ``no`` and ``vacant`` (the fallback)
============  ===================================================================================

Tags with none of these give ``None`` (schools, cinemas, offices of companies, other crafts).

Frame
-----
The frame of :mod:`navverse.assets.library` applies: x = width, y = depth, z = up, meters, the front
(street side) faces **+y** and the mesh is centred on its bounding box. The back plane of the facade
panel, at ``y = -depth / 2``, is the plane set flush into a building facade; awning and sign stand out
towards +y. Seen from the street (from +y), +x points to the viewer's *left*, so the sign texture runs
``u = 0`` at the board's largest x.

Designs
-------
Each category has :data:`DESIGNS_PER_CATEGORY` designs, combining a layout variant (door position,
window layout, sill height, awning style, sign style and icons) with one of three colour schemes of the
category and a facade material; :func:`storefront` builds design ``design`` or draws one. Building is
deterministic: the same generator state and arguments give byte-identical vertices, faces, colours and
sign images.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from navverse.assets.errors import AssetSizeError, UnknownCategoryError
from navverse.assets.facade import storefront_signs
from navverse.assets.materials import RGB, shade
from navverse.assets.parts import Assembly, Solid, bar, box, cylinder, ellipsoid, hull
from navverse.assets.primitives import boxes
from navverse.scene.geometry import MeshData, Texture

__all__ = [
    "DESIGNS_PER_CATEGORY",
    "MIN_HEIGHT",
    "MIN_WIDTH",
    "PLACE_CATEGORIES",
    "Storefront",
    "design_count",
    "place_category",
    "storefront",
]

PLACE_CATEGORIES: tuple[str, ...] = (
    "restaurant",
    "cafe",
    "fast_food",
    "bar",
    "bank",
    "pharmacy",
    "supermarket",
    "convenience",
    "bakery",
    "clothes",
    "hairdresser",
    "books",
    "florist",
    "hardware",
    "electronics",
    "post_office",
    "clinic",
    "ice_cream",
    "butcher",
    "optician",
    "jewelry",
    "shop",
)
"""Place categories a storefront can be built for (``shop`` is the generic fallback)."""

_AMENITY: dict[str, str] = {
    "restaurant": "restaurant",
    "cafe": "cafe",
    "fast_food": "fast_food",
    "food_court": "fast_food",
    "bar": "bar",
    "pub": "bar",
    "biergarten": "bar",
    "nightclub": "bar",
    "bank": "bank",
    "bureau_de_change": "bank",
    "money_transfer": "bank",
    "payment_centre": "bank",
    "pharmacy": "pharmacy",
    "post_office": "post_office",
    "doctors": "clinic",
    "dentist": "clinic",
    "clinic": "clinic",
    "ice_cream": "ice_cream",
}
_SHOP_VALUES: dict[str, tuple[str, ...]] = {
    "pharmacy": ("chemist", "drugstore"),
    "supermarket": ("supermarket", "wholesale"),
    "convenience": (
        "convenience", "kiosk", "newsagent", "grocery", "general", "food", "greengrocer", "deli",
        "health_food", "frozen_food", "dairy", "tobacco",
    ),
    "bakery": ("bakery", "pastry", "confectionery", "chocolate"),
    "clothes": (
        "clothes", "shoes", "boutique", "fashion", "fashion_accessories", "bag", "leather", "tailor",
    ),
    "hairdresser": ("hairdresser", "beauty", "barber"),
    "books": ("books", "stationery"),
    "florist": ("florist", "garden_centre"),
    "hardware": ("hardware", "doityourself", "paint", "trade", "tools", "electrical", "locksmith"),
    "electronics": (
        "electronics", "mobile_phone", "computer", "hifi", "telecommunication", "appliance", "camera",
        "video_games", "radiotechnics",
    ),
    "ice_cream": ("ice_cream", "frozen_yogurt"),
    "butcher": ("butcher",),
    "optician": ("optician",),
    "jewelry": ("jewelry", "jewellery", "watches"),
}  # fmt: skip
"""``shop=*`` values of each category (any other shop value is the generic ``shop``)."""
_CRAFT_VALUES: dict[str, tuple[str, ...]] = {
    "bakery": ("bakery", "confectionery", "pastry"),
    "clothes": ("tailor", "dressmaker", "shoemaker"),
    "hardware": ("locksmith", "key_cutter"),
    "electronics": ("electronics_repair",),
    "butcher": ("butcher",),
    "optician": ("optician",),
    "jewelry": ("jeweller", "goldsmith", "watchmaker"),
}
"""``craft=*`` values of each category: the crafts that keep a shop front (others have none)."""
_OFFICE_VALUES: dict[str, tuple[str, ...]] = {"clinic": ("physician",)}
"""``office=*`` values of each category: offices a pedestrian walks into as into a shop."""


def _by_value(values: Mapping[str, tuple[str, ...]]) -> dict[str, str]:
    """Invert ``{category: values}`` into ``{value: category}`` (each value is listed once)."""
    return {value: category for category, listed in values.items() for value in listed}


_SHOP = _by_value(_SHOP_VALUES)
_CRAFT = _by_value(_CRAFT_VALUES)
_OFFICE = _by_value(_OFFICE_VALUES)
_NOT_A_SHOP = frozenset({"no", "vacant", ""})

DESIGNS_PER_CATEGORY = 6
"""Designs of every category, addressed as ``design = 0 .. DESIGNS_PER_CATEGORY - 1``."""

MIN_WIDTH = 3.0
"""Narrowest storefront (m): a door and one window between piers."""
MIN_HEIGHT = 2.9
"""Lowest storefront (m): openings of 2.3 m, an awning above head height and a sign band."""

_FACADE_DEPTH = 0.4
_SIGN_DEPTH = 0.08
_FRAME = 0.06
_DOOR_WIDTH = 1.05
_END_PIER = 0.3
_MID_PIER = 0.25
_HEADROOM = 2.1

_WHITE: RGB = (240, 240, 236)
_DARK: RGB = (30, 30, 32)
_INTERIOR: RGB = (58, 52, 48)
_GLASS: RGB = (150, 184, 196)
_HANDLE: RGB = (190, 192, 196)
_WOOD: tuple[RGB, ...] = ((176, 132, 84), (110, 74, 48), (222, 196, 156))
"""Shop fittings: oak, walnut, birch."""
_FACADES: tuple[RGB, ...] = (
    (226, 218, 204),
    (150, 72, 56),
    (188, 184, 176),
    (64, 68, 74),
    (240, 240, 236),
    (122, 100, 78),
)
"""Facade panels: cream render, brick red, stone grey, anthracite, white, timber brown."""
_FRAMES: tuple[RGB, ...] = ((36, 36, 40), (232, 232, 228), (176, 180, 184), (92, 62, 42))
"""Window and door frames: black, white, aluminium, wood."""
_ACCENTS: dict[str, tuple[RGB, RGB]] = {
    "restaurant": ((150, 30, 40), (232, 204, 130)),
    "cafe": ((92, 58, 38), (238, 224, 196)),
    "fast_food": ((210, 40, 30), (250, 204, 30)),
    "bar": ((30, 62, 50), (216, 172, 84)),
    "bank": ((22, 60, 130), (232, 234, 238)),
    "pharmacy": ((20, 150, 72), (246, 246, 246)),
    "supermarket": ((228, 94, 24), (250, 244, 230)),
    "convenience": ((30, 110, 190), (250, 212, 40)),
    "bakery": ((168, 110, 52), (250, 240, 220)),
    "clothes": ((32, 32, 36), (240, 240, 240)),
    "hairdresser": ((190, 40, 110), (246, 232, 242)),
    "books": ((110, 30, 42), (240, 230, 200)),
    "florist": ((60, 130, 62), (250, 202, 212)),
    "hardware": ((222, 122, 22), (40, 40, 44)),
    "electronics": ((20, 120, 200), (236, 242, 246)),
    "post_office": ((250, 202, 0), (22, 42, 120)),
    "clinic": ((30, 120, 170), (246, 248, 250)),
    "ice_cream": ((236, 124, 168), (150, 218, 222)),
    "butcher": ((162, 22, 32), (246, 244, 240)),
    "optician": ((44, 48, 64), (204, 214, 224)),
    "jewelry": ((22, 22, 26), (214, 178, 60)),
    "shop": ((70, 92, 124), (240, 236, 226)),
}
"""``(brand, contrast)`` colours of each category's sign and awning."""
_GOODS: tuple[RGB, ...] = (
    (200, 60, 50),
    (40, 110, 190),
    (240, 180, 40),
    (60, 150, 90),
    (236, 236, 230),
    (120, 70, 160),
    (230, 120, 40),
    (30, 150, 160),
)
_CONTENTS: dict[str, str] = {
    "restaurant": "tables",
    "cafe": "tables",
    "fast_food": "tables",
    "bar": "tables",
    "bank": "counter",
    "pharmacy": "shelves",
    "supermarket": "shelves",
    "convenience": "shelves",
    "bakery": "counter",
    "clothes": "rails",
    "hairdresser": "salon",
    "books": "shelves",
    "florist": "plants",
    "hardware": "shelves",
    "electronics": "shelves",
    "post_office": "counter",
    "clinic": "blinds",
    "ice_cream": "counter",
    "butcher": "counter",
    "optician": "shelves",
    "jewelry": "counter",
    "shop": "shelves",
}
"""What is seen through the display windows of each category."""

_ADJECTIVES = (
    "Golden", "Blue", "Green", "Corner", "Old Town", "Sunny", "Royal", "Little",
    "Central", "Harbor", "Maple", "Oak", "Silver", "Red", "Happy", "Urban",
)  # fmt: skip
_SURNAMES = (
    "Rossi", "Miller", "Novak", "Garcia", "Khan", "Nguyen", "Schmidt", "Dubois",
    "Kowalski", "Silva", "Tanaka", "Olsen", "Murphy", "Costa", "Weber", "Park",
)  # fmt: skip
_NOUNS: dict[str, tuple[str, ...]] = {
    "restaurant": ("Kitchen", "Trattoria", "Bistro", "Grill", "Brasserie"),
    "cafe": ("Coffee", "Cafe", "Espresso", "Roasters", "Coffee House"),
    "fast_food": ("Burger", "Kebab", "Pizza", "Fried Chicken", "Noodle Bar"),
    "bar": ("Pub", "Tavern", "Bar", "Taproom", "Wine Bar"),
    "bank": ("Bank", "Savings Bank", "Credit Union", "Exchange"),
    "pharmacy": ("Pharmacy", "Apotheke", "Chemist", "Drugstore"),
    "supermarket": ("Market", "Supermarket", "Foods", "Fresh Market"),
    "convenience": ("Mini Market", "Corner Shop", "Grocery", "Kiosk"),
    "bakery": ("Bakery", "Bread", "Patisserie", "Bakehouse"),
    "clothes": ("Fashion", "Boutique", "Outfitters", "Shoes", "Apparel"),
    "hairdresser": ("Hair", "Salon", "Barber", "Hair Studio", "Beauty"),
    "books": ("Books", "Bookshop", "Stationery", "Paper & Pen"),
    "florist": ("Flowers", "Florist", "Blooms", "Garden"),
    "hardware": ("Hardware", "Tools", "DIY", "Home & Garden"),
    "electronics": ("Electronics", "Mobile", "Computers", "Phone Repair"),
    "post_office": ("Post Office", "Post", "Parcel Shop"),
    "clinic": ("Medical Centre", "Dental", "Clinic", "Family Practice"),
    "ice_cream": ("Gelato", "Ice Cream", "Gelateria", "Frozen Yogurt"),
    "butcher": ("Butcher", "Meats", "Fine Meats", "Butchery"),
    "optician": ("Optician", "Eyewear", "Optics", "Vision"),
    "jewelry": ("Jewellers", "Jewelry", "Gold & Silver", "Watches"),
    "shop": ("Store", "Shop", "Goods", "Emporium", "Trading"),
}


@dataclass(frozen=True)
class _Variant:
    """The layout half of a design."""

    door: float  # door centre as a fraction of the width along x
    windows: str  # "single", "mullion" or "transom"
    sill: float  # window sill height, m
    awning: str  # "none", "flat", "sloped" or "striped"
    sign: str  # "board" (nearly full width), "panel" (centred on the door) or "framed"
    icons: int  # icons on the sign: 1 or 2
    upper: bool  # sign text in capitals
    frame: int  # index into _FRAMES


_VARIANTS: tuple[_Variant, ...] = (
    _Variant(0.5, "single", 0.45, "striped", "board", 1, False, 0),
    _Variant(0.2, "mullion", 0.15, "sloped", "panel", 1, True, 1),
    _Variant(0.8, "transom", 0.6, "none", "framed", 2, False, 2),
    _Variant(0.5, "mullion", 0.6, "flat", "framed", 1, True, 3),
    _Variant(0.2, "single", 0.3, "striped", "board", 2, True, 1),
    _Variant(0.8, "transom", 0.15, "flat", "panel", 1, False, 0),
)


@dataclass(frozen=True, eq=False)
class Storefront:
    """A built storefront.

    Parameters
    ----------
    mesh : MeshData
        Closed coloured parts in the local frame (front +y, centred on the bounding box); the sign
        board's front face is textured with ``mesh.textures[0]``.
    category : str
        One of :data:`PLACE_CATEGORIES`.
    name : str
        The name on the sign.
    design : int
        Design id within the category, ``0 .. DESIGNS_PER_CATEGORY - 1``.
    size : tuple of float
        ``(width, depth, height)`` in m, the extents of the mesh.
    entrance : tuple of float
        The door centre on the front plane of the facade panel, at floor level (local frame).
    sign_center : tuple of float
        Centre of the sign board's front face (local frame).
    sign_size : tuple of float
        ``(width along x, height along z)`` of that face, m.
    glass_faces : ndarray of bool, shape (M,)
        Which faces of ``mesh`` are glass (for renderers that make glass see-through).
    """

    mesh: MeshData
    category: str
    name: str
    design: int
    size: tuple[float, float, float]
    entrance: tuple[float, float, float]
    sign_center: tuple[float, float, float]
    sign_size: tuple[float, float]
    glass_faces: np.ndarray = field(repr=False)

    @property
    def sign_image(self) -> np.ndarray:
        """The sign texture image, ``uint8 (H, W, 3)``, row 0 at the top."""
        return self.mesh.textures[0].image


def design_count() -> int:
    """Number of distinct designs over all categories."""
    return len(PLACE_CATEGORIES) * DESIGNS_PER_CATEGORY


def place_category(tags: Mapping[str, str]) -> str | None:
    """Map OpenStreetMap tags to a place category (see the module table).

    Parameters
    ----------
    tags : mapping of str to str
        Tags of one OSM element.

    Returns
    -------
    str or None
        The category of a listed ``amenity`` value, else of a listed ``shop`` value, ``"shop"`` for
        any other shop value except ``no`` / ``vacant``, else the category of a listed ``craft``,
        then ``office`` value, and ``None`` otherwise.
    """
    amenity = _value(tags, "amenity")
    if amenity in _AMENITY:
        return _AMENITY[amenity]
    shop = _value(tags, "shop")
    if shop in _SHOP:
        return _SHOP[shop]
    if shop not in _NOT_A_SHOP:
        return "shop"
    craft = _value(tags, "craft")
    if craft in _CRAFT:
        return _CRAFT[craft]
    return _OFFICE.get(_value(tags, "office"))


def _value(tags: Mapping[str, str], key: str) -> str:
    """A tag's value stripped and lower-case; ``""`` when not tagged."""
    return tags.get(key, "").strip().lower()


def generated_name(category: str, rng: np.random.Generator) -> str:
    """A plausible shop name for `category` (three draws from `rng`)."""
    noun = _NOUNS[category][int(rng.integers(len(_NOUNS[category])))]
    pattern = int(rng.integers(3))
    if pattern == 0:
        return f"{_ADJECTIVES[int(rng.integers(len(_ADJECTIVES)))]} {noun}"
    surname = _SURNAMES[int(rng.integers(len(_SURNAMES)))]
    return f"{surname}'s {noun}" if pattern == 1 else f"{noun} {surname}"


# ---------------------------------------------------------------------------------------------------
# layout


@dataclass(frozen=True)
class _Layout:
    """Openings and bands of one storefront in the floor frame (x 0..W, back plane y = 0, z up)."""

    width: float
    height: float
    top: float  # top of door and windows
    door: tuple[float, float]  # x range of the door opening
    windows: tuple[tuple[float, float], ...]  # x ranges of the window openings
    sill: float


def _layout(width: float, height: float, variant: _Variant) -> _Layout:
    """Place the door and windows along the width."""
    top = float(np.clip(height - 1.1, 2.3, 2.8))
    half = 0.5 * _DOOR_WIDTH
    centre = float(np.clip(variant.door * width, _END_PIER + half, width - _END_PIER - half))
    door = (centre - half, centre + half)
    spans = ((_END_PIER, door[0] - _MID_PIER), (door[1] + _MID_PIER, width - _END_PIER))
    windows = tuple((a, b) for a, b in spans if b - a >= 0.6)
    return _Layout(width, height, top, door, windows, variant.sill)


def _wall(asm: Assembly, lay: _Layout, color: RGB) -> None:
    """The facade panel around the openings: piers, sills and the band above."""
    openings = sorted([lay.door, *lay.windows])
    edges = [0.0] + [x for span in openings for x in span] + [lay.width]
    for x0, x1 in zip(edges[::2], edges[1::2], strict=True):
        if x1 - x0 > 1e-6:
            asm.box((x0, 0.0, 0.0), (x1, _FACADE_DEPTH, lay.top), color)
    for x0, x1 in lay.windows:
        asm.box((x0, 0.0, 0.0), (x1, _FACADE_DEPTH, lay.sill), color)
    asm.box((0.0, 0.0, lay.top), (lay.width, _FACADE_DEPTH, lay.height), color)


def _frame(
    asm: Assembly, x0: float, x1: float, z0: float, z1: float, color: RGB, *, sill: bool = True
) -> None:
    """A frame of bars lining an opening, set back from the front plane."""
    y0, y1 = _FACADE_DEPTH - 0.08, _FACADE_DEPTH - 0.01
    asm.box((x0, y0, z0), (x0 + _FRAME, y1, z1), color)
    asm.box((x1 - _FRAME, y0, z0), (x1, y1, z1), color)
    asm.box((x0 + _FRAME, y0, z1 - _FRAME), (x1 - _FRAME, y1, z1), color)
    if sill:
        asm.box((x0 + _FRAME, y0, z0), (x1 - _FRAME, y1, z0 + _FRAME), color)


def _pane(glass: Assembly, x0: float, x1: float, z0: float, z1: float) -> None:
    """A glass pane filling a frame's inside, recessed between the frame's front and back."""
    glass.box((x0, _FACADE_DEPTH - 0.06, z0), (x1, _FACADE_DEPTH - 0.045, z1), _GLASS)


def _window(
    asm: Assembly, glass: Assembly, x0: float, x1: float, lay: _Layout, kind: str, frame: RGB
) -> None:
    """One display window: interior backing, frame, mullions or transom, and glass."""
    z0, z1 = lay.sill, lay.top
    asm.box((x0, 0.0, z0), (x1, 0.03, z1), _INTERIOR)
    _frame(asm, x0, x1, z0, z1, frame)
    xi0, xi1, zi0, zi1 = x0 + _FRAME, x1 - _FRAME, z0 + _FRAME, z1 - _FRAME
    y0, y1 = _FACADE_DEPTH - 0.08, _FACADE_DEPTH - 0.01
    cuts_x: list[float] = []
    if kind == "mullion":
        panes = max(2, round((xi1 - xi0) / 0.9))
        cuts_x = list(np.linspace(xi0, xi1, panes + 1)[1:-1])
    for x in cuts_x:
        asm.box((x - 0.025, y0, zi0), (x + 0.025, y1, zi1), frame)
    bounds = [xi0, *[c for x in cuts_x for c in (x - 0.025, x + 0.025)], xi1]
    z_split = zi1 - 0.4 if kind == "transom" and zi1 - zi0 > 1.0 else None
    if z_split is not None:
        asm.box((xi0, y0, z_split - 0.03), (xi1, y1, z_split + 0.03), frame)
    for a, b in zip(bounds[::2], bounds[1::2], strict=True):
        if z_split is None:
            _pane(glass, a, b, zi0, zi1)
        else:
            _pane(glass, a, b, zi0, z_split - 0.03)
            _pane(glass, a, b, z_split + 0.03, zi1)


def _door(asm: Assembly, glass: Assembly, lay: _Layout, frame: RGB, *, handle_right: bool) -> None:
    """The door: frame, an optional fanlight, and a glazed leaf with a kick plate and a bar handle."""
    x0, x1 = lay.door
    asm.box((x0, 0.0, 0.0), (x1, 0.03, lay.top), _INTERIOR)
    _frame(asm, x0, x1, 0.0, lay.top, frame, sill=False)
    leaf_top = min(lay.top - _FRAME, 2.2)
    xi0, xi1 = x0 + _FRAME, x1 - _FRAME
    if lay.top - _FRAME - leaf_top > 0.15:
        asm.box((xi0, _FACADE_DEPTH - 0.08, leaf_top), (xi1, _FACADE_DEPTH - 0.01, leaf_top + 0.05), frame)
        _pane(glass, xi0, xi1, leaf_top + 0.05, lay.top - _FRAME)
    y0, y1 = _FACADE_DEPTH - 0.1, _FACADE_DEPTH - 0.06
    stile = 0.09
    asm.box((xi0, y0, 0.0), (xi0 + stile, y1, leaf_top), frame)
    asm.box((xi1 - stile, y0, 0.0), (xi1, y1, leaf_top), frame)
    asm.box((xi0 + stile, y0, 0.0), (xi1 - stile, y1, 0.25), frame)
    asm.box((xi0 + stile, y0, leaf_top - stile), (xi1 - stile, y1, leaf_top), frame)
    glass.box((xi0 + stile, y0 + 0.01, 0.25), (xi1 - stile, y1 - 0.01, leaf_top - stile), _GLASS)
    hx = xi1 - 0.05 if handle_right else xi0 + 0.05
    asm.box((hx - 0.015, y1, 0.75), (hx + 0.015, y1 + 0.04, 1.35), _HANDLE)


# ---------------------------------------------------------------------------------------------------
# window contents: modelled standing on the shop floor (z = 0) and cut off at the window sill


@dataclass(frozen=True)
class _Bay:
    """The visible inside of a window: x range, free depth behind the glass, sill and top heights."""

    x0: float
    x1: float
    y0: float
    y1: float
    z0: float
    z1: float

    def add(self, asm: Assembly, lo: Sequence[float], hi: Sequence[float], color: RGB) -> None:
        """Add a box, cut at the sill and at the top; nothing if nothing is left."""
        lo_z, hi_z = max(lo[2], self.z0), min(hi[2], self.z1)
        if hi_z - lo_z > 1e-3:
            asm.box((lo[0], lo[1], lo_z), (hi[0], hi[1], hi_z), color)


def _goods(asm: Assembly, rng: np.random.Generator, bay: _Bay, z: float, max_height: float) -> None:
    """A row of goods boxes of random widths, heights and colours standing on height `z`."""
    widths = rng.uniform(0.08, 0.22, size=int((bay.x1 - bay.x0) / 0.08) + 1)
    gaps = rng.uniform(0.01, 0.05, size=widths.size)
    starts = bay.x0 + 0.06 + np.concatenate([[0.0], np.cumsum(widths + gaps)[:-1]])
    keep = starts + widths < bay.x1 - 0.06
    if not keep.any():
        return
    starts, widths = starts[keep], widths[keep]
    heights = rng.uniform(0.4, 1.0, size=starts.size) * max_height
    depth = rng.uniform(0.5, 1.0, size=starts.size) * (bay.y1 - bay.y0 - 0.02)
    colors = rng.integers(len(_GOODS), size=starts.size)
    lo = np.stack([starts, np.full(starts.size, bay.y0 + 0.02), np.full(starts.size, z)], axis=1)
    hi = np.stack([starts + widths, bay.y0 + 0.02 + depth, z + heights], axis=1)
    hi[:, 2] = np.minimum(hi[:, 2], bay.z1 - 0.01)
    ok = hi[:, 2] - lo[:, 2] > 0.02
    for c in np.unique(colors[ok]):
        pick = ok & (colors == c)
        asm.add(boxes(lo[pick], hi[pick]), _GOODS[int(c)])


def _shelves(asm: Assembly, rng: np.random.Generator, bay: _Bay, wood: RGB) -> None:
    """A shelving unit at the back of the window, filled with goods."""
    y1 = bay.y0 + 0.2
    z_top = min(bay.z1 - 0.05, 2.1)
    for x in (bay.x0 + 0.02, bay.x1 - 0.05):
        bay.add(asm, (x, bay.y0, 0.0), (x + 0.03, y1, z_top), wood)
    for z in np.arange(0.1, z_top - 0.25, 0.42):
        if z + 0.02 > bay.z0:
            bay.add(asm, (bay.x0 + 0.05, bay.y0, z), (bay.x1 - 0.05, y1, z + 0.025), wood)
            _goods(asm, rng, bay, z + 0.025, 0.32)


def _tables(asm: Assembly, rng: np.random.Generator, bay: _Bay, wood: RGB) -> None:
    """Small tables with a chair either side, one set per 0.9 m of window."""
    count = max(1, int((bay.x1 - bay.x0) / 0.9))
    chair = _GOODS[int(rng.integers(len(_GOODS)))]
    y0, y1 = bay.y0 + 0.02, bay.y1 - 0.02
    for cx in bay.x0 + (np.arange(count) + 0.5) * (bay.x1 - bay.x0) / count:
        bay.add(asm, (cx - 0.25, y0, 0.72), (cx + 0.25, y1, 0.76), wood)
        bay.add(asm, (cx - 0.03, y0 + 0.05, 0.0), (cx + 0.03, y1 - 0.05, 0.72), _DARK)
        for side in (-1.0, 1.0):
            sx = cx + side * 0.36
            bay.add(asm, (sx - 0.1, y0, 0.44), (sx + 0.1, y1, 0.48), chair)
            bay.add(asm, (sx - 0.02, y0 + 0.05, 0.0), (sx + 0.02, y1 - 0.05, 0.44), _DARK)
            back = sx + side * 0.08
            bay.add(asm, (back - 0.02, y0, 0.48), (back + 0.02, y1, 0.9), chair)
        if bay.z0 < 0.76:
            colour = _GOODS[int(rng.integers(len(_GOODS)))]
            asm.add(cylinder((cx, 0.5 * (y0 + y1), 0.76), (cx, 0.5 * (y0 + y1), 0.9), 0.04), colour)


def _counter(asm: Assembly, rng: np.random.Generator, bay: _Bay, wood: RGB) -> None:
    """A counter with goods on top and a wall shelf of goods behind it."""
    x0, x1 = bay.x0 + 0.05, bay.x1 - 0.05
    bay.add(asm, (x0, bay.y0 + 0.08, 0.0), (x1, bay.y1 - 0.02, 0.95), wood)
    bay.add(asm, (x0 - 0.02, bay.y0 + 0.06, 0.95), (x1 + 0.02, bay.y1, 0.99), _WHITE)
    if bay.z0 < 0.99 < bay.z1 - 0.3:
        _goods(asm, rng, _Bay(x0, x1, bay.y0 + 0.06, bay.y1, bay.z0, bay.z1), 0.99, 0.2)
    shelf_z = 1.55
    if shelf_z + 0.4 < bay.z1:
        bay.add(asm, (x0, bay.y0, shelf_z), (x1, bay.y0 + 0.08, shelf_z + 0.03), wood)
        _goods(asm, rng, _Bay(x0, x1, bay.y0 - 0.02, bay.y0 + 0.08, bay.z0, bay.z1), shelf_z + 0.03, 0.25)


def _rails(asm: Assembly, rng: np.random.Generator, bay: _Bay, wood: RGB) -> None:
    """A clothes rail with hanging garments, and a mannequin when the window is wide enough."""
    yc = 0.5 * (bay.y0 + bay.y1)
    rail_z = min(1.6, bay.z1 - 0.1)
    bay.add(asm, (bay.x0 + 0.05, yc - 0.015, rail_z - 0.03), (bay.x1 - 0.05, yc + 0.015, rail_z), _HANDLE)
    garment_end = bay.x1 - 0.05 - (0.5 if bay.x1 - bay.x0 > 1.2 else 0.0)
    for x in np.arange(bay.x0 + 0.1, garment_end - 0.08, 0.11):
        colour = _GOODS[int(rng.integers(len(_GOODS)))]
        length = float(rng.uniform(0.6, 0.95))
        bay.add(
            asm, (x, bay.y0 + 0.02, rail_z - 0.03 - length), (x + 0.07, bay.y1 - 0.02, rail_z - 0.03), colour
        )
    if garment_end < bay.x1 - 0.1:
        mx = 0.5 * (garment_end + bay.x1)
        colour = _GOODS[int(rng.integers(len(_GOODS)))]
        if bay.z0 < 0.9:
            asm.add(cylinder((mx, yc, max(bay.z0, 0.0)), (mx, yc, 0.9), 0.02), _DARK)
        asm.add(ellipsoid((mx, yc, 1.25), (0.18, 0.1, 0.35)), colour)
        if bay.z1 > 1.75:
            asm.add(ellipsoid((mx, yc, 1.68), (0.08, 0.08, 0.1)), _WHITE)


def _plants(asm: Assembly, rng: np.random.Generator, bay: _Bay, wood: RGB) -> None:
    """Buckets of flowers on two tiers."""
    yc = 0.5 * (bay.y0 + bay.y1)
    radius = min(0.11, 0.5 * (bay.y1 - bay.y0) - 0.01)
    for tier, z in enumerate((max(bay.z0, 0.4), max(bay.z0, 0.4) + 0.55)):
        if z + 0.45 > bay.z1:
            break
        if z > bay.z0 + 0.01:
            bay.add(asm, (bay.x0 + 0.05, bay.y0, z - 0.03), (bay.x1 - 0.05, bay.y1, z), wood)
        for x in np.arange(bay.x0 + 0.15 + 0.12 * tier, bay.x1 - 0.15, 0.3):
            pot = _GOODS[int(rng.integers(len(_GOODS)))]
            asm.add(cylinder((x, yc, z), (x, yc, z + 0.2), radius), pot)
            asm.add(ellipsoid((x, yc, z + 0.3), (0.13, radius, 0.12)), (60, 130, 62))
            bloom = _GOODS[int(rng.integers(len(_GOODS)))]
            asm.add(ellipsoid((x, yc, z + 0.4), (0.07, 0.6 * radius, 0.05)), bloom)


def _salon(asm: Assembly, rng: np.random.Generator, bay: _Bay, wood: RGB) -> None:
    """Mirrors on the back wall with a styling chair in front of each."""
    count = max(1, int((bay.x1 - bay.x0) / 1.0))
    seat = _GOODS[int(rng.integers(len(_GOODS)))]
    for cx in bay.x0 + (np.arange(count) + 0.5) * (bay.x1 - bay.x0) / count:
        bay.add(asm, (cx - 0.3, bay.y0, 1.0), (cx + 0.3, bay.y0 + 0.02, 1.8), (200, 214, 222))
        bay.add(asm, (cx - 0.35, bay.y0, 0.8), (cx + 0.35, bay.y0 + 0.1, 0.84), wood)
        y0, y1 = bay.y0 + 0.04, bay.y1 - 0.02
        bay.add(asm, (cx - 0.04, y0 + 0.05, 0.0), (cx + 0.04, y1 - 0.05, 0.45), _HANDLE)
        bay.add(asm, (cx - 0.25, y0, 0.45), (cx + 0.25, y1, 0.55), seat)
        bay.add(asm, (cx - 0.22, y1 - 0.05, 0.55), (cx + 0.22, y1, 1.05), seat)


def _blinds(asm: Assembly, rng: np.random.Generator, bay: _Bay, wood: RGB) -> None:
    """Closed horizontal slat blinds across the whole window (rng unused, kept for one signature)."""
    del rng, wood
    z = np.arange(bay.z0 + 0.02, bay.z1 - 0.06, 0.07)
    lo = np.stack([np.full(z.size, bay.x0), np.full(z.size, bay.y1 - 0.03), z], axis=1)
    hi = np.stack([np.full(z.size, bay.x1), np.full(z.size, bay.y1 - 0.01), z + 0.06], axis=1)
    asm.add(boxes(lo, hi), _WHITE)


_CONTENT_BUILDERS = {
    "shelves": _shelves,
    "tables": _tables,
    "counter": _counter,
    "rails": _rails,
    "plants": _plants,
    "salon": _salon,
    "blinds": _blinds,
}


# ---------------------------------------------------------------------------------------------------
# awning and sign


def _awning(
    asm: Assembly, rng: np.random.Generator, lay: _Layout, style: str, colors: tuple[RGB, RGB], frame: RGB
) -> None:
    """A flat canopy or a sloped (plain or striped) awning with a valance, kept above head height."""
    x0, x1 = 0.1, lay.width - 0.1
    mount = lay.top + 0.1
    reach = float(rng.uniform(0.9, 1.3))
    front = _FACADE_DEPTH + reach
    if style == "flat":
        asm.box((x0, _FACADE_DEPTH, mount - 0.12), (x1, front - 0.04, mount), colors[0])
        asm.box((x0, front - 0.04, mount - 0.15), (x1, front, mount + 0.02), frame)
        return
    thick, valance = 0.03, 0.15
    drop = float(np.clip(mount - _HEADROOM - valance - thick, 0.05, 0.4))
    stripes = max(2, round((x1 - x0) / 0.35)) if style == "striped" else 1
    cuts = np.linspace(x0, x1, stripes + 1)
    for k, (a, b) in enumerate(itertools.pairwise(cuts)):
        colour = colors[k % 2]
        profile = [(_FACADE_DEPTH, mount), (_FACADE_DEPTH, mount - thick), (front, mount - drop - thick)]
        profile.append((front, mount - drop))
        asm.add(_prism_x(profile, a, b), colour)
        asm.box((a, front - 0.02, mount - drop - thick - valance), (b, front, mount - drop - thick), colour)
    for x in (x0 + 0.03, x1 - 0.03):
        asm.add(
            bar((x, _FACADE_DEPTH, mount - 0.45), (x, front - 0.03, mount - drop - thick - 0.02), 0.025),
            frame,
        )


def _prism_x(profile: Sequence[tuple[float, float]], x0: float, x1: float) -> Solid:
    """A convex (y, z) profile extruded along x from `x0` to `x1`."""
    return hull([(x, y, z) for x in (x0, x1) for y, z in profile])


@dataclass(frozen=True)
class _SignBoard:
    x0: float
    x1: float
    z0: float
    z1: float


def _sign_board(lay: _Layout, style: str) -> _SignBoard:
    """Where the sign board goes in the band above the openings."""
    band0, band1 = lay.top + 0.18, lay.height - 0.1
    inset = 0.05 if style == "framed" else 0.0
    height = min(0.8, band1 - band0) - 2 * inset
    zc = 0.5 * (band0 + band1)
    if style == "panel":
        width = min(lay.width - 0.3, max(2.0, 0.55 * lay.width))
        xc = float(np.clip(0.5 * sum(lay.door), 0.15 + 0.5 * width, lay.width - 0.15 - 0.5 * width))
        return _SignBoard(xc - 0.5 * width, xc + 0.5 * width, zc - 0.5 * height, zc + 0.5 * height)
    margin = 0.15 + inset
    return _SignBoard(margin, lay.width - margin, zc - 0.5 * height, zc + 0.5 * height)


def _sign_frame(asm: Assembly, sign: _SignBoard, color: RGB) -> None:
    """Four bars around a framed sign board, standing a little proud of it."""
    y0, y1, t = _FACADE_DEPTH, _FACADE_DEPTH + _SIGN_DEPTH + 0.02, 0.05
    asm.box((sign.x0 - t, y0, sign.z0 - t), (sign.x1 + t, y1, sign.z0), color)
    asm.box((sign.x0 - t, y0, sign.z1), (sign.x1 + t, y1, sign.z1 + t), color)
    asm.box((sign.x0 - t, y0, sign.z0), (sign.x0, y1, sign.z1), color)
    asm.box((sign.x1, y0, sign.z0), (sign.x1 + t, y1, sign.z1), color)


def _sign_mesh(sign: _SignBoard, image: np.ndarray, texture: Texture, color: RGB) -> MeshData:
    """The sign board as one box whose +y face shows `texture`, readable from +y."""
    vertices, faces = box((sign.x0, _FACADE_DEPTH, sign.z0), (sign.x1, _FACADE_DEPTH + _SIGN_DEPTH, sign.z1))
    tri = vertices[faces]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    front = normals[:, 1] > 0.9 * np.linalg.norm(normals, axis=1)
    u = (sign.x1 - tri[..., 0]) / (sign.x1 - sign.x0)  # +x is the reader's left
    v = (tri[..., 2] - sign.z0) / (sign.z1 - sign.z0)
    uvs = np.where(front[:, None, None], np.stack([u, v], axis=-1), 0.0)
    index = np.where(front, 0, -1).astype(np.int16)
    colors = np.broadcast_to(np.asarray(color, dtype=np.uint8), faces.shape)
    return MeshData(vertices, faces, colors, uvs, index, (texture,))


# ---------------------------------------------------------------------------------------------------
# public builder


def _scheme(category: str, design: int) -> tuple[RGB, RGB]:
    """``(sign background, lettering)`` of a design: brand on contrast, contrast on brand, or on dark."""
    brand, contrast = _ACCENTS[category]
    scheme = design % 3
    if scheme == 0:
        return brand, contrast
    if scheme == 1:
        return contrast, brand
    lighter = max((brand, contrast), key=lambda c: 0.3 * c[0] + 0.59 * c[1] + 0.11 * c[2])
    return _DARK, lighter


def _check(category: str, design: int | None, width: float | None, height: float) -> None:
    if category not in _ACCENTS:
        raise UnknownCategoryError(
            f"unknown place category {category!r}; known: {', '.join(PLACE_CATEGORIES)}"
        )
    if design is not None and not 0 <= design < DESIGNS_PER_CATEGORY:
        raise ValueError(f"design must be in 0..{DESIGNS_PER_CATEGORY - 1}, got {design}")
    if width is not None and not (np.isfinite(width) and width >= MIN_WIDTH):
        raise AssetSizeError(f"storefront width must be >= {MIN_WIDTH} m, got {width}")
    if not (np.isfinite(height) and height >= MIN_HEIGHT):
        raise AssetSizeError(f"storefront height must be >= {MIN_HEIGHT} m, got {height}")


def storefront(
    category: str,
    rng: np.random.Generator,
    *,
    name: str | None = None,
    width: float | None = None,
    height: float = 3.6,
    design: int | None = None,
) -> Storefront:
    """Build a storefront of a place category.

    Parameters
    ----------
    category : str
        One of :data:`PLACE_CATEGORIES` (see :func:`place_category` for OSM tags).
    rng : numpy.random.Generator
        Source of all randomness (design and width when not given, name, colour shades, contents).
    name : str, optional
        Text of the sign (an OSM ``name``); a plausible name for the category is generated if None.
    width : float, optional
        Width along x in m (>= :data:`MIN_WIDTH`); drawn from 4..8 m if None.
    height : float
        Height in m (>= :data:`MIN_HEIGHT`).
    design : int, optional
        Design id in ``0 .. DESIGNS_PER_CATEGORY - 1``; drawn if None.

    Returns
    -------
    Storefront
        Mesh and metadata in the local frame described in the module docstring.

    Raises
    ------
    UnknownCategoryError
        If `category` is not a place category.
    AssetSizeError
        If `width` or `height` is too small.
    ValueError
        If `design` is out of range.
    """
    _check(category, design, width, height)
    design = int(rng.integers(DESIGNS_PER_CATEGORY)) if design is None else int(design)
    width = float(rng.uniform(4.0, 8.0)) if width is None else float(width)
    name = generated_name(category, rng) if name is None else name
    variant = _VARIANTS[design]
    lay = _layout(width, float(height), variant)
    facade = shade(
        _FACADES[(design + PLACE_CATEGORIES.index(category)) % len(_FACADES)], rng.uniform(0.95, 1.05)
    )
    frame = _FRAMES[variant.frame]
    asm, glass = Assembly(), Assembly()
    _wall(asm, lay, facade)
    _door(asm, glass, lay, frame, handle_right=variant.door < 0.5)
    wood = _WOOD[design % len(_WOOD)]
    for x0, x1 in lay.windows:
        _window(asm, glass, x0, x1, lay, variant.windows, frame)
        bay = _Bay(x0 + _FRAME, x1 - _FRAME, 0.04, _FACADE_DEPTH - 0.09, lay.sill + _FRAME, lay.top - _FRAME)
        _CONTENT_BUILDERS[_CONTENTS[category]](asm, rng, bay, wood)
    background, lettering = _scheme(category, design)
    if variant.awning != "none":
        stripes = (_ACCENTS[category][0], _WHITE if variant.awning == "striped" else _ACCENTS[category][0])
        _awning(asm, rng, lay, variant.awning, stripes, frame)
    board = _sign_board(lay, variant.sign)
    if variant.sign == "framed":
        _sign_frame(asm, board, frame)
    text = name.upper() if variant.upper else name
    image = storefront_signs.sign_image(
        text,
        category,
        background=background,
        foreground=lettering,
        aspect=(board.x1 - board.x0) / (board.z1 - board.z0),
        icons=variant.icons,
        border=variant.sign == "board",
    )
    texture = Texture(storefront_signs.texture_name(category, design, text, image), image)
    parts = [asm.mesh(), glass.mesh(), _sign_mesh(board, image, texture, background)]
    return _assemble(parts, category, name, design, lay, board)


def _assemble(
    parts: list[MeshData], category: str, name: str, design: int, lay: _Layout, board: _SignBoard
) -> Storefront:
    """Join body, glass and sign, centre the result on its bounding box and move the metadata along."""
    joined = MeshData.concatenate(parts)
    lo, hi = joined.bounds()
    offset = -0.5 * (lo + hi)
    mesh = joined.transformed(offset)
    glass = np.zeros(mesh.num_faces, dtype=bool)
    glass[parts[0].num_faces : parts[0].num_faces + parts[1].num_faces] = True
    glass.setflags(write=False)
    entrance = np.array([0.5 * sum(lay.door), _FACADE_DEPTH, 0.0]) + offset
    sign_center = np.array(
        [0.5 * (board.x0 + board.x1), _FACADE_DEPTH + _SIGN_DEPTH, 0.5 * (board.z0 + board.z1)]
    )
    size = hi - lo
    return Storefront(
        mesh=mesh,
        category=category,
        name=name,
        design=design,
        size=(float(size[0]), float(size[1]), float(size[2])),
        entrance=tuple(float(c) for c in entrance),
        sign_center=tuple(float(c) for c in sign_center + offset),
        sign_size=(board.x1 - board.x0, board.z1 - board.z0),
        glass_faces=glass,
    )
