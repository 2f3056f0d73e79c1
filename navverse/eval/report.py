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
from collections.abc import Callable, Mapping, Sequence
from importlib import resources
from pathlib import Path

import numpy as np
from PIL import Image

from navverse.dataset import Dataset, Episode
from navverse.eval.figures import (
    THUMB_COLORS,
    Backdrop,
    episode_figure,
    label_color,
    label_name,
    png_data_uri,
    summary_figure,
)
from navverse.eval.measures import Robot
from navverse.eval.metrics import LABELS, definition
from navverse.eval.protocol import describe
from navverse.eval.scoring import EvalResult, robot_for
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

__all__ = ["REPORT_HTML", "write_report"]

REPORT_HTML = "report.html"
REPORT_CSS = "report.css"
"""The page's style sheet, package data of :mod:`navverse.eval`, inlined in the page."""
KEYFRAMES = 4
"""First-person keyframes per episode card."""
KEYFRAME_SIZE = (144, 108)
"""Width and height of one keyframe (pixels)."""
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


class _KeyframeStrips:
    """First-person keyframe strips of trajectories, one renderer per scene (built when first needed)."""

    def __init__(self, embodiment: str) -> None:
        self._embodiment = embodiment
        self._camera: np.ndarray | None = None
        self._renderers: dict[str, object] = {}

    def strip(self, scene: str, scene_dir: Path, trajectory: np.ndarray, count: int) -> str:
        """A PNG data URI of `count` frames side by side, along the trajectory, start on the left."""
        from navverse.scene.directory import read_scene
        from navverse.sim.camera import CameraIntrinsics
        from navverse.sim.embodiments import make_embodiment
        from navverse.sim.keyframes import render_keyframes
        from navverse.sim.render import SceneRenderer

        if self._camera is None:
            self._camera = np.asarray(make_embodiment(self._embodiment).camera_to_base, dtype=float)
        if scene not in self._renderers:
            intrinsics = CameraIntrinsics.from_hfov(*KEYFRAME_SIZE, 90.0)
            self._renderers[scene] = SceneRenderer(read_scene(scene_dir), intrinsics=intrinsics)
        frames = render_keyframes(self._renderers[scene], trajectory, self._camera, count)
        gap = np.full((KEYFRAME_SIZE[1], 2, 3), 255, dtype=np.uint8)
        row = np.concatenate([part for frame in frames for part in (frame, gap)][:-1], axis=1)
        buffer = io.BytesIO()
        Image.fromarray(row).save(buffer, format="JPEG", quality=80)
        return "data:image/jpeg;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


def _split_of(dataset: Dataset, scene_ids: set[str]) -> list[str]:
    return sorted(s for s, scenes in dataset.manifest.splits.items() if scene_ids & set(scenes))


def _scene_figures(
    rows: Sequence[Mapping[str, object]],
    episodes: Mapping[str, Episode],
    submission: Submission,
    *,
    robot: Robot,
    scene_dir: Path | None,
) -> dict[str, str]:
    """The top-down pictures (PNG data URIs) of one scene's episodes, ``{episode id: picture}``, over
    the scene's backdrop (its fields are in memory only while they are drawn)."""
    backdrop = Backdrop(scene_dir) if scene_dir is not None else None
    figures = {}
    for row in rows:
        episode_id, label = str(row["episode_id"]), str(row["label"])
        episode, record = episodes[episode_id], submission.records[episode_id]
        heading = (f"{episode_id}\n{label_name(label)} · SR {_value(row, 'success')} · "
                   f"SPL {_value(row, 'spl')}")  # fmt: skip
        fig = episode_figure(episode, record.trajectory, label=label, title=heading,
                             success_radius=robot.success_distance(episode.scene_type),
                             backdrop=backdrop)  # fmt: skip
        figures[episode_id] = png_data_uri(fig, colors=THUMB_COLORS)
    return figures


def _episode_pictures(
    result: EvalResult,
    episodes: Mapping[str, Episode],
    submission: Submission,
    scene_dirs: Mapping[str, Path],
    *,
    robot: Robot,
    embodiment: str,
    keyframes: int,
    progress: Callable[[int, int], None] | None,
) -> dict[str, tuple[str | None, str | None]]:
    """The top-down picture and the keyframe strip (data URIs) of every episode with a trajectory to
    draw, ``{episode id: (picture, strip)}``, drawn scene by scene: a scene's pictures over its fields,
    then its strips with its renderer, so that one scene's fields or its renderer are in memory at a
    time, and memory grows with the submission, not with the scenes."""
    by_scene: dict[str, list[Mapping[str, object]]] = {}
    drawn, total = 0, len(result.episodes)
    for row in result.episodes:
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
        figures = _scene_figures(rows, episodes, submission, robot=robot, scene_dir=scene_dir)
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
    pictures = _episode_pictures(
        result, episodes, submission, scene_dirs, robot=robot, embodiment=embodiment, keyframes=keyframes,
        progress=progress,
    )  # fmt: skip
    groups: dict[str, list[str]] = {}
    order = [*CARD_ORDER, *sorted({str(r["label"]) for r in result.episodes} - set(CARD_ORDER))]
    for label in order:
        rows = sorted((r for r in result.episodes if r["label"] == label), key=lambda r: str(r["episode_id"]))
        cards = []
        for row in rows:
            episode_id = str(row["episode_id"])
            picture, strip = pictures.get(episode_id, (None, None))
            cards.append(_card_html(row, picture, problems_of.get(episode_id, []), strip=strip))
        if cards:
            color = label_color(label)
            groups[label] = [
                f'<h3 id="label-{_e(label)}"><span class="swatch" style="background:{color}"></span>'
                f"{_e(label_name(label))} ({len(cards)})</h3>",
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
    nav = "".join(f'<a href="#label-{_e(label)}">{_e(label_name(label))}</a>' for label in groups)
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
            _glossary_html(list(dict.fromkeys([*_headline_names(result), *shown_columns(result)]))),
            _scored_html(result),
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
