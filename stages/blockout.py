"""Scenes assembled from primitive solids declared in the recipe (test courses, quick layouts)."""

from __future__ import annotations

import math
from typing import Annotated

import numpy as np
from pydantic import Field, model_validator

from navverse.scene.terrain import TerrainName
from navverse.scene_types import SceneTypeSettings
from pipeline import Params, StageContext, stage

MAX_SIZE_M = 2000.0
"""Longest side of a solid (m)."""
MAX_HEIGHT_M = 500.0
"""Tallest ramp or cylinder (m)."""
MAX_COORDINATE_M = 10_000.0
"""Farthest a solid's centre may be from the origin along each axis (m)."""
MAX_SOLIDS = 10_000
"""Most surfaces, and most objects, in one blockout."""

Length = Annotated[float, Field(gt=0, le=MAX_SIZE_M, description="Meters, more than 0, at most 2000.")]
Height = Annotated[float, Field(gt=0, le=MAX_HEIGHT_M, description="Meters, more than 0, at most 500.")]
Coordinate = Annotated[
    float, Field(ge=-MAX_COORDINATE_M, le=MAX_COORDINATE_M, description="Meters, -10000 to 10000.")
]
Vec3 = tuple[Coordinate, Coordinate, Coordinate]
Size3 = tuple[Length, Length, Length]


class RampShape(Params):
    """A wedge rising along its local +x by ``height`` over ``length`` (m; sides up to 2000 m,
    height up to 500 m)."""

    length: Length
    width: Length
    height: Height


class CylinderShape(Params):
    """An upright cylinder (m; radius up to 1000 m, height up to 500 m)."""

    radius: Annotated[float, Field(gt=0, le=MAX_SIZE_M / 2, description="Meters, at most 1000.")]
    height: Height


class Solid(Params):
    """A primitive solid: exactly one of ``box`` (its size), ``ramp`` or ``cylinder``, placed with
    its bounding-box centre at ``center`` and turned by ``yaw_deg`` about +z.

    Physical ranges: box sides 0 < s <= 2000 m, centre coordinates within +-10000 m, yaw within
    +-360 degrees.
    """

    center: Vec3
    """World position ``[x, y, z]`` of the solid's bounding-box centre (m, z up)."""
    yaw_deg: Annotated[float, Field(ge=-360.0, le=360.0, description="Degrees, -360 to 360.")] = 0.0
    box: Size3 | None = None
    """A box: its sides ``[x, y, z]`` along the solid's own axes (m)."""
    ramp: RampShape | None = None
    """A wedge rising along the solid's own +x (its ``length``, ``width`` and ``height``, m)."""
    cylinder: CylinderShape | None = None
    """An upright cylinder (its ``radius`` and ``height``, m)."""

    @model_validator(mode="after")
    def _one_shape(self) -> Solid:
        given = [name for name in ("box", "ramp", "cylinder") if getattr(self, name) is not None]
        if len(given) != 1:
            raise ValueError(f"give exactly one shape of box, ramp or cylinder (got {given or 'none'})")
        return self

    def local_mesh(self) -> tuple[np.ndarray, np.ndarray]:
        """Vertices (local frame, centred) and faces of the solid."""
        from navverse.assets.primitives import box, cylinder, ramp

        if self.box is not None:
            return box(self.box)
        if self.ramp is not None:
            return ramp(self.ramp.length, self.ramp.width, self.ramp.height)
        assert self.cylinder is not None
        return cylinder(self.cylinder.radius, self.cylinder.height)

    def size(self) -> Vec3:
        """Extent along the solid's own axes."""
        vertices, _ = self.local_mesh()
        extent = vertices.max(axis=0) - vertices.min(axis=0)
        return (float(extent[0]), float(extent[1]), float(extent[2]))


