"""A bird's-eye picture of a city's people and traffic: their tracks over some seconds on its navmesh.

Usage::

    python scripts/dynamics_views.py west-oakland [--seconds 30] [--size 160] [--out docs/img]

For a built city scene (``navverse build <scene>``: navmesh and look) it runs the scene's dynamics
(``navverse.dynamics.scene_dynamics``, mode ``full``, seed ``--seed``) for ``--seconds`` at 10 Hz and
writes

- ``dynamics_<scene>_bev.png``: over a ``--size`` meter window round the busiest crossing, the navmesh
  by terrain class, each person's track (ending in a dot) and each car's (ending in its outline);
- ``dynamics_<scene>_camera.png``: the robot's camera (640 x 480, 0.6 m up, the scene's look) at the
  end, from the navigable point 8-20 m from that crossing whose view towards it holds the most people
  and cars (none within 3 m of it): RGB beside the semantic image.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Patch
from matplotlib.patches import Polygon as PolygonPatch
from render_frames import panel, rgb_image, semantic_image

from navverse.dynamics.runtime import PERSON_ID_BASE, BodyPainter
from navverse.dynamics.scene_dynamics import DynamicsSettings, SceneDynamics
from navverse.dynamics.streets import crossings_of
from navverse.dynamics.traffic import CAR_LENGTH
from navverse.errors import NavverseError
from navverse.look.files import load_scene_look
from navverse.nav.scene_navmesh import load_scene_navmesh
from navverse.scene.directory import read_scene
from navverse.sim.camera import look_at
from navverse.sim.render import SceneRenderer
from pipeline.workspace import Workspace

AREA_COLORS = {
    "road": "#6b6b6b",
    "crosswalk": "#f2f2f2",
    "sidewalk": "#c9c9c9",
    "curb": "#a0a0a0",
    "parking": "#8a8a8a",
    "ground": "#e8e0cf",
    "green": "#b9d9a5",
}
CAR_WIDTH = 1.8


def car_outline(xy: np.ndarray, heading: float) -> np.ndarray:
    """The four corners of a car at `xy` facing `heading`."""
    forward = np.array([np.cos(heading), np.sin(heading)])
    left = np.array([-forward[1], forward[0]])
    half_l, half_w = CAR_LENGTH / 2.0, CAR_WIDTH / 2.0
    return np.array(
        [xy + s * half_l * forward + t * half_w * left for s, t in ((1, 1), (1, -1), (-1, -1), (-1, 1))]
    )


def camera_view(scene_dir: Path, finder, state, centre: np.ndarray, out: Path, scene_id: str) -> Path:
    """The robot's camera looking at `centre` from where it sees the most people and cars."""
    scene = read_scene(scene_dir)
    renderer = SceneRenderer(scene, look=load_scene_look(scene, scene_dir))
    painter = BodyPainter(renderer, max_people=len(state.people), max_cars=len(state.cars))
    painter.show(state)
    best, best_count = None, -1
    for distance in (8.0, 12.0, 16.0, 20.0):
        for angle in np.linspace(0.0, 2.0 * np.pi, 16, endpoint=False):
            spot = centre + distance * np.array([np.cos(angle), np.sin(angle)])
            snapped = finder.snap_point((spot[0], spot[1], 0.0), max_vertical=3.0, max_horizontal=1.0)
            if not np.isfinite(snapped).all():
                continue
            bodies = np.concatenate([state.people[:, :2], state.cars[:, :2]])
            if len(bodies) and np.linalg.norm(bodies - snapped[:2], axis=1).min() < 3.0:
                continue  # not in (or against) a person or a car
            eye = snapped + np.array([0.0, 0.0, 0.6])
            pose = look_at(eye, np.array([centre[0], centre[1], eye[2]]))
            seen, pixels = np.unique(renderer.render(pose).semantic, return_counts=True)
            count = int(((seen >= PERSON_ID_BASE) & (pixels >= 40)).sum())  # bodies seen, not pixels
            if count > best_count:
                best, best_count = pose, count
    frame = renderer.render(best)
    categories = BodyPainter.categories(state)
    picture = panel(
        [
            rgb_image(frame, f"{scene_id}, robot camera"),
            semantic_image(frame, renderer.class_names, categories),
        ],
        ["RGB", "semantic"],
    )
    target = out / f"dynamics_{scene_id}_camera.png"
    picture.save(target)
    return target


