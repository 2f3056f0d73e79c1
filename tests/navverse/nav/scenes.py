"""Test geometry for the navmesh: closed boxes and ramps (numpy only), and analytic path lengths."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.spatial import ConvexHull

from navverse.assets.primitives import HEXAHEDRON_FACES

FLOOR = 1  # area types used by the tests
WALL = 0  # never walkable
ROUTE_B = 2


@dataclass
class MeshBuilder:
    """Accumulates closed solids into one triangle mesh with an area type per triangle."""

    vertices: list[np.ndarray] = field(default_factory=list)
    faces: list[np.ndarray] = field(default_factory=list)
    areas: list[np.ndarray] = field(default_factory=list)
    _count: int = 0

    def _add(self, corners: np.ndarray, area: int) -> MeshBuilder:
        self.vertices.append(corners)
        self.faces.append(HEXAHEDRON_FACES + self._count)
        self.areas.append(np.full(len(HEXAHEDRON_FACES), area, dtype=np.uint8))
        self._count += len(corners)
        return self

    def box(self, lo: Sequence[float], hi: Sequence[float], area: int = FLOOR) -> MeshBuilder:
        """An axis-aligned box from corner ``lo`` to corner ``hi``."""
        (x0, y0, z0), (x1, y1, z1) = lo, hi
        corners = np.array(
            [[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0],
             [x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]],
            dtype=float,
        )  # fmt: skip
        return self._add(corners, area)

    def ramp(
        self,
        x0: float,
        x1: float,
        y0: float,
        y1: float,
        *,
        base: float,
        z0: float,
        z1: float,
        area: int = FLOOR,
    ) -> MeshBuilder:
        """A solid whose top rises along +x from height ``z0`` at ``x0`` to ``z1`` at ``x1``."""
        corners = np.array(
            [[x0, y0, base], [x1, y0, base], [x1, y1, base], [x0, y1, base],
             [x0, y0, z0], [x1, y0, z1], [x1, y1, z1], [x0, y1, z0]],
            dtype=float,
        )  # fmt: skip
        return self._add(corners, area)

    def walls(
        self, x0: float, y0: float, x1: float, y1: float, *, t: float = 0.2, h: float = 2.5
    ) -> MeshBuilder:
        """Four walls of thickness ``t`` just outside the rectangle [x0, x1] x [y0, y1]."""
        self.box((x0 - t, y0 - t, 0), (x1 + t, y0, h), WALL)
        self.box((x0 - t, y1, 0), (x1 + t, y1 + t, h), WALL)
        self.box((x0 - t, y0, 0), (x0, y1, h), WALL)
        return self.box((x1, y0, 0), (x1 + t, y1, h), WALL)

    def floor(
        self, x0: float, y0: float, x1: float, y1: float, *, z: float = 0.0, area: int = FLOOR
    ) -> MeshBuilder:
        """A 0.1 m slab whose top is at height ``z``."""
        return self.box((x0, y0, z - 0.1), (x1, y1, z), area)

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(vertices (N, 3), faces (M, 3), area types (M,))."""
        return np.vstack(self.vertices), np.vstack(self.faces), np.concatenate(self.areas)


def corridor() -> MeshBuilder:
    """A straight corridor 20 m long, 2.4 m wide: walkable y in [-0.6, 0.6] after erosion."""
    return MeshBuilder().floor(0, -1.2, 20, 1.2).walls(0, -1.2, 20, 1.2)


L_CORNER = (9.0, 3.0)


def l_corridor() -> MeshBuilder:
    """An L: leg A along x (y in [0, 3]) and leg B along y (x in [9, 12]); inner corner at (9, 3)."""
    b = MeshBuilder().floor(0, 0, 12, 12).walls(0, 0, 12, 12)
    return b.box((0, 3, 0), (9, 12, 2.5), WALL)


BOX_OBSTACLE = (6.0, 2.5, 8.0, 5.5)  # x0, y0, x1, y1


