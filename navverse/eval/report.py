"""The evaluation report ``report.html``: one self-contained page per scored submission.

:func:`write_report` writes ``<out_dir>/report.html``, a single file that opens offline in any browser
(no external URL, no script; CSS inline, pictures as base64 ``data:image/png`` URIs). It shows

* a header: dataset name and version, split, embodiment, submission file, episodes and invalid ones;
* the headline numbers (overall SR, SPL, SoftSPL, OS, NE, CR, ADO, NSR, CE; nDTW and SDTW for VLN);
* every table of :data:`navverse.eval.tables.TABLES` (so tables added there appear here too), the
  difficulty thresholds and the submission's problems;
* a summary picture: termination label shares per task (stacked bars) and SR per task × scene type;
* one card per episode, failures first, grouped by termination label: a small bird's-eye view of the
  submitted trajectory against the episode's reference path, the start, and each goal with its success
  circle (goal radius + success distance), over the scene's top-down fields
  (:func:`navverse.scene.fields.load_scene_fields`: terrain classes lightened, obstacles grey). An episode
  without a valid record gets a card with the submission's problems for it instead of a picture.

:func:`navverse.eval.screenshot.screenshot_report` renders it in headless Chromium.
"""

from __future__ import annotations

import base64
import html
import io
import math
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.patches import Circle
from PIL import Image

from navverse.dataset import Dataset, Episode, success_distance
from navverse.eval.metrics import LABELS
from navverse.eval.scoring import EvalResult, robot_for
from navverse.eval.submission import Submission
from navverse.eval.tables import HEADERS, PERCENT, TABLES, cell_text, table_rows
from navverse.files import atomic_write
from navverse.scene.colors import default_color, lighten
from navverse.scene.fields import SceneFields, load_scene_fields

__all__ = [
    "LABEL_COLORS",
    "REPORT_HTML",
    "write_report",
]

REPORT_HTML = "report.html"
LABEL_COLORS = {
    "success": "#2ca02c",
    "wrong_goal": "#ff7f0e",
    "fall": "#d62728",
    "timeout": "#9467bd",
    "invalid": "#7f7f7f",
}
"""Colour of each termination label (:data:`navverse.eval.metrics.LABELS`) in the report."""
CARD_ORDER = ("invalid", "fall", "timeout", "wrong_goal", "success")
"""Order of the episode card groups: failures first."""
HEADLINE = ("success", "spl", "soft_spl", "os", "ne", "cr", "ado", "nsr", "ce", "ndtw", "sdtw")
"""Overall metrics shown as headline numbers (those undefined for the result are left out)."""
TABLE_TITLES = {
    "task_scene": "Success and efficiency per task × scene type",
    "safety_efficiency": "Safety and efficiency per scene type",
    "failures": "Failures per task",
    "difficulty": "Success per task × difficulty",
    "transition": "Indoor-to-outdoor transition per task",
}
"""Headings of the tables; a table missing here is headed by its name."""
SCENE_TYPE_COLORS = {"indoor": "#4c72b0", "outdoor": "#55a868", "i2o": "#c44e52"}

THUMB_SIZE_PX = (300, 250)
"""Width and height of an episode picture (pixels)."""
THUMB_DPI = 100
THUMB_COLORS = 96
"""Palette size the episode pictures are reduced to (keeps 300 cards to a few MB)."""
MARGIN_M = 1.5
"""Room around an episode's trajectory, path, start and goals in its picture (m)."""
_OBSTACLE_RGB = (150, 150, 150)
_NO_SURFACE_RGB = (255, 255, 255)
_TERRAIN_LIGHTEN = 0.55
_MORE_HEADERS = {"ndtw": "nDTW (%)", "sdtw": "SDTW (%)"}
"""Names of headline metrics that no table shows (:data:`navverse.eval.tables.HEADERS` names the others)."""
_MAX_CARD_PROBLEMS = 5
_MAX_PROBLEMS = 200


# ---------------------------------------------------------------------------------------------- pictures


def _png_data_uri(fig: Figure, *, colors: int | None = None) -> str:
    """A figure as a ``data:image/png;base64,...`` URI, optionally reduced to a palette of `colors`."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=fig.dpi, metadata={"Software": None})
    if colors is not None:
        image = Image.open(io.BytesIO(buffer.getvalue())).convert("RGB")
        buffer = io.BytesIO()
        image.quantize(colors=colors, method=Image.Quantize.MEDIANCUT).save(
            buffer, format="PNG", optimize=True
        )
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


def _new_figure(width_px: int, height_px: int, dpi: int) -> Figure:
    fig = Figure(figsize=(width_px / dpi, height_px / dpi), dpi=dpi)
    FigureCanvasAgg(fig)
    return fig


def _label_name(label: str) -> str:
    return label.replace("_", " ")


def _label_color(label: str) -> str:
    """The label's colour in :data:`LABEL_COLORS`; a stable one for a label added to ``LABELS`` later."""
    return LABEL_COLORS.get(label) or "#{:02x}{:02x}{:02x}".format(*default_color(label))


