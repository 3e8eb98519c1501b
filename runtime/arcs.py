"""Arc geometry for G2/G3 as rs274 computes it, with rs274's errors.

Everything here works in *plane coordinates*: rs274 turns every arc into a
2-D problem in the selected plane plus a linear "axis" motion, and the plane
decides which machine axis is "first", "second" and "axis":

    plane  first  second  axis      (G17 / G18 / G19)
    XY     X      Y       Z
    XZ     Z      X       Y         <- note: Z comes first in G18
    YZ     Y      Z       X

`to_plane`/`from_plane` convert between (x, y, z) and that order. The values
of an :class:`Arc` are exactly what rs274 passes to
``ARC_FEED(end1, end2, center1, center2, rotation, axis_end, a, b, c)``.

The checks rs274 makes on an arc block are split by *when* rs274 makes them,
because the machine must interleave them with its own checks:

1. `check_arc_turns` - the P word, during rs274's whole-block checks.
2. `check_arc_format` - plane, R vs IJK presence (start of convert_arc).
3. `check_arc_feed` - feed rate for the feed mode (right after 2).
4. `arc_center_words` - per-plane word checks; returns the centre words.
5. `arc_from_center` / `arc_from_radius` - geometry and its errors.
"""

from __future__ import annotations

import math
from collections import namedtuple

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Mapping, Optional, Tuple

    Point2 = Tuple[float, float]

from runtime.errors import GCodeError
from runtime.ops import c_hypot, plus_half_pi

MM_PER_INCH = 25.4

#: Smallest radius that is not a "zero-radius" arc, and slack for R arcs
#: whose end point is slightly beyond the diameter (rs274's RADIUS_TOLERANCE).
RADIUS_TOLERANCE_INCH = 0.00005
RADIUS_TOLERANCE_MM = RADIUS_TOLERANCE_INCH * MM_PER_INCH

#: Default allowed difference between start and end radius of a centre-format
#: arc: wide enough that centres rounded to 0.001 in / 0.01 mm still pass.
#: The INI file ([RS274NGC] CENTER_ARC_RADIUS_TOLERANCE_*) can change these.
CENTER_ARC_RADIUS_TOLERANCE_INCH = 2 * 0.001 * math.sqrt(2)
CENTER_ARC_RADIUS_TOLERANCE_MM = 2 * 0.01 * math.sqrt(2)

#: Allowed relative difference of the two radii. rs274 2.9 rejects an arc
#: when BOTH the absolute and the relative tolerance are exceeded, or the
#: absolute one a hundred times over.
SPIRAL_RELATIVE_TOLERANCE = 0.001

#: An R arc whose chord is within this ratio of the diameter is treated as an
#: exact semicircle, so asin() never sees a value above 1.
_SEMICIRCLE_SLACK = 1e-12

#: rs274's feed modes (the numbers of its FEED_MODE enum).
UNITS_PER_MINUTE = 0
INVERSE_TIME = 1
UNITS_PER_REVOLUTION = 2

#: Plane name -> machine axis letters in (first, second, axis) order.
PLANE_AXES = {"XY": ("X", "Y", "Z"), "XZ": ("Z", "X", "Y"), "YZ": ("Y", "Z", "X")}

#: The G17.1/G18.1/G19.1 planes, in which rs274 refuses arcs.
UVW_PLANES = ("UV", "UW", "VW")

#: The centre-offset word letters of each plane, in (first, second) order.
_CENTER_LETTERS = {"XY": ("i", "j"), "XZ": ("k", "i"), "YZ": ("j", "k")}
#: The centre letter that is not allowed in each plane.
_FORBIDDEN_CENTER_LETTER = {"XY": "k", "XZ": "j", "YZ": "i"}


class Arc(namedtuple("Arc", "end1 end2 center1 center2 rotation")):
    """One arc in plane coordinates: ARC_FEED's first five arguments.

    ``rotation`` is rs274's signed turn count: +P for G3 (counter-clockwise),
    -P for G2 (clockwise), P defaulting to 1.
    """

    __slots__ = ()


# --------------------------------------------------------------------------
# Coordinates and tolerances
# --------------------------------------------------------------------------


def to_plane(plane: str, x: float, y: float, z: float) -> Tuple[float, float, float]:
    """(x, y, z) -> (first, second, axis) for ``plane`` ("XY", "XZ" or "YZ")."""
    if plane == "XY":
        return x, y, z
    if plane == "XZ":
        return z, x, y
    return y, z, x


def from_plane(
    plane: str, first: float, second: float, axis: float
) -> Tuple[float, float, float]:
    """(first, second, axis) for ``plane`` -> (x, y, z); inverse of `to_plane`."""
    if plane == "XY":
        return first, second, axis
    if plane == "XZ":
        return second, axis, first
    return axis, first, second


def radius_tolerance(inch: bool) -> float:
    """rs274's zero-radius / R-reach tolerance for the active length units."""
    return RADIUS_TOLERANCE_INCH if inch else RADIUS_TOLERANCE_MM


