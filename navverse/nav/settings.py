"""Navmesh build settings and the presets: the paper's indoor and outdoor ones, and indoor-to-outdoor.

Field names and units follow habitat-sim's ``NavMeshSettings``: lengths in meters, the slope in
degrees, and the Recast tuning values (region sizes, edge error, detail sampling) in cells, the
way habitat-sim and the Recast demo pass them on. :data:`INDOOR` and :data:`OUTDOOR` are the values
of the paper's table ``tab:navmesh_params``, defined here and nowhere else:
``recipes/presets/navmesh-{indoor,outdoor}.yaml`` name them (``preset: indoor``) and repeat no
value. :data:`I2O` is :data:`OUTDOOR` with a finer cell size over a region (the indoor part of a
scene), see :class:`NavMeshSettings`.
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType
from typing import Annotated, Any

from pydantic import BaseModel, ConfigDict, Field, ValidationError, create_model, model_validator

from navverse.nav.errors import NavMeshError

__all__ = ["I2O", "INDOOR", "OUTDOOR", "PRESETS", "NavMeshOverrides", "NavMeshSettings"]

# Most cells along a tile side: tile_size, and tile_size * fine_factor for the fine tiles.
_MAX_CELLS_PER_TILE = 4096
# Largest region size (cells), largest agent height, radius and climb (m), farthest coordinate (m).
_MAX_CELLS = float(_MAX_CELLS_PER_TILE)
_MAX_AGENT_M = 10.0
_Coordinate = Annotated[float, Field(ge=-1e7, le=1e7)]


class NavMeshSettings(BaseModel):
    """Everything Recast needs to voxelize a scene into a navmesh.

    The defaults are the :data:`INDOOR` preset. Integer Recast parameters are derived as
    ``ceil(agent_height / cell_height)``, ``floor(agent_max_climb / cell_height)`` and
    ``ceil(agent_radius / cell_size)`` cells (with a 1e-6 tolerance, so 0.30 / 0.10 is 3 cells).

    Mixed resolution: with ``fine_region`` and ``fine_factor`` f > 1, the tiles whose area meets
    the region are built with cells of ``cell_size / f`` by ``cell_height / f``, the others at
    ``cell_size``. Every tile has the same width in meters (``tile_size * cell_size``), so a fine
    tile has ``tile_size * f`` cells per side, and tiles of both resolutions join along their common
    borders. Values in meters and degrees (agent sizes, climb, slope, ``edge_max_len``) mean the
    same at both resolutions; the integer cell counts are derived from them per resolution. Values
    in cells stay in cells of the tile's own resolution: ``region_min_size``,
    ``region_merge_size`` and ``edge_max_error``; ``detail_sample_*`` are multiples of the tile's
    cell size and height. A fine tile has f**2 times the cells of a coarse one (so about that much
    more build memory per thread) and up to f**2 times its polygons and vertices (65535 vertices at
    most per tile). The region is a world xy rectangle (z up); tiles only
    touching its edge are not fine.
    """

    model_config = ConfigDict(frozen=True, extra="forbid", allow_inf_nan=False)

    cell_size: float = Field(
        0.05, ge=0.01, le=2.0, description="Voxel size on the ground plane (m, 0.01 to 2)."
    )
    cell_height: float = Field(0.05, ge=0.01, le=2.0, description="Voxel height (m, 0.01 to 2).")
    agent_height: float = Field(
        0.6, gt=0, le=_MAX_AGENT_M, description="Headroom the agent needs (m, more than 0, at most 10)."
    )
    agent_radius: float = Field(
        0.6,
        ge=0,
        le=_MAX_AGENT_M,
        description="Agent radius (m, 0 to 10); the walkable area is eroded by it, away from obstacles.",
    )
    agent_max_climb: float = Field(
        0.2, ge=0, le=_MAX_AGENT_M, description="Highest step the agent climbs, up or down (m, 0 to 10)."
    )
    agent_max_slope: float = Field(
        45.0, ge=0, lt=90, description="Steepest walkable triangle (degrees from horizontal)."
    )
    region_min_size: float = Field(
        8.0,
        ge=0,
        le=_MAX_CELLS,
        description=(
            "Side of the smallest isolated region kept (cells, 0 to 4096): regions of fewer than "
            "region_min_size**2 cells that touch no tile border are removed."
        ),
    )
    region_merge_size: float = Field(
        0.0,
        ge=0,
        le=_MAX_CELLS,
        description=(
            "Regions of fewer than region_merge_size**2 cells are merged into a neighbour (cells, 0 to 4096)."
        ),
    )
    edge_max_len: float = Field(
        0.0,
        ge=0,
        le=1000.0,
        description="Longest polygon border edge (m, 0 to 1000); 0 leaves edges unlimited.",
    )
    edge_max_error: float = Field(
        1.5,
        ge=0,
        le=100.0,
        description="Largest deviation of simplified borders from the voxel outline (cells, 0 to 100).",
    )
    verts_per_poly: int = Field(6, ge=3, le=6, description="Most vertices per polygon (Detour allows 3..6).")
    detail_sample_dist: float = Field(
        1.0,
        ge=0,
        le=100.0,
        description=(
            "Spacing of height samples of the detail mesh, in multiples of cell_size (0 to 100); below "
            "0.9 the detail mesh only follows the polygon outlines."
        ),
    )
    detail_sample_max_error: float = Field(
        0.0,
        ge=0,
        le=100.0,
        description="Largest height error of the detail mesh, in multiples of cell_height (0 to 100).",
    )
    filter_low_hanging_obstacles: bool = Field(
        True, description="Let the agent step onto obstacles lower than agent_max_climb (curbs, stairs)."
    )
    filter_ledge_spans: bool = Field(
        True, description="Make cells next to drops higher than the climb unwalkable."
    )
    filter_walkable_low_height_spans: bool = Field(
        True, description="Make cells with less than agent_height of headroom unwalkable."
    )
    fill_solid_interiors: bool = Field(
        True,
        description=(
            "Treat the inside of closed solids as solid: nothing between a downward-facing surface and "
            "where the solid ends above it is walkable (Recast alone sees surfaces only, so the floor "
            "inside a closed box would be a walkable island)."
        ),
    )
    tile_size: int = Field(
        256,
        ge=0,
        le=_MAX_CELLS_PER_TILE,
        description=(
            "Tile side in cells (0, or 16 to 4096); tiles are built in parallel. 0 builds the whole "
            "scene as one tile (at most 65535 polygon vertices)."
        ),
    )
    fine_region: tuple[_Coordinate, _Coordinate, _Coordinate, _Coordinate] | None = Field(
        None,
        description=(
            "World xy rectangle [xmin, ymin, xmax, ymax] (m, z up, each within +-1e7) whose tiles are "
            "built with cells fine_factor times smaller (e.g. the indoor part of a scene); None builds "
            "every tile at cell_size. Needs tile_size > 0."
        ),
    )
    fine_factor: int = Field(
        1,
        ge=1,
        le=4,
        description=(
            "How many times finer the tiles meeting fine_region are: cells of cell_size / fine_factor "
            "by cell_height / fine_factor (1..4; 1 builds every tile at cell_size)."
        ),
    )

    @model_validator(mode="after")
    def _recast_limits(self) -> NavMeshSettings:
        # The Recast limits hold for the finest cells in use: the fine tiles' when there is a region.
        factor = self.fine_factor if self.fine_region is not None else 1
        cell_size, cell_height = self.cell_size / factor, self.cell_height / factor
        fine = " (cell_size / fine_factor)" if factor > 1 else ""
        or_factor = " or decrease fine_factor" if factor > 1 else ""
        if self.agent_height / self.cell_height < 3 - 1e-6:
            raise ValueError(
                f"agent_height {self.agent_height} m must be at least 3 cells "
                f"of cell_height {self.cell_height} m"
            )
        if self.agent_radius / cell_size > 250:
            raise ValueError(
                f"agent_radius {self.agent_radius} m is more than 250 cells of cell_size {cell_size} m"
                f"{fine}: increase cell_size{or_factor}"
            )
        if self.agent_max_climb / cell_height > 8000:
            raise ValueError(
                f"agent_max_climb is more than 8000 cells of cell_height{fine}: "
                f"increase cell_height{or_factor}"
            )
        if 0 < self.tile_size < 16 or self.tile_size > _MAX_CELLS_PER_TILE:
            raise ValueError(
                f"tile_size must be 0 (one tile) or 16..{_MAX_CELLS_PER_TILE} cells, got {self.tile_size}"
            )
        if self.fine_region is not None:
            xmin, ymin, xmax, ymax = self.fine_region
            if not (xmin < xmax and ymin < ymax):
                raise ValueError(
                    "fine_region must be [xmin, ymin, xmax, ymax] with xmin < xmax and ymin < ymax, "
                    f"got {list(self.fine_region)}"
                )
            if self.tile_size == 0:
                raise ValueError(
                    "fine_region needs a tiled build (the tiles meeting it are built finer): "
                    "set tile_size > 0"
                )
            if self.tile_size * factor > _MAX_CELLS_PER_TILE:
                raise ValueError(
                    f"fine tiles have tile_size * fine_factor = {self.tile_size * factor} cells per side, "
                    f"more than {_MAX_CELLS_PER_TILE}: decrease tile_size or fine_factor"
                )
        return self

    @classmethod
    def preset(cls, name: str) -> NavMeshSettings:
        """The settings of a named preset (``"indoor"``, ``"outdoor"`` or ``"i2o"``).

        Parameters
        ----------
        name : str
            Preset name, a key of :data:`PRESETS`.

        Returns
        -------
        NavMeshSettings
            The preset (an immutable, shared instance).

        Raises
        ------
        NavMeshError
            On an unknown name.
        """
        try:
            return PRESETS[name]
        except KeyError:
            raise NavMeshError(
                f"unknown navmesh preset {name!r}; choose from: {', '.join(PRESETS)}"
            ) from None

    def with_overrides(self, overrides: BaseModel | Mapping[str, Any]) -> NavMeshSettings:
        """These settings with some fields replaced, validated as a whole.

        Parameters
        ----------
        overrides : NavMeshOverrides or mapping
            Fields to replace; unset (None) fields keep their value here.

        Returns
        -------
        NavMeshSettings

        Raises
        ------
        NavMeshError
            When the combination is invalid (e.g. an agent height under 3 cell heights).
        """
        changes = (
            overrides.model_dump(exclude_none=True) if isinstance(overrides, BaseModel) else dict(overrides)
        )
        try:
            return NavMeshSettings.model_validate({**self.model_dump(), **changes})
        except ValidationError as exc:
            problems = "; ".join(
                f"{'.'.join(str(p) for p in e['loc']) or 'settings'}: {e['msg']}" for e in exc.errors()
            )
            raise NavMeshError(f"invalid navmesh settings: {problems}") from None


INDOOR = NavMeshSettings(
    cell_size=0.05,
    cell_height=0.05,
    agent_height=0.6,
    agent_radius=0.6,
    agent_max_climb=0.2,
    agent_max_slope=45.0,
    region_min_size=8.0,
    region_merge_size=0.0,
    edge_max_len=0.0,
    edge_max_error=1.5,
    verts_per_poly=6,
    detail_sample_dist=1.0,
    detail_sample_max_error=0.0,
    filter_low_hanging_obstacles=True,
    filter_ledge_spans=True,
    filter_walkable_low_height_spans=True,
    fill_solid_interiors=True,
    tile_size=256,
)
"""Indoor scenes: fine voxels (5 cm) for narrow passages (paper, table ``tab:navmesh_params``)."""

OUTDOOR = INDOOR.model_copy(
    update={"cell_size": 0.1, "cell_height": 0.1, "agent_max_climb": 0.3, "detail_sample_max_error": 1.0}
)
"""Outdoor scenes: 10 cm voxels and curbs up to 0.30 m (paper, table ``tab:navmesh_params``).

