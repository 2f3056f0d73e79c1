"""Places of interest of synthetic cities: shops, cafes, banks... on the ground floors of buildings.

A building whose front faces a street (not the river or the window's edge) holds a ground-floor
place with probability ``arterial_poi_share`` on an arterial, ``poi_share`` on another street; a
building over 24 m wide holds a second one with probability 0.4. A place's category is drawn from
:data:`POI_TABLE`, the ``amenity=*`` and ``shop=*`` values common in city centres with rough
relative weights (rounded orders of magnitude of how often each value is mapped in OpenStreetMap,
not measured from any one city); every ``amenity`` value is one the OSM reader keeps as a place
(:data:`~navverse.city.tag_tables.POI_AMENITIES`). It stands just inside the street facade, 0.5 m
behind a point drawn along its middle 60 %, and that facade point is the building's entrance. Its
name comes from a word or family name and a label of its category (``Linden Pharmacy``,
``Parker's Bakery``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from navverse.city.map import Poi
from navverse.city.synthetic.names import SURNAMES, WORDS, pick
from navverse.city.synthetic.streets import XY

__all__ = ["POI_TABLE", "PoiDraft", "ground_floor_pois"]

POI_TABLE: tuple[tuple[str, str, int, tuple[str, ...]], ...] = (
    ("amenity", "restaurant", 14, ("Kitchen", "Bistro", "Trattoria", "Grill", "Brasserie")),
    ("shop", "convenience", 10, ("Corner Shop", "Express", "Mini Market", "Food & Wine")),
    ("amenity", "cafe", 9, ("Café", "Coffee House", "Espresso Bar", "Tea Room")),
    ("shop", "clothes", 9, ("Boutique", "Outfitters", "Fashion", "Clothing")),
    ("amenity", "fast_food", 8, ("Burger", "Pizza", "Kebab", "Fish & Chips", "Noodle Bar")),
    ("shop", "hairdresser", 7, ("Hair Studio", "Barbers", "Salon")),
    ("shop", "supermarket", 5, ("Supermarket", "Market", "Foods")),
    ("amenity", "bank", 4, ("Bank", "Savings Bank", "Building Society")),
    ("amenity", "pharmacy", 4, ("Pharmacy", "Chemists", "Apothecary")),
    ("amenity", "bar", 4, ("Bar", "Lounge", "Wine Bar", "Cocktail Bar")),
    ("shop", "bakery", 4, ("Bakery", "Bakehouse", "Patisserie")),
    ("shop", "beauty", 4, ("Beauty", "Nail Studio", "Spa")),
    ("amenity", "pub", 3, ("Arms", "Tavern", "Inn")),
    ("amenity", "dentist", 3, ("Dental Care", "Dental Practice")),
    ("amenity", "doctors", 3, ("Medical Centre", "Surgery", "Health Centre")),
    ("shop", "mobile_phone", 3, ("Mobile", "Phone Shop")),
    ("shop", "books", 2, ("Books", "Bookshop", "Booksellers")),
    ("shop", "florist", 2, ("Flowers", "Florist", "Blooms")),
    ("shop", "hardware", 2, ("Hardware", "DIY", "Ironmongers")),
    ("shop", "butcher", 2, ("Butchers", "Meats")),
    ("shop", "shoes", 2, ("Shoes", "Footwear")),
    ("shop", "optician", 2, ("Opticians", "Eyecare")),
    ("shop", "jewelry", 2, ("Jewellers", "Gold & Silver")),
    ("shop", "kiosk", 2, ("Kiosk", "News")),
    ("shop", "electronics", 2, ("Electronics", "Digital")),
    ("shop", "furniture", 2, ("Furniture", "Interiors")),
    ("amenity", "school", 2, ("Primary School", "School", "Academy", "High School")),
    ("amenity", "kindergarten", 1, ("Kindergarten", "Nursery", "Day Nursery")),
    ("amenity", "post_office", 1, ("Post Office",)),
    ("amenity", "ice_cream", 1, ("Gelateria", "Ice Cream")),
    ("amenity", "veterinary", 1, ("Veterinary Clinic", "Vets")),
    ("shop", "greengrocer", 1, ("Greengrocer", "Fruit & Veg")),
    ("shop", "gift", 1, ("Gifts", "Gift Shop")),
    ("shop", "bicycle", 1, ("Cycles", "Bike Shop")),
    ("shop", "alcohol", 1, ("Wines", "Off Licence")),
    ("shop", "laundry", 1, ("Laundrette", "Laundry")),
    ("shop", "dry_cleaning", 1, ("Dry Cleaners",)),
    ("shop", "travel_agency", 1, ("Travel", "Holidays")),
)
"""``(key, value, weight, name labels)`` of each place category; a category is drawn with
probability weight / sum of weights (restaurant 14 / 127 ≈ 11 %, travel agency 1 / 127)."""

_WEIGHTS = np.array([row[2] for row in POI_TABLE], dtype=float) / sum(row[2] for row in POI_TABLE)


@dataclass(frozen=True)
class PoiDraft:
    """A building that may hold places: its id, front facade end points (the inside on the
    facade's left), whether that facade faces a street (not the river or the window's edge) and
    whether the street is an arterial."""

    building: str
    front: tuple[XY, XY]
    street: bool
    arterial: bool


def _name(rng: np.random.Generator, labels: tuple[str, ...]) -> str:
    label = pick(rng, labels)
    style = int(rng.integers(3))
    if style == 0:
        return f"{pick(rng, WORDS)} {label}"
    if style == 1:
        return f"{pick(rng, SURNAMES)}'s {label}"
    return f"The {pick(rng, WORDS)} {label}"


def ground_floor_pois(
    rng: np.random.Generator, drafts: list[PoiDraft], *, share: float, arterial_share: float
) -> tuple[list[Poi], dict[str, list[XY]]]:
    """Places on ground floors (see the module docstring) and each building's entrances.

    Parameters
    ----------
    rng : numpy.random.Generator
        Draws counts, positions, categories and names.
    drafts : list of PoiDraft
        The buildings, in map order.
    share, arterial_share : float
        Chance of a place in a building on another street, on an arterial.

    Returns
    -------
    tuple of (list of Poi, dict)
        The places (``poi-1``...) and, by building id, the facade points they are entered from.
    """
    pois: list[Poi] = []
    entrances: dict[str, list[XY]] = {}
    for draft in drafts:
        (x0, y0), (x1, y1) = draft.front
        width = math.dist(draft.front[0], draft.front[1])
        draws = rng.uniform(size=2)
        count = int(draft.street and draws[0] < (arterial_share if draft.arterial else share))
        count += int(count == 1 and width > 24.0 and draws[1] < 0.4)
        ux, uy = (x1 - x0) / width, (y1 - y0) / width
        nx, ny = -uy, ux
        for k in range(count):
            share_along = float(rng.uniform(0.2, 0.8)) if count == 1 else (0.25 if k == 0 else 0.75)
            fx, fy = x0 + ux * width * share_along, y0 + uy * width * share_along
            key, value, _, labels = POI_TABLE[int(rng.choice(len(POI_TABLE), p=_WEIGHTS))]
            door = (round(fx, 3) + 0.0, round(fy, 3) + 0.0)
            entrances.setdefault(draft.building, []).append(door)
            pois.append(
                Poi(
                    id=f"poi-{len(pois) + 1}",
                    position=(round(fx + 0.5 * nx, 3) + 0.0, round(fy + 0.5 * ny, 3) + 0.0),
                    category=value,
                    tag=f"{key}={value}",
                    name=_name(rng, labels),
                    building=draft.building,
                )
            )
    return pois, entrances
