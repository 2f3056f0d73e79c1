"""VLN instructions (Appendix D.3): directives, alignment, visible landmarks, wording, drops, refiners."""

from __future__ import annotations

import itertools
import math
import re
import sys
from collections.abc import Sequence

import numpy as np
import pytest

from navverse.dataset import Episode, EpisodeInfo, Goal
from navverse.episodes.instructions import (
    InstructionSettings,
    InstructionWriter,
    RefinerError,
    align_directives,
    color_name,
    load_refiner,
    plan_directives,
    template_text,
    turn_class,
)
from navverse.scene.compose import ObjectPart
from navverse.scene.geometry import Scene, Surface
from navverse.sim.camera import CameraIntrinsics
from navverse.sim.embodiments import make_embodiment
from navverse.sim.render import SceneRenderer
from tests.scenes import box_part, quad, scene_of

SPOT = make_embodiment("spot")
BASE_Z = 0.5
# An L-shaped route: 8 m along +x, a left turn, 8 m along +y to the bed.
L_PATH = [(0.0, 0.0, 0.0), (8.0, 0.0, 0.0), (8.0, 8.0, 0.0)]
NO_DIGITS = re.compile(r"\d")


def yaw_quat(yaw: float) -> tuple[float, float, float, float]:
    return (0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0))


# Box-shaped objects of one colour; a scene numbers its objects 1, 2, ... in the order given.
BED = box_part("bed", (8.0, 9.4, 0.3), (1.6, 2.0, 0.6), rgb=(240, 240, 235))
SOFA = box_part("sofa", (3.5, 1.3, 0.45), (1.8, 0.8, 0.9), rgb=(30, 60, 200))  # ahead of the start
CABINET = box_part("cabinet", (9.4, -0.8, 0.6), (0.6, 0.6, 1.2), rgb=(200, 30, 30))  # at the corner
PLANT = box_part("potted_plant", (6.8, 9.0, 0.5), (0.5, 0.5, 1.0), rgb=(40, 160, 50))  # beside the bed


def l_scene(objects: Sequence[ObjectPart], scene_id: str = "l-room") -> Scene:
    """An open 12 x 12 m room with a floor and a ceiling and the given objects (the bed first: id 1)."""
    surfaces = (
        Surface("floor", "floor", quad(-2.0, -2.0, 11.0, 11.0, 0.0)),
        Surface("ceiling", "ceiling", quad(-2.0, -2.0, 11.0, 11.0, 3.0)),
    )
    return scene_of(surfaces, objects, scene_id=scene_id)


def l_episode(scene_id: str = "l-room", *, mirror: bool = False, start_yaw: float = 0.0) -> Episode:
    sign = -1.0 if mirror else 1.0
    path = [(x, sign * y, z) for x, y, z in L_PATH]
    return Episode(
        episode_id=f"{scene_id}-vln-0000",
        scene_id=scene_id,
        scene_type="indoor",
        task="vln",
        start_position=path[0],
        start_rotation=yaw_quat(start_yaw),
        object_category="bed",
        goals=[
            Goal(object_id=1, category="bed", position=(8.0, sign * 9.4, 0.3), radius=1.0, size=(1.6, 2, 0.6))
        ],
        reference_path=path,
        info=EpisodeInfo(
            geodesic_distance=16.0, euclidean_distance=12.0, closest_goal_object_id=1, success_distance=1.35
        ),
    )


def walk(path: Sequence[Sequence[float]], *, speed: float = 1.0, rate: float = 10.0) -> np.ndarray:
    """A rollout walking a polyline at constant speed, facing each segment: (K, 8) rows."""
    rows, t = [], 0.0
    for a, b in itertools.pairwise(path):
        a, b = np.asarray(a), np.asarray(b)
        length = float(np.hypot(*(b - a)[:2]))
        yaw = math.atan2(b[1] - a[1], b[0] - a[0])
        for s in np.arange(0.0, length, speed / rate):
            p = a + (b - a) * s / length
            rows.append([t, p[0], p[1], BASE_Z, *yaw_quat(yaw)])
            t += 1.0 / rate
    rows.append([t, *path[-1][:2], BASE_Z, *rows[-1][4:]])
    return np.array(rows)


# ---------------------------------------------------------------------------------------------- template


def test_turns_are_named_by_side_and_sharpness():
    assert turn_class(math.radians(5)) == "straight"
    assert turn_class(math.radians(40)) == "slight_left"
    assert turn_class(math.radians(-90)) == "right"
    assert turn_class(math.radians(140)) == "sharp_left"
    assert turn_class(math.radians(-175)) == "around"


