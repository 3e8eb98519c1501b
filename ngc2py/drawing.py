"""The toolpath drawn to a picture (what ``ngc2py plot`` writes).

The picture is drawn from :func:`ngc2py.moves.toolpath`'s arrays (the
path ``ngc2py stats`` measures): rapids dashed, straight feeds and arcs
solid in their own colours, arcs and helices as curves in their own plane
through as many points as the picture can show (no point further than a
fraction of a pixel off the curve). Every kind of move is one polyline of
NumPy arrays, broken by NaN where the path jumps: no Python object per move
or per point. matplotlib is imported only when a picture is drawn.

A kind with more points than a picture can show line by line (dense CAM
output: hundreds of thousands of strokes) is rasterised instead: Pillow
(matplotlib's own image library) draws its polylines into a mask of the
axes' pixels, shown as an image at the kind's place in the stack. Agg
spends ~60 us on a long antialiased stroke; Pillow's plain lines cost a
microsecond. Such a kind is drawn solid (the legend says so).
"""

from __future__ import annotations

import functools
from typing import List, Tuple

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
#: A kind of move with more polyline points than this is rasterised.
RASTER_FROM = 50_000
#: The stacking order of the kinds (arcs on top).
ZORDER = {"rapid": 1, "feed": 2, "arc": 3}
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


def arc_polyline(
    path: Toolpath, rows: np.ndarray, resolution: float, frame=None
) -> np.ndarray:
    """The arcs ``rows`` as one polyline of points at most ``resolution``
    (mm) off each curve, a NaN row between arcs. ``frame``: the path's
    ``arc_frame()``, if the caller has it."""
    if not len(rows):
        return np.empty((0, 3))
    frame = frame or path.arc_frame()
    points, owner = path.points(rows, resolution, frame=frame)
    if len(points) > MOST_ARC_POINTS:  # so many arcs that pixels are too fine
        factor = len(points) / MOST_ARC_POINTS
        points, owner = path.points(
            rows, resolution * factor * factor, most=16, frame=frame
        )
    last = np.flatnonzero(np.diff(owner)) + 1  # where each next arc begins
    return np.insert(points, last, np.nan, axis=0)


def bounds(path: Toolpath, frame=None) -> Tuple[np.ndarray, np.ndarray]:
    """A box (low, high over X, Y and Z) around every move: arcs by their
    centre and radius (cheap, a little generous). ``frame``: the path's
    ``arc_frame()``, if the caller has it."""
    ends = np.concatenate((path.start[:, :3], path.end[:, :3]))
    low, high = ends.min(axis=0), ends.max(axis=0)
    rows, first, second, _, _, r0, r1 = frame or path.arc_frame()
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


def rasterise(flat: np.ndarray, limits, size, width: int) -> np.ndarray:
    """The polyline ``flat`` ((m, 2), NaN rows between its runs) drawn
    into a (height, width) boolean mask whose pixels cover ``limits``
    ((x0, x1), (y0, y1)), its lines ``width`` pixels wide."""
    from PIL import Image, ImageDraw

    (x0, x1), (y0, y1) = limits
    columns, rows = size
    px = (flat[:, 0] - x0) * (columns / (x1 - x0))
    py = (y1 - flat[:, 1]) * (rows / (y1 - y0))
    gaps = np.flatnonzero(np.isnan(px[1:-1])) + 1
    # A break between runs that meet (arc after arc) is no break.
    meet = (px[gaps - 1] == px[gaps + 1]) & (py[gaps - 1] == py[gaps + 1])
    if meet.any():
        px, py = np.delete(px, gaps[meet]), np.delete(py, gaps[meet])
    mask = Image.new("1", (columns, rows), 0)
    line, point = _pens(ImageDraw.Draw(mask))
    breaks = np.flatnonzero(np.isnan(px))
    # Pillow has no NaN breaks: one line call per run of the polyline.
    ends = np.append(breaks, len(px))
    starts = np.insert(breaks + 1, 0, 0)
    # the coordinates as single floats, which Pillow reads from a buffer
    # without a Python float each (a pixel's thousandth is plenty here); a
    # run is a slice of their memoryview, made in a tenth of a microsecond
    coordinates = (
        memoryview(np.column_stack((px, py)).astype(np.float32).ravel())
        .cast("B")
        .cast("f")
    )
    for a, b in zip((2 * starts).tolist(), (2 * ends).tolist()):
        if b - a >= 4:
            line(coordinates[a:b])
        elif b - a == 2:
            point(coordinates[a:b])
    thin = np.asarray(mask, dtype=bool)
    wide = thin.copy()
    # Wider lines by shifting the one-pixel mask (Pillow's own wide lines
    # draw a joint at every vertex: several times slower).
    for shift in range(1, width):
        step = (shift + 1) // 2 * (1 if shift % 2 else -1)
        shifted_x = np.roll(thin, step, axis=1)
        shifted_y = np.roll(thin, step, axis=0)
        if step > 0:
            shifted_x[:, :step] = False
            shifted_y[:step, :] = False
        else:
            shifted_x[:, step:] = False
            shifted_y[step:, :] = False
        wide |= shifted_x | shifted_y
    return wide


