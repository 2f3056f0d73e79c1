"""A city map from a local OpenStreetMap file (``.osm``, ``.osm.gz``, ``.osm.pbf``), streamed.

:func:`read_osm` checks the file before parsing (:mod:`.osm_read`: a regular file whose content
matches its name, no ``<!DOCTYPE>`` in XML, not truncated), streams it through osmium keeping only
what the window needs, projects it to the UTM zone of the window's centre with the origin at that
centre, and turns it into a :class:`~navverse.city.map.CityMap` (:mod:`.osm_features`), every feature
clipped to the window (features crossing its edge are cut, not dropped).

What becomes what
-----------------

=============  ==========================================================================================
feature        from
=============  ==========================================================================================
roads          ways ``highway=`` a vehicle class of :data:`~navverse.city.tags.ROAD_CLASSES` (motorway ...
               service, track, busway, living_street), at ground level, not ``area=yes``. Width
               (``width``, else ``lanes`` × lane width, else the class default or a service road's
               by its ``service=*`` kind; painted cycle lanes widen the last two) and sidewalks
               (``sidewalk*`` tags, else the class rule) from :mod:`.tags`; ``lanes``, ``oneway``
               (``oneway=-1`` ways are turned so the points follow the traffic), ``kerb``, ``surface``,
               ``name``; parking strips from ``parking:<side>=lane|street_side|half_on_kerb|shoulder``
               with ``parking:<side>:orientation``, else ``parking:lane:<side>=parallel|diagonal|
               perpendicular``; width ``parking:<side>:width``, else 2.0 m parallel, 4.5 m diagonal,
               5.0 m perpendicular (the carriageway is not widened for them);
               cycle tracks (``cycleway[:left|right|both]=track``, ``opposite_track``) beside the
               carriageway at sidewalk level, ``cycleway[:side]:width`` else 1.8 m
               (:func:`~navverse.city.tags.cycle_tracks`); a side's track is left out where a mapped
               cycleway runs beside the road (as sidewalks are)
bridges        roads and walkways that are bridges (``bridge=*``, ``man_made=bridge``, ``layer`` > 0): kept
               level with the streets they join where they span water or a railway and cross no way
               at ground level; left out where they cross one (an overpass) or span neither (a
               viaduct over land); each counted
passages       roads and walkways under a building at ground level (``tunnel=building_passage``, whatever
               its ``layer``; ``covered=yes|arcade|colonnade``) are kept; each building they pass under
               stands, over the way's width and 1 m past its ends, from the passage's headroom up
               (``maxheight``, else 3.5 m), or leaves it open when less than 1 m taller; counted.
               Other tunnels, ``layer`` < 0 and ``level`` < 0 are not at ground level: left out
sidewalks      a side inferred by the class rule is left out where mapped sidewalks, footways or paths
               run parallel beside the road (within 6 m of its edge) along half its length or more
walkways       ways ``highway=footway|path|steps|cycleway|pedestrian`` at ground level; kind ``sidewalk``
               for ``footway=sidewalk``, ``crossing`` for ``footway=crossing``, else the highway value;
               width ``width``, else the class default
crossings      nodes ``highway=crossing`` (not ``crossing=no``) on a road way in the window; the road is
               the nearest piece of that way; kerb from the node's ``kerb`` (default ``lowered``);
               markings from ``crossing:markings``, else ``crossing_ref``, else ``crossing``
               (:func:`~navverse.city.tag_tables.crossing_markings`; default zebra)
areas          closed ways and multipolygons, the first matching row winning:

               ============  =============================================================================
               class         tags
               ============  =============================================================================
               water         ``natural=water``, ``waterway=riverbank``, ``landuse=reservoir|basin``
               parking       ``amenity=parking`` (not ``parking=underground|multi-storey|rooftop``)
               plaza         ``place=square``, ``highway=pedestrian`` areas (``area=yes`` on a way)
               pedestrian    ``highway=footway`` areas (``area=yes`` on a way)
               green         ``leisure=park|garden|pitch|playground``, ``landuse=grass|meadow|forest|
                             recreation_ground|village_green``, ``natural=wood|scrub|grassland``
               ground        ``landuse=brownfield|construction``, ``natural=bare_rock|sand``
               rail          ``railway=rail|light_rail|narrow_gauge|subway|funicular|preserved|monorail``
                             lines at ground level, as strips of the track bed's width (not ``tram``)
               water         also ``waterway=river|canal|stream|ditch|drain`` lines, ``width`` or a
                             default per kind
               ============  =============================================================================

               Buildings are never areas; areas not at ground level are left out
buildings      closed ways and multipolygons ``building=*`` (not ``no``; not ``roof``: open sides), at
               ground level; multipolygon inner rings are courtyards (holes). Height and base from
               ``height`` / ``building:levels`` (+ roof) / ``min_height``
               (:func:`~navverse.city.tags.building_height`);
               untagged, a whole number of 3 m storeys is drawn uniformly by ``building=*`` value:
               1 (garage, shed, hut, kiosk...), 1-2 (house, detached, terrace...), 2-3 (industrial,
               warehouse...), 2-5 (apartments, commercial, office, retail, hotel...), else 1-3, from
               ``numpy.random.default_rng([seed, type, sign, |id|])`` of the OSM object, so it does not
               depend on reading order. Entrances: ``entrance=*`` nodes of the outline. ``type`` is
               the ``building=*`` value. A building with ``building:part`` outlines (a part belongs to
               the smallest building holding half of it or more) stands as its parts, each clipped to
               the outline with its own heights (an untagged part: the building's), and the rest of
               the outline no part covers; each part names its ``outline``. Parts in no building
               stand alone
pois           nodes and building outlines with ``amenity=`` a place (:data:`.osm_features.POI_AMENITIES`:
               cafe, restaurant, fast_food, bank, pharmacy, bar, pub...), ``shop=*``, ``craft=*``,
               ``office=*`` (in that order); category is the value, ``tag`` is ``key=value``; a node
               in a building footprint names it (the smallest), a building's POI sits inside it
furniture      nodes ``natural=tree``, ``highway=street_lamp|bus_stop|traffic_signals``,
               ``amenity=bench|waste_basket|bicycle_parking|post_box|vending_machine``,
               ``emergency=fire_hydrant``; kind is the value
=============  ==========================================================================================

Polygons of closed ways are built here (so broken rings can be repaired); multipolygon relations
are assembled by osmium (inner rings become holes). Messy data is repaired or left out, and counted
in ``CityMap.dropped`` by reason: ways with missing nodes (lines are split at the gaps, rings skip
them), self-intersecting polygons (``make_valid``, the polygonal part kept), degenerate pieces after
clipping (lines under 0.1 m, polygons under 0.5 m²), OSM objects the file holds twice (one copy
kept; a file osmium refuses as unsorted is sorted in memory first, see :mod:`.osm_read`), ways
repeating their multipolygon's outline, multipolygons osmium cannot assemble, tags that do not read
as numbers (the rule is used), features not at ground level. Features are numbered in the order
(OSM type, OSM id, part), coordinates rounded to the millimetre: the same file, window and seed give
the same bytes from :func:`~navverse.city.map.write_city_map`.

Memory: only the window's objects are kept in Python; osmium's node location index holds every node of
the file, in memory for files that can hold at most 4 million nodes and in a temporary file beyond
(see :mod:`.osm_read`). Nothing is decompressed into memory but stream chunks.
"""

