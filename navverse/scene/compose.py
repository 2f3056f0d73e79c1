"""Scenes from parts: assemble, move, merge, and cut geometry out of a volume.

Every scene producer (blockout, mesh import, the building generator, later cities and assembled
indoor-to-outdoor scenes) builds its :class:`~navverse.scene.geometry.Scene` through
:func:`assemble_scene`, which numbers the objects and derives the bounds and the statistics from
the geometry, so that no producer computes them by hand. :func:`transform_scene` moves a whole
scene rigidly (geometry and every annotation), :func:`merge_scenes` joins scenes into one
(renumbering ids, keeping prim names unique, unifying terrain classes), :func:`remove_inside`
cuts away the geometry inside a closed volume with manifold3d (openings in facades) and
:func:`carve` subtracts a volume from one solid (a storefront's recess in its building).
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np
from numpy.typing import ArrayLike
from pydantic import BaseModel

from navverse.errors import SceneError
from navverse.scene.annotations import (
    Bounds,
    BuildingAnnotation,
    GeoReference,
    ObjectAnnotation,
    SceneAnnotations,
    SceneSource,
    SceneStatistics,
    StorefrontAnnotation,
    TerrainClass,
    Vec3,
)
from navverse.scene.geometry import MeshData, Scene, SceneObject, Surface, apply_linear, yaw_matrix
from navverse.scene.naming import object_prim_path, unique_name
from navverse.scene.terrain import terrain_classes as default_terrain_classes
from navverse.scene_types import SceneType

_M = TypeVar("_M", bound=BaseModel)

__all__ = [
    "ObjectPart",
    "assemble_scene",
    "carve",
    "merge_scenes",
    "object_parts",
    "remove_inside",
    "replace_parts",
    "scene_bounds",
    "transform_scene",
]


@dataclass(frozen=True, eq=False)
class ObjectPart:
    """An object to place in a scene; :func:`assemble_scene` gives it its id and prim path.

    Parameters
    ----------
    category : str
        Semantic category (what an agent is asked to find).
    mesh : MeshData
        Geometry in the object's local frame (bounding-box centre at the origin).
    center : tuple of float
        World position of the local origin.
    yaw : float
        Rotation about +z (radians).
    size : tuple of float, optional
        Extent along the object's own axes; by default the extent of ``mesh``.
    kind : str, optional
        What the object is, naming its prim (``<kind>_<id>``); by default ``category``.
    zone, group, source : str, optional
        Where it stands, its contextual group and what placed it (see
        :class:`~navverse.scene.annotations.ObjectAnnotation`).
    """

    category: str
    mesh: MeshData
    center: Vec3
    yaw: float = 0.0
    size: Vec3 | None = None
    kind: str | None = None
    zone: str | None = None
    group: str | None = None
    source: str | None = None

    def extent(self) -> Vec3:
        """``size``, or the extent of the local mesh."""
        if self.size is not None:
            return self.size
        lo, hi = self.mesh.bounds()
        extent = hi - lo
        return (float(extent[0]), float(extent[1]), float(extent[2]))


def object_parts(scene: Scene) -> list[ObjectPart]:
    """The objects of a scene as parts (to re-assemble them, e.g. into a merged scene)."""
    return [
        ObjectPart(
            category=o.annotation.category,
            mesh=o.mesh,
            center=o.annotation.center,
            yaw=o.annotation.yaw,
            size=o.annotation.size,
            kind=o.annotation.prim_path.rsplit("/", 1)[1].rsplit("_", 1)[0],
            zone=o.annotation.zone,
            group=o.annotation.group,
            source=o.annotation.source,
        )
        for o in scene.objects
    ]


def scene_bounds(surfaces: Iterable[Surface], objects: Iterable[SceneObject]) -> Bounds:
    """Axis-aligned bounds of every vertex of the surfaces and of the objects placed in the world.

    Raises
    ------
    SceneError
        If there is no geometry at all.
    """
    lows, highs = [], []
    for mesh in [s.mesh for s in surfaces] + [o.world_mesh() for o in objects]:
        if mesh.num_vertices:
            lows.append(mesh.vertices.min(axis=0))
            highs.append(mesh.vertices.max(axis=0))
    if not lows:
        raise SceneError("a scene needs some geometry: every surface and object is empty")
    lo, hi = np.min(lows, axis=0), np.max(highs, axis=0)
    return Bounds(min=tuple(float(v) for v in lo), max=tuple(float(v) for v in hi))


def assemble_scene(
    *,
    scene_id: str,
    scene_type: SceneType,
    surfaces: Sequence[Surface],
    objects: Sequence[ObjectPart] = (),
    buildings: Sequence[BuildingAnnotation] = (),
    storefronts: Sequence[StorefrontAnnotation] = (),
    terrain_classes: Mapping[str, TerrainClass] | None = None,
    indoor_anchor: Vec3 | None = None,
    road_length_m: float = 0.0,
    geo: GeoReference | None = None,
    source: SceneSource | None = None,
) -> Scene:
    """Build a scene from its parts, with bounds and statistics derived from them.

    Parameters
    ----------
    scene_id, scene_type : str
        The scene's id and type.
    surfaces : sequence of Surface
        Terrain geometry in world coordinates.
    objects : sequence of ObjectPart
        Objects, numbered 1, 2, ... in this order (prim paths ``/World/Objects/<kind>_<id>``).
    buildings, storefronts : sequence
        Annotations, kept as given.
    terrain_classes : mapping, optional
        The scene's terrain classes in the order their area types are numbered; by default the
        standard classes of the surfaces, sorted by name.
    indoor_anchor : tuple of float, optional
        The indoor anchor point of an indoor-to-outdoor scene.
    road_length_m : float
        Length of the road centre lines (statistics).
    geo : GeoReference, optional
        The map frame of a scene made from a map.
    source : SceneSource, optional
        Recipe and toolkit version.

    Returns
    -------
    Scene
        ``bounds`` enclose every vertex; ``statistics`` count faces (surfaces and objects),
        buildings and objects per category.

    Raises
    ------
    SceneError
        If there is no geometry, or a surface's class is not among ``terrain_classes``.
    """
    placed = []
    for index, part in enumerate(objects, start=1):
        annotation = ObjectAnnotation(
            id=index,
            category=part.category,
            prim_path=object_prim_path(part.kind or part.category, index),
            center=tuple(float(v) for v in part.center),
            size=part.extent(),
            yaw=float(part.yaw),
            zone=part.zone,
            group=part.group,
            source=part.source,
        )
        placed.append(SceneObject(annotation=annotation, mesh=part.mesh))
    classes = dict(
        terrain_classes
        if terrain_classes is not None
        else default_terrain_classes(sorted({s.terrain_class for s in surfaces}))
    )
    missing = sorted({s.terrain_class for s in surfaces} - set(classes))
    if missing:
        raise SceneError(f"surfaces use terrain classes the scene does not list: {', '.join(missing)}")
    annotations = SceneAnnotations(
        scene_id=scene_id,
        scene_type=scene_type,
        bounds=scene_bounds(surfaces, placed),
        objects=[o.annotation for o in placed],
        storefronts=list(storefronts),
        buildings=list(buildings),
        indoor_anchor=indoor_anchor,
        geo=geo,
        terrain_classes=classes,
        statistics=SceneStatistics(
            faces=sum(s.mesh.num_faces for s in surfaces) + sum(o.mesh.num_faces for o in placed),
            buildings=len(buildings),
            road_length_m=road_length_m,
            objects_per_category=dict(sorted(Counter(o.annotation.category for o in placed).items())),
        ),
        source=source,
    )
    return Scene(annotations=annotations, surfaces=tuple(surfaces), objects=tuple(placed))


_KEEP = object()


def replace_parts(
    scene: Scene,
    *,
    surfaces: Sequence[Surface] | None = None,
    objects: Sequence[ObjectPart] | None = None,
    buildings: Sequence[BuildingAnnotation] | None = None,
    storefronts: Sequence[StorefrontAnnotation] | None = None,
    indoor_anchor: Vec3 | object | None = _KEEP,
    geo: GeoReference | object | None = _KEEP,
    scene_id: str | None = None,
) -> Scene:
    """The scene with some of its parts replaced; bounds and statistics are derived again.

    Parts not given are kept; objects are renumbered in order. Terrain classes, the scene type, the
    road length and the source are kept, and so is the map frame (``geo``) unless given.
    """
    ann = scene.annotations
    return assemble_scene(
        scene_id=scene_id or ann.scene_id,
        scene_type=ann.scene_type,
        surfaces=scene.surfaces if surfaces is None else surfaces,
        objects=object_parts(scene) if objects is None else objects,
        buildings=ann.buildings if buildings is None else buildings,
        storefronts=ann.storefronts if storefronts is None else storefronts,
        terrain_classes=ann.terrain_classes,
        indoor_anchor=ann.indoor_anchor if indoor_anchor is _KEEP else indoor_anchor,
        road_length_m=ann.statistics.road_length_m,
        geo=ann.geo if geo is _KEEP else geo,
        source=ann.source,
    )


# ------------------------------------------------------------------------------- rigid transforms


class _Rigid:
    """A rotation by ``yaw`` about +z followed by a translation, applied to annotation values."""

    def __init__(self, translation: ArrayLike, yaw: float) -> None:
        self.offset = np.asarray(translation, dtype=np.float64).reshape(3)
        self.yaw = float(yaw)
        self.rotation = yaw_matrix(self.yaw)

    @property
    def is_identity(self) -> bool:
        """Whether it moves nothing."""
        return self.yaw == 0.0 and not self.offset.any()

    def point(self, xyz: Sequence[float]) -> Vec3:
        moved = apply_linear(xyz, self.rotation) + self.offset
        return (float(moved[0]), float(moved[1]), float(moved[2]))

    def xy(self, point: Sequence[float]) -> tuple[float, float]:
        moved = apply_linear(point, self.rotation[:2, :2]) + self.offset[:2]
        return (float(moved[0]), float(moved[1]))

    def direction(self, xy: Sequence[float]) -> tuple[float, float]:
        turned = apply_linear(xy, self.rotation[:2, :2])
        length = math.hypot(turned[0], turned[1])
        return (float(turned[0] / length), float(turned[1] / length))

    def angle(self, yaw: float) -> float:
        return math.remainder(yaw + self.yaw, math.tau)

    def building(self, b: BuildingAnnotation) -> BuildingAnnotation:
        dz = float(self.offset[2])
        return b.model_copy(
            update={
                "footprint": [self.xy(p) for p in b.footprint],
                "base_height": b.base_height + dz,
                "rooms": [
                    r.model_copy(
                        update={
                            "polygon": [self.xy(p) for p in r.polygon],
                            "floor_height": r.floor_height + dz,
                        }
                    )
                    for r in b.rooms
                ],
                "doors": [
                    _validated(d, center=self.point(d.center), facing=self.angle(d.facing)) for d in b.doors
                ],
                "exits": [
                    _validated(e, center=self.point(e.center), facing=self.angle(e.facing)) for e in b.exits
                ],
                "facades": [
                    f.model_copy(
                        update={
                            "segment": (self.xy(f.segment[0]), self.xy(f.segment[1])),
                            "normal": self.direction(f.normal),
                        }
                    )
                    for f in b.facades
                ],
            }
        )

    def storefront(self, s: StorefrontAnnotation) -> StorefrontAnnotation:
        return s.model_copy(
            update={
                "center": self.point(s.center),
                "entrance": self.point(s.entrance),
                "facing": self.angle(s.facing),
            }
        )


def transform_scene(
    scene: Scene, *, translation: ArrayLike = (0.0, 0.0, 0.0), yaw: float = 0.0, scene_id: str | None = None
) -> Scene:
    """Move a whole scene rigidly: rotate it by ``yaw`` about the world's +z axis, then translate it.

    Surfaces, objects (their centres and yaws; local meshes are unchanged), buildings (footprints,
    heights, rooms, doors, exits, facades), storefronts and the indoor anchor all move together;
    bounds are derived again. A scene that moves loses its map frame (``geo``), which no longer
    describes it.

    Parameters
    ----------
    scene : Scene
        The scene to move.
    translation : array_like, shape (3,)
        Offset added after the rotation (m).
    yaw : float
        Rotation about +z (radians).
    scene_id : str, optional
        Id of the result; by default the scene's own.

    Returns
    -------
    Scene
    """
    rigid = _Rigid(translation, yaw)
    ann = scene.annotations
    surfaces = [
        Surface(s.name, s.terrain_class, s.mesh.transformed(rigid.offset, rigid.yaw)) for s in scene.surfaces
    ]
    objects = [
        ObjectPart(
            category=p.category,
            mesh=p.mesh,
            center=rigid.point(p.center),
            yaw=rigid.angle(p.yaw),
            size=p.size,
            kind=p.kind,
        )
        for p in object_parts(scene)
    ]
    return replace_parts(
        scene,
        scene_id=scene_id,
        surfaces=surfaces,
        objects=objects,
        buildings=[rigid.building(b) for b in ann.buildings],
        storefronts=[rigid.storefront(s) for s in ann.storefronts],
        indoor_anchor=rigid.point(ann.indoor_anchor) if ann.indoor_anchor is not None else None,
        geo=ann.geo if rigid.is_identity else None,
    )


# ----------------------------------------------------------------------------------------- merging


class _Numbering:
    """Hands out fresh ids, one counter per kind of annotation, across the scenes being merged."""

    def __init__(self) -> None:
        self.next: Counter[str] = Counter()

    def renumber(self, kind: str, ids: Iterable[int]) -> dict[int, int]:
        mapping = {}
        for old in ids:
            self.next[kind] += 1
            mapping[old] = self.next[kind]
        return mapping


def merge_scenes(
    scenes: Sequence[Scene],
    *,
    scene_id: str,
    scene_type: SceneType,
    source: SceneSource | None = None,
) -> Scene:
    """Join scenes (already placed in one world frame) into one scene.

    Objects are renumbered 1, 2, ... in scene order (prim paths follow), as are buildings, rooms,
    doors, exits, facades and storefronts (references between them follow); a surface whose name is
    taken gets a suffix ``_2``, ``_3``...; terrain classes are unified in order of first appearance.
    The first scene's indoor anchor is kept, and the first map frame (``geo``) any scene has.

    Parameters
    ----------
    scenes : sequence of Scene
        At least one scene.
    scene_id, scene_type : str
        The merged scene's id and type.
    source : SceneSource, optional
        The merged scene's source (by default the first scene's).

    Returns
    -------
    Scene

    Raises
    ------
    SceneError
        If no scene is given or two scenes define a terrain class of the same name differently.
    """
    if not scenes:
        raise SceneError("merge_scenes needs at least one scene")
    classes: dict[str, TerrainClass] = {}
    for scene in scenes:
        for name, terrain_class in scene.annotations.terrain_classes.items():
            if name in classes and classes[name] != terrain_class:
                raise SceneError(
                    f"cannot merge scenes: terrain class {name!r} differs between them "
                    f"({classes[name].model_dump()} vs {terrain_class.model_dump()}); define it once"
                )
            classes.setdefault(name, terrain_class)
    numbering = _Numbering()
    taken: set[str] = set()
    surfaces: list[Surface] = []
    objects: list[ObjectPart] = []
    buildings: list[BuildingAnnotation] = []
    storefronts: list[StorefrontAnnotation] = []
    for scene in scenes:
        ann = scene.annotations
        surfaces += [Surface(unique_name(s.name, taken), s.terrain_class, s.mesh) for s in scene.surfaces]
        objects += object_parts(scene)
        building_ids = numbering.renumber("building", [b.id for b in ann.buildings])
        room_ids = numbering.renumber("room", [r.id for r in ann.rooms])
        door_ids = numbering.renumber("door", [d.id for d in ann.doors])
        exit_ids = numbering.renumber("exit", [e.id for e in ann.exits])
        facade_ids = numbering.renumber("facade", [f.id for b in ann.buildings for f in b.facades])
        for b in ann.buildings:
            buildings.append(
                b.model_copy(
                    update={
                        "id": building_ids[b.id],
                        "rooms": [r.model_copy(update={"id": room_ids[r.id]}) for r in b.rooms],
                        "doors": [
                            d.model_copy(
                                update={"id": door_ids[d.id], "rooms": tuple(room_ids[r] for r in d.rooms)}
                            )
                            for d in b.doors
                        ],
                        "exits": [
                            e.model_copy(
                                update={
                                    "id": exit_ids[e.id],
                                    "facade": facade_ids[e.facade] if e.facade is not None else None,
                                }
                            )
                            for e in b.exits
                        ],
                        "facades": [f.model_copy(update={"id": facade_ids[f.id]}) for f in b.facades],
                    }
                )
            )
        storefront_ids = numbering.renumber("storefront", [s.id for s in ann.storefronts])
        storefronts += [
            s.model_copy(
                update={
                    "id": storefront_ids[s.id],
                    "building": building_ids[s.building] if s.building is not None else None,
                    "facade": facade_ids[s.facade] if s.facade is not None else None,
                }
            )
            for s in ann.storefronts
        ]
    first = scenes[0].annotations
    return assemble_scene(
        scene_id=scene_id,
        scene_type=scene_type,
        surfaces=surfaces,
        objects=objects,
        buildings=buildings,
        storefronts=storefronts,
        terrain_classes=classes,
        indoor_anchor=first.indoor_anchor,
        geo=next((s.annotations.geo for s in scenes if s.annotations.geo is not None), None),
        road_length_m=sum(s.annotations.statistics.road_length_m for s in scenes),
        source=source or first.source,
    )


# ---------------------------------------------------------------------------------------- cutting


def _manifold(mesh: MeshData) -> tuple[Any, int] | None:
    """The mesh as a manifold3d solid, or None if it is not a closed solid, and the original id its
    triangles carry: each keeps its index as face id, so a boolean's result names the source
    triangle of each of its faces."""
    import manifold3d

    original = int(manifold3d.Manifold.reserve_ids(1))
    solid = manifold3d.Manifold(
        manifold3d.Mesh(
            vert_properties=np.ascontiguousarray(mesh.vertices, dtype=np.float32),
            tri_verts=np.ascontiguousarray(mesh.faces, dtype=np.uint32),
            run_index=np.array([0, 3 * mesh.num_faces], dtype=np.uint32),
            run_original_id=np.array([original], dtype=np.uint32),
            face_id=np.arange(mesh.num_faces, dtype=np.uint32),
        )
    )
    if solid.status() != manifold3d.Error.NoError or solid.is_empty():
        return None
    return solid, original


def _mesh_of(solid, original: MeshData, original_id: int) -> MeshData:
    """A manifold's triangles as a mesh; faces that came from `original` keep its colour and texture.

    Manifold may split an original triangle: the pieces' corner UVs are interpolated in it
    (barycentric coordinates of each corner in the original triangle). New faces of a cut take the
    first face colour and no texture.
    """
    out = solid.to_mesh()
    vertices = np.asarray(out.vert_properties, dtype=np.float64)[:, :3]
    faces = np.asarray(out.tri_verts, dtype=np.int64).reshape(-1, 3)
    if original.face_colors is None and not original.textured:
        return MeshData(vertices, faces)
    face_ids = np.asarray(out.face_id, dtype=np.int64)
    run_index = np.asarray(out.run_index, dtype=np.int64)
    from_original = np.zeros(len(faces), dtype=bool)
    for run, source in enumerate(np.asarray(out.run_original_id, dtype=np.int64)):
        if source == original_id:
            from_original[run_index[run] // 3 : run_index[run + 1] // 3] = True
    source_face = np.where(from_original, face_ids, -1)
    colors = None
    if original.face_colors is not None:
        colors = np.empty((len(faces), 3), dtype=np.uint8)
        colors[:] = original.face_colors[0]
        colors[from_original] = original.face_colors[source_face[from_original]]
    if not original.textured:
        return MeshData(vertices, faces, colors)
    texture = np.full(len(faces), -1, dtype=np.int16)
    uvs = np.zeros((len(faces), 3, 2), dtype=np.float32)
    textured = from_original.copy()
    textured[from_original] = original.face_texture[source_face[from_original]] >= 0
    if textured.any():
        src = source_face[textured]
        texture[textured] = original.face_texture[src]
        uvs[textured] = _interpolated_uvs(
            original.vertices[original.faces[src]], original.face_uvs[src], vertices[faces[textured]]
        )
    return MeshData(vertices, faces, colors, uvs, texture, original.textures)


def _interpolated_uvs(triangles: np.ndarray, uvs: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """UVs of `corners` (K, 3, 3) inside `triangles` (K, 3, 3) whose corners have `uvs` (K, 3, 2)."""
    p0 = triangles[:, 0, None, :]
    e1, e2 = triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0]
    d = corners - p0
    d11, d12, d22 = (e1 * e1).sum(-1), (e1 * e2).sum(-1), (e2 * e2).sum(-1)
    d1 = np.einsum("kcj,kj->kc", d, e1)
    d2 = np.einsum("kcj,kj->kc", d, e2)
    det = d11 * d22 - d12 * d12
    det = np.where(np.abs(det) > 1e-18, det, 1.0)[:, None]
    b1 = (d22[:, None] * d1 - d12[:, None] * d2) / det
    b2 = (d11[:, None] * d2 - d12[:, None] * d1) / det
    b0 = 1.0 - b1 - b2
    weights = np.stack([b0, b1, b2], axis=-1)  # (K, corner, source corner)
    return np.einsum("kcs,ksj->kcj", weights, uvs.astype(np.float64)).astype(np.float32)


def _box_solid(size: Sequence[float], center: Sequence[float], yaw: float):
    import manifold3d

    box = manifold3d.Manifold.cube(tuple(float(v) for v in size), center=True)
    degrees = math.degrees(yaw)
    return box.rotate((0.0, 0.0, degrees)).translate(tuple(float(v) for v in center))


def carve(mesh: MeshData, volume: MeshData) -> tuple[MeshData, float]:
    """Subtract a closed volume from a closed solid (e.g. a storefront's recess from a building).

    Parameters
    ----------
    mesh : MeshData
        A closed, consistently oriented solid; its faces keep their colours and textures where
        they survive (pieces of a split textured face get interpolated UVs).
    volume : MeshData
        The closed solid to remove.

    Returns
    -------
    carved : MeshData
        The solid without the volume.
    removed : float
        The volume taken away (m³): the part of `volume` that was inside `mesh`.

    Raises
    ------
    SceneError
        If either mesh is not a closed solid.
    """
    cutter = _manifold(volume)
    if cutter is None:
        raise SceneError("the volume to cut must be a closed, consistently oriented solid mesh")
    solid = _manifold(mesh)
    if solid is None:
        raise SceneError("only a closed, consistently oriented solid can be carved")
    result = solid[0] - cutter[0]
    return _mesh_of(result, mesh, solid[1]), float(solid[0].volume() - result.volume())


def remove_inside(scene: Scene, volume: MeshData) -> Scene:
    """Cut away everything inside a closed volume (e.g. the opening of a door in a facade).

    Every surface that is a closed solid loses the part inside the volume (a manifold3d boolean
    difference; faces kept from the surface keep their colour, the new faces of the cut take the
    surface's first colour). An open surface (a floor plane, a terrain sheet) loses the triangles
    whose three corners are inside. Objects whose oriented box meets the volume are removed with
    their annotations; the rest are renumbered. Empty surfaces are dropped.

    Parameters
    ----------
    scene : Scene
        The scene to cut.
    volume : MeshData
        A closed, consistently oriented triangle mesh in world coordinates.

    Returns
    -------
    Scene

    Raises
    ------
    SceneError
        If ``volume`` is not a closed solid.
    """
    made = _manifold(volume)
    if made is None:
        raise SceneError("the volume to cut must be a closed, consistently oriented solid mesh")
    cutter = made[0]
    surfaces: list[Surface] = []
    for surface in scene.surfaces:
        mesh = _cut_surface(surface.mesh, cutter)
        if mesh.num_faces:
            surfaces.append(Surface(surface.name, surface.terrain_class, mesh))
    objects = []
    for part, obj in zip(object_parts(scene), scene.objects, strict=True):
        box = _box_solid(obj.annotation.size, obj.annotation.center, obj.annotation.yaw)
        if (box ^ cutter).is_empty():
            objects.append(part)
    return replace_parts(scene, surfaces=surfaces, objects=objects)


def _cut_surface(mesh: MeshData, cutter) -> MeshData:
    if mesh.num_faces == 0:
        return mesh
    made = _manifold(mesh)
    if made is not None:
        solid, original = made
        if (solid ^ cutter).is_empty():
            return mesh  # untouched: keep the exact input
        return _mesh_of(solid - cutter, mesh, original)
    import open3d as o3d

    cut = cutter.to_mesh()
    solid = o3d.t.geometry.RaycastingScene()
    origin = mesh.vertices.min(axis=0)
    solid.add_triangles(
        o3d.core.Tensor((np.asarray(cut.vert_properties)[:, :3] - origin).astype(np.float32)),
        o3d.core.Tensor(np.asarray(cut.tri_verts, dtype=np.uint32)),
    )
    occupancy = solid.compute_occupancy(o3d.core.Tensor((mesh.vertices - origin).astype(np.float32)))
    corner_inside = occupancy.numpy() > 0.5
    return mesh.face_subset(~corner_inside[mesh.faces].all(axis=1))


def _validated(model: _M, **changes: Any) -> _M:
    """`model` with `changes`, validated (``model_copy(update=...)`` is not: positions would not be
    rounded as the annotations round them)."""
    return type(model).model_validate({**dict(model), **changes})
