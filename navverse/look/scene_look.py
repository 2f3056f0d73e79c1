"""A scene's look compiled for the renderer: the material under every hit point and its overlays.

:func:`scene_look` reads a scene once and decides, per face of its world mesh (the renderer's order:
visible surfaces, then objects), what the face is: an object (its own colours), a plain surface of a
material (by terrain class: asphalt roads, slab sidewalks, curb stones, grass...), a floor (its
material by the type of the room the hit is in), a wall (paint inside a room, render with a plinth
outside), a facade (:mod:`navverse.look.facades`), a roof, a road (markings from the map:
:mod:`navverse.look.markings`) or a crosswalk (the mapped crossing's markings: zebra stripes along its
long side, lines along its long edges, both, dashed edge lines, or none).
:meth:`SceneLook.surface` then gives, for the hits of a frame, the material tile to sample (the
surface's own, or what is painted over it) and the surface coordinates to sample it at.

Surface coordinates are in meters: ``(x, y)`` on faces that look up or down, along-the-wall and
height on the others (for facades, from the facade's own start and the building's base, so windows
sit in whole bays). Materials repeat as tiles (:func:`~navverse.look.materials.bake_tile`), baked once
per material and variant in a process.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from functools import cache, lru_cache
from typing import get_args

import numpy as np
import shapely
from numba import njit

from navverse.city.map import CityMap, CrossingMarkings
from navverse.look.facades import OVERLAY_NAMES, FacadeFrames, facade_frames
from navverse.look.markings import MarkedRoad, RoadMarkings, road_markings
from navverse.look.materials import (
    CLASS_MATERIALS,
    MATERIAL_NAMES,
    MATERIALS,
    bake_tile,
    facade_style,
    material_index,
    room_floor,
)
from navverse.look.patterns import cell_value
from navverse.look.rooms import RoomLights, room_lights
from navverse.look.settings import LookSettings
from navverse.scene.annotations import BuildingAnnotation
from navverse.scene.geometry import MeshData, Scene, unit_face_normals

__all__ = [
    "CROSSING_MARKINGS",
    "EDGE_LINE",
    "KIND_NAMES",
    "MapDetails",
    "SceneLook",
    "SurfaceLook",
    "map_details",
    "material_tiles",
    "scene_look",
]

OBJECT, PLAIN, FLOOR, WALL, FACADE, CROSSWALK, ROAD = range(7)
KIND_NAMES = ("object", "plain", "floor", "wall", "facade", "crosswalk", "road")
"""What a face is, by its kind number in :attr:`SceneLook.face_kind`."""
_BUILDING_SURFACE = re.compile(r"^building_(\d+)$")  # a city building's solid, named by its id
_UPWARD = 0.5  # |normal z| at and above which a face is floor-like (coordinates x, y)
_PLINTH = 0.4  # meters of plinth at the foot of outer walls
_STRIPE = 0.5  # zebra stripe and gap width, and dash and gap length (m)
_MARKED_WITHIN = 8.0  # a crosswalk patch shows the markings of a mapped crossing this near its centre (m)
CROSSING_MARKINGS: tuple[CrossingMarkings, ...] = get_args(CrossingMarkings)
"""Crossing markings by their code in :attr:`SceneLook.crossings` (column 5)."""
EDGE_LINE = 0.25
"""Width of the lines along a crossing's edges (m)."""
_ZEBRA, _LINES, _LADDER, _DASHES = (
    CROSSING_MARKINGS.index(m) for m in ("zebra", "lines", "ladder", "dashes")
)
_OVERLAY_MATERIALS = np.array([material_index(name) for name in OVERLAY_NAMES], dtype=np.int32)
TILE_SEED = 1000
"""Seed of the baked material tiles (variants tint and shift them; they are baked once)."""
VARIANT_BRIGHTNESS = 0.2
"""Largest relative change of a material's brightness in a material variant."""
VARIANT_HUE = 0.08
"""Largest relative change of one colour channel of a material in a material variant."""


