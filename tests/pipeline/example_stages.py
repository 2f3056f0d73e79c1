"""Tiny stages for engine tests: random numbers, sums, a fan-in, a failure and a slow writer."""

from __future__ import annotations

import json
import time
from typing import Annotated

import numpy as np
from pydantic import Field

from pipeline import Input, Params, SourceFile, StageContext, stage


class NumbersParams(Params):
    count: Annotated[int, Field(ge=1)] = 5
    scale: float = 1.0


@stage(name="ex_numbers", outputs=["numbers"], summary={"numbers": "count"})
def ex_numbers(ctx: StageContext, params: NumbersParams) -> None:
    """Random numbers drawn from the stage's generator (``numbers.npy``)."""
    values = ctx.rng.random(params.count) * params.scale
    np.save(ctx.output / "numbers.npy", values)
    ctx.record(count=params.count)


class SumParams(Params):
    offset: float = 0.0
    fail: bool = False


@stage(name="ex_sum", inputs=["numbers"], outputs=["total"])
def ex_sum(ctx: StageContext, params: SumParams) -> None:
    """The sum of the input numbers plus an offset (``total.json``)."""
    if params.fail:
        raise ValueError("asked to fail")
    values = np.load(ctx.input("numbers") / "numbers.npy")
    (ctx.output / "total.json").write_text(json.dumps({"total": float(values.sum()) + params.offset}))


class GatherParams(Params):
    pass


@stage(name="ex_gather", inputs=[Input("total", many=True)], outputs=["summary"])
def ex_gather(ctx: StageContext, params: GatherParams) -> None:
    """The totals of several targets, in target order (``summary.json``)."""
    totals = [json.loads((p / "total.json").read_text())["total"] for p in ctx.inputs["total"]]
    (ctx.output / "summary.json").write_text(json.dumps({"totals": totals}))


class SlowParams(Params):
    files: Annotated[int, Field(ge=1)] = 10
    delay_s: Annotated[float, Field(ge=0)] = 0.05


@stage(name="ex_slow", outputs=["numbers"])
def ex_slow(ctx: StageContext, params: SlowParams) -> None:
    """Numbers written slowly, one file at a time (``part_*.npy`` and ``numbers.npy``)."""
    values = ctx.rng.random(params.files)
    for index, value in enumerate(values):
        np.save(ctx.output / f"part_{index:03d}.npy", np.array([value]))
        ctx.progress(index + 1, params.files, "parts")
        time.sleep(params.delay_s)
    np.save(ctx.output / "numbers.npy", values)


class FileParams(Params):
    source: SourceFile


@stage(name="ex_read_file", outputs=["numbers"])
def ex_read_file(ctx: StageContext, params: FileParams) -> None:
    """Numbers parsed from a text file named by the recipe (``numbers.npy``)."""
    values = np.array([float(x) for x in params.source.read_text().split()])
    np.save(ctx.output / "numbers.npy", values)


class BlockParams(Params):
    size: Annotated[float, Field(gt=0)] = 1.0


@stage(name="ex_block", outputs=["geometry"])
def ex_block(ctx: StageContext, params: BlockParams) -> None:
    """A target's own 'geometry': one size (``geometry.json``)."""
    (ctx.output / "geometry.json").write_text(json.dumps({"size": params.size, "target": ctx.target}))


class AnnexParams(Params):
    pass


@stage(name="ex_annex", inputs=["geometry", Input("building", artifact="geometry")], outputs=["annex"])
def ex_annex(ctx: StageContext, params: AnnexParams) -> None:
    """The target's geometry beside a building's geometry, read under another name (``annex.json``)."""
    own = json.loads((ctx.input("geometry") / "geometry.json").read_text())
    building = json.loads((ctx.input("building") / "geometry.json").read_text())
    (ctx.output / "annex.json").write_text(json.dumps({"own": own, "building": building}))


class DecorateParams(Params):
    factor: float = 2.0


@stage(name="ex_decorate", inputs=["total"], outputs=["decorated"], passthrough={"decorated": "total"})
def ex_decorate(ctx: StageContext, params: DecorateParams) -> None:
    """The total scaled by a factor (``total.json``); optional in a chain: skipped, it is the total."""
    total = json.loads((ctx.input("total") / "total.json").read_text())["total"]
    (ctx.output / "total.json").write_text(json.dumps({"total": total * params.factor}))


class PublishParams(Params):
    pass


@stage(name="ex_publish", inputs=["decorated"], outputs=["published"])
def ex_publish(ctx: StageContext, params: PublishParams) -> None:
    """The decorated total as published (``total.json``)."""
    (ctx.output / "total.json").write_bytes((ctx.input("decorated") / "total.json").read_bytes())
