"""Render a contact sheet of every object category of the asset library.

Usage::

    python scripts/asset_gallery.py [--out docs/img/asset_gallery.png] [--seed 7] [--only chair sofa]
                                    [--set indoor|outdoor|all]

Each panel shows one object (sampled size, fixed seed) from the front-right, with its faces coloured
by their part colour and shaded by a fixed directional light, under the category name.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

from navverse.assets.library import asset, categories, make_object
from navverse.scene.geometry import MeshData

_LIGHT = np.array([0.35, 0.75, 0.9]) / np.linalg.norm([0.35, 0.75, 0.9])


def shaded_colors(mesh: MeshData) -> np.ndarray:
    """Face colours (RGB in 0..1) dimmed by the angle between each face normal and a fixed light."""
    tri = mesh.vertices[mesh.faces]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    lengths = np.linalg.norm(normals, axis=1, keepdims=True)
    normals = normals / np.where(lengths > 0, lengths, 1.0)
    intensity = 0.5 + 0.5 * np.clip(normals @ _LIGHT, 0.0, 1.0)
    assert mesh.face_colors is not None
    return np.clip(mesh.face_colors / 255.0 * intensity[:, None], 0.0, 1.0)


def facing_camera(mesh: MeshData, elev: float, azim: float) -> np.ndarray:
    """Mask of the faces whose outward normals point towards a camera at (`elev`, `azim`) degrees.

    Matplotlib sorts polygons by depth only, so hidden back faces of thin parts could be painted over
    the front faces of the parts behind them; culling them avoids that for closed, outward-wound meshes.
    """
    e, a = np.radians(elev), np.radians(azim)
    view = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
    tri = mesh.vertices[mesh.faces]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    return normals @ view > 0


def draw(ax: plt.Axes, mesh: MeshData, title: str, *, elev: float = 22.0, azim: float = 62.0) -> None:
    """Draw one mesh into a 3-D axes, at equal scale on all axes, seen from (`elev`, `azim`)."""
    keep = facing_camera(mesh, elev, azim)
    tri = mesh.vertices[mesh.faces][keep]
    colors = shaded_colors(mesh)[keep]
    # painting by the farthest vertex puts details lying on large faces (screens, doors) over those faces
    ax.add_collection3d(
        Poly3DCollection(tri, facecolors=colors, edgecolors=colors, linewidths=0.3, zsort="max")
    )
    lo, hi = mesh.bounds()
    extent = np.maximum(hi - lo, 0.02 * (hi - lo).max())
    centre = 0.5 * (lo + hi)
    ax.set_xlim(centre[0] - 0.5 * extent[0], centre[0] + 0.5 * extent[0])
    ax.set_ylim(centre[1] - 0.5 * extent[1], centre[1] + 0.5 * extent[1])
    ax.set_zlim(centre[2] - 0.5 * extent[2], centre[2] + 0.5 * extent[2])
    ax.set_box_aspect(tuple(extent))
    ax.view_init(elev=elev, azim=azim)
    ax.set_axis_off()
    size = hi - lo
    ax.set_title(f"{title}\n{size[0]:.2f}×{size[1]:.2f}×{size[2]:.2f} m", fontsize=8, pad=0)


def render(
    out: Path, *, seed: int, only: list[str] | None, columns: int, dpi: int, which: str = "all"
) -> None:
    """Build every category (of ``which`` set) with the same seed and save the contact sheet."""
    names = only or [n for n in categories() if which == "all" or asset(n).outdoor == (which == "outdoor")]
    rows = math.ceil(len(names) / columns)
    fig = plt.figure(figsize=(2.0 * columns, 2.1 * rows))
    for k, name in enumerate(names):
        mesh, _ = make_object(name, np.random.default_rng(seed))
        ax = fig.add_subplot(rows, columns, k + 1, projection="3d")
        draw(ax, mesh, name)
    fig.subplots_adjust(left=0.0, right=1.0, bottom=0.0, top=0.96, wspace=0.0, hspace=0.15)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=dpi)
    plt.close(fig)


def main() -> None:
    """Parse the command line and render."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("docs/img/asset_gallery.png"))
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--only", nargs="*", help="categories to draw (default: all)")
    parser.add_argument("--columns", type=int, default=9)
    parser.add_argument("--dpi", type=int, default=80)
    parser.add_argument("--set", dest="which", choices=("all", "indoor", "outdoor"), default="all")
    args = parser.parse_args()
    render(args.out, seed=args.seed, only=args.only, columns=args.columns, dpi=args.dpi, which=args.which)
    print(f"wrote {args.out} ({args.out.stat().st_size / 1e6:.2f} MB)")


if __name__ == "__main__":
    main()
