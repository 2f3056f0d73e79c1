"""The dataset stages through the engine: sample, verify, instructions, package; replay, bytes, errors."""

from __future__ import annotations

import hashlib
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from navverse.dataset import PUBLIC_FORMAT_VERSION, Dataset, DatasetError, built_version, read_json_gz
from navverse.episodes import files
from navverse.episodes.inspect import check_bounds, replay
from navverse.episodes.verification import REASONS
from pipeline.dag import build_graph
from pipeline.errors import RecipeError
from pipeline.recipes import RecipeLoader
from pipeline.runner import run_made
from pipeline.stage import discover
from tests.stages.conftest import (
    DATASET,
    SCENES,
    Built,
    build_all,
    navverse_command,
    scene_dirs,
    workspace_with,
)


def _digests(root: Path) -> dict[str, str]:
    return {
        str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(root.rglob("*"))
        if p.is_file()
    }


def test_the_dataset_has_scene_disjoint_splits_counts_and_checksums(built: Built, dataset: Dataset):
    manifest = dataset.manifest
    assert (
        manifest.format_version == PUBLIC_FORMAT_VERSION
        and manifest.version == "1.0"
        and manifest.name == "tiny"
    )
    assert dataset.root.parts[-2:] == ("tiny", "v1.0")
    assert manifest.splits == {"train": ["apartment-s0"], "eval": ["apartment-s1"]}
    assert set(manifest.scene_hashes) == {"apartment-s0", "apartment-s1"}
    assert manifest.recipe == "recipes/datasets/tiny.yaml" and len(manifest.recipe_hash) == 64
    assert dataset.verify_checksums() == []
    for split, scenes in manifest.splits.items():
        for task in dataset.tasks(split):
            episodes = list(dataset.episodes(split=split, task=task))
            assert {e.scene_id for e in episodes} <= set(scenes)
            assert manifest.counts[split][task]["indoor"] == len(episodes) > 0
    everything = list(dataset.episodes())
    assert len({e.episode_id for e in everything}) == len(everything)
    # Difficulty: per-task tertiles of the geodesic distance, recorded in the manifest.
    for task, (easy, hard) in manifest.difficulty_thresholds.items():
        for e in (e for e in everything if e.task == task):
            d = e.info.geodesic_distance
            assert e.info.difficulty == ("easy" if d < easy else "medium" if d < hard else "hard")


def test_verification_records_every_candidate(built: Built, dataset: Dataset):
    stats = built.manifest("tiny", "verified")["stats"]
    rejected = read_json_gz(built.output("tiny", "verified") / files.REJECTIONS)
    candidates = read_json_gz(built.output("tiny", "candidates") / files.CANDIDATES)["episodes"]
    assert stats["candidates"] == len(candidates) == 24
    assert stats["accepted"] + len(rejected) == len(candidates)
    assert sum(stats["rejected_by_reason"].values()) == len(rejected)
    assert {r["reason"] for r in rejected} <= set(REASONS)
    # The dataset holds the accepted ones, less VLN episodes dropped for want of landmarks.
    dropped = read_json_gz(built.output("tiny", "instructions") / files.DROPPED)
    assert len(list(dataset.episodes())) == stats["accepted"] - len(dropped)


def test_vln_episodes_carry_grounded_instructions(built: Built, dataset: Dataset):
    vln = [e for e in dataset.episodes() if e.task == "vln"]
    assert len(vln) >= 3
    for episode in vln:
        instruction = episode.instruction
        assert instruction is not None and len(instruction.landmarks) >= 2
        assert not re.search(r"\d|meter", instruction.instruction_text)
        assert len(instruction.directive_times) >= 2
        duration = episode.info.verification.duration_s
        assert instruction.directive_times == sorted(instruction.directive_times)
        assert instruction.directive_times[0] >= 0.0 and instruction.directive_times[-1] <= duration + 1e-6
    assert all(e.instruction is None for e in dataset.episodes() if e.task == "objnav")


