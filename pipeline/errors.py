"""Errors of the pipeline engine. Each says what to change; the CLI prints them without a traceback."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass


class PipelineError(Exception):
    """Base class of errors caused by recipes, targets or the build directory."""


@dataclass(frozen=True)
class RecipeIssue:
    """One problem found in a recipe file.

    Parameters
    ----------
    file : str
        Path of the recipe file the problem is in.
    line : int or None
        1-based line number, when known.
    key_path : str
        Dotted path of the offending key (``stages.blockout.boxes.0.size``), or ``""`` for the file.
    message : str
        What is wrong and what to change.
    """

    file: str
    line: int | None
    key_path: str
    message: str

    def __str__(self) -> str:
        where = f"{self.file}:{self.line}" if self.line is not None else self.file
        key = f" {self.key_path}:" if self.key_path else ""
        return f"{where}:{key} {self.message}"


class RecipeError(PipelineError):
    """One or more recipes are invalid; every problem found is listed at once."""

    def __init__(self, issues: Sequence[RecipeIssue]) -> None:
        self.issues = tuple(sorted(issues, key=lambda i: (i.file, i.line or 0, i.key_path)))
        count = len(self.issues)
        lines = [f"{count} problem{'s' if count != 1 else ''} in recipes (nothing was built):"]
        lines += [f"  {issue}" for issue in self.issues]
        super().__init__("\n".join(lines))


class DagError(PipelineError):
    """The stages of the selected targets do not form a valid graph (missing producer, cycle, clash)."""


class TargetError(PipelineError):
    """A requested target or recipe does not exist."""


class StoreError(PipelineError):
    """The build directory cannot be used (e.g. an artifact is corrupt or the path is not writable)."""


class CodeVersionError(PipelineError):
    """A stage's code version cannot be computed: a project module it imports is missing or unreadable."""


class StageImportError(PipelineError):
    """A stage module, or a project module it loads, cannot be imported (missing, unreadable, broken)."""

    def __init__(self, module: str, exc: BaseException) -> None:
        super().__init__(
            f"{module} cannot be imported: {type(exc).__name__}: {exc}; restore the module it names, "
            "or reinstall the toolkit (make setup)"
        )
