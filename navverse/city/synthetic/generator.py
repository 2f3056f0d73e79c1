"""Synthetic cities: a seed and a few parameters give a city map, the same records as a real one.

:func:`synthetic_city` draws, in this order:

1. a street network of the chosen ``layout`` (:mod:`.synthetic_streets`: ``grid``, ``radial`` rings
   and spokes, or ``organic``, an irregular bent lattice with dead ends), clipped to the window;
2. a river crossing the window (:mod:`.synthetic_land`): streets stop at its embankments but for up to
   ``bridges`` crossings; the network then keeps its largest connected part, so the streets form one
   network;
3. roads with classes, lanes, sidewalks and names, and crossings on every junction arm
   (:mod:`.synthetic_roads`);
4. blocks, the faces between the streets and the river, each a park (maybe with a pond), a plaza, a
   parking lot or built up with buildings along its edges (:mod:`.synthetic_blocks`), of storeys
   drawn higher on arterials;
5. places (shops, cafes, banks...) on ground floors (:mod:`.synthetic_pois`);
6. street furniture on the sidewalks (:mod:`.synthetic_furniture`).

Every draw comes from child generators spawned, one per step, from a single
``numpy.random.default_rng([seed, 0x5C17])``, and coordinates are rounded to the millimetre: the
same parameters and seed give the same map, byte for byte.
"""

from __future__ import annotations

import math

import numpy as np
import shapely

from navverse.city.map import Building, CityMap, Frame, LandArea, Polygon2, Source
from navverse.city.synthetic.blocks import FRONT_REACH, block_polygons, frontage_lots, polygon2, street_shapes
from navverse.city.synthetic.furniture import street_furniture
from navverse.city.synthetic.land import banks, block_uses, embankments, keepout, pond, river
from navverse.city.synthetic.params import Layout, SyntheticCityParams
from navverse.city.synthetic.pois import PoiDraft, ground_floor_pois
from navverse.city.synthetic.roads import crossings, junction_arms, rank_styles, road_records, street_styles
from navverse.city.synthetic.streets import (
    Network,
    Window,
    clip,
    cut_at_water,
    grid_network,
    main_component,
    merge_chains,
    organic_network,
    radial_network,
)
from navverse.city.tags import STOREY_HEIGHT

__all__ = ["Layout", "SyntheticCityParams", "synthetic_city"]

ARTERIALS = frozenset({"secondary", "tertiary"})


def _network(rng: np.random.Generator, window: Window, params: SyntheticCityParams) -> Network:
    if params.layout == "radial":
        return radial_network(
            rng, window, block=params.block, jitter=params.jitter, arterial_every=params.arterial_every
        )
    if params.layout == "organic":
        return organic_network(
            rng,
            window,
            block=params.block,
            node_jitter=params.node_jitter,
            removal=params.street_removal,
            dead_ends=params.dead_end_share,
            curviness=params.curviness,
            arterial_every=params.arterial_every,
        )
    return grid_network(
        rng, window, block=params.block, jitter=params.jitter, arterial_every=params.arterial_every
    )


def _river(
    rng: np.random.Generator, network: Network, window: Window, params: SyntheticCityParams
) -> tuple[shapely.Polygon, Network] | None:
    """The river and the network cut at it, drawing the river again (up to 6 times) while its
    bridges leave more than a tenth of the street length cut off from the main network; None
    without a river (``river_width`` 0, or no such river found)."""
    clearance = params.river_width / 2.0 + params.meander + 2.5 * max(params.block)
    halves = {rank: style.half for rank, style in rank_styles(params).items()}
    for _ in range(6):
        water = river(rng, window, params, avoid=network.squares, clearance=clearance)
        if water is None:
            return None
        cut, bridges = cut_at_water(
            network, rng, water, banks(water, halves, params), bridges=params.bridges, window=window
        )
        total = sum(piece.length for piece in cut.pieces)
        if bridges and sum(piece.length for piece in main_component(cut).pieces) >= 0.9 * total:
            return water, cut
    return None


def _storeys(rng: np.random.Generator, params: SyntheticCityParams, *, arterial: bool) -> int:
    """Storeys drawn from the range, skewed up on arterials and down on other streets."""
    low, high = sorted(params.storeys)
    draw = float(rng.uniform())
    draw = math.sqrt(draw) if arterial else draw**1.5
    return min(high, low + int(draw * (high - low + 1)))


