"""The texts of PlaceNav instructions: place names, category instructions and intentions.

A PlaceNav episode asks the robot to reach a storefront of a place category (one of
:data:`navverse.assets.facade.storefronts.PLACE_CATEGORIES`). It carries three instruction types (paper table
``tab:instruction_type_placenav``):

- ``category`` names the place category, in one of several sentence templates with its human name and
  the right article: "Find a bank.", "Take me to an ice-cream shop." (:func:`category_instruction`).
- ``intention`` states a need the category meets, and **never names the category** nor an obvious word
  of its name: "I need to withdraw some cash." for a bank, "My prescription ran out." for a pharmacy
  (:func:`intention_instruction`, texts in :data:`INTENTIONS`). The agent has to ground the need to a
  kind of place itself.
- the route (VLN-style) instruction describes the path to the goal; its arrival names the place with
  :func:`place_phrase` ("... and stop at the bank").

:data:`PLACE_NAMES` holds the human name of each category (``fast_food`` -> "fast-food restaurant").
The random generator chooses the wording only: the same generator state gives the same text.
"""

from __future__ import annotations

import numpy as np

__all__ = ["INTENTIONS", "PLACE_NAMES", "category_instruction", "intention_instruction", "place_phrase"]

PLACE_NAMES: dict[str, str] = {
    "restaurant": "restaurant",
    "cafe": "cafe",
    "fast_food": "fast-food restaurant",
    "bar": "bar",
    "bank": "bank",
    "pharmacy": "pharmacy",
    "supermarket": "supermarket",
    "convenience": "convenience store",
    "bakery": "bakery",
    "clothes": "clothes shop",
    "hairdresser": "hairdresser",
    "books": "bookshop",
    "florist": "florist",
    "hardware": "hardware store",
    "electronics": "electronics store",
    "post_office": "post office",
    "clinic": "clinic",
    "ice_cream": "ice-cream shop",
    "butcher": "butcher's",
    "optician": "optician's",
    "jewelry": "jewelry store",
    "shop": "shop",
}
"""Human name of each place category, as read after an article ("a bank", "an optician's")."""

# fmt: off
INTENTIONS: dict[str, tuple[str, ...]] = {
    "restaurant": (
        "I'd like to sit down for a proper three-course dinner.",
        "Let's book a table and have a waiter bring us a nice meal.",
        "Where can I have a sit-down lunch with a menu and table service?",
        "I want to take my family out for a dinner with wine and dessert.",
    ),
    "cafe": (
        "I could really use a cappuccino right now.",
        "Let's sit down somewhere for a coffee and a slice of cake.",
        "Where can I get a latte and work on my laptop for an hour?",
        "I'd like a cup of tea and a quiet place to read.",
    ),
    "fast_food": (
        "I want a burger and fries to take away.",
        "Let's grab a quick, cheap meal we can eat on the go.",
        "Where can I get a cheeseburger and a milkshake in a hurry?",
        "Let's get a box of chicken nuggets and a soda to go.",
    ),
    "bar": (
        "I'd like a pint of beer after work.",
        "Let's meet friends for a few cocktails tonight.",
        "Where can I get a glass of whisky and watch the match?",
        "I want to relax with a cold draught lager.",
    ),
    "bank": (
        "I need to withdraw some cash.",
        "I'd like to open a savings account.",
        "Where can I deposit this cheque?",
        "Let's change some euros into dollars before the trip.",
        "I want to talk to someone about a mortgage.",
    ),
    "pharmacy": (
        "My prescription ran out.",
        "I have a headache and need some painkillers.",
        "Where can I buy cough syrup and throat lozenges?",
        "I'd like to pick up my allergy tablets.",
        "Let's get some plasters and antiseptic for this cut.",
    ),
    "supermarket": (
        "I need to do the big weekly food run for the household.",
        "Let's fill a trolley with everything we eat in a week.",
        "Where can I buy fruit, vegetables, milk and detergent all in one trip?",
        "I'd like to stock up the fridge and the pantry for a family of five.",
    ),
    "convenience": (
        "I need a newspaper and a pack of chewing gum.",
        "Where can I quickly grab a bottle of water and a snack around the corner, late at night?",
        "I'd like to buy a lottery ticket and a magazine.",
        "Let's pop in somewhere small for a pint of milk and some batteries at midnight.",
    ),
    "bakery": (
        "I'd like a fresh sourdough loaf.",
        "Let's get some warm croissants for breakfast.",
        "Where can I order a birthday cake?",
        "I need a dozen bread rolls and a few pastries for the party.",
    ),
    "clothes": (
        "I need a warm jacket for the winter.",
        "I'd like to try on a pair of jeans.",
        "Where can I buy a dress for a wedding?",
        "Let's find some new trainers and a couple of T-shirts.",
    ),
    "hairdresser": (
        "I need a haircut.",
        "My fringe is getting too long and needs a trim.",
        "I'd like my roots coloured and a blow-dry.",
        "Where can I get a shave and a new hairstyle?",
    ),
    "books": (
        "I'd like a novel to read on holiday.",
        "Where can I find the latest bestseller in paperback?",
        "I need a dictionary and a few pens for school.",
        "Let's browse some poetry and cookery titles.",
    ),
    "florist": (
        "I'd like a bouquet of roses for our anniversary.",
        "I need some tulips to bring to my mother.",
        "Where can I order a wreath for a funeral?",
        "Let's pick up a potted orchid as a housewarming gift.",
    ),
    "hardware": (
        "I need a hammer and a box of nails.",
        "Where can I buy screws and a drill bit?",
        "My tap is leaking and I need a new washer and a wrench.",
        "Let's get a tin of paint and a brush for the fence.",
    ),
    "electronics": (
        "I need a new charger for my phone.",
        "I'd like to buy a laptop for work.",
        "Where can I get some wireless headphones?",
        "My phone screen is cracked and needs replacing.",
        "Let's pick up a new television and an HDMI cable.",
    ),
    "post_office": (
        "I need to send a parcel abroad.",
        "I'd like to buy some stamps for these letters.",
        "Where can I pick up a package that couldn't be delivered?",
        "Let's mail these birthday cards by registered delivery.",
    ),
    "clinic": (
        "I've had a fever for three days and want to be examined.",
        "I need a vaccination before my trip.",
        "My tooth has been aching all week.",
        "Where can I get a general health check-up and a blood test?",
    ),
    "ice_cream": (
        "I'd love a cone with two scoops of chocolate.",
        "It's so hot, let's get a frozen treat.",
        "Where can I get a sundae with sprinkles?",
        "I'd like a scoop of pistachio in a waffle cone.",
    ),
    "butcher": (
        "I need some fresh steaks for the barbecue.",
        "I'd like half a kilo of minced beef.",
        "Where can I get some lamb chops and homemade sausages?",
        "Let's pick up a whole chicken, freshly cut, for Sunday lunch.",
    ),
    "optician": (
        "My glasses broke and need new lenses.",
        "I'd like to get my eyes tested.",
        "Where can I buy contact lenses?",
        "I need new frames for my spectacles.",
    ),
    "jewelry": (
        "I need an engagement ring.",
        "I'd like a gold necklace for my wife's birthday.",
        "Where can I buy a pair of diamond earrings?",
        "Let's get a silver bracelet engraved as a gift.",
    ),
    "shop": (
        "I'd like to browse around and see what's for sale.",
        "Let's go and buy a few odds and ends.",
        "Where can I browse the window displays and buy something on a whim?",
        "I want to look around a local retailer for something nice.",
    ),
}
# fmt: on
"""Intentions per place category: needs the category meets, never naming the category."""

