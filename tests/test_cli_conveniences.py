"""The command line's conveniences: ``--version``, ``navverse list``, help with examples on every command,
and progress lines when the output is not a terminal."""

from __future__ import annotations

import argparse
import io
import itertools
import json
import re
import shlex
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest
from rich.console import Console

from navverse import __version__, cli
from navverse.commands import evaluate
from navverse.commands.progress import PlainProgress, show_progress

REPO = Path(__file__).resolve().parents[1]
NAVVERSE = str(Path(sys.executable).parent / "navverse")


def run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([NAVVERSE, *args], capture_output=True, text=True, timeout=300, cwd=REPO)


def listed(*args: str) -> list[dict]:
    result = run("list", *args, "--json")
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout)


# ------------------------------------------------------------------------------------------- --version


def test_version_names_the_toolkit_and_the_formats_it_reads_and_writes():
    from navverse.dataset import FORMAT_VERSION
    from navverse.scene.annotations import SCENE_FORMAT_VERSION

    result = run("--version")
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0] == f"navverse {__version__}"
    assert lines[1].startswith(f"dataset format {FORMAT_VERSION} (")
    assert lines[2].startswith(f"scene format {SCENE_FORMAT_VERSION} (")
    assert len(lines) == 3


# ---------------------------------------------------------------------------------------------- list


def test_list_building_types_json_has_every_program_with_its_footprint():
    from navverse.indoor.programs import PROGRAMS

    rows = {row["name"]: row for row in listed("building-types")}
    assert set(rows) == set(PROGRAMS)
    office = PROGRAMS["office"]
    assert rows["office"]["length_m"] == list(office.length) == [22.0, 32.0]
    # a corridor 2.6-3.2 m wide with rooms 4.5-6.5 m deep on both sides
    assert rows["office"]["depth_m"] == pytest.approx([2.6 + 2 * 4.5, 3.2 + 2 * 6.5])
    assert rows["grocery"]["depth_m"] == pytest.approx([12.0 + 4.0, 16.0 + 5.0])  # rooms at the back only
    assert rows["school"]["spine"] == "corridor" and "classroom" in rows["school"]["rooms"]


def test_list_room_types_covers_every_room_of_every_program():
    from navverse.indoor.programs import PROGRAMS

    rows = {row["name"]: row for row in listed("room-types")}
    for program in PROGRAMS.values():
        assert rows[program.spine.room_type]["role"] == "spine"
        for spec in program.rooms:
            assert program.building_type in rows[spec.room_type]["building_types"]
    assert rows["restroom"]["area_m2"] == [10.0, 16.0]  # the widest range over five building types
    assert "bed" in rows["bedroom"]["furniture"] and rows["corridor"]["area_m2"] is None


def test_list_categories_has_objects_with_sizes_and_places():
    from navverse.assets.facade.storefronts import PLACE_CATEGORIES
    from navverse.assets.library import asset

    rows = {(row["kind"], row["name"]): row for row in listed("categories")}
    bed = rows["object", "bed"]
    assert bed["size_min_m"] == list(asset("bed").size_min) and bed["size_max_m"] == list(
        asset("bed").size_max
    )
    assert rows["place", "pharmacy"]["designs"] > 0
    assert {name for kind, name in rows if kind == "place"} == set(PLACE_CATEGORIES)
    places = listed("categories", "--kind", "places")
    assert {row["kind"] for row in places} == {"place"} and len(places) == len(PLACE_CATEGORIES)


def test_list_agents_and_embodiments():
    result = run("list", "agents")
    assert result.returncode == 0, result.stderr
    assert "oracle" in result.stdout and "random" in result.stdout and "frontier" in result.stdout
    agents = {row["name"]: row for row in listed("agents")}
    assert agents["oracle"]["privileged"] is True and agents["oracle"]["action_mode"] == "waypoint"
    assert agents["random"]["privileged"] is False and agents["random"]["action_mode"] == "discrete"
    assert agents["frontier"]["sensors"] == ["depth", "semantic"]
    assert agents["random"]["description"].startswith("Uniformly random discrete actions")
    assert "`" not in agents["random"]["description"]  # reStructuredText roles made plain
    robots = {row["name"]: row for row in listed("embodiments")}
    assert robots["spot"]["radius_m"] == 0.6 and robots["turtlebot"]["max_velocity"][1] == 0.0


def test_list_refuses_an_unknown_listing_and_a_misplaced_kind():
    unknown = run("list", "robots")
    assert unknown.returncode == 2 and "invalid choice: 'robots'" in unknown.stderr
    misplaced = run("list", "agents", "--kind", "places")
    assert misplaced.returncode == 1 and "--kind" in misplaced.stderr and "Traceback" not in misplaced.stderr


# ---------------------------------------------------------------------------------------------- help


def _commands(parser: argparse.ArgumentParser, path: tuple[str, ...] = ()):
    """(command words, parser) of the top parser and of every sub-command, depth first."""
    yield path, parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, child in action.choices.items():
                yield from _commands(child, (*path, name))


def _example_commands(parser: argparse.ArgumentParser) -> list[str]:
    """The example commands of a parser's epilog, continuation lines joined."""
    text = parser.epilog.split("examples:\n", 1)[1]
    return [" ".join(part.strip() for part in block.split("\\\n")) for block in re.split(r"\n(?=  \S)", text)]


def test_every_argument_of_every_command_has_help_and_every_command_has_examples():
    commands = list(_commands(cli.build_parser()))
    assert len(commands) > 15
    for path, parser in commands:
        for action in parser._actions:
            if isinstance(action, argparse._HelpAction):
                continue
            assert action.help and action.help.strip(), (
                f"navverse {' '.join(path)}: {action.dest} has no help"
            )
        shown = parser.format_help()
        assert "\nexamples:\n  navverse " in shown, f"navverse {' '.join(path)} --help has no examples"
        examples = _example_commands(parser)
        assert examples, path
        assert len(examples) <= 3, path
        assert any(e.startswith(" ".join(("navverse", *path))) for e in examples), path


