"""Names for synthetic streets and places: plausible English names drawn from fixed word lists.

Names are drawn from a ``numpy.random.Generator`` in a fixed order, so the same generator state
gives the same names. Street names are unique within a city (a qualifier such as ``North`` or
``Upper`` is added once the plain words run out, then a number).
"""

from __future__ import annotations

import numpy as np

__all__ = ["SURNAMES", "WORDS", "StreetNamer", "pick"]

WORDS = (
    "Acacia", "Alder", "Amber", "Anchor", "Apple", "Ash", "Aspen", "Bay", "Beacon", "Beech", "Birch",
    "Bramble", "Bridge", "Brook", "Canal", "Castle", "Cedar", "Chapel", "Cherry", "Chestnut", "Church",
    "Clover", "Copper", "Cross", "Elm", "Fern", "Ferry", "Field", "Forge", "Fountain", "Garden",
    "Grove", "Harbour", "Hawthorn", "Hazel", "Heath", "Hill", "Holly", "Ivy", "Juniper", "King",
    "Lake", "Larch", "Laurel", "Lily", "Lime", "Linden", "Maple", "Market", "Meadow", "Mill",
    "Myrtle", "Oak", "Orchard", "Park", "Pine", "Poplar", "Queen", "Quarry", "Rose", "Rowan",
    "Sage", "School", "Silver", "Spring", "Station", "Stone", "Sycamore", "Thistle", "Tower",
    "Union", "Vine", "Walnut", "Water", "Well", "Willow", "Windmill", "Yew",
)  # fmt: skip
"""Words that street and place names are made of."""

SURNAMES = (
    "Abbott", "Baker", "Barnes", "Bell", "Bennett", "Brooks", "Carter", "Clarke", "Cole", "Cooper",
    "Davies", "Ellis", "Evans", "Fisher", "Fletcher", "Foster", "Gray", "Hall", "Harris", "Hayes",
    "Hughes", "Hunt", "Jones", "Kelly", "Knight", "Lane", "Lewis", "Marsh", "Mason", "Miller",
    "Moore", "Morgan", "Murray", "Palmer", "Parker", "Reed", "Russell", "Shaw", "Spencer", "Stone",
    "Taylor", "Turner", "Walker", "Ward", "Webb", "Wells", "West", "White", "Wood", "Young",
)  # fmt: skip
"""Family names for names such as ``Parker's Bakery``."""

_QUALIFIERS = ("North", "South", "East", "West", "Upper", "Lower", "Old", "New")


def pick(rng: np.random.Generator, options: tuple[str, ...]) -> str:
    """One of ``options``, uniformly."""
    return options[int(rng.integers(len(options)))]


class StreetNamer:
    """Unique street names: a word from :data:`WORDS` and a suffix for the street's kind."""

    SUFFIXES: dict[str, tuple[str, ...]] = {
        "secondary": ("Avenue", "Boulevard", "Road"),
        "tertiary": ("Road", "Avenue", "Parade"),
        "residential": ("Street", "Lane", "Way", "Terrace", "Place", "Row"),
        "ring": ("Ring", "Crescent", "Circus"),
        "stub": ("Close", "Court", "Mews"),
        "living_street": ("Mews", "Walk", "Yard"),
        "service": ("Yard", "Passage", "Alley"),
    }

    def __init__(self, rng: np.random.Generator) -> None:
        self.rng = rng
        self.words = [WORDS[int(i)] for i in rng.permutation(len(WORDS))]
        self.used: set[str] = set()

    def name(self, kind: str) -> str:
        """A new name for a street of ``kind`` (a key of :attr:`SUFFIXES`)."""
        suffix = pick(self.rng, self.SUFFIXES[kind])
        for word in self.words:
            if f"{word} {suffix}" not in self.used:
                self.used.add(f"{word} {suffix}")
                return f"{word} {suffix}"
        for qualifier in _QUALIFIERS:
            for word in self.words:
                candidate = f"{qualifier} {word} {suffix}"
                if candidate not in self.used:
                    self.used.add(candidate)
                    return candidate
        number = len(self.used) + 1
        self.used.add(f"{suffix} {number}")
        return f"{suffix} {number}"
