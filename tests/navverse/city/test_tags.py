"""OSM tag reading: lengths with units, counts, road widths, sidewalks, building heights."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from navverse.city.tags import (
    CYCLE_LANE_WIDTH,
    CYCLE_TRACK_WIDTH,
    DEFAULT_SIDEWALK_WIDTH,
    MAX_LENGTH,
    PASSAGE_CLEARANCE,
    ROAD_CLASSES,
    STOREY_HEIGHT,
    at_ground_level,
    building_height,
    cycle_tracks,
    is_passage,
    parse_count,
    parse_length,
    passage_clearance,
    road_width,
    sidewalks,
)


@pytest.mark.parametrize(
    ("text", "meters"),
    [
        ("3", 3.0),
        ("3.5", 3.5),
        ("3,5", 3.5),
        ("3 m", 3.0),
        ("3m", 3.0),
        ("3.5 metres", 3.5),
        ("350 cm", 3.5),
        ("12'", 12 * 0.3048),
        ("12 ft", 12 * 0.3048),
        ("12'6\"", 12 * 0.3048 + 6 * 0.0254),
        ("12' 6\"", 12 * 0.3048 + 6 * 0.0254),
        ("~4", 4.0),
        ("5;6", 5.0),
        (" 7 ", 7.0),
    ],
)
def test_lengths_are_read_in_meters(text: str, meters: float):
    assert parse_length(text).value == pytest.approx(meters, abs=1e-9)


@pytest.mark.parametrize(
    ("text", "problem"),
    [
        ("variable", "is not a length"),
        ("unknown", "is not a length"),
        ("wide", "is not a length"),
        ("3 parsecs", "is not a length"),
        ("-3", "is not a length"),
        ("0", "not a positive length"),
        ("nan", "is not a length"),
        ("inf", "is not a length"),
        ("1e9", "is not a length"),
        ("20000", f"longer than {MAX_LENGTH:g} m"),
        ("", "empty value"),
    ],
)
def test_unusable_lengths_give_no_value_and_say_why(text: str, problem: str):
    reading = parse_length(text)
    assert reading.value is None and problem in reading.problem


def test_several_values_take_the_first_and_say_so():
    reading = parse_length("5;6")
    assert reading.value == 5.0 and reading.problem == "several values; the first is used"
    assert parse_count("2;3").value == 2.0


@given(st.text(max_size=40))
def test_any_text_reads_as_a_positive_finite_length_or_none(text: str):
    reading = parse_length(text)
    assert reading.value is None or (math.isfinite(reading.value) and 0 < reading.value <= MAX_LENGTH)
    assert reading.value is not None or reading.problem is not None
    count = parse_count(text, integer=False)
    assert count.value is None or (math.isfinite(count.value) and 0 <= count.value <= 1000)


def test_width_tag_wins_then_lanes_then_the_class_default():
    assert road_width({"highway": "residential", "width": "7.2 m", "lanes": "4"})[:2] == (7.2, "width")
    lanes_width = 3 * ROAD_CLASSES["primary"].lane_width
    assert road_width({"highway": "primary", "lanes": "3"})[:2] == (lanes_width, "lanes")
    assert road_width({"highway": "secondary"})[:2] == (ROAD_CLASSES["secondary"].width, "default")
    assert road_width({"highway": "no_such_class"})[:2] == (ROAD_CLASSES["road"].width, "default")


def test_service_kinds_and_cycle_lanes_set_untagged_widths():
    assert road_width({"highway": "service", "service": "parking_aisle"})[:2] == (5.5, "default")
    assert road_width({"highway": "service", "service": "driveway"})[:2] == (3.0, "default")
    assert road_width({"highway": "service"})[:2] == (ROAD_CLASSES["service"].width, "default")
    residential = ROAD_CLASSES["residential"].width
    assert road_width({"highway": "residential", "cycleway": "lane"})[0] == residential + 2 * CYCLE_LANE_WIDTH
    primary = ROAD_CLASSES["primary"].lane_width
    tags = {"highway": "primary", "lanes": "2", "cycleway:right": "lane"}
    assert road_width(tags)[:2] == (2 * primary + CYCLE_LANE_WIDTH, "lanes")
    assert road_width({"highway": "primary", "width": "9", "cycleway": "lane"})[0] == 9.0  # the tag says all
    assert road_width({"highway": "residential", "cycleway": "track"})[0] == residential  # not in the road


def test_a_one_way_road_without_lanes_is_narrower():
    width, source, _ = road_width({"highway": "residential", "oneway": "yes"})
    kind = ROAD_CLASSES["residential"]
    assert source == "default one-way" and width == max(kind.lane_width, kind.width / 2)


def test_a_bad_width_falls_back_and_is_reported():
    width, source, problems = road_width({"highway": "tertiary", "width": "variable", "lanes": "two"})
    assert (width, source) == (ROAD_CLASSES["tertiary"].width, "default")
    assert problems == ["width: 'variable' is not a length", "lanes: 'two' is not a whole number"]


@pytest.mark.parametrize(
    ("tags", "left", "right", "source"),
    [
        ({"highway": "residential", "sidewalk": "both"}, 1.5, 1.5, "tags"),
        ({"highway": "residential", "sidewalk": "left"}, 1.5, None, "tags"),
        ({"highway": "residential", "sidewalk": "right"}, None, 1.5, "tags"),
        ({"highway": "residential", "sidewalk": "no"}, None, None, "tags"),
        ({"highway": "residential", "sidewalk": "separate"}, None, None, "tags"),
        ({"highway": "primary", "sidewalk:left": "yes", "sidewalk:right": "separate"}, 1.5, None, "tags"),
        ({"highway": "residential", "sidewalk:both": "yes", "sidewalk:both:width": "2.5"}, 2.5, 2.5, "tags"),
        ({"highway": "residential", "sidewalk": "both", "sidewalk:right:width": "3 m"}, 1.5, 3.0, "tags"),
        ({"highway": "residential"}, 1.5, 1.5, "rule"),
        ({"highway": "primary", "foot": "no"}, None, None, "rule"),
        ({"highway": "motorway"}, None, None, "rule"),
        ({"highway": "service"}, None, None, "rule"),
        ({"highway": "footway"}, None, None, "rule"),
        ({"highway": "residential", "junction": "roundabout"}, None, None, "rule"),
    ],
)
def test_sidewalks_follow_the_tags_then_the_class_rule(tags, left, right, source):
    sides = sidewalks(tags)
    assert (sides.left, sides.right, sides.source) == (left, right, source)
    assert DEFAULT_SIDEWALK_WIDTH == 1.5


def test_ways_below_ground_are_not_at_ground_level_but_building_passages_are():
    assert at_ground_level({"highway": "primary"})
    assert at_ground_level({"highway": "primary", "bridge": "yes", "layer": "1"})
    assert not at_ground_level({"highway": "primary", "tunnel": "yes"})
    assert not at_ground_level({"highway": "primary", "layer": "-1"})
    assert not at_ground_level({"highway": "footway", "level": "-1", "indoor": "yes"})
    assert at_ground_level({"highway": "primary", "tunnel": "no"})
    # Under a building or a roof at street level: mappers often add layer=-1 to a passage.
    for tags in ({"tunnel": "building_passage", "layer": "-1"}, {"covered": "yes"}, {"covered": "arcade"}):
        assert at_ground_level({"highway": "footway", **tags}) and is_passage(tags)
    assert not at_ground_level({"highway": "footway", "tunnel": "building_passage", "level": "-1"})
    assert not is_passage({"tunnel": "yes"}) and not is_passage({"covered": "no"})
    assert passage_clearance({"maxheight": "3.2"}) == 3.2
    assert passage_clearance({"maxheight": "none"}) == passage_clearance({}) == PASSAGE_CLEARANCE


def test_building_heights_from_height_then_levels():
    assert building_height({"building": "yes", "height": "12.5"})[:3] == (12.5, 0.0, "height")
    assert building_height({"building": "yes", "building:levels": "4"})[:3] == (
        4 * STOREY_HEIGHT,
        0.0,
        "levels",
    )
    with_roof = building_height({"building": "yes", "building:levels": "2", "roof:height": "2"})
    assert with_roof[0] == 2 * STOREY_HEIGHT + 2.0
    assert building_height({"building": "yes", "building:levels": "2", "roof:levels": "1"})[0] == 9.0
    assert building_height({"building": "yes", "height": "20", "building:levels": "2"})[2] == "height"
    assert building_height({"building": "yes"})[:3] == (None, 0.0, "untagged")


def test_building_parts_keep_their_base():
    height, base, _, problems = building_height({"building:part": "yes", "height": "30", "min_height": "10"})
    assert (height, base, problems) == (30.0, 10.0, [])
    height, base, _, _ = building_height(
        {"building:part": "yes", "building:levels": "5", "building:min_level": "2"}
    )
    assert (height, base) == (15.0, 6.0)
    height, base, _, problems = building_height({"building": "yes", "height": "5", "min_height": "8"})
    assert (height, base) == (5.0, 0.0) and "not above the base" in problems[0]


def test_cycle_tracks_by_side_and_width():
    assert cycle_tracks({"cycleway": "track"})[:2] == (CYCLE_TRACK_WIDTH, CYCLE_TRACK_WIDTH)
    assert cycle_tracks({"cycleway": "track", "oneway": "yes"})[:2] == (None, CYCLE_TRACK_WIDTH)
    assert cycle_tracks({"cycleway": "opposite_track", "oneway": "yes"})[:2] == (CYCLE_TRACK_WIDTH, None)
    assert cycle_tracks({"cycleway:both": "track", "cycleway:width": "2.2"})[:2] == (2.2, 2.2)
    assert cycle_tracks({"cycleway:left": "track", "cycleway:left:width": "1.2 m"})[:2] == (1.2, None)
    for tags in ({"cycleway": "lane"}, {"cycleway:right": "separate"}, {"cycleway": "no"}, {}):
        assert cycle_tracks(tags)[:2] == (None, None)
    left, right, problems = cycle_tracks({"cycleway:right": "track", "cycleway:right:width": "wide"})
    assert (left, right) == (None, CYCLE_TRACK_WIDTH) and problems[0].startswith(
        "cycleway:right:width: 'wide'"
    )
