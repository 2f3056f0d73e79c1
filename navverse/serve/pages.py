"""The server's HTML pages: the leaderboard and a public submission's tables.

Each page is self-contained: one inline style sheet and one inline script (the same on every page,
allowed by their SHA-256 in :data:`CONTENT_SECURITY_POLICY`, so that nothing else runs), no external
asset, font or CDN. Everything that comes from a user (team and submission names) or the database is
escaped. The script sorts a table by the column whose header is clicked (numbers by value, an
undefined value last) and shows the leaderboard rows of the task and scene type chosen in its filters.
"""

from __future__ import annotations

import base64
import hashlib
from collections.abc import Iterable, Mapping, Sequence
from html import escape
from typing import Any

__all__ = [
    "BOARD_COLUMNS",
    "CONTENT_SECURITY_POLICY",
    "PAGE_COLUMNS",
    "leaderboard_page",
    "not_found_page",
    "submission_page",
]

BOARD_COLUMNS = ("success", "spl", "soft_spl", "os", "ne")
"""The metrics of the leaderboard (the paper's main table: SR, SPL, SoftSPL, OS, NE)."""
PAGE_COLUMNS = (*BOARD_COLUMNS, "cr", "ado", "nsr", "ce", "wrong_goal_share", "fall_share", "timeout_share",
                "invalid_share")  # fmt: skip
"""The metrics and statistics of a submission's page."""
_GROUPINGS = (("overall", "overall"), ("task", "per task"), ("scene_type", "per scene type"),
              ("task_scene_type", "per task and scene type"))  # fmt: skip

_STYLE = """
body { font: 14px/1.45 system-ui, sans-serif; margin: 1.5rem auto; max-width: 80rem; padding: 0 1rem;
       color: #1d2433; }
h1 { font-size: 1.4rem; } h2 { font-size: 1.1rem; margin-top: 1.6rem; }
table { border-collapse: collapse; margin: .6rem 0; }
th, td { padding: .3rem .6rem; border-bottom: 1px solid #d8dde6; text-align: right; white-space: nowrap; }
th { background: #f2f4f8; cursor: pointer; user-select: none; }
th[aria-sort=ascending]::after { content: " \\25B2"; } th[aria-sort=descending]::after { content: " \\25BC"; }
td.text, th.text { text-align: left; }
dl { display: grid; grid-template-columns: max-content auto; gap: .2rem 1.2rem; } dd { margin: 0; }
dt { color: #5b6577; } .wide { overflow-x: auto; }
nav a { margin-right: .8rem; } .muted { color: #5b6577; } .filters label { margin-right: 1.2rem; }
"""
_SCRIPT = """
(function () {
  function value(cell) {
    var v = cell.getAttribute("data-value");
    return v === null ? cell.textContent.trim().toLowerCase() : v;
  }
  function compare(a, b, numeric) {
    if (!numeric) { return a < b ? -1 : a > b ? 1 : 0; }
    if (a === "" || b === "") { return a === b ? 0 : a === "" ? 1 : -1; }
    return parseFloat(a) - parseFloat(b);
  }
  document.querySelectorAll("table.sortable").forEach(function (table) {
    var heads = Array.prototype.slice.call(table.tHead.rows[0].cells);
    heads.forEach(function (head, index) {
      head.addEventListener("click", function () {
        var descending = head.getAttribute("aria-sort") !== "descending";
        heads.forEach(function (other) { other.removeAttribute("aria-sort"); });
        head.setAttribute("aria-sort", descending ? "descending" : "ascending");
        var numeric = head.getAttribute("data-kind") === "number";
        var body = table.tBodies[0];
        var rows = Array.prototype.slice.call(body.rows);
        rows.sort(function (r, s) {
          var a = value(r.cells[index]), b = value(s.cells[index]);
          if (numeric && (a === "" || b === "")) { return compare(a, b, true); }
          var order = compare(a, b, numeric);
          return descending ? -order : order;
        });
        rows.forEach(function (row) { body.appendChild(row); });
      });
    });
    table.setAttribute("data-sortable", "ready");
  });
  var board = document.getElementById("board");
  var task = document.getElementById("task"), scene = document.getElementById("scene");
  if (board && task && scene) {
    var filter = function () {
      var shown = 0;
      Array.prototype.forEach.call(board.tBodies[0].rows, function (row) {
        var on = row.getAttribute("data-task") === task.value &&
          row.getAttribute("data-scene") === scene.value;
        row.hidden = !on;
        if (on) { shown += 1; }
      });
      document.getElementById("empty").hidden = shown > 0;
      board.setAttribute("data-shown", String(shown));
    };
    task.addEventListener("change", filter);
    scene.addEventListener("change", filter);
    filter();
  }
})();
"""


