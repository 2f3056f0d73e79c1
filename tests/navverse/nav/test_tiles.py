"""Incremental navmeshes: tiles reused from a store give the same bytes as a build from scratch.

An indoor-to-outdoor scene (a street with a building, its tiles fine) reuses the street's coarse
tiles and builds only those its building reaches; a city whose populate seed changed rebuilds only
the tiles its objects moved in; damaged store files and changed settings are never reused.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from navverse import nav
from navverse.nav.tiles import TileStore
from tests.navverse.nav import scenes

TILE = 32  # cells: 3.2 m tiles at the outdoor cell size
STREET = (0.0, 0.0, 40.0, 16.0)
BUILDING = (26.0, 9.0, 34.0, 15.0)  # x0, y0, x1, y1: the indoor part, in the street's north-east


def _street() -> scenes.MeshBuilder:
    """A 40 m x 16 m street: ground with a raised sidewalk strip and a few boxes (cars, a kiosk)."""
    x0, y0, x1, y1 = STREET
    b = scenes.MeshBuilder().floor(x0, y0, x1, y1)
    b.box((x0, y0, -0.1), (x1, y0 + 3.0, 0.15), scenes.ROUTE_B)  # a sidewalk with a 15 cm curb
    for bx, by in [(4.0, 5.0), (13.0, 6.0), (21.0, 4.5)]:
        b.box((bx, by, 0.0), (bx + 4.2, by + 1.8, 1.5), scenes.WALL)
    return b


def _with_building(b: scenes.MeshBuilder) -> scenes.MeshBuilder:
    """The street plus a walled building with a door and an inner wall (its floor 5 cm up)."""
    x0, y0, x1, y1 = BUILDING
    b.floor(x0, y0, x1, y1, z=0.05)
    b.box((x0 - 0.2, y0 - 0.2, 0), (x0 + 3.0, y0, 3.0), scenes.WALL)  # south wall, a door x0+3..x0+4.2
    b.box((x0 + 4.2, y0 - 0.2, 0), (x1 + 0.2, y0, 3.0), scenes.WALL)
    b.box((x0 - 0.2, y1, 0), (x1 + 0.2, y1 + 0.2, 3.0), scenes.WALL)
    b.box((x0 - 0.2, y0, 0), (x0, y1, 3.0), scenes.WALL)
    b.box((x1, y0, 0), (x1 + 0.2, y1, 3.0), scenes.WALL)
    return b.box((x0 + 5.0, y0 + 1.5, 0), (x0 + 5.2, y1, 3.0), scenes.WALL)


def _build(builder: scenes.MeshBuilder, settings: nav.NavMeshSettings, store: TileStore | None) -> bytes:
    vertices, faces, areas = builder.arrays()
    finder = nav.build(vertices, faces, settings, area_types=areas, jobs=2, tile_store=store)
    return finder.to_bytes()


OUTDOOR = nav.OUTDOOR.with_overrides({"tile_size": TILE})


def test_a_store_gives_the_bytes_of_a_full_build_and_reuses_every_tile_the_second_time(tmp_path: Path):
    store = TileStore(tmp_path / "tiles")
    full = _build(_street(), OUTDOOR, None)
    first = _build(_street(), OUTDOOR, store)
    assert first == full
    assert store.last_use.reused == 0 and store.last_use.built == store.last_use.tiles == 13 * 6
    second = _build(_street(), OUTDOOR, store)
    assert second == full
    assert store.last_use.reused == 13 * 6 and store.last_use.built == 0


def test_an_i2o_scene_reuses_the_street_tiles_its_building_does_not_reach(tmp_path: Path):
    store = TileStore(tmp_path / "tiles")
    _build(_street(), OUTDOOR, store)  # the city, built first (outdoor preset)
    margin = 1.0
    x0, y0, x1, y1 = BUILDING
    region = (x0 - margin, y0 - margin, x1 + margin, y1 + margin)
    i2o = nav.I2O.with_overrides({"tile_size": TILE, "fine_region": region})
    full = _build(_with_building(_street()), i2o, None)
    incremental = _build(_with_building(_street()), i2o, store)
    assert incremental == full
    use = store.last_use
    # The building with the tiles' 0.9 m borders spans 10.2 m x 8.2 m: at most 4 x 3 tiles of 3.2 m
    # (here it covers 4 x 3 of the 13 x 6); every other tile is the street's, taken from the store.
    assert use.tiles == 13 * 6
    assert 0 < use.built <= 4 * 3
    assert use.reused == use.tiles - use.built


def test_a_changed_populate_seed_rebuilds_only_the_tiles_its_objects_reach(tmp_path: Path):
    def populated(seed: int) -> scenes.MeshBuilder:
        rng = np.random.default_rng(seed)
        b = _street()
        for _ in range(3):  # objects on the sidewalk, where the seed puts them
            x = float(rng.uniform(2.0, 36.0))
            b.box((x, 0.8, 0.15), (x + 0.6, 1.4, 1.0), scenes.WALL)
        return b

    store = TileStore(tmp_path / "tiles")
    _build(populated(1), OUTDOOR, store)
    full = _build(populated(2), OUTDOOR, None)
    assert full != _build(populated(1), OUTDOOR, None)  # the seed moved something
    incremental = _build(populated(2), OUTDOOR, store)
    assert incremental == full
    assert 0 < store.last_use.built < 13 * 6 / 2
    assert store.last_use.reused == 13 * 6 - store.last_use.built


def test_damaged_store_files_are_built_again(tmp_path: Path):
    store = TileStore(tmp_path / "tiles")
    full = _build(_street(), OUTDOOR, store)
    files = sorted(store.root.rglob("*.tile"))
    assert len(files) == 13 * 6
    files[0].write_bytes(files[0].read_bytes()[:40])  # cut short
    damaged = bytearray(files[1].read_bytes())
    damaged[-1] ^= 0xFF  # one bit of data flipped
    files[1].write_bytes(bytes(damaged))
    files[2].write_bytes(b"")
    assert _build(_street(), OUTDOOR, store) == full
    assert store.last_use.built == 3 and store.last_use.reused == 13 * 6 - 3


@pytest.mark.parametrize(
    "change", [{"agent_radius": 0.4}, {"detail_sample_max_error": 0.0}, {"fill_solid_interiors": False}]
)
def test_tiles_are_not_reused_under_other_settings(tmp_path: Path, change: dict):
    store = TileStore(tmp_path / "tiles")
    _build(_street(), OUTDOOR, store)
    settings = OUTDOOR.with_overrides(change)
    assert _build(_street(), settings, store) == _build(_street(), settings, None)
    assert store.last_use.reused == 0


def test_an_unwritable_store_only_costs_time(tmp_path: Path):
    blocker = tmp_path / "not-a-folder"
    blocker.write_text("a file where the store's folder would be")
    store = TileStore(blocker / "tiles")
    assert _build(_street(), OUTDOOR, store) == _build(_street(), OUTDOOR, None)
    assert store.last_use.built == 13 * 6
