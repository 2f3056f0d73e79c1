"""The review page in headless Chromium: reject episodes, and the next build publishes a new minor version
without them while the reviewed version stays as it was; the decisions file's format and errors."""

from __future__ import annotations

import contextlib
import hashlib
import http.client
import io
import json
import threading
import urllib.request
from collections.abc import Iterator
from datetime import datetime, timedelta, timezone
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from navverse.dataset import Dataset, built_version, publish
from navverse.eval.screenshot import find_browser
from navverse.review.cli import open_review
from navverse.review.decisions import (
    REVIEW_SUFFIX,
    Review,
    ReviewError,
    published_version,
    read_review,
    review_bytes,
    with_decision,
)
from tests.navverse.review.browser import Browser
from tests.stages.conftest import DATASET, Built, build_all, copy_built

REVIEW = f"tiny{REVIEW_SUFFIX}"
AT = "2025-01-31T09:30:00+00:00"


def _digests(root: Path) -> dict[str, str]:
    return {
        str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(root.rglob("*"))
        if p.is_file()
    }


@pytest.fixture(scope="module")
def published(tiny_build: Built, tmp_path_factory: pytest.TempPathFactory) -> Built:
    """The apartment scenes and the tiny dataset built (a copy of the test process's
    :func:`~tests.conftest.tiny_build`), v1.0 published to the workspace's episodes/."""
    built = copy_built(tiny_build, tmp_path_factory.mktemp("review") / "ws")
    publish(built_version(built.output("tiny", "dataset")), built.workspace.root / "episodes")
    return built


@contextlib.contextmanager
def _serving(published: Built) -> Iterator[str]:
    """The review server of the newest published tiny version, running in a thread: its URL."""
    server = open_review(
        published.workspace.root / "episodes" / "tiny", built_dir=lambda: published.workspace.built_dir
    )
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()
        thread.join()


@pytest.fixture
def served(published: Built) -> Iterator[str]:
    """The review server of the newest published tiny version: its URL."""
    with _serving(published) as url:
        yield url


def _get(url: str) -> bytes:
    with urllib.request.urlopen(url, timeout=120) as response:
        return response.read()


def _post(url: str, body: dict, headers: dict[str, str] | None = None) -> tuple[int, dict]:
    host = url.removeprefix("http://")
    connection = http.client.HTTPConnection(host, timeout=30)
    data = json.dumps(body).encode()
    connection.request("POST", "/api/decision", data, {"Content-Type": "application/json", **(headers or {})})
    response = connection.getresponse()
    return response.status, json.loads(response.read())


def _reject_in_page(browser: Browser, episode_id: str, reason: str) -> str:
    card = f'article.card[data-episode="{episode_id}"]'
    browser.type_into(f"{card} input.reason", reason)
    browser.click(f'{card} button[data-action="reject"]')
    return browser.wait_for(
        f"(() => {{ const s = document.querySelector('{card} .status').textContent;"
        " return s.startsWith('rejected') || s.startsWith('not saved') ? s : ''; })()"
    )


def _show_split(browser: Browser, split: str) -> list[list[str]]:
    """Pick a split in the filter; the [id, meta] of the cards then shown."""
    browser.evaluate(
        f"(() => {{ const s = document.getElementById('split'); s.value = '{split}';"
        " s.dispatchEvent(new Event('change')); })()"
    )
    return browser.evaluate(
        "[...document.querySelectorAll('article.card')].map(c => [c.dataset.episode,"
        " c.querySelector('.meta').textContent])"
    )


def _pixels_of(image: np.ndarray, rgb: tuple[int, int, int], tolerance: int = 40) -> int:
    return int((np.abs(image[..., :3].astype(int) - rgb).max(axis=-1) <= tolerance).sum())


# ---------------------------------------------------------------------------------------------- the page