_CATEGORY_TEMPLATES: tuple[str, ...] = (
    "Find {a} {name}.",
    "Go to the nearest {name}.",
    "Take me to {a} {name}.",
    "Navigate to {a} {name}.",
    "I'm looking for {a} {name}.",
    "Where is the closest {name}?",
    "Please head to {a} {name}.",
    "Can you find {a} {name} for me?",
)


def _name(category: str) -> str:
    """The human name of `category`; ValueError for a category without texts."""
    try:
        return PLACE_NAMES[category]
    except KeyError:
        known = ", ".join(PLACE_NAMES)
        raise ValueError(f"unknown place category {category!r}; known categories: {known}") from None


def _article(name: str) -> str:
    """The indefinite article before `name`: "an" before a vowel letter, else "a"."""
    return "an" if name[0].lower() in "aeiou" else "a"


def place_phrase(category: str) -> str:
    """The goal as named at the end of a route instruction ("... and stop at the bank").

    Parameters
    ----------
    category : str
        A place category (key of :data:`PLACE_NAMES`).

    Returns
    -------
    str
        ``"the <name>"``, e.g. "the post office".

    Raises
    ------
    ValueError
        For an unknown category; the message lists the known ones.
    """
    return f"the {_name(category)}"


def category_instruction(category: str, rng: np.random.Generator) -> str:
    """A ``category`` instruction: one sentence template naming the place category.

    Parameters
    ----------
    category : str
        A place category (key of :data:`PLACE_NAMES`).
    rng : numpy.random.Generator
        Chooses the template.

    Returns
    -------
    str
        E.g. "Find a bank.", "Take me to an ice-cream shop.", "Where is the closest pharmacy?".

    Raises
    ------
    ValueError
        For an unknown category; the message lists the known ones.
    """
    name = _name(category)
    template = _CATEGORY_TEMPLATES[int(rng.integers(len(_CATEGORY_TEMPLATES)))]
    return template.format(a=_article(name), name=name)


def intention_instruction(category: str, rng: np.random.Generator) -> str:
    """An ``intention`` instruction: a need the place category meets, without naming it.

    Parameters
    ----------
    category : str
        A place category (key of :data:`INTENTIONS`).
    rng : numpy.random.Generator
        Chooses the intention.

    Returns
    -------
    str
        One of ``INTENTIONS[category]``, e.g. "I need to withdraw some cash." for ``bank``.

    Raises
    ------
    ValueError
        For an unknown category; the message lists the known ones.
    """
    _name(category)
    options = INTENTIONS[category]
    return options[int(rng.integers(len(options)))]
