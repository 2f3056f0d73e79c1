"""Typed model of ``scene.json``: what a scene contains besides its geometry.

Every model is frozen and forbids unknown keys, so a typo in a hand-edited file is an error rather
than a silently ignored field. :func:`save_annotations` writes deterministic bytes and
:func:`load_annotations` checks the format version before anything else.
"""

from __future__ import annotations

import json
import math
import re
import typing
from collections import Counter
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Annotated, Any

from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    ValidationError,
    field_validator,
    model_validator,
)
from shapely.geometry import LinearRing, Point, Polygon

from navverse.errors import SceneError, rebuild_hint
from navverse.files import atomic_write
from navverse.scene.naming import OBJECTS_ROOT, is_identifier
from navverse.scene_types import SceneType

__all__ = [
    "SCENE_FORMAT_VERSION",
    "Bounds",
    "BuildingAnnotation",
    "DoorAnnotation",
    "ExitAnnotation",
    "FacadeAnnotation",
    "GeoReference",
    "ObjectAnnotation",
    "RoomAnnotation",
    "SceneAnnotations",
    "SceneSource",
    "SceneStatistics",
    "StorefrontAnnotation",
    "TerrainClass",
    "Vec3",
    "load_annotations",
    "save_annotations",
]

SCENE_FORMAT_VERSION = "2.3"
"""Version of the ``scene.json`` layout. 1.1 added ``regions.rooms`` and ``regions.doors``; 2.0 holds
``buildings`` (footprint, heights, rooms, doors, exits, facades) in place of ``regions``, and
storefronts name their building and facade; 2.1 adds the map frame of a city (``geo``), the map
feature a building was made from (``map_id``, ``osm``) and the road each facade faces
(``road``, ``road_distance``); 2.2 adds where a city's object stands and where it came from
(``zone``, ``group``, ``source`` of an object); 2.3 adds a storefront's ``name``, ``design``, the map
place it stands for (``poi``, ``osm``) and its ``door_width``. 1.x files are upgraded when read (see
:func:`upgrade_annotations`); a newer 2.x file is read without the fields this version does not know;
another major version cannot be read."""

_MODEL_CONFIG = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)
_VERSION = re.compile(r"^(\d+)\.(\d+)$")
_SCENE_ID = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")
_OBJECT_PRIM_PATH = re.compile(rf"^{re.escape(OBJECTS_ROOT)}/[A-Za-z_][A-Za-z0-9_]*$")

POSITION_DECIMALS = 9
"""Decimals (m) positions and extents of annotations are rounded to (:func:`_rounded`)."""


ANGLE_DECIMALS = 12
"""Decimals (rad) annotated angles are rounded to."""


def _rounded(values: tuple[float, ...]) -> tuple[float, ...]:
    """`values` rounded to :data:`POSITION_DECIMALS` decimals (a nanometre).

    Placements computed with ``@``/``dot`` (OpenBLAS kernels) or numpy's AVX-512 functions can differ in
    the last bit between processors; rounding (Python's correctly rounded ``round``) makes the
    annotations, and the poses written from them, the same bytes on every machine, and keeps short
    decimals as written (0.7 stays 0.7)."""
    return tuple(round(v, POSITION_DECIMALS) + 0.0 for v in values)


Vec3 = Annotated[tuple[float, float, float], AfterValidator(_rounded)]
Angle = Annotated[float, AfterValidator(lambda v: round(v, ANGLE_DECIMALS) + 0.0)]
"""An angle (rad), rounded to :data:`ANGLE_DECIMALS` for the reason positions are (:func:`_rounded`)."""
PositiveFloat = Annotated[float, Field(gt=0.0)]
PositiveVec3 = Annotated[tuple[PositiveFloat, PositiveFloat, PositiveFloat], AfterValidator(_rounded)]
Channel = Annotated[int, Field(ge=0, le=255)]
Vec2 = tuple[float, float]
MapId = Annotated[str, Field(pattern=r"^[a-z][a-z0-9_]*-[0-9]+$")]
"""A city map feature id (``road-12``, ``building-3``)."""


def _non_blank(value: str, what: str) -> str:
    if not value.strip():
        raise ValueError(f"{what} must be a non-empty name")
    return value