@pytest.mark.slow(seconds=35)
def test_rejecting_two_episodes_in_the_browser_publishes_a_new_minor_version_without_them(
    published: Built, served: str
):
    browser_path = find_browser()
    if browser_path is None:
        pytest.skip("no Chromium on PATH (apt-get install chromium)")
    root = published.workspace.root
    v10 = root / "episodes" / "tiny" / "v1.0"
    before = _digests(v10)
    dataset = Dataset(v10)
    by_id = {e.episode_id: e for e in dataset.episodes()}
    decisions_file = published.workspace.recipes_dir / "datasets" / REVIEW
    assert not decisions_file.exists()
    started = datetime.now(timezone.utc).replace(microsecond=0)
    with Browser(browser_path) as browser:
        browser.goto(served + "/")
        browser.wait_for("!!document.body && document.body.dataset.ready === '1'")
        assert browser.evaluate("document.title") == "Review: tiny v1.0"
        shown = browser.evaluate("document.querySelectorAll('article.card').length")
        assert shown == min(25, len(by_id))
        summary = browser.evaluate("document.getElementById('summary').textContent")
        assert summary == f"{len(by_id)} episodes: 0 accepted, 0 rejected, {len(by_id)} undecided"
        # The filter: eval only, each card saying so, with its task, scene, category, length, difficulty.
        eval_cards = _show_split(browser, "eval")
        eval_ids = [e.episode_id for e in dataset.episodes(split="eval")]
        assert sorted(i for i, _ in eval_cards) == sorted(eval_ids[:25])
        first = by_id[eval_cards[0][0]]
        assert eval_cards[0][1] == " · ".join(
            ["eval", first.task, f"{first.scene_id} (indoor)", first.goal_category,
             f"{first.info.geodesic_distance:.1f} m", first.info.difficulty]
        )  # fmt: skip
        # A VLN card shows its instruction text.
        vln = next(e for e in dataset.episodes(split="eval") if e.task == "vln")
        text = browser.evaluate(
            f"document.querySelector('article.card[data-episode=\"{vln.episode_id}\"] ul.instructions')"
            ".textContent"
        )
        assert vln.instruction.instruction_text in text
        # Its pictures load in the page: the bird's-eye view and four keyframes.
        card = f'article.card[data-episode="{first.episode_id}"]'
        browser.wait_for(
            f"[...document.querySelectorAll('{card} img')].every(i => i.complete && i.naturalWidth > 0)",
            timeout=240,
        )
        assert browser.evaluate(f"document.querySelectorAll('{card} .frames img').length") == 4
        # Reject one eval and one train episode, accept another; a rejection without reason is refused.
        train_cards = _show_split(browser, "train")
        train_id = train_cards[0][0]
        rejected = {eval_cards[0][0]: "goal region behind a wall", train_id: "path through a closed door"}
        _show_split(browser, "")
        for episode_id, reason in rejected.items():
            assert _reject_in_page(browser, episode_id, reason).startswith(f"rejected: {reason} (")
        refused = _reject_in_page(browser, train_cards[1][0], "")
        assert refused.startswith("not saved:") and "needs a reason" in refused
        browser.click(f'article.card[data-episode="{train_cards[2][0]}"] button[data-action="accept"]')
        browser.wait_for(
            f"document.querySelector('article.card[data-episode=\"{train_cards[2][0]}\"]').dataset.decision"
            " === 'accept'"
        )
        summary = browser.evaluate("document.getElementById('summary').textContent")
        assert summary == f"{len(by_id)} episodes: 1 accepted, 2 rejected, {len(by_id) - 3} undecided"
        assert browser.page_errors() == []
    # The decisions file beside the recipe: sorted, stable bytes, ISO times of now.
    review = read_review(decisions_file, dataset="tiny")
    assert review.reviewed_version == "1.0"
    assert {k: (v.decision, v.reason) for k, v in review.decisions.items()} == {
        **{k: ("reject", reason) for k, reason in rejected.items()},
        train_cards[2][0]: ("accept", ""),
    }
    for decision in review.decisions.values():
        at = datetime.fromisoformat(decision.at)
        assert started - timedelta(seconds=1) <= at <= datetime.now(timezone.utc)
    assert decisions_file.read_bytes() == review_bytes(review)
    assert decisions_file.read_text().startswith("dataset: tiny\ndecisions:\n")
    # The pictures the page shows: the rollout (orange) and the reference path (blue) on the BEV, and
    # first-person frames of the embodiment's camera.
    bev = np.asarray(Image.open(io.BytesIO(_get(f"{served}/bev/{first.episode_id}.png"))))
    assert bev.shape[0] > 300 and bev.shape[1] > 300
    assert _pixels_of(bev, (255, 127, 14)) > 100 and _pixels_of(bev, (31, 119, 180)) > 100
    frame = np.asarray(Image.open(io.BytesIO(_get(f"{served}/keyframes/{first.episode_id}/3.png"))))
    assert frame.shape == (180, 240, 3) and frame.std() > 10.0
    # Requests from elsewhere are refused: another origin, another host name.
    status, answer = _post(
        served, {"episode_id": train_id, "decision": "accept"}, {"Origin": "http://evil.example"}
    )
    assert status == 400 and "review page" in answer["error"]
    status, _ = _post(served, {"episode_id": train_id, "decision": "accept"}, {"Host": "evil.example"})
    assert status == 403
    assert read_review(decisions_file) == review

    # The recipe names the decisions file; the next build publishes v1.1 without the rejected episodes.
    recipe = published.workspace.recipes_dir / "datasets" / "tiny.yaml"
    recipe.write_text(DATASET.replace('    version: "1.0"\n', f'    version: "1.0"\n    review: {REVIEW}\n'))
    rebuilt = build_all(published.workspace)
    assert rebuilt.report.ok, rebuilt.report
    built = built_version(rebuilt.output("tiny", "dataset"))
    assert built.name == "v1.1"
    path, written = publish(built, root / "episodes")
    assert written and path == root / "episodes" / "tiny" / "v1.1"
    v11 = Dataset(path)
    v11.verify()
    assert v11.manifest.version == "1.1"
    assert sorted(e.episode_id for e in v11.episodes()) == sorted(set(by_id) - set(rejected))
    stats = rebuilt.manifest("tiny", "dataset")["stats"]
    assert stats["review"] == {
        "file": REVIEW, "sha256": hashlib.sha256(decisions_file.read_bytes()).hexdigest(),
        "reviewed_version": "1.0", "rejected": 2, "unknown": 0,
    }  # fmt: skip
    assert stats["episodes"] == len(by_id) - 2
    assert _digests(v10) == before  # the reviewed version is untouched
    # Nothing changed: nothing is rebuilt and v1.1 is up to date.
    again = build_all(published.workspace)
    assert again.report.ok and not again.report.built
    assert publish(built_version(again.output("tiny", "dataset")), root / "episodes") == (path, False)
    with _serving(published) as newest:  # the page now serves v1.1
        _reject_after_publishing(published, newest)


