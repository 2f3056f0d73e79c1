"""One profile per scene type, read by every module that decides by scene type."""

from __future__ import annotations

import typing

import pytest

from navverse import nav
from navverse.dataset import success_distance
from navverse.scene.annotations import SceneAnnotations
from navverse.scene_types import PROFILES, SCENE_TYPES, UnknownSceneTypeError, scene_profile
from navverse.sim.actions import step_size


def test_every_scene_type_of_the_contract_has_a_profile():
    declared = typing.get_args(SceneAnnotations.model_fields["scene_type"].annotation)
    assert SCENE_TYPES == declared == ("indoor", "outdoor", "i2o")
    for name, profile in PROFILES.items():
        assert profile.name == name
        assert profile.navmesh_preset in nav.PRESETS, name


def test_unknown_scene_type_names_the_known_ones():
    with pytest.raises(
        UnknownSceneTypeError, match="unknown scene type 'attic'; expected one of indoor, outdoor, i2o"
    ):
        scene_profile("attic")


def test_indoor_to_outdoor_scenes_have_their_own_profile():
    i2o, outdoor, indoor = PROFILES["i2o"], PROFILES["outdoor"], PROFILES["indoor"]
    assert i2o.navmesh_preset == "i2o" and i2o.fine_margin_m and i2o.fine_margin_m > 0
    fine = nav.PRESETS[i2o.navmesh_preset]
    assert fine.cell_size / fine.fine_factor == pytest.approx(
        nav.INDOOR.cell_size
    )  # indoor cells near buildings
    assert fine.agent_max_climb == nav.OUTDOOR.agent_max_climb  # outdoor curbs elsewhere
    assert i2o.start_region == "indoor" and i2o.transition_metrics
    assert not outdoor.transition_metrics and outdoor.start_region == "anywhere"
    assert indoor.field_cell_m < outdoor.field_cell_m


@pytest.mark.parametrize("scene_type", SCENE_TYPES)
def test_modules_read_the_profile(scene_type: str):
    profile = scene_profile(scene_type)
    assert step_size(scene_type) == profile.discrete_step_m
    assert success_distance(0.6, scene_type=scene_type) == pytest.approx(profile.success_margin_m + 0.6)
