"""Storefronts set into a city's facades: a place of the map becomes a shop front a robot can find.

For each place of the city map whose tags give a place category
(:func:`~navverse.assets.facade.storefronts.place_category`), :func:`place_storefronts`

1. finds the facades it may go on. A facade is usable when it is wide and high enough for a
   storefront and opens onto a street: it faces a road (scene format 2.0 ``road``, within
   ``max_road_distance``), or the walkable ground (a pedestrian street, a square) lies straight out
   of its middle within ``sidewalk_gap`` (a facade onto a pedestrian zone faces no road). Horizontal
   rays from the place (at 1.5 m above the ground) in every direction meet building walls; each hit
   belongs to the facade of that building whose base segment it lies on. The usable facades hit are
   tried nearest first (a place mapped in a building looks only at that building's), then that
   building's other usable facades, then the usable facades of the buildings within
   ``search_radius`` of the place, nearest first (a place whose building opens onto no street, a
   place mapped outside any building whose rays meet only back walls, a place whose facade is full),
   at most :data:`_FACADES_TRIED`. Then, for a place set back from the street (no facade near it
   opens onto the sidewalk), the facades whose doors would face the walkable ground (a sidewalk,
   footway, path, plaza or pedestrian street) within ``approach_distance``, across open ground
   that no building, road, water or railway crosses: its own building's, then the other buildings'
   within ``search_radius``, nearest first, then its own building's up to twice as far (a place
   inside a mall or a station); at most :data:`_FACADES_TRIED` again. The place goes on the first
   facade that takes it (steps 2-5): a facade that refuses it (its cut fails, it is full, no
   sidewalk in front) passes it on to the next;
2. builds a procedural storefront of the category (:func:`~navverse.assets.facade.storefronts.storefront`,
   the place's name on its sign, or a generated one) at the target height, facing out of the facade
   (so towards the street the facade faces), its base on the sidewalk in front;
3. finds room on the facade: the storefront's span is shifted sideways from the place's position to
   the nearest free stretch, away from the facade's corners and from storefronts already placed
   (on this facade, or reaching over from a neighbouring one), and on the building's wall (a facade
   is a run of outline edges that turn little, so on a bent or curved outline its segment leaves
   the wall: horizontal probes find where the wall is on it), and narrowed down to
   :data:`~navverse.assets.facade.storefronts.MIN_WIDTH` if the stretch is short;
4. carves the matching recess into the building with manifold3d
   (:func:`~navverse.scene.compose.carve`) and accepts it only if the volume removed is the
   recess's (the facade is where its segment says and the building is deep enough);
5. requires the sidewalk (or plaza, pedestrian area) in front of its door (for a set-back place: the
   walkable ground faced within ``approach_distance``), clears the street objects its front and its
   doorway would meet, and
6. accepts it only if its sign is visible: from some point of the walkable ground within
   ``view_radius`` in front of it (of a set-back storefront: that much beyond the ground it faces),
   at the robot's camera height, rays reach most of the sign's face.
   A map place whose sign is hidden tries the facades it had left once; then every sign is
   checked again.

The places are taken in rounds of their categories, the rarer categories first: in each round every
category with places left tries them, in map order, until one is placed. So every category has a
storefront, or has tried all its places, before any category has a second; where the facades run
short, every category has had its turns before any has more.

A recipe may add storefronts where the map has none (``fill_per_km2``): usable facades with the
sidewalk in front, drawn at random, get a category drawn from the synthetic cities' place table, and
go through the same steps.
Every rejection is counted by reason, and the map places lost by category and reason (``lost``):
``no facade within reach`` (no building within ``search_radius``), ``no facade onto a street or
walkable ground`` (none near faces a road, nor the walkable ground within ``approach_distance``: a
place far from any walkable surface, or whose building is outside the window), or the first
facade's reason for refusing it.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Annotated

import numpy as np
import shapely
from pydantic import AfterValidator, Field
from shapely.geometry import LineString, Point, Polygon
from shapely.geometry.base import BaseGeometry
from shapely.ops import nearest_points

from navverse.assets.facade.storefronts import (
    MIN_HEIGHT,
    MIN_WIDTH,
    PLACE_CATEGORIES,
    Storefront,
    place_category,
    storefront,
)
from navverse.city.geometry.street_plan import StreetPlan
from navverse.city.map import CityMap, Poi
from navverse.city.precision import union_of
from navverse.city.synthetic.pois import POI_TABLE
from navverse.errors import SceneError
from navverse.scene.annotations import (
    BuildingAnnotation,
    FacadeAnnotation,
    ObjectAnnotation,
    StorefrontAnnotation,
)
from navverse.scene.compose import ObjectPart, carve, object_parts, replace_parts
from navverse.scene.geometry import MeshData, Scene, Surface, yaw_matrix
from navverse.scene.heights import SurfaceHeights
from navverse.settings import Settings

__all__ = [
    "STOREFRONT_CATEGORY",
    "WALKABLE_FRONT",
    "FacadeReach",
    "StorefrontPlacement",
    "StorefrontSettings",
    "densify_storefronts",
    "object_box",
    "place_storefronts",
]

STOREFRONT_CATEGORY = "storefront"
"""The object category of a storefront's geometry (its place category is in its annotation)."""
WALKABLE_FRONT = ("sidewalk", "plaza", "pedestrian")
"""Street plan classes a storefront's door may open onto."""
_RAY_HEIGHT = 1.5
_ENTRANCE_OUT = 0.6  # the entrance point: this far in front of the door (m)
_CLEAR_OUT = 1.5  # the doorway kept clear of objects: this deep (m)
_CUT_OUTSIDE = 0.05  # the recess box reaches this far out of the facade, so no face is coplanar
_ROOF_MARGIN = 0.1  # a storefront's top stays this far below its building's roof
_FACADES_TRIED = 16
"""Facades a map place tries on each footing (onto the street, then set back), in order
(:meth:`_Placer.place_map_place`), before it is rejected."""
_WALL_STEP = 0.25  # spacing of the probes that find where a facade's wall stands (m)
_WALL_PROBE_OUT = 0.5  # a probe starts this far out of the facade's segment and looks back at it (m)
_WALL_TOLERANCE = 0.03  # the wall is on the segment where a probe meets it this close to it (m)
_APPROACH_HALF_ANGLE = math.radians(45.0)  # a set-back door faces the walkable ground within this
_OWN_REACH = 2.0
"""A place mapped in a building may go on that building's facades up to this many times
``search_radius`` away, after every nearer facade."""
_SET_BACK_PROBES = 9  # points of a facade from which a set-back door's view is tried
_BARRIERS = ("building", "road", "curb", "lowered_curb", "crosswalk", "water", "rail")
"""Street plan classes the way from a set-back door to the walkable ground may not cross."""