def _duplicates(values: Iterable[object]) -> list[object]:
    return sorted((v for v, n in Counter(values).items() if n > 1), key=str)


class Bounds(BaseModel):
    """Axis-aligned bounding box of the scene in world coordinates (meters)."""

    model_config = _MODEL_CONFIG

    min: Vec3
    max: Vec3

    @model_validator(mode="after")
    def _ordered(self) -> Bounds:
        if any(lo > hi for lo, hi in zip(self.min, self.max, strict=True)):
            raise ValueError(f"bounds min {self.min} must not exceed max {self.max} on any axis")
        return self

    @property
    def size(self) -> Vec3:
        """Extent along x, y and z."""
        return (self.max[0] - self.min[0], self.max[1] - self.min[1], self.max[2] - self.min[2])


class ObjectAnnotation(BaseModel):
    """One object instance: a possible ObjNav goal.

    ``center`` is the centre of the object's bounding box in the world frame, ``size`` its extent
    along the object's own axes, and ``yaw`` its rotation about +z. A point ``v`` of the object's
    local mesh is at ``Rz(yaw) @ v + center`` in the world.
    """

    model_config = _MODEL_CONFIG

    id: Annotated[int, Field(ge=1)]
    category: str
    prim_path: str
    center: Vec3
    size: PositiveVec3
    yaw: Angle
    zone: str | None = None
    """Where a populated city's object stands (``furniture``, ``frontage``, ``verge``, ``open``,
    ``parking_lane``, ``curbside``, ``parking_lot``...); None for objects not placed by zone."""
    group: str | None = None
    """The contextual group instance it belongs to (e.g. ``bus_stop_wait-3``), if any."""
    source: str | None = None
    """What placed it: the map feature (``osm:node/123``, ``map:furniture-4``) or the rule
    (``grammar``, ``parking``, ``group``); None if not recorded."""

    @field_validator("category")
    @classmethod
    def _category(cls, value: str) -> str:
        return _non_blank(value, "object category")

    @field_validator("prim_path")
    @classmethod
    def _prim_path(cls, value: str) -> str:
        if not _OBJECT_PRIM_PATH.match(value):
            raise ValueError(
                f"object prim_path {value!r} must be a direct child of {OBJECTS_ROOT} with a valid USD "
                f"name, e.g. '{OBJECTS_ROOT}/chair_0003'"
            )
        return value

    @property
    def goal_radius(self) -> float:
        """Goal radius used by the metrics: half the larger horizontal extent."""
        return 0.5 * max(self.size[0], self.size[1])


class StorefrontAnnotation(BaseModel):
    """A storefront on a facade: a PlaceNav goal.

    ``center`` is the centre of its bounding box and ``size`` its extent (width along the facade,
    depth out of it, height); ``facing`` is the yaw of the outward normal; ``entrance`` the point on
    the sidewalk just in front of its door. ``building`` and ``facade`` are the ids of the building
    and facade it is set into (when known); ``poi`` and ``osm`` the city map place it stands for
    (None for a storefront the recipe added where the map has none); ``name`` is the text of its
    sign and ``design`` its design (``<category>/<n>``)."""

    model_config = _MODEL_CONFIG

    id: Annotated[int, Field(ge=1)]
    place_category: str
    center: Vec3
    facing: float
    size: PositiveVec3
    entrance: Vec3
    building: Annotated[int, Field(ge=1)] | None = None
    facade: Annotated[int, Field(ge=1)] | None = None
    name: str | None = None
    design: str | None = None
    poi: MapId | None = None
    osm: Annotated[str, Field(pattern=r"^(node|way|relation)/-?[0-9]+$")] | None = None
    door_width: PositiveFloat | None = None

    @field_validator("place_category")
    @classmethod
    def _category(cls, value: str) -> str:
        return _non_blank(value, "storefront place_category")


class ExitAnnotation(BaseModel):
    """A doorway between a building's inside and the outside; ``facing`` points outwards and
    ``facade`` is the id of the facade it opens in (when known)."""

    model_config = _MODEL_CONFIG

    id: Annotated[int, Field(ge=1)]
    center: Vec3
    width: PositiveFloat
    facing: float
    facade: Annotated[int, Field(ge=1)] | None = None


