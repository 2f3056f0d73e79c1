"""The text-matching step: the category an instruction names (the frontier agent's VLN and PlaceNav goal)."""

from __future__ import annotations

from navverse.eval.agents.goal_text import named_goal_category

PLACES = ["bank", "bar", "cafe", "fast_food", "restaurant", "pharmacy"]


def test_the_category_named_last_is_the_goal():
    text = "Walk past the sofa, turn left at the tv and stop by the office chair."
    assert named_goal_category(text, ["sofa", "tv", "office_chair", "chair"]) == "office_chair"
    assert named_goal_category("Go to the bookshelf, not the sofa.", ["sofa", "bookshelf"]) == "sofa"


def test_places_are_named_by_their_human_names_and_plurals_count():
    assert named_goal_category("Follow the street to the fast-food restaurant.", PLACES) == "fast_food"
    assert named_goal_category("Find a restaurant.", PLACES) == "restaurant"
    assert named_goal_category("Pass two cafes, then the pharmacy on your right.", PLACES) == "pharmacy"
    assert named_goal_category("Walk past the cafes.", PLACES) == "cafe"


def test_a_name_inside_another_word_is_not_a_mention():
    assert named_goal_category("Ask the barber about the barbecue.", PLACES) == ""
    assert named_goal_category("The embankment is on your left.", PLACES) == ""


def test_an_intention_or_an_unknown_name_finds_nothing():
    assert named_goal_category("I need to withdraw some cash.", PLACES) == ""
    assert named_goal_category("Stop at the bank.", ["cafe"]) == ""
    assert named_goal_category("", PLACES) == ""