def center_tolerance(inch: bool) -> float:
    """The default start/end radius tolerance for centre-format arcs."""
    return CENTER_ARC_RADIUS_TOLERANCE_INCH if inch else CENTER_ARC_RADIUS_TOLERANCE_MM


# --------------------------------------------------------------------------
# Block checks, in the order rs274 makes them
# --------------------------------------------------------------------------


def check_arc_turns(p: Optional[float]) -> int:
    """Validate an arc's P word and return the number of turns (1 if absent).

    rs274 makes this check with its whole-block checks, before anything on
    the line executes.
    """
    if p is None:
        return 1
    turns = _round_to_int(p)
    if abs(turns - p) > 0.001:
        raise GCodeError("P value not an integer with M19 G2 or G3")
    if turns < 1:
        raise GCodeError("P value should be 1 or greater with G2 or G3")
    return turns


def check_arc_format(plane: str, words: Mapping[str, float]) -> None:
    """The first checks of an arc move: the plane, then R versus I/J/K.

    ``words`` maps the block's lower-case word letters (as passed to
    ``Machine.block``) to values; only presence matters here.
    """
    if plane in UVW_PLANES:
        raise GCodeError("Cannot do an arc in planes G17.1, G18.1, or G19.1")
    has_r = "r" in words
    has_ijk = any(letter in words for letter in "ijk")
    if not has_r and not has_ijk:
        raise GCodeError("R i j k words all missing for arc")
    if has_r and has_ijk:
        raise GCodeError("Mixed radius ijk format for arc")


def check_arc_feed(
    feed_mode: int, feed_rate: float, spindle_speed: float, has_f_word: bool
) -> None:
    """The feed checks rs274 makes on an arc right after `check_arc_format`."""
    if feed_mode == INVERSE_TIME:
        if not has_f_word:
            raise GCodeError("F word missing with inverse time arc move")
        return
    if feed_rate == 0.0:
        raise GCodeError("Cannot make arc with zero feed rate")
    if feed_mode == UNITS_PER_REVOLUTION and spindle_speed == 0.0:
        raise GCodeError("Cannot feed with zero spindle speed in feed per rev mode")


def arc_center_words(
    plane: str, words: Mapping[str, float], absolute_ijk: bool
) -> Optional[Point2]:
    """Per-plane word checks; the centre words in (first, second) order.

    Returns None for a radius-format arc (which must have an end-point word
    in the plane, since a full circle cannot be given by R). In incremental
    IJK mode a missing centre word means 0; in absolute mode (G90.1) it is an
    error. Run after `check_arc_format` and `check_arc_feed`.
    """
    if "r" in words:
        _check_radius_format_end_words(plane, words)
        return None
    forbidden = _FORBIDDEN_CENTER_LETTER[plane]
    if forbidden in words:
        raise GCodeError(
            f"{forbidden.upper()} word given for arc in {plane.lower()} plane"
        )
    first, second = _CENTER_LETTERS[plane]
    # rs274 checks the letters in alphabetical order, not plane order.
    for letter in sorted((first, second)):
        if letter not in words and absolute_ijk:
            raise GCodeError(f"{letter.upper()} word missing in absolute center arc")
    return words.get(first, 0.0), words.get(second, 0.0)


def _check_radius_format_end_words(plane: str, words: Mapping[str, float]) -> None:
    first, second, _ = PLANE_AXES[plane]
    letters = sorted((first.lower(), second.lower()))
    present = any(letter in words for letter in letters)
    if plane == "XY":
        # Polar coordinates can give the end point of an XY arc too.
        present = present or "polar_dist" in words or "polar_angle" in words
    if not present:
        raise GCodeError(
            f"{letters[0].upper()} and {letters[1]} words missing for arc in {plane.lower()} plane"
        )


# --------------------------------------------------------------------------
# Geometry
# --------------------------------------------------------------------------


def arc_from_center(
    clockwise: bool,
    plane: str,
    start: Point2,
    end: Point2,
    center_words: Point2,
    absolute_ijk: bool,
    turns: int,
    inch: bool,
    spiral_tolerance: Optional[float] = None,
) -> Arc:
    """A centre-format (I/J/K) arc; raises rs274's radius errors.

    ``center_words`` come from `arc_center_words`: offsets from ``start``
    (G91.1, the default) or the centre itself (G90.1). ``spiral_tolerance``
    is the allowed start/end radius difference; None means rs274's default
    for the units (see `center_tolerance`; the INI file may override it).
    """
    if absolute_ijk:
        center = center_words
    else:
        center = (start[0] + center_words[0], start[1] + center_words[1])
    r1 = c_hypot(center[0] - start[0], center[1] - start[1])
    r2 = c_hypot(center[0] - end[0], center[1] - end[1])
    if r1 < radius_tolerance(inch) or r2 < radius_tolerance(inch):
        raise GCodeError(
            f"Zero-radius arc: {_describe_points(plane, start, center, end, r1, r2)}"
        )
    abs_err = abs(r1 - r2)
    rel_err = abs_err / max(r1, r2)
    if spiral_tolerance is None:
        spiral_tolerance = center_tolerance(inch)
    # A difference a hundred times the tolerance fails even on a huge arc.
    if abs_err > spiral_tolerance * 100.0 or (
        abs_err > spiral_tolerance and rel_err > SPIRAL_RELATIVE_TOLERANCE
    ):
        raise GCodeError(
            "Radius to end of arc differs from radius to start: "
            f"{_describe_points(plane, start, center, end, r1, r2)} abs_err={abs_err:.4g} rel_err={rel_err * 100:.4f}%"
        )
    return Arc(end[0], end[1], center[0], center[1], _rotation(clockwise, turns))


