"""Scenes imported from a user mesh file (OBJ, glTF/GLB, PLY, USD), its nodes labelled by recipe rules."""

from __future__ import annotations

import re
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Literal

from pydantic import AfterValidator, Field, ValidationInfo, field_validator, model_validator

from navverse.scene.terrain import TerrainName, known_terrain_class
from navverse.scene_types import SceneTypeSettings
from pipeline import Params, SourceFile, StageContext, stage
from pipeline.params import ReadPolicy

if TYPE_CHECKING:
    from navverse.scene.mesh_nodes import MeshNode
    from navverse.scene.mesh_parts import NodeRole

DROP = "drop"


def _mesh_suffix(path: Path) -> Path:
    from navverse.scene.mesh_import import MESH_SUFFIXES

    if path.suffix.lower() not in MESH_SUFFIXES:
        raise ValueError(
            f"unsupported mesh format {path.suffix or '(no suffix)'!r} of {path.name}; use one of "
            f"{', '.join(MESH_SUFFIXES)} (convert the file, e.g. with Blender)"
        )
    return path


def _usd_files_allowed(path: Path, info: ValidationInfo) -> Path:
    """Refuse a USD file that brings in (sublayers, references, payloads, clips) a file the recipe
    may not read: not a regular file, too big, or outside the allowed folders."""
    from navverse.scene.mesh_files import MeshImportError, UsdDependencyError, usd_layer_files
    from navverse.scene.mesh_import import USD_SUFFIXES

    policy = ReadPolicy.from_context(info)
    if policy is None or path.suffix.lower() not in USD_SUFFIXES:
        return path  # without a project (parameters checked before), the stage checks when it reads
    try:
        usd_layer_files(path, check=lambda file, written: policy.refusal(file, written=written))
    except UsdDependencyError as exc:
        raise ValueError(str(exc)) from None
    except MeshImportError:
        pass  # a layer USD cannot parse: the stage reports it when it runs
    return path


MeshSource = Annotated[SourceFile, AfterValidator(_mesh_suffix), AfterValidator(_usd_files_allowed)]
"""A mesh file: a path relative to the recipe's folder, or ``{package_data: <package>, file: <path>}``
(a data file of an installed package, e.g. ``pybullet_data``); content-hashed into the cache key, with
the layers a USD file brings in. The file-access policy of :data:`pipeline.params.SourceFile` holds
for it and for every USD layer it brings in."""


class NodeRule(Params):
    """What the nodes matching a pattern become: exactly one of ``object`` (an annotated object of
    that category), ``surface`` (static geometry of that terrain class) or ``drop: true``.
    """

    pattern: str
    """Python regular expression searched (``re.search``, not anchored) in the node's name or path."""
    on: Literal["name", "path"] = "name"
    """What ``pattern`` is searched in: ``name`` (trimesh node name, OBJ object/group/material name, USD
    prim name) or ``path`` (``/parent/.../name``; the USD prim path)."""
    object: str | None = None
    """Make the matching nodes annotated objects (goal candidates) of this category (lower_snake_case,
    e.g. ``stone_lantern``)."""
    surface: TerrainName | None = None
    """Make the matching nodes static geometry of this terrain class (``floor``, ``wall``, ``road``...)."""
    drop: bool = False
    """Leave the matching nodes out of the scene."""
    split: Literal["none", "components"] = "none"
    """``none``: one object (or surface) per node; ``components``: one per connected piece of the node,
    pieces whose bounding boxes come within ``join_gap`` of each other counting as one (e.g. a
    lantern's stacked stones)."""
    join_gap: Annotated[float, Field(ge=0.0, le=10.0, description="Meters, 0 to 10.")] = 0.05

    @field_validator("pattern")
    @classmethod
    def _compiles(cls, value: str) -> str:
        try:
            re.compile(value)
        except re.error as exc:
            raise ValueError(f"invalid regular expression {value!r}: {exc}") from None
        return value

    @field_validator("object")
    @classmethod
    def _category(cls, value: str | None) -> str | None:
        from navverse.scene.categories import CATEGORY_PATTERN

        if value is not None and not re.match(CATEGORY_PATTERN, value):
            raise ValueError(f"object category {value!r} must be lower_snake_case, e.g. 'stone_lantern'")
        return value

    @model_validator(mode="after")
    def _one_outcome(self) -> NodeRule:
        given = [k for k in ("object", "surface") if getattr(self, k) is not None] + (
            ["drop"] if self.drop else []
        )
        if len(given) != 1:
            raise ValueError(
                f"give exactly one of 'object: <category>', 'surface: <terrain class>' or 'drop: true' "
                f"(got {', '.join(given) or 'none'})"
            )
        return self

    def matches(self, *, name: str, path: str) -> bool:
        """Whether the rule's pattern is found in the node's name (or path)."""
        return re.search(self.pattern, name if self.on == "name" else path) is not None


