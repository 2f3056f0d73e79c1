"""A mosaic of the bird's-eye views of the built real-city scenes, for the README.

    python scripts/real_city_mosaic.py [--root DIR] [--out docs/img/real-cities.png] [--columns 10]

Ray-casts from above the built scene ``<root>/data/built/targets/<id>/scene`` (root: this project) of
every recipe in
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


def _tile(scene_dir: Path, size: int) -> np.ndarray | None:
    """The scene ray-cast from above (:func:`~navverse.scene.bev.raster_bev`: terrain, buildings and
    objects, shaded), resampled to ``size`` × ``size`` RGB; None if it is not built."""
    from navverse.scene.bev import raster_bev
    from navverse.scene.scene_cache import cached_scene

    if not (scene_dir / "scene.json").is_file():
        return None
    scene = cached_scene(scene_dir)
    (x0, y0, _), (x1, y1, _) = scene.annotations.bounds.min, scene.annotations.bounds.max
    image = raster_bev(scene, meters_per_pixel=max(x1 - x0, y1 - y0) / size).rgb
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
        picture = _tile(built_dir / scene_id / "scene", tile)
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
    parser.add_argument("--tile", type=int, default=220, help="pixels per tile")
    args = parser.parse_args()
    ids = sorted(p.stem for p in RECIPES.glob("*.yaml"))
    built_dir = args.root / "data" / "built" / "targets"
    built = mosaic(ids, args.out, built_dir=built_dir, columns=args.columns, tile=args.tile)
    print(f"wrote {args.out}: {built} of {len(ids)} real-city scenes built")
    return 0


if __name__ == "__main__":
    sys.exit(main())