One value departs from the table: ``detail_sample_max_error`` is 1 cell height instead of 0. The
heightfield holds heights in whole cells, so on a ramp (street crossings, curb ramps, sloped
terrain) a detail mesh held to no error at all follows every voxel step, adding height samples up
to Recast's cap of 127 vertices per polygon; that tracing was ~80 % of a city's build time. Within
one cell height the detail mesh follows the surface rather than its voxel steps: on a 500 m
synthetic city the build is ~10x faster, the navigable area 0.3 % smaller (the steps' risers no
longer count) and geodesic distances change by 0.02 % (median; 99th percentile 0.3 %).
"""

I2O = OUTDOOR.model_copy(update={"fine_factor": 2})
"""Indoor-to-outdoor scenes: :data:`OUTDOOR`, with the tiles meeting ``fine_region`` at 5 cm.

The region is the scene's own (its buildings' footprints grown by a margin), so the preset has
``fine_region=None`` and builds like :data:`OUTDOOR` until the caller sets it, e.g.
``I2O.with_overrides({"fine_region": (xmin, ymin, xmax, ymax)})``. Fine tiles have 5 cm cells,
the indoor cell size, and keep the outdoor climb (0.30 m).
"""

PRESETS: Mapping[str, NavMeshSettings] = MappingProxyType({"indoor": INDOOR, "outdoor": OUTDOOR, "i2o": I2O})
"""The presets by name (read-only)."""


def _optional_fields() -> dict[str, Any]:
    fields: dict[str, Any] = {}
    for name, info in NavMeshSettings.model_fields.items():
        annotation = Annotated[(info.annotation, *info.metadata)] if info.metadata else info.annotation
        fields[name] = (annotation | None, Field(None, description=info.description))
    return fields


NavMeshOverrides = create_model(
    "NavMeshOverrides",
    __config__=ConfigDict(frozen=True, extra="forbid", allow_inf_nan=False),
    __doc__=(
        "Some fields of :class:`NavMeshSettings` (each optional, with the same constraints), to apply "
        "over a preset with :meth:`NavMeshSettings.with_overrides`; recipes use it."
    ),
    **_optional_fields(),
)
