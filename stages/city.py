"""Outdoor cities: a city map from an OSM file or a seed, then its geometry (roads below real curbs)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from pydantic import model_validator

from navverse.city.geometry.scene import CityGeometry
from navverse.city.osm.window import OsmWindow
from navverse.city.synthetic.generator import SyntheticCityParams
from pipeline import Params, SourceFile, StageContext, stage

if TYPE_CHECKING:
    from navverse.city.map import CityMap
    from navverse.scene.geometry import MeshData

CITY_MAP_FILE = "city_map.json"
"""The file of a ``city_map`` artifact."""

_MAP_SUMMARY = {
    "buildings": "buildings",
    "roads": "roads",
    "road km": "road_km",
    "pois": "pois",
    "dropped": "dropped",
}
"""What the build summary says a city map holds (its stats: :func:`_record_map`)."""


class OsmCityParams(Params, OsmWindow):
    """Parameters of :func:`osm_city`: the OSM file (``source``) and the window of it to read.

    The window is ``center`` ``[lat, lon]`` with ``size_m`` ``[east-west, north-south]`` (default
    1000 m × 1000 m), or ``bbox`` ``[min_lat, min_lon, max_lat, max_lon]``; with neither, the centre of
    the file's declared bounds (the node nearest the median of its nodes, for a file that declares none).
    Validation reads the file's header: the centre must lie inside the
    bounds it declares.
    """

    source: SourceFile
    """The local OSM file: OSM XML, gzipped or bzip2-compressed OSM XML, or PBF, recognised by its
    content (``.osm``, ``.osm.xml.gz``, ``.osm.bz2``, ``.osm.pbf``, a link named anything)."""

    @model_validator(mode="after")
    def _window_on_the_data(self) -> OsmCityParams:
        from navverse.city.map import CityMapError
        from navverse.city.osm.reader import check_window

        try:
            check_window(self.source, center=self.center, size_m=self.size_m, bbox=self.bbox)
        except CityMapError as exc:
            raise ValueError(str(exc)) from None
        return self


@stage(name="osm_city", outputs=["city_map"], summary=_MAP_SUMMARY)
def osm_city(ctx: StageContext, params: OsmCityParams) -> None:
    """city_map.json: roads, walkways, crossings, areas, buildings, POIs and furniture of an OSM window."""
    from navverse.city.map import write_city_map
    from navverse.city.osm.reader import read_osm

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
    """Parameters of :func:`synthetic_city` (:class:`navverse.city.synthetic.generator.SyntheticCityParams`),
    plus ``write_osm``."""

    write_osm: bool = False
    """Also write the map as ``city.osm`` in the artifact: OSM XML that osmnx and JOSM read."""


@stage(name="synthetic_city", outputs=["city_map"], summary=_MAP_SUMMARY)
def synthetic_city(ctx: StageContext, params: SyntheticCityStageParams) -> None:
    """city_map.json (and city.osm if asked): a city drawn from the target's seed, as a real one's records."""
    from navverse.city.map import write_city_map
    from navverse.city.osm.writer import write_osm
    from navverse.city.synthetic.generator import synthetic_city as draw_city

    knobs = SyntheticCityParams.model_validate(params.model_dump(exclude={"write_osm"}))
    city = draw_city(knobs, seed=ctx.seed % 2**32)
    write_city_map(city, ctx.output / CITY_MAP_FILE)
    if params.write_osm:
        write_osm(city, ctx.output / "city.osm")
    _record_map(ctx, city)


def _record_map(ctx: StageContext, city: CityMap) -> None:
    from navverse.city.geometry.scene import road_length

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


class CityGeometryParams(Params, CityGeometry):
    """Parameters of :func:`city_geometry`: those of :class:`navverse.city.geometry.scene.CityGeometry`
    (lengths in meters): the ground's heights, curb and crosswalk widths, junction crosswalks, an
    analytic ``slope`` every surface follows, seeded hills (``relief_height``, ``relief_wavelength``),
    and ``friction`` per terrain class; plus ``dem``."""

    dem: SourceFile | None = None
    """A GeoTIFF digital elevation model (heights in meters, any coordinate reference system) whose
    relief the city follows, in place of seeded hills: sampled in the map's frame, relative to the
    window's centre, and graded along the roads like the hills (:mod:`navverse.city.geometry.dem`). It
    must cover the window; it needs a map read from OSM and rasterio (``pip install 'navverse[dem]'``)."""

    @model_validator(mode="after")
    def _dem_readable(self) -> CityGeometryParams:
        if self.dem is None:
            return self
        if self.relief_height > 0.0:
            raise ValueError("give either dem or relief_height, not both: the DEM is the relief")
        from navverse.city.geometry.dem import rasterio_missing

        missing = rasterio_missing()
        if missing is not None:
            raise ValueError(missing)
        return self


@stage(
    name="city_geometry",
    inputs=["city_map"],
    outputs=["street_geometry"],
    summary={"buildings": "buildings", "dropped": "dropped", "road km": "road_km", "faces": "faces"},
)
def city_geometry(ctx: StageContext, params: CityGeometryParams) -> None:
    """A scene (roads below curbs, crosswalks, sidewalks, land, buildings), its street plan and settings.

    The relief's hills are drawn from the stage's seed (``ctx.seed``, derived from the target's); the
    manifest records the steepest grade measured along each road class (``road_grade_max``).
    """
    import navverse
    from navverse.city.city_settings import CITY_SETTINGS_FILE, CitySettings, save_city_settings
    from navverse.city.geometry.grades import road_grades
    from navverse.city.geometry.scene import city_scene, geometry_plan
    from navverse.city.geometry.street_plan import STREET_PLAN_FILE, save_street_plan
    from navverse.city.map import read_city_map
    from navverse.scene.annotations import SceneSource
    from navverse.scene.directory import write_scene_dir

    city = read_city_map(ctx.input("city_map") / CITY_MAP_FILE)
    geometry = CityGeometry.of(params)
    dem = None
    if params.dem is not None:
        from navverse.city.geometry.dem import read_dem

        dem = read_dem(params.dem, frame=city.frame, window=city.window)

    ctx.progress(0, 3, "plan")
    plan = geometry_plan(city, geometry)
    ctx.progress(1, 3, "geometry")
    scene = city_scene(
        city,
        scene_id=ctx.target,
        geometry=geometry,
        plan=plan,
        source=SceneSource(
            recipe=ctx.recipe, recipe_hash=ctx.recipe_hash, toolkit_version=navverse.__version__
        ),
        seed=ctx.seed % 2**32,
        dem=dem,
    )
    ctx.progress(2, 3, "writing")
    write_scene_dir(scene, ctx.output)
    save_street_plan(plan, ctx.output / STREET_PLAN_FILE)
    save_city_settings(CitySettings(geometry=geometry), ctx.output / CITY_SETTINGS_FILE)
    ctx.progress(3, 3, "done")
    stats = scene.annotations.statistics
    areas = {s.name: round(_top_area(s.mesh), 1) for s in scene.surfaces if s.terrain_class != "building"}
    ctx.record(
        faces=stats.faces,
        buildings=stats.buildings,
        road_km=round(stats.road_length_m / 1000.0, 3),
        surface_area_m2=areas,
        dropped=dict(city.dropped),
        road_grade_max=road_grades(scene, city, plan, road_depression=geometry.road_depression),
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
