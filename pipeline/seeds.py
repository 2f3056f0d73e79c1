"""Seeds derived from (recipe seed, target id, stage name); no global random state anywhere."""

from __future__ import annotations

import hashlib

import numpy as np


def derive_seed(recipe_seed: int, target_id: str, stage_name: str) -> int:
    """A 63-bit seed that depends only on the recipe seed, the target id and the stage name."""
    text = f"{recipe_seed}\x00{target_id}\x00{stage_name}".encode()
    return int.from_bytes(hashlib.sha256(text).digest()[:8], "little") >> 1


def make_rng(seed: int) -> np.random.Generator:
    """The generator a stage receives for ``seed`` (PCG64)."""
    return np.random.Generator(np.random.PCG64(seed))
