"""Render a contact sheet of procedural storefronts, one per place category, seen from the street.

Usage::

    python scripts/storefront_gallery.py [--out docs/img/storefront_gallery.png] [--seed 3] [--columns 4]

Each panel is an orthographic front view from +y (so +x runs to the viewer's left): faces are painted
far to near in their part colour, lightly shaded by their normal, glass faces half transparent, and
the sign image is drawn onto the sign rectangle (with ``u = 0`` at the board's largest x, as the
mesh's UVs map it).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.collections import PolyCollection

from navverse.assets.facade.storefronts import DESIGNS_PER_CATEGORY, PLACE_CATEGORIES, Storefront, storefront


def front_polygons(front: Storefront) -> tuple[np.ndarray, np.ndarray]:
    """Projected triangles ``(K, 3, 2)`` in (-x, z) facing +y, far to near, and their RGBA colours."""
    mesh = front.mesh
    tri = mesh.vertices[mesh.faces]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
    visible = normals[:, 1] > 1e-6
    order = np.argsort(tri[:, :, 1].max(axis=1)[visible], kind="stable")
    keep = np.flatnonzero(visible)[order]
    assert mesh.face_colors is not None
    shade = 0.72 + 0.28 * normals[keep, 1] + 0.1 * np.clip(normals[keep, 2], 0.0, 1.0)
    rgba = np.ones((keep.size, 4))
    rgba[:, :3] = np.clip(mesh.face_colors[keep] / 255.0 * shade[:, None], 0.0, 1.0)
    rgba[front.glass_faces[keep], 3] = 0.35
    projected = np.stack([-tri[keep, :, 0], tri[keep, :, 2]], axis=-1)
    return projected, rgba


def draw(ax: plt.Axes, front: Storefront) -> None:
    """Draw one storefront's front view with its sign image into a 2-D axes."""
    polygons, colors = front_polygons(front)
    edges = colors.copy()
    edges[edges[:, 3] < 1.0, 3] = 0.0  # outlined translucent glass would show its triangle seams
    ax.add_collection(PolyCollection(polygons, facecolors=colors, edgecolors=edges, linewidths=0.6))
    cx, _, cz = front.sign_center
    w, h = front.sign_size
    ax.imshow(
        front.sign_image, extent=(-(cx + 0.5 * w), -(cx - 0.5 * w), cz - 0.5 * h, cz + 0.5 * h), zorder=3
    )
    width, _, height = front.size
    ax.set_xlim(-0.5 * width - 0.1, 0.5 * width + 0.1)
    ax.set_ylim(-0.5 * height - 0.1, 0.5 * height + 0.1)
    ax.set_aspect("equal")
    ax.set_axis_off()
    ax.set_title(f"{front.category} (design {front.design})\n{front.name}", fontsize=8, pad=2)


def render(out: Path, *, seed: int, columns: int, dpi: int) -> None:
    """Build one storefront per category (designs cycling) and save the contact sheet."""
    rows = -(-len(PLACE_CATEGORIES) // columns)
    fig, axes = plt.subplots(rows, columns, figsize=(3.4 * columns, 2.3 * rows))
    for ax in axes.ravel():
        ax.set_axis_off()
    for k, (ax, category) in enumerate(zip(axes.ravel(), PLACE_CATEGORIES, strict=False)):
        rng = np.random.default_rng(seed + k)
        draw(ax, storefront(category, rng, design=k % DESIGNS_PER_CATEGORY, width=6.0))
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=dpi)
    plt.close(fig)


def main() -> None:
    """Parse the command line and render."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("docs/img/storefront_gallery.png"))
    parser.add_argument("--seed", type=int, default=3)
    parser.add_argument("--columns", type=int, default=4)
    parser.add_argument("--dpi", type=int, default=110)
    args = parser.parse_args()
    render(args.out, seed=args.seed, columns=args.columns, dpi=args.dpi)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
