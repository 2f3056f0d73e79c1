"""Quick bird's-eye pictures of a city map, drawn straight from its features (no scene is built).

:func:`draw_city_map` writes one map as a PNG; :func:`draw_city_mosaic` writes several side by side.
Land areas are filled by class, roads are lines of their carriageway width over their sidewalks,
walkways lines of their width, buildings filled and outlined, POIs dots; colours are those of the
terrain classes of a scene's BEV (:data:`~navverse.scene.terrain.DEFAULT_TERRAIN_CLASSES`). Drawn with
matplotlib's Agg canvas, imported when a picture is drawn; the same map gives the same picture.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from navverse.city.map import CityMap, Polygon2
from navverse.files import atomic_path
from navverse.scene.terrain import DEFAULT_TERRAIN_CLASSES

__all__ = ["MAP_BACKGROUND", "draw_city_map", "draw_city_mosaic"]

MAP_BACKGROUND = (236, 234, 228)
"""Colour of what no feature covers."""
_AREA_TERRAIN = {
    "green": "green",
    "water": "water",
    "ground": "ground",
    "parking": "parking",
    "plaza": "plaza",
    "pedestrian": "plaza",
}
"""The terrain class whose colour each land class is drawn in."""
_POI_COLOUR = (200, 52, 44)
_LABEL_COLOUR = (20, 20, 20)
_DPI = 100


def _rgb(colour: tuple[int, int, int], alpha: float = 1.0) -> tuple[float, float, float, float]:
    return (colour[0] / 255.0, colour[1] / 255.0, colour[2] / 255.0, alpha)


def _terrain(name: str) -> tuple[float, float, float, float]:
    return _rgb(DEFAULT_TERRAIN_CLASSES[name].color)


def _polygon_path(polygon: Polygon2) -> Any:
    """A matplotlib path of a polygon's exterior and holes (rings are stored open)."""
    from matplotlib.path import Path as MplPath

    vertices: list[tuple[float, float]] = []
    codes: list[int] = []
    for ring in (polygon.exterior, *polygon.holes):
        if len(ring) < 3:
            continue
        vertices += [*(tuple(p) for p in ring), tuple(ring[0])]
        codes += [MplPath.MOVETO, *[MplPath.LINETO] * (len(ring) - 1), MplPath.CLOSEPOLY]
    return MplPath(vertices, codes)


def _fill(axes: Any, polygons: Sequence[Polygon2], face: Any, edge: Any = "none", width: float = 0.0) -> None:
    from matplotlib.collections import PathCollection

    paths = [_polygon_path(p) for p in polygons]
    if paths:
        axes.add_collection(PathCollection(paths, facecolors=[face], edgecolors=[edge], linewidths=width))


def _lines(
    axes: Any, lines: Sequence[Any], widths: Sequence[float], colour: Any, *, points_per_m: float
) -> None:
    from matplotlib.collections import LineCollection

    if lines:
        scaled = [max(0.3, w * points_per_m) for w in widths]
        collection = LineCollection(
            lines, colors=[colour], linewidths=scaled, capstyle="round", joinstyle="round"
        )
        axes.add_collection(collection)


def _draw(axes: Any, city: CityMap, *, points_per_m: float) -> None:
    """Draw a map's features on ``axes`` (in the map's meters), bottom layer first."""
    from matplotlib.patches import Rectangle

    x0, y0, x1, y1 = city.window
    axes.add_patch(
        Rectangle((x0, y0), x1 - x0, y1 - y0, facecolor=_rgb(MAP_BACKGROUND), edgecolor="none", zorder=0)
    )
    for cls in ("ground", "green", "parking", "plaza", "pedestrian", "water"):
        _fill(axes, [a.polygon for a in city.areas if a.cls == cls], _terrain(_AREA_TERRAIN[cls]))
    roads = [r.centerline.points for r in city.roads]
    sidewalk_widths = [
        r.sidewalk_edge(1.0) + r.sidewalk_edge(-1.0) + (r.sidewalk_left or 0.0) + (r.sidewalk_right or 0.0)
        for r in city.roads
    ]
    _lines(axes, roads, sidewalk_widths, _terrain("sidewalk"), points_per_m=points_per_m)
    _lines(axes, [w.centerline.points for w in city.walkways], [w.width for w in city.walkways],
           _terrain("sidewalk"), points_per_m=points_per_m)  # fmt: skip
    _lines(axes, roads, [r.width for r in city.roads], _terrain("road"), points_per_m=points_per_m)
    building = DEFAULT_TERRAIN_CLASSES["building"].color
    edge = tuple(round(c * 0.6) for c in building)
    _fill(axes, [b.footprint for b in city.buildings], _rgb(building), _rgb(edge), 0.4)  # type: ignore[arg-type]
    if city.pois:
        xs, ys = zip(*(p.position for p in city.pois), strict=True)
        axes.scatter(
            xs, ys, s=max(2.0, 1.2 * points_per_m) ** 2, c=[_rgb(_POI_COLOUR)], linewidths=0, zorder=3
        )


