"""Hostile and malformed recipe files: each is one clear problem with file and line, in bounded time
and memory, and a broken file does not block what does not need it."""

from __future__ import annotations

import os
import resource
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

from pipeline import yaml_source
from pipeline.errors import DagError, RecipeError, TargetError
from pipeline.recipes import MAX_EXTENDS_FILES, RecipeLoader
from pipeline.selection import linked_broken, select_loaded, skipped_warnings
from pipeline.yaml_source import YamlSourceError, load_located, loads_located
from tests.pipeline.conftest import write

REPO = Path(__file__).resolve().parents[2]
GOOD = "stages: {ex_numbers: {count: 2}}\n"


def _issues(workspace, stages, path: Path) -> list:
    with pytest.raises(RecipeError) as info:
        RecipeLoader(workspace, stages=stages).load([path])
    return list(info.value.issues)


def _one_issue(workspace, stages, path: Path):
    (issue,) = _issues(workspace, stages, path)
    return issue


def _bomb(levels: int) -> str:
    """The issue's alias bomb: anchor k is a list of nine aliases of anchor k-1 (9**levels values)."""
    lines = ["a0: &a0 [x, x, x, x, x, x, x, x, x]"]
    lines += [f"a{k}: &a{k} [{', '.join([f'*a{k - 1}'] * 9)}]" for k in range(1, levels + 1)]
    lines.append(f"stages: {{ex_numbers: {{count: *a{levels}}}}}")
    return "\n".join(lines) + "\n"


# -- values the recipe language does not have ------------------------------------------------------

MALFORMED_TEXT = {
    # name: (text, line, words of the message)
    "int-tag": ("seed: !!int abc\n" + GOOD, 1, "'abc' is not an integer"),
    "float-tag": ("seed: !!float abc\n" + GOOD, 1, "'abc' is not a number"),
    "bool-tag": ("manual: !!bool maybe\n" + GOOD, 1, "'maybe' is not !!bool"),
    "binary": ("description: !!binary aGVsbG8=\n" + GOOD, 1, "!!binary is not a recipe value"),
    "set": ("description: !!set {a, b}\n" + GOOD, 1, "!!set (a mapping) is not a recipe value"),
    "custom-tag": ("description: !thing x\n" + GOOD, 1, "!thing is not a recipe value"),
    "date": ("description: 2001-12-14\n" + GOOD, 1, "dates are not recipe values: quote it ('2001-12-14')"),
    "date-tag": ("description: !!timestamp 2001-12-14\n" + GOOD, 1, "dates are not recipe values"),
    "bad-merge": ("stages:\n  ex_numbers:\n    <<: 5\n", 3, "the merge key '<<' takes a mapping or a list"),
    "nan": ("seed: .nan\n" + GOOD, 1, "'.nan' is not a finite number"),
    "inf": ("stages: {ex_sum: {offset: -.inf}, ex_numbers: {}}\n", 1, "'-.inf' is not a finite number"),
    "overflow": ("seed: 1\n" + GOOD + "description: 1e309\n", 3, "'1e309' is not a finite number"),
    "huge-int": (
        "seed: " + "9" * 5000 + "\n" + GOOD,
        1,
        "is out of range; recipe integers lie within ±2**53",
    ),
    "int-2**53+1": ("seed: 9007199254740993\n" + GOOD, 1, "out of range"),
    "deep-list": ("description: " + "[" * 5000 + "]" * 5000 + "\n" + GOOD, 1, "nest deeper than 64 levels"),
    "deep-map": ("description: " + "{a: " * 3000 + "1" + "}" * 3000 + "\n", 1, "nest deeper than 64 levels"),
    "recursive-alias": ("description: &a [1, *a]\n" + GOOD, 1, "the alias *a refers to a list or mapping"),
    "two-documents": (GOOD + "---\n" + GOOD, 2, "expected a single document"),
    "nul": ("description: a\x00b\n" + GOOD, 1, "holds the control character NUL"),
    "null-key": ("~: 1\n" + GOOD, 1, "unsupported key: an empty (null) key"),
}


@pytest.mark.parametrize("name", sorted(MALFORMED_TEXT))
def test_malformed_value_is_one_problem_with_its_line(workspace, stages, name):
    text, line, words = MALFORMED_TEXT[name]
    path = write(workspace.recipes_dir / f"{name}.yaml", text)
    issue = _one_issue(workspace, stages, path)
    assert (issue.file, issue.line) == (f"{name}.yaml", line)
    assert words in issue.message


