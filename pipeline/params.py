"""Base model of stage parameters, and source-file fields whose content is part of the cache key."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

from pydantic import AfterValidator, BaseModel, ConfigDict, ValidationInfo


class Params(BaseModel):
    """Frozen, strict-keyed base class of every stage's parameter model.

    Unknown keys are errors, instances are immutable, and defaults are validated, so a params
    object is a complete, hashable description of what a stage will do.
    """

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)


def _resolve_source_file(value: Path, info: ValidationInfo) -> Path:
    context = info.context or {}
    base = context.get("recipe_dir")
    path = Path(value).expanduser()
    if not path.is_absolute() and base is not None:
        path = Path(base) / path
    path = path.resolve()
    if not path.is_file():
        raise ValueError(f"file not found: {path} (paths are relative to the recipe's folder)")
    return path


SourceFile = Annotated[Path, AfterValidator(_resolve_source_file)]
"""A path to an input file of a stage; resolved against the recipe's folder, must exist, and its
content hash is part of the stage's cache key (editing the file rebuilds what depends on it)."""


def source_files(params: BaseModel) -> dict[str, Path]:
    """Every existing file named by a ``Path`` value in ``params`` (nested models and sequences included).

    Returns
    -------
    dict
        ``{dotted_field_path: path}``; the cache key holds each file's content hash.
    """
    found: dict[str, Path] = {}
    _collect(params, "", found)
    return found


def _collect(value: Any, prefix: str, found: dict[str, Path]) -> None:
    if isinstance(value, Path):
        if value.is_file():
            found[prefix.rstrip(".")] = value
    elif isinstance(value, BaseModel):
        for name in type(value).model_fields:
            _collect(getattr(value, name), f"{prefix}{name}.", found)
    elif isinstance(value, list | tuple):
        for index, item in enumerate(value):
            _collect(item, f"{prefix}{index}.", found)
    elif isinstance(value, dict):
        for key, item in value.items():
            _collect(item, f"{prefix}{key}.", found)