class ImportMeshParams(Params, SceneTypeSettings):
    """Parameters of :func:`import_mesh`: the mesh file, its units and up axis, and the rules that
    label its nodes (each node takes the first matching rule, unmatched nodes become ``default``).

    ``subdivide`` splits every triangle into four that many times (same shape, 4^n faces: dense test
    meshes for ``decimate``).
    """

    source: MeshSource
    """The mesh file (OBJ, glTF/GLB, PLY or USD); a USD file's sublayers, references, payloads and clips
    are read (and hashed into the cache key) with it."""
    units: (
        Annotated[float, Field(ge=1e-6, le=1e3, description="Meters per file unit: 1e-6 (µm) to 1000 (km).")]
        | str
        | None
    ) = None
    """Meters per file unit, as a number or a unit name (``meters``, ``centimeters``, ``millimeters``,
    ``inches``, ``feet``); null: what the file declares (a USD stage's ``metersPerUnit``, glTF's
    meters), else 1."""
    up_axis: Literal["y", "z"] | None = None
    """The file's up axis (the scene is turned to +z up); null: what the file declares (a USD stage's
    ``upAxis``, glTF's +y). OBJ and PLY files declare none, so their recipes must give it."""
    rules: list[NodeRule] = []
    """What the nodes become (object, surface or dropped), tried in order: a node takes the first rule
    whose pattern it matches."""
    default: str = "obstacle"
    """What a node no rule matches becomes: static geometry of this terrain class, or ``drop`` (left
    out)."""
    friction: dict[
        TerrainName, Annotated[float, Field(ge=0, le=5, description="Friction coefficient, 0 to 5.")]
    ] = {}
    """Friction coefficient (dimensionless) by terrain class, replacing the class's own; only classes
    the rules or ``default`` use."""
    subdivide: Annotated[int, Field(ge=0, le=3, description="Subdivisions, 0 to 3 (4^n faces).")] = 0

    def dependency_files(self) -> dict[str, Path]:
        """The layers a USD source brings in (sublayers, references, payloads, clips): their content
        is part of the cache key too, so editing a sublayer rebuilds the scene."""
        from navverse.scene.mesh_files import MeshImportError, usd_layer_files
        from navverse.scene.mesh_import import USD_SUFFIXES

        if self.source.suffix.lower() not in USD_SUFFIXES:
            return {}
        try:
            layers = usd_layer_files(self.source)
        except MeshImportError:
            return {}  # the stage reports it when it runs
        return {f"source_layer_{index}": path for index, path in enumerate(layers[1:], start=1)}

    @field_validator("units")
    @classmethod
    def _unit_name(cls, value: float | str | None) -> float | str | None:
        from navverse.scene.mesh_import import UNIT_SCALES

        if isinstance(value, str) and value not in UNIT_SCALES:
            raise ValueError(
                f"unknown unit {value!r}; give meters per unit as a number or one of {', '.join(UNIT_SCALES)}"
            )
        return value

    @field_validator("up_axis")
    @classmethod
    def _axis_known(cls, value: str | None, info: ValidationInfo) -> str | None:
        source = info.data.get("source")
        if value is None and source is not None and source.suffix.lower() in (".obj", ".ply"):
            raise ValueError(
                f"{source.suffix} files do not say which axis is up; set 'up_axis: y' or 'up_axis: z'"
            )
        return value

    @field_validator("default")
    @classmethod
    def _default_class(cls, value: str) -> str:
        return value if value == DROP else known_terrain_class(value)

    @field_validator("friction")
    @classmethod
    def _friction_used(cls, value: dict[str, float], info: ValidationInfo) -> dict[str, float]:
        used = {rule.surface for rule in info.data.get("rules", [])} | {info.data.get("default")}
        unused = sorted(set(value) - used)
        if unused:
            raise ValueError(f"'friction' names classes no rule (nor 'default') uses: {', '.join(unused)}")
        return value

    @property
    def meters_per_unit(self) -> float | None:
        """Meters per file unit set by the recipe (None: the file's own)."""
        from navverse.scene.mesh_import import UNIT_SCALES

        if isinstance(self.units, str):
            return UNIT_SCALES[self.units]
        return self.units