@pytest.mark.parametrize(
    ("name", "data", "words"),
    [
        ("utf16", ("description: é\n" + GOOD).encode("utf-16"), "is UTF-16 text"),
        ("latin1", ("description: é\n" + GOOD).encode("latin-1"), "is not UTF-8 text (byte 0xe9"),
        ("utf16-no-bom", ("description: x\n" + GOOD).encode("utf-16-le"), "control character NUL"),
    ],
)
def test_text_that_is_not_utf8_is_one_problem(workspace, stages, name, data, words):
    path = workspace.recipes_dir / f"{name}.yaml"
    path.write_bytes(data)
    issue = _one_issue(workspace, stages, path)
    assert issue.file == f"{name}.yaml" and issue.line == 1 and words in issue.message
    assert "save it as UTF-8" in issue.message or "save the file as UTF-8" in issue.message


def test_a_utf8_byte_order_mark_is_fine(workspace, stages):
    path = workspace.recipes_dir / "bom.yaml"
    path.write_bytes(b"\xef\xbb\xbf" + GOOD.encode())
    assert [t.id for t in RecipeLoader(workspace, stages=stages).load([path])] == ["bom"]


def test_yes_is_not_an_integer(workspace, stages):
    for key, text in (("seed", "seed: yes\n"), ("count", "count: on\n"), ("seeds.0", "seeds: [no]\n")):
        path = write(workspace.recipes_dir / "flags.yaml", text + GOOD)
        issue = _one_issue(workspace, stages, path)
        assert issue.key_path == key and issue.line == 1
        assert "booleans in YAML; write a number" in issue.message
    path = write(workspace.recipes_dir / "flags.yaml", "manual: 1\n" + GOOD)
    assert "valid boolean" in _one_issue(workspace, stages, path).message


def test_values_quoted_in_messages_stay_short(workspace, stages):
    path = write(workspace.recipes_dir / "long.yaml", f"description: [{', '.join(['x' * 50] * 400)}]\n{GOOD}")
    issue = _one_issue(workspace, stages, path)
    assert issue.key_path == "description" and len(issue.message) < 300


def test_merge_keys_follow_yaml(workspace, stages):
    located = loads_located(
        "base: &b {count: 2, scale: 3.0}\nstages:\n  ex_numbers:\n    <<: *b\n    count: 5\n", file="m.yaml"
    )
    assert located.data["stages"] == {"ex_numbers": {"count": 5, "scale": 3.0}}
    assert located.where(("stages", "ex_numbers", "count")) == ("m.yaml", 5)
    assert located.where(("stages", "ex_numbers", "scale")) == ("m.yaml", 1)  # where it is written
    first_wins = loads_located("a: {<<: [{x: 1}, {x: 2, y: 3}]}", file="m.yaml").data
    assert first_wins == {"a": {"x": 1, "y": 3}}


def test_merges_of_merges_are_levels_of_nesting():
    text = "m0: &m0 {x: 1}\n" + "".join(f"m{i}: &m{i} {{<<: *m{i - 1}, k{i}: 1}}\n" for i in range(1, 200))
    with pytest.raises(YamlSourceError, match="nest deeper than 64 levels"):
        loads_located(text, file="m.yaml")


# -- files that are not regular files --------------------------------------------------------------


def test_files_that_are_not_recipe_files(workspace, stages, tmp_path):
    recipes = workspace.recipes_dir
    (recipes / "folder.yaml").mkdir()
    (recipes / "loop.yaml").symlink_to("loop.yaml")
    (recipes / "zero.yaml").symlink_to("/dev/zero")
    (recipes / "gone.yaml").symlink_to("nowhere.yaml")
    os.mkfifo(recipes / "pipe.yaml")
    big = recipes / "big.yaml"
    big.write_text("description: " + "x" * yaml_source.MAX_FILE_BYTES + "\n" + GOOD)
    expected = {
        "folder.yaml": "is a directory, not a regular file",
        "loop.yaml": "is a symbolic link loop",
        "zero.yaml": "is a character device, not a regular file",
        "gone.yaml": "is a symbolic link to 'nowhere.yaml', which does not exist",
        "pipe.yaml": "is a named pipe (FIFO), not a regular file",
        "big.yaml": f"recipe files are at most {yaml_source.MAX_FILE_BYTES:,} bytes",
    }
    start = time.monotonic()
    loader = RecipeLoader(workspace, stages=stages)
    with pytest.raises(RecipeError) as info:
        loader.load()  # every file of the workspace, the pipe included: nothing blocks
    assert time.monotonic() - start < 10
    found = {issue.file: issue for issue in info.value.issues}
    assert set(found) == set(expected)
    for file, words in expected.items():
        assert words in found[file].message, (file, found[file].message)
    assert "Traceback" not in str(info.value)


