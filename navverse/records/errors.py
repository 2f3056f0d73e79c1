"""What goes wrong with a dataset: :class:`DatasetError`, the remedy its messages name, and how a
validation error is told in one line."""

from __future__ import annotations

from pydantic import ValidationError

from navverse.errors import NavverseError

__all__ = ["REMEDY", "DatasetError", "first_error"]

REMEDY = (
    "This dataset version is not as it was packaged: re-download it, or rebuild it with "
    "`navverse build <dataset>` in its workspace; never edit a published version"
)
"""What to do about a version that does not match its manifest (ends the messages that say so)."""


class DatasetError(NavverseError):
    """A dataset is missing, malformed, of another format version, or would overwrite a published one."""


def first_error(exc: ValidationError) -> str:
    """The first problem of a validation error, as ``where: what``."""
    error = exc.errors()[0]
    where = ".".join(str(p) for p in error["loc"]) or "top level"
    return f"{where}: {error['msg'].removeprefix('Value error, ')}"
