"""Properties of the recipe loader: whatever a file holds, loading it gives data or problems that name
the file, never another exception; data inside the recipe language survives a round trip."""

from __future__ import annotations

import math
import tempfile
from pathlib import Path
from typing import Any

import pytest
import yaml
from hypothesis import given
from hypothesis import strategies as st

import tests.pipeline.example_stages  # noqa: F401  (registers the example stages)
from pipeline import yaml_source
from pipeline.errors import RecipeError
from pipeline.recipes import RecipeLoader
from pipeline.stage import registered_stages
from pipeline.workspace import Workspace
from pipeline.yaml_source import MAX_DEPTH, MAX_INT, YamlSourceError, loads_located

STAGES = {name: spec for name, spec in registered_stages().items() if name in ("ex_numbers", "ex_sum")}

# Characters that make YAML structure, plus a few letters and digits to fill it in.
YAML_ALPHABET = "[]{}:,-?&*!|>'\"#%@`<=~.+_ \n\t0123456789abeinoulxyzEY\\é\x00\ufeff"
yamlish = st.text(alphabet=YAML_ALPHABET, max_size=200)

LOADERS = [yaml_source._Loader]
if getattr(yaml_source, "_LibyamlLoader", None) is not None:
    LOADERS.append(yaml_source._PythonLoader)


def _lines(text: str) -> int:
    return text.count("\n") + 1


def _load_in_workspace(data: bytes) -> tuple[list, RecipeError | None]:
    """Load ``data`` as the only recipe of a fresh workspace (a preset beside it to extend)."""
    with tempfile.TemporaryDirectory() as root:
        workspace = Workspace(Path(root))
        workspace.presets_dir.mkdir(parents=True)
        (workspace.presets_dir / "base.yaml").write_text("stages: {ex_numbers: {count: 2}}\n")
        path = workspace.recipes_dir / "fuzz.yaml"
        path.write_bytes(data)
        try:
            return RecipeLoader(workspace, stages=STAGES).load(), None
        except RecipeError as exc:
            return [], exc


def _check_problems(error: RecipeError | None) -> None:
    if error is None:
        return
    assert error.issues
    for issue in error.issues:
        assert issue.file in ("fuzz.yaml", "presets/base.yaml"), issue
        assert issue.line is None or issue.line >= 1, issue
        assert issue.message, issue


@pytest.mark.parametrize("loader", LOADERS, ids=lambda cls: cls.__name__)
@given(text=yamlish)
def test_yaml_like_text_loads_or_raises_a_located_error(loader, text):
    original = yaml_source._Loader
    yaml_source._Loader = loader
    try:
        located = loads_located(text, file="t.yaml")
    except YamlSourceError as exc:
        assert exc.file == "t.yaml" and str(exc)
        assert exc.line is None or 1 <= exc.line <= _lines(text), (exc.line, text)
    else:
        assert all(file == "t.yaml" and line >= 1 for file, line in located.marks.values())
    finally:
        yaml_source._Loader = original


@given(data=st.binary(max_size=300))
def test_any_bytes_give_targets_or_problems_naming_the_file(data):
    _, error = _load_in_workspace(data)
    _check_problems(error)


@given(text=yamlish)
def test_yaml_like_recipes_give_targets_or_problems_naming_the_file(text):
    _, error = _load_in_workspace(("extends: base\n" + text).encode("utf-8"))
    _check_problems(error)


# PyYAML's dumper writes YAML 1.1's line breaks NEL, LS and PS raw inside quotes, where its own
# loader folds them into spaces: a round trip PyYAML itself does not keep, left out here.
texts = st.text(alphabet=st.characters(codec="utf-8", exclude_characters="\x85\u2028\u2029"), max_size=20)
scalars = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(min_value=-(2**60), max_value=2**60),
    st.floats(allow_nan=True, allow_infinity=True),
    texts,
)
names = texts
documents = st.recursive(
    scalars,
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(names, inner, max_size=4),
    max_leaves=20,
)


def _depth(value: Any) -> int:
    if isinstance(value, dict):
        return 1 + max((_depth(v) for v in value.values()), default=0)
    if isinstance(value, list):
        return 1 + max((_depth(v) for v in value), default=0)
    return 0


def _in_language(value: Any) -> bool:
    """Whether ``value`` holds only what recipes hold (finite floats, integers within 2**53)."""
    if isinstance(value, dict):
        return all(_in_language(v) for v in value.values())
    if isinstance(value, list):
        return all(_in_language(v) for v in value)
    if isinstance(value, float):
        return math.isfinite(value)
    if isinstance(value, bool):
        return True
    if isinstance(value, int):
        return abs(value) <= MAX_INT
    if isinstance(value, str):  # a plain overflowing number written as text (YAML 1.1 reads it so)
        return not (yaml_source._OVERFLOWING_NUMBER.fullmatch(value) and math.isinf(float(value)))
    return True


@given(document=documents)
def test_data_dumped_to_yaml_round_trips_or_is_refused_for_a_reason(document):
    text = yaml.safe_dump(document, allow_unicode=True)
    try:
        located = loads_located(text, file="d.yaml")
    except YamlSourceError as exc:
        assert not _in_language(document) or _depth(document) > MAX_DEPTH, (document, exc)
        assert exc.file == "d.yaml" and exc.line is not None
    else:
        assert _in_language(document)
        assert located.data == document


@given(document=documents, seed=st.one_of(st.integers(), st.booleans(), st.floats(), st.text(max_size=5)))
def test_dumped_recipes_give_targets_or_problems_naming_the_file(document, seed):
    recipe = {"extends": "base", "seed": seed, "stages": {"ex_sum": {"offset": document}}}
    targets, error = _load_in_workspace(yaml.safe_dump(recipe, allow_unicode=True).encode("utf-8"))
    _check_problems(error)
    if error is None:
        (target,) = targets
        assert type(target.seed) is int and target.seed == seed and not isinstance(seed, bool)
