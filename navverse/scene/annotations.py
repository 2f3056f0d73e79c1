"""Typed model of ``scene.json``: what a scene contains besides its geometry.

Every model is frozen and forbids unknown keys, so a typo in a hand-edited file is an error rather
than a silently ignored field. :func:`save_annotations` writes deterministic bytes and
:func:`load_annotations` checks the format version before anything else.
"""

from __future__ import annotations

import json
import re
from collections import Counter
from collections.abc import Iterable
from pathlib import Path
from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from navverse.errors import SceneError
from navverse.scene.naming import OBJECTS_ROOT, is_identifier

__all__ = [
    "SCENE_FORMAT_VERSION",
    "Bounds",
    "DoorAnnotation",
    "ExitAnnotation",
    "ObjectAnnotation",
    "Regions",
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

SCENE_FORMAT_VERSION = "1.1"
"""Version of the ``scene.json`` layout. A different major version cannot be read; 1.1 added
``regions.rooms`` and ``regions.doors``."""

_MODEL_CONFIG = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)
_VERSION = re.compile(r"^(\d+)\.(\d+)$")
_SCENE_ID = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")
_OBJECT_PRIM_PATH = re.compile(rf"^{re.escape(OBJECTS_ROOT)}/[A-Za-z_][A-Za-z0-9_]*$")

Vec3 = tuple[float, float, float]
PositiveFloat = Annotated[float, Field(gt=0.0)]
PositiveVec3 = tuple[PositiveFloat, PositiveFloat, PositiveFloat]
Channel = Annotated[int, Field(ge=0, le=255)]
Vec2 = tuple[float, float]


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
    yaw: float

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
    """A storefront on a facade: a PlaceNav goal. ``facing`` is the yaw of the outward normal."""

    model_config = _MODEL_CONFIG

    id: Annotated[int, Field(ge=1)]
    place_category: str
    center: Vec3
    facing: float
    size: PositiveVec3
    entrance: Vec3

    @field_validator("place_category")
    @classmethod
    def _category(cls, value: str) -> str:
        return _non_blank(value, "storefront place_category")


class ExitAnnotation(BaseModel):
    """A doorway between the indoor region and the outside; ``facing`` points outwards."""

    model_config = _MODEL_CONFIG

    id: Annotated[int, Field(ge=1)]
    center: Vec3
    width: PositiveFloat
    facing: float


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


class Regions(BaseModel):
    """Indoor footprint polygons (xy), rooms and the doorways between them, building exits and the
    indoor anchor point."""

    model_config = _MODEL_CONFIG

    indoor: list[list[Vec2]] = Field(default_factory=list)
    rooms: list[RoomAnnotation] = Field(default_factory=list)
    doors: list[DoorAnnotation] = Field(default_factory=list)
    exits: list[ExitAnnotation] = Field(default_factory=list)
    indoor_anchor: Vec3 | None = None

    @model_validator(mode="after")
    def _rooms_and_doors(self) -> Regions:
        room_ids = [r.id for r in self.rooms]
        dup = _duplicates(room_ids)
        if dup:
            raise ValueError(f"room ids must be unique; repeated: {dup}")
        dup = _duplicates(d.id for d in self.doors)
        if dup:
            raise ValueError(f"door ids must be unique; repeated: {dup}")
        unknown = sorted({r for d in self.doors for r in d.rooms} - set(room_ids))
        if unknown:
            raise ValueError(f"doors name rooms that do not exist: {unknown}")
        return self

    @field_validator("indoor")
    @classmethod
    def _polygons(cls, value: list[list[Vec2]]) -> list[list[Vec2]]:
        for i, polygon in enumerate(value):
            if len(polygon) < 3:
                raise ValueError(
                    f"indoor polygon {i} has {len(polygon)} vertices; a polygon needs at least 3"
                )
        return value

    @field_validator("exits")
    @classmethod
    def _exit_ids(cls, value: list[ExitAnnotation]) -> list[ExitAnnotation]:
        dup = _duplicates(e.id for e in value)
        if dup:
            raise ValueError(f"exit ids must be unique; repeated: {dup}")
        return value


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
    scene_type: Literal["indoor", "outdoor", "i2o"]
    bounds: Bounds
    objects: list[ObjectAnnotation] = Field(default_factory=list)
    storefronts: list[StorefrontAnnotation] = Field(default_factory=list)
    regions: Regions = Field(default_factory=Regions)
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
        for key, terrain_class in self.terrain_classes.items():
            if key != terrain_class.name:
                raise ValueError(f"terrain class stored under key {key!r} is named {terrain_class.name!r}")
        return self


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
    Path(path).write_text(text + "\n", encoding="utf-8", newline="\n")


def _rebuild_hint(scene_id: str | None) -> str:
    return f"rebuild the scene with `navverse build {scene_id or '<scene_id>'}`"


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
        raise SceneError(f"scene annotations not found: {path}; {_rebuild_hint(None)}") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneError(f"cannot read scene annotations {path}: {exc}") from None
    try:
        raw = json.loads(text)
    except json.JSONDecodeError as exc:
        raise SceneError(
            f"{path} is not valid JSON (line {exc.lineno}, column {exc.colno}: {exc.msg}); "
            f"{_rebuild_hint(None)}"
        ) from None
    if not isinstance(raw, dict):
        raise SceneError(f"{path} must hold a JSON object, found {type(raw).__name__}; {_rebuild_hint(None)}")
    scene_id = raw.get("scene_id") if isinstance(raw.get("scene_id"), str) else None
    version = raw.get("format_version")
    match = _VERSION.match(version) if isinstance(version, str) else None
    if match is None:
        raise SceneError(
            f"{path} has no valid format_version (found {version!r}); this toolkit reads scene format "
            f"{SCENE_FORMAT_VERSION}; {_rebuild_hint(scene_id)}"
        )
    ours = SCENE_FORMAT_VERSION.split(".")[0]
    if match.group(1) != ours:
        raise SceneError(
            f"{path} has scene format version {version}, but this toolkit reads version {ours}.x; "
            f"{_rebuild_hint(scene_id)}, or use the navverse version that wrote it"
        )
    try:
        return SceneAnnotations.model_validate(raw)
    except ValidationError as exc:
        if int(match.group(2)) > int(SCENE_FORMAT_VERSION.split(".")[1]):
            raise SceneError(
                f"{path} has scene format version {version}, newer than this toolkit's "
                f"{SCENE_FORMAT_VERSION}, and fields this version does not know: update navverse"
            ) from None
        problems = "; ".join(
            f"{'.'.join(str(p) for p in err['loc']) or '<root>'}: {err['msg']}" for err in exc.errors()
        )
        raise SceneError(f"{path} is not a valid scene.json: {problems}; {_rebuild_hint(scene_id)}") from None