class RoomAnnotation(BaseModel):
    """A room of a building: its type (``kitchen``, ``corridor``, ``ward``...) and floor polygon (xy)."""

    model_config = _MODEL_CONFIG

    id: Annotated[int, Field(ge=1)]
    room_type: Annotated[str, Field(pattern=r"^[a-z][a-z0-9_]*$")]
    polygon: list[Vec2]
    floor_height: float = 0.0

    @field_validator("polygon")
    @classmethod
    def _polygon(cls, value: list[Vec2]) -> list[Vec2]:
        if len(value) < 3:
            raise ValueError(f"a room polygon needs at least 3 vertices, got {len(value)}")
        return value


class DoorAnnotation(BaseModel):
    """A doorway between two rooms; ``facing`` is the yaw of its normal, from ``rooms[0]`` to ``rooms[1]``."""

    model_config = _MODEL_CONFIG

    id: Annotated[int, Field(ge=1)]
    center: Vec3
    width: PositiveFloat
    facing: float
    rooms: tuple[Annotated[int, Field(ge=1)], Annotated[int, Field(ge=1)]]


class FacadeAnnotation(BaseModel):
    """One outer wall of a building: its base ``segment`` (xy, at the building's base height), the
    unit ``normal`` pointing out of the building (xy) and its ``height`` above the base. ``road`` is
    the city map id of the road the facade faces (the first thing its normal meets from the
    segment's middle, within 50 m, is that road's carriageway) and ``road_distance`` how far (m)."""

    model_config = _MODEL_CONFIG

    id: Annotated[int, Field(ge=1)]
    segment: tuple[Vec2, Vec2]
    normal: Vec2
    height: PositiveFloat
    road: MapId | None = None
    road_distance: Annotated[float, Field(ge=0.0)] | None = None

    @model_validator(mode="after")
    def _road(self) -> FacadeAnnotation:
        if (self.road is None) != (self.road_distance is None):
            raise ValueError(f"facade {self.id}: give both road and road_distance, or neither")
        return self

    @model_validator(mode="after")
    def _geometry(self) -> FacadeAnnotation:
        (x0, y0), (x1, y1) = self.segment
        if math.hypot(x1 - x0, y1 - y0) <= 0.0:
            raise ValueError(f"facade {self.id} has a segment of zero length")
        if abs(math.hypot(*self.normal) - 1.0) > 1e-6:
            raise ValueError(f"facade {self.id}: normal {self.normal} must have unit length")
        return self

    @property
    def width(self) -> float:
        """Length of the facade's base segment (m)."""
        (x0, y0), (x1, y1) = self.segment
        return math.hypot(x1 - x0, y1 - y0)

    @property
    def facing(self) -> float:
        """Yaw of the outward normal (radians)."""
        return math.atan2(self.normal[1], self.normal[0])


class BuildingAnnotation(BaseModel):
    """A building: footprint polygon (xy, counter-clockwise), base height and height, whether its
    inside is part of the scene (``indoor``: rooms a robot can enter), the city map feature it was
    made from (``map_id``, and its ``osm`` reference), and its rooms, the doors between them, its
    exits to the outside and its facades."""

    model_config = _MODEL_CONFIG

    id: Annotated[int, Field(ge=1)]
    footprint: list[Vec2]
    base_height: float = 0.0
    height: PositiveFloat
    indoor: bool = False
    map_id: MapId | None = None
    osm: Annotated[str, Field(pattern=r"^(node|way|relation)/-?[0-9]+$")] | None = None
    rooms: list[RoomAnnotation] = Field(default_factory=list)
    doors: list[DoorAnnotation] = Field(default_factory=list)
    exits: list[ExitAnnotation] = Field(default_factory=list)
    facades: list[FacadeAnnotation] = Field(default_factory=list)

    @field_validator("footprint")
    @classmethod
    def _footprint(cls, value: list[Vec2]) -> list[Vec2]:
        if len(value) < 3:
            raise ValueError(f"a building footprint needs at least 3 vertices, got {len(value)}")
        return value

    @model_validator(mode="after")
    def _parts(self) -> BuildingAnnotation:
        room_ids = {r.id for r in self.rooms}
        unknown = sorted({r for d in self.doors for r in d.rooms} - room_ids)
        if unknown:
            raise ValueError(f"building {self.id}: doors name rooms it does not have: {unknown}")
        facade_ids = {f.id for f in self.facades}
        unknown = sorted({e.facade for e in self.exits if e.facade is not None} - facade_ids)
        if unknown:
            raise ValueError(f"building {self.id}: exits name facades it does not have: {unknown}")
        return self


