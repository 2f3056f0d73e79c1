"""The Python API's in-process generation: a building and a synthetic city from a seed and parameters,
without the engine or any file; the same arguments give the same result; bad arguments say what to
change."""

from __future__ import annotations

import numpy as np
import pytest

import navverse.api as nv
from navverse.indoor.programs import PROGRAMS


def test_a_building_is_generated_in_process_and_the_same_seed_gives_the_same_one() -> None:
    cafe = nv.generate_building("cafe", seed=3, length=14.0)
    again = nv.generate_building("cafe", seed=3, length=14.0)
    other = nv.generate_building("cafe", seed=4, length=14.0)
    ann = cafe.annotations
    assert ann.scene_type == "indoor" and ann.scene_id == "cafe-s3" and ann.rooms and ann.objects
    (building,) = ann.buildings
    assert building.exits
    assert [o.center for o in again.annotations.objects] == [o.center for o in ann.objects]
    assert [o.center for o in other.annotations.objects] != [o.center for o in ann.objects]


def test_bad_building_arguments_name_what_is_known() -> None:
    with pytest.raises(
        nv.ApiError, match="unknown building type 'castle'; choose from: " + ", ".join(PROGRAMS)
    ):
        nv.generate_building("castle")
    with pytest.raises(nv.ApiError, match="the building options are: length, depth"):
        nv.generate_building("cafe", floors=3)


def test_a_synthetic_city_is_generated_in_process() -> None:
    town = nv.generate_city(seed=2, size=(200.0, 200.0))
    assert town.map.roads and town.map.buildings and town.scene.annotations.scene_type == "outdoor"
    assert len(town.scene.annotations.buildings) == len(town.map.buildings)
    again = nv.generate_city(seed=2, size=(200.0, 200.0))
    assert again.map == town.map
    with pytest.raises(nv.ApiError, match="synthetic city parameters"):
        nv.generate_city(seed=2, size=(-5.0, 200.0))


def test_a_synthetic_city_on_hills_is_generated_in_process() -> None:
    def heights(town) -> np.ndarray:
        sidewalk = next(s for s in town.scene.surfaces if s.terrain_class == "sidewalk")
        return sidewalk.mesh.vertices[:, 2]

    flat = heights(nv.generate_city(seed=2, size=(200.0, 200.0)))
    hilly = heights(nv.generate_city(seed=2, size=(200.0, 200.0), geometry={"relief_height": 8.0}))
    assert abs(flat.max()) < 0.01 and np.ptp(hilly) > np.ptp(flat) + 3.0  # the walls reach 1 m below
    with pytest.raises(nv.ApiError, match="city geometry parameters"):
        nv.generate_city(seed=2, size=(200.0, 200.0), geometry={"relief_height": -1.0})
