"""Buildings in a scene's USD file: footprints, heights, rooms, doors, exits and facades.

Layout under the default prim (one ``Scope`` per record, typed ``navverse:`` attributes named after
the fields of :mod:`navverse.scene.annotations`, so the file says what ``scene.json`` says)::

    /World/Buildings/building_0001                Scope: id, footprint, baseHeight, height, indoor,
                                                  mapId, osm (when set)
    /World/Buildings/building_0001/outline        BasisCurves (purpose guide): the footprint at the base
    /World/Buildings/building_0001/Rooms/room_0003    id, roomType, polygon, floorHeight
    /World/Buildings/building_0001/Doors/door_0002    id, center, width, facing, rooms
    /World/Buildings/building_0001/Exits/exit_0001    id, center, width, facing, facade (0: none)
    /World/Buildings/building_0001/Facades/facade_0004  id, segment, normal, height, road and
                                                  roadDistance (when it faces a road)

Values are stored in double precision, so they read back exactly.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from pxr import Gf, Sdf, Usd, UsdGeom, Vt
from pydantic import BaseModel

from navverse.scene.annotations import (
    BuildingAnnotation,
    DoorAnnotation,
    ExitAnnotation,
    FacadeAnnotation,
    RoomAnnotation,
)
from navverse.scene.naming import BUILDINGS_ROOT

__all__ = ["read_buildings", "write_buildings"]

_NS = "navverse:"


def _pairs(value: Any) -> Vt.Vec2dArray:
    return Vt.Vec2dArray([Gf.Vec2d(float(x), float(y)) for x, y in value])


def _tuple_pairs(value: Any) -> list[tuple[float, float]]:
    return [(float(v[0]), float(v[1])) for v in value]


@dataclass(frozen=True)
class _Field:
    """How one annotation field is stored: attribute name, USD type, and the conversions."""

    field: str
    attr: str
    type: Sdf.ValueTypeName
    to_usd: Callable[[Any], Any]
    from_usd: Callable[[Any], Any]
    optional: bool = False
    """Written only when set, and left to the model's default when absent (fields added in 2.1)."""


def _plain(field: str, attr: str, type_: Sdf.ValueTypeName, cast: Callable[[Any], Any]) -> _Field:
    return _Field(field, attr, type_, cast, cast)


def _optional(field: str, attr: str, type_: Sdf.ValueTypeName, cast: Callable[[Any], Any]) -> _Field:
    return _Field(field, attr, type_, cast, cast, optional=True)


_ID = _plain("id", "id", Sdf.ValueTypeNames.Int, int)
_CENTER = _Field("center", "center", Sdf.ValueTypeNames.Double3, lambda v: Gf.Vec3d(*v), tuple)
_WIDTH = _plain("width", "width", Sdf.ValueTypeNames.Double, float)
_FACING = _plain("facing", "facing", Sdf.ValueTypeNames.Double, float)

_LAYOUT: dict[type[BaseModel], tuple[str, str, tuple[_Field, ...]]] = {
    # model: (child scope of the building, prim name stem, stored fields)
    RoomAnnotation: (
        "Rooms",
        "room",
        (
            _ID,
            _plain("room_type", "roomType", Sdf.ValueTypeNames.String, str),
            _Field("polygon", "polygon", Sdf.ValueTypeNames.Double2Array, _pairs, _tuple_pairs),
            _plain("floor_height", "floorHeight", Sdf.ValueTypeNames.Double, float),
        ),
    ),
    DoorAnnotation: (
        "Doors",
        "door",
        (
            _ID,
            _CENTER,
            _WIDTH,
            _FACING,
            _Field("rooms", "rooms", Sdf.ValueTypeNames.Int2, lambda v: Gf.Vec2i(*v), tuple),
        ),
    ),
    ExitAnnotation: (
        "Exits",
        "exit",
        (
            _ID,
            _CENTER,
            _WIDTH,
            _FACING,
            _Field("facade", "facade", Sdf.ValueTypeNames.Int, lambda v: v or 0, lambda v: int(v) or None),
        ),
    ),
    FacadeAnnotation: (
        "Facades",
        "facade",
        (
            _ID,
            _Field(
                "segment",
                "segment",
                Sdf.ValueTypeNames.Double2Array,
                _pairs,
                lambda v: tuple(_tuple_pairs(v)),
            ),
            _Field(
                "normal", "normal", Sdf.ValueTypeNames.Double2, lambda v: Gf.Vec2d(*v), lambda v: tuple(v)
            ),
            _plain("height", "height", Sdf.ValueTypeNames.Double, float),
            _optional("road", "road", Sdf.ValueTypeNames.String, str),
            _optional("road_distance", "roadDistance", Sdf.ValueTypeNames.Double, float),
        ),
    ),
}
_BUILDING_FIELDS = (
    _ID,
    _Field("footprint", "footprint", Sdf.ValueTypeNames.Double2Array, _pairs, _tuple_pairs),
    _plain("base_height", "baseHeight", Sdf.ValueTypeNames.Double, float),
    _plain("height", "height", Sdf.ValueTypeNames.Double, float),
    _plain("indoor", "indoor", Sdf.ValueTypeNames.Bool, bool),
    _optional("map_id", "mapId", Sdf.ValueTypeNames.String, str),
    _optional("osm", "osm", Sdf.ValueTypeNames.String, str),
)
_PARTS = {
    RoomAnnotation: "rooms",
    DoorAnnotation: "doors",
    ExitAnnotation: "exits",
    FacadeAnnotation: "facades",
}