class TerrainClass(BaseModel):
    """A surface class: its friction, colour in pictures and role for navigation.

    ``navigable`` surfaces can be walked on; ``preferred`` ones are favoured by path planning
    (e.g. sidewalks over roads). ``show_in_bev=False`` hides the class from bird's-eye views
    (ceilings would otherwise cover the floor).
    """

    model_config = _MODEL_CONFIG

    name: str
    friction: Annotated[float, Field(ge=0.0)]
    color: tuple[Channel, Channel, Channel]
    navigable: bool
    preferred: bool
    show_in_bev: bool = True

    @field_validator("name")
    @classmethod
    def _name(cls, value: str) -> str:
        if not is_identifier(value):
            raise ValueError(
                f"terrain class name {value!r} must be a valid USD identifier ([A-Za-z_][A-Za-z0-9_]*)"
            )
        if value == "objects":
            raise ValueError("terrain class name 'objects' is reserved for the objects' physics material")
        return value


class SceneStatistics(BaseModel):
    """Counts reported by the scene stages."""

    model_config = _MODEL_CONFIG

    faces: Annotated[int, Field(ge=0)] = 0
    buildings: Annotated[int, Field(ge=0)] = 0
    road_length_m: Annotated[float, Field(ge=0.0)] = 0.0
    navigable_area_m2: Annotated[float, Field(ge=0.0)] | None = None
    objects_per_category: dict[str, Annotated[int, Field(ge=0)]] = Field(default_factory=dict)


class GeoReference(BaseModel):
    """Where a scene made from a map lies on Earth: its local frame (x east, y north, meters) is the
    projection ``epsg`` with the origin at ``origin_lat``, ``origin_lon``; ``map`` names the source
    (an OSM file's name, or ``synthetic``), with its sha256 and attribution."""

    model_config = _MODEL_CONFIG

    epsg: Annotated[int, Field(ge=0, le=999_999)]
    origin_lat: Annotated[float, Field(ge=-90.0, le=90.0)]
    origin_lon: Annotated[float, Field(ge=-180.0, le=180.0)]
    map: str
    sha256: Annotated[str, Field(pattern=r"^[0-9a-f]{64}$")] | None = None
    attribution: str = ""


class SceneSource(BaseModel):
    """Where the scene came from: recipe path, its content hash and the toolkit version."""

    model_config = _MODEL_CONFIG

    recipe: str
    recipe_hash: str
    toolkit_version: str