def _known_place_categories(names: list[str] | None) -> list[str] | None:
    if names is None:
        return None
    unknown = sorted(set(names) - set(PLACE_CATEGORIES))
    if unknown:
        raise ValueError(
            f"unknown place categories {', '.join(unknown)}; known: {', '.join(PLACE_CATEGORIES)}"
        )
    return sorted(set(names))


class FacadeReach(Settings):
    """How near its street a facade must be to open onto it (a storefront's door, an i2o exit)."""

    max_road_distance: Annotated[float, Field(gt=0.0, le=50.0)] = 30.0
    """How far the road a facade faces may be (m)."""
    sidewalk_gap: Annotated[float, Field(ge=0.0, le=20.0)] = 6.0
    """How much open ground (a front garden, a forecourt) may lie between a door and the sidewalk,
    plaza or pedestrian area in front of it (m)."""


class StorefrontSettings(FacadeReach):
    """How storefronts are placed (see the module docstring).

    Every place of the map whose ``amenity``/``shop``/``craft``/``office`` tag has a place category
    gets a storefront on the nearest facade onto a street (a road within ``max_road_distance``, or a
    pedestrian street or square straight ahead; found by ray casting, else the nearest within
    ``search_radius``), ``height`` tall and up to ``max_width`` wide (lower on a lower building),
    shifted sideways to fit and kept ``corner_margin`` from the facade's ends; it is accepted when its
    recess is carved, its door opens onto the sidewalk (across at most ``sidewalk_gap`` m of open
    ground) and its sign is seen from the walkable ground in front (within ``view_radius``) at
    ``camera_height``. A place set back from the street, whose facades near it all fail, goes on a
    facade whose door faces the walkable ground within ``approach_distance``, across open ground.
    ``fill_per_km2`` adds storefronts on such facades where the map has fewer
    places (categories drawn from the synthetic cities' place table); ``categories`` limits the place
    categories placed.
    """

    height: Annotated[float, Field(ge=3.2, le=6.0)] = 3.6
    """Height of a storefront (m); lower on a lower building, down to
    :data:`~navverse.assets.facade.storefronts.MIN_HEIGHT`, 0.1 m under its roof."""
    max_width: Annotated[float, Field(ge=4.0, le=20.0)] = 8.0
    """Widest storefront (m); widths are drawn from ``MIN_WIDTH + 1 .. max_width``."""
    corner_margin: Annotated[float, Field(ge=0.0, le=5.0)] = 0.4
    """Distance kept from a facade's ends (m)."""
    search_radius: Annotated[float, Field(gt=0.0, le=200.0)] = 40.0
    """How far from its place a facade may be (m)."""
    camera_height: Annotated[float, Field(gt=0.0, le=3.0)] = 0.6
    """Height of the robot's camera above the ground (m) for the visibility check."""
    view_radius: Annotated[float, Field(ge=2.0, le=30.0)] = 15.0
    """How far in front of a storefront (m) the sign may be seen from."""
    fill_per_km2: Annotated[float, Field(ge=0.0, le=2000.0)] = 0.0
    """Storefronts added per km² of the window where the map has no place, at most."""
    categories: Annotated[list[str] | None, AfterValidator(_known_place_categories)] = None
    """The place categories placed (all when None)."""
    rays: Annotated[int, Field(ge=8, le=720)] = 72
    """Horizontal rays cast from a place to find its facade."""
    approach_distance: Annotated[float, Field(ge=0.0, le=50.0)] = 25.0
    """How far (m) the walkable ground (a sidewalk, footway, path, plaza or pedestrian street) may be
    from the door of a map place set back from the street: when no facade near the place opens onto
    it within ``sidewalk_gap``, a facade whose door faces it (within 45° of straight ahead) across
    open ground, crossing no building, road, water or railway, takes the storefront (its sign seen
    from up to ``view_radius`` beyond that); 0 places no storefront set back."""


@dataclass(frozen=True)
class StorefrontPlacement:
    """The city scene with its storefronts, and what happened to every candidate place.

    Attributes
    ----------
    scene : Scene
        Buildings carved; each storefront added as an object of category :data:`STOREFRONT_CATEGORY`
        (prim ``storefront_<place category>_<id>``, zone ``facade``) and as a storefront annotation;
        the street objects in their way removed.
    counts : dict
        ``places`` (map places with a place category), ``filled`` (candidates added by
        ``fill_per_km2``), ``placed``, ``rejected`` {reason: n}, ``categories`` {category: n placed},
        ``lost`` {category: {reason: n}} (map places not placed), ``objects_cleared``, ``narrowed``
        (storefronts made narrower to fit), ``shifted`` (moved sideways from their place) and
        ``set_back`` (storefronts whose door faces the walkable ground from beyond ``sidewalk_gap``).
    """

    scene: Scene
    counts: dict = field(default_factory=dict)


@dataclass(frozen=True)
class _Option:
    """A facade a place may go on: its building, the facade, where along it (m) the place is, and
    whether its door may stand back from the walkable ground (``approach_distance``) rather than
    open onto it (``sidewalk_gap``)."""

    building: BuildingAnnotation
    facade: FacadeAnnotation
    at: float
    set_back: bool = False


@dataclass(frozen=True)
class _Candidate:
    category: str
    name: str | None
    poi: Poi | None


@dataclass
class _Placed:
    annotation: StorefrontAnnotation
    part: ObjectPart
    building: int
    recess: MeshData
    front: BaseGeometry  # footprint of the part outside the facade, and the doorway kept clear
    sign_points: np.ndarray  # (9, 3) points on the sign's face, just in front of it
    normal: np.ndarray
    facade_point: np.ndarray  # xy on the facade below the storefront's centre
    span: tuple[float, float]  # the stretch of its facade it covers (m along it)
    set_back: bool  # its door faces the walkable ground `approach` m away (not within sidewalk_gap)
    approach: float  # how far the walkable ground is from its door (m; 0: it opens onto it)


# ------------------------------------------------------------------------------------------- helpers


def _tags(poi: Poi) -> dict[str, str]:
    key, _, value = poi.tag.partition("=")
    return {key: value}


def _facade_frame(facade: FacadeAnnotation) -> tuple[np.ndarray, np.ndarray, float]:
    start, end = np.asarray(facade.segment, dtype=np.float64)
    length = float(np.hypot(*(end - start)))
    return start, (end - start) / length, length


def _rectangle(origin: np.ndarray, along: np.ndarray, normal: np.ndarray, s0: float, s1: float, depth: float):
    a, b = origin + along * s0, origin + along * s1
    return Polygon([a, b, b + normal * depth, a + normal * depth])