def test_a_symlink_to_a_recipe_inside_the_folder_is_read(workspace, stages):
    (workspace.recipes_dir / "alias.yaml").symlink_to("group/beta.yaml")
    targets = RecipeLoader(workspace, stages=stages).load([workspace.recipes_dir / "alias.yaml"])
    assert [(t.id, t.seed) for t in targets] == [("alias", 7)]


# -- alias bombs -------------------------------------------------------------------------------------


def test_a_modest_alias_bomb_is_refused_by_the_budget(monkeypatch):
    # 9**5 = 59 049 values: loadable without a budget, refused with one of 10 000.
    text = _bomb(5)
    monkeypatch.setattr(yaml_source, "MAX_VALUES", 10_000)
    start = time.monotonic()
    with pytest.raises(YamlSourceError) as info:
        loads_located(text, file="bomb.yaml")
    assert time.monotonic() - start < 5
    assert info.value.line is not None and info.value.line > 1
    assert "expands the recipe past 10,000 values" in str(info.value) and "use fewer (nested) aliases" in str(
        info.value
    )


def test_aliases_of_long_text_are_refused_by_the_text_budget():
    text = "s: &s " + "y" * 400_000 + "\nl: [" + ", ".join(["*s"] * 30) + "]\n"
    with pytest.raises(YamlSourceError, match="characters of text") as info:
        loads_located(text, file="text.yaml")
    assert info.value.line == 2


def test_the_issues_alias_bomb_is_refused_quickly(workspace, stages):
    path = write(workspace.recipes_dir / "bomb.yaml", _bomb(9))
    assert path.stat().st_size < 1024
    start = time.monotonic()
    issue = _one_issue(workspace, stages, path)
    assert time.monotonic() - start < 10
    assert issue.file == "bomb.yaml" and issue.line is not None
    assert f"past {yaml_source.MAX_VALUES:,} values" in issue.message


def test_a_file_of_too_many_values_is_refused_while_composed(monkeypatch):
    monkeypatch.setattr(yaml_source, "MAX_VALUES", 1_000)
    with pytest.raises(YamlSourceError, match="holds more than 1,000 values"):
        loads_located("a: [" + "0, " * 2_000 + "0]\n", file="many.yaml")


def test_both_yaml_parsers_refuse_the_same_way(monkeypatch):
    if getattr(yaml_source, "_LibyamlLoader", None) is None:
        pytest.skip("PyYAML without libyaml: only the Python parser exists")
    for loader in (yaml_source._LibyamlLoader, yaml_source._PythonLoader):
        monkeypatch.setattr(yaml_source, "_Loader", loader)
        for name in ("deep-list", "recursive-alias", "bad-merge", "date", "nan"):
            text, line, words = MALFORMED_TEXT[name]
            with pytest.raises(YamlSourceError) as info:
                loads_located(text, file="x.yaml")
            assert (info.value.line, words in str(info.value)) == (line, True), (loader, name)
        assert loads_located(GOOD, file="x.yaml").data == {"stages": {"ex_numbers": {"count": 2}}}


# -- extends ------------------------------------------------------------------------------------------


def test_an_extends_cycle_points_at_the_extends_that_closes_it(workspace, stages):
    write(workspace.presets_dir / "a.yaml", "description: a\nextends: b\n")
    write(workspace.presets_dir / "b.yaml", "description: b\n\nextends: a\n")
    path = write(workspace.recipes_dir / "cyc.yaml", "extends: a\n" + GOOD)
    issue = _one_issue(workspace, stages, path)
    assert (issue.file, issue.line, issue.key_path) == ("presets/b.yaml", 3, "extends")
    assert "'extends' forms a cycle: presets/a.yaml -> presets/b.yaml -> presets/a.yaml" in issue.message
    itself = write(workspace.recipes_dir / "self.yaml", GOOD + "extends: self.yaml\n")
    issue = _one_issue(workspace, stages, itself)
    assert (issue.file, issue.line) == ("self.yaml", 2) and "self.yaml -> self.yaml" in issue.message