class SceneAnnotations(BaseModel):
    """Contents of ``scene.json``."""

    model_config = _MODEL_CONFIG

    format_version: str = SCENE_FORMAT_VERSION
    scene_id: str
    scene_type: SceneType
    bounds: Bounds
    objects: list[ObjectAnnotation] = Field(default_factory=list)
    storefronts: list[StorefrontAnnotation] = Field(default_factory=list)
    buildings: list[BuildingAnnotation] = Field(default_factory=list)
    indoor_anchor: Vec3 | None = None
    geo: GeoReference | None = None
    terrain_classes: dict[str, TerrainClass]
    statistics: SceneStatistics = Field(default_factory=SceneStatistics)
    source: SceneSource | None = None

    @field_validator("format_version")
    @classmethod
    def _format_version(cls, value: str) -> str:
        if not _VERSION.match(value):
            raise ValueError(
                f"format_version {value!r} must look like 'MAJOR.MINOR', e.g. {SCENE_FORMAT_VERSION!r}"
            )
        return value

    @field_validator("scene_id")
    @classmethod
    def _scene_id(cls, value: str) -> str:
        if not _SCENE_ID.match(value):
            raise ValueError(
                f"scene_id {value!r} may only contain letters, digits, '_', '.', '-' and must start "
                "with a letter or digit (it names a directory)"
            )
        return value

    @model_validator(mode="after")
    def _consistent(self) -> SceneAnnotations:
        dup = _duplicates(o.id for o in self.objects)
        if dup:
            raise ValueError(f"object ids must be unique; repeated: {dup}")
        dup = _duplicates(o.prim_path for o in self.objects)
        if dup:
            raise ValueError(f"object prim paths must be unique; repeated: {dup}")
        dup = _duplicates(s.id for s in self.storefronts)
        if dup:
            raise ValueError(f"storefront ids must be unique; repeated: {dup}")
        for what, ids in (
            ("building", [b.id for b in self.buildings]),
            ("room", [r.id for r in self.rooms]),
            ("door", [d.id for d in self.doors]),
            ("exit", [e.id for e in self.exits]),
            ("facade", [f.id for b in self.buildings for f in b.facades]),
        ):
            dup = _duplicates(ids)
            if dup:
                raise ValueError(f"{what} ids must be unique in the scene; repeated: {dup}")
        facades = {b.id: {f.id for f in b.facades} for b in self.buildings}
        for storefront in self.storefronts:
            if storefront.building is not None and storefront.building not in facades:
                raise ValueError(
                    f"storefront {storefront.id} names building {storefront.building}, which does not exist"
                )
            if storefront.facade is not None and storefront.facade not in facades.get(
                storefront.building, ()
            ):
                raise ValueError(
                    f"storefront {storefront.id} names facade {storefront.facade}, which is not a facade of "
                    f"its building {storefront.building}"
                )
        for key, terrain_class in self.terrain_classes.items():
            if key != terrain_class.name:
                raise ValueError(f"terrain class stored under key {key!r} is named {terrain_class.name!r}")
        return self

    @property
    def indoor_polygons(self) -> list[list[Vec2]]:
        """The indoor region: the footprints of the buildings marked ``indoor``."""
        return [b.footprint for b in self.buildings if b.indoor]

    @property
    def rooms(self) -> list[RoomAnnotation]:
        """Every building's rooms, building by building."""
        return [room for b in self.buildings for room in b.rooms]

    @property
    def doors(self) -> list[DoorAnnotation]:
        """Every building's doors between rooms, building by building."""
        return [door for b in self.buildings for door in b.doors]

    @property
    def exits(self) -> list[ExitAnnotation]:
        """Every building's exits to the outside, building by building."""
        return [exit_ for b in self.buildings for exit_ in b.exits]

    def building_of(self, *, room: int | None = None, exit: int | None = None) -> BuildingAnnotation:
        """The building that holds room ``room`` or exit ``exit``.

        Raises
        ------
        KeyError
            If no building holds it.
        """
        for building in self.buildings:
            if room is not None and any(r.id == room for r in building.rooms):
                return building
            if exit is not None and any(e.id == exit for e in building.exits):
                return building
        raise KeyError(
            f"no building holds room {room}" if room is not None else f"no building holds exit {exit}"
        )


def save_annotations(annotations: SceneAnnotations, path: Path) -> None:
    """Write `annotations` as deterministic JSON.

    Keys follow the model's field order, floats are written as Python ``repr`` (shortest exact form),
    indentation is 2 and the file ends with a newline: the same model always gives the same bytes.

    Parameters
    ----------
    annotations : SceneAnnotations
        The model to write.
    path : Path
        Destination file; overwritten.
    """
    text = json.dumps(annotations.model_dump(mode="json"), indent=2, ensure_ascii=False, allow_nan=False)
    with atomic_write(path) as handle:
        handle.write((text + "\n").encode("utf-8"))