def test_the_build_summary_says_what_the_scene_and_dataset_stages_made(built: Built, dataset: Dataset):
    graph = build_graph(RecipeLoader(built.workspace, stages=discover("stages")).load())
    made = {node_id: run_made(node, built.store) for node_id, node in graph.nodes.items()}  # from manifests
    stats = {node_id: built.manifest(node.target.id, next(iter(node.artifact_keys)))["stats"]
             for node_id, node in graph.nodes.items()}  # fmt: skip
    layout = stats["apartment-s0:indoor_layout"]
    assert made["apartment-s0:indoor_layout"].startswith(f"building apartment, rooms {layout['rooms']} (")
    assert f", objects {layout['objects']}, faces " in made["apartment-s0:indoor_layout"]
    assert re.match(r"faces before \d+, faces after \d+$", made["apartment-s0:decimate"])
    navmesh = r"navigable m2 [\d.]+, islands \d+, largest island m2 [\d.]+, polygons \d+, preset indoor"
    assert re.fullmatch(navmesh, made["apartment-s1:navmesh"])
    sampled = stats["tiny:sample_episodes"]["per_task"]
    assert made["tiny:sample_episodes"].startswith(f"candidates {sum(sampled.values())} (")
    assert made["tiny:sample_episodes"].endswith("), scenes 2")
    assert all(f"{task} {n}" in made["tiny:sample_episodes"] for task, n in sampled.items())
    verified = stats["tiny:verify_episodes"]
    assert made["tiny:verify_episodes"].startswith(
        f"candidates {verified['candidates']}, accepted {verified['accepted']} ("
    )
    assert "rejected " in made["tiny:verify_episodes"] and "dropped " in made["tiny:instructions"]
    counts = {split: sum(n for types in tasks.values() for n in types.values())
              for split, tasks in dataset.manifest.counts.items()}  # fmt: skip
    assert made["tiny:package_dataset"].startswith(f"dataset tiny v1.0, episodes {sum(counts.values())} (")
    for split, count in counts.items():
        assert f"{split} {count}" in made["tiny:package_dataset"].split("by task")[0]


def test_every_episode_keeps_the_bounds_and_a_sample_replays_to_the_goal(built: Built, dataset: Dataset):
    episodes = list(dataset.episodes())
    assert [check_bounds(e) for e in episodes] == [None] * len(episodes)
    sample = [episodes[i] for i in np.random.default_rng(0).choice(len(episodes), 6, replace=False)]
    report = replay(sample, scene_dirs(built), embodiment=dataset.manifest.embodiment, jobs=1)
    assert report.replayed == report.reached == 6 and report.failures == []


def test_same_recipes_and_seeds_give_byte_identical_datasets(built: Built, tmp_path: Path):
    again = workspace_with(tmp_path / "again", [SCENES], {"datasets/tiny.yaml": DATASET})
    # Reuse the built scenes (their bytes are the scene stages' tests' concern); rebuild the dataset.
    shutil.copytree(built.workspace.built_dir, again.built_dir, symlinks=True)
    for stage in ("sample_episodes", "verify_episodes", "instructions", "package_dataset"):
        shutil.rmtree(again.built_dir / "artifacts" / stage)
    shutil.rmtree(again.built_dir / "targets" / "tiny")
    rebuilt = build_all(again)
    assert rebuilt.report.ok
    first, second = (built_version(b.output("tiny", "dataset")) for b in (built, rebuilt))
    assert first != second and rebuilt.report.built  # really built again
    assert _digests(first) == _digests(second)


def test_a_wrong_format_version_is_refused(dataset: Dataset, tmp_path: Path):
    copy = tmp_path / "copy"
    shutil.copytree(dataset.root, copy)
    manifest = copy / "manifest.json"
    manifest.write_text(
        manifest.read_text().replace(
            f'"format_version": "{PUBLIC_FORMAT_VERSION}"', '"format_version": "9.0"'
        )
    )
    with pytest.raises(DatasetError, match=r"format 9\.0"):
        Dataset(copy)


@pytest.mark.parametrize(
    ("section", "message"),
    [
        ("  sample_episodes:\n    tasks: {objnav: {episodes_per_scene: 4}}\n    embodiment: hexapod\n",
         "unknown embodiment 'hexapod'"),
        ("  sample_episodes:\n    tasks: {pointnav: {episodes_per_scene: 4}}\n", "pointnav"),
        ("  sample_episodes:\n    tasks: {objnav: {episodes_per_scene: 4}}\n    path_length: [9, 5]\n",
         r"path_length must be \[shortest, longest\]"),
        ("  verify_episodes:\n    duration_s: [100, 5]\n", r"duration_s must be \[lowest, highest\]"),
        ("  instructions:\n    refiner: my_vlm\n", "refiner"),
        ("  instructions:\n    min_landmark: 2\n", "min_landmark"),
        ("  package_dataset:\n    version: one\n    splits: {train: ['*']}\n", "version"),
        ("  package_dataset:\n    version: '1.0'\n    splits: {train: []}\n", "give every split a list"),
    ],
)  # fmt: skip
def test_recipe_mistakes_fail_validation(tmp_path: Path, section: str, message: str):
    text = "extends: dataset\nlinks:\n  scene: [apartment-s*]\nstages:\n" + section
    workspace = workspace_with(tmp_path, [SCENES], {"datasets/bad.yaml": text})
    with pytest.raises(RecipeError, match=message):
        RecipeLoader(workspace, stages=discover("stages")).load()