def _area(areas: list[LandArea], cls: str, polygon: shapely.Polygon) -> None:
    shape = polygon2(polygon.simplify(0.05))
    if shape is not None:
        areas.append(LandArea(id=f"area-{len(areas) + 1}", cls=cls, polygon=shape))


def synthetic_city(params: SyntheticCityParams, *, seed: int) -> CityMap:
    """A city map drawn from ``seed`` (see the module docstring).

    Parameters
    ----------
    params : SyntheticCityParams
        The layout, sizes and shares.
    seed : int
        Seed of the random generator (``>= 0``).

    Returns
    -------
    CityMap
        The map, in a local frame centred on the window (EPSG 0, origin 0°, 0°).
    """
    root = np.random.default_rng([seed, 0x5C17])
    streets_rng, water_rng, style_rng, name_rng, land_rng, lots_rng, poi_rng, furniture_rng = root.spawn(8)
    half_x, half_y = round(params.size[0] / 2.0, 3), round(params.size[1] / 2.0, 3)
    window = (-half_x, -half_y, half_x, half_y)
    network = clip(_network(streets_rng, window, params), window)
    styles = street_styles(style_rng, network, params)
    river_and_network = _river(water_rng, network, window, params)
    water = None
    if river_and_network is not None:
        water, network = river_and_network
    network = merge_chains(main_component(network))
    roads = road_records(name_rng, network, styles)
    arms = junction_arms(roads, network, offset=params.crossing_offset)
    shapes = street_shapes(roads)
    streets = shapely.union_all(shapes)

    areas: list[LandArea] = []
    if water is not None:
        _area(areas, "water", water)
        for strip in embankments(water, params, streets, window):
            _area(areas, "green", strip)
    blocks = block_polygons(window, streets, keepout(water, params), smallest=30.0)
    lots = []
    for block, use in zip(blocks, block_uses(land_rng, blocks, params, network.squares), strict=True):
        if use == "park":
            lake = pond(land_rng, block, params)
            if lake is not None:
                _area(areas, "green", shapely.Polygon(block.exterior, [lake.exterior]))
                _area(areas, "water", lake)
            else:
                _area(areas, "green", block)
        elif use in ("plaza", "parking"):
            _area(areas, use, block)
        else:
            lots += frontage_lots(lots_rng, block, params)

    # Buildings: storeys by the street each one faces.
    arterial, on_street = [False] * len(lots), [False] * len(lots)
    if lots and roads:
        fronts = shapely.points(
            [((a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0) for a, b in (lot.front for lot in lots)]
        )
        tree = shapely.STRtree([shapely.linestrings(road.centerline.points) for road in roads])
        arterial = [
            roads[int(k)].highway in ARTERIALS for k in tree.query_nearest(fronts, all_matches=False)[1]
        ]
        on_street = [False] * len(lots)
        near = shapely.STRtree(shapes).query(
            fronts, predicate="dwithin", distance=params.setback + FRONT_REACH
        )
        for k in near[0]:
            on_street[int(k)] = True
    drafts = [
        PoiDraft(f"building-{n}", lot.front, bool(street), on_arterial)
        for n, (lot, street, on_arterial) in enumerate(zip(lots, on_street, arterial, strict=True), start=1)
    ]
    pois, entrances = ground_floor_pois(
        poi_rng, drafts, share=params.poi_share, arterial_share=params.arterial_poi_share
    )
    buildings = []
    for draft, lot, on_arterial in zip(drafts, lots, arterial, strict=True):
        storeys = _storeys(lots_rng, params, arterial=on_arterial)
        buildings.append(
            Building(
                id=draft.building,
                footprint=Polygon2(exterior=[(round(x, 3) + 0.0, round(y, 3) + 0.0) for x, y in lot.corners]),
                height=storeys * STOREY_HEIGHT,
                height_source="synthetic",
                levels=storeys,
                entrances=entrances.get(draft.building, []),
            )
        )
    return CityMap(
        source=Source(kind="synthetic", name=params.layout, seed=seed),
        frame=Frame(epsg=0, origin_lat=0.0, origin_lon=0.0),
        window=window,
        roads=roads,
        crossings=crossings(roads, arms, window),
        areas=areas,
        buildings=buildings,
        pois=pois,
        furniture=street_furniture(furniture_rng, roads, arms, water, window, params),
    )
