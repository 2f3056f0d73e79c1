"""A scene's look as a USD layer over its ``scene.usdc``: the same materials for USD viewers.

:func:`write_look_usd` writes ``look.usdc`` beside a scene's ``scene.usdc`` (which it sublayers:
open ``look.usdc`` to see the scene with its look) and the images it reads, ``textures/look/*.png``.
The layer adds, over the scene's prims:

- ``/World/Looks/Look/<material>``: a ``UsdPreviewSurface`` whose diffuse colour is a ``UsdUVTexture``
  of the material's tile (:func:`~navverse.look.materials.bake_tile`), read through the primvar
  ``lookSt`` (repeat wrapping; the material variant's tint as the texture's ``scale``);
- on every terrain mesh, ``primvars:lookSt`` (faceVarying: per face corner, the surface coordinates
  the renderer uses, in tiles) and one ``GeomSubset`` per material (family ``materialBind``) bound to
  it: floors by the room each face is in, walls paint inside and render outside, facades a tile of
  one bay by one storey of their style with its window, roofs, crosswalks by their markings (zebras and
  ladders a stripe tile along the crossing, lines and dashes a tile of lines along both its edges,
  unpainted ones their material), the other classes their material;
- on every object mesh, a binding to a palette material: one texel per colour the objects use, each
  face (``lookSt`` uniform) on its colour, so the objects keep their colours through a texture.

What the renderer paints per hit and the layer does not: lane markings, doors at entrances, shop
windows on ground floors, plinths. Faces already bound to textures (storefront signs, textured
imported meshes) keep their own materials.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image
from pxr import Sdf, Usd, UsdGeom, UsdShade, Vt

from navverse.city.geometry.surfaces import CROSSWALK_WIDTH
from navverse.files import atomic_path
from navverse.look.facades import BASE, DX, DY, LENGTH, OVERLAY_ALBEDO, OVERLAY_NAMES, STOREY, STYLE, SX, SY
from navverse.look.materials import (
    FACADE_STYLES,
    MATERIAL_NAMES,
    MATERIALS,
    linear_to_srgb,
    material_albedo,
    material_index,
)
from navverse.look.scene_look import (
    CROSSING_MARKINGS,
    CROSSWALK,
    EDGE_LINE,
    FACADE,
    FLOOR,
    WALL,
    SceneLook,
    material_tiles,
)
from navverse.scene.colors import default_color
from navverse.scene.geometry import MeshData, Scene, SceneObject
from navverse.scene.naming import LOOKS_ROOT, PHYSICS_ROOT, TERRAIN_ROOT
from navverse.scene.usd import define_texture_material

__all__ = ["LOOK_PRIMVAR", "LOOK_TEXTURES", "LOOK_USD", "write_look_usd"]

LOOK_USD = "look.usdc"
"""The look layer's file name (beside ``scene.usdc``, which it sublayers)."""
LOOK_TEXTURES = "textures/look"
"""Folder of the look's images, relative to the layer."""
LOOK_PRIMVAR = "lookSt"
"""The primvar of the look's texture coordinates."""
_LOOKS = f"{LOOKS_ROOT}/Look"
_FACADE_TEXELS = 256
_UPWARD = 0.5
_PNG_LEVEL = 6
_STRIPE_TEXTURES = {
    "zebra": "zebra",
    "ladder": "zebra",
    "lines": "crossing_lines",
    "dashes": "crossing_lines",
}
"""The texture of a crosswalk by its markings (unpainted ones keep their material)."""


def write_look_usd(scene: Scene, look: SceneLook, directory: Path, *, scene_file: str = "scene.usdc") -> Path:
    """Write ``look.usdc`` and its images into `directory`, beside the scene's `scene_file`.

    Parameters
    ----------
    scene : Scene
        The scene (its faces in the order `look` was compiled for, nothing hidden).
    look : SceneLook
        Its look.
    directory : Path
        Where ``look.usdc`` and ``textures/look/`` go; `scene_file` is found there by relative path.
    scene_file : str
        The scene's USD file the layer sublayers.

    Returns
    -------
    Path
        The layer's path.
    """
    textures: dict[str, np.ndarray] = {}
    layer_path = directory / LOOK_USD
    with atomic_path(layer_path) as tmp:  # beside the scene's file: the sublayer resolves from there
        stage = Usd.Stage.CreateNew(str(tmp))
        stage.GetRootLayer().subLayerPaths.append(scene_file)
        _author(stage, scene, look, textures)
        stage.GetRootLayer().Save()
    (directory / LOOK_TEXTURES).mkdir(parents=True, exist_ok=True)
    for name, image in sorted(textures.items()):
        with atomic_path(directory / LOOK_TEXTURES / f"{name}.png") as tmp:
            Image.fromarray(image).save(tmp, format="PNG", compress_level=_PNG_LEVEL)
    return layer_path