def _pens(pen):
    """(line, point): a one-pixel line through a flat list of coordinates,
    and a pixel, in ink 1. Pillow's drawing core where it is as Pillow's
    own ImageDraw.line and point use it (``draw_lines`` with the ink of 1,
    once): tens of thousands of runs pay for ImageDraw's ink lookup each
    time otherwise; ImageDraw's methods where it is not."""
    core = getattr(pen, "draw", None)
    if all(hasattr(core, name) for name in ("draw_ink", "draw_lines", "draw_points")):
        ink = core.draw_ink(1)
        return (lambda xy: core.draw_lines(xy, ink, 1)), (
            lambda xy: core.draw_points(xy, ink)
        )
    return (lambda xy: pen.line(xy, fill=1, width=1)), (
        lambda xy: pen.point(xy, fill=1)
    )


def show_raster(axes, layers: List[Tuple[np.ndarray, str, float]], zorder: int) -> None:
    """Draw polylines on ``axes`` as one image of their pixels: ``layers``
    are (flat, colour, width), each drawn over the ones before it."""
    from matplotlib.colors import to_rgba

    box = axes.get_window_extent()
    size = (max(1, int(round(box.width))), max(1, int(round(box.height))))
    limits = (axes.get_xlim(), axes.get_ylim())
    image = np.zeros((size[1], size[0], 4), dtype=np.uint8)
    for flat, colour, width in layers:
        pixels = max(1, int(round(width * axes.figure.dpi / 72.0)))
        mask = rasterise(flat, limits, size, pixels)
        # bytes, not floats (a named colour's parts are whole 255ths)
        image[mask] = np.round(np.array(to_rgba(colour)) * 255.0).astype(np.uint8)
    (x0, x1), (y0, y1) = limits
    axes.set_autoscale_on(False)
    raster = _raster_class()(image, (x0, x1, y0, y1))
    raster.set_zorder(zorder)
    axes.add_artist(raster)
    axes.set_xlim(x0, x1)
    axes.set_ylim(y0, y1)


@functools.lru_cache(maxsize=None)
def _raster_class():
    """The artist of :func:`show_raster` (made once: matplotlib documents
    every Artist subclass as it is defined, which takes milliseconds)."""
    from matplotlib.artist import Artist
    from matplotlib.backends.backend_agg import RendererAgg
    from matplotlib.image import AxesImage

    class Raster(Artist):
        """An image as large as its axes in pixels. Agg draws it as it is,
        pixel for pixel: an AxesImage would be resampled onto the same
        pixels, a tenth of a 100k-arc picture's time. Any other renderer
        (a vector format, another dpi) gets it through an AxesImage."""

        def __init__(self, image: np.ndarray, extent) -> None:
            super().__init__()
            self.image, self.extent = image, extent

        def draw(self, renderer) -> None:
            if not self.get_visible():
                return
            box = self.axes.get_window_extent(renderer)
            if _draws_directly(renderer, RendererAgg, box, self.image):
                gc = renderer.new_gc()
                gc.set_clip_rectangle(box)
                # (Agg's rows run upwards from the given corner)
                upwards = np.ascontiguousarray(self.image[::-1])
                renderer.draw_image(gc, round(box.x0), round(box.y0), upwards)
                gc.restore()
                return
            image = AxesImage(self.axes, interpolation="nearest", origin="upper")
            image.set_transform(self.axes.transData)
            image.set_data(self.image)
            image.set_extent(self.extent)
            image.set_clip_path(self.axes.patch)
            image.draw(renderer)

    return Raster