def _reject_after_publishing(published: Built, served: str) -> None:
    """With v1.1 published and served, one more rejection publishes v1.2; v1.0 and v1.1 stay as they were
    (a part of the browser test, which publishes v1.1)."""
    root = published.workspace.root
    v11 = Dataset(root / "episodes" / "tiny" / "v1.1")
    before = {v: _digests(root / "episodes" / "tiny" / v) for v in ("v1.0", "v1.1")}
    victim = next(iter(v11.episodes())).episode_id
    status, saved = _post(served, {"episode_id": victim, "decision": "reject", "reason": "  too   easy "})
    assert status == 200 and saved["reason"] == "too easy" and saved["decision"] == "reject"
    status, answer = _post(served, {"episode_id": "nope-0000", "decision": "reject", "reason": "x"})
    assert status == 400 and "no episode 'nope-0000'" in answer["error"]
    decisions_file = published.workspace.recipes_dir / "datasets" / REVIEW
    assert read_review(decisions_file).reviewed_version == "1.1"
    rebuilt = build_all(published.workspace)  # the file's content is in the cache key: rebuilt
    assert rebuilt.report.ok, rebuilt.report
    path, written = publish(built_version(rebuilt.output("tiny", "dataset")), root / "episodes")
    assert written and path.name == "v1.2"
    assert sorted(e.episode_id for e in Dataset(path).episodes()) == sorted(
        e.episode_id for e in v11.episodes() if e.episode_id != victim
    )
    assert rebuilt.manifest("tiny", "dataset")["stats"]["review"]["rejected"] == 3
    assert {v: _digests(root / "episodes" / "tiny" / v) for v in ("v1.0", "v1.1")} == before


