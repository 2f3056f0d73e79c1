"""Physics verification (Appendix D.2): oracle success, the acceptance bounds, reasons, processes."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from navverse.dataset import Episode, goal_distance
from navverse.episodes.sampling import object_goals, sample_scene_episodes
from navverse.episodes.verification import REASONS, VerificationSettings, verify_episodes
from navverse.nav.scene_navmesh import load_scene_navmesh
from navverse.scene.directory import read_scene
from navverse.scene.geometry import Scene
from navverse.sim.world import objects_near


def test_accepted_rollouts_reach_a_goal_within_the_bounds(verified_vln):
    episodes, results = verified_vln
    accepted = [(e, r) for e, r in zip(episodes, results, strict=True) if r.accepted]
    assert len(accepted) >= len(episodes) // 2
    for episode, result in accepted:
        v = result.verification
        assert v.embodiment == "spot" and 5.0 < v.duration_s <= 100.0 and 5.0 < v.traveled_m < 50.0
        trajectory = result.trajectory
        assert trajectory.shape[1] == 8 and trajectory[0, 0] == 0.0
        # Oracle success, recomputed from the poses: the first time a goal is within tolerance.
        inside = [
            row[0]
            for row in trajectory
            if min(goal_distance(row[1:4], g) for g in episode.goals) <= episode.info.success_distance
        ]
        assert inside and v.oracle_success_time_s == pytest.approx(inside[0], abs=1e-3)
        # The rollout started where the episode starts and traveled its own poses' length.
        assert np.hypot(*(trajectory[0, 1:3] - episode.start_position[:2])) < 0.1
        steps = np.hypot(*np.diff(trajectory[:, 1:3], axis=0).T).sum()
        assert steps == pytest.approx(v.traveled_m, rel=0.05)
    for result in results:
        assert result.reason is None or result.reason in REASONS


def _moved(episode: Episode, **update) -> Episode:
    return episode.model_copy(update=update)


@pytest.fixture(scope="module")
def candidate(verified_vln) -> Episode:
    episodes, results = verified_vln
    return next(e for e, r in zip(episodes, results, strict=True) if r.accepted)


def test_each_unmet_condition_is_its_rejection_reason(candidate: Episode, scene_dirs: dict[str, Path]):
    far_goal = candidate.goals[0].model_copy(update={"position": (100.0, 100.0, 0.5)})
    start = candidate.reference_path[0]
    short_path = [start, tuple(np.add(start, (0.5, 0.0, 0.0)))]  # half a metre
    near_goal = candidate.goals[0].model_copy(update={"position": short_path[-1], "radius": 0.0})
    cases = {
        "no_oracle_success": _moved(candidate, episode_id="a", goals=[far_goal]),
        "too_short_duration": _moved(candidate, episode_id="b", reference_path=short_path, goals=[near_goal]),
    }
    results = verify_episodes(list(cases.values()), scene_dirs, embodiment="spot", jobs=1)
    assert [r.reason for r in results] == list(cases)
    # Tight bounds: the same good episode fails on the bound that excludes it.
    for settings, reason in [
        (VerificationSettings(traveled_m=(0.0, 3.0)), "too_long_distance"),
        (VerificationSettings(traveled_m=(60.0, 70.0)), "too_short_distance"),
        (VerificationSettings(duration_s=(1.0, 2.0)), "timeout"),
    ]:
        (result,) = verify_episodes([candidate], scene_dirs, embodiment="spot", settings=settings, jobs=1)
        assert result.reason == reason and not result.accepted


def test_a_path_through_a_wall_gets_stuck(apartment: Scene, scene_dirs: dict[str, Path], candidate: Episode):
    finder = load_scene_navmesh(scene_dirs["apartment-s0"])
    rng = np.random.default_rng(3)
    for _ in range(500):  # two points 3-6 m apart whose walk is at least twice the straight line
        a, b = finder.get_random_navigable_point(rng), finder.get_random_navigable_point(rng)
        straight = float(np.hypot(*(b - a)[:2]))
        if 3.0 < straight < 6.0 and finder.geodesic_distance(a, b) > 2.0 * straight:
            break
    else:
        pytest.fail("no pair of points separated by a wall")
    goal = candidate.goals[0].model_copy(update={"position": tuple(b), "radius": 0.0})
    episode = _moved(
        candidate,
        start_position=tuple(a),
        start_rotation=(
            0.0,
            0.0,
            math.sin(math.atan2(*(b - a)[1::-1]) / 2),
            math.cos(math.atan2(*(b - a)[1::-1]) / 2),
        ),
        reference_path=[tuple(a), tuple(b)],
        goals=[goal],
    )
    (result,) = verify_episodes([episode], scene_dirs, embodiment="spot", jobs=1)
    assert result.reason == "stuck"


def test_results_do_not_depend_on_the_number_of_processes(scene_dirs: dict[str, Path]):
    episodes = []
    for path in scene_dirs.values():
        scene = read_scene(path)
        goals = object_goals(scene.annotations, categories=["bed", "sofa", "sink", "chair", "cafe_table"])
        episodes += sample_scene_episodes(
            load_scene_navmesh(path), scene.annotations, goals, task="objnav", count=3,
            rng=np.random.default_rng(7), robot_radius=0.6, base_height=0.55,
        ).episodes  # fmt: skip
    assert {e.scene_id for e in episodes} == set(scene_dirs)
    one = verify_episodes(episodes, scene_dirs, embodiment="turtlebot", jobs=1)
    two = verify_episodes(episodes, scene_dirs, embodiment="turtlebot", jobs=2)
    assert [r.episode_id for r in two] == [e.episode_id for e in episodes]
    for a, b in zip(one, two, strict=True):
        assert a.reason == b.reason and a.verification == b.verification
        np.testing.assert_array_equal(a.trajectory, b.trajectory)


def test_bounds_are_lowest_then_highest():
    with pytest.raises(ValueError, match=r"duration_s must be \[lowest, highest\], got \[5.0, 2.0\]"):
        VerificationSettings(duration_s=(5.0, 2.0))


def test_objects_far_from_the_paths_do_not_change_a_verdict(
    verified_vln, apartment: Scene, scene_dirs: dict[str, Path]
):
    # The follower keeps the robot near its path: with only the furniture within a metre of the
    # candidates' paths given collision geometry, every verdict is that of the furnished scene.
    episodes, _ = verified_vln
    near = objects_near(apartment, [np.asarray(e.reference_path) for e in episodes], margin=1.0)
    assert 0 < len(near) < len(apartment.objects)  # the check is not vacuous: some objects are left out
    results = {
        margin: verify_episodes(
            episodes,
            scene_dirs,
            embodiment="spot",
            settings=VerificationSettings(object_margin_m=margin),
            jobs=1,
        )
        for margin in (1.0, None)
    }
    assert [r.reason for r in results[1.0]] == [r.reason for r in results[None]]
    for a, b in zip(results[1.0], results[None], strict=True):
        assert a.verification.traveled_m == pytest.approx(b.verification.traveled_m, abs=0.05)
