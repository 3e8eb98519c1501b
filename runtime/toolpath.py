"""The tool's path, as a canon sees it: straight moves and arcs in space.

:class:`ToolpathCanon` turns the motion calls of the canon protocol into
moves with a start and an end point, in millimetres, whatever units the
program uses, so that statistics (``runtime.stats``) and plots
(``ngc2py.plot``) measure one and the same path. Subclasses override
:meth:`ToolpathCanon.line` and :meth:`ToolpathCanon.arc`.

Conventions (those of LinuxCNC's canon layer, as ``rs274 -g`` shows them):

* Positions are in program units (``USE_LENGTH_UNITS``) and in program
  coordinates: the current work offset, G92/G52 offset and tool length
  offset are already taken off. When an offset changes, the tool does not
  move, so its position in program coordinates shifts by the change; the
  next move starts from there. (A G10 L2 R rotation is not undone.)
* ``ARC_FEED(first_end, second_end, first_axis, second_axis, rotation,
  axis_end, ...)``: the arc's end and centre in the plane's two axes and the
  end on the axis normal to it (a helix when that changes). The plane's axes
  in that order: XY -> (X, Y, Z), XZ -> (Z, X, Y), YZ -> (Y, Z, X).
  ``rotation`` > 0 turns counter-clockwise in that frame, < 0 clockwise, and
  ``abs(rotation) - 1`` extra full turns are made. An arc that ends where it
  starts is a full circle. The radius may change a little from start to end
  (LinuxCNC accepts that within a tolerance): it is interpolated linearly.
* Angles (A, B, C) are degrees and never converted.
* ``NURBS_FEED`` (splines): the polyline through the points LinuxCNC's
  preview draws (``runtime.nurbs``), ending on the last control point.

Standard library only, like the rest of the runtime.
"""

from __future__ import annotations

import math
from collections import namedtuple

TYPE_CHECKING = False  # typing and dataclasses cost milliseconds at every start
if TYPE_CHECKING:
    from typing import List, Optional, Sequence, Tuple

from runtime.canon import Canon
from runtime.nurbs import preview_points

try:  # the C library's, as runtime._arc_stats takes it (a batch of arcs
    # in C then gives the very doubles of these functions)
    from runtime._arc_stats import hypot
except ImportError:  # not built: Python's own, in both
    from math import hypot

MM_PER_INCH = 25.4
#: Linear axes (X Y Z U V W) among the nine; A B C are angles.
LINEAR = (0, 1, 2, 6, 7, 8)
AXIS_NAMES = "xyzabcuvw"
#: (first, second, normal) axis indexes of ARC_FEED in each canon plane.
PLANE_AXES = {"XY": (0, 1, 2), "XZ": (2, 0, 1), "YZ": (1, 2, 0)}
TAU = 2.0 * math.pi
#: An arc whose end is this close (mm) to its start is a full circle.
FULL_CIRCLE_CHORD = 1e-9

Point = "Tuple[float, ...]"