def _author(stage: Usd.Stage, scene: Scene, look: SceneLook, textures: dict[str, np.ndarray]) -> None:
    """Author the look's materials and bindings over the scene's prims; the images they read go into
    `textures` by name."""
    UsdGeom.Scope.Define(stage, _LOOKS)
    materials: dict[str, UsdShade.Material] = {}

    def material(name: str, *, tint: np.ndarray | None = None) -> UsdShade.Material:
        if name not in materials:
            textures[name] = _image(name)
            materials[name] = _texture_material(stage, name, tint)
        return materials[name]

    start = 0
    for surface in scene.surfaces:
        mesh = surface.mesh
        faces = np.arange(start, start + mesh.num_faces)
        start += mesh.num_faces
        prim = stage.GetPrimAtPath(f"{TERRAIN_ROOT}/{surface.name}")
        if not prim.IsValid():
            continue
        names, st = _surface_looks(look, faces, mesh)
        free = np.ones(mesh.num_faces, dtype=bool) if not mesh.textured else mesh.face_texture < 0
        _set_st(prim, st)
        binding = UsdShade.MaterialBindingAPI.Apply(prim)
        physics = UsdShade.Material(stage.GetPrimAtPath(f"{PHYSICS_ROOT}/{surface.terrain_class}"))
        for name in sorted(set(names[free])):
            chosen = np.flatnonzero((names == name) & free).astype(np.int32)
            bound = material(name, tint=_tint(look, name))
            subset = binding.CreateMaterialBindSubset(f"look_{name}", Vt.IntArray.FromNumpy(chosen), "face")
            subset_binding = UsdShade.MaterialBindingAPI.Apply(subset.GetPrim())
            subset_binding.Bind(bound)
            if physics:
                subset_binding.Bind(physics, UsdShade.Tokens.fallbackStrength, "physics")
        if not mesh.textured:
            binding.SetMaterialBindSubsetsFamilyType(UsdGeom.Tokens.nonOverlapping)
    if scene.objects:
        palette, colors = _palette(scene)
        textures["palette"] = palette
        bound = _texture_material(stage, "palette", None)
        for obj in scene.objects:
            prim = stage.GetPrimAtPath(f"{obj.annotation.prim_path}/mesh")
            if not prim.IsValid():
                continue
            _set_st(prim, _palette_st(obj, colors, palette.shape[0]))
            UsdShade.MaterialBindingAPI.Apply(prim).Bind(bound)


def _texture_material(stage: Usd.Stage, name: str, tint: np.ndarray | None) -> UsdShade.Material:
    """A preview surface reading ``textures/look/<name>.png`` through ``lookSt``."""
    glossy = name in ("glass", "water") or name.startswith("facade_")
    return define_texture_material(
        stage,
        f"{_LOOKS}/{name}",
        f"./{LOOK_TEXTURES}/{name}.png",
        primvar=LOOK_PRIMVAR,
        scale=None if tint is None else tuple(float(t) for t in tint),
        roughness=0.35 if glossy else 0.85,
    )


def _set_st(prim: Usd.Prim, st: np.ndarray) -> None:
    """``primvars:lookSt`` of a mesh: faceVarying from ``(F, 3, 2)`` corner coordinates, uniform from
    ``(F, 2)`` face coordinates."""
    interpolation = UsdGeom.Tokens.faceVarying if st.ndim == 3 else UsdGeom.Tokens.uniform
    primvar = UsdGeom.PrimvarsAPI(prim).CreatePrimvar(
        LOOK_PRIMVAR, Sdf.ValueTypeNames.TexCoord2fArray, interpolation
    )
    primvar.Set(Vt.Vec2fArray.FromNumpy(np.ascontiguousarray(st.reshape(-1, 2), dtype=np.float32)))


