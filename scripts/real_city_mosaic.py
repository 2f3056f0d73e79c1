"""A mosaic of the bird's-eye views of the built real-city scenes, for the README.

    python scripts/real_city_mosaic.py [--root DIR] [--out docs/img/real-cities.png] [--columns 10]

Reads ``<root>/data/built/targets/<id>/scene/bev.png`` (root: this project) of every recipe in
``recipes/scenes/real-cities`` (build them first, by name: ``navverse build $(ls
recipes/scenes/real-cities | sed 's/.yaml$//')``),
labels each tile with its id and writes one PNG; scenes not built are tiles that say so.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

PROJECT = Path(__file__).resolve().parents[1]
RECIPES = PROJECT / "recipes" / "scenes" / "real-cities"


def _tile(image_path: Path, size: int) -> np.ndarray | None:
    """The BEV picture resampled to ``size`` × ``size`` RGB (nearest pixel), or None if missing."""
    import matplotlib.image as mpimg

    if not image_path.is_file():
        return None
    image = mpimg.imread(image_path)
    if image.dtype != np.uint8:
        image = (np.clip(image, 0.0, 1.0) * 255).astype(np.uint8)
    image = image[..., :3]
    rows = np.linspace(0, image.shape[0] - 1, size).astype(int)
    cols = np.linspace(0, image.shape[1] - 1, size).astype(int)
    return image[rows][:, cols]


def mosaic(ids: list[str], out: Path, *, built_dir: Path, columns: int, tile: int) -> int:
    """Write the mosaic of the scenes ``ids`` under ``built_dir`` (``data/built/targets``); returns
    how many were built."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = math.ceil(len(ids) / columns)
    figure = plt.figure(figsize=(columns * tile / 100.0, rows * (tile + 22) / 100.0), dpi=100)
    built = 0
    for n, scene_id in enumerate(ids):
        axes = figure.add_subplot(rows, columns, n + 1)
        axes.set_axis_off()
        picture = _tile(built_dir / scene_id / "scene" / "bev.png", tile)
        if picture is None:
            axes.text(0.5, 0.5, "not built", ha="center", va="center", fontsize=8)
        else:
            axes.imshow(picture, interpolation="nearest")
            built += 1
        axes.set_title(scene_id, fontsize=8, pad=2)
    figure.subplots_adjust(left=0.005, right=0.995, top=0.985, bottom=0.005, wspace=0.03, hspace=0.12)
    out.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(out)
    plt.close(figure)
    return built


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--root", type=Path, default=PROJECT, help="the workspace the scenes were built in")
    parser.add_argument("--out", type=Path, default=PROJECT / "docs" / "img" / "real-cities.png")
    parser.add_argument("--columns", type=int, default=10)
    parser.add_argument("--tile", type=int, default=240, help="pixels per tile")
    args = parser.parse_args()
    ids = sorted(p.stem for p in RECIPES.glob("*.yaml"))
    built_dir = args.root / "data" / "built" / "targets"
    built = mosaic(ids, args.out, built_dir=built_dir, columns=args.columns, tile=args.tile)
    print(f"wrote {args.out}: {built} of {len(ids)} real-city scenes built")
    return 0


if __name__ == "__main__":
    sys.exit(main())