def _write_fields(prim: Usd.Prim, record: BaseModel, fields: tuple[_Field, ...]) -> None:
    for f in fields:
        value = getattr(record, f.field)
        if f.optional and value is None:
            continue
        prim.CreateAttribute(_NS + f.attr, f.type, custom=True).Set(f.to_usd(value))


def _read_fields(prim: Usd.Prim, fields: tuple[_Field, ...]) -> dict[str, Any] | None:
    values: dict[str, Any] = {}
    for f in fields:
        attr = prim.GetAttribute(_NS + f.attr)
        value = attr.Get() if attr else None
        if value is None:
            if f.optional:
                continue
            return None
        values[f.field] = f.from_usd(value)
    return values


def write_buildings(stage: Usd.Stage, buildings: list[BuildingAnnotation]) -> None:
    """Define :data:`~navverse.scene.naming.BUILDINGS_ROOT` and one scope per building (none: nothing)."""
    if not buildings:
        return
    UsdGeom.Scope.Define(stage, BUILDINGS_ROOT)
    for building in buildings:
        path = f"{BUILDINGS_ROOT}/building_{building.id:04d}"
        prim = UsdGeom.Scope.Define(stage, path).GetPrim()
        _write_fields(prim, building, _BUILDING_FIELDS)
        outline = UsdGeom.BasisCurves.Define(stage, f"{path}/outline")
        ring = [Gf.Vec3f(float(x), float(y), float(building.base_height)) for x, y in building.footprint]
        outline.CreatePointsAttr(Vt.Vec3fArray([*ring, ring[0]]))
        outline.CreateCurveVertexCountsAttr(Vt.IntArray([len(ring) + 1]))
        outline.CreateTypeAttr(UsdGeom.Tokens.linear)
        outline.CreatePurposeAttr(UsdGeom.Tokens.guide)
        for model, (scope, stem, fields) in _LAYOUT.items():
            records = getattr(building, _PARTS[model])
            if not records:
                continue
            UsdGeom.Scope.Define(stage, f"{path}/{scope}")
            for record in records:
                child = UsdGeom.Scope.Define(stage, f"{path}/{scope}/{stem}_{record.id:04d}").GetPrim()
                _write_fields(child, record, fields)


def read_buildings(stage: Usd.Stage) -> tuple[BuildingAnnotation, ...] | None:
    """The buildings a scene file holds, or ``None`` if it has no buildings scope (older files).

    Raises
    ------
    ValueError
        If a building or one of its parts lacks an attribute or holds invalid values; the message
        names the prim.
    """
    root = stage.GetPrimAtPath(BUILDINGS_ROOT)
    if not root:
        return None
    buildings = []
    for prim in root.GetChildren():
        values = _read_fields(prim, _BUILDING_FIELDS)
        if values is None:
            raise ValueError(f"building {prim.GetPath()} lacks a navverse attribute")
        for model, (scope, _, fields) in _LAYOUT.items():
            records = []
            parent = prim.GetChild(scope)
            for child in parent.GetChildren() if parent else ():
                record = _read_fields(child, fields)
                if record is None:
                    raise ValueError(f"{child.GetPath()} lacks a navverse attribute")
                records.append(model.model_validate(record))
            values[_PARTS[model]] = records
        buildings.append(BuildingAnnotation.model_validate(values))
    return tuple(buildings)
