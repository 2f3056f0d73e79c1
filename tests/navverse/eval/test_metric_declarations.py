"""Every metric and group statistic is declared once, in full: what the docs and reports show comes from
its declaration in :mod:`navverse.eval.metrics`, and an incomplete declaration fails at registration."""

from __future__ import annotations

import re

import numpy as np
import pytest

from navverse.eval import metrics
from navverse.eval.metrics import METRICS, STATISTICS, UNITS, definition, metric, statistic
from navverse.eval.scoring import group_means
from navverse.eval.tables import HEADERS, TABLES, cell_text

PUBLIC = {name: spec for name, spec in METRICS.items() if not name.startswith("_")}
DECLARED = {**PUBLIC, **STATISTICS}
PAPER_NAMES = {
    "success": ("SR", "Success Rate"),
    "spl": ("SPL", "Success weighted by Path Length"),
    "soft_success": ("SS", "Soft Success"),
    "soft_spl": ("SoftSPL", "Soft Success weighted by Path Length"),
    "ne": ("NE", "Navigation Error"),
    "os": ("OS", "Oracle Success"),
    "ce": ("CE", "Coverage Efficiency"),
    "cr": ("CR", "Collision Rate"),
    "ado": ("ADO", "Average Distance to Obstacles"),
    "nsr": ("NSR", "Navigable Surface Ratio"),
    "ind_only": ("Ind-Only", "Indoor Only"),
    "reach_out": ("Reach-Out", "Reached Outdoors"),
    "ndtw": ("nDTW", "Normalized Dynamic Time Warping"),
}
"""Abbreviation and full name of the metrics the paper (or, for nDTW, the VLN literature) names."""


def _balanced(formula: str) -> bool:
    depth = 0
    for char in re.sub(r"\\[{}]", "", formula):  # \{ and \} are literal braces
        depth += {"{": 1, "}": -1}.get(char, 0)
        if depth < 0:
            return False
    return depth == 0 and formula.count(r"\left") == formula.count(r"\right")


@pytest.mark.parametrize("name", sorted(DECLARED))
def test_every_public_metric_and_statistic_is_declared_in_full(name):
    spec = DECLARED[name]
    for field in ("title", "abbreviation", "description", "formula"):
        assert getattr(spec, field).strip(), (name, field)
    assert "\n" not in spec.description and spec.description.endswith("."), name
    assert spec.unit in UNITS and _balanced(spec.formula), name
    assert spec.reference == "" or spec.reference.startswith(("Appendix", "Section")), name
    assert definition(name) is spec


def test_the_papers_metrics_have_its_names():
    got = {name: (PUBLIC[name].abbreviation, PUBLIC[name].title) for name in PAPER_NAMES}
    assert got == PAPER_NAMES
    assert all(PUBLIC[n].reference == "Appendix A.5 (Metrics)" for n in ("success", "ne", "os", "ado", "nsr"))
    assert PUBLIC["speed"].reference == PUBLIC["ndtw"].reference == ""  # the paper does not define them


def test_a_metric_or_statistic_without_its_definition_fails_at_registration(monkeypatch):
    monkeypatch.setattr(metrics, "METRICS", {})
    monkeypatch.setattr(metrics, "STATISTICS", {})
    full = {"title": "Widget Rate", "abbreviation": "WR", "description": "Share of widgets.", "formula": "w"}
    for field in full:
        with pytest.raises(ValueError, match=f"needs a {field}"):
            metric("widget", needs=("dtg",), **{**full, field: " "}, unit="%")
    with pytest.raises(ValueError, match="one line"):
        metric("widget", needs=("dtg",), **{**full, "description": "two\nlines"}, unit="%")
    with pytest.raises(ValueError, match="unit"):
        metric("widget", needs=("dtg",), **full, unit="furlongs")
    with pytest.raises(ValueError, match="needs a title"):
        statistic("widgets", **{**full, "title": ""}, unit="")
    assert metrics.METRICS == {} and metrics.STATISTICS == {}
    metric("_internal", needs=("dtg",), description="an internal value")(np.negative)  # needs none of them
    metric("widget", needs=("dtg",), **full, unit="%")(np.negative)
    assert list(metrics.METRICS) == ["_internal", "widget"]
    assert metrics.METRICS["widget"].title == "Widget Rate"
    with pytest.raises(ValueError, match="registered twice"):
        statistic("widget", **full, unit="")


def test_every_group_value_is_a_metric_or_a_declared_statistic():
    rows = [
        {"episode_id": f"e{i}", "task": "objnav", "scene_type": "i2o", "difficulty": "easy", "label": label,
         **dict.fromkeys(PUBLIC, None), "success": float(label == "success"), "post_exit_timeout": timeout}
        for i, (label, timeout) in enumerate([("success", None), ("fall", 0.0), ("timeout", 1.0)])
    ]  # fmt: skip
    entry = group_means(rows)["overall"]["all"]
    undeclared = {k for k in entry if k != "episodes" and not k.endswith("_n")} - set(DECLARED)
    assert undeclared == set()
    assert {k for k in entry if k.endswith("_n")} == {f"{n}_n" for n in PUBLIC}
    assert entry["failures"] == 2 and entry["post_exit_failures"] == 2 and entry["fall_share"] == 0.333333


def test_table_columns_are_declared_and_named_from_their_declaration():
    columns = {c for _, names in TABLES.values() for c in names}
    assert columns <= set(DECLARED)
    for name in columns:
        spec = DECLARED[name]
        assert HEADERS[name] == (f"{spec.abbreviation} ({spec.unit})" if spec.unit else spec.abbreviation)
    assert len(set(HEADERS.values())) == len(HEADERS)  # no two columns share a name
    assert [HEADERS[n] for n in ("success", "ne", "ce", "failures", "wrong_goal_share", "ce_pre_exit")] == [
        "SR (%)", "NE (m)", "CE (cells/m)", "#Fail", "wrong goal (%)", "CE pre-exit (cells/m)"]  # fmt: skip
    # The unit decides how a value is shown: rates in %, counts as integers, the rest with two decimals.
    shown = [cell_text(n, v) for n, v in (("wrong_goal_share", 0.25), ("failures", 3), ("ne", 1.234))]
    assert shown == ["25.0", "3", "1.23"]
