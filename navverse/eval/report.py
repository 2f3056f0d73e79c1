"""The evaluation report ``report.html``: one self-contained page per scored submission.

:func:`write_report` writes ``<out_dir>/report.html``, a single file that opens offline in any browser
(no external URL, no script; CSS inline, from the package file ``report.css``; pictures, drawn by
:mod:`navverse.eval.figures`, as base64 ``data:image/png`` URIs). It shows

* a header: dataset name and version, split, embodiment, submission file, episodes and invalid ones;
* the headline numbers (overall SR, SPL, SoftSPL, OS, NE, CR, ADO, NSR, CE; nDTW and SDTW for VLN), each
  with its full name and its n (the episodes it is a mean over);
* every table of :data:`navverse.eval.tables.TABLES` (so tables added there appear here too; a cell over
  fewer episodes than its row's shows its own n), the difficulty thresholds;
* the metrics glossary: abbreviation, full name and one-line definition of every metric shown, from
  their declarations in :mod:`navverse.eval.metrics`; the scored episode ids (collapsed); the
  submission's problems;
* a summary picture: termination label shares per task (stacked bars) and SR per task × scene type;
* the episodes grouped by termination label, failures first. A bounded selection of them
  (:func:`navverse.eval.selection.pictured_episodes`: at most ``pictures``, every episode when there are
  no more; otherwise among those with a valid trajectory, every outcome shown, failures first, spread
  over tasks, scene types and scenes; the page says how they were chosen) get a card each: a small
  bird's-eye view of the submitted trajectory against the episode's reference path, the start, and each
  goal with its success circle (goal radius + success distance), over the scene's top-down fields
  (:func:`navverse.scene.fields.load_scene_fields`: terrain classes lightened, obstacles grey), and a
  strip of first-person keyframes; an episode without a valid record, the submission's problems for it
  instead. Every other episode is a row of a compact table under its label: its facts and metrics, as a
  card's caption shows them (and its first problem when it has no valid record).

The pictures are drawn scene by scene: a scene's bird's-eye views over its fields, then its keyframe
strips with its renderer, so that a scene's fields and its renderer are never in memory together. Given
the :class:`PictureBackdrops` that scoring filled (:func:`~navverse.eval.scoring.score`'s ``on_fields``),
the report reads no scene's fields at all: their backdrops were cut while scoring held the fields.

:func:`navverse.eval.screenshot.screenshot_report` renders it in headless Chromium.
"""

from __future__ import annotations

import base64
import html
import io
from collections.abc import Callable, Iterable, Mapping, Sequence
from importlib import resources
from pathlib import Path

import numpy as np
from PIL import Image

from navverse.dataset import Dataset, Episode
from navverse.eval.figures import (
    THUMB_COLORS,
    THUMB_SIZE_PX,
    Backdrop,
    BackdropCrop,
    episode_figure,
    label_color,
    label_name,
    picture_limits,
    png_data_uri,
    summary_figure,
)
from navverse.eval.measures import Robot
from navverse.eval.metrics import LABELS, definition
from navverse.eval.protocol import describe
from navverse.eval.scoring import EvalResult, labelled_episodes, robot_for
from navverse.eval.selection import CARD_ORDER, NO_TRAJECTORY, PICTURES, pictured_episodes, selection_text
from navverse.eval.submission import Submission
from navverse.eval.tables import (
    HEADERS,
    TABLES,
    cell_text,
    glossary,
    scope_text,
    scored_episode_groups,
    shown_columns,
    table_rows,
)
from navverse.files import atomic_write
from navverse.scene.fields import SceneFields

__all__ = ["REPORT_HTML", "PictureBackdrops", "write_report"]

REPORT_HTML = "report.html"
REPORT_CSS = "report.css"
"""The page's style sheet, package data of :mod:`navverse.eval`, inlined in the page."""
ROWS_CSS = (
    "table.episodes{margin:6px 0 4px}\n"
    ".episodes td:nth-child(-n+5),.episodes th:nth-child(-n+5),.episodes .why{text-align:left}\n"
    ".episodes td:first-child{font-family:ui-monospace,monospace}\n"
)
"""The style of the episode rows, added to the page's when it has rows (episodes without a card)."""
KEYFRAMES = 4
"""First-person keyframes per episode card."""
KEYFRAME_SIZE = (144, 108)
"""Width and height of one keyframe (pixels)."""
ROW_FACTS = ("success", "spl", "ne", "path_length", "ndtw", "sdtw")
"""The metrics of an episode row (and of a card's caption)."""
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
GROUP_TITLE = "the row's group of episodes"
ROW_N_TITLE = "the row's number of episodes: the n of its values (a value over fewer shows its own n)"
"""Tooltips of the tables' first two columns (the others show their metric's full name)."""
_MAX_CARD_PROBLEMS = 5
_MAX_PROBLEMS = 200