def arc_from_radius(
    clockwise: bool, start: Point2, end: Point2, radius: float, turns: int, inch: bool
) -> Arc:
    """A radius-format (R) arc; negative R asks for the arc longer than half."""
    if end[0] == start[0] and end[1] == start[1]:
        raise GCodeError("Current point same as end point of arc")
    centre = radius_centre(
        clockwise, start[0], start[1], end[0], end[1], radius, radius_tolerance(inch)
    )
    if centre is None:
        raise GCodeError("Arc radius too small to reach end point")
    return Arc(end[0], end[1], centre[0], centre[1], _rotation(clockwise, turns))


#: The NaN that x86's invalid operations make (sign bit set: printf's "-nan").
_DEFAULT_NAN = -math.nan


def radius_centre(
    clockwise: bool, s1: float, s2: float, e1: float, e2: float, radius: float, zero: float
) -> "Optional[Tuple[float, float]]":
    """The centre of an R-format arc from (s1, s2) to (e1, e2), by rs274's
    operations in its order (arc_data_r), or None when R is too short to
    reach the end point (more than ``zero`` short). The end point must differ
    from the start point.

    The centre lies on the perpendicular bisector of the chord: to the right
    of it for a short clockwise arc (or a long counter-clockwise one), to
    the left otherwise. An R of 0 with a chord within ``zero`` makes rs274
    divide 0 by 0: its centre is then the default NaN, printed ``-nan``."""
    abs_radius = abs(radius)
    mid1 = (e1 + s1) / 2.0
    mid2 = (e2 + s2) / 2.0
    half = c_hypot(mid1 - e1, mid2 - e2)  # printed through the centre: exact
    if half - abs_radius > zero:
        return None
    if abs_radius == 0.0:
        return _DEFAULT_NAN, _DEFAULT_NAN
    if half / abs_radius > 1 - _SEMICIRCLE_SLACK:
        half = abs_radius  # a semicircle: asin() never sees more than 1
    theta = plus_half_pi(
        math.atan2(e2 - s2, e1 - s1), -1 if clockwise == (radius > 0) else 1
    )
    offset = abs_radius * math.cos(math.asin(half / abs_radius))
    return mid1 + offset * math.cos(theta), mid2 + offset * math.sin(theta)


def arc_angle(start: Point2, arc: Arc) -> float:
    """Signed angle swept by ``arc`` from ``start`` (radians, CCW positive).

    A start and end at the same angle make a full circle, never zero.
    """
    alpha = math.atan2(start[1] - arc.center2, start[0] - arc.center1)
    beta = math.atan2(arc.end2 - arc.center2, arc.end1 - arc.center1)
    full = 2 * math.pi
    if arc.rotation > 0:
        if beta <= alpha:
            beta += full
        return beta - alpha + (arc.rotation - 1) * full
    if alpha <= beta:
        alpha += full
    return beta - alpha + (arc.rotation + 1) * full


def arc_length(start: Point2, start_axis: float, arc: Arc, end_axis: float) -> float:
    """Path length of a (possibly helical) arc, as used for G93 feed rates."""
    radius = c_hypot(arc.center1 - start[0], arc.center2 - start[1])
    theta = arc_angle(start, arc)
    if end_axis == start_axis:
        return radius * abs(theta)
    return c_hypot(radius * theta, end_axis - start_axis)


# --------------------------------------------------------------------------
# Helpers
# --------------------------------------------------------------------------


def _rotation(clockwise: bool, turns: int) -> int:
    return -turns if clockwise else turns


def _round_to_int(value: float) -> int:
    """rs274's round_to_int: halves round up (towards +infinity)."""
    return int(math.floor(value + 0.5))


def _describe_points(
    plane: str, start: Point2, center: Point2, end: Point2, r1: float, r2: float
) -> str:
    """The 'start=(..) center=(..) end=(..) r1=.. r2=..' part of arc errors."""
    a, b, _ = PLANE_AXES[plane]

    def point(p: Point2) -> str:
        return f"({a}{p[0]:.4f},{b}{p[1]:.4f})"

    return f"start={point(start)} center={point(center)} end={point(end)} r1={r1:.4f} r2={r2:.4f}"