@pytest.mark.parametrize(
    ("extends", "words"),
    [
        ("/etc/hosts.yaml", "is an absolute path"),
        ("../../outside.yaml", "leads outside recipes/"),
        ("../../etc/passwd", "is neither"),
        ("~/x.yaml", "is an absolute path"),
    ],
)
def test_extends_stays_inside_the_recipes_folder(workspace, stages, extends, words):
    write(workspace.root / "outside.yaml", GOOD)
    path = write(workspace.recipes_dir / "group" / "escape.yaml", f"description: x\nextends: {extends}\n")
    issue = _one_issue(workspace, stages, path)
    assert (issue.file, issue.line, issue.key_path) == ("group/escape.yaml", 2, "extends")
    assert words in issue.message and "names a preset" in issue.message


def test_a_preset_linked_to_outside_the_folder_is_refused(workspace, stages, tmp_path_factory):
    elsewhere = write(tmp_path_factory.mktemp("elsewhere") / "shared.yaml", GOOD)
    (workspace.presets_dir / "shared.yaml").symlink_to(elsewhere)
    path = write(workspace.recipes_dir / "uses.yaml", "extends: shared\n")
    assert "leads outside recipes/" in _one_issue(workspace, stages, path).message


def test_extends_reaches_a_bounded_number_of_files(workspace, stages):
    # Each level extends the next one twice: 2**12 loads without a bound.
    for level in range(12):
        write(workspace.presets_dir / f"l{level}.yaml", f"extends: [l{level + 1}, l{level + 1}]\n")
    write(workspace.presets_dir / "l12.yaml", GOOD)
    path = write(workspace.recipes_dir / "fan.yaml", "extends: l0\n")
    start = time.monotonic()
    issue = _one_issue(workspace, stages, path)
    assert time.monotonic() - start < 5
    assert f"reaches more than {MAX_EXTENDS_FILES} files" in issue.message


def test_extends_between_recipe_folders_still_works(workspace, stages):
    write(workspace.recipes_dir / "other" / "gamma.yaml", "extends: ../group/beta.yaml\nid: gamma\n")
    targets = RecipeLoader(workspace, stages=stages).load([workspace.recipes_dir / "other" / "gamma.yaml"])
    assert [t.id for t in targets] == ["gamma"] and targets[0].seed == 7


# -- a broken file does not block what does not need it ----------------------------------------------


def _break_beta(workspace) -> None:
    write(workspace.recipes_dir / "group" / "beta.yaml", "extends: base\nseed: yes\n")


def test_load_all_keeps_the_good_files_and_lists_the_broken(workspace, stages):
    _break_beta(workspace)
    recipes = RecipeLoader(workspace, stages=stages).load_all()
    assert sorted(t.id for t in recipes.targets) == ["all", "alpha-s0", "alpha-s1"]
    (broken,) = recipes.broken
    assert broken.file == "group/beta.yaml" and broken.base_id == "beta"
    assert [i.key_path for i in broken.issues] == ["seed"]
    with pytest.raises(RecipeError, match=r"beta\.yaml:2: seed"):
        RecipeLoader(workspace, stages=stages).load()


def test_a_selection_that_does_not_need_a_broken_file_goes_ahead_with_a_warning(workspace, stages):
    _break_beta(workspace)
    recipes = RecipeLoader(workspace, stages=stages).load_all()
    chosen = select_loaded(recipes, ["alpha-*"])
    assert [t.id for t in chosen] == ["alpha-s0", "alpha-s1"]
    (warning,) = skipped_warnings(recipes, selectors=["alpha-*"])
    assert warning.startswith("skipped recipes/group/beta.yaml (1 problem; ")
    assert "navverse validate recipe recipes/group/beta.yaml" in warning
    assert "selector" not in warning and "links" not in warning


