"""The one colour draw of every family: a palette by name or a family's own colours, varied in brightness."""

from __future__ import annotations

import numpy as np
import pytest

from navverse.assets.materials import PALETTES, pick, shade


def test_a_family_palette_draws_like_a_named_one():
    for seed in range(20):
        by_name = pick(np.random.default_rng(seed), "fabric", variation=0.05)
        by_colours = pick(np.random.default_rng(seed), PALETTES["fabric"], variation=0.05)
        assert by_name == by_colours


def test_the_brightness_varies_within_its_range():
    colours = ((200, 100, 50), (10, 20, 30))
    for seed in range(20):
        rng, twin = np.random.default_rng(seed), np.random.default_rng(seed)
        base = colours[int(twin.integers(len(colours)))]
        assert pick(rng, colours, variation=0.05) == shade(base, 1.0 + float(twin.uniform(-0.05, 0.05)))
        rng, twin = np.random.default_rng(seed), np.random.default_rng(seed)
        base = colours[int(twin.integers(len(colours)))]
        assert pick(rng, colours, brightness=(0.94, 1.06)) == shade(base, float(twin.uniform(0.94, 1.06)))
    drawn = np.array([pick(np.random.default_rng(s), ((200, 200, 200),), variation=0.1) for s in range(50)])
    assert drawn.min() >= 180 and drawn.max() <= 220 and len(np.unique(drawn)) > 10


def test_an_unknown_palette_is_a_programming_error():
    with pytest.raises(KeyError):
        pick(np.random.default_rng(0), "plaid")