def _e(value: object) -> str:
    return html.escape(str(value), quote=True)


def _table_html(
    header: Sequence[str], rows: Sequence[Sequence[str]], titles: Sequence[str] | None = None
) -> str:
    """An HTML table; `titles` are the columns' tooltips (their full names)."""
    tips = titles or [""] * len(header)
    head = "".join(
        f'<th title="{_e(tip)}">{_e(h)}</th>' if tip else f"<th>{_e(h)}</th>"
        for h, tip in zip(header, tips, strict=True)
    )
    body = []
    for row in rows:
        css = ' class="total"' if row[0] == "all" else ""  # the overall row ``table_rows`` ends with
        body.append(f"<tr{css}>" + "".join(f"<td>{_e(c)}</td>" for c in row) + "</tr>")
    return f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>"


def _tables_html(result: EvalResult) -> str:
    if not result.groups.get("overall"):
        return "<p>No episode was scored.</p>"
    parts = []
    for name, (grouping, columns) in TABLES.items():
        if not result.groups.get(grouping):
            continue
        header, rows = table_rows(result, name)
        titles = [GROUP_TITLE, ROW_N_TITLE, *(definition(c).title for c in columns)]
        title = TABLE_TITLES.get(name, name.replace("_", " "))
        table = _table_html(header, rows, titles)
        parts.append(f'<section id="table-{_e(name)}"><h3>{_e(title)}</h3>{table}</section>')
    return '<div class="tables">' + "".join(parts) + "</div>"


def _headline_names(result: EvalResult) -> list[str]:
    """The headline metrics the result defines (:data:`HEADLINE`)."""
    overall = result.groups.get("overall", {}).get("all", {})
    return [name for name in HEADLINE if overall.get(name) is not None]


def _headline_html(result: EvalResult) -> str:
    """One tile per headline metric: value, column name, full name and n (its definition on hover)."""
    overall = result.groups.get("overall", {}).get("all", {})
    tiles = []
    for name in _headline_names(result):
        spec = definition(name)
        n = overall.get(f"{name}_n", overall.get("episodes", 0))
        tiles.append(
            f'<div class="tile" id="headline-{_e(name)}" title="{_e(spec.title)}: {_e(spec.description)}">'
            f'<div class="v">{_e(cell_text(name, overall[name]))}</div>'
            f'<div class="k">{_e(HEADERS.get(name, name))}</div><div class="t">{_e(spec.title)}</div>'
            f'<div class="n">n = {_e(n)}</div></div>'
        )
    return '<div class="tiles">' + "".join(tiles) + "</div>" if tiles else ""


def _glossary_html(names: Sequence[str]) -> str:
    """The ``Metrics`` section: abbreviation, full name and one-line definition of each metric shown."""
    if not names:
        return ""
    rows = [[e["column"], e["title"], e["description"], e["better"], e["name"]] for e in glossary(names)]
    note = (
        "Every number above is the mean over its n episodes (a tile's n; a table row's <code>episodes</code>,"
        " or a cell's own (n=…)) of the per-episode value defined here, except the counts (#); rates in %."
    )
    table = _table_html(["column", "full name", "definition", "better", "key"], rows)
    return f'<h2 id="metrics">Metrics</h2><p>{note}</p><div class="glossary">{table}</div>'


def _ids_html(ids: Sequence[str]) -> str:
    links = ", ".join(f'<a href="#ep-{_e(i)}">{_e(i)}</a>' for i in ids)
    return f'<p class="ids">{links}</p>'


def _scored_html(result: EvalResult) -> str:
    """The scored episode ids by task / scene type, in a collapsed ``<details>``, each a link to its card."""
    if not result.episodes:
        return ""
    parts = [f"<h4>{_e(key.replace('/', ' / '))} ({len(ids)})</h4>{_ids_html(ids)}"
             for key, ids in scored_episode_groups(result)]  # fmt: skip
    invalid = sorted(str(r["episode_id"]) for r in result.episodes if r["label"] == "invalid")
    if invalid:
        parts.append(
            f"<h4>without a valid record, scored as failures ({len(invalid)})</h4>{_ids_html(invalid)}"
        )
    count = len(result.episodes)
    return (
        f'<h2 id="scored">Scored episodes ({count})</h2><details class="scored"><summary>The {count} '
        f"episode ids in the means, by task / scene type</summary>{''.join(parts)}</details>"
    )


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