class _FacadeFinder:
    """The facades of a city's buildings, hit by horizontal rays (one Open3D scene of the solids)."""

    def __init__(self, scene: Scene) -> None:
        import open3d as o3d

        self._o3d = o3d
        self.buildings = {b.id: b for b in scene.annotations.buildings}
        meshes, owners = [], []
        for surface in scene.surfaces:
            number = _building_number(surface.name)
            if number is not None and number in self.buildings:
                meshes.append(surface.mesh)
                owners.append(np.full(surface.mesh.num_faces, number, dtype=np.int64))
        self._rays = o3d.t.geometry.RaycastingScene()
        self._owner = np.concatenate(owners) if owners else np.zeros(0, dtype=np.int64)
        if meshes:
            mesh = MeshData.concatenate(meshes)
            self._origin = mesh.vertices[:, :2].min(axis=0)
            local = mesh.vertices - np.array([*self._origin, 0.0])
            self._rays.add_triangles(
                o3d.core.Tensor(local.astype(np.float32)), o3d.core.Tensor(mesh.faces.astype(np.uint32))
            )
        else:
            self._origin = np.zeros(2)

    def hits(self, xy: np.ndarray, z: float, rays: int, reach: float) -> list[tuple[float, int, np.ndarray]]:
        """(distance, building id, hit xy) of horizontal rays from a point, nearest first."""
        if not len(self._owner):
            return []
        angles = np.arange(rays) * (2.0 * math.pi / rays)
        directions = np.stack([np.cos(angles), np.sin(angles)], axis=1)
        cast = np.zeros((rays, 6), dtype=np.float32)
        cast[:, :2], cast[:, 2], cast[:, 3:5] = xy - self._origin, z, directions
        result = self._rays.cast_rays(self._o3d.core.Tensor(cast))
        t = result["t_hit"].numpy().astype(np.float64)
        ids = result["primitive_ids"].numpy().astype(np.int64)
        found = [
            (float(t[k]), int(self._owner[ids[k]]), xy + directions[k] * t[k])
            for k in np.flatnonzero(np.isfinite(t) & (t <= reach))
        ]
        return sorted(found, key=lambda hit: (hit[0], hit[1]))

    def off_wall(self, building: BuildingAnnotation, facade: FacadeAnnotation) -> list[tuple[float, float]]:
        """Stretches of a facade (m along it) where its building's wall is not on its base segment.

        A facade is a run of outline edges that turn little, so on a curved or stepped outline its
        segment is a chord that cuts across the wall: a recess carved there would miss the wall (or
        bury the storefront in it). Horizontal probes every :data:`_WALL_STEP` from just out of the
        segment look back at it; where one meets no wall of the building within
        :data:`_WALL_TOLERANCE` of the segment, the stretch around it is off the wall.
        """
        start, along, length = _facade_frame(facade)
        normal = np.asarray(facade.normal, dtype=np.float64)
        at = np.arange(_WALL_STEP / 2.0, length, _WALL_STEP)
        if not len(self._owner) or not len(at):
            return [(0.0, length)]
        cast = np.zeros((len(at), 6), dtype=np.float32)
        cast[:, :2] = start + along * at[:, None] + normal * _WALL_PROBE_OUT - self._origin
        cast[:, 2] = building.base_height + _RAY_HEIGHT
        cast[:, 3:5] = -normal
        result = self._rays.cast_rays(self._o3d.core.Tensor(cast))
        t = result["t_hit"].numpy().astype(np.float64)
        ids = result["primitive_ids"].numpy().astype(np.int64)
        hit = np.isfinite(t)
        on = np.zeros(len(at), dtype=bool)
        on[hit] = (np.abs(t[hit] - _WALL_PROBE_OUT) <= _WALL_TOLERANCE) & (
            self._owner[ids[hit]] == building.id
        )
        return _runs(at, ~on, _WALL_STEP / 2.0, length)


def _runs(at: np.ndarray, flags: np.ndarray, half: float, length: float) -> list[tuple[float, float]]:
    """The stretches (m along a facade of `length`) covered by the runs of flagged probes at `at`,
    each probe covering `half` either side."""
    spans: list[tuple[float, float]] = []
    for k in np.flatnonzero(flags):
        a, b = max(0.0, float(at[k]) - half), min(length, float(at[k]) + half)
        if spans and a <= spans[-1][1] + 1e-9:
            spans[-1] = (spans[-1][0], b)
        else:
            spans.append((a, b))
    return spans


def _building_number(name: str) -> int | None:
    prefix, _, number = name.rpartition("_")
    return int(number) if prefix == "building" and number.isdigit() else None


def _along(facade: FacadeAnnotation, xy: np.ndarray) -> float:
    """Where along a facade (m from its start, within it) a point lies, seen square to it."""
    start, along, length = _facade_frame(facade)
    return float(np.clip((xy - start) @ along, 0.0, length))


def _facade_distances(building: BuildingAnnotation, point: np.ndarray) -> np.ndarray:
    """Distance (m) from a point to the base segment of each of a building's facades, in their order."""
    segments = np.asarray([f.segment for f in building.facades], dtype=np.float64).reshape(-1, 2, 2)
    start, step = segments[:, 0], segments[:, 1] - segments[:, 0]
    squared = np.maximum(np.einsum("ij,ij->i", step, step), 1e-12)
    t = np.clip(np.einsum("ij,ij->i", point - start, step) / squared, 0.0, 1.0)
    return np.hypot(*(start + step * t[:, None] - point).T)


def _facade_at(
    building: BuildingAnnotation, point: np.ndarray, tolerance: float = 0.25
) -> FacadeAnnotation | None:
    """The facade of a building whose base segment passes nearest a point, within `tolerance`."""
    if not building.facades:
        return None
    distances = _facade_distances(building, point)
    nearest = int(np.argmin(distances))
    return building.facades[nearest] if distances[nearest] < tolerance else None


def _spans(
    stores: Sequence[StorefrontAnnotation], buildings: Sequence[BuildingAnnotation]
) -> dict[int, list[tuple[float, float]]]:
    """The stretch of its facade each storefront already there covers, by facade id."""
    facades = {f.id: f for b in buildings for f in b.facades}
    spans: dict[int, list[tuple[float, float]]] = {}
    for store in stores:
        if store.facade is None or store.facade not in facades:
            continue
        start, along, _ = _facade_frame(facades[store.facade])
        at = float((np.asarray(store.center[:2]) - start) @ along)
        spans.setdefault(store.facade, []).append((at - store.size[0] / 2, at + store.size[0] / 2))
    return spans


