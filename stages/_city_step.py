"""What the stages that change a built city scene share: reading the map, the scene, its street
plan and the settings it was built with, and writing the changed scene with the plan, the map and
the settings (its own added) beside it."""

from __future__ import annotations

from typing import TYPE_CHECKING

from pipeline import StageContext

if TYPE_CHECKING:
    from navverse.city.city_settings import CitySettings
    from navverse.city.geometry.street_plan import StreetPlan
    from navverse.city.map import CityMap
    from navverse.scene.geometry import Scene


def read_city_step(ctx: StageContext, scene_artifact: str) -> tuple[CityMap, Scene, StreetPlan, CitySettings]:
    """The city map (artifact ``city_map``), the scene of `scene_artifact`, its street plan and the
    settings it was built with."""
    from navverse.city.city_settings import CITY_SETTINGS_FILE, load_city_settings
    from navverse.city.geometry.street_plan import STREET_PLAN_FILE, load_street_plan
    from navverse.city.map import read_city_map
    from navverse.scene.directory import read_scene
    from stages.city import CITY_MAP_FILE

    ctx.progress(0, 3, "reading")
    city = read_city_map(ctx.input("city_map") / CITY_MAP_FILE)
    scene = read_scene(ctx.input(scene_artifact))
    plan = load_street_plan(ctx.input(scene_artifact) / STREET_PLAN_FILE)
    settings = load_city_settings(ctx.input(scene_artifact) / CITY_SETTINGS_FILE)
    ctx.progress(1, 3, "placing")
    return city, scene, plan, settings


def write_city_step(
    ctx: StageContext, scene: Scene, plan: StreetPlan, settings: CitySettings, counts: dict
) -> None:
    """Write the changed scene, its street plan, the settings it was built with and a copy of its
    city map (so that a stage linking the scene, such as ``assemble_i2o``, has the map it was made
    from and follows its settings) and record `counts`."""
    import shutil

    from navverse.city.city_settings import CITY_SETTINGS_FILE, save_city_settings
    from navverse.city.geometry.street_plan import STREET_PLAN_FILE, save_street_plan
    from navverse.scene.directory import write_scene_dir
    from stages.city import CITY_MAP_FILE

    ctx.progress(2, 3, "writing")
    write_scene_dir(scene, ctx.output)
    save_street_plan(plan, ctx.output / STREET_PLAN_FILE)
    save_city_settings(settings, ctx.output / CITY_SETTINGS_FILE)
    shutil.copyfile(ctx.input("city_map") / CITY_MAP_FILE, ctx.output / CITY_MAP_FILE)
    ctx.progress(3, 3, "done")
    ctx.record(**counts)