def draw(scene_id: str, *, seconds: float, size: float, seed: int, out: Path) -> Path:
    """Run the dynamics and write the pictures; returns the bird's-eye one's path."""
    scene_dir = Workspace.find().built_dir / "targets" / scene_id / "scene"
    finder = load_scene_navmesh(scene_dir)
    dynamics = SceneDynamics(scene_dir, finder, DynamicsSettings(mode="full"), seed=seed)
    states = [dynamics.step(0.1) for _ in range(round(seconds / 0.1))]
    people = np.array([s.people[:, :2] for s in states])  # (T, P, 2)
    cars = np.array([s.cars[:, :2] for s in states])  # (T, C, 2)
    crossings = crossings_of(finder)
    if len(crossings):  # centre the window on the crossing with the most people passing near it
        visits = [(np.linalg.norm(people.reshape(-1, 2) - c, axis=1) < 30.0).sum() for c in crossings]
        centre = crossings[int(np.argmax(visits))]
    else:
        centre = people.reshape(-1, 2).mean(axis=0)
    low, high = centre - size / 2.0, centre + size / 2.0

    fig, ax = plt.subplots(figsize=(9, 9), dpi=110)
    names = {v: k for k, v in finder.area_names.items()}
    for polygon, area in zip(finder.polygons(), finder.polygon_area_types(), strict=True):
        xy = polygon[:, :2]
        if (xy.max(axis=0) < low).any() or (xy.min(axis=0) > high).any():
            continue
        color = AREA_COLORS.get(names.get(int(area), ""), "#dddddd")
        ax.add_patch(PolygonPatch(xy, closed=True, facecolor=color, edgecolor=color, linewidth=0.3))
    for p in range(people.shape[1]):
        track = people[:, p]
        ax.plot(track[:, 0], track[:, 1], color="#1f5fbf", linewidth=0.8, alpha=0.8)
        ax.plot(track[-1, 0], track[-1, 1], "o", color="#1f5fbf", markersize=3)
    for c in range(cars.shape[1]):
        track = cars[:, c]
        jumps = np.flatnonzero(np.linalg.norm(np.diff(track, axis=0), axis=1) > 5.0)  # a car re-entering
        for piece in np.split(track, jumps + 1):
            ax.plot(piece[:, 0], piece[:, 1], color="#c0392b", linewidth=1.6, alpha=0.85)
        ax.add_patch(PolygonPatch(car_outline(track[-1], states[-1].car_headings[c]), closed=True,
                                  facecolor="#c0392b", edgecolor="black", linewidth=0.5))  # fmt: skip
    ax.set_xlim(low[0], high[0])
    ax.set_ylim(low[1], high[1])
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(
        f"{scene_id}: {people.shape[1]} people and {cars.shape[1]} cars over {seconds:.0f} s (seed {seed})"
    )
    legend = [Patch(color=c, label=a) for a, c in AREA_COLORS.items() if a in finder.area_names]
    legend += [Patch(color="#1f5fbf", label="people"), Patch(color="#c0392b", label="cars")]
    ax.legend(handles=legend, loc="upper right", fontsize=7, framealpha=0.9)
    out.mkdir(parents=True, exist_ok=True)
    target = out / f"dynamics_{scene_id}_bev.png"
    fig.savefig(target, bbox_inches="tight")
    plt.close(fig)
    camera_view(scene_dir, finder, states[-1], centre, out, scene_id)
    return target


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", help="a built city scene")
    parser.add_argument("--seconds", type=float, default=30.0)
    parser.add_argument("--size", type=float, default=160.0, help="window side (m)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=Path("docs/img"))
    args = parser.parse_args(argv)
    try:
        print(f"wrote {draw(args.scene, seconds=args.seconds, size=args.size, seed=args.seed, out=args.out)}")
    except NavverseError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