def _digest(text: str) -> str:
    return "sha256-" + base64.b64encode(hashlib.sha256(text.encode("utf-8")).digest()).decode("ascii")


CONTENT_SECURITY_POLICY = (
    f"default-src 'none'; script-src '{_digest(_SCRIPT)}'; style-src '{_digest(_STYLE)}'; img-src 'none'; "
    "base-uri 'none'; form-action 'none'; frame-ancestors 'none'"
)
"""The pages' Content-Security-Policy: their own inline style and script, nothing else."""


def _page(title: str, body: str) -> str:
    return (
        '<!doctype html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
        f"<title>{escape(title)}</title>\n<style>{_STYLE}</style>\n</head>\n<body>\n{body}\n"
        f"<script>{_SCRIPT}</script>\n</body>\n</html>\n"
    )


def _columns(names: Sequence[str]) -> list[dict[str, str]]:
    from navverse.eval.tables import glossary

    return glossary(names)


def _head(column: Mapping[str, str]) -> str:
    tip = f"{column['title']}: {column['description']} ({column['better']} is better)"
    return f'<th data-kind="number" title="{escape(tip)}">{escape(column["column"])}</th>'


def _cell(name: str, entry: Mapping[str, Any]) -> str:
    """A metric's cell: its value as the evaluator's tables show it, with its own N when it is defined on
    fewer episodes than the row's; sorted by the value itself."""
    from navverse.eval.tables import cell_text

    value = entry.get(name)
    text = cell_text(name, value)
    n = entry.get(f"{name}_n")
    if value is not None and n is not None and n != entry.get("episodes"):
        text = f"{text} (n={n})"
    shown = "" if value is None else repr(float(value))
    return f'<td data-value="{escape(shown)}">{escape(text)}</td>'


def _split_nav(splits: Iterable[str], current: str) -> str:
    links = []
    for split in splits:
        label = escape(split)
        links.append(
            f"<strong>{label}</strong>"
            if split == current
            else f'<a href="/?split={escape(split)}">{label}</a>'
        )
    return f"<nav>split: {' '.join(links)}</nav>"


def _groups(metrics: Mapping[str, Any]) -> Iterable[tuple[str, str, Mapping[str, Any]]]:
    """(task, scene type, entry) of every published group: ``all`` stands for every task or scene type."""
    for entry in metrics.get("overall", {}).values():
        yield "all", "all", entry
    for task, entry in metrics.get("task", {}).items():
        yield task, "all", entry
    for scene, entry in metrics.get("scene_type", {}).items():
        yield "all", scene, entry
    for key, entry in metrics.get("task_scene_type", {}).items():
        task, _, scene = key.partition("/")
        yield task, scene, entry


def _options(select_id: str, label: str, values: Iterable[str]) -> str:
    options = ['<option value="all" selected>all</option>']
    options += [f'<option value="{escape(v)}">{escape(v)}</option>' for v in sorted(set(values) - {"all"})]
    return f'<label>{escape(label)} <select id="{select_id}">{"".join(options)}</select></label>'


