"""Parameters of synthetic cities (:class:`SyntheticCityParams`): every knob bounded, lengths in m."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from navverse.settings import Settings

__all__ = ["Layout", "SyntheticCityParams"]

Layout = Literal["grid", "radial", "organic"]
"""Street network layouts: a jittered grid, rings and spokes, an irregular bent lattice."""

_Side = Annotated[float, Field(ge=50.0, le=5000.0)]
_Block = Annotated[float, Field(ge=30.0, le=500.0)]
_Span = Annotated[float, Field(ge=4.0, le=200.0)]
_Share = Annotated[float, Field(ge=0.0, le=1.0)]


class SyntheticCityParams(Settings):
    """Knobs of a synthetic city (lengths in m, shares in [0, 1]).

    The defaults give a dense European-style city: a 1 km × 1 km window holds about 36–40 km of
    street centre line and 600–900 buildings in every layout.
    """

    layout: Layout = "grid"
    """Street network: ``grid``, ``radial`` (rings and spokes) or ``organic`` (bent, thinned lattice)."""
    size: tuple[_Side, _Side] = (1000.0, 1000.0)
    """Width (x) and height (y) of the window, centred on the origin (m)."""
    block: tuple[_Block, _Block] = (60.0, 44.0)
    """Street spacing (m): along x and y (grid, organic lattice), or along the rings and between rings
    (radial)."""
    jitter: Annotated[float, Field(ge=0.0, le=0.3)] = 0.1
    """Grid and radial layouts: each street spacing (grid lines, radial rings) is ``block`` × (1 ± up to
    ``jitter``); spoke angles vary as much."""
    arterial_every: Annotated[int, Field(ge=2, le=50)] = 4
    """Every n-th street (grid line, lattice row, ring) is an arterial, alternately ``secondary`` and
    ``tertiary``; the radial layout's first spokes are ``secondary``."""
    arterial_lanes: Annotated[int, Field(ge=2, le=8)] = 4
    """Lanes of a ``secondary`` street (its carriageway width is lanes × the class's lane width)."""
    collector_lanes: Annotated[int, Field(ge=2, le=6)] = 3
    """Lanes of a ``tertiary`` street."""
    sidewalk: Annotated[float, Field(gt=0.0, le=6.0)] = 1.8
    """Sidewalk width of residential streets, on each side (m)."""
    arterial_sidewalk: Annotated[float, Field(gt=0.0, le=8.0)] = 3.0
    """Sidewalk width of ``secondary`` streets, on each side (m)."""
    collector_sidewalk: Annotated[float, Field(gt=0.0, le=8.0)] = 2.5
    """Sidewalk width of ``tertiary`` streets, on each side (m)."""
    living_street_share: _Share = 0.0
    """Share of residential streets (not dead ends) built as ``living_street`` (shared surface, no
    sidewalks)."""
    service_share: _Share = 0.0
    """Share of residential dead ends (organic layout) built as ``service`` roads without sidewalks."""
    node_jitter: Annotated[float, Field(ge=0.0, le=0.24)] = 0.18
    """Organic layout: junction displacement, as a share of ``block`` each way (under a quarter, so
    streets cannot cross)."""
    street_removal: Annotated[float, Field(ge=0.0, le=0.6)] = 0.1
    """Organic layout: share of residential lattice edges outside a spanning tree that are removed."""
    dead_end_share: _Share = 0.6
    """Organic layout: share of removed edges that keep a dead-end stub (35–60 % of the edge, from one
    end)."""
    curviness: Annotated[float, Field(ge=0.0, le=60.0)] = 25.0
    """Organic layout: amplitude of each of the three smooth displacement waves that bend the streets
    (m)."""
    river_width: Annotated[float, Field(ge=0.0, le=200.0)] = 24.0
    """Width of the river crossing the window (m); 0 for none."""
    meander: Annotated[float, Field(ge=0.0, le=100.0)] = 40.0
    """Scale of the river's bends (m): its centre line swings by a long sine wave of 0.6–1 × ``meander``
    amplitude and a shorter one of 0.1–0.25 ×."""
    bridges: Annotated[int, Field(ge=1, le=6)] = 2
    """Streets that cross the river (at most; the others stop at its embankment)."""
    embankment: Annotated[float, Field(ge=0.0, le=30.0)] = 6.0
    """Width of the green strip along each river bank (m); 0 for none."""
    park_share: _Share = 0.08
    """Share of blocks that are parks."""
    pond_share: _Share = 0.5
    """Share of parks with a pond."""
    pond_size: Annotated[float, Field(ge=0.05, le=0.6)] = 0.3
    """Largest share of a park's area its pond takes (a pond is drawn at 50–100 % of that)."""
    plaza_share: _Share = 0.03
    """Share of blocks that are paved squares (plazas); the radial layout's central block is one too
    (unless the river takes its ring)."""
    parking_share: _Share = 0.04
    """Share of blocks that are parking lots."""
    setback: Annotated[float, Field(ge=0.0, le=20.0)] = 1.0
    """Distance from the sidewalk's outer edge to the building fronts (m)."""
    frontage: tuple[_Span, _Span] = (18.0, 45.0)
    """Range of building widths along the street (m), drawn uniformly."""
    depth: tuple[_Span, _Span] = (10.0, 18.0)
    """Range of building depths away from the street (m), drawn uniformly."""
    storeys: tuple[Annotated[int, Field(ge=1, le=100)], Annotated[int, Field(ge=1, le=100)]] = (2, 8)
    """Range of storeys (of :data:`~navverse.city.tags.STOREY_HEIGHT`, 3 m); arterial fronts skew tall,
    others low."""
    gap: Annotated[float, Field(ge=0.0, le=50.0)] = 3.0
    """Mean gap between neighbouring buildings along a block edge (m, exponentially distributed)."""
    crossing_offset: Annotated[float, Field(ge=0.0, le=30.0)] = 3.0
    """Distance of a crossing's centre beyond the junction it serves (m): past the point where its
    crosswalk clears the other roads' carriageways and sidewalks."""
    poi_share: _Share = 0.2
    """Share of street-facing buildings on non-arterial streets with a ground-floor place (shop,
    cafe...)."""
    arterial_poi_share: _Share = 0.6
    """Share of street-facing buildings on arterials with a ground-floor place."""
    lamp_spacing: Annotated[float, Field(ge=10.0, le=200.0)] = 30.0
    """Distance between street lamps along a street (m): on both sides, staggered, on arterials; on one
    side elsewhere."""
    tree_spacing: Annotated[float, Field(ge=5.0, le=100.0)] = 10.0
    """Distance between street trees along each sidewalk of a tree-lined street (m)."""
    tree_street_share: _Share = 0.4
    """Share of streets lined with trees on both sides (arterials: twice that, at most all)."""
    bench_spacing: Annotated[float, Field(ge=20.0, le=2000.0)] = 150.0
    """Mean distance between benches along each sidewalk (m; each bench with a waste basket)."""
    hydrant_spacing: Annotated[float, Field(ge=30.0, le=2000.0)] = 120.0
    """Mean distance between fire hydrants along a street, either side (m)."""
    bus_stop_spacing: Annotated[float, Field(ge=100.0, le=5000.0)] = 350.0
    """Mean distance between bus stops along an arterial (m; a stop on each side)."""
    bus_shelter_share: _Share = 0.5
    """Share of bus stops with a shelter (``shelter=yes``)."""
