"""Category rules: first match wins, name or path, null drops, bad patterns are refused."""

from __future__ import annotations

import pytest
from pydantic import ValidationError

from navverse.scene.categories import CategoryRule, assign_category, category_name

RULES = [
    CategoryRule(pattern=r"^office_chair", category="chair"),
    CategoryRule(pattern=r"/Lanterns?/", on="path", category="lantern"),
    CategoryRule(pattern=r"^decor_"),
    CategoryRule(pattern=r"chair", category="seat"),
]


@pytest.mark.parametrize(
    ("name", "path", "expected"),
    [
        ("office_chair_0003", "/World/Objects/office_chair_0003", "chair"),  # first rule wins
        ("armchair_0001", "/World/Objects/armchair_0001", "seat"),
        ("stone_1", "/Scene/Lanterns/stone_1", "lantern"),  # matched on the path
        ("Lanterns", "/Scene/Other", "fallback"),  # the path rule does not look at the name
        ("decor_vase", "/x/decor_vase", None),  # category null: not annotated
        ("table_0001", "/World/Objects/table_0001", "fallback"),
    ],
)
def test_first_matching_rule_wins(name: str, path: str, expected: str | None):
    assert assign_category(RULES, name=name, path=path, default="fallback") == expected


def test_invalid_rules_are_refused():
    with pytest.raises(ValidationError, match="invalid regular expression"):
        CategoryRule(pattern="(unclosed", category="x")
    with pytest.raises(ValidationError):
        CategoryRule(pattern="x", category="Not Snake")
    with pytest.raises(ValidationError):
        CategoryRule(pattern="x", on="prim", category="x")


def test_category_names_from_free_text():
    assert category_name("Office Chair") == "office_chair"
    assert category_name("TV-stand #2") == "tv_stand_2"
    assert category_name("3d print") == "c_3d_print"
