"""A spatial index that grows: shapes added one at a time, found by the grid cells they cover.

An STR tree is built once over a fixed set of shapes; placement loops (street objects, groups,
ground pieces) add a shape after each query, so they index by a uniform grid of ``cell`` metres
instead. A shape is listed in every cell its envelope covers; queries return each shape once, in the
order the shapes were added, so results never depend on hashing.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

from shapely.geometry.base import BaseGeometry

__all__ = ["ShapeGrid"]


class ShapeGrid:
    """Shapes by grid cell.

    Parameters
    ----------
    cell : float
        Cell size (m): about the size of the shapes or of the query distances.
    """

    def __init__(self, cell: float) -> None:
        self.cell = cell
        self.shapes: list[BaseGeometry] = []
        self._cells: dict[tuple[int, int], list[int]] = {}

    def _keys(self, bounds: tuple[float, float, float, float], grow: float) -> Iterator[tuple[int, int]]:
        c = self.cell
        x0, y0, x1, y1 = bounds
        for i in range(math.floor((x0 - grow) / c), math.floor((x1 + grow) / c) + 1):
            for j in range(math.floor((y0 - grow) / c), math.floor((y1 + grow) / c) + 1):
                yield (i, j)

    def add(self, shape: BaseGeometry) -> None:
        """Index ``shape`` (non-empty)."""
        index = len(self.shapes)
        self.shapes.append(shape)
        for key in self._keys(shape.bounds, 0.0):
            self._cells.setdefault(key, []).append(index)

    def candidates(self, shape: BaseGeometry, grow: float = 0.0) -> list[BaseGeometry]:
        """The shapes in the cells of ``shape``'s envelope grown by ``grow``, in the order added."""
        if shape.is_empty:
            return []
        found = {i for key in self._keys(shape.bounds, grow) for i in self._cells.get(key, ())}
        return [self.shapes[i] for i in sorted(found)]

    def near(self, shape: BaseGeometry, distance: float) -> bool:
        """Whether any shape lies closer than ``distance`` to ``shape``."""
        return any(shape.distance(other) < distance for other in self.candidates(shape, distance))

    def meeting(self, shape: BaseGeometry) -> list[BaseGeometry]:
        """The shapes whose envelopes meet ``shape``'s, in the order added."""
        envelope = shape.envelope
        return [other for other in self.candidates(shape) if other.envelope.intersects(envelope)]