def test_a_link_glob_that_might_match_a_broken_file_needs_it(workspace, stages):
    _break_beta(workspace)
    recipes = RecipeLoader(workspace, stages=stages).load_all()
    chosen = select_loaded(recipes, ["all"])  # links total: ["alpha-*", "beta"]
    in_graph = [t for t in recipes.targets if t.id in ("all", "alpha-s0", "alpha-s1")]
    assert [t.id for t in chosen] == ["all"]
    assert [b.file for b in linked_broken(recipes, in_graph)] == ["group/beta.yaml"]
    assert linked_broken(recipes, [t for t in in_graph if t.id != "all"]) == []


@pytest.mark.parametrize("selectors", [[], ["group"], ["group/beta.yaml"], ["beta"], ["be*"]])
def test_a_selection_that_needs_a_broken_file_reports_its_problems(workspace, stages, selectors):
    _break_beta(workspace)
    recipes = RecipeLoader(workspace, stages=stages).load_all()
    with pytest.raises(RecipeError) as info:
        select_loaded(recipes, selectors)
    assert [i.file for i in info.value.issues] == ["group/beta.yaml"]


def test_a_selector_matching_nothing_names_the_skipped_files(workspace, stages):
    _break_beta(workspace)
    recipes = RecipeLoader(workspace, stages=stages).load_all()
    with pytest.raises(
        TargetError, match=r"(?s)matches 'gamma'.*skipped for their problems.*group/beta.yaml"
    ):
        select_loaded(recipes, ["gamma"])


def test_a_broken_file_is_known_by_the_id_its_text_gives(workspace, stages):
    write(workspace.recipes_dir / "group" / "beta.yaml", "id: gamma\nextends: base\nseed: yes\n")
    recipes = RecipeLoader(workspace, stages=stages).load_all()
    (broken,) = recipes.broken
    assert broken.base_id == "gamma" and broken.may_define("gamma-s1") and broken.may_define("g*")
    assert not broken.may_define("beta") and not broken.may_define("alpha-*")
    with pytest.raises(RecipeError):
        select_loaded(recipes, ["gamma"])


def test_a_link_to_nothing_but_a_broken_file_names_it(workspace, stages, capsys):
    from navverse.cli import _graph_over

    _break_beta(workspace)
    write(workspace.recipes_dir / "only-beta.yaml", "stages: {ex_gather: {}}\nlinks: {total: [beta]}\n")
    recipes = RecipeLoader(workspace, stages=stages).load_all()
    with pytest.raises(DagError, match=r"(?s)match no target.*skipped for their problems.*group/beta\.yaml"):
        _graph_over(select_loaded(recipes, ["only-beta"]), recipes, selectors=["only-beta"])
    with pytest.raises(RecipeError) as info:  # 'all' links [alpha-*, beta]: it would read less
        _graph_over(select_loaded(recipes, ["all"]), recipes, selectors=["all"])
    assert [i.file for i in info.value.issues] == ["group/beta.yaml"]
    graph = _graph_over(select_loaded(recipes, ["alpha-*"]), recipes, selectors=["alpha-*"])
    stages_of_alpha = ("ex_numbers", "ex_sum")
    assert sorted(graph.nodes) == [f"alpha-s{i}:{stage}" for i in (0, 1) for stage in stages_of_alpha]
    assert "warning: skipped recipes/group/beta.yaml" in capsys.readouterr().err


def test_a_broken_preset_breaks_the_files_extending_it_only(workspace, stages):
    write(workspace.presets_dir / "base.yaml", "stages: {ex_numbers: {count: zero}}\n")
    write(workspace.recipes_dir / "solo.yaml", GOOD)
    recipes = RecipeLoader(workspace, stages=stages).load_all()
    assert sorted(b.file for b in recipes.broken) == ["group/alpha.yaml", "group/beta.yaml"]
    assert all(i.file == "presets/base.yaml" for b in recipes.broken for i in b.issues)
    assert [t.id for t in select_loaded(recipes, ["solo"])] == ["solo"]


def test_a_broken_file_keeps_at_most_a_bounded_list_of_problems(workspace, stages):
    path = write(workspace.recipes_dir / "many.yaml", f"seeds: [{', '.join(['x'] * 500)}]\n{GOOD}")
    issues = _issues(workspace, stages, path)
    assert len(issues) == 50 and any("more problems in this file are not listed" in i.message for i in issues)


# -- the command line --------------------------------------------------------------------------------


