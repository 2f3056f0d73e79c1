"""PlaceNav instruction texts: place names, category instructions, intentions that never name the place."""

from __future__ import annotations

import re

import numpy as np
import pytest

from navverse.assets.facade.storefronts import PLACE_CATEGORIES
from navverse.episodes.instructions.places import (
    INTENTIONS,
    PLACE_NAMES,
    category_instruction,
    intention_instruction,
    place_phrase,
)

STOP_WORDS = frozenset({"a", "an", "the", "of", "and", "s"})
# Synonyms of a category's name that would give it away as much as the name itself.
EXTRA_GIVEAWAYS: dict[str, tuple[str, ...]] = {
    "cafe": ("café",),
    "bar": ("pub", "tavern", "biergarten"),
    "bank": ("banker", "atm"),
    "pharmacy": ("chemist", "pharmacist", "drugstore"),
    "supermarket": ("market", "grocer"),
    "convenience": ("convenien", "kiosk", "newsagent"),
    "bakery": ("bake", "baker"),
    "hairdresser": ("salon", "barber"),
    "books": ("bookstore", "stationer"),
    "florist": ("flower", "garden"),
    "hardware": ("diy",),
    "electronics": ("electronic",),
    "clinic": ("doctor", "dentist", "surgery"),
    "ice_cream": ("gelato",),
    "optician": ("optometrist", "optic"),
    "jewelry": ("jewel", "jeweller", "jewellery"),
    "shop": ("shopping", "store"),
}
ARTICLE = re.compile(r"\b(a|an) ([a-z][\w'-]*)", re.IGNORECASE)


def _stem(word: str) -> str:
    return word[:-1] if len(word) > 3 and word.endswith("s") else word


def _words(text: str) -> set[str]:
    return {_stem(w) for w in re.findall(r"[a-zé]+", text.lower()) if w not in STOP_WORDS}


def giveaway_words(category: str) -> set[str]:
    """Words of the category's human name and id, plus its listed synonyms, stemmed."""
    text = " ".join((PLACE_NAMES[category], category.replace("_", " "), *EXTRA_GIVEAWAYS.get(category, ())))
    return _words(text)


def gives_away(sentence: str, category: str) -> set[str]:
    """The words of `sentence` that name `category`: equal, or one a prefix of the other."""
    found = set()
    for t in _words(sentence):
        for w in giveaway_words(category):
            if t == w or (len(w) >= 3 and t.startswith(w)) or (len(t) >= 4 and w.startswith(t)):
                found.add(t)
    return found


def test_giveaway_check_catches_names() -> None:
    assert gives_away("I need to find a bank.", "bank") == {"bank"}
    assert gives_away("Let's go shopping.", "shop") == {"shopping"}
    assert gives_away("I want a good book.", "books") == {"book"}
    assert gives_away("Post this letter.", "post_office") == {"post"}
    assert gives_away("Some freshly baked bread.", "bakery") == {"baked"}
    assert gives_away("I want some ice.", "ice_cream") == {"ice"}
    assert gives_away("I need to withdraw some cash.", "bank") == set()


def test_every_category_has_a_name_and_intentions() -> None:
    assert set(PLACE_NAMES) == set(PLACE_CATEGORIES)
    assert set(INTENTIONS) == set(PLACE_CATEGORIES)
    for category in PLACE_CATEGORIES:
        assert PLACE_NAMES[category].strip(), category
        texts = INTENTIONS[category]
        assert len(set(texts)) >= 4, category
        assert len(set(texts)) == len(texts), category
        for text in texts:
            assert text[0].isupper() and text[-1] in ".?", text


@pytest.mark.parametrize("category", PLACE_CATEGORIES)
def test_intentions_never_name_the_category(category: str) -> None:
    for text in INTENTIONS[category]:
        assert not gives_away(text, category), (category, text)


def test_intentions_are_distinct_across_categories() -> None:
    all_texts = [t for texts in INTENTIONS.values() for t in texts]
    assert len(set(all_texts)) == len(all_texts)


def test_category_instruction_uses_name_and_article() -> None:
    seen_articles: dict[str, set[str]] = {}
    for category in PLACE_CATEGORIES:
        name = PLACE_NAMES[category]
        rng = np.random.default_rng(7)
        for _ in range(40):
            text = category_instruction(category, rng)
            assert name in text, (category, text)
            assert text[0].isupper() and text[-1] in ".?", text
            for article, word in ARTICLE.findall(text):
                expected = "an" if word[0].lower() in "aeiou" else "a"
                assert article.lower() == expected, text
                seen_articles.setdefault(name, set()).add(article.lower())
    assert seen_articles["electronics store"] == {"an"}
    assert seen_articles["ice-cream shop"] == {"an"}
    assert seen_articles["optician's"] == {"an"}
    assert seen_articles["bank"] == {"a"}
    assert seen_articles["hardware store"] == {"a"}


def test_category_instruction_examples() -> None:
    texts = {category_instruction("ice_cream", np.random.default_rng(s)) for s in range(200)}
    assert "Find an ice-cream shop." in texts
    assert "Go to the nearest ice-cream shop." in texts
    assert len(texts) >= 5


@pytest.mark.parametrize("make", [category_instruction, intention_instruction])
def test_deterministic_and_varied(make) -> None:
    for category in ("bank", "fast_food", "shop"):
        first = [make(category, np.random.default_rng(11)) for _ in range(3)]
        assert first[0] == first[1] == first[2]
        texts = {make(category, np.random.default_rng(seed)) for seed in range(50)}
        assert len(texts) >= 3, texts
    rng_a, rng_b = np.random.default_rng(3), np.random.default_rng(3)
    assert [make("cafe", rng_a) for _ in range(10)] == [make("cafe", rng_b) for _ in range(10)]


def test_intention_instruction_draws_from_intentions() -> None:
    texts = {intention_instruction("pharmacy", np.random.default_rng(s)) for s in range(100)}
    assert texts == set(INTENTIONS["pharmacy"])


def test_place_phrase() -> None:
    assert place_phrase("bank") == "the bank"
    assert place_phrase("post_office") == "the post office"
    assert place_phrase("fast_food") == "the fast-food restaurant"


@pytest.mark.parametrize(
    "call",
    [
        lambda c: category_instruction(c, np.random.default_rng(0)),
        lambda c: intention_instruction(c, np.random.default_rng(0)),
        place_phrase,
    ],
)
def test_unknown_category_raises(call) -> None:
    with pytest.raises(ValueError, match=r"unknown place category 'casino'.*restaurant.*jewelry"):
        call("casino")
