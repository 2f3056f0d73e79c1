"""Synthetic cities: a seed and a few parameters give a city map, the same records as a real one.

The street network is a grid over the window: lines every ``block`` meters (jittered by the seed),
every ``arterial_every``-th one an arterial (``secondary``, more lanes, wider sidewalks), the others
residential streets. Each block is a park, a plaza, or built up: buildings stand along its edges,
set back from the sidewalk, with frontages, depths and storeys drawn from the seed. Crossings sit on
every arm of every junction, a little way from it. Everything is drawn from one
``numpy.random.Generator`` seeded by ``seed`` in a fixed order, so the same parameters and seed give
the same map.
"""

from __future__ import annotations

import itertools
from typing import Annotated

import numpy as np
from pydantic import BaseModel, ConfigDict, Field
from shapely.geometry import Polygon, box

from navverse.city.map import Building, CityMap, Crossing, Frame, LandArea, Path2, Polygon2, Road, Source
from navverse.city.tags import ROAD_CLASSES, STOREY_HEIGHT

__all__ = ["SyntheticCityParams", "synthetic_city"]


class SyntheticCityParams(BaseModel):
    """Knobs of a synthetic grid city (lengths in m)."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    size: tuple[Annotated[float, Field(ge=50.0, le=5000.0)], Annotated[float, Field(ge=50.0, le=5000.0)]] = (
        1000.0,
        1000.0,
    )
    block: tuple[Annotated[float, Field(ge=30.0, le=500.0)], Annotated[float, Field(ge=30.0, le=500.0)]] = (
        90.0,
        70.0,
    )
    jitter: Annotated[float, Field(ge=0.0, le=0.3)] = 0.1
    """Spread of the street spacing, as a share of the block size."""
    arterial_every: Annotated[int, Field(ge=2, le=50)] = 4
    arterial_lanes: Annotated[int, Field(ge=2, le=8)] = 4
    sidewalk: Annotated[float, Field(gt=0.0, le=6.0)] = 1.8
    arterial_sidewalk: Annotated[float, Field(gt=0.0, le=8.0)] = 3.0
    park_share: Annotated[float, Field(ge=0.0, le=1.0)] = 0.08
    plaza_share: Annotated[float, Field(ge=0.0, le=1.0)] = 0.03
    setback: Annotated[float, Field(ge=0.0, le=20.0)] = 1.0
    frontage: tuple[Annotated[float, Field(ge=4.0, le=200.0)], Annotated[float, Field(ge=4.0, le=200.0)]] = (
        14.0,
        32.0,
    )
    depth: tuple[Annotated[float, Field(ge=4.0, le=200.0)], Annotated[float, Field(ge=4.0, le=200.0)]] = (
        10.0,
        18.0,
    )
    storeys: tuple[Annotated[int, Field(ge=1, le=100)], Annotated[int, Field(ge=1, le=100)]] = (2, 8)
    gap: Annotated[float, Field(ge=0.0, le=50.0)] = 3.0
    """Mean gap between neighbouring buildings along a block edge."""
    crossing_offset: Annotated[float, Field(ge=0.0, le=30.0)] = 3.0
    """Distance of a crossing's centre from the edge of the junction it serves."""


def _lines(rng: np.random.Generator, start: float, end: float, spacing: float, jitter: float) -> list[float]:
    """Street positions from ``start`` to ``end``, ``spacing`` apart on average."""
    positions = [start]
    while positions[-1] + spacing * (1.0 + jitter) < end:
        positions.append(positions[-1] + spacing * (1.0 + jitter * float(rng.uniform(-1.0, 1.0))))
    return positions


def _road(index: int, points: list[tuple[float, float]], arterial: bool, params: SyntheticCityParams) -> Road:
    highway = "secondary" if arterial else "residential"
    kind = ROAD_CLASSES[highway]
    lanes = params.arterial_lanes if arterial else 2
    side = params.arterial_sidewalk if arterial else params.sidewalk
    return Road(
        id=f"road-{index}",
        highway=highway,
        centerline=Path2(points=points),
        width=lanes * kind.lane_width,
        width_source="synthetic",
        lanes=lanes,
        sidewalk_left=side,
        sidewalk_right=side,
        sidewalk_source="synthetic",
        kerb="raised",
    )