# ---------------------------------------------------------------------------------------------- the file


def test_the_version_rule_bumps_the_minor_past_the_reviewed_version_only_when_episodes_go():
    review = Review(dataset="d", reviewed_version="1.1")
    assert published_version("1.1", review, left_out=0) == "1.1"
    assert published_version("1.1", review, left_out=2) == "1.2"
    assert published_version("1.0", review, left_out=1) == "1.2"
    assert published_version("1.5", review, left_out=1) == "1.5"
    with pytest.raises(ReviewError, match=r"of version 1\.1 but the recipe builds 2\.0"):
        published_version("2.0", review, left_out=1)


def test_reviewed_version_moves_to_the_newest_published_only_when_the_rejections_change():
    review = Review(dataset="d", reviewed_version="1.0")
    accepted = with_decision(review, "e-1", decision="accept", reason="", at=AT, newest="1.3")
    assert accepted.reviewed_version == "1.0"  # accepting changes no content
    rejected = with_decision(accepted, "e-2", decision="reject", reason="bad", at=AT, newest="1.3")
    assert rejected.reviewed_version == "1.3" and rejected.rejected == {"e-2"}
    withdrawn = with_decision(
        rejected, "e-2", decision="accept", reason="fine after all", at=AT, newest="1.4"
    )
    assert withdrawn.reviewed_version == "1.4" and withdrawn.rejected == frozenset()
    with pytest.raises(ReviewError, match="needs a reason"):
        with_decision(review, "e-3", decision="reject", reason="   ", at=AT, newest="1.0")
    with pytest.raises(ReviewError, match="decision"):
        with_decision(review, "e-3", decision="maybe", reason="", at=AT, newest="1.0")


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("- a\n- b\n", "must be a mapping"),
        ("dataset: tiny\nreviewed_version: 1.1\n", "reviewed_version"),
        ("dataset: tiny\nreviewed_version: '1.1'\nextra: 1\n", "extra: Extra inputs are not permitted"),
        ("dataset: tiny\nreviewed_version: '1.1'\ndecisions:\n  e-1: {decision: reject, at: '" + AT + "'}\n",
         "decisions.e-1: a rejection needs a reason"),
        ("dataset: tiny\nreviewed_version: '1.1'\ndecisions:\n  e-1: {decision: nope, reason: x, at: '" + AT
         + "'}\n", "decisions.e-1.decision"),
        ("dataset: tiny\nreviewed_version: '1.1'\ndecisions:\n  e-1: {decision: accept, at: yesterday}\n",
         "not an ISO 8601 time"),
        ("dataset: tiny\nreviewed_version: '1.1'\ndecisions:\n  ../x: {decision: accept, at: '" + AT + "'}\n",
         "decisions.../x"),
        ("dataset: &a tiny\nreviewed_version: *a\n", "aliases"),
        ("dataset: [unclosed\n", "not readable YAML"),
        ("dataset: other\nreviewed_version: '1.1'\n", "reviews dataset 'other', not 'tiny'"),
    ],
)  # fmt: skip
def test_a_malformed_decisions_file_is_refused_naming_the_entry(tmp_path: Path, text: str, message: str):
    path = tmp_path / REVIEW
    path.write_text(text)
    with pytest.raises(ReviewError, match=message) as caught:
        read_review(path, dataset="tiny")
    assert str(path) in str(caught.value)


def test_a_decisions_file_round_trips_to_the_same_bytes(tmp_path: Path):
    review = Review(dataset="tiny", reviewed_version="1.0")
    for index, reason in enumerate(["über: a 'quoted' reason", "", "# not a comment"]):
        decision = "reject" if reason else "accept"
        review = with_decision(
            review, f"e-{9 - index}", decision=decision, reason=reason, at=AT, newest="1.0"
        )
    path = tmp_path / REVIEW
    path.write_bytes(review_bytes(review))
    again = read_review(path)
    assert again == review and review_bytes(again) == path.read_bytes()
    assert list(again.decisions) == ["e-7", "e-8", "e-9"]
    assert f"at: '{AT}'" in path.read_text()  # quoted: read back as text, not a YAML timestamp