def test_splits_that_miss_a_scene_fail_the_build_with_what_to_change(built: Built, tmp_path: Path):
    text = DATASET.replace('splits: {train: ["*-s0"], eval: ["*-s1"]}', 'splits: {train: ["*-s0"]}')
    workspace = workspace_with(tmp_path / "w", [SCENES], {"datasets/tiny.yaml": text})
    shutil.copytree(built.workspace.built_dir, workspace.built_dir, symlinks=True)
    shutil.rmtree(workspace.built_dir / "artifacts" / "package_dataset")
    report = build_all(workspace).report
    assert not report.ok
    assert "apartment-s1" in str(report) and "split" in str(report)


def test_a_quota_keeps_that_many_and_a_shortfall_warns(
    built: Built, dataset: Dataset, tmp_path: Path, navverse_here
):
    counts = dataset.manifest.counts
    available = sum(counts["eval"]["objnav"].values())
    assert available >= 2  # the quota below must bite
    text = DATASET.replace(
        'splits: {train: ["*-s0"], eval: ["*-s1"]}',
        'splits: {train: ["*-s0"], eval: ["*-s1"]}\n    quota: {eval: {objnav: 1, vln: 999}}',
    )
    root = tmp_path / "w"
    workspace = workspace_with(root, [SCENES], {"datasets/tiny.yaml": text})
    shutil.copytree(built.workspace.built_dir, workspace.built_dir, symlinks=True)
    result = navverse_here(root, "build", "tiny", "--jobs", "0")  # only the packaging runs
    output = " ".join((result.stdout + result.stderr).split())
    assert result.returncode == 0, output
    vln = sum(counts["eval"]["vln"].values())
    assert f"warning tiny:package_dataset: eval vln: {vln} episodes, short of its quota of 999" in output
    quota = Dataset(root / "episodes" / "tiny" / "v1.0").manifest.counts
    assert sum(quota["eval"]["objnav"].values()) == 1
    assert quota["train"] == counts["train"]  # no quota there: all kept
    assert sum(quota["eval"]["vln"].values()) == vln


# ---------------------------------------------------------------------------------------------- command line


def test_show_and_validate_a_dataset_from_the_command_line(built: Built, dataset: Dataset, tmp_path: Path):
    root = built.workspace.root
    shown = navverse_command(root, "show", "dataset", str(dataset.root))
    assert shown.returncode == 0, shown.stderr
    total = len(list(dataset.episodes()))
    assert re.search(rf"all\s.*\s{total}\s", shown.stdout) and "goal categories" in shown.stdout
    # the scenes table: the tiny dataset's two apartments, one per split
    assert re.search(r"eval\s*│\s*1\s*│\s*0\s*│\s*0\s*│\s*1\s", shown.stdout), shown.stdout
    assert re.search(r"all\s*│\s*2\s*│\s*0\s*│\s*0\s*│\s*2\s", shown.stdout), shown.stdout
    assert "eval: apartment-s1" in shown.stdout  # two scenes: listed without --scenes
    episode = next(e for e in dataset.episodes() if e.task == "vln")
    picture = tmp_path / "ep.png"
    drawn = navverse_command(
        root, "show", "episode", str(dataset.root), episode.episode_id, "-o", str(picture)
    )
    assert drawn.returncode == 0, drawn.stderr
    assert picture.stat().st_size > 10_000 and episode.instruction.instruction_text[:30] in " ".join(
        drawn.stdout.split()
    )
    checked = navverse_command(root, "validate", "dataset", str(dataset.root), "--replay", "3", "--jobs", "1")
    assert checked.returncode == 0, checked.stdout + checked.stderr
    assert f"{total} of {total} keep them" in checked.stdout and "3 of 3 reach a goal" in checked.stdout


