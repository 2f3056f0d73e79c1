"""report.html from a real scoring of a tiny synthetic dataset, and its headless-Chromium screenshot."""

from __future__ import annotations

import base64
import dataclasses
import html
import io
import itertools
import json
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from navverse.dataset import (
    Dataset,
    Episode,
)
from navverse.eval import figures, screenshot
from navverse.eval.metrics import METRICS, STATISTICS
from navverse.eval.report import HEADLINE, PictureBackdrops, write_report
from navverse.eval.scoring import EvalResult, labelled_episodes, score
from navverse.eval.screenshot import ScreenshotError, find_browser, screenshot_report
from navverse.eval.submission import Submission, read_submission
from navverse.eval.tables import HEADERS, TABLES, table_rows
from navverse.scene.directory import write_scene_dir
from tests.navverse.eval.toy_dataset import write_toy_dataset
from tests.navverse.scene.conftest import build_scene

REPO = Path(__file__).resolve().parents[3]
LEVEL = [0.0, 0.0, 0.0, 1.0]
TILTED = [math.sin(math.radians(30)), 0.0, 0.0, math.cos(math.radians(30))]  # 60 degrees about x
CHAIR = {
    "object_id": 1,
    "category": "chair",
    "position": (3.0, 5.0, 0.45),
    "radius": 0.25,
    "size": (0.5, 0.5, 0.9),
}
TABLE = {
    "object_id": 3,
    "category": "table",
    "position": (7.0, 5.0, 0.375),
    "radius": 0.6,
    "size": (1.2, 0.8, 0.75),
}


def _episode(episode_id: str, scene: str, scene_type: str, task: str, goal: dict, path: list) -> Episode:
    return Episode.model_validate(
        {
            "episode_id": episode_id,
            "scene_id": scene,
            "scene_type": scene_type,
            "task": task,
            "start_position": path[0],
            "start_rotation": LEVEL,
            "object_category": goal["category"],
            "goals": [goal],
            "reference_path": path,
            "info": {
                "geodesic_distance": sum(itertools.starmap(math.dist, itertools.pairwise(path))),
                "euclidean_distance": math.dist(path[0], path[-1]),
                "closest_goal_object_id": goal["object_id"],
                "success_distance": 1.6,
                "difficulty": "easy",
            },
        }
    )


def _rows(points: list, quats: list | None = None) -> list[list[float]]:
    quats = quats or [LEVEL] * len(points)
    return [[float(i), *p, *q] for i, (p, q) in enumerate(zip(points, quats, strict=True))]


# Episodes in the tiny room of tests/navverse/scene (floor 0..10 x 0..8 m); "tiny_room_b" is the same
# scene under another id, so the result has two scene types.
TO_TABLE = [(8.0, 2.0, 0.55), (8.0, 3.5, 0.55), (7.0, 4.2, 0.55)]
TO_CHAIR = [(8.0, 2.0, 0.55), (6.0, 3.0, 0.55), (3.8, 4.3, 0.55)]
EPISODES = [
    # (id, scene, scene type, task, goal, reference path, submitted points or None, stop, quaternions)
    ("room-objnav-0000", "tiny_room", "i2o", "objnav", TABLE, TO_TABLE, TO_TABLE, True, None),
    ("room-objnav-0001", "tiny_room", "i2o", "objnav", CHAIR, TO_CHAIR, [(8.0, 2.0, 0.55), (9.0, 2.0, 0.55)],
     True, None),
    ("room-vln-0000", "tiny_room", "i2o", "vln", CHAIR, TO_CHAIR, TO_CHAIR[:2], False, None),
    ("room-objnav-0002", "tiny_room_b", "indoor", "objnav", TABLE, TO_TABLE, TO_TABLE, True,
     [LEVEL, TILTED, LEVEL]),
    ("room-objnav-0003", "tiny_room_b", "indoor", "objnav", CHAIR, TO_CHAIR, None, True, None),  # missing
    ("room-vln-0001", "tiny_room_b", "indoor", "vln", TABLE, TO_TABLE, TO_TABLE, True, "nan"),
]  # fmt: skip
LABELS = {"room-objnav-0000": "success", "room-objnav-0001": "wrong_goal", "room-vln-0000": "timeout",
          "room-objnav-0002": "fall", "room-objnav-0003": "invalid", "room-vln-0001": "invalid"}  # fmt: skip


