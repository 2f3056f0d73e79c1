"""The growing grid index finds what an exhaustive search finds, each shape once, in the order added."""

from __future__ import annotations

import numpy as np
from shapely.geometry import Point, Polygon, box

from navverse.city.shape_grid import ShapeGrid


def test_queries_match_a_search_over_every_shape() -> None:
    rng = np.random.default_rng(3)
    grid = ShapeGrid(4.0)
    shapes = []
    for x, y, w, h in rng.uniform((-50, -50, 0.2, 0.2), (50, 50, 12.0, 3.0), size=(300, 4)):
        shape = box(x, y, x + w, y + h)
        grid.add(shape)
        shapes.append(shape)
    for x, y, r in rng.uniform((-60, -60, 0.1), (60, 60, 6.0), size=(200, 3)):
        probe = Point(x, y).buffer(r, quad_segs=4)
        assert grid.near(probe, 1.5) == any(probe.distance(s) < 1.5 for s in shapes)
        expected = [s for s in shapes if s.envelope.intersects(probe.envelope)]
        assert grid.meeting(probe) == expected  # in the order added, no repeats
    assert grid.meeting(Polygon()) == [] and grid.candidates(Polygon()) == []
