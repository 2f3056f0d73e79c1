"""The pictures of the evaluation report (matplotlib, Agg): the summary figure and the episode cards'
bird's-eye views, and the colours of the termination labels.

:func:`summary_figure` draws the termination label shares per task and SR per task × scene type;
:func:`episode_figure` one episode's trajectory against its reference path, start and goals, over the
scene's top-down fields (:class:`Backdrop`, or the :class:`BackdropCrop` of the picture's
:func:`picture_limits` cut while the fields were in memory); :func:`png_data_uri` turns a figure into
the ``data:image/png`` URI the page embeds.
"""

from __future__ import annotations

import base64
import io
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.patches import Circle
from matplotlib.transforms import Bbox
from PIL import Image

from navverse.dataset import Episode
from navverse.eval.metrics import LABELS
from navverse.eval.scoring import EvalResult
from navverse.scene.colors import default_color, lighten
from navverse.scene.fields import SceneFields, load_scene_fields

__all__ = [
    "LABEL_COLORS",
    "THUMB_COLORS",
    "THUMB_SIZE_PX",
    "Backdrop",
    "BackdropCrop",
    "episode_figure",
    "label_color",
    "label_name",
    "picture_limits",
    "png_data_uri",
    "summary_figure",
]

LABEL_COLORS = {
    "success": "#2ca02c",
    "wrong_goal": "#ff7f0e",
    "fall": "#d62728",
    "timeout": "#9467bd",
    "invalid": "#7f7f7f",
}
"""Colour of each termination label (:data:`navverse.eval.metrics.LABELS`) in the report."""
SCENE_TYPE_COLORS = {"indoor": "#4c72b0", "outdoor": "#55a868", "i2o": "#c44e52"}


THUMB_SIZE_PX = (300, 250)
"""Width and height of an episode picture (pixels)."""
THUMB_DPI = 100
_THUMB_AXES = (0.01, 0.01, 0.98, 0.84)
"""Left, bottom, width and height of an episode picture's axes (fractions of the figure)."""
THUMB_COLORS = 96
"""Palette size the episode pictures are reduced to (keeps 300 cards to a few MB)."""
MARGIN_M = 1.5
"""Room around an episode's trajectory, path, start and goals in its picture (m)."""
_OBSTACLE_RGB = (150, 150, 150)
_NO_SURFACE_RGB = (255, 255, 255)
_TERRAIN_LIGHTEN = 0.55


def png_data_uri(fig: Figure, *, colors: int | None = None) -> str:
    """A figure as a ``data:image/png;base64,...`` URI, optionally reduced to a palette of `colors` (from
    the canvas's pixels, which are those a saved PNG holds: no PNG is written and read back)."""
    buffer = io.BytesIO()
    if colors is None:
        fig.savefig(buffer, format="png", dpi=fig.dpi, metadata={"Software": None})
    else:
        fig.canvas.draw()
        image = Image.fromarray(np.ascontiguousarray(np.asarray(fig.canvas.buffer_rgba())[..., :3]))
        image.quantize(colors=colors, method=Image.Quantize.MEDIANCUT).save(
            buffer, format="PNG", optimize=True
        )
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


def _new_figure(width_px: int, height_px: int, dpi: int) -> Figure:
    fig = Figure(figsize=(width_px / dpi, height_px / dpi), dpi=dpi)
    FigureCanvasAgg(fig)
    return fig


def label_name(label: str) -> str:
    """A termination label as shown: underscores as spaces."""
    return label.replace("_", " ")


def label_color(label: str) -> str:
    """The label's colour in :data:`LABEL_COLORS`; a stable one for a label added to ``LABELS`` later."""
    return LABEL_COLORS.get(label) or "#{:02x}{:02x}{:02x}".format(*default_color(label))


