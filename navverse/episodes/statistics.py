"""The statistics of an episode dataset the paper shows: per task and scene type, how many episodes,
how long their geodesic paths and their verified rollouts are, and how they split into difficulty
tertiles; as a table and as a figure (``navverse show dataset --stats``)."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from rich.table import Table

from navverse.dataset import Dataset
from navverse.files import atomic_path
from navverse.scene_types import SCENE_TYPES

__all__ = ["Cell", "DatasetStatistics", "dataset_statistics", "statistics_figure", "statistics_table"]

DIFFICULTIES = ("easy", "medium", "hard")
_QUANTILES = (0.1, 0.5, 0.9)
_DISTRIBUTIONS = (("lengths", "geodesic length (m)"), ("durations", "duration (s)"))


@dataclass
class Cell:
    """The episodes of one task and scene type: geodesic lengths (m), verified durations (s; the
    rollouts' of the dataset's robot) and episodes per difficulty."""

    lengths: list[float] = field(default_factory=list)
    durations: list[float] = field(default_factory=list)
    difficulty: Counter[str] = field(default_factory=Counter)


@dataclass
class DatasetStatistics:
    """Statistics of a dataset (of one split, or of all): its cells by (task, scene type)."""

    name: str
    split: str | None
    cells: dict[tuple[str, str], Cell]


def dataset_statistics(dataset: Dataset, *, split: str | None = None) -> DatasetStatistics:
    """Collect the statistics of ``dataset`` (of ``split``, or of every split; a private split's
    episodes only when its private files were given)."""
    cells: dict[tuple[str, str], Cell] = {}
    for episode in dataset.episodes(split=split):
        if episode.info is None:
            continue  # a private split's public record: its lengths are not known here
        cell = cells.setdefault((episode.task, episode.scene_type), Cell())
        cell.lengths.append(float(episode.info.geodesic_distance))
        if episode.info.verification is not None:
            cell.durations.append(float(episode.info.verification.duration_s))
        cell.difficulty[episode.info.difficulty or "none"] += 1
    order = sorted(cells, key=lambda key: (key[0], SCENE_TYPES.index(key[1])))
    name = f"{dataset.manifest.name} v{dataset.manifest.version}"
    return DatasetStatistics(name=name, split=split, cells={key: cells[key] for key in order})


def _spread(values: list[float]) -> str:
    """``p10 / median / p90`` of ``values`` ("-" when there are none)."""
    if not values:
        return "-"
    return " / ".join(f"{q:.1f}" for q in np.quantile(np.asarray(values), _QUANTILES))


def statistics_table(stats: DatasetStatistics) -> Table:
    """Per task and scene type: episodes, geodesic length and verified duration (10th percentile,
    median, 90th percentile) and episodes per difficulty tertile."""
    scope = f"{stats.split} split" if stats.split else "all splits"
    table = Table(title=f"{stats.name}: episode statistics ({scope})")
    for column in ("task", "scene type", "episodes", "geodesic m (p10 / med / p90)",
                   "duration s (p10 / med / p90)", *DIFFICULTIES):  # fmt: skip
        table.add_column(column, justify="left" if column in ("task", "scene type") else "right")
    for (task, scene_type), cell in stats.cells.items():
        table.add_row(
            task,
            scene_type,
            str(len(cell.lengths)),
            _spread(cell.lengths),
            _spread(cell.durations),
            *(str(cell.difficulty.get(d, 0)) for d in DIFFICULTIES),
        )
    return table


def statistics_figure(stats: DatasetStatistics, path: str | Path) -> Path:
    """Draw the geodesic length and verified duration distributions per task (one curve per scene
    type) and the difficulty tertiles per cell into a PNG at ``path``."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    tasks = sorted({task for task, _ in stats.cells})
    if not tasks:
        raise ValueError(f"{stats.name} has no episodes to draw")
    figure = Figure(figsize=(4.2 * len(tasks), 9.5))
    FigureCanvasAgg(figure)
    axes = figure.subplots(3, len(tasks), squeeze=False)
    colours = {"indoor": "#4c72b0", "outdoor": "#55a868", "i2o": "#c44e52"}
    for column, task in enumerate(tasks):
        cells = {scene_type: cell for (t, scene_type), cell in stats.cells.items() if t == task}
        for row, (what, unit) in enumerate(
            (("lengths", "geodesic length (m)"), ("durations", "duration (s)"))
        ):
            axis = axes[row][column]
            every = [v for cell in cells.values() for v in getattr(cell, what)]
            bins = np.linspace(0.0, max(every, default=1.0), 21)
            for scene_type, cell in cells.items():
                values = getattr(cell, what)
                if values:
                    axis.hist(values, bins=bins, histtype="step", linewidth=1.8, color=colours[scene_type],
                              label=f"{scene_type} (n={len(values)})")  # fmt: skip
            axis.set_xlabel(unit)
            axis.set_ylabel("episodes")
            axis.set_title(f"{task}: {unit.split(' (')[0]}")
            axis.legend(fontsize=8)
        axis = axes[2][column]
        bottom = np.zeros(len(cells))
        for difficulty, shade in zip(DIFFICULTIES, ("#a1d99b", "#fdae6b", "#e6550d"), strict=True):
            counts = np.asarray([cell.difficulty.get(difficulty, 0) for cell in cells.values()], dtype=float)
            axis.bar(list(cells), counts, bottom=bottom, color=shade, label=difficulty)
            bottom += counts
        axis.set_title(f"{task}: difficulty tertiles")
        axis.set_ylabel("episodes")
        axis.legend(fontsize=8)
    scope = f"{stats.split} split" if stats.split else "all splits"
    figure.suptitle(f"{stats.name} ({scope})")
    figure.tight_layout()
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(out) as tmp:
        figure.savefig(tmp, dpi=90, format="png", metadata={"Software": None})
    return out
