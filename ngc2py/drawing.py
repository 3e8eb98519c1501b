"""The toolpath drawn to a picture (what ``ngc2py plot`` writes).

The picture is drawn from :func:`ngc2py.moves.toolpath`'s arrays (the
path ``ngc2py stats`` measures): rapids dashed, straight feeds and arcs
solid in their own colours, arcs and helices as curves in their own plane
through as many points as the picture can show (no point further than a
fraction of a pixel off the curve). Every kind of move is one polyline of
NumPy arrays, broken by NaN where the path jumps: no Python object per move
or per point. matplotlib is imported only when a picture is drawn.
"""

from __future__ import annotations

from typing import Tuple

import numpy as np

from ngc2py.moves import ARC, FEED, PROBE, RAPID, Toolpath
from runtime.toolpath import MM_PER_INCH

#: How each kind of move is drawn: legend label, colour, line style, width.
STYLES = {
    "rapid": ("rapid (G0)", "#d62728", (0, (4, 3)), 0.9),
    "feed": ("feed (G1)", "#1f77b4", "solid", 1.3),
    "arc": ("arc (G2/G3)", "#2ca02c", "solid", 1.3),
}
#: The picture's size: inches and dots per inch.
FIGURE_SIZE = (8, 6.5)
DPI = 150
#: How far (in pixels) a drawn arc may stray from the true one.
PIXEL_TOLERANCE = 0.25
#: Points in each polyline handed to matplotlib.
PIECE = 2000
#: Beyond this many arc points, arcs are drawn coarser (memory stays bounded).
MOST_ARC_POINTS = 8_000_000
_COS30 = np.cos(np.radians(30.0))
_SIN30 = 0.5


def project(points: np.ndarray, view: str) -> Tuple[np.ndarray, np.ndarray]:
    """The 2-D coordinates of the (m, 3) ``points`` seen from ``view``."""
    x, y, z = points[:, 0], points[:, 1], points[:, 2]
    if view == "xy":
        return x, y
    if view == "xz":
        return x, z
    if view == "yz":
        return y, z
    return (x - y) * _COS30, (x + y) * _SIN30 + z