def _draws_directly(renderer, agg, box, image: np.ndarray) -> bool:
    """Whether Agg draws the raster ``image`` as it is: its pixels are
    the axes' (``box``) at this renderer's dpi."""
    rows, columns = image.shape[:2]
    return isinstance(renderer, agg) and (round(box.width), round(box.height)) == (
        columns,
        rows,
    )


def axis_labels(view: str, units: str) -> Tuple[str, str]:
    if view == "iso":
        return (
            "isometric: X to the upper right, Y to the upper left, Z up (%s)" % units,
            "",
        )
    return ("%s (%s)" % (view[0].upper(), units), "%s (%s)" % (view[1].upper(), units))


#: Formats whose tight box draw() finds before adding the raster layers
#: (text laid out at the figure's dpi, as the picture is).
BOX_BEFORE_RASTERS = {"png"}


def prepare() -> None:
    """Import what :func:`draw` uses (most of a small picture's time)."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import collections, colors, lines, pyplot  # noqa: F401
    from PIL import Image, ImageDraw  # noqa: F401


class Sketch:
    """What a picture shows, worked out with NumPy alone (no matplotlib):
    each kind of move as one projected polyline, its number of moves, the
    plunges seen end-on, the extents. Small to pickle: the plot's child
    process makes it while the parent imports matplotlib (ngc2py.plot)."""

    __slots__ = ("view", "units", "kinds", "dots", "extents")

    def __init__(self, view: str, units: str) -> None:
        self.view, self.units = view, units
        #: kind -> (number of moves, its (m, 2) polyline in program units)
        self.kinds: dict = {}
        #: the feeds' plunges seen end-on: (u, v) arrays, or None
        self.dots = None
        self.extents = [np.full(3, np.inf), np.full(3, -np.inf)]

    def __getstate__(self):
        return tuple(getattr(self, name) for name in self.__slots__)

    def __setstate__(self, state) -> None:
        for name, value in zip(self.__slots__, state):
            setattr(self, name, value)


def sketch(path: Toolpath, view: str) -> Sketch:
    """The picture of ``path`` seen from ``view``, as a :class:`Sketch`."""
    inches = path.units == "inch"
    scale = 1.0 / MM_PER_INCH if inches else 1.0
    made = Sketch(view, path.units)
    kinds = {
        "rapid": path.kind == RAPID,
        "feed": (path.kind == FEED) | (path.kind == PROBE),
        "arc": path.kind == ARC,
    }
    resolution, frame = 0.0, None
    if len(path):
        frame = path.arc_frame()  # (bounds and the arcs' points share it)
        low, high = bounds(path, frame)
        span = float((high - low).max())
        pixels = max(FIGURE_SIZE) * DPI
        resolution = max(span, 1e-9) / pixels * PIXEL_TOLERANCE
    for kind in STYLES:
        chosen = kinds[kind]
        if kind == "arc":
            vertices = arc_polyline(path, np.flatnonzero(chosen), resolution, frame)
        else:
            vertices = polyline(path.start[chosen, :3], path.end[chosen, :3])
        flat = None
        if len(vertices):
            flat = _projected(vertices * scale, view, made.extents)
            if kind == "feed":
                made.dots = _plunges(path, chosen, view, scale)
        made.kinds[kind] = (int(chosen.sum()), flat)
    return made


def draw(path: Toolpath, view: str, title: str, out, fmt: str) -> None:
    """Draw ``path`` seen from ``view`` and save it to ``out`` (a path or a
    binary file)."""
    render(sketch(path, view), title, out, fmt)


def render(made: Sketch, title: str, out, fmt: str) -> None:
    """Draw the sketch ``made`` and save it to ``out`` (a path or a binary
    file)."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import pyplot
    from matplotlib.lines import Line2D

    figure, axes = pyplot.subplots(figsize=FIGURE_SIZE, dpi=DPI)
    handles = []
    dense = {}  # kind -> its (m, 2) polyline, rasterised once the axes are laid out
    for kind, (label, colour, style, width) in STYLES.items():
        count, flat = made.kinds[kind]
        if flat is not None:
            if len(flat) > RASTER_FROM:
                style = "solid"
                dense[kind] = flat
                axes.update_datalim(np.array(_extremes(flat)))
            else:
                _add_lines(axes, flat, kind)
            if kind == "feed" and made.dots is not None:
                u, v = made.dots
                axes.plot(u, v, "o", color=colour, markersize=3, zorder=4)
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
    _lay_out(figure, axes, made.view, made.units, title, handles, made.extents)
    bbox = "tight"
    if dense and fmt in BOX_BEFORE_RASTERS:
        # savefig's "tight" box, found before the rasters are added (they lie
        # within the axes): "tight" would draw them once more to find it.
        # (A vector format lays text out at 72 dpi: there savefig finds it.)
        figure.draw_without_rendering()
        pad = matplotlib.rcParams["savefig.pad_inches"]
        bbox = figure.get_tightbbox(figure.canvas.get_renderer()).padded(pad)
    if dense:
        axes.apply_aspect()  # the limits the picture will have
        for kinds in _raster_groups(dense):
            layers = []
            for kind in kinds:
                _, colour, _, width = STYLES[kind]
                layers.append((dense[kind], colour, width))
            show_raster(axes, layers, ZORDER[kinds[-1]])
    figure.savefig(out, format=fmt, bbox_inches=bbox)
    pyplot.close(figure)