def load_annotations(path: Path) -> SceneAnnotations:
    """Read and validate ``scene.json``.

    Parameters
    ----------
    path : Path
        The file to read.

    Returns
    -------
    SceneAnnotations
        The validated annotations.

    Raises
    ------
    SceneError
        If the file is missing, is not valid JSON, has an unsupported major format version or does
        not match the model. The message says what is wrong and how to fix it.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise SceneError(f"scene annotations not found: {path}; {rebuild_hint(None)}") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneError(f"cannot read scene annotations {path}: {exc}") from None
    try:
        raw = json.loads(text)
    except json.JSONDecodeError as exc:
        raise SceneError(
            f"{path} is not valid JSON (line {exc.lineno}, column {exc.colno}: {exc.msg}); "
            f"{rebuild_hint(None)}"
        ) from None
    if not isinstance(raw, dict):
        raise SceneError(f"{path} must hold a JSON object, found {type(raw).__name__}; {rebuild_hint(None)}")
    scene_id = raw.get("scene_id") if isinstance(raw.get("scene_id"), str) else None
    version = raw.get("format_version")
    match = _VERSION.match(version) if isinstance(version, str) else None
    if match is None:
        raise SceneError(
            f"{path} has no valid format_version (found {version!r}); this toolkit reads scene format "
            f"{SCENE_FORMAT_VERSION}; {rebuild_hint(scene_id)}"
        )
    major, minor = int(match.group(1)), int(match.group(2))
    ours_major, ours_minor = (int(v) for v in SCENE_FORMAT_VERSION.split("."))
    if major == 1:
        raw = upgrade_annotations(raw)
    elif major != ours_major:
        raise SceneError(
            f"{path} has scene format version {version}, but this toolkit reads versions 1.x and "
            f"{ours_major}.x; {rebuild_hint(scene_id)}, or use the navverse version that wrote it"
        )
    elif minor > ours_minor:
        raw = _known_fields(SceneAnnotations, raw)
    try:
        return SceneAnnotations.model_validate(raw)
    except ValidationError as exc:
        problems = "; ".join(
            f"{'.'.join(str(p) for p in err['loc']) or '<root>'}: {err['msg']}" for err in exc.errors()
        )
        raise SceneError(f"{path} is not a valid scene.json: {problems}; {rebuild_hint(scene_id)}") from None


def _model_of(annotation: Any) -> type[BaseModel] | None:
    """The model class inside a field annotation (``Model``, ``list[Model]``, ``Model | None``...)."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    for arg in getattr(annotation, "__args__", ()) or ():
        found = _model_of(arg)
        if found is not None:
            return found
    return None


def _known_fields(model: type[BaseModel], data: Any) -> Any:
    """``data`` without the keys ``model`` (and its nested models) do not know: a newer minor
    format's additions, which this version reads past."""
    if isinstance(data, list):
        return [_known_fields(model, item) for item in data]
    if not isinstance(data, dict):
        return data
    kept: dict[str, Any] = {}
    for key, value in data.items():
        field = model.model_fields.get(key)
        if field is None:
            continue
        nested = _model_of(field.annotation)
        if nested is None:
            kept[key] = value
        elif typing.get_origin(field.annotation) is dict and isinstance(value, dict):
            kept[key] = {k: _known_fields(nested, v) for k, v in value.items()}
        else:
            kept[key] = _known_fields(nested, value)
    return kept


def footprint_facades(
    footprint: Sequence[Vec2], *, height: float, first_id: int = 1
) -> list[FacadeAnnotation]:
    """One facade per edge of a footprint polygon, numbered from ``first_id``, normals pointing out.

    Parameters
    ----------
    footprint : sequence of (x, y)
        The polygon, in either orientation (closing vertex optional).
    height : float
        The facades' height above the building's base.
    first_id : int
        Id of the first facade.

    Returns
    -------
    list of FacadeAnnotation
        In the order of the footprint's edges; edges of zero length are skipped.
    """
    points = [tuple(map(float, p)) for p in footprint]
    if len(points) > 1 and points[0] == points[-1]:
        points = points[:-1]
    sign = 1.0 if LinearRing(points).is_ccw else -1.0  # counter-clockwise: the outside is to the right
    facades: list[FacadeAnnotation] = []
    for (x0, y0), (x1, y1) in zip(points, [*points[1:], points[0]], strict=True):
        length = math.hypot(x1 - x0, y1 - y0)
        if length <= 1e-9:
            continue
        normal = (sign * (y1 - y0) / length, -sign * (x1 - x0) / length)
        facades.append(
            FacadeAnnotation(
                id=first_id + len(facades), segment=((x0, y0), (x1, y1)), normal=normal, height=height
            )
        )
    return facades


