"""Recipe loading: extends/presets, expansion, and every error reported with file and line."""

from __future__ import annotations

import dataclasses

import pytest

from pipeline.errors import RecipeError, TargetError
from pipeline.recipes import RecipeLoader
from pipeline.selection import select_targets
from tests.pipeline.conftest import write


def test_extends_presets_and_seed_expansion(workspace, stages):
    targets = {t.id: t for t in RecipeLoader(workspace, stages=stages).load()}
    assert sorted(targets) == ["all", "alpha-s0", "alpha-s1", "beta"]
    alpha = targets["alpha-s1"]
    assert alpha.seed == 1 and alpha.recipe == "group/alpha.yaml"
    params = {c.spec.name: c.params for c in alpha.stages}
    assert params["ex_numbers"].count == 4 and params["ex_sum"].offset == 1.0
    beta = {c.spec.name: c.params for c in targets["beta"].stages}
    assert beta["ex_sum"].offset == 2.5 and beta["ex_numbers"].count == 4
    assert targets["beta"].seed == 7
    assert targets["alpha-s0"].recipe_hash != targets["alpha-s1"].recipe_hash


def test_count_expansion_and_null_removes_stage(workspace, stages):
    path = write(
        workspace.recipes_dir / "many.yaml",
        """
        extends: base
        count: 3
        seed: 10
        stages:
          ex_sum: null
    """,
    )
    targets = RecipeLoader(workspace, stages=stages).load([path])
    assert [(t.id, t.seed) for t in targets] == [("many-00", 10), ("many-01", 11), ("many-02", 12)]
    assert [c.spec.name for c in targets[0].stages] == ["ex_numbers"]


def test_three_mistakes_reported_together_with_lines(workspace, stages):
    path = write(
        workspace.recipes_dir / "bad.yaml",
        """
        seed: 0
        stages:
          ex_numbers:
            count: -3
            colour: red
          ex_sum:
            offset: lots
    """,
    )
    with pytest.raises(RecipeError) as info:
        RecipeLoader(workspace, stages=stages).load([path])
    issues = {i.key_path: i for i in info.value.issues}
    assert set(issues) == {"stages.ex_numbers.count", "stages.ex_numbers.colour", "stages.ex_sum.offset"}
    assert issues["stages.ex_numbers.count"].line == 4
    assert issues["stages.ex_numbers.colour"].line == 5
    assert issues["stages.ex_sum.offset"].line == 7
    assert "unknown key 'colour'" in issues["stages.ex_numbers.colour"].message
    assert "count" in issues["stages.ex_numbers.colour"].message  # lists the known keys
    text = str(info.value)
    assert "bad.yaml:4" in text and "bad.yaml:5" in text and "bad.yaml:7" in text


def test_errors_across_files_and_top_level(workspace, stages):
    one = write(
        workspace.recipes_dir / "one.yaml",
        """
        seeds: [1, 1]
        stages:
          nonexistent_stage: {}
    """,
    )
    two = write(
        workspace.recipes_dir / "two.yaml",
        """
        extends: no-such-preset
        stages: {ex_numbers: {}}
    """,
    )
    three = write(workspace.recipes_dir / "three.yaml", "stages: [unclosed\n")
    with pytest.raises(RecipeError) as info:
        RecipeLoader(workspace, stages=stages).load([one, two, three])
    text = str(info.value)
    assert "one.yaml" in text and "distinct" in text
    assert "unknown stage 'nonexistent_stage'" in text and "ex_numbers" in text
    assert "two.yaml:1" in text and "no-such-preset" in text
    assert "three.yaml" in text and "invalid YAML" in text


def test_error_in_preset_points_at_preset_line(workspace, stages):
    write(
        workspace.presets_dir / "broken.yaml",
        """
        stages:
          ex_numbers:
            count: zero
    """,
    )
    path = write(workspace.recipes_dir / "child.yaml", "extends: broken\n")
    with pytest.raises(RecipeError) as info:
        RecipeLoader(workspace, stages=stages).load([path])
    (issue,) = info.value.issues
    assert issue.file == "presets/broken.yaml" and issue.line == 3