def _dataset(root: Path) -> Dataset:
    return write_toy_dataset(
        root, [_episode(*spec[:6]) for spec in EPISODES], thresholds={"objnav": [4.0, 8.0], "vln": [3.5, 7.5]}
    )


def _submission(path: Path, ids: list[str]) -> Submission:
    lines = []
    for episode_id, *_, points, stop, quats in EPISODES:
        if points is None:
            continue
        rows = _rows(points, None if quats == "nan" else quats)
        if quats == "nan":
            rows[1][2] = float("nan")
        lines.append(json.dumps({"episode_id": episode_id, "trajectory": rows, "stop": stop}))
    path.write_text("\n".join(lines) + "\n")
    return read_submission(path, episode_ids=ids)


@pytest.fixture(scope="module")
def scored(tmp_path_factory: pytest.TempPathFactory) -> tuple[EvalResult, Dataset, Submission, dict, Path]:
    root = tmp_path_factory.mktemp("report")
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("NAVVERSE_CACHE_DIR", str(root / "cache"))
        scene_dir = root / "scenes" / "tiny_room"
        scene_dir.mkdir(parents=True)
        write_scene_dir(build_scene(), scene_dir, bev=False)
        scene_dirs = {"tiny_room": scene_dir, "tiny_room_b": scene_dir}
        dataset = _dataset(root / "toy" / "v1.0")
        submission = _submission(root / "toy.jsonl", [spec[0] for spec in EPISODES])
        result = score(dataset, submission, split="eval", scene_dirs=scene_dirs)
        out = write_report(
            result, dataset=dataset, submission=submission, scene_dirs=scene_dirs, out_dir=root / "out"
        )
    return result, dataset, submission, scene_dirs, out


def test_the_scoring_gives_every_label(scored):
    result = scored[0]
    assert {row["episode_id"]: row["label"] for row in result.episodes} == LABELS


def test_the_report_holds_the_header_tables_and_one_card_per_episode(scored):
    result, *_, out = scored
    assert out.name == "report.html" and sorted(p.name for p in out.parent.iterdir()) == ["report.html"]
    text = out.read_text(encoding="utf-8")
    assert text.startswith("<!DOCTYPE html>") and "</html>" in text
    for fact in ("toy v1.0", "eval", "spot", "toy.jsonl", "<dt>episodes</dt><dd>6</dd>", "<dd>2 (no valid"):
        assert fact in text, fact
    shown = [name for name, (grouping, _) in TABLES.items() if result.groups.get(grouping)]
    assert {"task_scene", "safety_efficiency", "failures", "difficulty"} <= set(shown)
    assert re.findall(r'<section id="table-([^"]+)">', text) == shown  # every table there is, in order
    for name in shown:
        header, _ = table_rows(result, name)
        for cell in header:
            assert re.search(rf'<th( title="[^"]+")?>{re.escape(html.escape(cell))}</th>', text), (name, cell)
    assert "objnav: easy &lt; 4.00 m" in text  # the difficulty thresholds
    assert "Submission problems (1)" in text and "holds NaN or infinity" in text
    assert '<p class="chosen">Every episode has a card (a report draws at most 60:' in text
    # One card per episode, failures first; the invalid ones say why, without a picture.
    cards = re.findall(r'<div class="card" id="ep-([^"]+)" data-label="([^"]+)"', text)
    assert sorted(cards) == sorted(LABELS.items())
    assert [label for _, label in cards] == ["invalid", "invalid", "fall", "timeout", "wrong_goal", "success"]
    missing = text[text.index('id="ep-room-objnav-0003"') :].split('<div class="card"')[0]
    assert "no record in the submission" in missing and "<img" not in missing
    broken = text[text.index('id="ep-room-vln-0001"') :].split('<div class="card"')[0]
    assert "holds NaN" in broken and "<img" not in broken


def _between(text: str, start: str, end: str) -> str:
    return text[text.index(start) : text.index(end, text.index(start))]