def _fact(row: Mapping[str, object], name: str) -> str:
    """``abbreviation value unit`` of a card, kept on one line (no-break spaces)."""
    spec = definition(name)
    unit = {"": "", "%": "%"}.get(spec.unit, f" {spec.unit}") if row.get(name) is not None else ""
    return f"{spec.abbreviation} {_value(row, name)}{unit}".replace(" ", "\u00a0")


def _card_html(
    row: Mapping[str, object], picture: str | None, problems: Sequence[str], *, strip: str | None = None
) -> str:
    label = str(row["label"])
    color = label_color(label)
    facts = [
        f"{_e(row['task'])} · {_e(row['scene_id'])} ({_e(row['scene_type'])}) · "
        f"{_e(row.get('difficulty') or '–')}",
        " · ".join([_e(label_name(label)), *(_fact(row, n) for n in ("success", "spl"))]),
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
    if strip is not None:
        body += f'<img class="strip" src="{strip}" alt="{_e(row["episode_id"])}: keyframes" width="300">'
    caption = "<br>".join(f for f in facts if f)
    episode_id = _e(row["episode_id"])
    return (
        f'<div class="card" id="ep-{episode_id}" data-label="{_e(label)}" style="--c:{color}">{body}'
        f'<div class="cap"><div class="id">{episode_id}</div>{caption}</div></div>'
    )


def _row_columns(rows: Iterable[Mapping[str, object]]) -> list[str]:
    """The metrics of the episode rows: those of :data:`ROW_FACTS` some of the rows define."""
    rows = list(rows)
    return [n for n in ROW_FACTS if any(row.get(n) is not None for row in rows)]


def _rows_html(
    rows: Sequence[Mapping[str, object]],
    problems_of: Mapping[str, Sequence[str]],
    *,
    names: Sequence[str],
    invalid: bool,
) -> str:
    """The table of a label's episodes without a card: a row each, with the facts and metrics (`names`) a
    card's caption shows (and, for episodes without a valid record, their first problem)."""
    header = ["episode", "task", "scene", "scene type", "difficulty", *(HEADERS.get(n, n) for n in names)]
    tips = ["", "", "", "", "", *(definition(n).title for n in names)]
    head = "".join(
        f'<th title="{_e(tip)}">{_e(h)}</th>' if tip else f"<th>{_e(h)}</th>"
        for h, tip in zip(header, tips, strict=True)
    )
    if invalid:
        head += '<th class="why" title="the first problem of the episode\'s line">why</th>'
    body = []
    for row in rows:
        episode_id = _e(row["episode_id"])
        cells = [row["task"], row["scene_id"], row["scene_type"], row.get("difficulty") or "–"]
        cells += [_value(row, n) for n in names]
        why = ""
        if invalid:
            problems = problems_of.get(str(row["episode_id"]), [])
            more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
            text = problems[0] + more if problems else "no record in the submission"
            why = f'<td class="why">{_e(text)}</td>'
        body.append(
            f'<tr id="ep-{episode_id}"><td>{episode_id}</td>' + "".join(f"<td>{_e(c)}</td>" for c in cells)
            + f"{why}</tr>"
        )  # fmt: skip
    return f'<table class="episodes"><thead><tr>{head}</tr></thead><tbody>{"".join(body)}</tbody></table>'


class _KeyframeStrips:
    """First-person keyframe strips of trajectories, one renderer per scene (built when first needed)."""

    def __init__(self, embodiment: str) -> None:
        self._embodiment = embodiment
        self._camera: np.ndarray | None = None
        self._renderers: dict[str, object] = {}

    def strip(self, scene: str, scene_dir: Path, trajectory: np.ndarray, count: int) -> str:
        """A JPEG data URI of `count` frames side by side, along the trajectory, start on the left."""
        from navverse.look.files import load_scene_look
        from navverse.scene.scene_cache import cached_scene
        from navverse.sim.camera import CameraIntrinsics
        from navverse.sim.embodiments import make_embodiment
        from navverse.sim.keyframes import render_keyframes
        from navverse.sim.render import SceneRenderer

        if self._camera is None:
            self._camera = np.asarray(make_embodiment(self._embodiment).camera_to_base, dtype=float)
        if scene not in self._renderers:
            intrinsics = CameraIntrinsics.from_hfov(*KEYFRAME_SIZE, 90.0)
            shown = cached_scene(scene_dir)
            look = load_scene_look(shown, scene_dir)
            self._renderers[scene] = SceneRenderer(shown, intrinsics=intrinsics, look=look)
        frames = render_keyframes(self._renderers[scene], trajectory, self._camera, count)
        gap = np.full((KEYFRAME_SIZE[1], 2, 3), 255, dtype=np.uint8)
        row = np.concatenate([part for frame in frames for part in (frame, gap)][:-1], axis=1)
        buffer = io.BytesIO()
        Image.fromarray(row).save(buffer, format="JPEG", quality=80)
        return "data:image/jpeg;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


class PictureBackdrops:
    """The backdrops of the episodes a report pictures, cut from each scene's fields while scoring holds
    them, so that the report reads no scene's fields again.

    Made before scoring: the pictured episodes (:func:`~navverse.eval.selection.pictured_episodes`) are
    chosen by the labels :func:`~navverse.eval.scoring.labelled_episodes` gives, which need no fields and
    equal the scored ones. Give :meth:`take` to :func:`~navverse.eval.scoring.score` as ``on_fields``,
    then this object to :func:`write_report` as ``backdrops`` (with the same ``pictures`` and
    embodiment: a report of another embodiment, whose goal circles differ, does not use the crops).
    Memory: one crop per pictured episode (about the cells its picture shows), whatever the scenes'
    sizes.

    Parameters
    ----------
    dataset, submission
        As given to :func:`~navverse.eval.scoring.score`.
    split : str
        The split scored.
    scene_dirs : mapping
        Built scene directory by scene id (the terrain classes' colours).
    embodiment : str, optional
        The robot scored (the success circles); the dataset's by default.
    episodes : str
        ``all`` or ``submitted``, as given to :func:`~navverse.eval.scoring.score`.
    pictures : int
        The most episodes pictured, as given to :func:`write_report`.
    """

    def __init__(
        self,
        dataset: Dataset,
        submission: Submission,
        *,
        split: str,
        scene_dirs: Mapping[str, Path],
        embodiment: str | None = None,
        episodes: str = "all",
        pictures: int = PICTURES,
    ) -> None:
        rows = labelled_episodes(dataset, submission, split=split, embodiment=embodiment, episodes=episodes)
        chosen = {i for i in pictured_episodes(rows, pictures) if i in submission.records}
        self.embodiment: str = embodiment or dataset.manifest.embodiment
        """The embodiment the crops were cut for (its success distances size the pictures)."""
        self._robot = robot_for(self.embodiment)
        self._submission = submission
        self._scene_dirs = scene_dirs
        self._wanted: dict[str, list[Episode]] = {}
        for episode in dataset.episodes(split=split):
            if episode.episode_id in chosen:
                self._wanted.setdefault(episode.scene_id, []).append(episode)
        self.crops: dict[str, BackdropCrop | None] = {}
        """Each pictured episode's crop once its scene was taken (None: its picture misses the grid)."""

    def take(self, scene: str, fields: SceneFields) -> None:
        """Cut the backdrops of the scene's pictured episodes from its fields (``score``'s ``on_fields``)."""
        wanted = self._wanted.get(scene)
        if not wanted or scene not in self._scene_dirs:
            return
        backdrop = Backdrop(Path(self._scene_dirs[scene]), fields=fields)
        for episode in wanted:
            trajectory = self._submission.records[episode.episode_id].trajectory
            limits = picture_limits(
                episode, trajectory, success_radius=self._robot.success_distance(episode.scene_type)
            )
            self.crops[episode.episode_id] = backdrop.crop(*limits, THUMB_SIZE_PX[0])


def _split_of(dataset: Dataset, scene_ids: set[str]) -> list[str]:
    return sorted(s for s, scenes in dataset.manifest.splits.items() if scene_ids & set(scenes))


def _scene_figures(
    rows: Sequence[Mapping[str, object]],
    episodes: Mapping[str, Episode],
    submission: Submission,
    *,
    robot: Robot,
    scene_dir: Path | None,
    crops: Mapping[str, BackdropCrop | None],
) -> dict[str, str]:
    """The top-down pictures (PNG data URIs) of one scene's episodes, ``{episode id: picture}``, over
    the scene's backdrop: the `crops` cut while scoring held the fields when they hold every episode's,
    else the scene's fields (in memory only while they are drawn)."""
    cut = all(str(row["episode_id"]) in crops for row in rows)
    backdrop = Backdrop(scene_dir) if scene_dir is not None and not cut else None
    figures = {}
    for row in rows:
        episode_id, label = str(row["episode_id"]), str(row["label"])
        episode, record = episodes[episode_id], submission.records[episode_id]
        heading = (f"{episode_id}\n{label_name(label)} · SR {_value(row, 'success')} · "
                   f"SPL {_value(row, 'spl')}")  # fmt: skip
        fig = episode_figure(episode, record.trajectory, label=label, title=heading,
                             success_radius=robot.success_distance(episode.scene_type),
                             backdrop=crops[episode_id] if cut else backdrop)  # fmt: skip
        figures[episode_id] = png_data_uri(fig, colors=THUMB_COLORS)
    return figures


def _episode_pictures(
    result: EvalResult,
    episodes: Mapping[str, Episode],
    submission: Submission,
    scene_dirs: Mapping[str, Path],
    *,
    chosen: set[str],
    robot: Robot,
    embodiment: str,
    keyframes: int,
    crops: Mapping[str, BackdropCrop | None],
    progress: Callable[[int, int], None] | None,
) -> dict[str, tuple[str | None, str | None]]:
    """The top-down picture and the keyframe strip (data URIs) of every `chosen` episode with a
    trajectory to draw, ``{episode id: (picture, strip)}``, drawn scene by scene: a scene's pictures over
    its backdrop, then its strips with its renderer, so that one scene's fields or its renderer are in
    memory at a time, and memory grows with the pictures, not with the scenes."""
    by_scene: dict[str, list[Mapping[str, object]]] = {}
    cards = [row for row in result.episodes if str(row["episode_id"]) in chosen]
    drawn, total = 0, len(cards)
    if progress is not None:
        progress(drawn, total)
    for row in cards:
        episode = episodes.get(str(row["episode_id"]))
        if (
            submission.records.get(str(row["episode_id"])) is None
            or episode is None
            or row["label"] == "invalid"
        ):
            drawn += 1  # a card without pictures
            if progress is not None:
                progress(drawn, total)
            continue
        by_scene.setdefault(episode.scene_id, []).append(row)
    pictures: dict[str, tuple[str | None, str | None]] = {}
    for scene, rows in sorted(by_scene.items()):
        scene_dir = Path(scene_dirs[scene]) if scene in scene_dirs else None
        figures = _scene_figures(rows, episodes, submission, robot=robot, scene_dir=scene_dir, crops=crops)
        strips = _KeyframeStrips(embodiment) if keyframes and scene_dir is not None else None
        for row in rows:
            episode_id = str(row["episode_id"])
            strip = None
            if strips is not None:
                strip = strips.strip(scene, scene_dir, submission.records[episode_id].trajectory, keyframes)
            pictures[episode_id] = (figures[episode_id], strip)
            drawn += 1
            if progress is not None:
                progress(drawn, total)
        del figures, strips
    return pictures


def write_report(
    result: EvalResult,
    *,
    dataset: Dataset,
    submission: Submission,
    scene_dirs: Mapping[str, Path],
    out_dir: Path,
    title: str | None = None,
    embodiment: str | None = None,
    keyframes: int = KEYFRAMES,
    pictures: int = PICTURES,
    backdrops: PictureBackdrops | None = None,
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
    keyframes : int
        First-person frames per episode card, evenly spaced along its trajectory, as the robot's
        camera sees them (0: none).
    pictures : int
        The most episodes drawn as cards (:func:`~navverse.eval.selection.pictured_episodes`); every
        other episode is a row of its label's table.
    backdrops : PictureBackdrops, optional
        The pictured episodes' backdrops, cut while scoring held each scene's fields (made with the
        same ``pictures`` and embodiment); without it (or for a scene with an episode it lacks) the
        report reads the scene's fields.
    progress : callable, optional
        Called with (episode cards drawn, cards to draw), first with none drawn, then after each card.

    Returns
    -------
    Path
        The report file.

    Raises
    ------
    ValueError
        If `pictures` is negative.
    """
    if pictures < 0:
        raise ValueError(f"pictures must be 0 or more, not {pictures}")
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    manifest = dataset.manifest
    embodiment = embodiment or manifest.embodiment
    robot = robot_for(embodiment)
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

    summary = ""  # drawn first: the episode pictures load the renderer
    if result.groups.get("overall"):
        picture = png_data_uri(summary_figure(result))
        summary = f'<img class="summary" src="{picture}" alt="summary" width="960" height="330">'
    chosen = set(pictured_episodes(result.episodes, pictures))
    crops = backdrops.crops if backdrops is not None and backdrops.embodiment == embodiment else {}
    listed_columns = _row_columns(r for r in result.episodes if str(r["episode_id"]) not in chosen)
    drawn = _episode_pictures(
        result, episodes, submission, scene_dirs, chosen=chosen, robot=robot, embodiment=embodiment,
        keyframes=keyframes, crops=crops, progress=progress,
    )  # fmt: skip
    groups: dict[str, list[str]] = {}
    order = [*CARD_ORDER, *sorted({str(r["label"]) for r in result.episodes} - set(CARD_ORDER))]
    for label in order:
        rows = sorted((r for r in result.episodes if r["label"] == label), key=lambda r: str(r["episode_id"]))
        cards, listed = [], []
        for row in rows:
            episode_id = str(row["episode_id"])
            if episode_id not in chosen:
                listed.append(row)
                continue
            picture, strip = drawn.get(episode_id, (None, None))
            cards.append(_card_html(row, picture, problems_of.get(episode_id, []), strip=strip))
        if rows:
            color = label_color(label)
            groups[label] = [
                f'<h3 id="label-{_e(label)}"><span class="swatch" style="background:{color}"></span>'
                f"{_e(label_name(label))} ({len(rows)})</h3>"
            ]
            if cards:
                groups[label] += ['<div class="cards">', *cards, "</div>"]
            if listed:
                groups[label].append(
                    _rows_html(listed, problems_of, names=listed_columns, invalid=label == NO_TRAJECTORY)
                )

    meta = [
        ("dataset", f"{manifest.name} v{manifest.version}"),
        ("split", ", ".join(splits) or "–"),
        ("embodiment", embodiment),
        ("submission", submission.path.name),
        ("episodes", str(len(result.episodes))),
        ("scored", scope_text(result) or "–"),
        ("track", describe(result.track)),
        ("invalid", f"{invalid} (no valid trajectory: scored as failures)" if invalid else "0"),
        ("submission problems", str(len(result.problems))),
    ]
    legend = "".join(
        f'<span><span class="swatch" style="background:{label_color(label)}"></span>'
        f"{_e(label_name(label))}</span>"
        for label in LABELS
    )
    reach = ", ".join(
        f"{d:.1f} m" for d in sorted({robot.success_distance(e.scene_type) for e in episodes.values()})
    )
    legend += (
        "<span>━ trajectory (in its label's colour)</span><span>┅ reference path</span>"
        "<span>○ start</span><span>✕ end</span>"
        "<span>★ goal, circle: goal radius + success distance "
        f"({reach or '–'})</span><span>grey: obstacles</span>"
    )
    css = resources.files("navverse.eval").joinpath(REPORT_CSS).read_text(encoding="utf-8")
    if len(chosen) < len(result.episodes):
        css += ROWS_CSS
    nav = "".join(f'<a href="#label-{_e(label)}">{_e(label_name(label))}</a>' for label in groups)
    said = selection_text(len(chosen), len(result.episodes), pictures)
    chosen_text = [f'<p class="chosen">{said}</p>'] if result.episodes else []
    page = "\n".join(
        [
            "<!DOCTYPE html>",
            '<html lang="en"><head><meta charset="utf-8">',
            '<meta name="viewport" content="width=device-width, initial-scale=1">',
            f"<title>{_e(title)}</title><style>\n{css}</style></head><body><main>",
            f"<h1>{_e(title)}</h1>",
            '<dl class="meta">' + "".join(f"<dt>{_e(k)}</dt><dd>{_e(v)}</dd>" for k, v in meta) + "</dl>",
            "<h2>Overall</h2>",
            _headline_html(result),
            summary,
            "<h2>Tables</h2>",
            _tables_html(result),
            _thresholds_html(result),
            _glossary_html(
                list(dict.fromkeys([*_headline_names(result), *shown_columns(result), *listed_columns]))
            ),
            _scored_html(result),
            _problems_html(result.problems),
            f'<h2 id="episodes">Episodes ({len(result.episodes)})</h2>',
            *chosen_text,
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