def _summary_figure(result: EvalResult) -> Figure:
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
        shares.barh(names, values, left=left, color=_label_color(label), label=_label_name(label), height=0.6)
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


class _Backdrop:
    """A scene's top-down fields drawn as a light picture: terrain classes lightened, obstacles grey.

    Only the part an episode's picture shows is coloured, so large outdoor scenes cost no more memory
    than their (cached) fields.
    """

    def __init__(self, scene_dir: Path) -> None:
        from navverse.scene import read_annotations

        self.fields: SceneFields = load_scene_fields(scene_dir)
        classes = read_annotations(scene_dir).terrain_classes
        palette = [
            lighten(tuple(classes[n].color), _TERRAIN_LIGHTEN) if n in classes else _NO_SURFACE_RGB
            for n in self.fields.class_names
        ]
        self.palette = np.array([*palette, _NO_SURFACE_RGB], dtype=np.uint8)

    def draw(self, ax: Axes, xlim: tuple[float, float], ylim: tuple[float, float], pixels: int) -> None:
        """Show the part of the picture within the limits, at most about 2 cells per output pixel."""
        f = self.fields
        h, w = f.terrain.shape
        c0 = max(0, math.floor((xlim[0] - f.origin[0]) / f.cell))
        c1 = min(w, math.ceil((xlim[1] - f.origin[0]) / f.cell))
        r0 = max(0, math.floor((ylim[0] - f.origin[1]) / f.cell))
        r1 = min(h, math.ceil((ylim[1] - f.origin[1]) / f.cell))
        if c1 <= c0 or r1 <= r0:
            return
        step = max(1, (c1 - c0) // (2 * pixels))
        terrain = f.terrain[r0:r1:step, c0:c1:step].astype(np.int64)
        crop = self.palette[np.where(terrain >= 0, terrain, len(self.palette) - 1)]
        crop[f.obstacle[r0:r1:step, c0:c1:step]] = _OBSTACLE_RGB
        extent = (
            f.origin[0] + c0 * f.cell,
            f.origin[0] + (c0 + crop.shape[1] * step) * f.cell,
            f.origin[1] + r0 * f.cell,
            f.origin[1] + (r0 + crop.shape[0] * step) * f.cell,
        )
        ax.imshow(crop, origin="lower", extent=extent, interpolation="nearest", zorder=0)


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


def _episode_figure(
    episode: Episode,
    trajectory: np.ndarray | None,
    *,
    label: str,
    title: str,
    success_radius: float,
    backdrop: _Backdrop | None = None,
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
    backdrop : _Backdrop, optional
        The scene's top-down picture, drawn underneath.

    Returns
    -------
    Figure
        :data:`THUMB_SIZE_PX` pixels at :data:`THUMB_DPI`.
    """
    width_px, height_px = THUMB_SIZE_PX
    fig = _new_figure(width_px, height_px, THUMB_DPI)
    ax = fig.add_axes((0.01, 0.01, 0.98, 0.84))
    reference = np.asarray(episode.reference_path, dtype=float).reshape(-1, 3)[:, :2]
    goals = np.array([g.position[:2] for g in episode.goals], dtype=float).reshape(-1, 2)
    rims = np.array([g.radius + success_radius for g in episode.goals], dtype=float)
    start = np.asarray(episode.start_position[:2], dtype=float)
    path = trajectory[:, 1:3] if trajectory is not None and len(trajectory) else np.zeros((0, 2))
    extremes = [start[None], reference, path]
    if len(goals):
        extremes += [goals - rims[:, None], goals + rims[:, None]]
    box = ax.get_position()
    xlim, ylim = _limits(np.concatenate(extremes), (box.width * width_px) / (box.height * height_px))
    if backdrop is not None:
        backdrop.draw(ax, xlim, ylim, width_px)
    for (x, y), r in zip(goals, rims, strict=True):
        ax.add_patch(Circle((x, y), r, facecolor="#2ca02c", alpha=0.15, edgecolor="none", zorder=1))
        ax.add_patch(Circle((x, y), r, fill=False, edgecolor="#1b6e1b", linewidth=0.8, zorder=2))
    if len(goals):
        ax.scatter(goals[:, 0], goals[:, 1], marker="*", s=40, color="#1b6e1b", zorder=4, linewidths=0)
    if len(path):  # the reference path goes over it, thin and dashed, so both show where they agree
        color = _label_color(label)
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
        spine.set_edgecolor(_label_color(label))
        spine.set_linewidth(1.5)
    return fig


# ---------------------------------------------------------------------------------------------- page

_CSS = """
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;margin:0;color:#222;background:#fafafa}
main{max-width:1400px;margin:0 auto;padding:12px 16px}
h1{font-size:1.5em;margin:0.2em 0}h2{font-size:1.2em;margin:1.2em 0 0.4em;border-bottom:1px solid #ddd}
h3{font-size:1em;margin:1em 0 0.3em}
.meta{display:grid;grid-template-columns:max-content auto;gap:2px 12px;font-size:0.9em}
.meta dt{color:#666}.meta dd{margin:0}
.tiles{display:flex;flex-wrap:wrap;gap:8px}
.tile{background:#fff;border:1px solid #ddd;border-radius:6px;padding:6px 12px;min-width:90px}
.tile .v{font-size:1.4em;font-weight:600}.tile .k{font-size:0.8em;color:#666}
.tables{display:flex;flex-wrap:wrap;gap:8px 32px;align-items:flex-start}
table{border-collapse:collapse;font-size:0.85em;background:#fff}
th,td{border:1px solid #ddd;padding:3px 8px;text-align:right}th{background:#f0f0f0}
td:first-child,th:first-child{text-align:left}tr.total td{font-weight:600;background:#f7f7f7}
img.summary{max-width:100%;height:auto}
.problems{font-family:ui-monospace,monospace;font-size:0.8em;max-height:16em;overflow:auto;background:#fff;
 border:1px solid #ddd;padding:6px 6px 6px 24px}
.legend span{display:inline-block;margin-right:14px;font-size:0.85em}
.swatch{display:inline-block;width:12px;height:12px;border-radius:2px;vertical-align:-1px;margin-right:4px}
.cards{display:grid;grid-template-columns:repeat(auto-fill,302px);gap:6px}
.card{background:#fff;border:1px solid #ddd;border-top:4px solid var(--c);border-radius:3px;font-size:0.72em}
.card img{display:block;width:300px;height:250px}
.card .cap{padding:2px 4px 4px}.card .id{font-weight:600;word-break:break-all}
.card .missing{height:130px;width:300px;display:flex;align-items:center;justify-content:center;
 background:#f3f3f3;color:#555;text-align:center;padding:0 12px;box-sizing:border-box}
.card ul{margin:2px 0;padding:0;list-style:none;color:#a33;word-break:break-word}
nav a{margin-right:12px}
"""


def _e(value: object) -> str:
    return html.escape(str(value), quote=True)


def _metric_name(name: str) -> str:
    if name in HEADERS or name in _MORE_HEADERS:
        return HEADERS.get(name) or _MORE_HEADERS[name]
    return f"{name.upper()} (%)" if name in PERCENT else name


def _table_html(header: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    head = "".join(f"<th>{_e(h)}</th>" for h in header)
    body = []
    for row in rows:
        css = ' class="total"' if row[0] == "all" else ""  # the overall row ``table_rows`` ends with
        body.append(f"<tr{css}>" + "".join(f"<td>{_e(c)}</td>" for c in row) + "</tr>")
    return f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>"


def _tables_html(result: EvalResult) -> str:
    if not result.groups.get("overall"):
        return "<p>No episode was scored.</p>"
    parts = []
    for name, (grouping, _) in TABLES.items():
        if not result.groups.get(grouping):
            continue
        header, rows = table_rows(result, name)
        title = TABLE_TITLES.get(name, name.replace("_", " "))
        parts.append(
            f'<section id="table-{_e(name)}"><h3>{_e(title)}</h3>{_table_html(header, rows)}</section>'
        )
    return '<div class="tables">' + "".join(parts) + "</div>"


def _headline_html(result: EvalResult) -> str:
    overall = result.groups.get("overall", {}).get("all", {})
    tiles = []
    for name in HEADLINE:
        value = overall.get(name)
        if value is None:
            continue
        tiles.append(f'<div class="tile"><div class="v">{_e(cell_text(name, value))}</div>'
                     f'<div class="k">{_e(_metric_name(name))}</div></div>')  # fmt: skip
    return '<div class="tiles">' + "".join(tiles) + "</div>" if tiles else ""


def _thresholds_html(result: EvalResult) -> str:
    if not result.difficulty_thresholds:
        return ""
    items = "".join(
        f"<li>{_e(task)}: easy &lt; {a:.2f} m ≤ medium &lt; {b:.2f} m ≤ hard</li>"
        for task, (a, b) in sorted(result.difficulty_thresholds.items())
    )
    return f"<h3>Difficulty by geodesic distance</h3><ul>{items}</ul>"


def _problems_html(problems: Sequence[str]) -> str:
    if not problems:
        return ""
    shown = "".join(f"<li>{_e(p)}</li>" for p in problems[:_MAX_PROBLEMS])
    more = (
        f"<p>… and {len(problems) - _MAX_PROBLEMS} more (all in metrics.json).</p>"
        if len(problems) > _MAX_PROBLEMS
        else ""
    )
    return (f'<h2 id="problems">Submission problems ({len(problems)})</h2>'
            f'<ol class="problems">{shown}</ol>{more}')  # fmt: skip


def _value(row: Mapping[str, object], name: str, *, unit: str = "") -> str:
    value = row.get(name)
    return "–" if value is None else cell_text(name, float(value)) + unit


_CARD_FACTS = {"success": ("SR", ""), "spl": ("SPL", ""), "ne": ("NE", " m"), "path_length": ("P", " m"),
               "ndtw": ("nDTW", ""), "sdtw": ("SDTW", "")}  # fmt: skip


def _fact(row: Mapping[str, object], name: str) -> str:
    """``name value unit`` of a card, kept on one line (no-break spaces)."""
    short, unit = _CARD_FACTS[name]
    return f"{short} {_value(row, name)}{unit}".replace(" ", "\u00a0")


def _card_html(row: Mapping[str, object], picture: str | None, problems: Sequence[str]) -> str:
    label = str(row["label"])
    color = _label_color(label)
    facts = [
        f"{_e(row['task'])} · {_e(row['scene_id'])} ({_e(row['scene_type'])}) · "
        f"{_e(row.get('difficulty') or '–')}",
        " · ".join([_e(_label_name(label)), *(_fact(row, n) for n in ("success", "spl"))]),
        " · ".join(_fact(row, n) for n in ("ne", "path_length", "ndtw", "sdtw") if row.get(n) is not None),
    ]
    if picture is not None:
        body = f'<img src="{picture}" alt="{_e(row["episode_id"])}: trajectory" width="300" height="250">'
    else:
        why = "".join(f"<li>{_e(p)}</li>" for p in problems[:_MAX_CARD_PROBLEMS])
        if len(problems) > _MAX_CARD_PROBLEMS:
            why += f"<li>… {len(problems) - _MAX_CARD_PROBLEMS} more</li>"
        what = f"<ul>{why}</ul>" if why else "<p>no record in the submission</p>"
        body = f'<div class="missing"><div><b>no valid trajectory</b>{what}</div></div>'
    caption = "<br>".join(f for f in facts if f)
    episode_id = _e(row["episode_id"])
    return (
        f'<div class="card" id="ep-{episode_id}" data-label="{_e(label)}" style="--c:{color}">{body}'
        f'<div class="cap"><div class="id">{episode_id}</div>{caption}</div></div>'
    )


def _split_of(dataset: Dataset, scene_ids: set[str]) -> list[str]:
    return sorted(s for s, scenes in dataset.manifest.splits.items() if scene_ids & set(scenes))


def write_report(
    result: EvalResult,
    *,
    dataset: Dataset,
    submission: Submission,
    scene_dirs: Mapping[str, Path],
    out_dir: Path,
    title: str | None = None,
    embodiment: str | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> Path:
    """Write ``<out_dir>/report.html``, a self-contained page of the evaluation (atomically).

    Parameters
    ----------
    result : EvalResult
        The scored submission (:func:`navverse.eval.scoring.score`).
    dataset : Dataset
        The dataset version it was scored on (episodes: start, goals, reference paths).
    submission : Submission
        The submission scored (trajectories, problems).
    scene_dirs : mapping
        Built scene directory by scene id, as given to :func:`~navverse.eval.scoring.score` (for the
        scenes' top-down fields under the episode pictures).
    out_dir : Path
        Output folder; created if missing.
    title : str, optional
        Page title; by default "Evaluation of <submission file>".
    embodiment : str, optional
        The robot scored, as given to :func:`~navverse.eval.scoring.score` (the success circles); the
        dataset's by default.
    progress : callable, optional
        Called with (episode cards drawn, episodes) after each card.

    Returns
    -------
    Path
        The report file.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    manifest = dataset.manifest
    embodiment = embodiment or manifest.embodiment
    reach = success_distance(robot_for(embodiment).radius)
    scene_ids = {str(row["scene_id"]) for row in result.episodes}
    splits = _split_of(dataset, scene_ids)
    wanted = {str(row["episode_id"]) for row in result.episodes}
    episodes = {e.episode_id: e for s in splits for e in dataset.episodes(split=s) if e.episode_id in wanted}
    problems_of: dict[str, list[str]] = {}
    for problem in submission.problems:
        if problem.episode_id is not None:
            problems_of.setdefault(problem.episode_id, []).append(str(problem))
    title = title or f"Evaluation of {submission.path.name}"
    invalid = sum(row["label"] == "invalid" for row in result.episodes)

    backdrops: dict[str, _Backdrop | None] = {}
    groups: dict[str, list[str]] = {}
    drawn = 0
    order = [*CARD_ORDER, *sorted({str(r["label"]) for r in result.episodes} - set(CARD_ORDER))]
    for label in order:
        rows = sorted((r for r in result.episodes if r["label"] == label), key=lambda r: str(r["episode_id"]))
        cards = []
        for row in rows:
            episode_id = str(row["episode_id"])
            record = submission.records.get(episode_id)
            episode = episodes.get(episode_id)
            picture = None
            if record is not None and episode is not None and label != "invalid":
                scene = episode.scene_id
                if scene not in backdrops:
                    backdrops[scene] = _Backdrop(Path(scene_dirs[scene])) if scene in scene_dirs else None
                heading = (f"{episode_id}\n{_label_name(label)} · SR {_value(row, 'success')} · "
                           f"SPL {_value(row, 'spl')}")  # fmt: skip
                fig = _episode_figure(episode, record.trajectory, label=label, title=heading,
                                     success_radius=reach, backdrop=backdrops[scene])  # fmt: skip
                picture = _png_data_uri(fig, colors=THUMB_COLORS)
            cards.append(_card_html(row, picture, problems_of.get(episode_id, [])))
            drawn += 1
            if progress is not None:
                progress(drawn, len(result.episodes))
        if cards:
            color = _label_color(label)
            groups[label] = [
                f'<h3 id="label-{_e(label)}"><span class="swatch" style="background:{color}"></span>'
                f"{_e(_label_name(label))} ({len(cards)})</h3>",
                '<div class="cards">',
                *cards,
                "</div>",
            ]

    meta = [
        ("dataset", f"{manifest.name} v{manifest.version}"),
        ("split", ", ".join(splits) or "–"),
        ("embodiment", embodiment),
        ("submission", submission.path.name),
        ("episodes", str(len(result.episodes))),
        ("invalid", f"{invalid} (no valid trajectory: scored as failures)" if invalid else "0"),
        ("submission problems", str(len(result.problems))),
    ]
    summary = ""
    if result.groups.get("overall"):
        picture = _png_data_uri(_summary_figure(result))
        summary = f'<img class="summary" src="{picture}" alt="summary" width="960" height="330">'
    legend = "".join(
        f'<span><span class="swatch" style="background:{_label_color(label)}"></span>'
        f"{_e(_label_name(label))}</span>"
        for label in LABELS
    )
    legend += (
        "<span>━ trajectory (in its label's colour)</span><span>┅ reference path</span>"
        "<span>○ start</span><span>✕ end</span>"
        "<span>★ goal, circle: goal radius + success distance "
        f"({reach:.1f} m)</span><span>grey: obstacles</span>"
    )
    nav = "".join(f'<a href="#label-{_e(label)}">{_e(_label_name(label))}</a>' for label in groups)
    page = "\n".join(
        [
            "<!DOCTYPE html>",
            '<html lang="en"><head><meta charset="utf-8">',
            '<meta name="viewport" content="width=device-width, initial-scale=1">',
            f"<title>{_e(title)}</title><style>{_CSS}</style></head><body><main>",
            f"<h1>{_e(title)}</h1>",
            '<dl class="meta">' + "".join(f"<dt>{_e(k)}</dt><dd>{_e(v)}</dd>" for k, v in meta) + "</dl>",
            "<h2>Overall</h2>",
            _headline_html(result),
            summary,
            "<h2>Tables</h2>",
            _tables_html(result),
            _thresholds_html(result),
            _problems_html(result.problems),
            f'<h2 id="episodes">Episodes ({len(result.episodes)})</h2>',
            f'<div class="legend">{legend}</div>',
            f"<nav>{nav}</nav>",
            *(line for label in groups for line in groups[label]),
            "</main></body></html>",
            "",
        ]
    )
    target = out_dir / REPORT_HTML
    with atomic_write(target, mode="w") as handle:
        handle.write(page)
    return target
