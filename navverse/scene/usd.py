"""Write a :class:`~navverse.scene.geometry.Scene` to USD and read it back.

Layout of the stage (z up, meters, default prim ``/World``)::

    /World/PhysicsScene           UsdPhysics.Scene, gravity 9.81 m/s^2 along -z
    /World/Looks/<class>          UsdPreviewSurface per terrain class (+ ``objects``)
    /World/Looks/Textures/<name>  UsdPreviewSurface showing texture <name> (only in textured scenes)
    /World/Physics/<class>        physics material per terrain class (+ ``objects``)
    /World/Terrain/<surface>      Mesh, collider, terrain class, semantic label
    /World/Objects/<name>         Xform (translate, rotateZ) with category, instance id, size, label
    /World/Objects/<name>/mesh    Mesh in the object's local frame, collider
    /World/Buildings/<building>   footprint, heights, rooms, doors, exits, facades (see usd_buildings)

Vertex positions are stored as ``point3f`` (float32, ~0.1 mm at 1 km from the origin); object
placements use double-precision xform ops. Colours are stored in ``displayColor`` as linear RGB
(converted from the sRGB values of the annotations) and the look materials read that primvar, so
per-face colours show in usdview and Isaac Sim.

Textured meshes also hold ``primvars:st`` (faceVarying texture coordinates, one per face corner) and
one ``GeomSubset`` per texture (family ``materialBind``, its faces) bound to the texture's material,
a ``UsdUVTexture`` reading ``./textures/<name>.png`` beside the ``.usdc`` file. Faces in no subset
keep the mesh's own look. Subsets are bound to the mesh's physics material too, so per-subset
physics resolves to the same friction.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PIL import Image, UnidentifiedImageError
from pxr import Gf, Sdf, Tf, Usd, UsdGeom, UsdPhysics, UsdSemantics, UsdShade, Vt

from navverse.errors import SceneError, rebuild_hint
from navverse.files import atomic_path
from navverse.scene.annotations import BuildingAnnotation, SceneAnnotations
from navverse.scene.colors import default_color, linear_to_srgb, srgb_to_linear
from navverse.scene.geometry import MeshData, Scene, SceneObject, Surface, Texture
from navverse.scene.naming import (
    LOOKS_ROOT,
    OBJECTS_ROOT,
    PHYSICS_ROOT,
    TERRAIN_ROOT,
    TEXTURES_DIR,
    WORLD_PATH,
)
from navverse.scene.usd_buildings import read_buildings, write_buildings

__all__ = [
    "ATTR_CATEGORY",
    "ATTR_INSTANCE_ID",
    "ATTR_SIZE",
    "ATTR_TERRAIN_CLASS",
    "GRAVITY",
    "OBJECT_FRICTION",
    "OBJECT_MATERIAL",
    "SEMANTIC_TAXONOMY",
    "TEXTURES_DIR",
    "UsdObject",
    "UsdScene",
    "UsdSurface",
    "define_texture_material",
    "export_usd",
    "physics_materials",
    "read_usd",
    "scene_from_usd",
    "texture_asset_path",
]

GRAVITY = 9.81
OBJECT_FRICTION = 0.6
OBJECT_MATERIAL = "objects"
PHYSICS_PURPOSE = "physics"
SEMANTIC_TAXONOMY = "class"
ATTR_TERRAIN_CLASS = "navverse:terrainClass"
ATTR_CATEGORY = "navverse:category"
ATTR_INSTANCE_ID = "navverse:instanceId"
ATTR_SIZE = "navverse:size"
OBJECT_MESH_NAME = "mesh"
TEXTURE_LOOKS = "Textures"
ST_PRIMVAR = "st"
_TEXTURE_SUBSET_PREFIX = "texture_"
_TEXTURE_SHADER = "UsdUVTexture"
# zlib level of the texture PNGs: fixed, so the same pixels always give the same bytes.
_PNG_COMPRESS_LEVEL = 6

# float32 storage of friction and positions; comparisons against scene.json use these tolerances.
_FRICTION_TOL = 1e-6
_POSITION_TOL = 1e-6
_ANGLE_TOL = 1e-6


# ----------------------------------------------------------------------------------------- colours


def _vec3f(rgb: tuple[int, int, int]) -> Gf.Vec3f:
    return Gf.Vec3f(*(float(v) for v in srgb_to_linear(np.array(rgb))))


# ------------------------------------------------------------------------------------------ export


def export_usd(scene: Scene, path: Path) -> None:
    """Write `scene` as a USD crate file.

    The same scene always gives byte-identical files. The file is written next to `path` under a
    temporary name and renamed into place, so readers never see a partial file.

    Parameters
    ----------
    scene : Scene
        The scene to write.
    path : Path
        Destination, ending in ``.usdc``; its directory must exist.

    Raises
    ------
    SceneError
        If `path` does not end in ``.usdc`` or its directory does not exist.
    ValueError
        If two textures of the scene share a name but not their pixels, or a textured scene has a
        terrain class named ``Textures`` (the prim that holds the texture materials).

    Notes
    -----
    The textures the faces use are written first, as ``textures/<name>.png`` beside `path` (each
    atomically; the same pixels always give the same bytes), so a reader of the new ``.usdc`` finds
    them. Other files in ``textures/`` are left alone.
    """
    path = Path(path)
    if path.suffix != ".usdc":
        raise SceneError(f"USD scenes are written as crate files; give a path ending in '.usdc', not {path}")
    if not path.parent.is_dir():
        raise SceneError(f"cannot write {path}: directory {path.parent} does not exist; create it first")
    textures = _scene_textures(scene)
    if textures and TEXTURE_LOOKS in scene.annotations.terrain_classes:
        raise ValueError(f"terrain class name {TEXTURE_LOOKS!r} clashes with the scope of the texture looks")
    _write_textures(textures.values(), path.parent / TEXTURES_DIR)
    # CreateNew refuses a path whose layer is still open in this process: the temporary name is fresh.
    with atomic_path(path) as tmp:
        stage = Usd.Stage.CreateNew(str(tmp))
        _populate(stage, scene, textures)
        stage.Save()
        del stage


def texture_asset_path(name: str) -> str:
    """The asset path of texture `name` as a scene file refers to it, relative to the ``.usdc``.

    Parameters
    ----------
    name : str
        The texture's name.

    Returns
    -------
    str
        ``./textures/<name>.png``.
    """
    return f"./{TEXTURES_DIR}/{name}.png"


def _used_textures(mesh: MeshData) -> list[Texture]:
    if not mesh.textured:
        return []
    used = np.unique(mesh.face_texture[mesh.face_texture >= 0])
    return [mesh.textures[i] for i in used]


def _scene_textures(scene: Scene) -> dict[str, Texture]:
    """The textures any face of the scene shows, by name, sorted by name."""
    meshes = [s.mesh for s in scene.surfaces] + [o.mesh for o in scene.objects]
    found: dict[str, Texture] = {}
    for texture in (t for mesh in meshes for t in _used_textures(mesh)):
        known = found.setdefault(texture.name, texture)
        if not known.same_image(texture):
            raise ValueError(f"two different images of the scene are both named {texture.name!r}")
    return dict(sorted(found.items()))


def _write_textures(textures: Iterable[Texture], directory: Path) -> None:
    textures = list(textures)
    if not textures:
        return
    directory.mkdir(exist_ok=True)
    for texture in textures:
        with atomic_path(directory / f"{texture.name}.png") as tmp:
            Image.fromarray(texture.image).save(
                tmp, format="PNG", compress_level=_PNG_COMPRESS_LEVEL, optimize=False
            )


def _populate(stage: Usd.Stage, scene: Scene, textures: Mapping[str, Texture]) -> None:
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    UsdPhysics.SetStageKilogramsPerUnit(stage, 1.0)
    world = UsdGeom.Xform.Define(stage, WORLD_PATH)
    stage.SetDefaultPrim(world.GetPrim())

    physics_scene = UsdPhysics.Scene.Define(stage, f"{WORLD_PATH}/PhysicsScene")
    physics_scene.CreateGravityDirectionAttr(Gf.Vec3f(0.0, 0.0, -1.0))
    physics_scene.CreateGravityMagnitudeAttr(GRAVITY)

    UsdGeom.Scope.Define(stage, LOOKS_ROOT)
    UsdGeom.Scope.Define(stage, PHYSICS_ROOT)
    looks: dict[str, UsdShade.Material] = {}
    physics: dict[str, UsdShade.Material] = {}
    for name, terrain_class in scene.annotations.terrain_classes.items():
        looks[name] = _define_look(stage, name, terrain_class.color)
        physics[name] = _define_physics_material(stage, name, terrain_class.friction)
    looks[OBJECT_MATERIAL] = _define_look(stage, OBJECT_MATERIAL, (200, 200, 200))
    physics[OBJECT_MATERIAL] = _define_physics_material(stage, OBJECT_MATERIAL, OBJECT_FRICTION)
    texture_looks = _define_texture_looks(stage, textures)

    UsdGeom.Xform.Define(stage, TERRAIN_ROOT)
    for surface in scene.surfaces:
        color = scene.annotations.terrain_classes[surface.terrain_class].color
        mesh = _define_mesh(stage, f"{TERRAIN_ROOT}/{surface.name}", surface.mesh, color)
        prim = mesh.GetPrim()
        _make_collider(prim, looks[surface.terrain_class], physics[surface.terrain_class])
        _bind_textures(mesh, surface.mesh, texture_looks, physics[surface.terrain_class])
        prim.CreateAttribute(ATTR_TERRAIN_CLASS, Sdf.ValueTypeNames.String, custom=True).Set(
            surface.terrain_class
        )
        _label(prim, surface.terrain_class)

    UsdGeom.Xform.Define(stage, OBJECTS_ROOT)
    for obj in scene.objects:
        _define_object(stage, obj, looks[OBJECT_MATERIAL], physics[OBJECT_MATERIAL], texture_looks)
    write_buildings(stage, scene.annotations.buildings)


def _define_look(stage: Usd.Stage, name: str, color: tuple[int, int, int]) -> UsdShade.Material:
    material = UsdShade.Material.Define(stage, f"{LOOKS_ROOT}/{name}")
    reader = UsdShade.Shader.Define(stage, f"{LOOKS_ROOT}/{name}/DisplayColor")
    reader.CreateIdAttr("UsdPrimvarReader_float3")
    reader.CreateInput("varname", Sdf.ValueTypeNames.Token).Set("displayColor")
    reader.CreateInput("fallback", Sdf.ValueTypeNames.Float3).Set(_vec3f(color))
    reader.CreateOutput("result", Sdf.ValueTypeNames.Float3)
    shader = UsdShade.Shader.Define(stage, f"{LOOKS_ROOT}/{name}/PreviewSurface")
    shader.CreateIdAttr("UsdPreviewSurface")
    shader.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f).ConnectToSource(
        reader.ConnectableAPI(), "result"
    )
    shader.CreateInput("roughness", Sdf.ValueTypeNames.Float).Set(0.8)
    shader.CreateInput("metallic", Sdf.ValueTypeNames.Float).Set(0.0)
    material.CreateSurfaceOutput().ConnectToSource(shader.ConnectableAPI(), "surface")
    return material


def _define_texture_looks(stage: Usd.Stage, textures: Mapping[str, Texture]) -> dict[str, UsdShade.Material]:
    if not textures:
        return {}
    UsdGeom.Scope.Define(stage, f"{LOOKS_ROOT}/{TEXTURE_LOOKS}")
    return {name: _define_texture_look(stage, name) for name in sorted(textures)}


def _define_texture_look(stage: Usd.Stage, name: str) -> UsdShade.Material:
    """A material showing ``textures/<name>.png`` through the ``st`` coordinates of the mesh."""
    return define_texture_material(
        stage, f"{LOOKS_ROOT}/{TEXTURE_LOOKS}/{name}", texture_asset_path(name), primvar=ST_PRIMVAR
    )


def define_texture_material(
    stage: Usd.Stage,
    path: str,
    asset: str,
    *,
    primvar: str,
    scale: tuple[float, float, float] | None = None,
    roughness: float = 0.8,
) -> UsdShade.Material:
    """A ``UsdPreviewSurface`` material at `path` whose diffuse colour is the image `asset` (an sRGB
    ``UsdUVTexture``, repeating) read through the mesh's texture-coordinate primvar `primvar`.

    Parameters
    ----------
    stage : Usd.Stage
        Where to define it.
    path : str
        The material's prim path.
    asset : str
        The image's asset path (relative to the layer).
    primvar : str
        The primvar of texture coordinates it reads.
    scale : tuple of float, optional
        A factor per colour channel (the texture's ``scale`` input).
    roughness : float
        The surface's roughness.
    """
    material = UsdShade.Material.Define(stage, path)
    reader = UsdShade.Shader.Define(stage, f"{path}/TexCoords")
    reader.CreateIdAttr("UsdPrimvarReader_float2")
    reader.CreateInput("varname", Sdf.ValueTypeNames.String).Set(primvar)
    reader.CreateOutput("result", Sdf.ValueTypeNames.Float2)
    texture = UsdShade.Shader.Define(stage, f"{path}/Texture")
    texture.CreateIdAttr(_TEXTURE_SHADER)
    texture.CreateInput("file", Sdf.ValueTypeNames.Asset).Set(Sdf.AssetPath(asset))
    texture.CreateInput("st", Sdf.ValueTypeNames.Float2).ConnectToSource(reader.ConnectableAPI(), "result")
    texture.CreateInput("wrapS", Sdf.ValueTypeNames.Token).Set("repeat")
    texture.CreateInput("wrapT", Sdf.ValueTypeNames.Token).Set("repeat")
    texture.CreateInput("sourceColorSpace", Sdf.ValueTypeNames.Token).Set("sRGB")
    if scale is not None:
        texture.CreateInput("scale", Sdf.ValueTypeNames.Float4).Set((*map(float, scale), 1.0))
    texture.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)
    shader = UsdShade.Shader.Define(stage, f"{path}/PreviewSurface")
    shader.CreateIdAttr("UsdPreviewSurface")
    shader.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f).ConnectToSource(
        texture.ConnectableAPI(), "rgb"
    )
    shader.CreateInput("roughness", Sdf.ValueTypeNames.Float).Set(float(roughness))
    shader.CreateInput("metallic", Sdf.ValueTypeNames.Float).Set(0.0)
    material.CreateSurfaceOutput().ConnectToSource(shader.ConnectableAPI(), "surface")
    return material


def _define_physics_material(stage: Usd.Stage, name: str, friction: float) -> UsdShade.Material:
    material = UsdShade.Material.Define(stage, f"{PHYSICS_ROOT}/{name}")
    api = UsdPhysics.MaterialAPI.Apply(material.GetPrim())
    api.CreateStaticFrictionAttr(float(friction))
    api.CreateDynamicFrictionAttr(float(friction))
    api.CreateRestitutionAttr(0.0)
    return material


def _define_mesh(stage: Usd.Stage, path: str, mesh: MeshData, color: tuple[int, int, int]) -> UsdGeom.Mesh:
    usd_mesh = UsdGeom.Mesh.Define(stage, path)
    points = mesh.vertices.astype(np.float32)
    usd_mesh.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(points))
    usd_mesh.CreateFaceVertexCountsAttr(Vt.IntArray.FromNumpy(np.full(mesh.num_faces, 3, dtype=np.int32)))
    usd_mesh.CreateFaceVertexIndicesAttr(Vt.IntArray.FromNumpy(mesh.faces.reshape(-1).astype(np.int32)))
    usd_mesh.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    if mesh.num_vertices:
        lo, hi = points.min(axis=0), points.max(axis=0)
        usd_mesh.CreateExtentAttr(Vt.Vec3fArray([Gf.Vec3f(*map(float, lo)), Gf.Vec3f(*map(float, hi))]))
    if mesh.face_colors is not None:
        colors = srgb_to_linear(mesh.face_colors).astype(np.float32)
        primvar = usd_mesh.CreateDisplayColorPrimvar(UsdGeom.Tokens.uniform)
        primvar.Set(Vt.Vec3fArray.FromNumpy(colors))
    else:
        primvar = usd_mesh.CreateDisplayColorPrimvar(UsdGeom.Tokens.constant)
        primvar.Set(Vt.Vec3fArray([_vec3f(color)]))
    if mesh.textured:
        st = UsdGeom.PrimvarsAPI(usd_mesh).CreatePrimvar(
            ST_PRIMVAR, Sdf.ValueTypeNames.TexCoord2fArray, UsdGeom.Tokens.faceVarying
        )
        st.Set(Vt.Vec2fArray.FromNumpy(np.ascontiguousarray(mesh.face_uvs.reshape(-1, 2), dtype=np.float32)))
    return usd_mesh


def _bind_textures(
    usd_mesh: UsdGeom.Mesh,
    mesh: MeshData,
    texture_looks: Mapping[str, UsdShade.Material],
    physics: UsdShade.Material,
) -> None:
    """Bind the faces of each texture, a ``materialBind`` subset, to the texture's look.

    The subsets are named ``texture_<name>`` and made in name order. Each is bound to `physics` for
    purpose ``physics`` too, so whoever resolves physics materials per subset finds the mesh's.
    """
    if not mesh.textured:
        return
    binding = UsdShade.MaterialBindingAPI(usd_mesh.GetPrim())
    for index, texture in sorted(enumerate(mesh.textures), key=lambda item: item[1].name):
        faces = np.flatnonzero(mesh.face_texture == index).astype(np.int32)
        if faces.size == 0:
            continue
        subset = binding.CreateMaterialBindSubset(
            f"{_TEXTURE_SUBSET_PREFIX}{texture.name}", Vt.IntArray.FromNumpy(faces), UsdGeom.Tokens.face
        )
        subset_binding = UsdShade.MaterialBindingAPI.Apply(subset.GetPrim())
        subset_binding.Bind(texture_looks[texture.name])
        subset_binding.Bind(physics, UsdShade.Tokens.fallbackStrength, PHYSICS_PURPOSE)
    binding.SetMaterialBindSubsetsFamilyType(UsdGeom.Tokens.nonOverlapping)


def _make_collider(prim: Usd.Prim, look: UsdShade.Material, physics: UsdShade.Material) -> None:
    UsdPhysics.CollisionAPI.Apply(prim)
    UsdPhysics.MeshCollisionAPI.Apply(prim).CreateApproximationAttr(UsdPhysics.Tokens.none)
    binding = UsdShade.MaterialBindingAPI.Apply(prim)
    binding.Bind(look)
    binding.Bind(physics, UsdShade.Tokens.fallbackStrength, PHYSICS_PURPOSE)


def _label(prim: Usd.Prim, label: str) -> None:
    labels = UsdSemantics.LabelsAPI.Apply(prim, SEMANTIC_TAXONOMY)
    labels.CreateLabelsAttr(Vt.TokenArray([label]))


def _define_object(
    stage: Usd.Stage,
    obj: SceneObject,
    look: UsdShade.Material,
    physics: UsdShade.Material,
    texture_looks: Mapping[str, UsdShade.Material],
) -> None:
    ann = obj.annotation
    xform = UsdGeom.Xform.Define(stage, ann.prim_path)
    xform.AddTranslateOp(UsdGeom.XformOp.PrecisionDouble).Set(Gf.Vec3d(*ann.center))
    xform.AddRotateZOp(UsdGeom.XformOp.PrecisionDouble).Set(math.degrees(ann.yaw))
    prim = xform.GetPrim()
    prim.CreateAttribute(ATTR_CATEGORY, Sdf.ValueTypeNames.String, custom=True).Set(ann.category)
    prim.CreateAttribute(ATTR_INSTANCE_ID, Sdf.ValueTypeNames.Int, custom=True).Set(ann.id)
    prim.CreateAttribute(ATTR_SIZE, Sdf.ValueTypeNames.Float3, custom=True).Set(Gf.Vec3f(*ann.size))
    _label(prim, ann.category)
    mesh = _define_mesh(stage, f"{ann.prim_path}/{OBJECT_MESH_NAME}", obj.mesh, default_color(ann.category))
    _make_collider(mesh.GetPrim(), look, physics)
    _bind_textures(mesh, obj.mesh, texture_looks, physics)


# -------------------------------------------------------------------------------------------- read


@dataclass(frozen=True, eq=False)
class UsdSurface:
    """A terrain mesh as stored in a USD file."""

    name: str
    prim_path: str
    terrain_class: str
    mesh: MeshData
    labels: tuple[str, ...]
    physics_material: str
    static_friction: float
    dynamic_friction: float


@dataclass(frozen=True, eq=False)
class UsdObject:
    """An object as stored in a USD file; `position` and `yaw` come from its world transform."""

    prim_path: str
    instance_id: int
    category: str
    position: np.ndarray
    yaw: float
    size: tuple[float, float, float]
    mesh: MeshData
    labels: tuple[str, ...]
    physics_material: str
    static_friction: float
    dynamic_friction: float


@dataclass(frozen=True, eq=False)
class UsdScene:
    """What a scene USD file says: stage metadata, terrain surfaces, objects and buildings, in file
    order (``buildings`` is ``None`` for a file written before scenes held buildings)."""

    up_axis: str
    meters_per_unit: float
    default_prim: str
    surfaces: tuple[UsdSurface, ...]
    objects: tuple[UsdObject, ...]
    buildings: tuple[BuildingAnnotation, ...] | None = None


def _open(path: Path) -> Usd.Stage:
    path = Path(path)
    if not path.is_file():
        raise SceneError(f"USD scene not found: {path}; build the scene with `navverse build <scene_id>`")
    try:
        return Usd.Stage.Open(str(path), Usd.Stage.LoadAll)
    except Tf.ErrorException as exc:
        raise SceneError(f"cannot open USD scene {path}: {exc}; {rebuild_hint()}") from None


def _malformed(path: Path, what: str) -> SceneError:
    return SceneError(f"{path} is not a NavVerse scene: {what}; {rebuild_hint()}")


def _triangle_corners(path: Path, prim: Usd.Prim, counts: np.ndarray, num_indices: int) -> np.ndarray:
    """Fan-triangulate polygons: the face-vertex (corner) numbers of each triangle, and its polygon.

    Polygon p with n corners starting at s gives triangles (s, s+k+1, s+k+2) for k in 0..n-3 (a
    no-op for the triangles this module writes). Returns an (T, 4) array: three corners, polygon.
    """
    if (counts.size and counts.min() < 3) or counts.sum() != num_indices:
        raise _malformed(path, f"mesh {prim.GetPath()} has inconsistent face vertex counts")
    triangles_per_polygon = counts - 2
    polygon = np.repeat(np.arange(counts.size), triangles_per_polygon)
    first_triangle = np.cumsum(triangles_per_polygon) - triangles_per_polygon
    k = np.arange(polygon.size) - np.repeat(first_triangle, triangles_per_polygon)
    start = (np.cumsum(counts) - counts)[polygon]
    return np.stack([start, start + k + 1, start + k + 2, polygon], axis=1)


def _read_mesh(path: Path, prim: Usd.Prim, *, cache: dict[Path, Texture] | None = None) -> MeshData:
    """Read a mesh prim as triangles, with face colours and textures when it has them.

    `cache` maps texture files to textures already read, so meshes sharing a file share its image.
    """
    mesh = UsdGeom.Mesh(prim)
    points = mesh.GetPointsAttr().Get()
    counts = mesh.GetFaceVertexCountsAttr().Get()
    indices = mesh.GetFaceVertexIndicesAttr().Get()
    if points is None or counts is None or indices is None:
        raise _malformed(path, f"mesh {prim.GetPath()} lacks points or faces")
    vertices = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    counts_np = np.asarray(counts, dtype=np.int64)
    indices_np = np.asarray(indices, dtype=np.int64)
    corners = _triangle_corners(path, prim, counts_np, indices_np.size)
    polygon = corners[:, 3]
    faces = indices_np[corners[:, :3]].reshape(-1, 3)
    colors = None
    primvar = UsdGeom.PrimvarsAPI(prim).GetPrimvar("displayColor")
    if primvar and primvar.GetInterpolation() == UsdGeom.Tokens.uniform:
        values = primvar.Get()
        if values is not None and len(values) == counts_np.size:
            colors = linear_to_srgb(np.asarray(values, dtype=np.float64).reshape(-1, 3))[polygon]
    uvs, face_texture, textures = _read_textures(
        path, prim, corners, counts_np, {} if cache is None else cache
    )
    try:
        return MeshData(vertices, faces, colors, uvs, face_texture, textures)
    except ValueError as exc:
        raise _malformed(path, f"mesh {prim.GetPath()}: {exc}") from None


def _texture_asset(material: UsdShade.Material) -> Sdf.AssetPath | None:
    """The file of the ``UsdUVTexture`` feeding the material's diffuse colour, if any."""
    surface, _, _ = material.ComputeSurfaceSource()
    diffuse = surface.GetInput("diffuseColor") if surface else None
    sources = diffuse.GetConnectedSources()[0] if diffuse else []
    for source in sources:
        shader = UsdShade.Shader(source.source.GetPrim())
        if shader and shader.GetIdAttr().Get() == _TEXTURE_SHADER:
            file = shader.GetInput("file")
            value = file.Get() if file else None
            return value if isinstance(value, Sdf.AssetPath) and value.path else None
    return None


def _texture_subsets(prim: Usd.Prim) -> list[tuple[np.ndarray, Sdf.AssetPath, str]]:
    """``(polygon indices, texture file, material path)`` of each textured ``materialBind`` subset."""
    found = []
    for subset in UsdShade.MaterialBindingAPI(prim).GetMaterialBindSubsets():
        material, _ = UsdShade.MaterialBindingAPI(subset.GetPrim()).ComputeBoundMaterial()
        asset = _texture_asset(material) if material else None
        if asset is not None:
            faces = np.asarray(subset.GetIndicesAttr().Get() or [], dtype=np.int64)
            found.append((faces, asset, str(material.GetPath())))
    return found


def _texture_file(path: Path, asset: Sdf.AssetPath) -> Path:
    if asset.resolvedPath:
        return Path(asset.resolvedPath)
    return Path(os.path.normpath(path.parent / asset.path))


def _load_texture(path: Path, file: Path, material: str) -> Texture:
    """Read texture ``file`` (used by `material` of scene `path`); its name is the file's stem."""
    if not file.is_file():
        raise SceneError(
            f"{path}: texture file {file} (used by material {material}) is missing; {rebuild_hint()}"
        )
    try:
        with Image.open(file) as image:
            pixels = np.asarray(image.convert("RGB"), dtype=np.uint8)
    except (OSError, UnidentifiedImageError) as exc:
        raise SceneError(f"{path}: cannot read texture file {file}: {exc}; {rebuild_hint()}") from None
    try:
        return Texture(file.stem, pixels)
    except ValueError as exc:
        raise _malformed(path, str(exc)) from None


def _read_st(path: Path, prim: Usd.Prim, num_corners: int) -> np.ndarray:
    """The faceVarying ``st`` coordinates of every face corner, shape (num_corners, 2)."""
    primvar = UsdGeom.PrimvarsAPI(prim).GetPrimvar(ST_PRIMVAR)
    values = primvar.ComputeFlattened() if primvar else None
    if (
        values is None
        or primvar.GetInterpolation() != UsdGeom.Tokens.faceVarying
        or len(values) != num_corners
    ):
        raise _malformed(
            path,
            f"textured mesh {prim.GetPath()} needs faceVarying primvars:{ST_PRIMVAR} "
            f"with {num_corners} values",
        )
    return np.asarray(values, dtype=np.float32).reshape(-1, 2)


def _read_textures(
    path: Path, prim: Usd.Prim, corners: np.ndarray, counts: np.ndarray, cache: dict[Path, Texture]
) -> tuple[np.ndarray | None, np.ndarray | None, tuple[Texture, ...]]:
    """``(face_uvs, face_texture, textures)`` of a mesh's triangles; ``(None, None, ())`` if untextured.

    Textures are ordered by name; triangles of polygons in no textured subset get ``-1``.
    """
    subsets = _texture_subsets(prim)
    if not subsets:
        return None, None, ()
    num_polygons, num_corners = counts.size, int(counts.sum())
    st = _read_st(path, prim, num_corners)
    by_name: dict[str, Texture] = {}
    polygon_texture = np.full(num_polygons, -1, dtype=np.int64)
    assignments = []
    for faces, asset, material in subsets:
        file = _texture_file(path, asset)
        if file not in cache:
            cache[file] = _load_texture(path, file, material)
        texture = by_name.setdefault(cache[file].name, cache[file])
        if not texture.same_image(cache[file]):
            raise _malformed(path, f"mesh {prim.GetPath()} shows two different images named {texture.name!r}")
        if faces.size and (faces.min() < 0 or faces.max() >= num_polygons):
            raise _malformed(
                path, f"subset of {prim.GetPath()} bound to {material} has face indices out of range"
            )
        assignments.append((faces, texture.name))
    names = sorted(by_name)
    for faces, name in assignments:
        polygon_texture[faces] = names.index(name)
    uvs = st[corners[:, :3]]
    return uvs, polygon_texture[corners[:, 3]].astype(np.int16), tuple(by_name[n] for n in names)


def _physics_binding(path: Path, prim: Usd.Prim) -> tuple[str, float, float]:
    material, _ = UsdShade.MaterialBindingAPI(prim).ComputeBoundMaterial(PHYSICS_PURPOSE)
    if not material or not material.GetPrim().HasAPI(UsdPhysics.MaterialAPI):
        raise _malformed(path, f"{prim.GetPath()} has no bound physics material")
    api = UsdPhysics.MaterialAPI(material.GetPrim())
    return (
        str(material.GetPath()),
        float(api.GetStaticFrictionAttr().Get()),
        float(api.GetDynamicFrictionAttr().Get()),
    )


def _labels(prim: Usd.Prim) -> tuple[str, ...]:
    if not prim.HasAPI(UsdSemantics.LabelsAPI, SEMANTIC_TAXONOMY):
        return ()
    value = UsdSemantics.LabelsAPI(prim, SEMANTIC_TAXONOMY).GetLabelsAttr().Get()
    return tuple(str(v) for v in value or ())


def _attr(path: Path, prim: Usd.Prim, name: str) -> object:
    attr = prim.GetAttribute(name)
    value = attr.Get() if attr else None
    if value is None:
        raise _malformed(path, f"{prim.GetPath()} lacks attribute {name}")
    return value


def read_usd(path: Path) -> UsdScene:
    """Read the surfaces and objects of a scene USD file.

    Friction is read from the physics material bound to each mesh (purpose ``physics``), and an
    object's position and yaw from its world transform.

    Parameters
    ----------
    path : Path
        A file written by :func:`export_usd` (or edited since, e.g. in usdview).

    Returns
    -------
    UsdScene
        Stage metadata, surfaces and objects.

    Raises
    ------
    SceneError
        If the file is missing, unreadable or lacks what a scene needs.
    """
    path = Path(path)
    stage = _open(path)
    time = Usd.TimeCode.Default()
    textures: dict[Path, Texture] = {}
    surfaces: list[UsdSurface] = []
    terrain = stage.GetPrimAtPath(TERRAIN_ROOT)
    for prim in terrain.GetChildren() if terrain else ():
        if not prim.IsA(UsdGeom.Mesh):
            continue
        material, static, dynamic = _physics_binding(path, prim)
        surfaces.append(
            UsdSurface(
                name=prim.GetName(),
                prim_path=str(prim.GetPath()),
                terrain_class=str(_attr(path, prim, ATTR_TERRAIN_CLASS)),
                mesh=_read_mesh(path, prim, cache=textures),
                labels=_labels(prim),
                physics_material=material,
                static_friction=static,
                dynamic_friction=dynamic,
            )
        )
    objects: list[UsdObject] = []
    objects_root = stage.GetPrimAtPath(OBJECTS_ROOT)
    for prim in objects_root.GetChildren() if objects_root else ():
        mesh_prim = prim.GetChild(OBJECT_MESH_NAME)
        if not mesh_prim or not mesh_prim.IsA(UsdGeom.Mesh):
            raise _malformed(path, f"object {prim.GetPath()} has no child mesh '{OBJECT_MESH_NAME}'")
        matrix = UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(time)
        translation = matrix.ExtractTranslation()
        material, static, dynamic = _physics_binding(path, mesh_prim)
        size = _attr(path, prim, ATTR_SIZE)
        objects.append(
            UsdObject(
                prim_path=str(prim.GetPath()),
                instance_id=int(_attr(path, prim, ATTR_INSTANCE_ID)),
                category=str(_attr(path, prim, ATTR_CATEGORY)),
                position=np.array([translation[0], translation[1], translation[2]], dtype=np.float64),
                # USD matrices act on row vectors: row 0 is the image of the local x axis.
                yaw=math.atan2(matrix[0][1], matrix[0][0]),
                size=(float(size[0]), float(size[1]), float(size[2])),
                mesh=_read_mesh(path, mesh_prim, cache=textures),
                labels=_labels(prim),
                physics_material=material,
                static_friction=static,
                dynamic_friction=dynamic,
            )
        )
    try:
        buildings = read_buildings(stage)
    except ValueError as exc:
        raise _malformed(path, str(exc)) from None
    default_prim = stage.GetDefaultPrim()
    return UsdScene(
        up_axis=str(UsdGeom.GetStageUpAxis(stage)),
        meters_per_unit=float(UsdGeom.GetStageMetersPerUnit(stage)),
        default_prim=str(default_prim.GetPath()) if default_prim else "",
        surfaces=tuple(surfaces),
        objects=tuple(objects),
        buildings=buildings,
    )


def physics_materials(path: Path) -> dict[str, tuple[float, float]]:
    """List the physics materials of a USD file.

    Parameters
    ----------
    path : Path
        A USD file.

    Returns
    -------
    dict of str to (float, float)
        ``prim path -> (static friction, dynamic friction)`` for every prim with
        ``PhysicsMaterialAPI``, in stage order.
    """
    stage = _open(Path(path))
    result: dict[str, tuple[float, float]] = {}
    for prim in stage.Traverse():
        if prim.HasAPI(UsdPhysics.MaterialAPI):
            api = UsdPhysics.MaterialAPI(prim)
            static, dynamic = api.GetStaticFrictionAttr().Get(), api.GetDynamicFrictionAttr().Get()
            result[str(prim.GetPath())] = (
                float(static) if static is not None else 0.0,
                float(dynamic) if dynamic is not None else 0.0,
            )
    return result


def _angle_diff(a: float, b: float) -> float:
    return abs(math.remainder(a - b, math.tau))


def scene_from_usd(path: Path, annotations: SceneAnnotations) -> Scene:
    """Rebuild the in-memory scene from its USD file and its annotations.

    Parameters
    ----------
    path : Path
        The scene's ``scene.usdc``.
    annotations : SceneAnnotations
        The scene's ``scene.json``.

    Returns
    -------
    Scene
        Surfaces from the file; objects in the order of ``annotations.objects`` with local meshes
        from the file.

    Raises
    ------
    SceneError
        If the file and the annotations disagree (terrain classes, friction, object ids,
        categories or placements).
    """
    path = Path(path)
    usd = read_usd(path)

    def disagree(what: str) -> SceneError:
        return SceneError(
            f"{path} and the scene annotations disagree: {what}; {rebuild_hint(annotations.scene_id)}"
        )

    surfaces = []
    for surface in usd.surfaces:
        terrain_class = annotations.terrain_classes.get(surface.terrain_class)
        if terrain_class is None:
            raise disagree(f"surface {surface.name!r} has unknown terrain class {surface.terrain_class!r}")
        if abs(surface.static_friction - terrain_class.friction) > _FRICTION_TOL * max(
            1.0, terrain_class.friction
        ):
            raise disagree(
                f"surface {surface.name!r} has friction {surface.static_friction:.6g}, "
                f"class {terrain_class.name!r} says {terrain_class.friction:.6g}"
            )
        surfaces.append(Surface(surface.name, surface.terrain_class, surface.mesh))

    by_id = {obj.instance_id: obj for obj in usd.objects}
    if len(by_id) != len(usd.objects) or set(by_id) != {a.id for a in annotations.objects}:
        raise disagree(
            f"object ids {sorted(by_id)} in the USD file, "
            f"{sorted(a.id for a in annotations.objects)} in scene.json"
        )
    objects = []
    for ann in annotations.objects:
        obj = by_id[ann.id]
        if obj.category != ann.category or obj.prim_path != ann.prim_path:
            raise disagree(
                f"object {ann.id} is {obj.category!r} at {obj.prim_path}, expected {ann.category!r} "
                f"at {ann.prim_path}"
            )
        if (
            np.abs(obj.position - np.asarray(ann.center)).max()
            > _POSITION_TOL * max(1.0, float(np.abs(ann.center).max()))
            or _angle_diff(obj.yaw, ann.yaw) > _ANGLE_TOL
        ):
            raise disagree(f"object {ann.id} ({ann.category}) has moved")
        objects.append(SceneObject(ann, obj.mesh))
    if usd.buildings is not None and list(usd.buildings) != annotations.buildings:
        raise disagree(
            f"buildings {[b.id for b in usd.buildings]} in the USD file differ from "
            f"{[b.id for b in annotations.buildings]} in scene.json"
        )
    try:
        return Scene(annotations, tuple(surfaces), tuple(objects))
    except ValueError as exc:
        raise disagree(str(exc)) from None