@pytest.mark.parametrize(("mirror", "turn"), [(False, "left"), (True, "right")])
def test_an_l_path_is_a_start_one_turn_and_an_arrival(mirror: bool, turn: str):
    episode = l_episode(mirror=mirror, start_yaw=math.radians(-50.0 if not mirror else 50.0))
    directives = plan_directives(episode.reference_path, episode.start_yaw)
    assert [d.kind for d in directives] == ["start", "turn", "arrive"]
    assert directives[0].turn == ("slight_left" if not mirror else "slight_right")  # 50 degrees to face +x
    assert directives[1].turn == turn and directives[1].angle == pytest.approx(
        math.copysign(math.pi / 2, -mirror + 0.5)
    )
    assert [d.length for d in directives] == pytest.approx([8.0, 8.0, 0.0])
    text = template_text(directives, "bed")
    assert text == (
        f"Turn slightly {'left' if not mirror else 'right'} and walk forward about 8 meters, "
        f"turn {turn} and walk about 8 meters, then stop at the bed."
    )


def test_wiggles_and_short_jogs_are_not_turns():
    path = [(0, 0, 0), (3, 0.1, 0), (6, -0.1, 0), (6.3, 0.3, 0), (10, 0.2, 0), (10, 6, 0)]
    directives = plan_directives(path, 0.0)
    assert [d.turn for d in directives] == ["straight", "left", "straight"]
    assert directives[0].length == pytest.approx(10.0, abs=0.3)


def test_alignment_follows_path_order_even_when_the_route_comes_back():
    # Out 6 m along +x, back along y = 1 to the start: the start and the end vertex are close together.
    path = [(0, 0, 0), (6, 0, 0), (6, 1, 0), (0.5, 1, 0)]
    directives = plan_directives(path, 0.0, min_segment=0.5)
    rollout = walk(path)
    rows, errors = align_directives(directives, rollout)
    assert list(rows) == sorted(rows) and len(set(rows)) == len(rows)
    assert rows[0] == 0 and rows[-1] == len(rollout) - 1  # the end is matched to the end, not the start
    assert errors.max() < 0.15


def test_colour_names():
    assert color_name((220, 30, 30)) == "red"
    assert color_name((30, 60, 200)) == "blue"
    assert color_name((40, 160, 50)) == "green"
    assert color_name((128, 128, 128)) == "gray"
    assert color_name((245, 245, 245)) == "white"
    assert color_name((15, 15, 15)) == "black"
    assert color_name((110, 70, 30)) == "brown"
    assert color_name((230, 210, 170)) == "beige"


# ---------------------------------------------------------------------------------------------- landmarks


def _writer(scene: Scene, **settings) -> InstructionWriter:
    return InstructionWriter(
        scene, camera_to_base=SPOT.camera_to_base, settings=InstructionSettings(**settings)
    )


def test_landmarks_are_the_objects_seen_at_each_step():
    scene = l_scene([BED, SOFA, CABINET, PLANT])
    episode = l_episode()
    instruction, reason = _writer(scene).write(episode, walk(L_PATH), np.random.default_rng(0))
    assert reason is None
    named = {(lm.step, lm.object_id, lm.color) for lm in instruction.landmarks}
    assert named == {(0, 2, "blue"), (1, 3, "red"), (2, 4, "green")}
    text = instruction.instruction_text
    for phrase in ("blue sofa", "red cabinet", "green potted plant", "bed"):
        assert phrase in text
    assert not NO_DIGITS.search(text) and "meter" not in text
    assert instruction.instruction_type == "landmark"
    # Directive times: the start, the corner after 8 m at 1 m/s, the end after 16 m.
    assert instruction.directive_times == pytest.approx([0.0, 8.0, 16.0], abs=0.15)
    assert "turn left" in instruction.template_text