from __future__ import annotations

import os
from pathlib import Path

from navverse.city.map import CityMap, CityMapError, Frame, Source
from navverse.city.osm.features import Features, build_features
from navverse.city.osm.files import (
    Progress,
    check_osm_file,
    file_bounds,
    head_bounds,
    node_spread,
    peek_osm_file,
)
from navverse.city.osm.stream import read_extract
from navverse.city.osm.window import OsmWindow, Window, box_text, make_window
from navverse.city.tag_tables import FEATURE_KEYS
from navverse.files import file_sha256

__all__ = ["OSM_ATTRIBUTION", "check_window", "read_osm"]

OSM_ATTRIBUTION = "© OpenStreetMap contributors, ODbL 1.0"
"""Attribution every map read from OSM carries (``source.attribution``)."""


def read_osm(
    path: str | os.PathLike[str],
    *,
    center: tuple[float, float] | None = None,
    size_m: tuple[float, float] | None = None,
    bbox: tuple[float, float, float, float] | None = None,
    seed: int = 0,
    progress: Progress | None = None,
) -> CityMap:
    """Read a city map from a local OSM file, in a window.

    Parameters
    ----------
    path : path
        A ``.osm`` (OSM XML), ``.osm.gz`` or ``.osm.pbf`` file.
    center : (lat, lon), optional
        Centre of the window (the frame's origin); default: the centre of the file's declared bounds,
        or, for a file that declares none, the node nearest the median of its nodes
        (:func:`~navverse.city.osm.files.node_spread`).
    size_m : (width, height), optional
        Sides of a centred window (m), east-west and north-south;
        :class:`~navverse.city.osm.window.OsmWindow`'s
        default (1 km square) when omitted.
    bbox : (min_lat, min_lon, max_lat, max_lon), optional
        The window as a lat/lon box instead of ``center``: the map covers the local rectangle around
        it, with the origin at its centre.
    seed : int
        Seed of the heights drawn for buildings without height tags (recorded as ``source.seed``).
    progress : callable, optional
        ``progress(phase, done)`` with ``"checksum"`` (bytes) and ``"read"`` (OSM objects).

    Returns
    -------
    CityMap
        Source ``osm`` with the file's name, sha256 and the ODbL attribution; frame of the window's
        UTM zone; everything the window holds, and what was dropped by reason.

    Raises
    ------
    CityMapError
        If the file cannot be read (see :func:`~navverse.city.osm.files.check_osm_file`), the window is
        invalid or
        misses the file's data, or the window holds no roads and no buildings.
    """
    path = Path(path)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise CityMapError(f"seed must be a whole number >= 0, not {seed!r}")
    osm_file = check_osm_file(path)
    bounds = file_bounds(path, osm_file.format)
    size_m = OsmWindow.model_fields["size_m"].default if size_m is None else size_m
    data_bounds = bounds
    if bounds is None and center is None and bbox is None:  # an Overpass export: centre on its data
        spread = node_spread(path, osm_file.format)
        if spread is None:
            raise CityMapError(f"{path.name} holds no node with a location: it has no map data to read")
        data_bounds, center = spread.box, spread.centre
    window = make_window(center=center, size_m=size_m, bbox=bbox, data_bounds=data_bounds, path=path)
    sha256 = file_sha256(path, progress=progress)
    extract = read_extract(osm_file, window, keys=FEATURE_KEYS, progress=progress)
    if bounds is None and (extract.extent is None or not window.meets(extract.extent)):
        data = box_text(extract.extent) if extract.extent else "no map features at all"
        raise CityMapError(
            f"the window ({box_text(window.lonlat)}) does not meet the data of {path.name} ({data}): "
            "move it onto the data"
        )
    features = build_features(extract, window.rect, seed=seed)
    if not features.roads and not features.buildings:
        raise CityMapError(
            f"no roads or buildings in the window of {path.name} ({box_text(window.lonlat)}): "
            "move or enlarge the window (center=, size_m= or bbox=)"
        )
    return _city_map(path, sha256, seed, window, features)