def box_room() -> MeshBuilder:
    """A 14 m x 8 m room with a 2 m x 3 m box in its middle."""
    x0, y0, x1, y1 = BOX_OBSTACLE
    return MeshBuilder().floor(0, 0, 14, 8).walls(0, 0, 14, 8).box((x0, y0, 0), (x1, y1, 1.0), WALL)


def two_rooms() -> MeshBuilder:
    """Two walled rooms, 5 m x 5 m and 6 m x 5 m, 2 m apart, no connection."""
    return MeshBuilder().floor(0, 0, 5, 5).walls(0, 0, 5, 5).floor(7, 0, 13, 5).walls(7, 0, 13, 5)


def step(height: float) -> MeshBuilder:
    """A 4 m wide floor (x in [0, 10]) with a platform ``height`` higher on x in [5, 10]."""
    return MeshBuilder().floor(0, 0, 10, 4).box((5, 0, 0), (10, 4, height), FLOOR)


RAMP_RISE = 1.0


def ramp(angle_deg: float) -> tuple[MeshBuilder, float]:
    """Floor, a ramp rising 1 m at ``angle_deg`` from x = 3, then a platform 3 m long.

    Returns the builder and the x where the platform starts.
    """
    run = RAMP_RISE / np.tan(np.radians(angle_deg))
    x1 = 3.0 + run
    b = MeshBuilder().floor(0, 0, x1 + 3.0, 4)
    b.ramp(3.0, x1, 0, 4, base=-0.1, z0=0.0, z1=RAMP_RISE)
    b.box((x1, 0, -0.1), (x1 + 3.0, 4, RAMP_RISE))
    return b, x1


def two_routes() -> MeshBuilder:
    """A 20 m x 9 m hall split by a 14 m wall: a south route (area 1) and a north route (area 2).

    The wall spans x in [3, 17], y in [-1, 1]; the north strip y in [1, 4.5] has area type 2.
    """
    b = MeshBuilder().floor(0, -4.5, 20, 1).floor(3, 1, 17, 4.5, area=ROUTE_B)
    b.floor(0, 1, 3, 4.5).floor(17, 1, 20, 4.5).walls(0, -4.5, 20, 4.5)
    return b.box((3, -1, 0), (17, 1, 2.5), WALL)


def hall_with_pillars() -> MeshBuilder:
    """A 30 m x 20 m hall with scattered boxes, for tiled vs single-tile builds."""
    b = MeshBuilder().floor(0, 0, 30, 20).walls(0, 0, 30, 20)
    for x, y, sx, sy in [(5, 4, 2, 1), (12, 10, 1.5, 6), (20, 3, 3, 3), (24, 14, 1, 1), (8, 15, 4, 0.8)]:
        b.box((x, y, 0), (x + sx, y + sy, 2.0), WALL)
    return b


def disc(center: Sequence[float], radius: float, n: int = 1440) -> np.ndarray:
    """Points on a circle (n of them), shape (n, 2)."""
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.column_stack([center[0] + radius * np.cos(t), center[1] + radius * np.sin(t)])


def taut_path_length(a: Sequence[float], b: Sequence[float], obstacles: Sequence[np.ndarray]) -> float:
    """Length of the shortest 2-D path from a to b that wraps around convex obstacles.

    The path is a chain of the convex hull of {a, b, obstacles}: of the two chains from a to b, the
    shorter one that touches an obstacle (the other may be the blocked straight segment).
    """
    pts = np.vstack([np.asarray(a, float)[:2], np.asarray(b, float)[:2], *obstacles])
    order = list(ConvexHull(pts).vertices)  # counter-clockwise
    ia, ib = order.index(0), order.index(1)
    best = np.inf
    for i, j in ((ia, ib), (ib, ia)):
        chain = [order[i]]
        k = i
        while k != j:
            k = (k + 1) % len(order)
            chain.append(order[k])
        if any(idx >= 2 for idx in chain):
            best = min(best, float(np.linalg.norm(np.diff(pts[chain], axis=0), axis=1).sum()))
    return best