def test_a_room_without_distinctive_objects_drops_the_episode():
    bare = l_scene([BED])
    instruction, reason = _writer(bare).write(l_episode(), walk(L_PATH), np.random.default_rng(0))
    assert instruction is None and reason.startswith("too_few_landmarks")
    # Two sofas of one colour where one would be named: neither is distinctive.
    twin = box_part("sofa", (5.0, 1.3, 0.45), (1.0, 0.8, 0.9), rgb=(30, 60, 200))
    instruction, reason = _writer(l_scene([BED, SOFA, twin]), min_landmarks=1).write(
        l_episode(), walk(L_PATH), np.random.default_rng(0)
    )
    assert instruction is None and reason.startswith("too_few_landmarks")
    # Told apart by colour, both may be named.
    red = box_part("sofa", (5.0, 1.3, 0.45), (1.0, 0.8, 0.9), rgb=(200, 30, 30))
    instruction, _ = _writer(l_scene([BED, SOFA, red]), min_landmarks=1).write(
        l_episode(), walk(L_PATH), np.random.default_rng(0)
    )
    assert instruction is not None and re.search(r"(blue|red) sofa", instruction.instruction_text)


def test_objects_hidden_behind_the_robot_or_far_away_are_not_landmarks():
    behind = box_part("piano", (-1.5, 0.0, 0.6), (0.8, 1.4, 1.2), rgb=(20, 20, 20))  # id 2
    far = box_part("wardrobe", (8.0, -1.5, 1.0), (1.0, 0.6, 2.0), rgb=(200, 160, 40))  # id 3
    scene = l_scene([BED, behind, far])
    assert [(o.id, o.category) for o in scene.annotations.objects] == [
        (1, "bed"),
        (2, "piano"),
        (3, "wardrobe"),
    ]
    instruction, reason = _writer(scene, min_landmarks=0, max_landmark_distance=3.0).write(
        l_episode(), walk([(0, 0, 0), (8, 0, 0), (8, 8, 0)]), np.random.default_rng(0)
    )
    assert reason is None
    ids = {lm.object_id for lm in instruction.landmarks}
    assert 2 not in ids  # never in front of the camera
    assert 3 in ids  # seen at the corner: the control that a landmark can be found here
    instruction, _ = _writer(l_scene([BED, far]), min_landmarks=0, max_landmark_distance=0.5).write(
        l_episode(), walk(L_PATH), np.random.default_rng(0)
    )
    assert instruction.landmarks == []


def test_bad_alignment_drops_and_bad_input_raises():
    scene = l_scene([BED, SOFA, CABINET, PLANT])
    elsewhere = walk([(0, 0, 0), (8, 0, 0), (8, -8, 0)])  # turned right instead of left
    instruction, reason = _writer(scene).write(l_episode(), elsewhere, np.random.default_rng(0))
    assert instruction is None and reason.startswith("alignment_failed")
    with pytest.raises(ValueError, match=r"episode .* is of scene other"):
        _writer(scene).write(l_episode("other"), walk(L_PATH), np.random.default_rng(0))
    with pytest.raises(ValueError, match=r"\(K, 8\)"):
        _writer(scene).write(l_episode(), np.zeros((4, 3)), np.random.default_rng(0))


# ---------------------------------------------------------------------------------------------- real scenes


@pytest.fixture(scope="module")
def written(apartment: Scene, verified_vln):
    episodes, results = verified_vln
    writer = InstructionWriter(apartment, camera_to_base=SPOT.camera_to_base)
    out = []
    for episode, result in zip(episodes, results, strict=True):
        if result.accepted:
            rng = np.random.default_rng(int(episode.episode_id[-4:]))
            out.append((episode, result.trajectory, *writer.write(episode, result.trajectory, rng)))
    return out


def test_landmarks_in_a_furnished_building_exist_and_are_visible_along_the_rollout(apartment: Scene, written):
    objects = {o.id: o for o in apartment.annotations.objects}
    renderer = SceneRenderer(apartment, intrinsics=CameraIntrinsics.from_hfov(320, 240, 90.0))
    instructions = [(e, t, i) for e, t, i, _ in written if i is not None]
    assert len(instructions) >= 5
    for episode, trajectory, instruction in instructions:
        assert len(instruction.landmarks) >= 2
        goal_ids = {g.object_id for g in episode.goals}
        times = [0.0, *instruction.directive_times]
        for landmark in instruction.landmarks:
            obj = objects[landmark.object_id]  # a real object of the scene...
            assert landmark.category == obj.category and landmark.object_id not in goal_ids
            assert landmark.category.replace("_", " ") in instruction.instruction_text.lower()
            # ...that this test's own camera sees from the rollout, up to its step's directive.
            lo, hi = times[landmark.step], times[landmark.step + 1]
            if landmark.step == 0:
                hi = times[2]  # the start's landmark is seen on the first segment
            rows = trajectory[(trajectory[:, 0] >= lo - 1e-6) & (trajectory[:, 0] <= hi + 1e-6)][::3]
            poses = np.tile(np.eye(4), (len(rows), 1, 1))
            from scipy.spatial.transform import Rotation

            poses[:, :3, :3] = Rotation.from_quat(rows[:, 4:8]).as_matrix()
            poses[:, :3, 3] = rows[:, 1:4]
            pixels = max(
                int((f.semantic == obj.id).sum()) for f in renderer.render_batch(poses @ SPOT.camera_to_base)
            )
            assert pixels >= 100, (episode.episode_id, landmark)


