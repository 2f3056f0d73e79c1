"""Where recipes and build outputs live."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from pipeline.errors import PipelineError

PRESETS_DIRNAME = "presets"


@dataclass(frozen=True)
class Workspace:
    """A project directory: ``recipes/`` in, ``data/built/`` out.

    Attributes
    ----------
    root : Path
        Project root.
    """

    root: Path

    @property
    def recipes_dir(self) -> Path:
        """Recipe files (``*.yaml``)."""
        return self.root / "recipes"

    @property
    def presets_dir(self) -> Path:
        """Presets that recipes extend by name; never targets themselves."""
        return self.recipes_dir / PRESETS_DIRNAME

    @property
    def built_dir(self) -> Path:
        """Content-addressed build outputs."""
        return self.root / "data" / "built"

    @classmethod
    def find(cls, start: Path | None = None) -> Workspace:
        """The workspace holding ``start`` (default: ``$NAVVERSE_ROOT`` or the current directory).

        Raises
        ------
        PipelineError
            If no parent directory has a ``recipes/`` folder.
        """
        env = os.environ.get("NAVVERSE_ROOT")
        here = Path(start or env or Path.cwd()).resolve()
        for candidate in (here, *here.parents):
            if (candidate / "recipes").is_dir():
                return cls(candidate)
        raise PipelineError(
            f"no recipes/ folder in {here} or its parents: run from the project directory "
            "or set NAVVERSE_ROOT to it"
        )