@dataclass(frozen=True)
class MapDetails:
    """What a city map adds to a scene's look: building types and levels, the roads' and the crossings'
    markings.

    Attributes
    ----------
    buildings : dict
        By scene building id, its map type (``building=*``, None for ``yes``) and levels (or None).
    roads : list of MarkedRoad
        The mapped roads.
    crossings : list of tuple
        The mapped crossings: position x, y and markings (one of :data:`CROSSING_MARKINGS`).
    """

    buildings: dict[int, tuple[str | None, float | None]]
    roads: list[MarkedRoad]
    crossings: list[tuple[float, float, str]] = field(default_factory=list)


def map_details(scene: Scene, city_map: CityMap) -> MapDetails:
    """The map details of a city scene made from `city_map` (its buildings name their map ids)."""
    by_map_id = {b.id: b for b in city_map.buildings}
    buildings = {}
    for building in scene.annotations.buildings:
        mapped = by_map_id.get(building.map_id) if building.map_id else None
        if mapped is not None:
            buildings[building.id] = (None if mapped.type in (None, "yes") else mapped.type, mapped.levels)
    roads = [
        MarkedRoad(
            tuple((float(x), float(y)) for x, y in r.centerline.points), r.width, r.lanes, r.oneway, r.highway
        )
        for r in city_map.roads
    ]
    crossings = [(float(c.position[0]), float(c.position[1]), str(c.markings)) for c in city_map.crossings]
    return MapDetails(buildings=buildings, roads=roads, crossings=crossings)


@dataclass(frozen=True)
class SurfaceLook:
    """What the renderer shows at `K` hits: the material tile to sample where.

    Attributes
    ----------
    tile : ndarray of int32, shape (K,)
        Index into :attr:`SceneLook.tiles` of each hit's material: the surface's own, or what is
        painted over it (windows, frames, doors, plinths, stripes, lane markings).
    u, v : ndarray of float64, shape (K,)
        Surface coordinates in meters.
    reflect : ndarray of float32, shape (K,)
        Share of the sky each hit mirrors (glass, water).
    modulate : ndarray of bool, shape (K,)
        Hits on objects: their tile (``object_grain``) modulates the face's own colour, relative to the
        tile's base colour, instead of replacing it.
    """

    tile: np.ndarray
    u: np.ndarray
    v: np.ndarray
    reflect: np.ndarray
    modulate: np.ndarray