def _free_span(
    occupied: Sequence[tuple[float, float]], length: float, margin: float, want: float, at: float
) -> tuple[float, float] | None:
    """The span of width up to `want` (at least MIN_WIDTH) nearest `at`, clear of `occupied` and the ends."""
    edges = sorted((max(margin, a), min(length - margin, b)) for a, b in occupied)
    gaps, cursor = [], margin
    for a, b in edges:
        if a > cursor:
            gaps.append((cursor, a))
        cursor = max(cursor, b)
    if length - margin > cursor:
        gaps.append((cursor, length - margin))
    best: tuple[float, float, float] | None = None
    for g0, g1 in gaps:
        width = min(want, g1 - g0)
        if width < MIN_WIDTH - 1e-9:
            continue
        centre = float(np.clip(at, g0 + width / 2, g1 - width / 2))
        key = (abs(centre - at), -width)
        if best is None or key < (abs(best[0] - at), -best[1]):
            best = (centre, width, 0.0)
    if best is None:
        return None
    return best[0] - best[1] / 2, best[0] + best[1] / 2


# ------------------------------------------------------------------------------------------- placing


class _Placer:
    def __init__(
        self,
        scene: Scene,
        plan: StreetPlan,
        rng: np.random.Generator,
        settings: StorefrontSettings,
        *,
        region: BaseGeometry | None = None,
    ) -> None:
        self.scene = scene
        self.rng = rng
        self.settings = settings
        self.region = region  # where added storefronts may go (their facade's middle); anywhere if None
        self.finder = _FacadeFinder(scene)
        self.heights = SurfaceHeights(scene)
        self.walkable = union_of(plan.classes.get(name, Polygon()) for name in WALKABLE_FRONT)
        shapely.prepare(self.walkable)
        self.roads = union_of(plan.classes.get(name, Polygon()) for name in ("road", "curb", "water"))
        shapely.prepare(self.roads)
        self.meshes = {
            number: surface.mesh
            for surface in scene.surfaces
            if (number := _building_number(surface.name)) is not None
        }
        footprints = [Polygon(b.footprint) for b in scene.annotations.buildings]
        self.footprints = shapely.STRtree(footprints)
        self.footprint_ids = [b.id for b in scene.annotations.buildings]
        self.footprint_index = {number: index for index, number in enumerate(self.footprint_ids)}
        self.footprint_shapes = footprints
        self.by_map_id = {b.map_id: b.id for b in scene.annotations.buildings if b.map_id is not None}
        self.walkway_ahead: dict[int, bool] = {}  # facade id -> walkable ground straight ahead
        self.set_back_at: dict[int, list[float]] = {}  # facade id -> where a set-back door faces it
        self.off_wall: dict[int, list[tuple[float, float]]] = {}  # facade id -> stretches off its wall
        self.barriers = union_of(plan.classes.get(name, Polygon()) for name in _BARRIERS)
        shapely.prepare(self.barriers)
        self.existing = list(scene.annotations.storefronts)
        self.occupied: dict[int, list[tuple[float, float]]] = _spans(
            self.existing, scene.annotations.buildings
        )
        self.placed: list[_Placed] = []
        self.rejected: Counter[str] = Counter()
        self.lost: Counter[tuple[str, str]] = Counter()  # (category, reason) of map places not placed
        self.narrowed = 0
        self.shifted = 0
        self.serial = len(self.existing)
        # placed id -> the map place, the facades it did not try, whether its set-back ones are left
        self.spare: dict[int, tuple[_Candidate, list[_Option], bool]] = {}

    # -- finding the facade

    def place_map_place(self, candidate: _Candidate) -> bool:
        """Place a map place on the first of its facades that takes it; whether it was placed (a place
        that was not is counted lost, with its reason).

        Onto the street first: the usable facades its rays hit, nearest first (only its own
        building's, when it is mapped in one), then its own building's other usable facades, then
        the usable facades of the buildings within ``search_radius``, nearest first. Only when none
        takes it, set back from the street: the facades whose doors face the walkable ground within
        ``approach_distance`` (:meth:`_set_back_options`). At most :data:`_FACADES_TRIED` of each.
        """
        xy, own = self._where(candidate)
        street, hits = self._street_options(xy, own)
        reason = self.place_on_one(candidate, street[:_FACADES_TRIED], set_back_left=True)
        if reason is None:
            return True
        later = self.place_on_one(candidate, self._set_back_options(xy, own)[:_FACADES_TRIED])
        if later is None:
            return True
        reason = reason or later
        if not reason and not hits and not self._buildings_near(xy) and own is None:
            reason = "no facade within reach"
        reason = reason or "no facade onto a street or walkable ground"
        self.rejected[reason] += 1
        self.lost[candidate.category, reason] += 1
        return False

    def retry(self, number: int) -> bool:
        """Place the map place of a dropped storefront (whose sign proved hidden) on the facades it had
        left, once; whether it was placed again."""
        candidate, rest, set_back_left = self.spare.pop(number, (None, [], False))
        if candidate is None:
            return False
        if set_back_left:
            rest = rest + self._set_back_options(*self._where(candidate))[:_FACADES_TRIED]
        return self.place_on_one(candidate, rest) is None

    def _where(self, candidate: _Candidate) -> tuple[np.ndarray, int | None]:
        """A map place's position and the scene building it is mapped in (None: none)."""
        poi = candidate.poi
        assert poi is not None
        return np.asarray(poi.position, dtype=np.float64), self._own_building(poi)

    def _street_options(self, xy: np.ndarray, own: int | None) -> tuple[list[_Option], int]:
        """The usable facades of a place, in the order they are tried (:meth:`place_map_place`), and how
        many walls its rays hit."""
        z = self._ground_under(xy) + _RAY_HEIGHT
        hits = self.finder.hits(xy, z, self.settings.rays, self.settings.search_radius)
        options: dict[int, _Option] = {}
        for _, number, point in hits:
            if own is not None and number != own:
                continue
            building = self.finder.buildings[number]
            facade = _facade_at(building, point)
            if facade is not None and facade.id not in options and self._usable(facade):
                start, along, _ = _facade_frame(facade)
                options[facade.id] = _Option(building, facade, float((point - start) @ along))
        for building, facade in self._facades_near(xy, own):
            options.setdefault(facade.id, _Option(building, facade, _along(facade, xy)))
        return list(options.values()), len(hits)

    def _set_back_options(self, xy: np.ndarray, own: int | None) -> list[_Option]:
        """Facades whose doors face the walkable ground across open ground (:meth:`_walkable_faced`):
        its own building's within ``search_radius``, then the other buildings' within it, nearest
        first, then its own building's up to :data:`_OWN_REACH` times as far (a place inside a large
        building, a mall or a station, opens onto its outside); each at the point of it nearest the
        place from which the walkable ground is faced."""
        radius = self.settings.search_radius
        indices = set(self._buildings_near(xy))
        if own is not None:
            indices.add(self.footprint_index[own])
        found = []
        for index in sorted(indices):
            building = self.finder.buildings[self.footprint_ids[index]]
            if not building.facades:
                continue
            for facade, distance in zip(building.facades, _facade_distances(building, xy), strict=True):
                reach = radius * (_OWN_REACH if building.id == own else 1.0)
                reached = self._walkable_faced(facade) if distance <= reach and self._fits(facade) else []
                if reached:
                    at = min(reached, key=lambda a: (abs(a - _along(facade, xy)), a))
                    key = (distance > radius, building.id != own, float(distance), facade.id)
                    found.append((key, _Option(building, facade, at, set_back=True)))
        return [option for _, option in sorted(found, key=lambda row: row[0])]

    def _own_building(self, poi: Poi) -> int | None:
        """The scene building of the map building a place is mapped in (None: none)."""
        if poi.building is None:
            return None
        return self.by_map_id.get(poi.building)

    def _buildings_near(self, xy: np.ndarray) -> list[int]:
        """Indices (into the footprints) of the buildings within ``search_radius`` of a point."""
        found = self.footprints.query(Point(xy), predicate="dwithin", distance=self.settings.search_radius)
        return sorted(int(k) for k in found)

    def _facades_near(
        self, xy: np.ndarray, own: int | None
    ) -> list[tuple[BuildingAnnotation, FacadeAnnotation]]:
        """Usable facades within ``search_radius`` of a point: its own building's first, then by distance."""
        found = []
        for index in self._buildings_near(xy):
            building = self.finder.buildings[self.footprint_ids[index]]
            if not building.facades:
                continue
            for facade, distance in zip(building.facades, _facade_distances(building, xy), strict=True):
                if distance <= self.settings.search_radius and self._usable(facade):
                    found.append((building.id != own, float(distance), facade.id, building, facade))
        found.sort(key=lambda row: row[:3])
        return [(building, facade) for *_, building, facade in found]

    def place_on_one(
        self, candidate: _Candidate, options: Sequence[_Option], *, set_back_left: bool = False
    ) -> str | None:
        """Place a map place on the first of these facades that takes it (the facades after it are
        kept in :attr:`spare`, should its sign prove hidden; with `set_back_left`, its set-back
        facades too); None when one does, else the first facade's reason for refusing it ("" when
        there is none)."""
        first = ""
        for index, option in enumerate(options):
            reason = self.place(
                candidate, option.building, option.facade, option.at, set_back=option.set_back
            )
            if reason is None:
                rest = list(options[index + 1 :])
                self.spare[self.placed[-1].annotation.id] = (candidate, rest, set_back_left)
                return None
            first = first or reason
        return first

    def _ground_under(self, xy: np.ndarray) -> float:
        """The ground's height at a point: the base of the building it is in, else the surface under it."""
        for index in self.footprints.query(Point(xy), predicate="intersects"):
            return float(self.finder.buildings[self.footprint_ids[index]].base_height)
        height = self.heights(xy)[0]
        return 0.0 if math.isnan(height) else float(height)

    def _fits(self, facade: FacadeAnnotation) -> bool:
        """Whether a facade is wide and high enough for a storefront."""
        return (
            facade.width >= MIN_WIDTH + 2 * self.settings.corner_margin
            and facade.height >= MIN_HEIGHT + _ROOF_MARGIN
        )

    def _usable(self, facade: FacadeAnnotation) -> bool:
        """Whether a storefront may go on a facade: wide and high enough, opening onto a street."""
        return self._fits(facade) and (self._faces_road(facade) or self._faces_walkway(facade))

    def _faces_road(self, facade: FacadeAnnotation) -> bool:
        reach = self.settings.max_road_distance
        return facade.road is not None and facade.road_distance is not None and facade.road_distance <= reach

    def _faces_walkway(self, facade: FacadeAnnotation) -> bool:
        """Whether the walkable ground (a pedestrian street, a square) lies straight out of the facade's
        middle, within ``sidewalk_gap`` (a facade onto a pedestrian zone faces no road)."""
        if facade.id not in self.walkway_ahead:
            middle = np.mean(np.asarray(facade.segment, dtype=np.float64), axis=0)
            self.walkway_ahead[facade.id] = self._sidewalk_ahead(middle, np.asarray(facade.normal))
        return self.walkway_ahead[facade.id]

    def _walkable_faced(self, facade: FacadeAnnotation) -> list[float]:
        """Where along a facade (m, at most :data:`_SET_BACK_PROBES` points spread over it) a door
        would face the walkable ground within ``approach_distance`` (:meth:`_approach`)."""
        if facade.id not in self.set_back_at:
            start, along, length = _facade_frame(facade)
            normal = np.asarray(facade.normal, dtype=np.float64)
            probes = (np.arange(_SET_BACK_PROBES) + 0.5) * (length / _SET_BACK_PROBES)
            self.set_back_at[facade.id] = [
                float(a) for a in probes if self._approach(start + along * a, normal) is not None
            ]
        return self.set_back_at[facade.id]

    def _off_wall(self, building: BuildingAnnotation, facade: FacadeAnnotation) -> list[tuple[float, float]]:
        """Stretches of a facade off its building's wall (:meth:`_FacadeFinder.off_wall`), once per facade."""
        if facade.id not in self.off_wall:
            self.off_wall[facade.id] = self.finder.off_wall(building, facade)
        return self.off_wall[facade.id]

    def fill_facades(self) -> list[tuple[BuildingAnnotation, FacadeAnnotation]]:
        """Every usable facade with the sidewalk in front of its middle, in a random order."""
        region = self.region
        found = [
            (b, f)
            for b in self.scene.annotations.buildings
            if not b.indoor
            for f in b.facades
            if self._usable(f)
            and (region is None or region.contains(Point(np.mean(f.segment, axis=0))))
            and self._sidewalk_ahead(np.mean(f.segment, axis=0), np.asarray(f.normal))
        ]
        order = self.rng.permutation(len(found))
        return [found[k] for k in order]

    # -- placing on a facade

    def place(
        self,
        candidate: _Candidate,
        building: BuildingAnnotation,
        facade: FacadeAnnotation,
        at: float,
        *,
        set_back: bool = False,
    ) -> str | None:
        """Place a storefront on the facade near `at` (m along it); the reason it failed, or None.

        With `set_back`, its door may face the walkable ground up to ``approach_distance`` away
        (:meth:`_approach`) rather than open onto it within ``sidewalk_gap``.
        """
        s = self.settings
        start, along, _ = _facade_frame(facade)
        normal = np.asarray(facade.normal, dtype=np.float64)
        want = float(self.rng.uniform(MIN_WIDTH + 1.0, max(MIN_WIDTH + 1.0, s.max_width)))
        span = self._free_stretch(building, facade, want, at)
        if isinstance(span, str):
            return span
        width = span[1] - span[0]
        middle = start + along * (0.5 * (span[0] + span[1]))
        ground = self.heights(middle + normal * 0.5)[0]
        if math.isnan(ground):
            return "no ground in front"
        base = float(ground)
        if building.base_height > base + 0.3:
            return "building does not reach the ground"
        height = min(s.height, building.base_height + building.height - base - _ROOF_MARGIN)
        if height < MIN_HEIGHT:
            return "building too low"
        built = storefront(candidate.category, self.rng, name=candidate.name, width=width, height=height)
        recess = built.entrance[1] + built.size[1] / 2  # depth of the facade panel behind its front
        yaw = math.atan2(normal[1], normal[0]) - math.pi / 2  # local +y (the front) -> the normal
        rotation = yaw_matrix(yaw)
        centre_xy = middle + normal * (built.size[1] / 2 - recess)
        centre = np.array([*centre_xy, base + built.size[2] / 2])
        entrance = rotation @ np.asarray(built.entrance) + centre
        door_xy = entrance[:2]
        entrance_xy = door_xy + normal * _ENTRANCE_OUT
        approach = self._door_front(door_xy, normal, set_back=set_back)
        if isinstance(approach, str):
            return approach
        protrusion = built.size[1] - recess
        s_door = float((door_xy - start) @ along)
        front = _rectangle(start, along, normal, span[0], span[1], max(protrusion, 0.05)).union(
            _rectangle(start, along, normal, s_door - 0.8, s_door + 0.8, _CLEAR_OUT)
        )
        if self._blocked_by_building(front, building.id):
            return "blocked by a building"
        box = MeshData.box((width, recess + _CUT_OUTSIDE, height), center=(0.0, 0.0, 0.0)).transformed(
            (*(middle - normal * (recess - _CUT_OUTSIDE) / 2), base + height / 2), yaw
        )
        try:
            carved, removed = carve(self.meshes[building.id], box)
        except SceneError:
            return "cut failed: the building is not a closed solid"
        if removed < 0.9 * width * recess * height:
            return "cut failed: the facade is not there or the building is too shallow"
        self.meshes[building.id] = carved
        if span[1] - span[0] < want - 1e-6:
            self.narrowed += 1
        if abs(0.5 * (span[0] + span[1]) - at) > 0.5:
            self.shifted += 1
        self.occupied.setdefault(facade.id, []).append(span)
        self.serial += 1
        number = self.serial  # unique while placing; the scene numbers its storefronts in build()
        poi = candidate.poi
        annotation = StorefrontAnnotation(
            id=number,
            place_category=candidate.category,
            center=tuple(float(v) for v in centre),
            facing=math.atan2(normal[1], normal[0]),
            size=(float(width), float(built.size[1]), float(built.size[2])),
            entrance=(
                float(entrance_xy[0]),
                float(entrance_xy[1]),
                float(self._height_or(entrance_xy, base)),
            ),
            building=building.id,
            facade=facade.id,
            name=built.name,
            design=f"{built.category}/{built.design}",
            poi=poi.id if poi is not None else None,
            osm=poi.osm if poi is not None else None,
            door_width=1.05,
        )
        self.placed.append(
            _Placed(
                annotation=annotation,
                part=ObjectPart(
                    category=STOREFRONT_CATEGORY,
                    mesh=built.mesh,
                    center=tuple(float(v) for v in centre),
                    yaw=yaw,
                    size=built.size,
                    kind=f"storefront_{candidate.category}",
                    zone="facade",
                    source=f"storefront:{poi.id if poi is not None else 'added'}",
                ),
                building=building.id,
                recess=box,
                front=front,
                sign_points=_sign_points(built, rotation, centre),
                normal=normal,
                facade_point=middle,
                span=span,
                set_back=set_back,
                approach=approach,
            )
        )
        return None

    def _free_stretch(
        self, building: BuildingAnnotation, facade: FacadeAnnotation, want: float, at: float
    ) -> tuple[float, float] | str:
        """The stretch of a facade (m along it) a storefront up to `want` wide takes nearest `at`: clear
        of its corners, of the storefronts there or reaching over from a neighbouring facade, and on
        the building's wall (:meth:`_FacadeFinder.off_wall`); or why there is none."""
        s = self.settings
        start, along, length = _facade_frame(facade)
        normal = np.asarray(facade.normal, dtype=np.float64)
        occupied = list(self.occupied.get(facade.id, []))
        occupied += self._reaching_over(facade, start, along, normal, length)
        span = _free_span(occupied + self._off_wall(building, facade), length, s.corner_margin, want, at)
        if span is not None:
            return span
        if _free_span(occupied, length, s.corner_margin, want, at) is not None:
            return "no straight wall on the facade"
        return "no room on the facade"

    def _door_front(self, door: np.ndarray, normal: np.ndarray, *, set_back: bool) -> float | str:
        """How far the walkable ground is from a door (0 when it opens onto it within
        ``sidewalk_gap``), or why the door has none in front."""
        if not set_back:
            return 0.0 if self._sidewalk_ahead(door, normal) else "no sidewalk in front"
        approach = self._approach(door, normal)
        return "no walkable ground in front" if approach is None else approach

    def _approach(self, door: np.ndarray, normal: np.ndarray) -> float | None:
        """How far (m) a door set back from the street is from the walkable ground it faces, or None.

        The walkable ground faced is the part within ``approach_distance`` of the door and within
        :data:`_APPROACH_HALF_ANGLE` of straight out of it; its point straight ahead, else its
        nearest point, must be reached by a straight line that crosses none of :data:`_BARRIERS`
        (open ground, a lawn, a parking lot or a service road may lie between).
        """
        start = door + normal * 0.05
        reach = self.settings.approach_distance
        if reach <= 0.0:
            return None
        angles = np.linspace(-_APPROACH_HALF_ANGLE, _APPROACH_HALF_ANGLE, 7) + math.atan2(
            normal[1], normal[0]
        )
        arc = start + reach * np.stack([np.cos(angles), np.sin(angles)], axis=1)
        wedge = Polygon([start, *arc])
        if not self.walkable.intersects(wedge):
            return None
        faced = shapely.clip_by_rect(self.walkable, *wedge.bounds).intersection(wedge)
        if faced.is_empty:
            return None
        ahead = LineString([start, start + normal * reach]).intersection(faced)
        ends = [] if ahead.is_empty else [nearest_points(ahead, Point(start))[0]]
        ends.append(nearest_points(faced, Point(start))[0])
        for end in sorted(ends, key=lambda e: (e.distance(Point(start)), e.x, e.y)):
            distance = end.distance(Point(start))
            if distance < 0.1:
                return 0.0
            way = LineString([start, start + (np.asarray(end.coords[0]) - start) * (1.0 - 0.05 / distance)])
            if not way.intersects(self.barriers):
                return float(distance)
        return None

    def _sidewalk_ahead(self, door: np.ndarray, normal: np.ndarray) -> bool:
        """Whether the walkable front is reached from the door, straight out, within the gap allowed
        (a front garden or forecourt of open ground may lie between)."""
        start = Point(door + normal * 0.05)
        ray = LineString([start, door + normal * (self.settings.sidewalk_gap + _ENTRANCE_OUT)])
        walk = ray.intersection(self.walkable)
        if walk.is_empty:
            return False
        road = ray.intersection(self.roads)
        return road.is_empty or start.distance(walk) < start.distance(road)

    def _height_or(self, xy: np.ndarray, default: float) -> float:
        height = self.heights(xy)[0]
        return default if math.isnan(height) else float(height)

    def _reaching_over(
        self,
        facade: FacadeAnnotation,
        start: np.ndarray,
        along: np.ndarray,
        normal: np.ndarray,
        length: float,
    ) -> list[tuple[float, float]]:
        """Spans of this facade that storefronts of other facades reach over (corners)."""
        zone = _rectangle(start, along, normal, 0.0, length, 2.0)
        spans = []
        for other in self.placed:
            if other.annotation.facade == facade.id or not other.front.intersects(zone):
                continue
            coords = np.asarray(other.front.exterior.coords) if hasattr(other.front, "exterior") else None
            if coords is None:
                coords = np.concatenate([np.asarray(g.exterior.coords) for g in other.front.geoms])
            along_other = (coords - start) @ along
            spans.append((float(along_other.min()) - 0.3, float(along_other.max()) + 0.3))
        return spans

    def _blocked_by_building(self, front: BaseGeometry, own: int) -> bool:
        for index in self.footprints.query(front, predicate="intersects"):
            if (
                self.footprint_ids[index] != own
                and self.footprint_shapes[index].intersection(front).area > 0.01
            ):
                return True
        return False

    def drop(self, numbers: set[int]) -> None:
        """Forget placed storefronts (they failed a later check); the buildings are re-carved."""
        keep = [p for p in self.placed if p.annotation.id not in numbers]
        touched = {p.building for p in self.placed if p.annotation.id in numbers}
        originals = {
            number: surface.mesh
            for surface in self.scene.surfaces
            if (number := _building_number(surface.name)) in touched
        }
        for number, mesh in originals.items():
            for p in keep:
                if p.building == number:
                    mesh, _ = carve(mesh, p.recess)
            self.meshes[number] = mesh
        for p in self.placed:
            if p.annotation.id in numbers:
                self.occupied[p.annotation.facade].remove(p.span)
        self.placed = keep

    def build(self) -> tuple[Scene, int]:
        """The scene with the placed storefronts, and how many street objects were cleared."""
        fronts = union_of(p.front for p in self.placed)
        parts, kept = object_parts(self.scene), []
        for part, obj in zip(parts, self.scene.objects, strict=True):
            if not object_box(obj.annotation).intersects(fronts):
                kept.append(part)
        surfaces = []
        for surface in self.scene.surfaces:
            number = _building_number(surface.name)
            mesh = self.meshes.get(number, surface.mesh) if number is not None else surface.mesh
            surfaces.append(Surface(surface.name, surface.terrain_class, mesh))
        first = len(self.existing) + 1
        renumbered = self.existing + [
            p.annotation.model_copy(update={"id": k}) for k, p in enumerate(self.placed, start=first)
        ]
        scene = replace_parts(
            self.scene,
            surfaces=surfaces,
            objects=kept + [p.part for p in self.placed],
            storefronts=renumbered,
        )
        return scene, len(parts) - len(kept)


