"""What a stage function receives besides its params."""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

ProgressSink = Callable[[int, int, str], None]


@dataclass
class StageContext:
    """The run of one stage for one target.

    A stage reads only :attr:`inputs`, writes only into :attr:`outputs`, and draws randomness only
    from :attr:`rng`.

    Attributes
    ----------
    target : str
        Target id.
    stage : str
        Stage name.
    recipe : str
        Recipe path (relative to the recipes folder).
    recipe_hash : str
        Hash of the target's recipe.
    seed : int
        The derived seed of this stage run.
    rng : numpy.random.Generator
        Seeded from :attr:`seed`.
    inputs : dict
        ``{name: Path}`` (or ``list[Path]`` for many-inputs) of committed input artifacts.
    outputs : dict
        ``{name: Path}`` empty directories to write into.
    log : logging.Logger
        Writes to the stage's log file.
    """

    target: str
    stage: str
    recipe: str
    recipe_hash: str
    seed: int
    rng: np.random.Generator
    inputs: dict[str, Path | list[Path]]
    outputs: dict[str, Path]
    log: logging.Logger
    stats: dict[str, Any] = field(default_factory=dict)
    progress_sink: ProgressSink | None = None

    @property
    def output(self) -> Path:
        """The output directory of a stage with exactly one output."""
        if len(self.outputs) != 1:
            raise RuntimeError(f"stage {self.stage} has {len(self.outputs)} outputs; use ctx.outputs[name]")
        return next(iter(self.outputs.values()))

    def input(self, name: str) -> Path:
        """The directory of the single input artifact ``name``."""
        value = self.inputs[name]
        if isinstance(value, list):
            raise RuntimeError(f"input {name!r} of stage {self.stage} is a list; use ctx.inputs[name]")
        return value

    def record(self, **stats: Any) -> None:
        """Record counts or figures (JSON-able) in the artifact manifests under ``stats``."""
        self.stats.update(stats)

    def progress(self, done: int, total: int, description: str = "") -> None:
        """Report inner progress (shown as a bar while the stage runs)."""
        if self.progress_sink is not None:
            self.progress_sink(done, total, description)