@pytest.mark.parametrize("problem", ["missing", "format", "tampered", "no such episode"])
def test_dataset_commands_refuse_bad_datasets_cleanly(dataset: Dataset, tmp_path: Path, problem: str):
    copy = tmp_path / "copy"
    shutil.copytree(dataset.root, copy)
    args, message = ["validate", "dataset", str(copy)], ""
    if problem == "missing":
        args, message = ["show", "dataset", str(tmp_path / "nowhere")], "is not a dataset version"
    elif problem == "format":
        manifest = copy / "manifest.json"
        manifest.write_text(
            manifest.read_text().replace(
                f'"format_version": "{PUBLIC_FORMAT_VERSION}"', '"format_version": "2.0"'
            )
        )
        message = "has dataset format 2.0"
    elif problem == "tampered":
        (copy / "train" / "objnav.json.gz").write_bytes(b"\x1f\x8b not really")
        message = "differ from the manifest's checksums: train/objnav.json.gz"
    else:
        args, message = (
            ["show", "episode", str(copy), "nope-objnav-0000", "-o", str(tmp_path / "x.png")],
            "nope-objnav-0000",
        )
    result = navverse_command(tmp_path, *args)
    assert result.returncode == 1 and message in result.stderr and "Traceback" not in result.stderr


@pytest.mark.slow(seconds=15)
def test_building_a_published_version_with_other_content_is_refused(
    built: Built, tmp_path: Path, navverse_here
):
    root = tmp_path / "w"
    workspace = workspace_with(root, [SCENES], {"datasets/tiny.yaml": DATASET})
    shutil.copytree(built.workspace.built_dir, workspace.built_dir, symlinks=True)
    # The command and its stages run in this process: publishing is what this test is about.
    first = navverse_here(root, "build", "tiny", "--jobs", "0")
    assert first.returncode == 0, first.stderr
    assert "published: episodes/tiny/v1.0" in first.stdout
    published = Dataset(root / "episodes" / "tiny" / "v1.0")
    again = navverse_here(root, "build", "tiny", "--jobs", "0")
    assert again.returncode == 0 and "up to date: episodes/tiny/v1.0" in again.stdout
    # Other content, same version: refused, and the published files are untouched. The scenes' splits
    # swapped: only the packaging runs again.
    swapped = DATASET.replace(
        'splits: {train: ["*-s0"], eval: ["*-s1"]}', 'splits: {train: ["*-s1"], eval: ["*-s0"]}'
    )
    assert swapped != DATASET
    (workspace.recipes_dir / "datasets" / "tiny.yaml").write_text(swapped)
    changed = navverse_here(root, "build", "tiny", "--jobs", "0")
    assert changed.returncode == 1 and "Traceback" not in changed.stderr
    assert (
        "already published with different content" in changed.stderr
        and "bump the dataset version" in changed.stderr
    )
    assert published.verify_checksums() == []
    # A new version is published beside it.
    (workspace.recipes_dir / "datasets" / "tiny.yaml").write_text(
        swapped.replace('version: "1.0"', 'version: "1.1"')
    )
    bumped = navverse_here(root, "build", "tiny", "--jobs", "0")
    assert bumped.returncode == 0 and "published: episodes/tiny/v1.1" in bumped.stdout
    assert [e.episode_id for e in Dataset(root / "episodes" / "tiny" / "v1.1").episodes(split="eval")] == [
        e.episode_id for e in published.episodes(split="train")
    ]


def _oracle_lines(dataset: Dataset, split: str) -> list[dict]:
    """A submission of the packaged verification rollouts (the oracle) of a split."""
    return [
        {"episode_id": e.episode_id, "trajectory": dataset.rollout(e), "stop": True}
        for e in dataset.episodes(split=split)
    ]