class SurfaceSolid(Solid):
    """Static geometry of one terrain class (floor, wall, road, curb...)."""

    name: Annotated[str, Field(pattern=r"^[A-Za-z_][A-Za-z0-9_]*$")]
    """Name of the surface, unique in the blockout (letters, digits and underscores)."""
    terrain: TerrainName
    """Terrain class of the surface (``floor``, ``wall``, ``road``, ``curb``...), a class of the default
    terrain table; it sets the surface's friction."""


class ObjectSolid(Solid):
    """An annotated object (a goal candidate) of a semantic category."""

    category: Annotated[str, Field(pattern=r"^[a-z][a-z0-9_]*$")]
    """Semantic category of the object (lower_snake_case): what an agent is asked to find."""


class BlockoutParams(Params, SceneTypeSettings):
    """Parameters of :func:`blockout`: the ``scene_type`` (:class:`navverse.scene_types.SceneTypeSettings`),
    ``friction`` per terrain class used, the ``surfaces`` and the ``objects``."""

    friction: dict[str, Annotated[float, Field(ge=0, le=5, description="Friction coefficient, 0 to 5.")]] = {}
    """Friction coefficient (dimensionless) by terrain class, replacing the class's own; only classes
    the surfaces use."""
    surfaces: Annotated[list[SurfaceSolid], Field(min_length=1, max_length=MAX_SOLIDS)]
    """The static geometry: solids of a terrain class each, with unique names."""
    objects: Annotated[list[ObjectSolid], Field(max_length=MAX_SOLIDS)] = []
    """The annotated objects (goal candidates): solids of a semantic category each."""

    @model_validator(mode="after")
    def _consistent(self) -> BlockoutParams:
        names = [s.name for s in self.surfaces]
        repeated = sorted({n for n in names if names.count(n) > 1})
        if repeated:
            raise ValueError(f"surface names must be unique; repeated: {', '.join(repeated)}")
        unused = sorted(set(self.friction) - {s.terrain for s in self.surfaces})
        if unused:
            raise ValueError(f"'friction' names classes no surface uses: {', '.join(unused)}")
        return self


@stage(name="blockout", outputs=["geometry"], summary=("surfaces", "objects", "faces"))
def blockout(ctx: StageContext, params: BlockoutParams) -> None:
    """A scene directory (scene.usdc, scene.json, bev.png) built from the recipe's primitive solids."""
    import navverse
    from navverse.scene.annotations import SceneSource
    from navverse.scene.compose import ObjectPart, assemble_scene
    from navverse.scene.directory import write_scene_dir
    from navverse.scene.geometry import MeshData, Surface
    from navverse.scene.terrain import terrain_classes

    surfaces = []
    for solid in params.surfaces:
        vertices, faces = solid.local_mesh()
        local = MeshData(vertices=vertices, faces=faces)
        mesh = local.transformed(solid.center, math.radians(solid.yaw_deg))
        surfaces.append(Surface(name=solid.name, terrain_class=solid.terrain, mesh=mesh))
    objects = []
    for solid in params.objects:
        vertices, faces = solid.local_mesh()
        mesh = MeshData(vertices=vertices, faces=faces)
        objects.append(
            ObjectPart(solid.category, mesh, solid.center, math.radians(solid.yaw_deg), solid.size())
        )
    scene = assemble_scene(
        scene_id=ctx.target,
        scene_type=params.scene_type,
        surfaces=surfaces,
        objects=objects,
        terrain_classes=terrain_classes(
            sorted({s.terrain for s in params.surfaces}), overrides=params.friction
        ),
        source=SceneSource(
            recipe=ctx.recipe, recipe_hash=ctx.recipe_hash, toolkit_version=navverse.__version__
        ),
    )
    faces = scene.annotations.statistics.faces
    write_scene_dir(scene, ctx.output)
    ctx.record(faces=faces, surfaces=len(surfaces), objects=len(objects))
    ctx.log.info(
        "blockout %s: %d surfaces, %d objects, %d faces", ctx.target, len(surfaces), len(objects), faces
    )