def _tint(look: SceneLook, name: str) -> np.ndarray | None:
    """The variant's tint of a material (None for textures that are not one material's tile)."""
    if name not in MATERIALS or look.settings.material_variant == 0:
        return None
    return look.tint[material_index(name)]


def _surface_looks(look: SceneLook, faces: np.ndarray, mesh: MeshData) -> tuple[np.ndarray, np.ndarray]:
    """Per face of a terrain mesh (world-mesh faces `faces`), the texture it shows and its corners'
    coordinates in that texture ``(F, 3, 2)``."""
    corners = mesh.vertices[mesh.faces]  # (F, 3, 3)
    centers = corners.mean(axis=1)
    normal = look.face_normals[faces]
    kind = look.face_kind[faces]
    material = look.face_material[faces].astype(np.int64)
    inside = np.flatnonzero((kind == FLOOR) | (kind == WALL))
    if len(inside):
        room = look.room_of(centers[inside], normal[inside])
        floors = kind[inside] == FLOOR
        material[inside[floors & (room >= 0)]] = look.room_floor[room[floors & (room >= 0)]]
        material[inside[~floors & (room >= 0)]] = material_index("wall_paint")
        material[inside[~floors & (room < 0)]] = material_index("render")
    names = np.array([MATERIAL_NAMES[m] if m >= 0 else "concrete" for m in material], dtype=object)
    flat = np.abs(normal[:, 2]) >= _UPWARD
    horizontal = np.hypot(normal[:, 0], normal[:, 1])
    horizontal[horizontal == 0.0] = 1.0
    x, y, z = corners[..., 0], corners[..., 1], corners[..., 2]
    along = (y * normal[:, None, 0] - x * normal[:, None, 1]) / horizontal[:, None]
    u = np.where(flat[:, None], x, along)
    v = np.where(flat[:, None], y, z)
    tiles = np.array([MATERIALS[n].tile if n in MATERIALS else 1.0 for n in names])
    shift = look.shift[np.maximum(material, 0)]
    st = np.stack(
        [(u + shift[:, None, 0]) / tiles[:, None], (v + shift[:, None, 1]) / tiles[:, None]], axis=-1
    )
    facade = np.flatnonzero(kind == FACADE)
    if len(facade):
        rows = look.facades.rows[look.face_frame[faces[facade]]]
        names[facade], st[facade] = _facade_st(rows, corners[facade])
    crosswalk = np.flatnonzero(kind == CROSSWALK)
    if len(crosswalk):
        patch = look.crossings[look.face_frame[faces[crosswalk]]]
        texture, st_crosswalk = _crosswalk_st(patch, corners[crosswalk])
        painted = texture != ""
        names[crosswalk[painted]] = texture[painted]
        st[crosswalk[painted]] = st_crosswalk[painted]
    return names.astype(str), st


