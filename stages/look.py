"""The look stage: a scene's appearance, kept apart from its geometry, navmesh and episodes."""

from __future__ import annotations

from navverse.files import link_or_copy
from navverse.look.settings import LookSettings
from pipeline import Params, StageContext, stage


class LookParams(Params, LookSettings):
    """Parameters of :func:`look`: the scene's look (by default the evaluation look), which the
    renderer uses unless told otherwise. Nothing else reads it: datasets link a scene's ``scene``
    output, never its ``look``, so changing a look rebuilds only the look."""


@stage(
    name="look",
    inputs=["geometry"],
    outputs=["look"],
    summary={"materials": "materials", "facades": "facades", "marked roads": "marked_roads"},
    appearance=True,
)
def look(ctx: StageContext, params: LookParams) -> None:
    """look/: look.json (settings, map details), look.usdc over a link of scene.usdc, textures/look/*.png."""
    from navverse.city.map import read_city_map
    from navverse.files import file_sha256
    from navverse.look.files import LOOK_JSON, write_look
    from navverse.look.scene_look import map_details, scene_look
    from navverse.look.usd_look import LOOK_TEXTURES, LOOK_USD, write_look_usd
    from navverse.scene.directory import SceneFiles, read_scene
    from stages.city import CITY_MAP_FILE

    source = SceneFiles(ctx.inputs["geometry"])  # the scene before its navmesh: a look needs no navmesh
    out = ctx.outputs["look"]
    ctx.progress(0, 3, "reading")
    scene = read_scene(source.root)
    city_map = source.root / CITY_MAP_FILE
    details = map_details(scene, read_city_map(city_map)) if city_map.is_file() else None
    settings = LookSettings.of(params)
    ctx.progress(1, 3, "compiling")
    compiled = scene_look(scene, settings, details=details)
    link_or_copy(source.usd, out / source.usd.name)
    if source.textures.is_dir():  # the images scene.usdc names (signs): the layer reads it from here
        (out / source.textures.name).mkdir(exist_ok=True)
        for image in sorted(source.textures.glob("*.png")):
            link_or_copy(image, out / source.textures.name / image.name)
    ctx.progress(2, 3, "writing")
    write_look_usd(scene, compiled, out, scene_file=source.usd.name)
    write_look(out / LOOK_JSON, settings, details, geometry_sha256=file_sha256(source.usd))
    ctx.progress(3, 3, "done")
    ctx.record(
        materials=len(list((out / LOOK_TEXTURES).glob("*.png"))),
        facades=len(compiled.facades.rows),
        marked_roads=0 if details is None else len(details.roads),
        crossings=len(compiled.crossings),
        rooms=len(compiled.rooms.lamps),
        layer=LOOK_USD,
    )
