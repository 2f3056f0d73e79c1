"""Outdoor cities: a city map from an OSM file or a seed, then its geometry (roads below real curbs)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

from pydantic import AfterValidator, Field, model_validator

from navverse.city.synthetic import SyntheticCityParams
from pipeline import Params, SourceFile, StageContext, stage
from stages._terrain_names import TerrainName

if TYPE_CHECKING:
    from navverse.city.map import CityMap
    from navverse.scene.geometry import MeshData

CITY_MAP_FILE = "city_map.json"
"""The file of a ``city_map`` artifact."""


def _osm_name(path: Path) -> Path:
    if not path.name.lower().endswith((".osm", ".osm.gz", ".osm.pbf")):
        raise ValueError(f"{path.name} is not an OSM file: give a .osm, .osm.gz or .osm.pbf file")
    return path


Latitude = Annotated[float, Field(ge=-90.0, le=90.0, description="Degrees north, -90 to 90.")]
Longitude = Annotated[float, Field(ge=-180.0, le=180.0, description="Degrees east, -180 to 180.")]
Side = Annotated[float, Field(gt=0.0, le=50_000.0, description="Meters, more than 0, at most 50 km.")]


class OsmCityParams(Params):
    """Parameters of :func:`osm_city`.

    ``source`` is a local ``.osm``, ``.osm.gz`` or ``.osm.pbf`` file. The window is ``center``
    ``[lat, lon]`` with ``size_m`` ``[east-west, north-south]`` (default 1000 m × 1000 m), or
    ``bbox`` ``[min_lat, min_lon, max_lat, max_lon]``; with neither, the centre of the file's
    declared bounds. Validation reads the file's header: the centre must lie inside the bounds it
    declares.
    """

    source: Annotated[SourceFile, AfterValidator(_osm_name)]
    center: tuple[Latitude, Longitude] | None = None
    size_m: tuple[Side, Side] = (1000.0, 1000.0)
    bbox: tuple[Latitude, Longitude, Latitude, Longitude] | None = None

    @model_validator(mode="after")
    def _window_on_the_data(self) -> OsmCityParams:
        from navverse.city.map import CityMapError
        from navverse.city.osm import check_window

        try:
            check_window(self.source, center=self.center, size_m=self.size_m, bbox=self.bbox)
        except CityMapError as exc:
            raise ValueError(str(exc)) from None
        return self


@stage(name="osm_city", outputs=["city_map"])
def osm_city(ctx: StageContext, params: OsmCityParams) -> None:
    """city_map.json: roads, walkways, crossings, areas, buildings, POIs and furniture of an OSM window."""
    from navverse.city.map import write_city_map
    from navverse.city.osm import read_osm

    def progress(phase: str, done: int) -> None:
        ctx.progress(done, 0, "checksum (bytes)" if phase == "checksum" else "OSM objects")

    city = read_osm(
        params.source,
        center=params.center,
        size_m=params.size_m,
        bbox=params.bbox,
        seed=ctx.seed % 2**32,
        progress=progress,
    )
    write_city_map(city, ctx.output / CITY_MAP_FILE)
    _record_map(ctx, city)


class SyntheticCityStageParams(Params, SyntheticCityParams):
    """Parameters of :func:`synthetic_city` (:class:`navverse.city.synthetic.SyntheticCityParams`),
    plus ``write_osm``: also write the map as ``city.osm`` (OSM XML that osmnx and JOSM read)."""

    write_osm: bool = False


@stage(name="synthetic_city", outputs=["city_map"])
def synthetic_city(ctx: StageContext, params: SyntheticCityStageParams) -> None:
    """city_map.json (and city.osm if asked): a city drawn from the target's seed, as a real one's records."""
    from navverse.city.map import write_city_map
    from navverse.city.osm_xml import write_osm
    from navverse.city.synthetic import synthetic_city as draw_city

    knobs = SyntheticCityParams.model_validate(params.model_dump(exclude={"write_osm"}))
    city = draw_city(knobs, seed=ctx.seed % 2**32)
    write_city_map(city, ctx.output / CITY_MAP_FILE)
    if params.write_osm:
        write_osm(city, ctx.output / "city.osm")
    _record_map(ctx, city)


def _record_map(ctx: StageContext, city: CityMap) -> None:
    from navverse.city.scene import road_length

    ctx.record(
        roads=len(city.roads),
        road_km=round(road_length(city) / 1000.0, 3),
        walkways=len(city.walkways),
        crossings=len(city.crossings),
        areas=len(city.areas),
        buildings=len(city.buildings),
        pois=len(city.pois),
        furniture=len(city.furniture),
        dropped=dict(city.dropped),
    )
    dropped = ", ".join(f"{reason} {n}" for reason, n in city.dropped.items()) or "nothing"
    ctx.log.info(
        "city map %s: %d roads (%.1f km), %d buildings, %d crossings, %d areas; dropped: %s",
        ctx.target, len(city.roads), road_length(city) / 1000.0, len(city.buildings),
        len(city.crossings), len(city.areas), dropped,
    )  # fmt: skip


Grade = Annotated[float, Field(ge=-0.3, le=0.3, description="Rise per meter, -0.3 to 0.3.")]


class CityGeometryParams(Params):
    """Parameters of :func:`city_geometry` (lengths in meters).

    ``road_depression``: how far roads lie below the sidewalks (the curb height).
    ``lowered_curb_height``: the step left where a crosswalk meets the curb (``kerb=lowered``).
    ``ramp_length``: how far into the road a crosswalk ramps down from it.
    ``junction_crosswalks``: add crosswalks across every arm of junctions of roads with sidewalks,
    besides the mapped crossings. ``slope``: an analytic terrain (rise per meter east, north) that
    every surface follows, curbs included. ``friction``: per terrain class, replacing the table's.
    """

    road_depression: Annotated[float, Field(ge=0.0, le=0.5)] = 0.2
    lowered_curb_height: Annotated[float, Field(ge=0.0, le=0.05)] = 0.005
    ramp_length: Annotated[float, Field(ge=0.3, le=5.0)] = 1.5
    curb_width: Annotated[float, Field(ge=0.05, le=1.0)] = 0.15
    crosswalk_width: Annotated[float, Field(ge=2.0, le=10.0)] = 4.0
    water_depth: Annotated[float, Field(ge=0.1, le=5.0)] = 0.5
    junction_crosswalks: bool = True
    slope: tuple[Grade, Grade] = (0.0, 0.0)
    friction: dict[
        TerrainName,
        Annotated[float, Field(ge=0, le=5, description="Friction coefficient, 0 to 5.")],
    ] = {}

    @model_validator(mode="after")
    def _lip_below_curb(self) -> CityGeometryParams:
        if self.lowered_curb_height > self.road_depression:
            raise ValueError(
                f"lowered_curb_height ({self.lowered_curb_height}) must not exceed road_depression "
                f"({self.road_depression})"
            )
        return self


@stage(name="city_geometry", inputs=["city_map"], outputs=["street_geometry"])
def city_geometry(ctx: StageContext, params: CityGeometryParams) -> None:
    """A scene (roads below curbs, crosswalks, sidewalks, land, buildings) and its street plan."""
    import numpy as np

    import navverse
    from navverse.city.ground import GroundSettings
    from navverse.city.map import read_city_map
    from navverse.city.scene import CityGeometry, city_scene, geometry_plan
    from navverse.city.street_plan import STREET_PLAN_FILE, save_street_plan
    from navverse.scene import SceneSource, write_scene_dir

    city = read_city_map(ctx.input("city_map") / CITY_MAP_FILE)
    geometry = CityGeometry(
        ground=GroundSettings(
            road_depression=params.road_depression,
            lowered_curb_height=params.lowered_curb_height,
            ramp_length=params.ramp_length,
            water_depth=params.water_depth,
        ),
        curb_width=params.curb_width,
        crosswalk_width=params.crosswalk_width,
        junction_crosswalks=params.junction_crosswalks,
        friction=dict(params.friction),
    )
    grade_x, grade_y = params.slope

    def terrain(points: np.ndarray) -> np.ndarray:
        return points[:, 0] * grade_x + points[:, 1] * grade_y

    ctx.progress(0, 3, "plan")
    plan = geometry_plan(city, geometry)
    ctx.progress(1, 3, "geometry")
    scene = city_scene(
        city,
        scene_id=ctx.target,
        geometry=geometry,
        terrain=terrain,
        plan=plan,
        source=SceneSource(
            recipe=ctx.recipe, recipe_hash=ctx.recipe_hash, toolkit_version=navverse.__version__
        ),
    )
    ctx.progress(2, 3, "writing")
    write_scene_dir(scene, ctx.output)
    save_street_plan(plan, ctx.output / STREET_PLAN_FILE)
    ctx.progress(3, 3, "done")
    stats = scene.annotations.statistics
    areas = {s.name: round(_top_area(s.mesh), 1) for s in scene.surfaces if s.terrain_class != "building"}
    ctx.record(
        faces=stats.faces,
        buildings=stats.buildings,
        road_km=round(stats.road_length_m / 1000.0, 3),
        surface_area_m2=areas,
        dropped=dict(city.dropped),
    )
    ctx.log.info(
        "city geometry %s: %d buildings, %.1f km of roads, %.0f m2 of sidewalk, %d faces",
        ctx.target, stats.buildings, stats.road_length_m / 1000.0, areas.get("sidewalk", 0.0), stats.faces,
    )  # fmt: skip


def _top_area(mesh: MeshData) -> float:
    """Area of a mesh's upward faces, projected on the ground (m²)."""
    import numpy as np

    v = mesh.vertices[mesh.faces]
    cross = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    return float(cross[cross[:, 2] > 1e-12, 2].sum() / 2.0)