class Arc(namedtuple("Arc", "start end axes centre sweep r0 r1 theta0")):
    """An arc or helix, in millimetres: ``start`` and ``end`` are nine-axis
    points; the arc turns about ``centre`` (in the plane) through ``sweep``
    radians, counter-clockwise if positive, in the plane given by ``axes``
    (first, second, normal axis indexes); from ``r0`` to ``r1`` about it
    (a spiral when they differ), starting at angle ``theta0``."""

    __slots__ = ()

    @property
    def length(self) -> float:
        """Path length of the helix (in the plane: mean radius times angle)."""
        normal = self.end[self.axes[2]] - self.start[self.axes[2]]
        return helix_length(self.sweep, self.r0, self.r1, normal)

    def point(self, t: float) -> Point:
        """The point a fraction ``t`` (0..1) along the arc (every axis moves
        in proportion: the plane's two by angle, the others linearly)."""
        f, s, _ = self.axes
        start, end = self.start, self.end
        # Kept between the ends: a + (b - a) * t may round past b (a helix's
        # Z never goes beyond its end, whatever the rounding).
        p = [
            min(max(a + (b - a) * t, min(a, b)), max(a, b)) for a, b in zip(start, end)
        ]
        theta = self.theta0 + self.sweep * t
        radius = self.r0 + (self.r1 - self.r0) * t
        p[f] = self.centre[0] + radius * math.cos(theta)
        p[s] = self.centre[1] + radius * math.sin(theta)
        return tuple(p)

    def sample(self, step: float = math.radians(5.0)) -> List[Point]:
        """Points along the arc no more than ``step`` radians apart, start and end included."""
        count = max(2, int(math.ceil(abs(self.sweep) / step)))
        points = [self.point(i / count) for i in range(count)]
        points.append(self.end)
        return points

    def extreme_points(self) -> List[Point]:
        """The start, the end, and the points where the arc is furthest out
        along its plane's axes: together they bound it, exactly.

        The plane's two coordinates are r(θ)·cos θ and r(θ)·sin θ about the
        centre, the radius r changing linearly with the angle θ (a spiral
        when the start and end radii differ; a circle when not). Their
        derivatives are R·cos(θ + φ) and R·sin(θ + φ), with R = √(k² + r²),
        k = dr/dθ and φ = atan2(r, k), so both are stationary exactly where
        h(θ) = θ + φ(θ) is a multiple of a quarter turn. h rises with slope
        1 + k²/(k² + r²), between 1 and 2: each multiple is met once, and
        the root is found by a safeguarded Newton iteration. In one
        direction (say +X: h = π/2 modulo 2π) the radius is largest at the
        first or the last such root, since r is monotonic, so two roots per
        direction are enough whatever the number of turns: O(1) per arc.
        The other axes move linearly, so their extremes are the ends."""
        points = [self.start, self.end]
        sweep = self.sweep
        if sweep == 0.0:
            return points
        theta0, r0 = self.theta0, self.r0
        k = (self.r1 - r0) / sweep  # dr/dθ
        if not math.isfinite(k):
            # A sweep too small for its change of radius to be divided by is
            # a radial segment: its ends bound it.
            return points

        def h(theta: float) -> float:
            return theta + math.atan2(r0 + k * (theta - theta0), k)

        def slope(theta: float) -> float:
            if not k:
                return 1.0
            ratio = (r0 + k * (theta - theta0)) / k  # k² would overflow first
            return 1.0 + 1.0 / (1.0 + ratio * ratio)

        low, high = sorted((theta0, theta0 + sweep))
        h_low, h_high = h(low), h(high)
        quarter = math.pi / 2
        first, last = math.ceil(h_low / quarter), math.floor(h_high / quarter)
        if last < first:
            return points
        wanted = set()
        for direction in range(4):  # the four multiples modulo a full turn
            m = first + (direction - first) % 4
            if m <= last:
                wanted.add(m)
                wanted.add(m + (last - m) // 4 * 4)
        for m in sorted(wanted):
            theta = _solve_increasing(h, slope, m * quarter, low, high)
            points.append(self.point((theta - theta0) / sweep))
        return points


def _solve_increasing(h, slope, target: float, low: float, high: float) -> float:
    """The θ in [low, high] where the increasing function ``h`` (its
    derivative ``slope``, between 1 and 2) equals ``target``: Newton steps kept inside a
    shrinking bracket (bisection when a step leaves it)."""
    theta = min(max(target - (h(low) - low), low), high)
    for _ in range(60):
        value = h(theta) - target
        if value == 0.0:
            return theta
        if value > 0.0:
            high = theta
        else:
            low = theta
        guess = theta - value / slope(theta)
        if not low < guess < high:
            guess = 0.5 * (low + high)
        if abs(guess - theta) <= 1e-15 * max(1.0, abs(theta)):
            return guess
        theta = guess
    return theta


def helix_length(sweep: float, r0: float, r1: float, rise: float) -> float:
    """Path length of an arc of ``sweep`` radians from radius ``r0`` to
    ``r1`` rising ``rise`` along its normal (in the plane: mean radius times
    angle)."""
    return hypot(abs(sweep) * (r0 + r1) / 2.0, rise)


def make_arc(
    start: Point, end: Point, axes: Tuple[int, int, int], centre, rotation: int
) -> Arc:
    """The :class:`Arc` from ``start`` to ``end`` as ARC_FEED describes it."""
    geometry = arc_geometry(start, end, axes, centre, rotation)
    return Arc(tuple(start), tuple(end), axes, tuple(centre), *geometry)


def arc_geometry(
    start: Point, end: Point, axes: Tuple[int, int, int], centre, rotation: int
) -> Tuple[float, float, float, float]:
    """The arc ARC_FEED describes from ``start`` to ``end``: (sweep, start
    radius, end radius, start angle), as :class:`Arc` holds them."""
    f, s, _ = axes
    cf, cs = centre
    theta0 = math.atan2(start[s] - cs, start[f] - cf)
    theta1 = math.atan2(end[s] - cs, end[f] - cf)
    closed = hypot(end[f] - start[f], end[s] - start[s]) < FULL_CIRCLE_CHORD
    if rotation >= 0:
        sweep = (theta1 - theta0) % TAU
        if closed or sweep == 0.0:
            sweep = TAU
        sweep += TAU * max(rotation - 1, 0)
    else:
        sweep = -((theta0 - theta1) % TAU)
        if closed or sweep == 0.0:
            sweep = -TAU
        sweep -= TAU * (-rotation - 1)
    r0 = hypot(start[f] - cf, start[s] - cs)
    r1 = hypot(end[f] - cf, end[s] - cs)
    return sweep, r0, r1, theta0


def distance(a: Sequence[float], b: Sequence[float]) -> float:
    """Straight-line distance between two points over X, Y and Z: the square
    root of the sum of the three squares, added in that order, so that C
    (runtime._arc_stats.straight_sums) and NumPy (ngc2py.moves) get the very
    same double; ``math.hypot`` only where the squares overflow (beyond
    1e150), which neither of those meets."""
    dx, dy, dz = b[0] - a[0], b[1] - a[1], b[2] - a[2]
    length = math.sqrt(dx * dx + dy * dy + dz * dz)
    if length == math.inf:
        return math.hypot(dx, dy, dz)
    return length


class ToolpathCanon(Canon):
    """Follows the tool through the motion calls; see the module docstring.

    :attr:`position` is the current nine-axis point in millimetres (and
    degrees). :attr:`first_units` is True/False (inches/mm) for the units in
    force at the first move, None until there is one: reports use them.
    """

    def __init__(self) -> None:
        self.position: Point = (0.0,) * 9
        self.inches = False
        self.first_units: Optional[bool] = None
        self.plane = "XY"
        self._offsets = {"g5x": (0.0,) * 9, "g92": (0.0,) * 9, "tool": (0.0,) * 9}

    # --- subclasses --------------------------------------------------------
    def line(self, kind: str, start: Point, end: Point) -> None:
        """A straight move: ``kind`` is "rapid", "feed" or "probe"."""

    def arc(self, arc: Arc) -> None:
        """An arc or helix (a feed move)."""

    def spline(self, path: List[Point]) -> None:
        """A spline (G5, G5.1, G5.2) as the polyline ``path`` (its start
        first): by default, one straight feed per segment."""
        for start, end in zip(path, path[1:]):
            self.line("feed", start, end)

    # --- units and coordinates -----------------------------------------
    def to_mm(self, value: float) -> float:
        return value * MM_PER_INCH if self.inches else value

    def _point(self, values: Point) -> Point:
        """``values`` (program units) in millimetres."""
        if not self.inches:
            return values
        k = MM_PER_INCH
        x, y, z, a, b, c, u, v, w = values
        return (x * k, y * k, z * k, a, b, c, u * k, v * k, w * k)

    def use_length_units(self, inches: bool):
        self.inches = bool(inches)

    #: a batch's restated G17 (runtime.canon.Canon.takes_planes) leaves the
    #: XY plane the batch's arcs are in: the protocol's defaults, or the
    #: batch methods below, which keep it so
    takes_planes = True

    def select_plane(self, plane: str):
        self.plane = plane

    def _planes_told(self, planes) -> bool:
        """A batch's ``planes`` (its rows restating G17) taken in one go:
        the plane is XY after each (and before: its arcs are in it), unless
        a subclass watches select_plane (then False: row by row)."""
        if type(self).select_plane is not ToolpathCanon.select_plane:
            return False
        self.plane = "XY"
        return True

    def _shift(self, kind: str, values: Sequence[float]) -> None:
        new = self._point(tuple(values))
        old = self._offsets[kind]
        self.position = tuple(p - (n - o) for p, n, o in zip(self.position, new, old))
        self._offsets[kind] = new

    def set_g5x_offset(self, index, x, y, z, a, b, c, u, v, w):
        self._shift("g5x", (x, y, z, a, b, c, u, v, w))

    def set_g92_offset(self, x, y, z, a, b, c, u, v, w):
        self._shift("g92", (x, y, z, a, b, c, u, v, w))

    def use_tool_length_offset(self, x, y, z, a, b, c, u, v, w):
        self._shift("tool", (x, y, z, a, b, c, u, v, w))

    # --- motion ----------------------------------------------------------
    def _move(self, kind: str, values: Sequence[float]) -> None:
        if self.first_units is None:
            self.first_units = self.inches
        start = self.position
        self.position = end = self._point(values)
        self.line(kind, start, end)

    def straight_traverse(self, x, y, z, a, b, c, u, v, w):
        self._move("rapid", (x, y, z, a, b, c, u, v, w))

    def straight_feed(self, x, y, z, a, b, c, u, v, w):
        self._move("feed", (x, y, z, a, b, c, u, v, w))

    def straight_probe(self, x, y, z, a, b, c, u, v, w, probe_type):
        self._move("probe", (x, y, z, a, b, c, u, v, w))

    def rigid_tap(self, x, y, z, scale):
        # The spindle reverses at the bottom: in to the point and back out.
        start = self.position
        k = MM_PER_INCH if self.inches else 1.0
        target = (x * k, y * k, z * k) + start[3:]  # only X, Y and Z move
        self.line("feed", start, target)
        self.line("feed", target, start)

    def nurbs_feed(self, control_points, order):
        # The curve through the points LinuxCNC's preview draws
        # (runtime/nurbs.py); it ends on the last control point, the other
        # axes staying where they are.
        if self.first_units is None:
            self.first_units = self.inches
        start = self.position
        k = MM_PER_INCH if self.inches else 1.0
        path = [start] + [
            (x * k, y * k) + tuple(start[2:])
            for x, y in preview_points(control_points, order)
        ]
        self.position = path[-1]
        self.spline(path)

    def arc_feed(
        self,
        first_end,
        second_end,
        first_axis,
        second_axis,
        rotation,
        axis_end,
        a,
        b,
        c,
        u,
        v,
        w,
    ):
        if self.first_units is None:
            self.first_units = self.inches
        start = self.position
        end = list(start[:3]) + list(self._point((0, 0, 0, a, b, c, u, v, w))[3:])
        axes = PLANE_AXES.get(self.plane)
        if axes is None or first_axis != first_axis:
            # A UVW plane: X, Y and Z stay where they are. A centre that is
            # not a number (rs274's R 0 arc, its end within the tolerance of
            # its start): a straight feed there.
            if axes is not None:
                f, s, n = axes
                end[f], end[s], end[n] = (
                    self.to_mm(first_end),
                    self.to_mm(second_end),
                    self.to_mm(axis_end),
                )
            self.position = tuple(end)
            self.line("feed", start, self.position)
            return
        f, s, n = axes
        end[f], end[s], end[n] = (
            self.to_mm(first_end),
            self.to_mm(second_end),
            self.to_mm(axis_end),
        )
        self.position = end = tuple(end)
        centre = (self.to_mm(first_axis), self.to_mm(second_axis))
        self.arc(make_arc(start, end, axes, centre, rotation))


class Extents:
    """Running minimum and maximum of each of the nine axes (``low`` and
    ``high``, nine values each)."""

    def __init__(self) -> None:
        inf = math.inf
        self._xyz = [inf, -inf, inf, -inf, inf, -inf]
        self._rest_low = [inf] * 6
        self._rest_high = [-inf] * 6
        self._rest: Optional[Tuple[float, ...]] = None

    def add(self, point: Sequence[float]) -> None:
        # This runs for every move: X, Y and Z unrolled, and the other six
        # axes only looked at when they changed (they seldom do).
        box = self._xyz
        x, y, z = point[0], point[1], point[2]
        if x < box[0]:
            box[0] = x
        if x > box[1]:
            box[1] = x
        if y < box[2]:
            box[2] = y
        if y > box[3]:
            box[3] = y
        if z < box[4]:
            box[4] = z
        if z > box[5]:
            box[5] = z
        rest = tuple(point[3:])
        if rest != self._rest:
            self._rest = rest
            self._rest_low = list(map(min, self._rest_low, rest))
            self._rest_high = list(map(max, self._rest_high, rest))

    def encloses(self, axes: Tuple[int, int, int], centre, radius: float) -> bool:
        """Whether the square of half-side ``radius`` about ``centre`` in the
        plane of ``axes`` (an arc's, whose every point is that close to its
        centre) lies within the extents so far: then only its ends can add
        to them."""
        box = self._xyz
        f, s = axes[0] * 2, axes[1] * 2
        cf, cs = centre
        return (
            box[f] <= cf - radius
            and cf + radius <= box[f + 1]
            and box[s] <= cs - radius
            and cs + radius <= box[s + 1]
        )

    def add_columns(self, columns: Sequence[Sequence[float]]) -> None:
        """Every point of nine columns (x .. w, of equal length) at once."""
        box = self._xyz
        for i, column in enumerate(columns[:3]):
            low, high = min(column), max(column)
            if low < box[2 * i]:
                box[2 * i] = low
            if high > box[2 * i + 1]:
                box[2 * i + 1] = high
        self._rest = tuple(column[-1] for column in columns[3:])
        lows = [min(column) for column in columns[3:]]
        highs = [max(column) for column in columns[3:]]
        self._rest_low = list(map(min, self._rest_low, lows))
        self._rest_high = list(map(max, self._rest_high, highs))

    @property
    def low(self) -> List[float]:
        return self._xyz[0::2] + self._rest_low

    @property
    def high(self) -> List[float]:
        return self._xyz[1::2] + self._rest_high

    @property
    def empty(self) -> bool:
        return self._xyz[0] == math.inf


__all__ = [
    "Arc",
    "AXIS_NAMES",
    "Extents",
    "MM_PER_INCH",
    "PLANE_AXES",
    "ToolpathCanon",
    "distance",
    "make_arc",
]