def check_window(
    path: str | os.PathLike[str],
    *,
    center: tuple[float, float] | None = None,
    size_m: tuple[float, float] | None = None,
    bbox: tuple[float, float, float, float] | None = None,
) -> None:
    """Check, cheaply, that a file looks like OSM data and that a window lies on it.

    Reads the file's first bytes (:func:`~navverse.city.osm.files.peek_osm_file`) and its header: the centre
    given (or the bbox's) must lie inside the bounds the file declares, and the window must meet
    them. A file that declares no bounds is checked when it is read (and a window without a centre
    is then centred on its data).

    Raises
    ------
    CityMapError
        Saying what to change.
    """
    path = Path(path)
    fmt, head = peek_osm_file(path)
    bounds = file_bounds(path, fmt) if fmt == "pbf" else head_bounds(head)
    if bounds is None and center is None and bbox is None:
        return  # the window is centred on the data when the file is read
    size_m = OsmWindow.model_fields["size_m"].default if size_m is None else size_m
    window = make_window(center=center, size_m=size_m, bbox=bbox, data_bounds=bounds, path=path)
    if bounds is not None:
        west, south, east, north = bounds
        if not (west <= window.origin_lon <= east and south <= window.origin_lat <= north):
            raise CityMapError(
                f"the window's centre ({window.origin_lat:.6f}, {window.origin_lon:.6f}) lies outside "
                f"the data of {path.name} ({box_text(bounds)}): give a center inside it"
            )


def _city_map(path: Path, sha256: str, seed: int, window: Window, features: Features) -> CityMap:
    source = Source(kind="osm", name=path.name, sha256=sha256, seed=seed, attribution=OSM_ATTRIBUTION)
    frame = Frame(epsg=window.epsg, origin_lat=window.origin_lat, origin_lon=window.origin_lon)
    return CityMap(
        source=source,
        frame=frame,
        window=window.rect,
        roads=features.roads,
        walkways=features.walkways,
        crossings=features.crossings,
        areas=features.areas,
        buildings=features.buildings,
        pois=features.pois,
        furniture=features.furniture,
        dropped=dict(sorted(features.dropped.items())),
    )
