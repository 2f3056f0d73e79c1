"""The street plan saved beside a city scene reads back as the plan the scene was built from."""

from __future__ import annotations

from pathlib import Path

import pytest

from navverse.city.geometry.scene import CityGeometry, geometry_plan
from navverse.city.geometry.street_plan import load_street_plan, save_street_plan
from navverse.city.geometry.surfaces import SURFACE_CLASSES
from navverse.city.osm.reader import read_osm
from navverse.errors import NavverseError

T_JUNCTION = Path(__file__).parent / "data" / "t_junction.osm"


@pytest.fixture(scope="module")
def city():
    return read_osm(T_JUNCTION, center=(48.0, 11.0), size_m=(200.0, 200.0))


def test_the_plan_round_trips_with_its_crossings(city, tmp_path: Path) -> None:
    plan = geometry_plan(city, CityGeometry(junction_crosswalks=True))
    assert len(plan.crossings) > len(city.crossings)  # the junction's arms got crosswalks
    save_street_plan(plan, tmp_path / "street_plan.json")
    again = load_street_plan(tmp_path / "street_plan.json")
    assert again.crossings == plan.crossings
    for cls in SURFACE_CLASSES:
        assert again.classes[cls].equals_exact(plan.classes[cls], tolerance=0.0), cls
    assert again.classes["sidewalk"].area > 0 and again.classes["crosswalk"].area > 0
    save_street_plan(again, tmp_path / "again.json")
    assert (tmp_path / "again.json").read_bytes() == (tmp_path / "street_plan.json").read_bytes()


def test_a_missing_or_broken_plan_says_how_to_rebuild(tmp_path: Path) -> None:
    with pytest.raises(NavverseError, match=r"is missing.*navverse build"):
        load_street_plan(tmp_path / "street_plan.json")
    (tmp_path / "street_plan.json").write_text('{"format_version": "1.0", "classes": {}}')
    with pytest.raises(NavverseError, match="not a readable street plan"):
        load_street_plan(tmp_path / "street_plan.json")
