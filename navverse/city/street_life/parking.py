"""Where cars park: slots along the curbs' parking bands and in rows in parking lots.

A slot is a rectangle a car of up to its length and width fits in, with the heading the car faces.
Along a street (:func:`street_slots`) slots follow the band's middle line at the band's side of the
road, one car length plus a drawn gap apart, and face the traffic of their side (right-hand
traffic: along the way on its right side, against it on the left; along it on a one-way street).
A slot is kept only if its rectangle lies wholly inside the band, so slots never reach a
crosswalk, a junction corner or a driveway (:mod:`navverse.city.street_life.zones` cut those out).
In a parking lot (:func:`lot_slots`) stalls of ``stall`` size stand in double rows between
``aisle``-wide aisles, laid along the lot's longest side; a stall is kept if it lies inside the
lot, away from its edge by ``edge_margin``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from shapely.geometry import LineString, Polygon
from shapely.geometry.base import BaseGeometry
from shapely.prepared import prep

from navverse.city.geometry.surfaces import SHARED_SURFACE_HIGHWAYS
from navverse.city.map import CityMap
from navverse.city.street_life.zones import StreetZones, ZoneSettings

__all__ = ["Slot", "lot_slots", "slot_polygon", "street_slots"]


@dataclass(frozen=True)
class Slot:
    """A parking slot: centre (m), heading of the car's front (radians from +x), free length and
    width (m), and where it is: ``parking_lane`` (a mapped strip), ``curbside`` or ``parking_lot``."""

    x: float
    y: float
    heading: float
    length: float
    width: float
    zone: str


def slot_polygon(slot: Slot, *, length: float | None = None, width: float | None = None) -> Polygon:
    """The slot's rectangle (or a car's of ``length`` x ``width`` centred in it)."""
    half_l, half_w = 0.5 * (length or slot.length), 0.5 * (width or slot.width)
    c, s = math.cos(slot.heading), math.sin(slot.heading)
    corners = [(a * half_l, b * half_w) for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    return Polygon([(slot.x + u * c - v * s, slot.y + u * s + v * c) for u, v in corners])


def _pieces(geometry: BaseGeometry) -> list[Polygon]:
    return [g for g in getattr(geometry, "geoms", [geometry]) if isinstance(g, Polygon) and not g.is_empty]


def street_slots(
    city: CityMap,
    zones: StreetZones,
    rng: np.random.Generator,
    *,
    settings: ZoneSettings | None = None,
    length: float = 5.6,
    gap: tuple[float, float] = (0.5, 3.0),
) -> list[Slot]:
    """Slots along the parking bands of every street, in road order.

    Parameters
    ----------
    city : CityMap
        The map the zones were laid from.
    zones : StreetZones
        Its zones (parking and curbside bands).
    rng : numpy.random.Generator
        Draws the gaps between cars.
    settings : ZoneSettings, optional
        The settings the zones were laid with (the curbside band width).
    length : float
        Length of a slot (m): room for a car up to this long.
    gap : (float, float)
        Range of the free space drawn between two slots (m).
    """
    settings = settings or ZoneSettings()
    bands = {"parking_lane": prep(zones.parking.buffer(1e-6)), "curbside": prep(zones.curbside.buffer(1e-6))}
    slots: list[Slot] = []
    for road in city.roads:
        if road.highway in SHARED_SURFACE_HIGHWAYS:
            continue
        line = LineString(road.centerline.points)
        half = road.width / 2.0
        for sign, strip in ((1.0, road.parking_left), (-1.0, road.parking_right)):
            zone, width = (
                ("parking_lane", strip) if strip is not None else ("curbside", settings.curbside_band)
            )
            middle = line.offset_curve(sign * (half - width / 2.0), quad_segs=4, join_style="mitre")
            if middle.is_empty or middle.geom_type != "LineString" or middle.length < length:
                continue
            if not bands[zone].intersects(middle):
                continue
            forward = road.oneway or sign < 0
            along = float(rng.uniform(0.0, gap[1]))
            while along + length <= middle.length:
                centre = middle.interpolate(along + length / 2.0)
                a, b = middle.interpolate(along), middle.interpolate(along + length)
                heading = math.atan2(b.y - a.y, b.x - a.x) + (0.0 if forward else math.pi)
                slot = Slot(centre.x, centre.y, math.remainder(heading, math.tau), length, width - 0.2, zone)
                if bands[zone].contains(slot_polygon(slot)):
                    slots.append(slot)
                    along += length + float(rng.uniform(*gap))
                else:
                    along += 0.5
    return slots


def lot_slots(
    lots: BaseGeometry,
    *,
    stall: tuple[float, float] = (2.5, 5.0),
    aisle: float = 6.0,
    edge_margin: float = 0.3,
) -> list[Slot]:
    """Stalls in rows in every parking lot polygon, lot by lot (largest first), row by row.

    Parameters
    ----------
    lots : BaseGeometry
        The parking lots (the plan's ``parking`` class).
    stall : (float, float)
        Width and length of a stall (m).
    aisle : float
        Width of the driving aisle between double rows (m).
    edge_margin : float
        Free margin kept inside the lot's edge (m).
    """
    stall_w, stall_l = stall
    slots: list[Slot] = []
    for lot in sorted(_pieces(lots), key=lambda p: -p.area):
        inner = lot.buffer(-edge_margin)
        if inner.is_empty:
            continue
        inside = prep(inner)
        rect = np.asarray(lot.minimum_rotated_rectangle.exterior.coords)[:4]
        edges = np.diff(np.vstack([rect, rect[:1]]), axis=0)
        longest = int(np.argmax(np.hypot(edges[:, 0], edges[:, 1])))
        along = edges[longest] / np.hypot(*edges[longest])
        across = np.array([-along[1], along[0]])
        origin = rect[longest]
        u = (rect - origin) @ along
        v = (rect - origin) @ across
        # Double rows (two stall lengths) separated by aisles, across the lot.
        pitch = 2 * stall_l + aisle
        for row_start in np.arange(v.min() + aisle / 2.0, v.max(), pitch):
            for k, facing in ((0, 1.0), (1, -1.0)):
                v_mid = row_start + (k + 0.5) * stall_l
                heading = math.atan2(*(facing * across)[::-1])
                for u_mid in np.arange(u.min() + stall_w / 2.0, u.max(), stall_w):
                    x, y = origin + u_mid * along + v_mid * across
                    slot = Slot(float(x), float(y), heading, stall_l - 0.3, stall_w - 0.3, "parking_lot")
                    if inside.contains(slot_polygon(slot, length=stall_l, width=stall_w)):
                        slots.append(slot)
    return slots
