"""The procedural materials of a look: what each surface is made of and its colour at a point.

A :class:`Material` is a base colour and a pattern (plain, grainy, or units laid in rows: slabs,
tiles, bricks, boards, pavers) with joints, a tint per unit and a grain of smooth noise; glass
reflects some of the sky. :func:`material_albedo` evaluates one material at surface coordinates
``(u, v)`` in meters (the renderer takes them from the hit point: ``x, y`` on floors and grounds,
along-the-wall and height on walls). The catalogue :data:`MATERIALS` holds every material by name;
the tables below say which material a terrain class, a room type or a building type gets.
Colours are sRGB in the catalogue and linear RGB once evaluated.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType
from typing import Literal

import numpy as np

from navverse.look.patterns import laid_units, value_noise
from navverse.scene.colors import linear_to_srgb, srgb_to_linear

__all__ = [
    "CLASS_MATERIALS",
    "FACADE_STYLES",
    "MATERIALS",
    "MATERIAL_NAMES",
    "ROOM_FLOORS",
    "FacadeStyle",
    "Material",
    "bake_tile",
    "facade_style",
    "linear_to_srgb",
    "material_albedo",
    "material_index",
    "room_floor",
    "srgb_to_linear",
]

Pattern = Literal["plain", "units"]


@dataclass(frozen=True)
class Material:
    """One procedural material.

    Attributes
    ----------
    name : str
        Its name in :data:`MATERIALS`.
    color : tuple of int
        Base sRGB colour.
    grain, grain_scale : float
        Amplitude (0: none, 1: from black to twice the colour) and feature size (m) of smooth noise.
    pattern : {"plain", "units"}
        Plain (colour and grain) or units laid in rows (see
        :func:`~navverse.look.patterns.laid_units`).
    unit : tuple of float
        ``(length, width)`` of a unit in meters (units only).
    joint : float
        Width of the joints between units in meters.
    joint_color : tuple of int
        sRGB colour of the joints.
    stagger : float
        Row offset of the units (0.5 running bond, 0 grid, -1 drawn per row).
    tint : float
        Amplitude of each unit's own shade (0 to 1).
    reflect : float
        Share of the sky's light it mirrors (glass, water), 0 to 1.
    tile : float
        Side in meters of the square tile the material is baked into and repeats with: a whole number
        of grain cells and of units (of two rows of a running bond).
    texels : int
        Side of the baked tile in texels (a power of two).
    """

    name: str
    color: tuple[int, int, int]
    grain: float = 0.1
    grain_scale: float = 0.5
    pattern: Pattern = "plain"
    unit: tuple[float, float] = (1.0, 1.0)
    joint: float = 0.0
    joint_color: tuple[int, int, int] = (0, 0, 0)
    stagger: float = 0.0
    tint: float = 0.0
    reflect: float = 0.0
    tile: float = 4.0
    texels: int = 256

    def __post_init__(self) -> None:
        def whole(value: float) -> bool:
            return abs(value - round(value)) < 1e-6 and round(value) >= 1

        rows = self.tile / self.unit[1] / (2.0 if self.stagger == 0.5 else 1.0)
        if self.grain > 0.0 and not whole(self.tile / self.grain_scale):
            raise ValueError(f"material {self.name}: tile {self.tile} m is no whole number of grain cells")
        if self.pattern == "units" and not (whole(self.tile / self.unit[0]) and whole(rows)):
            raise ValueError(f"material {self.name}: tile {self.tile} m is no whole number of units")
        if self.texels < 1 or self.texels & (self.texels - 1):
            raise ValueError(f"material {self.name}: texels must be a power of two, got {self.texels}")

    @property
    def texel_size(self) -> float:
        """Side of a texel of the baked tile in meters."""
        return self.tile / self.texels


def _materials(*materials: Material) -> MappingProxyType[str, Material]:
    return MappingProxyType({m.name: m for m in materials})


MATERIALS = _materials(
    # Streets and grounds.
    Material("asphalt", (78, 78, 80), grain=0.35, grain_scale=0.08, tile=4.0, texels=512),
    Material("asphalt_light", (104, 104, 106), grain=0.3, grain_scale=0.1, tile=4.0, texels=512),
    Material("concrete_slabs", (178, 176, 170), grain=0.18, grain_scale=0.15, pattern="units",
             unit=(1.2, 1.2), joint=0.02, joint_color=(120, 118, 114), tint=0.12, tile=4.8, texels=512),
    Material("curb_stone", (150, 150, 148), grain=0.25, grain_scale=0.05, pattern="units",
             unit=(1.0, 0.3), joint=0.01, joint_color=(100, 100, 98), tint=0.15, tile=3.0, texels=256),
    Material("pavers", (176, 150, 132), grain=0.15, grain_scale=0.05, pattern="units",
             unit=(0.2, 0.1), joint=0.008, joint_color=(120, 108, 98), stagger=0.5, tint=0.3, tile=2.0,
             texels=512),
    Material("grass", (92, 134, 62), grain=0.5, grain_scale=0.5, tile=8.0, texels=256),
    Material("earth", (150, 128, 96), grain=0.22, grain_scale=0.25, tile=4.0, texels=256),
    Material("water", (44, 78, 100), grain=0.15, grain_scale=2.0, reflect=0.35, tile=16.0, texels=64),
    Material("ballast", (110, 100, 92), grain=0.6, grain_scale=0.05, tile=2.0, texels=256),
    Material("concrete", (150, 148, 144), grain=0.2, grain_scale=0.4, tile=4.0, texels=128),
    Material("marking", (236, 236, 228), grain=0.1, grain_scale=0.1, tile=2.0, texels=64),
    # Inside.
    Material("wood_floor", (160, 112, 72), grain=0.25, grain_scale=0.05, pattern="units",
             unit=(1.4, 0.175), joint=0.004, joint_color=(96, 64, 40), stagger=-1.0, tint=0.35, tile=2.8,
             texels=512),
    Material("floor_tiles", (206, 202, 194), grain=0.06, grain_scale=0.2, pattern="units",
             unit=(0.4, 0.4), joint=0.006, joint_color=(150, 146, 140), tint=0.06, tile=1.6, texels=256),
    Material("carpet", (112, 116, 128), grain=0.2, grain_scale=0.05, tile=1.0, texels=128),
    Material("linoleum", (184, 186, 170), grain=0.12, grain_scale=0.25, tile=2.0, texels=128),
    Material("wall_paint", (226, 222, 212), grain=0.04, grain_scale=0.25, tile=2.0, texels=64),
    Material("ceiling_plaster", (236, 236, 232), grain=0.03, grain_scale=0.5, tile=2.0, texels=64),
    # Buildings.
    Material("brick", (150, 82, 60), grain=0.12, grain_scale=0.05, pattern="units",
             unit=(0.25, 0.075), joint=0.012, joint_color=(190, 180, 166), stagger=0.5, tint=0.25,
             tile=1.5, texels=256),
    Material("render", (214, 200, 176), grain=0.1, grain_scale=0.5, tile=4.0, texels=64),
    Material("concrete_panels", (170, 168, 162), grain=0.1, grain_scale=0.5, pattern="units",
             unit=(3.0, 1.5), joint=0.025, joint_color=(120, 118, 114), tint=0.08, tile=6.0, texels=256),
    Material("metal_cladding", (150, 158, 164), grain=0.05, grain_scale=0.5, pattern="units",
             unit=(0.3, 2.0), joint=0.03, joint_color=(110, 116, 122), tint=0.04, tile=6.0, texels=256),
    Material("plinth", (112, 108, 104), grain=0.2, grain_scale=0.1, tile=2.0, texels=128),
    Material("roof", (96, 94, 92), grain=0.3, grain_scale=0.25, tile=4.0, texels=128),
    Material("glass", (34, 46, 58), grain=0.02, grain_scale=1.0, reflect=0.22, tile=4.0, texels=16),
    Material("frame", (226, 224, 218), grain=0.0, tile=1.0, texels=16),
    Material("door", (92, 66, 48), grain=0.1, grain_scale=0.1, tile=1.0, texels=64),
    # Objects keep their own colours; this grain modulates them (paint, plastic, wood, metal up close).
    Material("object_grain", (186, 186, 186), grain=0.14, grain_scale=0.03, tile=0.96, texels=128),
)  # fmt: skip
"""Every material by name (read-only)."""
MATERIAL_NAMES = tuple(MATERIALS)
"""Material names in catalogue order: a material's index is its place here."""