def leaderboard_page(
    *, dataset: str, split: str, splits: Sequence[str], entries: Sequence[Mapping[str, Any]]
) -> str:
    """The leaderboard of `split` as a page.

    Parameters
    ----------
    dataset : str
        The dataset's name and version, for the title.
    split : str
        The split shown.
    splits : sequence of str
        The splits with a leaderboard (links).
    entries : sequence of dict
        :func:`navverse.serve.leaderboard.best_entries`.
    """
    columns = _columns(BOARD_COLUMNS)
    heads = [
        '<th data-kind="number">#</th>', '<th class="text">team</th>', '<th class="text">submission</th>',
        '<th class="text">track</th>', '<th class="text">instruction</th>', '<th class="text">task</th>',
        '<th class="text">scene type</th>', '<th data-kind="number">episodes</th>',
        *(_head(c) for c in columns),
    ]  # fmt: skip
    rows, tasks, scenes = [], set(), set()
    for entry in entries:
        link = f'<a href="/submissions/{escape(entry["id"])}">{escape(entry["name"])}</a>'
        for task, scene, group in _groups(entry.get("metrics", {})):
            tasks.add(task)
            scenes.add(scene)
            cells = [
                f'<td data-value="{int(entry["rank"])}">{int(entry["rank"])}</td>',
                f'<td class="text">{escape(entry["team"])}</td>', f'<td class="text">{link}</td>',
                f'<td class="text">{escape(entry["track_text"])}</td>',
                f'<td class="text">{escape(entry["instruction_type"] or "–")}</td>',
                f'<td class="text">{escape(task)}</td>', f'<td class="text">{escape(scene)}</td>',
                f'<td data-value="{int(group.get("episodes", 0))}">{int(group.get("episodes", 0))}</td>',
                *(_cell(c["name"], group) for c in columns),
            ]  # fmt: skip
            rows.append(f'<tr data-task="{escape(task)}" data-scene="{escape(scene)}">{"".join(cells)}</tr>')
    empty = "No scored public submission yet." if not entries else "No row matches the filters."
    body = [
        f"<h1>{escape(dataset)}: leaderboard of split {escape(split)}</h1>",
        _split_nav(splits, split),
        '<p class="muted">The best public submission of each team and track, ranked by overall SPL, then SR, '
        "then the earliest. Choose a task and scene type to see their means; click a column's header to "
        "sort by it. A value defined on fewer episodes than its row's shows its own n.</p>",
        f'<div class="filters">{_options("task", "task", tasks)}'
        f"{_options('scene', 'scene type', scenes)}</div>",
        f'<div class="wide"><table id="board" class="sortable"><thead><tr>{"".join(heads)}</tr></thead>',
        f"<tbody>{''.join(rows)}</tbody></table></div>",
        f'<p id="empty" class="muted"{"" if not entries else " hidden"}>{empty}</p>',
    ]
    return _page(f"{dataset} leaderboard: {split}", "\n".join(body))


def _table(title: str, groups: Mapping[str, Mapping[str, Any]], columns: Sequence[Mapping[str, str]]) -> str:
    heads = [
        '<th class="text">group</th>',
        '<th data-kind="number">episodes</th>',
        *(_head(c) for c in columns),
    ]
    rows = []
    for key, entry in groups.items():
        cells = [
            f'<td class="text">{escape(key)}</td>',
            f'<td data-value="{int(entry.get("episodes", 0))}">{int(entry.get("episodes", 0))}</td>',
            *(_cell(c["name"], entry) for c in columns),
        ]
        rows.append(f"<tr>{''.join(cells)}</tr>")
    return (
        f'<h2>{escape(title)}</h2>\n<div class="wide"><table class="sortable">'
        f"<thead><tr>{''.join(heads)}</tr></thead><tbody>{''.join(rows)}</tbody></table></div>"
    )


def submission_page(*, dataset: str, view: Mapping[str, Any]) -> str:
    """A public submission's page: what it is and, once scored, its tables of group means.

    Parameters
    ----------
    dataset : str
        The dataset's name and version.
    view : dict
        :func:`navverse.serve.leaderboard.submission_view` with ``team`` and ``track_text``.
    """
    facts = [
        ("team", view["team"]), ("split", view["split"]), ("track", view["track_text"]),
        ("instruction type", view["instruction_type"] or "–"), ("status", view["status"]),
        ("submitted", view["created"]), ("scored", view["scored"] or "–"),
    ]  # fmt: skip
    scope = view.get("scope") or {}
    if scope:
        facts.append(
            ("episodes", f"{scope.get('scored')} of the split's {scope.get('split_episodes')} scored, "
                         f"{scope.get('missing')} without a valid record (failures)")
        )  # fmt: skip
    body = [
        f'<h1>{escape(view["name"])} <span class="muted">by {escape(view["team"])}</span></h1>',
        f'<nav><a href="/?split={escape(view["split"])}">leaderboard of {escape(view["split"])}</a></nav>',
        "<dl>" + "".join(f"<dt>{escape(k)}</dt><dd>{escape(str(v))}</dd>" for k, v in facts) + "</dl>",
    ]
    metrics = view.get("metrics")
    if metrics:
        columns = _columns(PAGE_COLUMNS)
        for grouping, title in _GROUPINGS:
            if metrics.get(grouping):
                body.append(_table(f"Means {title}", metrics[grouping], columns))
        body.append(
            '<p class="muted">Means over the episodes where each metric is defined; a value defined on '
            "fewer episodes than its row's shows its own n. Hover a column's header for its definition.</p>"
        )
    return _page(f"{dataset}: {view['name']} by {view['team']}", "\n".join(body))


def not_found_page() -> str:
    """The page of an unknown (or private) submission."""
    return _page("not found", '<h1>Not found</h1>\n<p><a href="/">the leaderboard</a></p>')