def test_every_headline_card_names_its_metric_in_full_with_its_n(scored):
    result, *_, out = scored
    text = out.read_text(encoding="utf-8")
    tiles = re.findall(
        r'<div class="tile" id="headline-([^"]+)" title="([^"]+)"><div class="v">([^<]+)</div>'
        r'<div class="k">([^<]+)</div><div class="t">([^<]+)</div><div class="n">n = (\d+)</div></div>',
        text,
    )
    overall = result.groups["overall"]["all"]
    assert [t[0] for t in tiles] == [n for n in HEADLINE if overall.get(n) is not None]
    assert {"success", "ne", "ndtw"} <= {t[0] for t in tiles}
    for name, tip, _, column, title, n in tiles:
        spec = METRICS[name]
        assert (html.unescape(tip), column, html.unescape(title)) == (
            f"{spec.title}: {spec.description}", HEADERS[name], spec.title)  # fmt: skip
        assert int(n) == overall[f"{name}_n"], name
    n_of = {t[0]: int(t[5]) for t in tiles}
    # SR is over all 6 episodes; NE needs a valid trajectory (4); nDTW is over the one valid VLN episode.
    assert (n_of["success"], n_of["ne"], n_of["ndtw"]) == (6, 4, 1)
    # So is a table cell over fewer episodes than its row's: the "all" row of the task / scene table.
    task_scene = _between(text, 'id="table-task_scene"', "</section>")
    assert "<td>all</td><td>6</td><td>16.7</td>" in task_scene and "<td>2.81 (n=4)</td>" in task_scene


def test_every_metric_the_report_shows_is_defined_in_its_glossary(scored):
    text = scored[4].read_text(encoding="utf-8")
    glossary = _between(text, '<h2 id="metrics">', "</table>")
    rows = re.findall(r"<tr><td>([^<]+)</td><td>([^<]+)</td><td>([^<]+)</td><td>(higher|lower)</td>"
                      r"<td>([^<]+)</td></tr>", glossary)  # fmt: skip
    defined = {html.unescape(column): (key, html.unescape(title), html.unescape(what))
               for column, title, what, _, key in rows}  # fmt: skip
    tiles = re.findall(r'<div class="k">([^<]+)</div>', text)
    headers = {
        html.unescape(h)
        for section in re.findall(r'<section id="table-[^"]+">.*?</section>', text)
        for h in re.findall(r"<th[^>]*>([^<]+)</th>", section)[2:]  # after the group and its n
    }
    assert len(tiles) == 11 and len(headers) == 22
    assert set(defined) == {html.unescape(t) for t in tiles} | headers  # everything shown, nothing else
    for column, (key, title, what) in defined.items():
        spec = METRICS.get(key) or STATISTICS[key]
        assert (column, title, what) == (HEADERS[key], spec.title, spec.description)
    assert defined["ADO (m)"][1] == "Average Distance to Obstacles"
    assert defined["OS (%)"][1] == "Oracle Success"


def test_the_report_lists_the_scored_episode_ids(scored):
    text = scored[4].read_text(encoding="utf-8")
    listed = _between(text, '<details class="scored">', "</details>")
    groups = re.findall(r"<h4>([^<]+)</h4><p class=\"ids\">(.*?)</p>", listed)
    ids = {title: re.findall(r'<a href="#ep-([^"]+)">\1</a>', body) for title, body in groups}
    invalid = ids.pop("without a valid record, scored as failures (2)")
    assert sorted(i for group in ids.values() for i in group) == sorted(LABELS)  # each once
    assert ids["objnav / indoor (2)"] == ["room-objnav-0002", "room-objnav-0003"]
    assert invalid == [e for e, label in sorted(LABELS.items()) if label == "invalid"]
    assert all(f'id="ep-{e}"' in text for e in LABELS)  # the links lead to the cards


def test_the_report_is_self_contained(scored):
    text = scored[4].read_text(encoding="utf-8")
    assert not re.search(r"""(src|href)\s*=\s*["']?\s*(https?:)?//""", text, re.IGNORECASE)
    assert "url(" not in text and "@import" not in text and "<script" not in text
    assert all(
        src.startswith(("data:image/png;base64,", "data:image/jpeg;base64,"))
        for src in re.findall(r'src="([^"]*)"', text)
    )
    pictures = re.findall(r"data:image/png;base64,([A-Za-z0-9+/=]+)", text)
    assert len(pictures) == 1 + 4  # the summary and one per episode with a trajectory
    for encoded in pictures:
        data = base64.b64decode(encoded, validate=True)
        assert data[:8] == b"\x89PNG\r\n\x1a\n"
        image = Image.open(io.BytesIO(data))
        image.verify()
    thumbnail = Image.open(io.BytesIO(base64.b64decode(pictures[-1])))
    assert thumbnail.size == figures.THUMB_SIZE_PX