def object_box(annotation: ObjectAnnotation) -> Polygon:
    """The ground footprint of an object's oriented box."""
    sx, sy = annotation.size[0] / 2, annotation.size[1] / 2
    corners = np.array([[-sx, -sy], [sx, -sy], [sx, sy], [-sx, sy]])
    c, s = math.cos(annotation.yaw), math.sin(annotation.yaw)
    return Polygon(corners @ np.array([[c, s], [-s, c]]) + np.asarray(annotation.center[:2]))


def _sign_points(built: Storefront, rotation: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """3 x 3 points spread over the sign's face (80 % of it), 2 cm in front of it, in the world."""
    cx, cy, cz = built.sign_center
    width, height = built.sign_size
    u, v = np.meshgrid(np.linspace(-0.4, 0.4, 3) * width, np.linspace(-0.4, 0.4, 3) * height)
    local = np.stack([cx + u.ravel(), np.full(9, cy + 0.02), cz + v.ravel()], axis=1)
    return local @ rotation.T + centre


# ------------------------------------------------------------------------------------------ visible


def _invisible(
    scene: Scene, placed: Sequence[_Placed], walkable: BaseGeometry, settings: StorefrontSettings
) -> set[int]:
    """Ids of the storefronts whose sign no walkable point in front of them sees (most of it)."""
    import open3d as o3d

    if not placed:
        return set()
    mesh = scene.world_mesh(include_objects=True).mesh
    origin = mesh.vertices.min(axis=0)
    rays = o3d.t.geometry.RaycastingScene()
    rays.add_triangles(
        o3d.core.Tensor((mesh.vertices - origin).astype(np.float32)),
        o3d.core.Tensor(mesh.faces.astype(np.uint32)),
    )
    heights = SurfaceHeights(scene)
    hidden = set()
    for p in placed:
        radius = settings.view_radius + p.approach  # a set-back sign is seen from beyond its approach
        along = np.array([-p.normal[1], p.normal[0]])
        offsets = np.arange(-radius, radius + 1e-9, 2.0)
        outs = np.arange(1.0, radius + 1e-9, 1.5)
        grid = np.array([p.facade_point + along * a + p.normal * o for a in offsets for o in outs])
        grid = grid[np.hypot(*(grid - p.facade_point).T) <= radius]
        inside = shapely.contains_xy(walkable, grid[:, 0], grid[:, 1])
        views = grid[inside]
        if not len(views):
            hidden.add(p.annotation.id)
            continue
        ground = heights(views)
        views = np.column_stack(
            [views[np.isfinite(ground)], ground[np.isfinite(ground)] + settings.camera_height]
        )
        if not len(views):
            hidden.add(p.annotation.id)
            continue
        starts = np.repeat(views, len(p.sign_points), axis=0)
        targets = np.tile(p.sign_points, (len(views), 1))
        direction = targets - starts
        distance = np.linalg.norm(direction, axis=1)
        cast = np.concatenate([starts - origin, direction / distance[:, None]], axis=1).astype(np.float32)
        t = rays.cast_rays(o3d.core.Tensor(cast))["t_hit"].numpy()
        clear = (t >= distance - 0.05).reshape(len(views), len(p.sign_points))
        if not (clear.sum(axis=1) >= 5).any():
            hidden.add(p.annotation.id)
    return hidden


# ------------------------------------------------------------------------------------------- public


def _candidates(city: CityMap, settings: StorefrontSettings) -> list[_Candidate]:
    found = []
    for poi in sorted(city.pois, key=lambda p: p.id):
        category = place_category(_tags(poi))
        if category is None or (settings.categories is not None and category not in settings.categories):
            continue
        found.append(_Candidate(category=category, name=poi.name, poi=poi))
    return found


def _by_category(candidates: Sequence[_Candidate]) -> list[list[_Candidate]]:
    """Map places by category, each in map order, the rarer categories first (then the one mapped
    first)."""
    groups: dict[str, list[_Candidate]] = {}
    for candidate in candidates:
        groups.setdefault(candidate.category, []).append(candidate)
    return sorted(groups.values(), key=len)


def _in_rounds(placer: _Placer, groups: Sequence[Sequence[_Candidate]]) -> None:
    """Place map places in rounds of their categories (:func:`_by_category`): in each round every
    category with places left tries them in turn until one is placed, so every category has a
    storefront, or has tried all its places, before any has a second (where the facades run short,
    each category has had its turns before any has more)."""
    queues = [list(group)[::-1] for group in groups]
    while any(queues):
        for queue in queues:
            while queue and not placer.place_map_place(queue.pop()):
                pass


def _fill_categories(settings: StorefrontSettings) -> tuple[list[str], np.ndarray]:
    weights: Counter[str] = Counter()
    for key, value, weight, _ in POI_TABLE:
        category = place_category({key: value})
        if category is not None and (settings.categories is None or category in settings.categories):
            weights[category] += weight
    names = sorted(weights)
    total = float(sum(weights.values()))
    return names, np.array([weights[n] / total for n in names])


def place_storefronts(
    scene: Scene, city: CityMap, plan: StreetPlan, rng: np.random.Generator, settings: StorefrontSettings
) -> StorefrontPlacement:
    """Set storefronts into the facades of a city scene at the map's places (module docstring).

    Parameters
    ----------
    scene : Scene
        The city scene (buildings with facades from the city geometry stage, usually populated).
    city : CityMap
        Its map: the places.
    plan : StreetPlan
        Its ground plan: where the sidewalks are.
    rng : numpy.random.Generator
        Source of all randomness (widths, designs, generated names, filled facades).
    settings : StorefrontSettings
        How to place them.

    Returns
    -------
    StorefrontPlacement
    """
    placer = _Placer(scene, plan, rng, settings)
    candidates = _candidates(city, settings)
    _in_rounds(placer, _by_category(candidates))
    (x0, y0, x1, y1) = city.window
    filled = _fill(placer, int(settings.fill_per_km2 * (x1 - x0) * (y1 - y0) / 1e6), rng, settings)
    return _finish(placer, settings, places=len(candidates), filled=filled)


def densify_storefronts(
    scene: Scene,
    plan: StreetPlan,
    rng: np.random.Generator,
    settings: StorefrontSettings,
    *,
    region: BaseGeometry,
    count: int,
) -> StorefrontPlacement:
    """Add up to `count` storefronts on road-facing facades inside `region` (its storefronts kept).

    Categories are drawn from the synthetic cities' place table; the steps and checks are those of
    :func:`place_storefronts` (an indoor-to-outdoor scene's neighbourhood of its exit, for instance).
    """
    placer = _Placer(scene, plan, rng, settings, region=region)
    filled = _fill(placer, count, rng, settings)
    return _finish(placer, settings, places=0, filled=filled)


def _fill(placer: _Placer, wanted: int, rng: np.random.Generator, settings: StorefrontSettings) -> int:
    """Add storefronts on random usable facades until `wanted` are placed; returns the facades tried."""
    filled = 0
    if wanted <= len(placer.placed):
        return filled
    names, weights = _fill_categories(settings)
    for building, facade in placer.fill_facades():
        if len(placer.placed) >= wanted or not names:
            break
        category = names[int(rng.choice(len(names), p=weights))]
        filled += 1
        _, _, length = _facade_frame(facade)
        at = float(rng.uniform(0.3, 0.7)) * length
        reason = placer.place(_Candidate(category, None, None), building, facade, at)
        if reason is not None:
            placer.rejected[reason] += 1
    return filled


def _finish(
    placer: _Placer, settings: StorefrontSettings, *, places: int, filled: int
) -> StorefrontPlacement:
    """Check the signs of the placed storefronts, drop the hidden ones (a map place hidden once tries
    its other facades, then every sign is checked again), and build the scene."""
    result, cleared = placer.build()
    hidden = _invisible(result, placer.placed, placer.walkable, settings)
    if hidden:  # build again without them (fewer storefronts never hide a sign that was seen)
        retried = _drop_hidden(placer, hidden, retry=True)
        if retried:  # the moved ones could hide a sign: check them all again
            hidden = _invisible(placer.build()[0], placer.placed, placer.walkable, settings)
            _drop_hidden(placer, hidden, retry=False)
        result, cleared = placer.build()
    counts = {
        "places": places,
        "filled": filled,
        "placed": len(placer.placed),
        "rejected": dict(sorted(placer.rejected.items())),
        "categories": dict(sorted(Counter(p.annotation.place_category for p in placer.placed).items())),
        "lost": _lost(placer.lost),
        "objects_cleared": cleared,
        "narrowed": placer.narrowed,
        "shifted": placer.shifted,
        "set_back": sum(p.set_back for p in placer.placed),
    }
    return StorefrontPlacement(scene=result, counts=counts)


def _drop_hidden(placer: _Placer, hidden: set[int], *, retry: bool) -> int:
    """Drop the storefronts whose sign is hidden, counting them rejected unless (with `retry`) their
    map place is placed on one of its other facades; returns how many were placed again."""
    if not hidden:
        return 0
    dropped = [p.annotation for p in placer.placed if p.annotation.id in hidden]
    placer.drop(hidden)
    again = 0
    for annotation in dropped:
        if retry and placer.retry(annotation.id):
            again += 1
            continue
        placer.rejected["sign not visible"] += 1
        if annotation.poi is not None:
            placer.lost[annotation.place_category, "sign not visible"] += 1
    return again


def _lost(lost: Counter[tuple[str, str]]) -> dict[str, dict[str, int]]:
    """Map places not placed, ``{category: {reason: n}}``, sorted."""
    nested: dict[str, dict[str, int]] = {}
    for (category, reason), n in sorted(lost.items()):
        nested.setdefault(category, {})[reason] = n
    return nested