def test_instructions_have_no_distances_and_varied_wording(written):
    texts = [i.instruction_text for _, _, i, _ in written if i is not None]
    assert len(texts) == len(set(texts))
    for text in texts:
        assert not NO_DIGITS.search(text), text
        assert not re.search(r"\b(meters?|metres?|m)\b", text), text
    openings = {" ".join(t.split()[:2]) for t in texts}
    assert len(openings) >= 3
    # The templates carry the distances instead.
    assert all(re.search(r"about \d+ meters?", i.template_text) for _, _, i, _ in written if i is not None)


def test_same_seed_same_instruction_other_seed_other_wording(apartment: Scene, written):
    episode, trajectory, instruction, _ = next(w for w in written if w[2] is not None)
    writer = InstructionWriter(apartment, camera_to_base=SPOT.camera_to_base)
    seed = int(episode.episode_id[-4:])
    again, _ = writer.write(episode, trajectory, np.random.default_rng(seed))
    assert again == instruction
    others = [writer.write(episode, trajectory, np.random.default_rng(s))[0] for s in range(100, 108)]
    assert {o.landmarks == instruction.landmarks for o in others} == {True}  # wording only
    assert len({o.instruction_text for o in others}) >= 3


# ---------------------------------------------------------------------------------------------- plug-in


def test_a_refiner_receives_keyframes_and_the_template():
    calls = []

    def refiner(keyframes, template, landmark_text, episode):
        calls.append((keyframes, template, landmark_text, episode))
        return "  Walk to the blue sofa, then left past the red cabinet to the bed.  "

    scene = l_scene([BED, SOFA, CABINET, PLANT])
    writer = InstructionWriter(
        scene, camera_to_base=SPOT.camera_to_base, refiner=refiner,
        settings=InstructionSettings(keyframe_resolution=(64, 48)),
    )  # fmt: skip
    instruction, _ = writer.write(l_episode(), walk(L_PATH), np.random.default_rng(0))
    ((keyframes, template, landmark_text, episode),) = calls
    assert len(keyframes) == 3 and all(k.shape == (48, 64, 3) and k.dtype == np.uint8 for k in keyframes)
    assert keyframes[0].std() > 0  # rendered, not blank
    assert "about 8 meters" in template and "blue sofa" in landmark_text and episode.task == "vln"
    assert instruction.instruction_type == "refined"
    assert instruction.instruction_text == "Walk to the blue sofa, then left past the red cabinet to the bed."
    assert instruction.template_text == template

    writer = InstructionWriter(scene, camera_to_base=SPOT.camera_to_base, refiner=lambda *a: None)
    assert writer.write(l_episode(), walk(L_PATH), np.random.default_rng(0))[1].startswith("refiner_declined")
    writer = InstructionWriter(scene, camera_to_base=SPOT.camera_to_base, refiner=lambda *a: 42)
    with pytest.raises(RefinerError, match="must return the instruction text"):
        writer.write(l_episode(), walk(L_PATH), np.random.default_rng(0))


def test_load_refiner(tmp_path, monkeypatch):
    (tmp_path / "my_vlm.py").write_text(
        "LIMIT = 3\n\ndef refine(keyframes, template, text, episode):\n    return text.upper()\n"
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    assert load_refiner("my_vlm:refine")([], "", "go", None) == "GO"
    with pytest.raises(RefinerError, match=r"package\.module:function"):
        load_refiner("my_vlm.refine")
    with pytest.raises(RefinerError, match="no module named 'no_such_vlm'"):
        load_refiner("no_such_vlm:refine")
    with pytest.raises(RefinerError, match="has no attribute 'rewrite'"):
        load_refiner("my_vlm:rewrite")
    with pytest.raises(RefinerError, match="is a int, not a callable"):
        load_refiner("my_vlm:LIMIT")
    sys.modules.pop("my_vlm", None)