@dataclass(frozen=True, eq=False)
class SceneLook:
    """A scene's look for the renderer (see the module's docstring); made by :func:`scene_look`.

    Attributes
    ----------
    settings : LookSettings
        The look's settings.
    rooms : RoomLights
        The rooms' lamps and raster.
    tiles : tuple of ndarray
        Baked sRGB tiles ``(n, n, 3)``, one per material of
        :data:`~navverse.look.materials.MATERIAL_NAMES`.
    tile_sizes : ndarray of float64, shape (T,)
        Side of each tile in meters.
    face_kind, face_material, face_frame : ndarray, shape (F + 1,)
        Per face (and the miss row): its kind, its material (plain surfaces, roofs; ``-1`` for
        objects) and its frame (facades: a row of `facades`; crosswalks: a row of `crossings`; ``-1``
        otherwise).
    face_normals : ndarray of float64, shape (F + 1, 3)
        Unit face normals (zero on objects and the miss row).
    facades : FacadeFrames
        The facade frames.
    crossings : ndarray of float64, shape (C, 6)
        Per crosswalk patch: a corner (x, y), the unit direction of its long side (x, y), its width
        (the short side, m) and its markings' code in :data:`CROSSING_MARKINGS` (those of the mapped
        crossing nearest its centre within 8 m, zebra where none is).
    room_floor : ndarray of int32, shape (R,)
        Each room's floor material.
    markings : RoadMarkings or None
        The road markings (None without a map).
    tint, shift : ndarray of float32, shape (T, 3) and (T, 2)
        The material variant: a colour factor per material (linear RGB) and a shift of its pattern (m).
    buildings : tuple of BuildingAnnotation
        The scene's buildings (facade frames are remade from them for other settings).
    details : MapDetails or None
        The map details the look was made with.
    """

    settings: LookSettings
    rooms: RoomLights
    tiles: tuple[np.ndarray, ...]
    tile_sizes: np.ndarray
    face_kind: np.ndarray
    face_material: np.ndarray
    face_frame: np.ndarray
    face_normals: np.ndarray
    facades: FacadeFrames
    crossings: np.ndarray
    room_floor: np.ndarray
    markings: RoadMarkings | None
    tint: np.ndarray
    shift: np.ndarray
    buildings: tuple
    details: MapDetails | None

    def room_of(self, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
        """The room of each hit at world `points` on faces with unit `normals` turned towards the viewer:
        the room holding the point lifted 5 cm off its surface (so a wall's face belongs to the room it
        faces), ``-1`` in the open."""
        if self.rooms.empty:
            return np.full(len(points), -1, dtype=np.int32)
        return self.rooms.room_at(points, lift=normals * np.float32(0.05))

    def with_settings(self, settings: LookSettings) -> SceneLook:
        """This look under other settings: the same scene and map, other facade picks and material
        variants (cheap: nothing about the surfaces is recomputed)."""
        facades, _ = facade_frames(self.buildings, _facade_styles(self.buildings, self.details, settings))
        tint, shift = _variant(settings.material_variant)
        return replace(self, settings=settings, facades=facades, tint=tint, shift=shift)

    def surface(
        self, face: np.ndarray, points: np.ndarray, normal: np.ndarray, room: np.ndarray
    ) -> SurfaceLook:
        """The tiles, coordinates and overlays at hits on `face` (``(K,)`` world-mesh face indices) at
        world `points` ``(K, 3)`` (float64) on faces of unit `normal` ``(K, 3)`` in rooms `room` (``(K,)``,
        ``-1`` in the open: see :meth:`room_of`)."""
        count = len(face)
        kind = np.empty(count, dtype=self.face_kind.dtype)
        material = np.empty(count, dtype=np.int32)
        u, v = np.empty(count), np.empty(count)
        _base_surface(self.face_kind, self.face_material, face, points, normal, kind, material, u, v)
        reflect = np.zeros(len(face), dtype=np.float32)
        inside = np.flatnonzero((kind == FLOOR) | (kind == WALL))
        if len(inside):
            their_room = room[inside]
            is_floor = kind[inside] == FLOOR
            floors = is_floor & (their_room >= 0)
            material[inside[floors]] = self.room_floor.take(their_room[floors])
            material[inside[~is_floor & (their_room >= 0)]] = material_index("wall_paint")
            outer = inside[~is_floor & (their_room < 0)]
            material[outer] = material_index("render")
            base = float(self.rooms.floors.min()) if not self.rooms.empty else 0.0
            material[outer[points[outer, 2] - base < _PLINTH]] = material_index("plinth")
        facade = np.flatnonzero(kind == FACADE)
        if len(facade):
            paint = self.facades.paint(self.face_frame.take(face.take(facade)), points[facade])
            u[facade], v[facade] = paint.s, paint.h
            material[facade] = paint.wall
            painted = paint.overlay >= 0
            material[facade[painted]] = _OVERLAY_MATERIALS.take(paint.overlay[painted])
            reflect[facade[paint.overlay == OVERLAY_NAMES.index("glass")]] = MATERIALS["glass"].reflect
        crosswalk = np.flatnonzero(kind == CROSSWALK)
        if len(crosswalk):
            patch = self.crossings.take(self.face_frame.take(face.take(crosswalk)), axis=0)
            material[crosswalk[_crossing_paint(patch, points[crosswalk])]] = material_index("marking")
        roads = np.flatnonzero(kind == ROAD)
        if len(roads) and self.markings is not None:
            material[roads[self.markings.painted(points[roads])]] = material_index("marking")
        reflect[(material == material_index("water")) & (kind == PLAIN)] = MATERIALS["water"].reflect
        objects = kind == OBJECT
        material[objects] = material_index("object_grain")
        return SurfaceLook(tile=material, u=u, v=v, reflect=reflect, modulate=objects)


def _crossing_paint(patch: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Whether each hit on a crosswalk at world `points` ``(K, 3)`` is painted, by its patch's row
    ``(K, 6)`` of :attr:`SceneLook.crossings`: zebra bars across the whole width, 0.5 m wide and apart
    along the long side; lines along both long edges; a ladder both; dashes the lines in 0.5 m pieces."""
    rx, ry = points[:, 0] - patch[:, 0], points[:, 1] - patch[:, 1]
    along = rx * patch[:, 2] + ry * patch[:, 3]
    across = np.abs(patch[:, 2] * ry - patch[:, 3] * rx)  # from the long edge through the corner
    code = patch[:, 5]
    bars = np.mod(along, 2.0 * _STRIPE) < _STRIPE
    edges = (across < EDGE_LINE) | (across > patch[:, 4] - EDGE_LINE)
    return (
        (bars & ((code == _ZEBRA) | (code == _LADDER)))
        | (edges & ((code == _LINES) | (code == _LADDER)))
        | (edges & bars & (code == _DASHES))
    )


@njit(cache=True, nogil=True)
def _base_surface(
    face_kind: np.ndarray,
    face_material: np.ndarray,
    face: np.ndarray,
    points: np.ndarray,
    normal: np.ndarray,
    kind: np.ndarray,
    material: np.ndarray,
    u: np.ndarray,
    v: np.ndarray,
) -> None:
    """Per hit: its face's kind and material, and its surface coordinates: ``(x, y)`` on floor-like
    faces, else the distance along the wall's horizontal direction and the height."""
    for k in range(face.shape[0]):
        f = face[k]
        kind[k] = face_kind[f]
        material[k] = face_material[f]
        nx, ny, nz = normal[k, 0], normal[k, 1], normal[k, 2]
        if abs(nz) >= _UPWARD:
            u[k], v[k] = points[k, 0], points[k, 1]
        else:
            horizontal = math.sqrt(nx * nx + ny * ny)
            if horizontal == 0.0:
                horizontal = 1.0
            u[k] = (points[k, 1] * nx - points[k, 0] * ny) / horizontal
            v[k] = points[k, 2]


@cache
def material_tiles() -> tuple[np.ndarray, ...]:
    """Every material's tile, in :data:`~navverse.look.materials.MATERIAL_NAMES` order (baked once per
    process; read-only)."""
    tiles = tuple(bake_tile(MATERIALS[name], seed=TILE_SEED) for name in MATERIAL_NAMES)
    for tile in tiles:
        tile.setflags(write=False)
    return tiles


@lru_cache(maxsize=64)
def _variant(variant: int) -> tuple[np.ndarray, np.ndarray]:
    """The colour factors ``(T, 3)`` and pattern shifts ``(T, 2)`` of a material variant: none for 0;
    else each material lighter or darker by up to :data:`VARIANT_BRIGHTNESS` and its hue moved by up
    to :data:`VARIANT_HUE` per channel, its pattern shifted by a fraction of its tile."""
    count = len(MATERIAL_NAMES)
    if variant == 0:
        return np.ones((count, 3), dtype=np.float32), np.zeros((count, 2), dtype=np.float32)
    index = np.arange(count)
    draws = [cell_value(index, np.full(count, k), variant) for k in range(6)]
    brightness = 1.0 + VARIANT_BRIGHTNESS * (2.0 * draws[0] - 1.0)
    hue = 1.0 + VARIANT_HUE * (2.0 * np.stack(draws[1:4], axis=1) - 1.0)
    tint = (brightness[:, None] * hue).astype(np.float32)
    sizes = np.array([MATERIALS[name].tile for name in MATERIAL_NAMES])
    shift = (np.stack(draws[4:6], axis=1) * sizes[:, None]).astype(np.float32)
    return tint, shift


def _facade_styles(
    buildings: Sequence[BuildingAnnotation], details: MapDetails | None, settings: LookSettings
) -> dict[int, tuple[str, float | None]]:
    """Each building's facade style and levels: by its map type where known, houses brick or render
    by the material variant."""
    known = details.buildings if details is not None else {}
    styles = {}
    for building in buildings:
        map_type, levels = known.get(building.id, (None, None))
        pick = float(cell_value(np.array([building.id]), np.array([0]), settings.material_variant)[0])
        styles[building.id] = (facade_style(map_type, pick=pick), levels)
    return styles


def scene_look(
    scene: Scene,
    settings: LookSettings,
    *,
    hidden_classes: Sequence[str] = (),
    details: MapDetails | None = None,
) -> SceneLook:
    """Compile the look of `scene` for the renderer.

    Parameters
    ----------
    scene : Scene
        The scene.
    settings : LookSettings
        The look's settings (its material variant picks the materials' variants and the houses' walls).
    hidden_classes : sequence of str
        Terrain classes the renderer leaves out (the face order follows it).
    details : MapDetails, optional
        The city map's building types and levels, its roads and crossings (:func:`map_details`);
        without them, buildings are houses of brick or render with storeys from their height, roads
        bare and crosswalks zebras.

    Returns
    -------
    SceneLook
    """
    hidden = set(hidden_classes)
    styles = _facade_styles(scene.annotations.buildings, details, settings)
    facades, facade_rows = facade_frames(scene.annotations.buildings, styles)
    buildings = {b.id: b for b in scene.annotations.buildings}
    crossings: list[tuple[float, ...]] = []
    mapped = _mapped_crossings(details)
    kinds, materials, frames, normals = [], [], [], []
    for surface in scene.surfaces:
        if surface.terrain_class in hidden:
            continue
        mesh = surface.mesh
        face_normals = unit_face_normals(mesh.vertices, mesh.faces)
        kind = np.full(mesh.num_faces, PLAIN, dtype=np.int8)
        material = np.full(
            mesh.num_faces, material_index(CLASS_MATERIALS.get(surface.terrain_class, "concrete"))
        )
        frame = np.full(mesh.num_faces, -1, dtype=np.int32)
        match = _BUILDING_SURFACE.match(surface.name)
        if surface.terrain_class == "floor":
            kind[:] = FLOOR
        elif surface.terrain_class == "wall":
            kind[:] = WALL
        elif surface.terrain_class == "road":
            kind[:] = ROAD
        elif surface.terrain_class == "crosswalk":
            kind[:] = CROSSWALK
            frame[:] = _crosswalk_patches(mesh, crossings, mapped)
        elif surface.terrain_class == "building" and match and int(match.group(1)) in buildings:
            building = buildings[int(match.group(1))]
            up = np.abs(face_normals[:, 2]) >= _UPWARD
            material[up] = material_index("roof")
            walls = np.flatnonzero(~up)
            if building.facades and len(walls):
                kind[walls] = FACADE
                frame[walls] = [
                    facade_rows[(building.id, f)]
                    for f in _nearest_facades(building, mesh, face_normals, walls)
                ]
        kinds.append(kind)
        materials.append(material)
        frames.append(frame)
        normals.append(face_normals)
    for obj in scene.objects:
        n = obj.mesh.num_faces
        kinds.append(np.full(n, OBJECT, dtype=np.int8))
        materials.append(np.full(n, -1))
        frames.append(np.full(n, -1, dtype=np.int32))
        normals.append(np.zeros((n, 3)))
    rooms = room_lights(scene.annotations)
    tint, shift = _variant(settings.material_variant)
    return SceneLook(
        settings=settings,
        rooms=rooms,
        tiles=material_tiles(),
        tile_sizes=np.array([MATERIALS[name].tile for name in MATERIAL_NAMES]),
        face_kind=np.concatenate([*kinds, [OBJECT]]).astype(np.int8),
        face_material=np.concatenate([*materials, [-1]]).astype(np.int16),
        face_frame=np.concatenate([*frames, [-1]]).astype(np.int32),
        face_normals=np.concatenate([*normals, np.zeros((1, 3))]),
        facades=facades,
        crossings=np.asarray(crossings, dtype=np.float64).reshape(-1, 6),
        room_floor=np.array([material_index(room_floor(t)) for t in rooms.room_types], dtype=np.int32),
        markings=road_markings(details.roads) if details is not None and details.roads else None,
        tint=tint,
        shift=shift,
        buildings=tuple(scene.annotations.buildings),
        details=details,
    )


def _nearest_facades(
    building: BuildingAnnotation, mesh: MeshData, face_normals: np.ndarray, walls: np.ndarray
) -> list[int]:
    """The facade (id) of each wall face of a building's solid: the one whose outward normal agrees
    with the face's and whose line runs nearest the face's centre."""
    segments = np.array([f.segment for f in building.facades], dtype=np.float64)
    outward = np.array([f.normal for f in building.facades], dtype=np.float64)
    centers = mesh.vertices[mesh.faces[walls]].mean(axis=1)[:, :2]
    normals = face_normals[walls, :2]
    offset = np.abs(centers @ outward.T - np.einsum("nk,nk->n", segments[:, 0], outward)[None, :])
    disagreement = 1.0 - normals @ outward.T
    best = np.argmin(offset + 10.0 * disagreement, axis=1)
    return [building.facades[k].id for k in best]


def _mapped_crossings(details: MapDetails | None) -> tuple[np.ndarray, np.ndarray]:
    """The mapped crossings' positions ``(M, 2)`` and markings' codes ``(M,)`` (none without a map)."""
    crossings = details.crossings if details is not None else []
    positions = np.array([(x, y) for x, y, _ in crossings], dtype=np.float64).reshape(-1, 2)
    codes = np.array([CROSSING_MARKINGS.index(m) for _, _, m in crossings], dtype=np.float64)
    return positions, codes


def _markings_code(centre: np.ndarray, mapped: tuple[np.ndarray, np.ndarray]) -> float:
    """The markings' code of a crosswalk patch centred at `centre`: the nearest mapped crossing's within
    8 m, zebra where none is."""
    positions, codes = mapped
    if not len(positions):
        return float(_ZEBRA)
    distance = np.hypot(positions[:, 0] - centre[0], positions[:, 1] - centre[1])
    nearest = int(np.argmin(distance))
    return float(codes[nearest]) if distance[nearest] <= _MARKED_WITHIN else float(_ZEBRA)


def _crosswalk_patches(
    mesh: MeshData, crossings: list[tuple[float, ...]], mapped: tuple[np.ndarray, np.ndarray]
) -> np.ndarray:
    """The patch (a row appended to `crossings`: a corner, the direction of its long side, its width and
    its markings' code from the `mapped` crossings' positions and codes) of each face of a crosswalk
    surface; a patch is a piece of faces joined by corners within 2 cm in plan."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    corners = mesh.vertices[mesh.faces][:, :, :2].reshape(-1, 2)  # face f's corners are 3f .. 3f + 2
    count = len(corners)
    near = cKDTree(corners).query_pairs(0.02, output_type="ndarray")
    same_face = np.arange(count) // 3 * 3
    rows = np.concatenate([near[:, 0], np.arange(count)])
    cols = np.concatenate([near[:, 1], same_face])
    graph = coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(count, count))
    _, label = connected_components(graph, directed=False)
    patch_of_face = label[0::3]
    first = len(crossings)
    patches, index = np.unique(patch_of_face, return_inverse=True)
    for patch in patches:
        points = corners.reshape(-1, 3, 2)[patch_of_face == patch].reshape(-1, 2)
        box = np.asarray(shapely.MultiPoint(points).minimum_rotated_rectangle.exterior.coords)[:4]
        edges = np.diff(np.vstack([box, box[:1]]), axis=0)
        lengths = np.hypot(edges[:, 0], edges[:, 1])
        longest = edges[np.argmax(lengths)]
        direction = longest / max(float(np.hypot(*longest)), 1e-9)
        code = _markings_code(box.mean(axis=0), mapped)
        corner = (float(box[0, 0]), float(box[0, 1]))
        crossings.append((*corner, float(direction[0]), float(direction[1]), float(lengths.min()), code))
    return first + index.astype(np.int32)