def test_rewriting_replaces_the_report_atomically(scored, tmp_path: Path):
    result, dataset, submission, scene_dirs, _ = scored
    target = tmp_path / "new" / "deeper"
    first = write_report(
        result, dataset=dataset, submission=submission, scene_dirs=scene_dirs, out_dir=target, title="Run <1>"
    )
    calls = []
    second = write_report(
        result, dataset=dataset, submission=submission, scene_dirs=scene_dirs, out_dir=target,
        progress=lambda done, total: calls.append((done, total)),
    )  # fmt: skip
    assert calls == [(i, 6) for i in range(7)]  # every episode has a card: none drawn, then each
    assert first == second and [p.name for p in target.iterdir()] == ["report.html"]
    assert "Evaluation of toy.jsonl" in second.read_text() and "Run &lt;1&gt;" not in second.read_text()


def test_a_table_whose_grouping_is_absent_is_left_out(scored, tmp_path: Path):
    result, dataset, submission, scene_dirs, _ = scored
    groups = {k: v for k, v in result.groups.items() if k != "task_difficulty"}
    fewer = dataclasses.replace(result, groups=groups)
    text = write_report(
        fewer, dataset=dataset, submission=submission, scene_dirs=scene_dirs, out_dir=tmp_path
    ).read_text()
    assert 'id="table-difficulty"' not in text and 'id="table-task_scene"' in text


# ---------------------------------------------------------------------------------------------- screenshots

needs_chromium = pytest.mark.skipif(
    find_browser() is None,
    reason="no chromium, chromium-browser or google-chrome on PATH (scripts/system-deps.sh installs it)",
)


@needs_chromium
def test_chromium_renders_the_report_without_console_errors(scored, tmp_path: Path):
    png = tmp_path / "shot.png"
    errors = screenshot_report(scored[4], png, width=1000, height=1600)
    assert errors == []
    with Image.open(png) as image:
        assert image.size == (1000, 1600)
        assert len(image.convert("RGB").getcolors(1 << 20) or []) > 50  # a rendered page, not a blank one


