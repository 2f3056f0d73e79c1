"""``tables.md`` and ``metrics.json`` explain themselves: every column defined, every value with its n, the
scored episode ids listed (on the hand-worked transition result of ``test_transition``)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from navverse.eval.metrics import METRICS, STATISTICS
from navverse.eval.scoring import EvalResult, group_means
from navverse.eval.tables import write_outputs
from tests.navverse.eval.test_transition import transition_result


def _sections(text: str) -> dict[str, str]:
    """The ``## `` sections of a Markdown file by title."""
    parts = re.split(r"^## (.+)$", text, flags=re.MULTILINE)
    return dict(zip(parts[1::2], parts[2::2], strict=True))


def _table(section: str) -> list[list[str]]:
    """The rows of the Markdown table in a section (header first, the |---| line left out)."""
    rows = [line for line in section.splitlines() if line.startswith("| ")]
    return [[cell.strip() for cell in re.split(r"(?<!\\)\|", row)[1:-1]] for row in rows]


def _blocks(section: str) -> dict[str, list[str]]:
    """The fenced id lists of a section by their ``### `` heading: the ids, comma-separated over lines."""
    found = re.findall(r"^### ([^\n]+)\n\n```text\n(.*?)\n```", section, flags=re.MULTILINE | re.DOTALL)
    return {title: [i.strip() for i in body.replace("\n", " ").split(",")] for title, body in found}


@pytest.fixture(scope="module")
def written(tmp_path_factory: pytest.TempPathFactory) -> tuple[EvalResult, dict[str, str], Path]:
    result = transition_result()
    out = write_outputs(result, tmp_path_factory.mktemp("tables"), meta={"submission": "test"})
    return result, _sections((out / "tables.md").read_text()), out


def test_every_column_tables_md_shows_is_defined_under_metrics(written):
    _, sections, _ = written
    data = [name for name in sections if name not in ("Metrics", "Scored episodes")]
    assert data == ["task scene", "safety efficiency", "failures", "difficulty", "transition"]
    shown = {cell for name in data for cell in _table(sections[name])[0][2:]}
    glossary = {row[0]: row for row in _table(sections["Metrics"])[1:]}
    assert set(glossary) == shown  # every column shown is defined, and nothing else
    for column, (_, title, description, better, key) in glossary.items():
        spec = METRICS.get(key.strip("`")) or STATISTICS[key.strip("`")]
        expected = (spec.title, spec.description, "higher" if spec.higher_is_better else "lower")
        assert (title, description, better) == expected, column
    assert glossary["NE (m)"][1:3] == ["Navigation Error", METRICS["ne"].description]
    assert glossary["#Fail"][1] == "Failed Episodes" and glossary["Ind-Only (%)"][1] == "Indoor Only"


def test_every_cell_carries_its_n(written):
    _, sections, _ = written
    header, *rows = _table(sections["task scene"])
    assert header[:2] == ["task / scene", "episodes"]
    assert [row[1] for row in rows] == ["1", "7", "1", "9"]  # the row's n
    # NE needs a trajectory: over 6 of the 7 ObjNav i2o episodes (one has no valid record), 8 of all 9.
    assert rows[1][header.index("NE (m)")] == "4.85 (n=6)" and rows[3][header.index("NE (m)")] == "5.46 (n=8)"
    assert rows[1][header.index("SR (%)")] == "14.3"  # over the row's 7
    header, *rows = _table(sections["transition"])
    assert rows[0][:4] == ["objnav", "7", "16.7 (n=6)", "83.3 (n=6)"]
    assert rows[0][header.index("post-exit fall (%)")] == "25.0 (n=4)"  # its n: the 4 post-exit failures


def test_tables_md_lists_every_scored_episode(written):
    result, sections, _ = written
    blocks = _blocks(sections["Scored episodes"])
    invalid = blocks.pop("without a valid record, scored as failures (1)")
    assert list(blocks) == ["objnav / indoor (1)", "objnav / i2o (7)", "placenav / i2o (1)"]
    listed = [i for ids in blocks.values() for i in ids]
    assert sorted(listed) == sorted(row["episode_id"] for row in result.episodes) and len(listed) == 9
    assert invalid == ["e6"] and result.episodes[6]["label"] == "invalid"


def test_a_long_id_list_is_wrapped_and_complete(tmp_path: Path):
    base = transition_result().episodes[0]
    rows = [{**base, "episode_id": f"scene-{k:04d}-objnav-{k:05d}"} for k in range(300)]
    out = write_outputs(EvalResult(episodes=rows, groups=group_means(rows)), tmp_path, meta={})
    section = _sections((out / "tables.md").read_text())["Scored episodes"]
    block = re.search(r"```text\n(.*?)\n```", section, flags=re.DOTALL).group(1)
    assert all(len(line) <= 100 for line in block.splitlines()) and len(block.splitlines()) > 50
    assert _blocks(section)["objnav / i2o (300)"] == [r["episode_id"] for r in rows]


def test_metrics_json_holds_each_definition(written):
    _, _, out = written
    data = json.loads((out / "metrics.json").read_text())
    assert set(data["definitions"]) == {n for n in METRICS if not n.startswith("_")}
    assert data["definitions"]["os"] == {
        "title": "Oracle Success", "abbreviation": "OS", "description": METRICS["os"].description,
        "formula": METRICS["os"].formula, "unit": "%", "reference": "Appendix A.5 (Metrics)",
        "higher_is_better": True,
    }  # fmt: skip
    assert set(data["statistic_definitions"]) == set(STATISTICS)
    assert data["statistic_definitions"]["fall_share"]["title"] == "Fall Share"
