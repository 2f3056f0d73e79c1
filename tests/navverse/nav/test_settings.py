"""Settings presets match the paper's table and the recipe presets."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml
from pydantic import ValidationError

from navverse import nav
from navverse.nav import NavMeshError, NavMeshSettings
from navverse.nav.settings import NavMeshOverrides

REPO = Path(__file__).resolve().parents[3]

# The paper's table tab:navmesh_params.
PAPER = {
    "indoor": {"cell_size": 0.05, "cell_height": 0.05, "agent_max_climb": 0.20},
    "outdoor": {"cell_size": 0.10, "cell_height": 0.10, "agent_max_climb": 0.30},
}
PAPER_COMMON = {
    "agent_height": 0.60,
    "agent_radius": 0.60,
    "agent_max_slope": 45.0,
    "region_min_size": 8.0,
    "region_merge_size": 0.0,
    "edge_max_error": 1.5,
    "edge_max_len": 0.0,
    "detail_sample_dist": 1.0,
    "detail_sample_max_error": 0.0,
    "verts_per_poly": 6,
}


# Where a preset departs from the table, and why (the presets' docstrings measure the effect): outdoor
# detail meshes may stray one cell height from the voxel heights instead of tracing their steps.
DEPARTURES = {"indoor": {}, "outdoor": {"detail_sample_max_error": 1.0}}


@pytest.mark.parametrize("name", ["indoor", "outdoor"])
def test_presets_match_the_paper(name: str):
    preset = NavMeshSettings.preset(name)
    assert preset is nav.PRESETS[name]
    for key, value in {**PAPER_COMMON, **PAPER[name], **DEPARTURES[name]}.items():
        assert getattr(preset, key) == value, key


@pytest.mark.parametrize("name", ["indoor", "outdoor"])
def test_recipe_presets_name_the_constants_and_repeat_no_setting(name: str):
    data = yaml.safe_load((REPO / "recipes" / "presets" / f"navmesh-{name}.yaml").read_text())
    assert list(data) == ["stages"] and list(data["stages"]) == ["navmesh"]
    assert data["stages"]["navmesh"]["preset"] == name
    assert "settings" not in data["stages"]["navmesh"]  # one source: navverse.nav.PRESETS


def test_i2o_preset_is_outdoor_with_indoor_cells_in_the_region():
    assert NavMeshSettings.preset("i2o") is nav.PRESETS["i2o"] is nav.I2O
    assert nav.I2O.model_dump(exclude={"fine_factor"}) == nav.OUTDOOR.model_dump(exclude={"fine_factor"})
    assert nav.I2O.fine_region is None  # set per scene
    assert nav.I2O.cell_size / nav.I2O.fine_factor == nav.INDOOR.cell_size
    assert nav.I2O.cell_height / nav.I2O.fine_factor == nav.INDOOR.cell_height


def test_defaults_are_the_indoor_preset():
    assert NavMeshSettings() == nav.INDOOR


def test_settings_are_strict_and_frozen():
    with pytest.raises(ValidationError):
        NavMeshSettings(voxel_size=0.1)
    with pytest.raises(ValidationError):
        NavMeshSettings(agent_max_slope=90)
    with pytest.raises(ValidationError, match="at least 3 cells"):
        NavMeshSettings(agent_height=0.1)
    with pytest.raises(ValidationError):
        nav.INDOOR.cell_size = 0.2  # type: ignore[misc]
    with pytest.raises(NavMeshError, match="unknown navmesh preset 'attic'"):
        NavMeshSettings.preset("attic")


def test_overrides_replace_single_fields():
    changed = nav.OUTDOOR.with_overrides(NavMeshOverrides(agent_radius=0.3, tile_size=0))
    assert changed.agent_radius == 0.3 and changed.tile_size == 0
    assert changed.cell_size == nav.OUTDOOR.cell_size  # untouched fields keep the preset's values
    assert nav.INDOOR.with_overrides(NavMeshOverrides()) == nav.INDOOR
    assert nav.INDOOR.with_overrides({"cell_height": 0.1}).cell_height == 0.1


def test_overrides_are_checked_alone_and_together():
    assert set(NavMeshOverrides.model_fields) == set(NavMeshSettings.model_fields)
    with pytest.raises(ValidationError, match=r"greater than or equal to 0\.01"):
        NavMeshOverrides(cell_size=0)
    with pytest.raises(ValidationError, match="Extra inputs"):
        NavMeshOverrides(voxel_size=0.1)
    # Valid alone, but 0.1 m of headroom is fewer than 3 cells of 0.05 m.
    with pytest.raises(NavMeshError, match=r"invalid navmesh settings: .*at least 3 cells"):
        nav.INDOOR.with_overrides(NavMeshOverrides(agent_height=0.1))
