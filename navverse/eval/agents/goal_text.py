"""The goal category an instruction names: the text-matching step of a non-privileged agent.

An agent told an instruction rather than a category (VLN, PlaceNav under ``route`` or
``intention``) can still look for what the text names. :func:`named_goal_category` matches the
categories an agent's semantic sensor knows (``task.semantic_categories``) by their names, singular
or plural (``office_chair`` as "office chair", a place by its human name, ``fast_food`` as
"fast-food restaurant"), and takes the one named last: instructions end at their destination. An
intention ("I need to withdraw some cash.") names no category, so nothing is found: telling what
serves an intention is the language understanding this matcher does not have.

>>> named_goal_category("Walk past the sofa and stop at the bookshelf.", ["sofa", "bookshelf", "tv"])
'bookshelf'
>>> named_goal_category("I need to withdraw some cash.", ["bank", "cafe"])
''
"""

from __future__ import annotations

import re
from collections.abc import Iterable

__all__ = ["named_goal_category"]


def _names(category: str) -> set[str]:
    """The words a text may name `category` by."""
    # here: the instructions package loads the camera renderer, which loading an agent does not need
    from navverse.episodes.instructions.places import PLACE_NAMES

    names = {category.replace("_", " ").lower()}
    if category in PLACE_NAMES:
        names.add(PLACE_NAMES[category].lower())
    return names


def named_goal_category(text: str, categories: Iterable[str]) -> str:
    """The category of `categories` named last in `text` ("" when none is named).

    Parameters
    ----------
    text : str
        The instruction.
    categories : iterable of str
        Categories the agent can recognise.

    Returns
    -------
    str
        The category whose name ends last in the text; of names ending at the same place, the
        longest ("fast-food restaurant" over "restaurant"); "" when no name occurs.
    """
    lowered = text.lower()
    best: tuple[int, int, str] | None = None
    for category in sorted(set(categories)):
        for name in _names(category):
            pattern = r"(?<![\w-])" + re.escape(name) + r"(?:s|es)?(?![\w-])"
            for match in re.finditer(pattern, lowered):
                found = (match.end(), len(name), category)
                if best is None or found[:2] > best[:2]:
                    best = found
    return best[2] if best is not None else ""
