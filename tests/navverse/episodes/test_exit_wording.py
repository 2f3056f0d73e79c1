"""Routes that leave a building say so at the directive during which the robot walks out."""

from __future__ import annotations

import numpy as np

from navverse.episodes.instructions.directives import plan_directives
from navverse.episodes.instructions.wording import landmark_text


def test_the_exit_is_told_at_its_directive() -> None:
    directives = plan_directives([(1.0, 1.0, 0.0), (9.0, 1.0, 0.0), (9.0, 20.0, 0.0), (25.0, 20.0, 0.0)], 0.0)
    assert len(directives) == 4
    for seed in range(8):
        text = landmark_text(
            directives, [None] * 4, "bank", goal_seen=True, rng=np.random.default_rng(seed), exit_at=1
        )
        lowered = text.lower()
        said = [lowered.find(w) for w in ("building", "exit") if w in lowered]
        assert len(said) == 1, text  # said once
        # after the left turn (directive 1), before the right turn (directive 2)
        assert lowered.find("left") < said[0] < lowered.find("right"), text
    plain = landmark_text(directives, [None] * 4, "bank", goal_seen=True, rng=np.random.default_rng(0))
    assert "building" not in plain and "exit" not in plain