def test_the_examples_parse_and_name_datasets_the_recipes_publish(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    parser = cli.build_parser()
    for path, command in _commands(parser):
        for example in _example_commands(command):
            words = shlex.split(example)
            for flag, value in itertools.pairwise(words):
                if flag == "--scenes":
                    (tmp_path / value).mkdir(exist_ok=True)  # --scenes must name a folder that exists
            args = parser.parse_args(words[1:])
            assert callable(args.func), example
            for name, version in re.findall(r"episodes/([\w-]+)/v([\d.]+)", example):
                recipe = (REPO / "recipes" / "datasets" / f"{name}.yaml").read_text()
                assert f'version: "{version}"' in recipe, (path, example)


def test_examples_keep_their_lines_while_descriptions_are_filled():
    parser = next(p for path, p in _commands(cli.build_parser()) if path == ("export", "scenes"))
    shown = parser.format_help()
    assert "\n  navverse export scenes episodes/navverse-mini/v2.2 mini-scenes\n" in shown
    description = shown.split("\n\n")[1]
    assert description.startswith("Copy the scenes") and max(map(len, description.splitlines())) <= 80


# ------------------------------------------------------------------------------------------ progress


class FakeClock:
    def __init__(self) -> None:
        self.now = 1000.0

    def __call__(self) -> float:
        return self.now


def test_plain_progress_writes_a_line_per_n_items_and_per_interval_whichever_comes_later():
    clock, lines = FakeClock(), []
    progress = PlainProgress("run-agent oracle on eval", unit="episodes", write=lines.append, every=5,
                             seconds=10.0, clock=clock)  # fmt: skip
    progress(0, 100)
    for done, seconds in ((5, 4.0), (6, 4.0), (7, 5.0), (12, 1.0), (13, 10.0)):
        clock.now += seconds
        progress(done, 100)
    # 5 items after 4 s: too soon; 7 items after 13 s: due; 12 after 1 s more: too soon; 13 after 11 s: due
    assert lines == [
        "run-agent oracle on eval: 7/100 episodes, 13 s, ~3 min left",
        "run-agent oracle on eval: 13/100 episodes, 24 s, ~3 min left",
    ]
    clock.now += 600.0
    progress(100, 100)
    progress(100, 100)  # the last line once
    assert lines[2:] == ["run-agent oracle on eval: 100/100 episodes, 10 min"]


def test_plain_progress_estimates_from_the_items_done_since_it_started():
    clock, lines = FakeClock(), []
    progress = PlainProgress("run", unit="episodes", write=lines.append, seconds=10.0, clock=clock)
    progress(50, 100)  # 50 resumed from an interrupted run
    clock.now += 3600.0
    progress(75, 100)  # 25 in an hour: an hour left, not 20 minutes
    assert lines == ["run: 75/100 episodes, 60 min, ~60 min left"]


def test_the_progress_shown_depends_on_whether_the_output_is_a_terminal(capsys):
    piped = Console(file=io.StringIO(), force_terminal=False)
    with show_progress(piped, "eval: scoring run.jsonl", unit="episodes") as progress:
        progress(0, 3)
        progress(3, 3)
    assert capsys.readouterr().err == "eval: scoring run.jsonl: 3/3 episodes, 0 s\n"
    terminal = Console(file=io.StringIO(), force_terminal=True)
    with show_progress(terminal, "eval: scoring run.jsonl", unit="episodes") as progress:
        progress(0, 3)
        progress(3, 3)
    assert capsys.readouterr().err == ""


def test_run_agent_prints_progress_lines_when_its_output_is_piped(monkeypatch, capsys):
    import navverse.dataset
    import navverse.eval.runner

    episodes = [SimpleNamespace(episode_id=f"ep-{i}", scene_id="corridor") for i in range(4)]
    fake_dataset = SimpleNamespace(
        splits=("eval",),
        manifest=SimpleNamespace(embodiment="spot", scene_hashes={}),
        verify=lambda: None,
        episodes=lambda split=None: iter(episodes),
        private_splits=frozenset(),
        has_goals=lambda split: True,
    )

    def fake_run(dataset, *, progress, out, **kwargs):
        for done in range(len(episodes) + 1):
            progress(done, len(episodes))
        return SimpleNamespace(timeouts=[], log=None, terminations={"stop": 4}, resumed=0, episodes=4,
                               seconds=1.0, out=out)  # fmt: skip

    monkeypatch.setattr(navverse.dataset, "local_dataset", lambda root, private=None: fake_dataset)
    monkeypatch.setattr(navverse.eval.runner, "run_agent", fake_run)
    monkeypatch.setattr(evaluate, "dataset_scene_dirs", lambda *args: {"corridor": Path("corridor")})
    monkeypatch.setattr("navverse.commands.progress.PLAIN_PROGRESS_SECONDS", 0.0)
    code = cli.main(["run-agent", "--dataset", "episodes/x/v1.0", "--agent", "oracle", "--out", "o.jsonl"])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    lines = [line for line in captured.err.splitlines() if line.startswith("run-agent oracle on eval:")]
    counts = [line.split(": ")[1].split(",")[0] for line in lines]
    assert counts == ["1/4 episodes", "2/4 episodes", "3/4 episodes", "4/4 episodes"]
    assert "left" in lines[0] and "left" not in lines[-1]
    assert "4 episodes in 1 s" in captured.out  # the summary stays on stdout
