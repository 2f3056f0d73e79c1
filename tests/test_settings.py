"""One declaration per setting: a setting's type, bounds, default and docstring live on one library
settings model (:class:`navverse.settings.Settings`), which the stage's parameter model derives
from. The stage registry and the library are walked, so a new stage, model or function is covered
without editing this file. A setting declared twice (a stage re-declaring a library field, two
library models declaring one name, a library function repeating a stage's default as a keyword
default) fails, naming both places.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import pkgutil
import sys
from collections.abc import Iterator
from typing import Any

import pytest
from pydantic import BaseModel

import navverse
from navverse.settings import Settings
from pipeline.stage import discover

STAGES = {name: spec for name, spec in discover("stages").items() if spec.fn.__module__.startswith("stages.")}


def _library_modules() -> list[Any]:
    modules = []
    for info in pkgutil.walk_packages(navverse.__path__, prefix="navverse."):
        modules.append(importlib.import_module(info.name))
    return modules


LIBRARY = _library_modules()


def _subclasses(cls: type) -> Iterator[type]:
    for sub in cls.__subclasses__():
        yield sub
        yield from _subclasses(sub)


def _own_fields(cls: type) -> set[str]:
    """The fields a class declares itself (not those it inherits)."""
    fields = getattr(cls, "__pydantic_fields__", {})
    return {name for name in vars(cls).get("__annotations__", {}) if name in fields}


def _where(cls: type) -> str:
    return f"{cls.__module__}.{cls.__qualname__}"


def library_models() -> list[type[Settings]]:
    """Every settings model of the library (defined in a ``navverse`` module)."""
    found = {
        cls
        for cls in _subclasses(Settings)
        if cls.__module__.startswith("navverse.")
        and getattr(sys.modules.get(cls.__module__), cls.__name__, None) is cls  # not a test's own
    }
    return sorted(found, key=_where)


def _valued(cls: type[BaseModel], name: str) -> Any | None:
    """The default of a field if it carries a value (not required, not None, not an empty
    collection), else None."""
    field = cls.model_fields[name]
    default = field.default
    if field.is_required() or default is None or callable(default):
        return None
    if isinstance(default, (list, tuple, dict, set, frozenset, str)) and not default:
        return None
    return default


def declared_twice(models: list[type[BaseModel]], stage_models: list[type[BaseModel]]) -> list[str]:
    """Problems: a setting (a field name with the same valued default) declared by two library
    models, or by a stage's own class and a library model (or another stage's own class)."""
    owners: list[type] = list(models)
    for params in stage_models:
        owners += [cls for cls in params.__mro__ if cls.__module__.startswith("stages.")]
    seen: dict[tuple[str, str], type] = {}
    problems = []
    for cls in dict.fromkeys(owners):
        for name in sorted(_own_fields(cls)):
            default = _valued(cls, name)
            if default is None:
                continue
            key = (name, repr(_plain(default)))
            if key in seen and seen[key] is not cls:
                problems.append(
                    f"{name!r} = {default!r} is declared by {_where(seen[key])} and by {_where(cls)}: "
                    "declare it once, on a library settings model the others derive from"
                )
            seen.setdefault(key, cls)
    return problems


def library_calls(spec: Any) -> dict[str, Any]:
    """The library functions and classes a stage's module calls: ``{dotted name: object}``, the
    names it imports from ``navverse`` (at module level or inside functions) that it calls."""
    module = sys.modules[spec.fn.__module__]
    tree = ast.parse(inspect.getsource(module))
    imported: dict[str, Any] = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("navverse"):
            source = importlib.import_module(node.module)
            for alias in node.names:
                value = getattr(source, alias.name, None)
                if value is not None and (inspect.isfunction(value) or inspect.isclass(value)):
                    imported[alias.asname or alias.name] = (f"{node.module}.{alias.name}", value)
    called = {n.func.id for n in ast.walk(tree) if isinstance(n, ast.Call) and isinstance(n.func, ast.Name)}
    return dict(imported[name] for name in sorted(called & set(imported)))


def repeated_defaults(stage_model: type[BaseModel], calls: dict[str, Any]) -> list[str]:
    """Problems: a library call whose keyword default repeats a setting of the stage's parameters
    (the same name, an equal valued default) instead of taking it from the settings model."""
    problems = []
    for where, target in calls.items():
        if inspect.isclass(target) and issubclass(target, BaseModel):
            continue  # a settings model: its fields are checked by declared_twice
        try:
            signature = inspect.signature(target)
        except (TypeError, ValueError):
            continue
        for parameter in signature.parameters.values():
            if parameter.name not in stage_model.model_fields:
                continue
            value = _valued(stage_model, parameter.name)
            default = parameter.default
            if value is None or default is inspect.Parameter.empty or default is None:
                continue
            if _plain(default) == _plain(value):
                problems.append(
                    f"{where}({parameter.name}={default!r}) repeats the default of "
                    f"{_where(stage_model)}: take it from the settings model"
                )
    return problems


def _plain(value: Any) -> Any:
    return list(value) if isinstance(value, tuple) else value


def _stage_models() -> list[type[BaseModel]]:
    return [spec.params_model for spec in STAGES.values()]


def test_library_settings_exist() -> None:
    names = {cls.__name__ for cls in library_models()}
    assert {"CityGeometry", "PopulateSettings", "StorefrontSettings", "DensifySettings"} <= names


def test_no_setting_is_declared_twice() -> None:
    problems = declared_twice(library_models(), _stage_models())
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("name", sorted(STAGES))
def test_the_library_calls_of_a_stage_repeat_none_of_its_defaults(name: str) -> None:
    spec = STAGES[name]
    problems = repeated_defaults(spec.params_model, library_calls(spec))
    assert not problems, "\n".join(problems)


def test_the_checks_catch_a_default_declared_twice() -> None:
    """The checks fail on purpose-made duplicates: a stage re-declaring a library field, a second
    library model declaring it, and a function repeating a stage default."""
    from navverse.city.geometry.scene import CityGeometry
    from pipeline import Params

    class Stage(Params, CityGeometry):
        road_depression: float = 0.2

    Stage.__module__ = "stages.duplicated"

    class Other(Settings):
        road_depression: float = 0.2

    Other.__module__ = "navverse.duplicated"

    def depress(*, road_depression: float = 0.2) -> None:
        """A library call with a repeated default."""

    assert any("Stage" in p for p in declared_twice(library_models(), [Stage]))
    assert any("Other" in p for p in declared_twice([*library_models(), Other], []))
    assert repeated_defaults(Stage, {"navverse.duplicated.depress": depress})
    assert not declared_twice(
        [CityGeometry], [type("Fine", (Params, CityGeometry), {"__module__": "stages.x"})]
    )