def _crosswalk_st(patch: np.ndarray, corners: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Crosswalk faces (their patches' rows of :attr:`SceneLook.crossings`, corners ``(F, 3, 3)``): the
    texture of their markings (``""``: unpainted) and their corners' coordinates in it: along the patch's
    long side in meters, and across it in meters (zebra tiles) or in widths (edge-line tiles)."""
    rx, ry = corners[..., 0] - patch[:, None, 0], corners[..., 1] - patch[:, None, 1]
    length = rx * patch[:, None, 2] + ry * patch[:, None, 3]
    across = patch[:, None, 2] * ry - patch[:, None, 3] * rx
    markings = [CROSSING_MARKINGS[int(code)] for code in patch[:, 5]]
    texture = np.array([_STRIPE_TEXTURES.get(m, "") for m in markings], dtype=object)
    lines = texture == "crossing_lines"
    across[lines] = np.abs(across[lines]) / np.maximum(patch[lines, 4:5], 1e-9)
    return texture, np.stack([length, across], axis=-1)


def _facade_st(rows: np.ndarray, corners: np.ndarray) -> tuple[list[str], np.ndarray]:
    """Facade faces (their frame rows): their style's bay texture, and coordinates in bays and storeys."""
    style_names = tuple(FACADE_STYLES)
    s = (corners[..., 0] - rows[:, None, SX]) * rows[:, None, DX] + (
        corners[..., 1] - rows[:, None, SY]
    ) * rows[:, None, DY]
    h = corners[..., 2] - rows[:, None, BASE]
    styles = rows[:, STYLE].astype(int)
    bay_target = np.array([FACADE_STYLES[style_names[i]].bay for i in styles])
    bay = rows[:, LENGTH] / np.maximum(1.0, np.round(rows[:, LENGTH] / bay_target))
    st = np.stack([s / bay[:, None], h / rows[:, None, STOREY]], axis=-1)
    return [f"facade_{style_names[i]}" for i in styles], st


def _image(name: str) -> np.ndarray:
    """The image of a look texture: a material's tile, a facade style's bay, the zebra stripes, the
    edge lines of a crossing."""
    if name in MATERIALS:
        return material_tiles()[material_index(name)]
    if name == "zebra":  # 1 m of crossing: a stripe on its first half, asphalt on the other
        asphalt = material_tiles()[material_index("asphalt")]
        n = asphalt.shape[0] // 4  # the asphalt tile is 4 m: a quarter of it is 1 m
        image = asphalt[:n, :n].copy()
        image[:, : n // 2] = MATERIALS["marking"].color
        return image
    if name == "crossing_lines":  # 1 m along a crossing (s), its whole width across (t): lines at both edges
        asphalt = material_tiles()[material_index("asphalt")]
        n = asphalt.shape[0] // 4
        image = asphalt[:n, :n].copy()
        line = max(1, round(n * EDGE_LINE / CROSSWALK_WIDTH))  # as wide as on a crosswalk of the usual width
        image[:line] = MATERIALS["marking"].color
        image[-line:] = MATERIALS["marking"].color
        return image
    if name.startswith("facade_"):
        return _facade_bay(name.removeprefix("facade_"))
    raise KeyError(name)


def _facade_bay(style_name: str) -> np.ndarray:
    """One bay by one storey of an upper floor of a facade style: its wall with the window, framed."""
    style = FACADE_STYLES[style_name]
    n = _FACADE_TEXELS
    x = (np.arange(n) + 0.5) / n
    s, h = np.meshgrid(x * style.bay, x * style.storey)  # row 0 at the bottom of the storey
    wall = material_albedo(MATERIALS[style.wall], s.reshape(-1), h.reshape(-1), seed=0).T.reshape(n, n, 3)
    centred = np.abs(s - 0.5 * style.bay)
    width = min(style.window[0], style.bay - 0.6)
    glass = (centred < 0.5 * width) & (h > style.sill) & (h < style.sill + style.window[1])
    frame = (
        (centred < 0.5 * width + 0.07) & (h > style.sill - 0.07) & (h < style.sill + style.window[1] + 0.07)
    )
    wall[frame] = OVERLAY_ALBEDO[:, OVERLAY_NAMES.index("frame")]
    wall[glass] = OVERLAY_ALBEDO[:, OVERLAY_NAMES.index("glass")]
    return np.ascontiguousarray(linear_to_srgb(wall)[::-1])  # image row 0 is the top (t = 1)


def _object_colors(obj: SceneObject) -> np.ndarray:
    """The sRGB colour ``(F, 3)`` of each face of an object (its category's where it has none)."""
    if obj.mesh.face_colors is not None:
        return np.asarray(obj.mesh.face_colors, dtype=np.uint8)
    return np.tile(np.array(default_color(obj.annotation.category), dtype=np.uint8), (obj.mesh.num_faces, 1))


def _palette(scene: Scene) -> tuple[np.ndarray, dict[tuple[int, int, int], int]]:
    """A square image with one texel per colour the objects' faces use, and each colour's texel."""
    found: dict[tuple[int, int, int], int] = {}
    for obj in scene.objects:
        for color in np.unique(_object_colors(obj), axis=0):
            found.setdefault(tuple(int(c) for c in color), len(found))
    side = 1
    while side * side < max(len(found), 1):
        side *= 2
    image = np.zeros((side, side, 3), dtype=np.uint8)
    for color, k in found.items():
        image[k // side, k % side] = color
    return image, found


def _palette_st(obj: SceneObject, colors: dict[tuple[int, int, int], int], side: int) -> np.ndarray:
    """Face coordinates ``(F, 2)`` putting every face of an object on its colour's texel."""
    unique, inverse = np.unique(_object_colors(obj), axis=0, return_inverse=True)
    texel = np.array([colors[tuple(int(c) for c in color)] for color in unique], dtype=np.int64)
    index = texel[inverse.reshape(-1)]
    return np.stack([(index % side + 0.5) / side, 1.0 - (index // side + 0.5) / side], axis=-1)