@pytest.fixture
def cli_root(tmp_path: Path) -> Path:
    """A workspace of two shipped blockout scenes and the presets."""
    scenes = tmp_path / "recipes" / "scenes" / "blockout"
    scenes.mkdir(parents=True)
    shutil.copytree(REPO / "recipes" / "presets", tmp_path / "recipes" / "presets")
    for name in ("corridor.yaml", "box-room.yaml"):
        shutil.copy(REPO / "recipes" / "scenes" / "blockout" / name, scenes / name)
    return tmp_path


def _navverse(root: Path, monkeypatch, capsys, *args: str) -> tuple[int, str, str]:
    from navverse.cli import main

    monkeypatch.setenv("NAVVERSE_ROOT", str(root))
    monkeypatch.chdir(root)
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


CLI_CASES = {
    "bomb.yaml": (_bomb(9).encode(), "bomb.yaml:", "values, the most a recipe may hold"),
    "int-tag.yaml": (b"seed: !!int abc\n", "int-tag.yaml:1: 'abc' is not an integer", ""),
    "binary.yaml": (b"description: !!binary aGk=\n", "binary.yaml:1: !!binary is not a recipe value", ""),
    "date.yaml": (b"description: !!timestamp 2001-12-14\n", "date.yaml:1: dates are not recipe values", ""),
    "merge.yaml": (b"stages:\n  blockout:\n    <<: 5\n", "merge.yaml:3: the merge key '<<'", ""),
    "utf16.yaml": ("description: é\n".encode("utf-16"), "utf16.yaml:1: is UTF-16 text", ""),
    "latin1.yaml": ("description: é\n".encode("latin-1"), "latin1.yaml:1: is not UTF-8 text", ""),
    "nul.yaml": (b"description: a\x00b\n", "nul.yaml:1: holds the control character NUL", ""),
    "nan.yaml": (b"seed: .nan\n", "nan.yaml:1: '.nan' is not a finite number", ""),
    "inf.yaml": (b"seed: .inf\n", "inf.yaml:1: '.inf' is not a finite number", ""),
    "e309.yaml": (b"seed: 1e309\n", "e309.yaml:1: '1e309' is not a finite number", ""),
    "digits.yaml": (b"seed: " + b"7" * 5000 + b"\n", "digits.yaml:1: the integer 7777", "out of range"),
    "list.yaml": (
        b"a: " + b"[" * 5000 + b"]" * 5000 + b"\n",
        "list.yaml:1: lists and mappings nest deeper",
        "",
    ),
    "map.yaml": (
        b"a: " + b"{a: " * 3000 + b"1" + b"}" * 3000,
        "map.yaml:1: lists and mappings nest deeper",
        "",
    ),
    "yes.yaml": (
        b"seed: yes\nstages: {navmesh: {}}\n",
        "yes.yaml:1: seed: Input should be a valid integer",
        "",
    ),
}


@pytest.mark.parametrize("name", sorted(CLI_CASES))
def test_validate_recipe_prints_one_line_per_problem(cli_root, monkeypatch, capsys, name):
    data, first, second = CLI_CASES[name]
    path = cli_root / "recipes" / "scenes" / name
    path.write_bytes(data)
    code, out, err = _navverse(cli_root, monkeypatch, capsys, "validate", "recipe", str(path))
    assert code == 1 and "Traceback" not in out + err
    assert f"  scenes/{first}" in err and second in err


def test_validate_recipe_refuses_files_that_are_not_files(cli_root, monkeypatch, capsys):
    recipes = cli_root / "recipes"
    (recipes / "dir.yaml").mkdir()
    (recipes / "loop.yaml").symlink_to("loop.yaml")
    (recipes / "zero.yaml").symlink_to("/dev/zero")
    os.mkfifo(recipes / "fifo.yaml")
    code, out, err = _navverse(cli_root, monkeypatch, capsys, "validate", "recipe")
    assert code == 1 and "Traceback" not in out + err and "4 problems in recipes" in err
    for line in (
        "  dir.yaml: is a directory, not a regular file",
        "  loop.yaml: is a symbolic link loop",
        "  zero.yaml: is a character device, not a regular file",
        "  fifo.yaml: is a named pipe (FIFO), not a regular file",
    ):
        assert line in err