def material_index(name: str) -> int:
    """The index of material `name` in :data:`MATERIAL_NAMES`."""
    return MATERIAL_NAMES.index(name)


CLASS_MATERIALS = MappingProxyType(
    {
        "road": "asphalt",
        "parking": "asphalt_light",
        "crosswalk": "asphalt",
        "sidewalk": "concrete_slabs",
        "curb": "curb_stone",
        "plaza": "pavers",
        "green": "grass",
        "ground": "earth",
        "water": "water",
        "rail": "ballast",
        "obstacle": "concrete",
        "floor": "linoleum",
        "wall": "wall_paint",
        "ceiling": "ceiling_plaster",
        "building": "render",
    }
)
"""The material of each terrain class before the finer rules (floors by room, walls outside, buildings
by facade); a class not listed is ``concrete``."""

ROOM_FLOORS = MappingProxyType(
    {
        **dict.fromkeys(
            ("living_room", "bedroom", "hallway", "dining_area", "meeting_room", "private_office",
             "teachers_room"), "wood_floor"),
        **dict.fromkeys(
            ("kitchen", "bathroom", "kitchenette", "restroom", "cafe_kitchen", "sales_floor"), "floor_tiles"),
        **dict.fromkeys(("open_office", "reception", "back_office"), "carpet"),
    }
)  # fmt: skip
"""The floor material by room type; other rooms (corridors, wards, storage...) are ``linoleum``."""


