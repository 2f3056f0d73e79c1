"""The index_scenes stage: the linked scenes built, listed with their hashes and checked against a
published dataset's manifest (a dataset's scenes as one target: ``navverse build navverse-full-scenes``)."""

from __future__ import annotations

import json

from pipeline import Input, Params, SourceFile, StageContext, stage

SCENES_JSON = "scenes.json"
"""The index an ``index_scenes`` artifact holds: ``{"scenes": {scene_id: {"scene_type", "scene_hash",
"map"}}, "counts": {scene_type: n, "outdoor from maps": n}, "dataset": the manifest checked against or
null}``; ``map`` is the map file a city was made from (null for generated scenes)."""


class IndexScenesParams(Params):
    """Parameters of :func:`index_scenes`.

    The recipe links the scenes (``links: {scene: [...]}``, globs allowed); building the target builds
    every one of them. With ``dataset`` (a published version's ``manifest.json``), the linked scenes
    must be exactly the scenes the dataset names, each with the scene hash it gives; otherwise the
    stage fails naming every scene that differs, missing or is not the dataset's.
    """

    dataset: SourceFile | None = None
    """``manifest.json`` of the published dataset version these scenes must reproduce (path relative
    to the recipe's folder); none: the scenes are only listed."""


@stage(
    name="index_scenes",
    inputs=[Input("scene", artifact="scene", many=True)],
    outputs=["scenes"],
    summary={
        "scenes": "scenes",
        "indoor": "counts.indoor",
        "outdoor": "counts.outdoor",
        "from maps": "counts.outdoor from maps",
        "i2o": "counts.i2o",
    },
)
def index_scenes(ctx: StageContext, params: IndexScenesParams) -> None:
    """scenes.json: every linked scene's type and hash, checked against the dataset's manifest if given."""
    from collections import Counter

    from navverse.dataset.manifest import read_manifest
    from navverse.records.errors import DatasetError
    from navverse.scene.directory import read_annotations, scene_hash

    index: dict[str, dict[str, str | None]] = {}
    scene_dirs = ctx.inputs["scene"]
    for done, path in enumerate(scene_dirs):
        ctx.progress(done, len(scene_dirs), "hashing")
        annotations = read_annotations(path)
        geo = annotations.geo
        index[annotations.scene_id] = {
            "scene_type": annotations.scene_type,
            "scene_hash": scene_hash(path),
            "map": geo.map if geo is not None and geo.sha256 is not None else None,
        }
    ctx.progress(len(scene_dirs), len(scene_dirs), "checking")
    dataset = None
    if params.dataset is not None:
        manifest, _ = read_manifest(params.dataset)
        dataset = f"{manifest.name} v{manifest.version}"
        problems = _differences(index, manifest.scene_hashes)
        if problems:
            raise DatasetError(
                f"the scenes built here are not those of {dataset} ({params.dataset}):\n  "
                + "\n  ".join(problems)
                + "\na scene differs when its recipe or the code that builds it changed since the dataset "
                "was built: build at the commit the dataset was published from, or link exactly the "
                "dataset's scenes"
            )
    counts = dict(sorted(Counter(str(entry["scene_type"]) for entry in index.values()).items()))
    counts["outdoor from maps"] = sum(
        e["scene_type"] == "outdoor" and e["map"] is not None for e in index.values()
    )
    document = {"scenes": dict(sorted(index.items())), "counts": counts, "dataset": dataset}
    (ctx.output / SCENES_JSON).write_text(json.dumps(document, indent=1) + "\n")
    ctx.record(scenes=len(index), counts=counts, dataset=dataset)
    ctx.log.info("%d scenes %s%s", len(index), counts, f", as in {dataset}" if dataset else "")


def _differences(index: dict[str, dict[str, str | None]], expected: dict[str, str]) -> list[str]:
    """Each way the indexed scenes differ from a dataset's ``{scene_id: scene_hash}``."""
    problems = [
        f"{scene}: not built (the dataset names it; link it)" for scene in sorted(set(expected) - set(index))
    ]
    problems += [
        f"{scene}: not a scene of the dataset (unlink it)" for scene in sorted(set(index) - set(expected))
    ]
    problems += [
        f"{scene}: scene hash {str(index[scene]['scene_hash'])[:12]}… differs from the dataset's "
        f"{expected[scene][:12]}…"
        for scene in sorted(set(index) & set(expected))
        if index[scene]["scene_hash"] != expected[scene]
    ]
    return problems