def _frame_axes(axes: Any, rect: tuple[float, float, float, float], label: str | None) -> None:
    axes.set_xlim(rect[0], rect[2])
    axes.set_ylim(rect[1], rect[3])
    axes.set_aspect("equal")
    axes.set_axis_off()
    if label:
        axes.text(
            0.02, 0.98, label, transform=axes.transAxes, ha="left", va="top", fontsize=9,
            color=_rgb(_LABEL_COLOUR),
            bbox={"facecolor": "white", "alpha": 0.8, "edgecolor": "none", "pad": 2},
        )  # fmt: skip


def _square_around(rect: tuple[float, float, float, float]) -> tuple[float, float, float, float]:
    """The square with the same centre holding ``rect``."""
    side = max(rect[2] - rect[0], rect[3] - rect[1])
    cx, cy = (rect[0] + rect[2]) / 2.0, (rect[1] + rect[3]) / 2.0
    return (cx - side / 2.0, cy - side / 2.0, cx + side / 2.0, cy + side / 2.0)


def _save(figure: Any, path: str | os.PathLike[str]) -> Path:
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(figure)
    target = Path(path)
    with atomic_path(target) as tmp:
        figure.savefig(
            tmp, dpi=_DPI, format="png", facecolor=figure.get_facecolor(), metadata={"Software": None}
        )
    return target


def _check_pixels(pixels: int, what: str) -> None:
    if isinstance(pixels, bool) or not isinstance(pixels, int) or not 16 <= pixels <= 8000:
        raise ValueError(f"{what} must be a whole number of pixels from 16 to 8000, not {pixels!r}")


def draw_city_map(
    city: CityMap, path: str | os.PathLike[str], *, pixels: int = 600, label: str | None = None
) -> Path:
    """Write a bird's-eye picture of a city map's window as a PNG.

    Parameters
    ----------
    city : CityMap
        The map; its ``window`` is what the picture shows.
    path : path
        The PNG to write (replaced whole, never left half written); its folder must exist.
    pixels : int
        The picture's longer side; the other follows the window's proportions.
    label : str, optional
        Text written in the top-left corner.

    Returns
    -------
    Path
        ``path``.
    """
    from matplotlib.figure import Figure

    _check_pixels(pixels, "pixels")
    rect = city.window
    width_m, height_m = rect[2] - rect[0], rect[3] - rect[1]
    if width_m >= height_m:
        size = (pixels, max(1, round(pixels * height_m / width_m)))
    else:
        size = (max(1, round(pixels * width_m / height_m)), pixels)
    figure = Figure(figsize=(size[0] / _DPI, size[1] / _DPI), dpi=_DPI, facecolor=_rgb(MAP_BACKGROUND))
    axes = figure.add_axes((0.0, 0.0, 1.0, 1.0))
    _draw(axes, city, points_per_m=size[0] / width_m * 72.0 / _DPI)
    _frame_axes(axes, rect, label)
    return _save(figure, path)


def draw_city_mosaic(
    tiles: Sequence[tuple[str, CityMap]],
    path: str | os.PathLike[str],
    *,
    tile_pixels: int = 300,
    columns: int | None = None,
) -> Path:
    """Write several city maps side by side as one PNG, each in a square tile with its label.

    Parameters
    ----------
    tiles : sequence of (label, CityMap)
        The maps, in reading order (left to right, then down); at least one.
    path : path
        The PNG to write (replaced whole); its folder must exist.
    tile_pixels : int
        A tile's side; each map is drawn at the scale that fits its window's longer side.
    columns : int, optional
        Tiles a row (default: as many as make the mosaic about square).

    Returns
    -------
    Path
        ``path``.
    """
    from matplotlib.figure import Figure

    if not tiles:
        raise ValueError("a mosaic needs at least one map")
    _check_pixels(tile_pixels, "tile_pixels")
    columns = columns or math.ceil(math.sqrt(len(tiles)))
    rows = math.ceil(len(tiles) / columns)
    side = tile_pixels / _DPI
    figure = Figure(figsize=(columns * side, rows * side), dpi=_DPI, facecolor="white")
    gap = 0.02  # of a tile, white between tiles
    for index, (label, city) in enumerate(tiles):
        row, column = divmod(index, columns)
        box = (
            (column + gap) / columns,
            1.0 - (row + 1 - gap) / rows,
            (1 - 2 * gap) / columns,
            (1 - 2 * gap) / rows,
        )
        axes = figure.add_axes(box)
        square = _square_around(city.window)
        _draw(axes, city, points_per_m=tile_pixels * (1 - 2 * gap) / (square[2] - square[0]) * 72.0 / _DPI)
        _frame_axes(axes, square, label)
    return _save(figure, path)
