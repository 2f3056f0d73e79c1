"""Every number a recipe gives a registered stage has finite physical bounds.

The registry is walked, so a new stage (or a new field) is covered without editing this file: each
float field, wherever it sits (nested models, tuples, lists, dicts, optional unions), must refuse
``inf``, ``nan`` and ``1e308``, and each integer field ``10**15``.
"""

from __future__ import annotations

import math
import types
import typing
from collections.abc import Iterator
from pathlib import Path
from typing import Annotated, Any, Literal, Union

import pytest
from pydantic import BaseModel, ValidationError

from pipeline.errors import RecipeError
from pipeline.recipes import RecipeLoader
from pipeline.stage import discover
from tests.stages.conftest import workspace_with

STAGES = {  # the project's stages (the registry may also hold the engine tests' example stages)
    name: spec for name, spec in discover("stages").items() if spec.fn.__module__.startswith("stages.")
}
BAD_FLOATS = (math.inf, -math.inf, math.nan, 1e308, -1e308)
BAD_INT = 10**15


def _args(annotation: Any) -> tuple[Any, ...]:
    return typing.get_args(annotation)


def _leaves(annotation: Any, kind: type) -> Iterator[tuple[str, Any]]:
    """``(description, builder)`` for every ``kind`` leaf of an annotation: ``builder(bad)`` is an
    input holding ``bad`` at that leaf (other places may be left invalid or missing)."""
    origin = typing.get_origin(annotation)
    if origin is Annotated:
        yield from _leaves(_args(annotation)[0], kind)
    elif origin in (Union, types.UnionType):
        seen = set()
        for member in _args(annotation):
            for where, build in _leaves(member, kind):
                if where not in seen:  # the same leaf through two members of a union: once
                    seen.add(where)
                    yield where, build
    elif origin is tuple:
        members = _args(annotation)
        for index, member in enumerate(members):
            for where, build in _leaves(member, kind):
                yield f"[{index}]{where}", _in_tuple(len(members), index, build)
    elif origin in (list, set, frozenset):
        for where, build in _leaves(_args(annotation)[0], kind):
            yield f"[0]{where}", lambda bad, build=build: [build(bad)]
    elif origin is dict:
        _, value = _args(annotation)
        for where, build in _leaves(value, kind):
            yield f"[key]{where}", lambda bad, build=build: {"floor": build(bad)}
    elif isinstance(annotation, type) and issubclass(annotation, BaseModel):
        for name, field in annotation.model_fields.items():
            annotated = Annotated[(field.annotation, *field.metadata)] if field.metadata else field.annotation
            for where, build in _leaves(annotated, kind):
                yield f".{name}{where}", lambda bad, name=name, build=build: {name: build(bad)}
    elif annotation is kind:
        yield "", lambda bad: bad


def _in_tuple(size: int, index: int, build: Any) -> Any:
    return lambda bad: [build(bad) if i == index else 0 for i in range(size)]


def _refused(model: type[BaseModel], data: Any, bad: Any) -> bool:
    """Whether validating ``data`` reports an error on the value ``bad`` itself."""
    try:
        model.model_validate(data)
    except ValidationError as exc:
        return any(_same(error.get("input"), bad) for error in exc.errors())
    return False


def _same(value: Any, bad: Any) -> bool:
    if isinstance(bad, float) and math.isnan(bad):
        return isinstance(value, float) and math.isnan(value)
    return type(value) is type(bad) and value == bad


def _cases(kind: type) -> list[Any]:
    cases = []
    for name, spec in sorted(STAGES.items()):
        for where, build in _leaves(spec.params_model, kind):
            cases.append(pytest.param(spec.params_model, build, id=f"{name}{where}"))
    return cases


FLOAT_CASES = _cases(float)
INT_CASES = _cases(int)


def test_the_walk_finds_the_fields_of_every_kind_of_container():
    ids = {case.id for case in FLOAT_CASES}
    # A tuple in a nested model in a list, a dict value, an optional union, a model from navverse.
    assert "blockout.surfaces[0].center[2]" in ids
    assert "blockout.friction[key]" in ids
    assert "import_mesh.units" in ids
    assert "navmesh.settings.cell_size" in ids
    assert "navmesh.settings.fine_region[3]" in ids
    assert {case.id for case in INT_CASES} >= {"decimate.target_faces", "navmesh.settings.tile_size"}


@pytest.mark.parametrize(("model", "build"), FLOAT_CASES)
def test_every_float_field_refuses_non_finite_and_absurd_values(model: type[BaseModel], build: Any):
    accepted = [bad for bad in BAD_FLOATS if not _refused(model, build(bad), bad)]
    assert not accepted, f"accepted {accepted}: give the field finite bounds (Field(ge=..., le=...))"


@pytest.mark.parametrize(("model", "build"), INT_CASES)
def test_every_integer_field_has_an_upper_bound(model: type[BaseModel], build: Any):
    assert _refused(model, build(BAD_INT), BAD_INT), "give the field an upper bound (Field(le=...))"


def test_the_walk_skips_literals_booleans_and_paths():
    class Example(BaseModel):
        mode: Literal["a", "b"] = "a"
        flag: bool = False
        path: Path | None = None

    assert list(_leaves(Example, float)) == [] and list(_leaves(Example, int)) == []


def test_a_huge_box_in_a_recipe_is_refused_with_its_line(tmp_path: Path):
    recipe = (
        "stages:\n"
        "  blockout:\n"
        "    surfaces:\n"
        "      - {name: floor, terrain: floor, center: [0, 0, 0], box: [1e308, 4, 0.1]}\n"
    )
    workspace = workspace_with(tmp_path, [], {"scenes/huge.yaml": recipe})
    with pytest.raises(RecipeError) as caught:
        RecipeLoader(workspace, stages=STAGES).load()
    text = str(caught.value)
    assert "scenes/huge.yaml:4: stages.blockout.surfaces.0.box.0:" in text, text
    assert "less than or equal to 2000" in text, text