def summary_figure(result: EvalResult) -> Figure:
    """Termination label shares per task (stacked bars) and SR per task × scene type (grouped bars).

    Parameters
    ----------
    result : EvalResult
        A scored submission.

    Returns
    -------
    Figure
        A matplotlib figure (Agg canvas), about 960 × 330 pixels.
    """
    fig = _new_figure(960, 330, 100)
    shares, rates = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1, 1.2], "wspace": 0.35})
    by_task = {**result.groups.get("task", {}), "all": result.groups.get("overall", {}).get("all", {})}
    by_task = {k: v for k, v in by_task.items() if v}
    names = list(by_task)
    left = np.zeros(len(names))
    for label in LABELS:
        values = np.array([100.0 * (by_task[n].get(f"{label}_share") or 0.0) for n in names])
        shares.barh(names, values, left=left, color=label_color(label), label=label_name(label), height=0.6)
        left += values
    shares.set_xlim(0, 100)
    shares.invert_yaxis()
    shares.set_xlabel("episodes (%)")
    shares.set_title("termination per task", fontsize=10)
    shares.legend(
        fontsize=7, ncols=len(LABELS), loc="upper center", bbox_to_anchor=(0.5, -0.2), frameon=False
    )

    cells = result.groups.get("task_scene_type", {})
    tasks = sorted({key.split("/")[0] for key in cells})
    types = sorted({key.split("/")[1] for key in cells})
    width = 0.8 / max(len(types), 1)
    for j, scene_type in enumerate(types):
        values = [100.0 * (cells.get(f"{t}/{scene_type}", {}).get("success") or 0.0) for t in tasks]
        present = [f"{t}/{scene_type}" in cells for t in tasks]
        x = np.arange(len(tasks)) + (j - (len(types) - 1) / 2) * width
        color = SCENE_TYPE_COLORS.get(scene_type) or tuple(c / 255.0 for c in default_color(scene_type))
        bars = rates.bar(x[present], np.array(values)[present], width=width * 0.95, color=color,
                         label=scene_type)  # fmt: skip
        rates.bar_label(bars, fmt="%.0f", fontsize=7, padding=1)
    rates.set_xticks(np.arange(len(tasks)), tasks)
    rates.set_ylim(0, 110)
    rates.set_ylabel("SR (%)")
    rates.set_title("success rate per task × scene type", fontsize=10)
    if types:
        rates.legend(fontsize=7, loc="upper right", title="scene type", title_fontsize=7)
    for ax in (shares, rates):
        ax.tick_params(labelsize=8)
        ax.spines[["top", "right"]].set_visible(False)
    fig.subplots_adjust(left=0.09, right=0.98, top=0.9, bottom=0.25)
    return fig


Limits = tuple[tuple[float, float], tuple[float, float]]
"""``((x min, x max), (y min, y max))`` of a picture (m)."""


@dataclass(frozen=True, eq=False)
class BackdropCrop:
    """The part of a scene's backdrop one picture shows, cut from its fields (:meth:`Backdrop.crop`), so
    that the picture can be drawn once the fields are no longer in memory.

    Parameters
    ----------
    codes : ndarray of uint8 or uint16, shape (H, W)
        The cells within the limits, row 0 the lowest y, as indices into `palette` (a byte a cell when
        the palette allows: a third of the image's size).
    palette : ndarray of uint8, shape (C, 3)
        The colour of each code.
    extent : tuple of float
        ``(x min, x max, y min, y max)`` the image covers (m).
    limits : tuple
        The picture's limits it was cut for.
    pixels : int
        The picture's width (pixels) it was cut for.
    """

    codes: np.ndarray
    palette: np.ndarray
    extent: tuple[float, float, float, float]
    limits: Limits
    pixels: int

    @property
    def image(self) -> np.ndarray:
        """The crop's colours, shape (H, W, 3), uint8."""
        return self.palette[self.codes]

    def draw(self, ax: Axes, xlim: tuple[float, float], ylim: tuple[float, float], pixels: int) -> None:
        """Show the crop, as :meth:`Backdrop.draw` shows the picture within the same limits.

        Raises
        ------
        ValueError
            If the limits or the width are not those the crop was cut for.
        """
        if ((tuple(xlim), tuple(ylim)), pixels) != (self.limits, self.pixels):
            raise ValueError(
                f"a backdrop crop cut for {self.limits} at {self.pixels} px is drawn for {(xlim, ylim)} at "
                f"{pixels} px"
            )
        ax.imshow(self.image, origin="lower", extent=self.extent, interpolation="nearest", zorder=0)