def _roles(params: ImportMeshParams, nodes: list[MeshNode]) -> tuple[list[NodeRole | None], list[int]]:
    """The role of every node (first matching rule, else the default) and the matches per rule."""
    from navverse.scene.mesh_parts import NodeRole

    hits = [0] * len(params.rules)
    roles: list[NodeRole | None] = []
    for node in nodes:
        index = next(
            (i for i, r in enumerate(params.rules) if r.matches(name=node.name, path=node.path)), None
        )
        if index is None:
            role = None if params.default == DROP else NodeRole("surface", params.default)
        else:
            hits[index] += 1
            rule = params.rules[index]
            split, gap = rule.split == "components", rule.join_gap
            if rule.object is not None:
                role = NodeRole("object", rule.object, split=split, join_gap=gap)
            elif rule.surface is not None:
                role = NodeRole("surface", rule.surface, split=split, join_gap=gap)
            else:
                role = None
        roles.append(role)
    return roles, hits


@stage(
    name="import_mesh",
    outputs=["raw_geometry"],
    summary={
        "nodes": "nodes",
        "dropped nodes": "dropped_nodes",
        "surfaces": "surfaces",
        "objects": "objects",
        "faces": "faces",
    },
)
def import_mesh(ctx: StageContext, params: ImportMeshParams) -> None:
    """A scene directory (scene.usdc, scene.json, bev.png) of a mesh file's nodes as objects and surfaces."""
    import navverse
    from navverse.scene.annotations import SceneSource
    from navverse.scene.compose import assemble_scene
    from navverse.scene.directory import write_scene_dir
    from navverse.scene.mesh_files import MeshImportError
    from navverse.scene.mesh_import import check_extent, read_mesh_nodes, to_z_up
    from navverse.scene.mesh_nodes import MeshNode
    from navverse.scene.mesh_parts import scene_parts
    from navverse.scene.terrain import terrain_classes

    nodes, frame = read_mesh_nodes(params.source, progress=ctx.progress)
    up_axis = params.up_axis or frame.up_axis or "z"
    meters_per_unit = params.meters_per_unit or frame.meters_per_unit or 1.0
    nodes = [
        MeshNode(n.name, n.path, to_z_up(n.mesh, up_axis=up_axis, meters_per_unit=meters_per_unit))
        for n in nodes
    ]
    check_extent(nodes, source=params.source, meters_per_unit=meters_per_unit)
    roles, hits = _roles(params, nodes)
    for rule, count in zip(params.rules, hits, strict=True):
        if count == 0:
            ctx.log.warning(
                "rule %r (on %s) matches no node of %s", rule.pattern, rule.on, params.source.name
            )
    surfaces, objects = scene_parts(nodes, roles, subdivisions=params.subdivide, progress=ctx.progress)
    if not surfaces and not objects:
        raise MeshImportError(
            f"nothing of {params.source.name} is kept: every one of its {len(nodes)} nodes is dropped; "
            "change the rules or set 'default' to a terrain class"
        )
    used = {s.terrain_class for s in surfaces}
    scene = assemble_scene(
        scene_id=ctx.target,
        scene_type=params.scene_type,
        surfaces=surfaces,
        objects=objects,
        terrain_classes=terrain_classes(
            sorted(used), overrides={k: v for k, v in params.friction.items() if k in used}
        ),
        source=SceneSource(
            recipe=ctx.recipe, recipe_hash=ctx.recipe_hash, toolkit_version=navverse.__version__
        ),
    )
    write_scene_dir(scene, ctx.output)
    faces = scene.annotations.statistics.faces
    ctx.record(
        source=params.source.name,
        up_axis=up_axis,
        meters_per_unit=meters_per_unit,
        nodes=len(nodes),
        dropped_nodes=sum(role is None for role in roles),
        rule_matches=hits,
        faces=faces,
        surfaces=len(surfaces),
        objects=len(objects),
    )
    ctx.log.info(
        "import_mesh %s: %d nodes of %s -> %d surfaces, %d objects, %d faces",
        ctx.target, len(nodes), params.source.name, len(surfaces), len(objects), faces,
    )  # fmt: skip
