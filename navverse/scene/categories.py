"""Category rules: regular expressions over prim (or node) names and paths that name object categories.

Scene recipes use them to say which objects are goals and what they are called, as the paper's
Appendix D.1 does for GRScenes: the first rule whose pattern matches wins; a rule with
``category: null`` drops the object from the annotations (it stays as static geometry).

>>> rules = [CategoryRule(pattern=r"^office_chair", category="chair"), CategoryRule(pattern=r"^plant_")]
>>> assign_category(rules, name="office_chair_0003", path="/World/Objects/office_chair_0003", default="x")
'chair'
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator

__all__ = ["CATEGORY_PATTERN", "CategoryRule", "assign_category", "category_name", "unmatched_rules"]

CATEGORY_PATTERN = r"^[a-z][a-z0-9_]*$"
"""Object categories are lower_snake_case names."""


class CategoryRule(BaseModel):
    """One rule: objects whose name (or path) matches ``pattern`` get ``category``."""

    model_config = ConfigDict(extra="forbid", frozen=True, use_attribute_docstrings=True)

    pattern: str
    """A Python regular expression, searched (``re.search``, not anchored) in the name or the path."""
    on: Literal["name", "path"] = "name"
    """What ``pattern`` is searched in: the prim (or node) ``name``, or its full ``path``."""
    category: str | None = Field(default=None, pattern=CATEGORY_PATTERN)
    """The category the matching objects get (lower_snake_case); null: they get none (they are dropped)."""

    @field_validator("pattern")
    @classmethod
    def _compiles(cls, value: str) -> str:
        try:
            re.compile(value)
        except re.error as exc:
            raise ValueError(f"invalid regular expression {value!r}: {exc}") from None
        return value


def assign_category(
    rules: Sequence[CategoryRule],
    *,
    name: str,
    path: str,
    default: str | None,
    hits: list[int] | None = None,
) -> str | None:
    """The category of an object by the first matching rule, else ``default``.

    Parameters
    ----------
    rules : sequence of CategoryRule
        Tried in order.
    name, path : str
        The object's prim (or node) name and full path.
    default : str or None
        What an object no rule matches gets (None: not an annotated object).
    hits : list of int, optional
        One counter per rule: the matching rule's is incremented (to tell rules that match nothing:
        :func:`unmatched_rules`).

    Returns
    -------
    str or None
        The category, or None when the object is not annotated.
    """
    for index, rule in enumerate(rules):
        if re.search(rule.pattern, name if rule.on == "name" else path):
            if hits is not None:
                hits[index] += 1
            return rule.category
    return default


def unmatched_rules(rules: Sequence[CategoryRule], hits: Sequence[int]) -> list[str]:
    """A warning for every rule that matched no object (by the counters of :func:`assign_category`)."""
    return [
        f"category rule {rule.pattern!r} (on {rule.on}, category {rule.category!r}) matches no object: "
        "check its pattern against the objects' prim names (`navverse show scene`), or remove it"
        for rule, count in zip(rules, hits, strict=True)
        if count == 0
    ]


def category_name(text: str) -> str:
    """A lower_snake_case category from free text (``"Office Chair"`` -> ``"office_chair"``)."""
    name = re.sub(r"[^a-z0-9]+", "_", text.lower()).strip("_")
    if not name or not name[0].isalpha():
        name = f"c_{name}" if name else "object"
    return name