def test_duplicate_keys_and_ids_are_errors(workspace, stages):
    dup = write(workspace.recipes_dir / "dup.yaml", "seed: 1\nseed: 2\nstages: {ex_numbers: {}}\n")
    with pytest.raises(RecipeError, match="duplicate key 'seed'"):
        RecipeLoader(workspace, stages=stages).load([dup])
    clash = write(workspace.recipes_dir / "clash.yaml", "id: beta\nstages: {ex_numbers: {}}\n")
    beta = workspace.recipes_dir / "group" / "beta.yaml"
    with pytest.raises(RecipeError, match="also made by"):
        RecipeLoader(workspace, stages=stages).load([beta, clash])


def test_extends_cycle_is_reported(workspace, stages):
    write(workspace.presets_dir / "a.yaml", "extends: b\n")
    write(workspace.presets_dir / "b.yaml", "extends: a\n")
    path = write(workspace.recipes_dir / "cyc.yaml", "extends: a\nstages: {ex_numbers: {}}\n")
    with pytest.raises(RecipeError, match="cycle"):
        RecipeLoader(workspace, stages=stages).load([path])


def test_source_file_is_resolved_and_checked(workspace, stages):
    write(workspace.recipes_dir / "data" / "values.txt", "1 2 3\n")
    good = write(
        workspace.recipes_dir / "data" / "read.yaml", "stages: {ex_read_file: {source: values.txt}}\n"
    )
    (target,) = RecipeLoader(workspace, stages=stages).load([good])
    assert target.stages[0].params.source == (workspace.recipes_dir / "data" / "values.txt").resolve()
    bad = write(
        workspace.recipes_dir / "data" / "missing.yaml", "stages: {ex_read_file: {source: nope.txt}}\n"
    )
    with pytest.raises(RecipeError, match="file not found"):
        RecipeLoader(workspace, stages=stages).load([bad])


def test_select_targets(workspace, stages):
    targets = RecipeLoader(workspace, stages=stages).load()
    assert [t.id for t in select_targets(targets, ["group"])] == ["alpha-s0", "alpha-s1", "beta"]
    assert [t.id for t in select_targets(targets, ["alpha-*"])] == ["alpha-s0", "alpha-s1"]
    assert [t.id for t in select_targets(targets, ["recipes/group/beta.yaml"])] == ["beta"]
    with pytest.raises(TargetError, match="no target or recipe matches 'gamma'"):
        select_targets(targets, ["gamma"])


def test_manual_targets_are_built_only_when_named(workspace, stages):
    write(workspace.recipes_dir / "group" / "huge.yaml", "extends: base\nmanual: true\ncount: 2\n")
    targets = RecipeLoader(workspace, stages=stages).load()
    everything = [t.id for t in select_targets(targets, [])]
    assert "huge-00" not in everything and "beta" in everything  # not by building everything...
    assert "huge-00" not in [t.id for t in select_targets(targets, ["group"])]  # ...nor by folder
    with pytest.raises(TargetError, match=r"no target or recipe matches 'huge-\*'"):
        select_targets(targets, ["huge-*"])  # ...nor by a glob
    assert [t.id for t in select_targets(targets, ["huge-01"])] == ["huge-01"]  # by id
    assert [t.id for t in select_targets(targets, ["group/huge.yaml"])] == ["huge-00", "huge-01"]  # by file


def test_keys_keep_their_text():
    from pipeline.yaml_source import loads_located

    data = loads_located("rule: {on: path, yes: 1, 3: x, 'true': y}", file="k.yaml").data
    assert data == {"rule": {"on": "path", "yes": 1, "3": "x", "true": "y"}}


def test_the_recipe_hash_leaves_out_appearance_stages(workspace, stages):
    # ex_sum made an appearance stage: its section no longer moves the hash other stages record.
    looks = {**stages, "ex_sum": dataclasses.replace(stages["ex_sum"], appearance=True)}

    def hashes(sum_offset: float, count: int) -> tuple[str, str]:
        write(
            workspace.recipes_dir / "group" / "beta.yaml",
            f"""
            extends: base
            seed: 7
            stages:
              ex_numbers: {{count: {count}}}
              ex_sum: {{offset: {sum_offset}}}
            """,
        )
        plain = {t.id: t for t in RecipeLoader(workspace, stages=stages).load()}["beta"]
        look = {t.id: t for t in RecipeLoader(workspace, stages=looks).load()}["beta"]
        return plain.recipe_hash, look.recipe_hash

    plain_a, look_a = hashes(2.5, 4)
    plain_b, look_b = hashes(9.0, 4)
    _, look_c = hashes(2.5, 5)
    assert plain_a != plain_b and look_a == look_b  # only the appearance stage changed
    assert look_c != look_a  # another stage's section still counts