def test_an_extends_cycle_and_an_escape_on_the_command_line(cli_root, monkeypatch, capsys):
    presets = cli_root / "recipes" / "presets"
    write(presets / "one.yaml", "extends: two\n")
    write(presets / "two.yaml", "description: two\nextends: one\n")
    cyc = write(cli_root / "recipes" / "scenes" / "cyc.yaml", "extends: one\n")
    code, _, err = _navverse(cli_root, monkeypatch, capsys, "validate", "recipe", str(cyc))
    assert code == 1 and "presets/two.yaml:2: extends: 'extends' forms a cycle" in err
    escape = write(cli_root / "recipes" / "scenes" / "escape.yaml", "extends: /etc/hosts.yaml\n")
    code, _, err = _navverse(cli_root, monkeypatch, capsys, "validate", "recipe", str(escape))
    assert code == 1 and "scenes/escape.yaml:1: extends: 'extends' names a preset" in err


def test_a_bad_file_blocks_only_the_commands_that_need_it(cli_root, monkeypatch, capsys):
    bad = cli_root / "recipes" / "scenes" / "blockout" / "bad.yaml"
    bad.write_text("stages:\n  blockout: {colour: red}\n")
    code, out, err = _navverse(cli_root, monkeypatch, capsys, "build", "corridor", "--dry-run")
    assert code == 0, err
    assert "corridor" in out and "box-room" not in out
    assert (
        "warning: skipped recipes/scenes/blockout/bad.yaml (2 problems; see navverse validate recipe "
        "recipes/scenes/blockout/bad.yaml): its targets do not exist"
    ) in err
    code, out, err = _navverse(cli_root, monkeypatch, capsys, "status", "corridor")
    assert code == 0 and "1 missing" in out and "warning: skipped recipes/scenes/blockout/bad.yaml" in err
    code, _, err = _navverse(
        cli_root, monkeypatch, capsys, "validate", "recipe", "scenes/blockout/corridor.yaml"
    )
    assert code == 0 and "warning: skipped" in err
    for needs_it in (["build", "--dry-run"], ["build", "scenes/blockout", "--dry-run"], ["status", "bad"]):
        code, out, err = _navverse(cli_root, monkeypatch, capsys, *needs_it)
        assert code == 1, needs_it
        assert "bad.yaml:2: stages.blockout.colour: unknown key 'colour'" in err
        assert "Traceback" not in out + err
    code, _, err = _navverse(cli_root, monkeypatch, capsys, "validate", "recipe", str(bad))
    assert code == 1 and "2 problems" in err
    code, _, err = _navverse(cli_root, monkeypatch, capsys, "validate", "recipe")
    assert code == 1 and "2 problems" in err


def test_the_issues_cases_exit_1_without_a_traceback_in_a_process(cli_root):
    """As a user runs it: a pipe in the recipes folder hangs nothing, an alias bomb stays small."""
    recipes = cli_root / "recipes" / "scenes"
    os.mkfifo(recipes / "pipe.yaml")
    write(recipes / "bomb.yaml", _bomb(9))
    navverse = str(Path(sys.executable).parent / "navverse")
    python_path = os.pathsep.join(p for p in (str(REPO), os.environ.get("PYTHONPATH", "")) if p)
    env = {**os.environ, "NAVVERSE_ROOT": str(cli_root), "PYTHONPATH": python_path}  # this tree's code

    def limit_memory() -> None:  # well above the command's own needs, far below an expanded bomb
        resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))

    result = subprocess.run(
        [navverse, "validate", "recipe"],
        env=env,
        cwd=cli_root,
        capture_output=True,
        text=True,
        timeout=120,
        preexec_fn=limit_memory,
    )
    assert result.returncode == 1 and "Traceback" not in result.stdout + result.stderr
    assert "scenes/pipe.yaml: is a named pipe (FIFO)" in result.stderr
    assert "scenes/bomb.yaml:" in result.stderr and "values, the most a recipe may hold" in result.stderr
    status = subprocess.run(
        [navverse, "status", "corridor"], env=env, cwd=cli_root, capture_output=True, text=True, timeout=120
    )
    assert status.returncode == 0 and "warning: skipped recipes/scenes/pipe.yaml" in status.stderr


def test_load_located_reads_a_regular_file(tmp_path):
    path = write(tmp_path / "ok.yaml", GOOD)
    assert load_located(path).data == {"stages": {"ex_numbers": {"count": 2}}}