def room_floor(room_type: str) -> str:
    """The floor material of a room type."""
    return ROOM_FLOORS.get(room_type, "linoleum")


@dataclass(frozen=True)
class FacadeStyle:
    """How the facades of a kind of building look.

    Attributes
    ----------
    wall : str
        The wall material (a :data:`MATERIALS` name).
    storey : float
        Storey height in meters (when the map gives no levels).
    window : tuple of float
        ``(width, height)`` of a window in meters; windows stand one per bay.
    bay : float
        Target width of a bay (one window each) in meters.
    sill : float
        Height of a window's sill above its storey's floor.
    shop_front : bool
        The ground floor is one band of shop windows.
    """

    wall: str
    storey: float
    window: tuple[float, float]
    bay: float
    sill: float
    shop_front: bool = False


FACADE_STYLES = MappingProxyType(
    {
        "brick": FacadeStyle("brick", 3.0, (1.2, 1.5), 3.0, 0.9),
        "render": FacadeStyle("render", 3.0, (1.1, 1.4), 2.8, 0.9),
        "office": FacadeStyle("concrete_panels", 3.6, (2.4, 1.9), 3.0, 0.8, shop_front=True),
        "retail": FacadeStyle("render", 4.0, (1.6, 1.6), 3.5, 1.0, shop_front=True),
        "industrial": FacadeStyle("metal_cladding", 5.0, (2.0, 1.0), 8.0, 3.0),
    }
)
"""Facade styles by name."""

_BUILDING_STYLES = {
    **dict.fromkeys(("commercial", "office", "government", "civic", "public", "hospital", "university",
                     "college", "school", "hotel"), "office"),
    **dict.fromkeys(("retail", "supermarket", "kiosk", "shop", "mall"), "retail"),
    **dict.fromkeys(("industrial", "warehouse", "hangar", "factory", "manufacture", "shed", "garage",
                     "garages", "service", "storage_tank"), "industrial"),
}  # fmt: skip


def facade_style(building_type: str | None, *, pick: float) -> str:
    """The facade style of a building of map type `building_type` (``building=*``; None or ``yes``:
    unknown), houses and unknown buildings brick or render by `pick` in [0, 1)."""
    style = _BUILDING_STYLES.get(building_type or "")
    if style is not None:
        return style
    return "brick" if pick < 0.4 else "render"


def material_albedo(material: Material, u: np.ndarray, v: np.ndarray, *, seed: int) -> np.ndarray:
    """Linear RGB albedo ``(3, K)`` of `material` at surface coordinates ``(u, v)`` (meters); the
    pattern repeats every ``material.tile`` meters along both.

    Parameters
    ----------
    material : Material
        The material.
    u, v : ndarray, shape (K,)
        Surface coordinates in meters.
    seed : int
        Varies the pattern and the tints (the look's material variant).
    """
    shade = np.ones(len(u), dtype=np.float32)
    if material.grain > 0.0:
        cells = round(material.tile / material.grain_scale)
        noise = value_noise(u, v, scale=material.grain_scale, seed=seed, octaves=2, period=cells)
        shade += np.float32(material.grain) * (noise - np.float32(0.5))
    joints = None
    if material.pattern == "units":
        length, width = material.unit
        period = (round(material.tile / length), round(material.tile / width))
        unit, joints = laid_units(
            u, v, length=length, width=width, joint=material.joint, stagger=material.stagger, seed=seed + 17,
            period=period,
        )  # fmt: skip
        shade += np.float32(material.tint) * (unit - np.float32(0.5))
    base = _linear(material.color)
    albedo = base[:, None] * np.maximum(shade, 0.0)[None, :]
    if joints is not None and joints.any():
        albedo[:, joints] = _linear(material.joint_color)[:, None] * shade[joints][None, :]
    return albedo


def bake_tile(material: Material, *, seed: int) -> np.ndarray:
    """The material's repeating tile as sRGB bytes ``(texels, texels, 3)``: texel ``(row, col)`` is its
    albedo at ``u = (col + 0.5) * texel_size``, ``v = (row + 0.5) * texel_size``."""
    n = material.texels
    centers = (np.arange(n) + 0.5) * material.texel_size
    v, u = np.meshgrid(centers, centers, indexing="ij")
    albedo = material_albedo(material, u.reshape(-1), v.reshape(-1), seed=seed)
    return linear_to_srgb(albedo.T).reshape(n, n, 3)


def _linear(color: tuple[int, int, int]) -> np.ndarray:
    """Linear RGB of an sRGB triple."""
    return srgb_to_linear(color)