class Backdrop:
    """A scene's top-down fields drawn as a light picture: terrain classes lightened, obstacles grey.

    Only the part an episode's picture shows is coloured, so large outdoor scenes cost no more memory
    than their (cached) fields.

    Parameters
    ----------
    scene_dir : Path
        A built scene directory (its terrain classes' colours; its fields unless given).
    fields : SceneFields, optional
        The scene's fields, when already in memory (:func:`navverse.scene.fields.load_scene_fields` by
        default).
    """

    def __init__(self, scene_dir: Path, *, fields: SceneFields | None = None) -> None:
        from navverse.scene.directory import read_annotations

        self.fields: SceneFields = fields if fields is not None else load_scene_fields(scene_dir)
        classes = read_annotations(scene_dir).terrain_classes
        palette = [
            lighten(tuple(classes[n].color), _TERRAIN_LIGHTEN) if n in classes else _NO_SURFACE_RGB
            for n in self.fields.class_names
        ]
        self.palette = np.array([*palette, _NO_SURFACE_RGB], dtype=np.uint8)

    def crop(self, xlim: tuple[float, float], ylim: tuple[float, float], pixels: int) -> BackdropCrop | None:
        """The part of the picture within the limits, at most about 2 cells per output pixel (None when
        the limits miss the scene's grid)."""
        f = self.fields
        h, w = f.terrain.shape
        c0 = max(0, math.floor((xlim[0] - f.origin[0]) / f.cell))
        c1 = min(w, math.ceil((xlim[1] - f.origin[0]) / f.cell))
        r0 = max(0, math.floor((ylim[0] - f.origin[1]) / f.cell))
        r1 = min(h, math.ceil((ylim[1] - f.origin[1]) / f.cell))
        if c1 <= c0 or r1 <= r0:
            return None
        step = max(1, (c1 - c0) // (2 * pixels))
        terrain = f.terrain[r0:r1:step, c0:c1:step]
        palette = np.vstack([self.palette, np.array(_OBSTACLE_RGB, dtype=np.uint8)])  # obstacles: the last
        codes = np.where(terrain >= 0, terrain, len(self.palette) - 1)
        codes[f.obstacle[r0:r1:step, c0:c1:step]] = len(palette) - 1
        codes = codes.astype(np.uint8 if len(palette) <= 256 else np.uint16)
        extent = (
            f.origin[0] + c0 * f.cell,
            f.origin[0] + (c0 + codes.shape[1] * step) * f.cell,
            f.origin[1] + r0 * f.cell,
            f.origin[1] + (r0 + codes.shape[0] * step) * f.cell,
        )
        return BackdropCrop(codes, palette, extent, (tuple(xlim), tuple(ylim)), pixels)

    def draw(self, ax: Axes, xlim: tuple[float, float], ylim: tuple[float, float], pixels: int) -> None:
        """Show the part of the picture within the limits, at most about 2 cells per output pixel."""
        crop = self.crop(xlim, ylim, pixels)
        if crop is not None:
            crop.draw(ax, xlim, ylim, pixels)


def _limits(points: np.ndarray, aspect: float) -> tuple[tuple[float, float], tuple[float, float]]:
    """Axis limits around points (N, 2) with a margin, widened to the width/height ratio `aspect`."""
    lo = points.min(axis=0) - MARGIN_M
    hi = points.max(axis=0) + MARGIN_M
    center = (lo + hi) / 2.0
    width, height = hi - lo
    width, height = max(width, height * aspect), max(height, width / aspect)
    return (center[0] - width / 2, center[0] + width / 2), (center[1] - height / 2, center[1] + height / 2)


def _scale_bar(ax: Axes, xlim: tuple[float, float], ylim: tuple[float, float]) -> None:
    span = (xlim[1] - xlim[0]) / 4.0
    length = max(n for n in (0.5, 1, 2, 5, 10, 20, 50, 100, 200, 500) if n <= max(span, 0.5))
    x0 = xlim[0] + 0.04 * (xlim[1] - xlim[0])
    y0 = ylim[0] + 0.05 * (ylim[1] - ylim[0])
    ax.plot([x0, x0 + length], [y0, y0], color="black", linewidth=2.0, solid_capstyle="butt", zorder=6)
    ax.text(
        x0 + length / 2,
        y0,
        f"{length:g} m",
        ha="center",
        va="bottom",
        fontsize=6,
        zorder=6,
        bbox={"boxstyle": "square,pad=0.1", "facecolor": "white", "alpha": 0.7, "edgecolor": "none"},
    )


def _picture_points(
    episode: Episode, trajectory: np.ndarray | None, success_radius: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """An episode picture's reference path, goals, their circles' radii, start and path (xy)."""
    reference = np.asarray(episode.reference_path, dtype=float).reshape(-1, 3)[:, :2]
    goals = np.array([g.position[:2] for g in episode.goals], dtype=float).reshape(-1, 2)
    rims = np.array([g.radius + success_radius for g in episode.goals], dtype=float)
    start = np.asarray(episode.start_position[:2], dtype=float)
    path = trajectory[:, 1:3] if trajectory is not None and len(trajectory) else np.zeros((0, 2))
    return reference, goals, rims, start, path


def picture_limits(episode: Episode, trajectory: np.ndarray | None, *, success_radius: float) -> Limits:
    """The limits of an episode's picture (:func:`episode_figure`): its trajectory, reference path, start
    and goal circles with a margin, at the picture's width/height ratio.

    Parameters
    ----------
    episode : Episode
        The dataset episode.
    trajectory : ndarray, shape (K, 8), or None
        The submitted rows; None: none.
    success_radius : float
        The success distance (m).

    Returns
    -------
    tuple
        ``((x min, x max), (y min, y max))`` (m).
    """
    reference, goals, rims, start, path = _picture_points(episode, trajectory, success_radius)
    extremes = [start[None], reference, path]
    if len(goals):
        extremes += [goals - rims[:, None], goals + rims[:, None]]
    width_px, height_px = THUMB_SIZE_PX
    box = Bbox.from_bounds(*_THUMB_AXES)  # the axes' place in the figure, as ``add_axes`` makes it
    return _limits(np.concatenate(extremes), (box.width * width_px) / (box.height * height_px))


def episode_figure(
    episode: Episode,
    trajectory: np.ndarray | None,
    *,
    label: str,
    title: str,
    success_radius: float,
    backdrop: Backdrop | BackdropCrop | None = None,
) -> Figure:
    """A small bird's-eye view of one episode: the trajectory against the reference path and goals.

    Parameters
    ----------
    episode : Episode
        The dataset episode (start, goals, reference path).
    trajectory : ndarray, shape (K, 8), or None
        The submitted ``[t, x, y, z, qx, qy, qz, qw]`` rows; None draws no trajectory.
    label : str
        The episode's termination label, which colours the trajectory.
    title : str
        The picture's title.
    success_radius : float
        The success distance (m); each goal's circle has radius goal radius + this.
    backdrop : Backdrop or BackdropCrop, optional
        The scene's top-down picture, drawn underneath (a crop: the one cut for this picture's
        :func:`picture_limits`).

    Returns
    -------
    Figure
        :data:`THUMB_SIZE_PX` pixels at :data:`THUMB_DPI`.
    """
    width_px, height_px = THUMB_SIZE_PX
    fig = _new_figure(width_px, height_px, THUMB_DPI)
    ax = fig.add_axes(_THUMB_AXES)
    reference, goals, rims, start, path = _picture_points(episode, trajectory, success_radius)
    xlim, ylim = picture_limits(episode, trajectory, success_radius=success_radius)
    if backdrop is not None:
        backdrop.draw(ax, xlim, ylim, width_px)
    for (x, y), r in zip(goals, rims, strict=True):
        ax.add_patch(Circle((x, y), r, facecolor="#2ca02c", alpha=0.15, edgecolor="none", zorder=1))
        ax.add_patch(Circle((x, y), r, fill=False, edgecolor="#1b6e1b", linewidth=0.8, zorder=2))
    if len(goals):
        ax.scatter(goals[:, 0], goals[:, 1], marker="*", s=40, color="#1b6e1b", zorder=4, linewidths=0)
    if len(path):  # the reference path goes over it, thin and dashed, so both show where they agree
        color = label_color(label)
        ax.plot(path[:, 0], path[:, 1], color=color, linewidth=2.2, zorder=3)
        ax.scatter(path[-1:, 0], path[-1:, 1], marker="X", s=36, color=color, edgecolors="black",
                   linewidths=0.4, zorder=6)  # fmt: skip
    if len(reference) > 1:
        ax.plot(
            reference[:, 0], reference[:, 1], color="#1f4e9c", linewidth=0.9, linestyle=(0, (3, 2)), zorder=4
        )
    ax.scatter([start[0]], [start[1]], marker="o", s=30, color="white", edgecolors="black", linewidths=1.0,
               zorder=6)  # fmt: skip
    _scale_bar(ax, xlim, ylim)
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title(title, fontsize=7, pad=3)
    for spine in ax.spines.values():
        spine.set_edgecolor(label_color(label))
        spine.set_linewidth(1.5)
    return fig