def polyline(starts: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """Consecutive straight moves as one polyline: the (m, 3) vertices,
    a NaN row wherever a move does not start where the one before ended."""
    count = len(ends)
    if not count:
        return np.empty((0, 3))
    jump = np.ones(count, dtype=bool)
    jump[1:] = (starts[1:] != ends[:-1]).any(axis=1)
    jumps = np.cumsum(jump)
    at_end = np.arange(count) + 2 * jumps  # a jump adds a NaN and its start
    out = np.full((count + 2 * int(jumps[-1]), 3), np.nan)
    out[at_end] = ends
    out[at_end[jump] - 1] = starts[jump]
    return out[1:]


def arc_polyline(path: Toolpath, rows: np.ndarray, resolution: float) -> np.ndarray:
    """The arcs ``rows`` as one polyline of points at most ``resolution``
    (mm) off each curve, a NaN row between arcs."""
    if not len(rows):
        return np.empty((0, 3))
    points, owner = path.points(rows, resolution)
    if len(points) > MOST_ARC_POINTS:  # so many arcs that pixels are too fine
        factor = len(points) / MOST_ARC_POINTS
        points, owner = path.points(rows, resolution * factor * factor, most=16)
    last = np.flatnonzero(np.diff(owner)) + 1  # where each next arc begins
    return np.insert(points, last, np.nan, axis=0)


def bounds(path: Toolpath) -> Tuple[np.ndarray, np.ndarray]:
    """A box (low, high over X, Y and Z) around every move: arcs by their
    centre and radius (cheap, a little generous)."""
    ends = np.concatenate((path.start[:, :3], path.end[:, :3]))
    low, high = ends.min(axis=0), ends.max(axis=0)
    rows, first, second, _, _, r0, r1 = path.arc_frame()
    if len(rows):
        radius = np.maximum(r0, r1)
        for axis, column in ((first, 0), (second, 1)):
            centre = path.centre[rows, column]
            for k in range(3):
                mine = axis == k
                if mine.any():
                    low[k] = min(low[k], (centre[mine] - radius[mine]).min())
                    high[k] = max(high[k], (centre[mine] + radius[mine]).max())
    return low, high


def axis_labels(view: str, units: str) -> Tuple[str, str]:
    if view == "iso":
        return (
            "isometric: X to the upper right, Y to the upper left, Z up (%s)" % units,
            "",
        )
    return ("%s (%s)" % (view[0].upper(), units), "%s (%s)" % (view[1].upper(), units))


def draw(path: Toolpath, view: str, title: str, out, fmt: str) -> None:
    """Draw ``path`` seen from ``view`` and save it to ``out`` (a path or a
    binary file)."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import pyplot
    from matplotlib.collections import LineCollection
    from matplotlib.lines import Line2D

    inches = path.units == "inch"
    units = path.units
    scale = 1.0 / MM_PER_INCH if inches else 1.0
    figure, axes = pyplot.subplots(figsize=FIGURE_SIZE, dpi=DPI)
    kinds = {
        "rapid": path.kind == RAPID,
        "feed": (path.kind == FEED) | (path.kind == PROBE),
        "arc": path.kind == ARC,
    }
    resolution = 0.0
    if len(path):
        low, high = bounds(path)
        span = float((high - low).max())
        pixels = max(FIGURE_SIZE) * DPI
        resolution = max(span, 1e-9) / pixels * PIXEL_TOLERANCE
    handles = []
    low3 = np.full(3, np.inf)
    high3 = np.full(3, -np.inf)
    for kind, (label, colour, style, width) in STYLES.items():
        chosen = kinds[kind]
        count = int(chosen.sum())
        if kind == "arc":
            vertices = arc_polyline(path, np.flatnonzero(chosen), resolution)
        else:
            vertices = polyline(path.start[chosen, :3], path.end[chosen, :3])
        if len(vertices):
            vertices = vertices * scale
            low3 = np.fmin(low3, np.nanmin(vertices, axis=0))
            high3 = np.fmax(high3, np.nanmax(vertices, axis=0))
            u, v = project(vertices, view)
            flat = np.column_stack((u, v))
            # Pieces of a bounded size: Agg's memory for one path grows with
            # its length (one path of a million points takes gigabytes).
            pieces = [flat[i : i + PIECE + 1] for i in range(0, len(flat), PIECE)]
            axes.add_collection(
                LineCollection(
                    pieces,
                    colors=colour,
                    linestyles=style,
                    linewidths=width,
                    zorder={"rapid": 1, "feed": 2, "arc": 3}[kind],
                )
            )
            if kind == "feed":
                # A plunge seen end-on (a drilled hole from the top) is a dot.
                su, sv = project(path.start[chosen, :3] * scale, view)
                eu, ev = project(path.end[chosen, :3] * scale, view)
                dots = (su == eu) & (sv == ev)
                if dots.any():
                    axes.plot(
                        su[dots], sv[dots], "o", color=colour, markersize=3, zorder=4
                    )
        handles.append(
            Line2D(
                [],
                [],
                color=colour,
                linestyle=style,
                linewidth=width,
                label="%s: %d move%s" % (label, count, "" if count == 1 else "s"),
            )
        )
    axes.autoscale()
    axes.set_aspect("equal", adjustable="datalim")
    axes.margins(0.05)
    xlabel, ylabel = axis_labels(view, units)
    axes.set_xlabel(xlabel)
    axes.set_ylabel(ylabel)
    if view == "iso":
        axes.set_xticks([])
        axes.set_yticks([])
    axes.grid(True, linewidth=0.3, alpha=0.5)
    axes.legend(handles=handles, loc="upper right", fontsize=8, framealpha=0.9)
    axes.set_title("%s - %s view" % (title, view.upper()), fontsize=11)
    if np.isfinite(low3).all():
        extent = "   ".join(
            "%s %.4g .. %.4g" % (name, low3[i], high3[i])
            for i, name in enumerate("XYZ")
        )
        figure.text(
            0.5, 0.015, "extents (%s):   %s" % (units, extent), ha="center", fontsize=8
        )
    else:
        figure.text(0.5, 0.015, "no moves", ha="center", fontsize=8)
    figure.savefig(out, format=fmt, bbox_inches="tight")
    pyplot.close(figure)


__all__ = ["STYLES", "arc_polyline", "bounds", "draw", "polyline", "project"]