def nearest_facade(facades: Sequence[FacadeAnnotation], point: Sequence[float]) -> FacadeAnnotation:
    """The facade whose base segment is closest to ``point`` (xy; ties: the first).

    Raises
    ------
    ValueError
        If there are no facades.
    """
    if not facades:
        raise ValueError("no facades to choose from")
    px, py = float(point[0]), float(point[1])

    def distance(facade: FacadeAnnotation) -> float:
        (x0, y0), (x1, y1) = facade.segment
        dx, dy = x1 - x0, y1 - y0
        t = min(1.0, max(0.0, ((px - x0) * dx + (py - y0) * dy) / (dx * dx + dy * dy)))
        return math.hypot(px - x0 - t * dx, py - y0 - t * dy)

    return min(facades, key=distance)


def upgrade_annotations(raw: dict[str, Any]) -> dict[str, Any]:
    """Turn a format 1.x ``scene.json`` (a parsed dict) into format 2.0.

    1.x had one ``regions`` object for the whole scene: indoor polygons, rooms, doors, exits and an
    anchor. Each indoor polygon becomes a building marked ``indoor`` (rooms, doors and exits go to the
    building whose footprint holds their centre, else the first); rooms without an indoor polygon
    make one building (not indoor) with the rooms' bounding rectangle as footprint. Buildings stand on
    ``z = 0`` (or the scene's floor, if higher) and reach the top of the scene's bounds; their
    facades are their footprint's edges, and each exit opens in its nearest facade.
    """
    data = {k: v for k, v in raw.items() if k != "regions"}
    regions = raw.get("regions") or {}
    if not isinstance(regions, dict):
        return {**data, "regions": regions}  # invalid; validation reports the unknown key
    indoor = list(regions.get("indoor") or [])
    rooms = list(regions.get("rooms") or [])
    doors = list(regions.get("doors") or [])
    exits = list(regions.get("exits") or [])
    data["format_version"] = SCENE_FORMAT_VERSION
    data["indoor_anchor"] = regions.get("indoor_anchor")
    data["buildings"] = []
    if not (indoor or rooms or doors or exits):
        return data
    try:
        bounds = raw["bounds"]
        base = max(0.0, float(bounds["min"][2])) if float(bounds["max"][2]) > 0.0 else float(bounds["min"][2])
        height = max(float(bounds["max"][2]) - base, 1e-3)
        footprints = [[tuple(map(float, p)) for p in polygon] for polygon in indoor]
        if not footprints:
            corners = [tuple(map(float, p)) for room in rooms for p in room["polygon"]]
            if not corners:
                corners = [tuple(map(float, b[:2])) for b in (bounds["min"], bounds["max"])]
            xs, ys = [c[0] for c in corners], [c[1] for c in corners]
            footprints = [[(min(xs), min(ys)), (max(xs), min(ys)), (max(xs), max(ys)), (min(xs), max(ys))]]

        shapes = [Polygon(fp) for fp in footprints]

        def owner(x: float, y: float) -> int:
            return next((i for i, shape in enumerate(shapes) if shape.contains(Point(x, y))), 0)

        buildings = [
            {"id": i + 1, "footprint": fp, "base_height": base, "height": height, "indoor": bool(indoor),
             "rooms": [], "doors": [], "exits": [], "facades": []}
            for i, fp in enumerate(footprints)
        ]  # fmt: skip
        room_owner: dict[int, int] = {}
        for room in rooms:
            xs = [float(p[0]) for p in room["polygon"]]
            ys = [float(p[1]) for p in room["polygon"]]
            index = owner(sum(xs) / len(xs), sum(ys) / len(ys))
            room_owner[room["id"]] = index
            buildings[index]["rooms"].append(room)
        for door in doors:
            buildings[room_owner.get(door["rooms"][0], 0)]["doors"].append(door)
        next_facade = 1
        for building in buildings:
            facades = footprint_facades(building["footprint"], height=height, first_id=next_facade)
            next_facade += len(facades)
            building["facades"] = [f.model_dump(mode="json") for f in facades]
        for exit_ in exits:
            x, y = float(exit_["center"][0]), float(exit_["center"][1])
            building = buildings[owner(x, y)]
            facades = [FacadeAnnotation.model_validate(f) for f in building["facades"]]
            chosen = nearest_facade(facades, (x, y)) if facades else None
            building["exits"].append({**exit_, "facade": chosen.id if chosen else None})
    except (KeyError, TypeError, ValueError, IndexError, ValidationError):
        return {**data, "regions": regions}  # malformed 1.x regions: validation reports them
    data["buildings"] = buildings
    return data