@needs_chromium
def test_the_screenshot_script_fails_on_a_page_with_errors(tmp_path: Path):
    page = tmp_path / "broken.html"
    page.write_text("<!DOCTYPE html><html><body><p>x</p><script>notDefined();</script></body></html>")
    run = subprocess.run(
        [sys.executable, str(REPO / "scripts" / "report_screenshot.py"), str(page),
         "-o", str(tmp_path / "b.png"), "--width", "400", "--height", "300"],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert run.returncode == 1 and "1 console errors" in run.stderr and "notDefined" in run.stderr
    assert (tmp_path / "b.png").is_file()


def test_a_missing_browser_is_a_clear_error(scored, tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    monkeypatch.setattr(screenshot, "find_browser", lambda: None)
    with pytest.raises(ScreenshotError, match="no headless browser found on PATH"):
        screenshot_report(scored[4], tmp_path / "x.png")
    with pytest.raises(ScreenshotError, match="cannot run the browser"):
        screenshot_report(scored[4], tmp_path / "x.png", browser=str(tmp_path / "no-such-browser"))


def test_every_card_with_a_trajectory_has_a_first_person_keyframe_strip(scored):
    import base64
    import io

    from PIL import Image

    from navverse.eval.report import KEYFRAME_SIZE, KEYFRAMES

    text = scored[4].read_text(encoding="utf-8")
    pattern = r'<img class="strip" src="data:image/jpeg;base64,([^"]+)" alt="([^"]+): keyframes"'
    found = {episode: data for data, episode in re.findall(pattern, text)}
    assert set(found) == {e for e, label in LABELS.items() if label != "invalid"}
    image = np.asarray(Image.open(io.BytesIO(base64.b64decode(found["room-objnav-0000"]))))
    width, height = KEYFRAME_SIZE
    assert image.shape == (height, KEYFRAMES * width + 2 * (KEYFRAMES - 1), 3)
    first, last = image[:, :width].astype(int), image[:, -width:].astype(int)
    assert first.std() > 5 and np.abs(first - last).mean() > 3  # a room seen, and seen change as it moves


def test_a_scene_s_fields_and_its_renderer_are_never_in_memory_together(
    scored, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
):
    import weakref

    from navverse.eval import report

    result, dataset, submission, scene_dirs, out = scored
    monkeypatch.setenv("NAVVERSE_CACHE_DIR", str(out.parent.parent / "cache"))
    backdrops: weakref.WeakSet = weakref.WeakSet()
    live_at_strips: list[int] = []

    class Tracked(report.Backdrop):
        def __init__(self, scene_dir: Path) -> None:
            super().__init__(scene_dir)
            backdrops.add(self)

    strip = report._KeyframeStrips.strip

    def tracked_strip(self, *args, **kwargs):
        live_at_strips.append(len(backdrops))
        return strip(self, *args, **kwargs)

    monkeypatch.setattr(report, "Backdrop", Tracked)
    monkeypatch.setattr(report._KeyframeStrips, "strip", tracked_strip)
    again = write_report(
        result, dataset=dataset, submission=submission, scene_dirs=scene_dirs, out_dir=tmp_path
    )
    assert len(live_at_strips) == 4 and not any(live_at_strips)  # four cards have a trajectory
    assert again.read_bytes() == out.read_bytes()


# ------------------------------------------------------------------------------------------ pictured cards


def _cards_and_rows(text: str) -> tuple[list[str], list[str]]:
    cards = re.findall(r'<div class="card" id="ep-([^"]+)"', text)
    rows = re.findall(r'<tr id="ep-([^"]+)">', text)
    return cards, rows


def _card(text: str, episode_id: str) -> str:
    """The HTML of an episode's card: its pictures, up to the end of its caption."""
    start = text.index(f'<div class="card" id="ep-{episode_id}"')
    end = text.index("</div></div>", text.index('<div class="cap">', start))
    return text[start:end]


def test_a_report_draws_at_most_pictures_cards_and_lists_every_other_episode_as_a_row(scored, tmp_path: Path):
    result, dataset, submission, scene_dirs, out = scored
    calls = []
    text = write_report(
        result, dataset=dataset, submission=submission, scene_dirs=scene_dirs, out_dir=tmp_path, pictures=3,
        progress=lambda done, total: calls.append((done, total)),
    ).read_text(encoding="utf-8")  # fmt: skip
    assert calls == [(i, 3) for i in range(4)]
    cards, rows = _cards_and_rows(text)
    # The labels of the episodes with a trajectory take turns, failures first: the fall, the timeout,
    # the wrong goal; the success and the episodes without a valid record are rows.
    assert cards == ["room-objnav-0002", "room-vln-0000", "room-objnav-0001"]
    assert sorted(rows) == ["room-objnav-0000", "room-objnav-0003", "room-vln-0001"]
    assert sorted(cards + rows) == sorted(LABELS)  # each once: every link of the scored ids leads somewhere
    assert "3 of the 6 episodes have a card (a report draws at most 3:" in text
    assert "the termination labels take turns (fall, timeout, wrong goal, success)" in text
    # Under its label's heading, a row holds what a card's caption shows; an invalid one, its problem.
    success = _between(text, 'id="label-success"', "</table>")
    assert "success (1)" in success and '<tr id="ep-room-objnav-0000"><td>room-objnav-0000</td>' in success
    assert "<td>objnav</td><td>tiny_room</td><td>i2o</td><td>easy</td><td>100.0</td>" in success
    invalid = _between(text, 'id="label-invalid"', "</table>")
    assert "invalid (2)" in invalid and '<div class="card"' not in invalid
    assert '<td class="why">no record in the submission</td>' in invalid
    assert '<td class="why">line 5 (room-vln-0001): trajectory row 1 holds NaN or infinity' in invalid
    glossary = _between(text, '<h2 id="metrics">', "</table>")
    for column in ("SR (%)", "SPL (%)", "NE (m)", "P (m)"):  # the rows' columns are defined
        assert f"<td>{html.escape(column)}</td>" in glossary, column
    # The pictured cards are those of the report that pictures every episode.
    full = out.read_text(encoding="utf-8")
    for episode_id in cards:
        assert _card(text, episode_id) == _card(full, episode_id)
    assert len(re.findall(r"data:image/png;base64,", text)) == 1 + 3  # the summary and the three cards


def test_a_report_without_cards_lists_every_episode(scored, tmp_path: Path):
    result, dataset, submission, scene_dirs, _ = scored
    text = write_report(
        result, dataset=dataset, submission=submission, scene_dirs=scene_dirs, out_dir=tmp_path, pictures=0
    ).read_text(encoding="utf-8")
    cards, rows = _cards_and_rows(text)
    assert cards == [] and sorted(rows) == sorted(LABELS) and "0 of the 6 episodes have a card" in text
    with pytest.raises(ValueError, match="pictures must be 0 or more"):
        write_report(result, dataset=dataset, submission=submission, scene_dirs=scene_dirs, out_dir=tmp_path,
                     pictures=-1)  # fmt: skip


def test_the_scoring_s_fields_serve_the_report_s_pictures(
    scored, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
):
    from navverse.eval import figures, scoring

    _, dataset, submission, scene_dirs, out = scored
    monkeypatch.setenv("NAVVERSE_CACHE_DIR", str(out.parent.parent / "cache"))
    loads: list[str] = []
    for module in (scoring, figures):
        load = module.load_scene_fields
        monkeypatch.setattr(module, "load_scene_fields", lambda d, load=load: loads.append(str(d)) or load(d))
    backdrops = PictureBackdrops(dataset, submission, split="eval", scene_dirs=scene_dirs)
    again = score(dataset, submission, split="eval", scene_dirs=scene_dirs, on_fields=backdrops.take)
    assert len(loads) == 2  # once per scene with a valid record, by the scoring
    assert sorted(backdrops.crops) == sorted(e for e, label in LABELS.items() if label != "invalid")
    page = write_report(
        again, dataset=dataset, submission=submission, scene_dirs=scene_dirs, out_dir=tmp_path,
        backdrops=backdrops,
    )  # fmt: skip
    assert len(loads) == 2  # and never again by the report
    assert page.read_bytes() == out.read_bytes()  # the same pictures as over the fields themselves


def test_backdrops_cut_for_another_robot_are_not_used(
    scored, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
):
    # The turtlebot's success circles are smaller: its pictures' limits, and crops, differ from spot's.
    _, dataset, submission, scene_dirs, out = scored
    monkeypatch.setenv("NAVVERSE_CACHE_DIR", str(out.parent.parent / "cache"))
    backdrops = PictureBackdrops(
        dataset, submission, split="eval", scene_dirs=scene_dirs, embodiment="turtlebot"
    )
    result = score(dataset, submission, split="eval", scene_dirs=scene_dirs, on_fields=backdrops.take)
    assert backdrops.embodiment == "turtlebot" and len(backdrops.crops) == 4
    page = write_report(
        result,
        dataset=dataset,
        submission=submission,
        scene_dirs=scene_dirs,
        out_dir=tmp_path,
        backdrops=backdrops,
    )  # spot's report, over the scenes' fields
    assert page.read_bytes() == out.read_bytes()


def test_the_labels_known_before_scoring_are_the_scored_ones(scored, monkeypatch: pytest.MonkeyPatch):
    _, dataset, submission, scene_dirs, out = scored
    monkeypatch.setenv("NAVVERSE_CACHE_DIR", str(out.parent.parent / "cache"))
    keys = ("episode_id", "scene_id", "task", "scene_type", "difficulty", "label")
    for which in ("all", "submitted"):
        again = score(dataset, submission, split="eval", scene_dirs=scene_dirs, episodes=which)
        early = labelled_episodes(dataset, submission, split="eval", episodes=which)
        assert early == [{k: row[k] for k in keys} for row in again.episodes]
        assert len(early) == (6 if which == "all" else 5)  # one episode has no line
    assert {row["label"] for row in early} == set(LABELS.values())  # every label