def _edge_buildings(
    rng: np.random.Generator, lot: Polygon, params: SyntheticCityParams, first_id: int
) -> list[Building]:
    """Buildings along the four edges of a block's buildable ``lot``, never overlapping."""
    min_x, min_y, max_x, max_y = lot.bounds
    placed: list[Polygon] = []
    buildings: list[Building] = []
    # Each edge: its start, direction along it, and the inward direction (counter-clockwise walk).
    edges = [
        ((min_x, min_y), (1.0, 0.0), (0.0, 1.0), max_x - min_x),
        ((max_x, min_y), (0.0, 1.0), (-1.0, 0.0), max_y - min_y),
        ((max_x, max_y), (-1.0, 0.0), (0.0, -1.0), max_x - min_x),
        ((min_x, max_y), (0.0, -1.0), (1.0, 0.0), max_y - min_y),
    ]
    half_span = min(max_x - min_x, max_y - min_y) / 2.0
    for (x0, y0), (ax, ay), (nx, ny), length in edges:
        at = float(rng.uniform(0.0, params.gap))
        while True:
            frontage = float(rng.uniform(*sorted(params.frontage)))
            depth = min(float(rng.uniform(*sorted(params.depth))), half_span)
            if at + frontage > length or depth < 4.0:
                break
            corners = [
                (x0 + ax * (at + da) + nx * dn, y0 + ay * (at + da) + ny * dn)
                for da, dn in ((0.0, 0.0), (frontage, 0.0), (frontage, depth), (0.0, depth))
            ]
            footprint = Polygon(corners)
            if not any(footprint.intersects(other) for other in placed):
                placed.append(footprint)
                storeys = int(rng.integers(params.storeys[0], max(params.storeys) + 1))
                buildings.append(
                    Building(
                        id=f"building-{first_id + len(buildings)}",
                        footprint=Polygon2(exterior=[(round(x, 3), round(y, 3)) for x, y in corners]),
                        height=storeys * STOREY_HEIGHT,
                        height_source="synthetic",
                        levels=storeys,
                    )
                )
            at += frontage + float(rng.exponential(params.gap)) if params.gap > 0 else frontage
    return buildings


def synthetic_city(params: SyntheticCityParams, *, seed: int) -> CityMap:
    """A grid city drawn from ``seed`` (see the module docstring)."""
    rng = np.random.default_rng([seed, 0x5C17])
    width, height = params.size
    window = (-width / 2.0, -height / 2.0, width / 2.0, height / 2.0)
    xs = _lines(rng, window[0] + params.block[0] / 2.0, window[2], params.block[0], params.jitter)
    ys = _lines(rng, window[1] + params.block[1] / 2.0, window[3], params.block[1], params.jitter)
    roads: list[Road] = []
    for i, x in enumerate(xs):
        roads.append(
            _road(len(roads) + 1, [(x, window[1]), (x, window[3])], i % params.arterial_every == 0, params)
        )
    vertical = list(roads)
    for j, y in enumerate(ys):
        roads.append(
            _road(len(roads) + 1, [(window[0], y), (window[2], y)], j % params.arterial_every == 0, params)
        )
    horizontal = roads[len(vertical) :]
    crossings: list[Crossing] = []
    for v in vertical:
        for h in horizontal:
            x, y = v.centerline.points[0][0], h.centerline.points[0][1]
            reach_v = h.width / 2.0 + (h.sidewalk_left or 0.0) + params.crossing_offset + 2.0
            reach_h = v.width / 2.0 + (v.sidewalk_left or 0.0) + params.crossing_offset + 2.0
            for road, (px, py) in (
                (v, (x, y - reach_v)),
                (v, (x, y + reach_v)),
                (h, (x - reach_h, y)),
                (h, (x + reach_h, y)),
            ):
                if window[0] < px < window[2] and window[1] < py < window[3]:
                    crossings.append(
                        Crossing(id=f"crossing-{len(crossings) + 1}", position=(px, py), road=road.id)
                    )
    areas: list[LandArea] = []
    buildings: list[Building] = []
    for left, right in itertools.pairwise(vertical):
        for bottom, top in itertools.pairwise(horizontal):
            margin_l = left.width / 2.0 + (left.sidewalk_right or 0.0)
            margin_r = right.width / 2.0 + (right.sidewalk_left or 0.0)
            margin_b = bottom.width / 2.0 + (bottom.sidewalk_left or 0.0)
            margin_t = top.width / 2.0 + (top.sidewalk_right or 0.0)
            x0 = left.centerline.points[0][0] + margin_l
            x1 = right.centerline.points[0][0] - margin_r
            y0 = bottom.centerline.points[0][1] + margin_b
            y1 = top.centerline.points[0][1] - margin_t
            if x1 - x0 < 8.0 or y1 - y0 < 8.0:
                continue
            draw = float(rng.uniform())
            block_ring = [
                (round(x0, 3), round(y0, 3)),
                (round(x1, 3), round(y0, 3)),
                (round(x1, 3), round(y1, 3)),
            ]
            block_ring.append((round(x0, 3), round(y1, 3)))
            if draw < params.park_share:
                areas.append(
                    LandArea(id=f"area-{len(areas) + 1}", cls="green", polygon=Polygon2(exterior=block_ring))
                )
                continue
            if draw < params.park_share + params.plaza_share:
                areas.append(
                    LandArea(id=f"area-{len(areas) + 1}", cls="plaza", polygon=Polygon2(exterior=block_ring))
                )
                continue
            lot = box(x0, y0, x1, y1).buffer(-params.setback, join_style="mitre")
            if lot.is_empty:
                continue
            buildings += _edge_buildings(rng, lot, params, len(buildings) + 1)
    return CityMap(
        source=Source(kind="synthetic", name="grid", seed=seed),
        frame=Frame(epsg=0, origin_lat=0.0, origin_lon=0.0),
        window=window,
        roads=roads,
        crossings=crossings,
        areas=areas,
        buildings=buildings,
    )
