"""Where the toolkit caches derived data: ``$NAVVERSE_CACHE_DIR``, default ``~/.cache/navverse``."""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["cache_root"]


def cache_root() -> Path:
    """The cache folder (``$NAVVERSE_CACHE_DIR``, else ``~/.cache/navverse``); not created here."""
    return Path(os.environ.get("NAVVERSE_CACHE_DIR") or Path.home() / ".cache" / "navverse")
