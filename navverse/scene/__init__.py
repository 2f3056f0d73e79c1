"""The scene contract: annotations, in-memory scenes, USD files, scene directories and BEV pictures.

A scene directory holds ``scene.usdc`` (geometry, semantic labels, physics), ``scene.json``
(:class:`SceneAnnotations`) and ``bev.png``. Stages build a :class:`Scene` and call
:func:`write_scene_dir`; everything downstream calls :func:`read_scene` or :func:`read_annotations`.
"""

from navverse.scene.annotations import (
    SCENE_FORMAT_VERSION,
    Bounds,
    BuildingAnnotation,
    DoorAnnotation,
    ExitAnnotation,
    FacadeAnnotation,
    GeoReference,
    ObjectAnnotation,
    RoomAnnotation,
    SceneAnnotations,
    SceneSource,
    SceneStatistics,
    StorefrontAnnotation,
    TerrainClass,
    Vec3,
    footprint_facades,
    load_annotations,
    nearest_facade,
    save_annotations,
)
from navverse.scene.bev import BevInfo, BevOverlay, BevRaster, raster_bev, render_bev
from navverse.scene.colors import default_color, lighten
from navverse.scene.compose import (
    ObjectPart,
    assemble_scene,
    merge_scenes,
    remove_inside,
    transform_scene,
)
from navverse.scene.directory import (
    BEV_PNG,
    NAVMESH_BIN,
    NAVMESH_JSON,
    SCENE_JSON,
    SCENE_USD,
    SceneFiles,
    read_annotations,
    read_scene,
    write_scene_dir,
)
from navverse.scene.geometry import LabeledMesh, MeshData, Scene, SceneObject, Surface
from navverse.scene.naming import object_prim_path, sanitize_identifier
from navverse.scene.terrain import DEFAULT_TERRAIN_CLASSES, terrain_classes
from navverse.scene.usd import (
    UsdObject,
    UsdScene,
    UsdSurface,
    export_usd,
    physics_materials,
    read_usd,
    scene_from_usd,
)

__all__ = [
    "BEV_PNG",
    "DEFAULT_TERRAIN_CLASSES",
    "NAVMESH_BIN",
    "NAVMESH_JSON",
    "SCENE_FORMAT_VERSION",
    "SCENE_JSON",
    "SCENE_USD",
    "BevInfo",
    "BevOverlay",
    "BevRaster",
    "Bounds",
    "BuildingAnnotation",
    "DoorAnnotation",
    "ExitAnnotation",
    "FacadeAnnotation",
    "GeoReference",
    "LabeledMesh",
    "MeshData",
    "ObjectAnnotation",
    "ObjectPart",
    "RoomAnnotation",
    "Scene",
    "SceneAnnotations",
    "SceneFiles",
    "SceneObject",
    "SceneSource",
    "SceneStatistics",
    "StorefrontAnnotation",
    "Surface",
    "TerrainClass",
    "UsdObject",
    "UsdScene",
    "UsdSurface",
    "Vec3",
    "assemble_scene",
    "default_color",
    "export_usd",
    "footprint_facades",
    "lighten",
    "load_annotations",
    "merge_scenes",
    "nearest_facade",
    "object_prim_path",
    "physics_materials",
    "raster_bev",
    "read_annotations",
    "read_scene",
    "read_usd",
    "remove_inside",
    "render_bev",
    "sanitize_identifier",
    "save_annotations",
    "scene_from_usd",
    "terrain_classes",
    "transform_scene",
    "write_scene_dir",
]
