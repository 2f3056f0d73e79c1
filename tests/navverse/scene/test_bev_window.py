"""A BEV window: the square around a point, resized, and world points placed on it."""

from __future__ import annotations

import numpy as np

from navverse.scene.bev import bev_window
from navverse.scene.geometry import Surface
from tests.scenes import quad, scene_of


def test_a_window_shows_the_square_around_its_centre_and_places_points() -> None:
    # a 40 m road square with a 4 m sidewalk patch in its north-east
    scene = scene_of(
        [
            Surface("road", "road", quad(-20, -20, 20, 20, 0.0)),
            Surface("walk", "sidewalk", quad(8, 8, 12, 12, 0.05)),
        ],
        scene_id="square",
        scene_type="outdoor",
    )
    window = bev_window(scene, (10.0, 10.0), 10.0, pixels=200)
    assert window.image.shape[1] == 200 and abs(window.image.shape[0] - 200) <= 2
    x, y = window.pixel((10.0, 10.0))
    assert abs(x - 100) <= 3 and abs(y - 100) <= 3  # the centre is in the middle
    x0, y0 = window.pixel((5.0, 15.0))  # the square's north-west corner: top left
    assert abs(x0) <= 3 and abs(y0) <= 3
    sidewalk = window.image[int(y), int(x)].astype(int)
    road = window.image[int(window.pixel((6.5, 6.5))[1]), int(window.pixel((6.5, 6.5))[0])].astype(int)
    assert np.abs(sidewalk - road).sum() > 60  # the patch shows in its own colour