def _raster_groups(dense: dict) -> List[List[str]]:
    """The dense kinds, bottom to top, in images of their own: feeds and
    arcs share one (their zorders are next to each other, nothing is drawn
    between them), which saves the figure resampling a second image."""
    groups: List[List[str]] = []
    for kind in sorted(dense, key=ZORDER.get):
        if groups and groups[-1][-1] == "feed" and kind == "arc":
            groups[-1].append(kind)
        else:
            groups.append([kind])
    return groups


def _projected(vertices, view: str, extents: List) -> "np.ndarray":
    """``vertices`` (m, 3) seen from ``view`` as (m, 2); ``extents`` (low,
    high) grow to take them in."""
    low, high = _extremes(vertices)
    extents[0] = np.fmin(extents[0], low)
    extents[1] = np.fmax(extents[1], high)
    u, v = project(vertices, view)
    return np.column_stack((u, v))


def _extremes(points: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """The least and greatest of each column of ``points`` (m, n), NaN rows
    left out (``nanmin`` and ``nanmax`` along axis 0), a column at a time:
    a reduction along the short axis of millions of rows is five times
    slower."""
    columns = range(points.shape[1])
    return (
        np.array([np.fmin.reduce(points[:, k]) for k in columns]),
        np.array([np.fmax.reduce(points[:, k]) for k in columns]),
    )


def _add_lines(axes, flat, kind: str) -> None:
    """A kind's polyline as a collection of pieces of a bounded size: Agg's
    memory for one path grows with its length (one path of a million
    points takes gigabytes)."""
    from matplotlib.collections import LineCollection

    _, colour, style, width = STYLES[kind]
    pieces = [flat[i : i + PIECE + 1] for i in range(0, len(flat), PIECE)]
    axes.add_collection(
        LineCollection(
            pieces,
            colors=colour,
            linestyles=style,
            linewidths=width,
            zorder=ZORDER[kind],
        )
    )


def _plunges(path: Toolpath, chosen, view: str, scale: float):
    """A plunge seen end-on (a drilled hole from the top) is a dot: the
    dots' (u, v), or None."""
    su, sv = project(path.start[chosen, :3] * scale, view)
    eu, ev = project(path.end[chosen, :3] * scale, view)
    dots = (su == eu) & (sv == ev)
    if dots.any():
        return su[dots], sv[dots]
    return None


def _lay_out(figure, axes, view: str, units: str, title: str, handles, extents) -> None:
    """Scale, labels, legend, title and the extents line."""
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
    low3, high3 = extents
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


__all__ = [
    "STYLES",
    "arc_polyline",
    "bounds",
    "draw",
    "polyline",
    "project",
    "rasterise",
    "render",
    "sketch",
    "Sketch",
]