def test_eval_scores_the_oracle_and_counts_bad_records_as_failures(
    built: Built, dataset: Dataset, tmp_path: Path
):
    import json

    lines = _oracle_lines(dataset, "eval")
    assert len(lines) >= 4
    missing = lines.pop(0)["episode_id"]
    lines[0]["trajectory"][1][2] = float("nan")
    nan_id = lines[0]["episode_id"]
    lines.append(dict(lines[1]))  # a duplicate
    dup_id = lines[1]["episode_id"]
    submission = tmp_path / "oracle.jsonl"
    submission.write_text("".join(json.dumps(line) + "\n" for line in lines))
    root = built.workspace.root
    checked = navverse_command(
        root, "validate", "submission", str(submission), "--dataset", str(dataset.root)
    )
    assert checked.returncode == 1
    assert f"line 1 ({nan_id}): trajectory row 1 holds NaN" in checked.stdout
    assert (
        f"duplicate episode id (lines 2, {len(lines)})" in checked.stdout
        and f"missing: {missing}" in checked.stdout
    )
    out = tmp_path / "out"
    scored = navverse_command(
        root, "eval", "--dataset", str(dataset.root), "--submission", str(submission), "--out", str(out)
    )
    assert scored.returncode == 0, scored.stderr
    metrics = json.loads((out / "metrics.json").read_text())
    labels = {row["episode_id"]: row["label"] for row in metrics["episodes"]}
    assert len(labels) == len(list(dataset.episodes(split="eval")))
    assert {labels[i] for i in (missing, nan_id, dup_id)} == {"invalid"}
    others = [row for row in metrics["episodes"] if row["episode_id"] not in (missing, nan_id, dup_id)]
    assert all(row["label"] == "success" for row in others)  # the oracle reaches every goal
    overall = metrics["overall"]
    assert overall["success"] == pytest.approx(len(others) / len(labels)) and overall["failures"] == 3
    assert len(metrics["problems"]) == 3
    for name in (
        "tables.md",
        "task_scene.csv",
        "safety_efficiency.csv",
        "failures.csv",
        "difficulty.csv",
        "episodes.csv",
    ):
        assert (out / name).is_file()
    assert "SR (%)" in scored.stdout and "3 episodes have no valid trajectory" in " ".join(
        scored.stdout.split()
    )
    (tmp_path / "bad.jsonl.gz").write_bytes(b"not gzip at all")
    broken = navverse_command(
        root, "eval", "--dataset", str(dataset.root), "--submission", str(tmp_path / "bad.jsonl.gz")
    )
    assert (
        broken.returncode == 1 and "not gzip-compressed" in broken.stderr and "Traceback" not in broken.stderr
    )


def test_dataset_statistics_per_task_and_scene_type_as_a_table_and_a_figure(
    built: Built, dataset: Dataset, tmp_path: Path
):
    from navverse.episodes.statistics import dataset_statistics

    stats = dataset_statistics(dataset, split="eval")
    episodes = list(dataset.episodes(split="eval"))
    assert sum(len(cell.lengths) for cell in stats.cells.values()) == len(episodes)
    for (task, scene_type), cell in stats.cells.items():
        mine = [e for e in episodes if (e.task, e.scene_type) == (task, scene_type)]
        assert sorted(cell.lengths) == sorted(e.info.geodesic_distance for e in mine)
        assert sum(cell.difficulty.values()) == len(mine) == len(cell.durations)
        assert all(5.0 <= d <= 100.0 for d in cell.durations)  # verified rollouts last 5-100 s
    picture = tmp_path / "stats" / "eval.png"
    shown = navverse_command(
        built.workspace.root, "show", "dataset", str(dataset.root), "--stats", "--split", "eval",
        "--figure", str(picture),
    )  # fmt: skip
    assert shown.returncode == 0, shown.stderr
    text = " ".join(shown.stdout.split())
    assert "episode statistics (eval split)" in text and f"wrote {picture}" in text
    task, scene_type = next(iter(stats.cells))
    assert re.search(
        rf"{task}\s+│?\s*{scene_type}\s+│?\s*{len(stats.cells[task, scene_type].lengths)}\b", shown.stdout
    )
    assert picture.stat().st_size > 20_000
    wrong = navverse_command(
        built.workspace.root, "show", "dataset", str(dataset.root), "--stats", "--split", "x"
    )
    assert wrong.returncode == 1 and "has no split 'x'" in wrong.stderr + wrong.stdout
    assert "Traceback" not in wrong.stderr


def test_status_tells_what_each_stage_of_a_build_cost(built: Built):
    from navverse.cli import _graph_for
    from pipeline.costs import stage_costs

    _, _, graph, store = _graph_for([], every_target=True, root=built.workspace.root)
    costs = {cost.stage: cost for cost in stage_costs(graph, store)}
    assert sum(cost.runs for cost in costs.values()) == len(graph.nodes)
    verify = costs["verify_episodes"]
    assert verify.built == verify.runs >= 1 and verify.cpu_s > 0.0 and verify.wall_s > 0.0
    manifests = [
        store.read_manifest(store.artifact_path(n.stage, *sorted(n.artifact_keys.items())[0]))
        for n in graph.nodes.values()
        if n.stage == "verify_episodes"
    ]
    assert abs(verify.cpu_s - sum(m["run"]["cpu_s"] for m in manifests)) < 1e-6
    shown = navverse_command(built.workspace.root, "status", "--cost")
    assert shown.returncode == 0, shown.stderr
    text = " ".join(shown.stdout.split())
    assert (
        "cost of the built stage runs" in text and f"verify_episodes │ {verify.built} / {verify.runs}" in text
    )
