"""Statistics of a program's toolpath and an estimate of its cycle time.

:class:`StatsCanon` is a canon back end: run a program against it (no trace
is formatted) and ask :meth:`StatsCanon.report` for the numbers.

The cycle time model (also in ``ngc2py stats --help`` and the README):

* every move starts and ends at rest (exact stop): a trapezoidal velocity
  profile, accelerating at ``acceleration`` up to the move's speed and
  braking to a stop, or a triangle when the move is too short to reach it.
  Real machines blending moves (G64) are faster on short segments, so this
  errs on the long side;
* rapids (G0) run at ``rapid_rate``; feed moves and arcs at the programmed
  feed rate. Inverse time moves (G93) need nothing special: LinuxCNC
  turns each ``F`` into a units-per-minute rate before the move, and that is
  what the canon sees. Feed per revolution (G95) is the rate times the
  spindle speed in force (``S``, taken as rpm, also under G96); moves with
  no usable rate are counted in ``untimed_moves`` and add no time;
* a move of the rotary axes alone runs at the feed rate in degrees per
  minute, as LinuxCNC does; rotary axes add no length otherwise;
* dwells (G4) add their time; each tool change (M6) adds ``tool_change_time``.

Lengths and extents are in the program's units: those in force at its first
move (a program that switches units has the rest converted). Extents are the
bounding box of every point the tool is sent to, arcs included (their
bulge, not just their end points), in program coordinates as the trace
prints them; the start position counts only if the program returns to it.
"""

from __future__ import annotations

import math
from collections import namedtuple
from functools import reduce
from operator import add

TYPE_CHECKING = False  # typing and dataclasses cost milliseconds at every start
if TYPE_CHECKING:
    from typing import Dict, List, Optional

from runtime.fast.hole_rows import HOLE_MOVES, RESTATED_SWITCHES
from runtime.toolpath import (
    AXIS_NAMES,
    LINEAR,
    MM_PER_INCH,
    PLANE_AXES,
    Arc,
    Extents,
    Point,
    ToolpathCanon,
    arc_geometry,
    distance,
    helix_length,
)

#: Default rapid rate, mm/min.
DEFAULT_RAPID_RATE = 3000.0
#: Default acceleration, mm/s^2.
DEFAULT_ACCELERATION = 500.0

#: What StatsCanon.hole_moves takes in columns: moves, and the switches
#: around a hole (dwells counted; the others change nothing it counts).
#: (a restated line's comment is no statistic; its F goes call by call)
_HOLE_CALLS = (HOLE_MOVES | RESTATED_SWITCHES) - {"set_feed_rate"}


class Model(
    namedtuple(
        "Model",
        "rapid_rate acceleration tool_change_time",
        defaults=(DEFAULT_RAPID_RATE, DEFAULT_ACCELERATION, 0.0),
    )
):
    """Machine limits for the cycle time estimate, in millimetres: the rapid
    rate (mm/min), the acceleration (mm/s^2; 0 or inf: instant) and the
    seconds a tool change takes."""

    __slots__ = ()


def move_time(length: float, rate_per_minute: float, acceleration: float) -> float:
    """Seconds to move ``length`` from rest to rest at up to ``rate_per_minute``."""
    if length <= 0.0:
        return 0.0
    speed = rate_per_minute / 60.0
    if not acceleration or math.isinf(acceleration):
        return length / speed
    ramp = speed * speed / acceleration  # distance to speed up and slow down
    if length >= ramp:
        return length / speed + speed / acceleration
    return 2.0 * math.sqrt(length / acceleration)


def python_arc_sums(
    s1, s2, sn, start_rest, first_end, second_end, first_axis, second_axis,
    rotation, axis_end, rest, box, rest_low, rest_high, f, s, n, length,
    feed_length, time, rate, acceleration,
):  # fmt: skip
    """A batch of arcs from (s1, s2, sn), the start's plane and normal
    coordinates, as columns of arc_feed's arguments (``rest``: the six of
    A B C U V W; ``start_rest``: the start's); a row of rotation 0 is a
    straight feed (Canon.contour_moves). Every end goes into the extents
    (``box`` is Extents._xyz, ``f s n`` the plane's axes in it; ``rest_low``,
    ``rest_high``: changed in place). Returns ``(length, feed_length, time,
    untimed, straights)``: the arcs' and the straight feeds' length totals
    and the time total with each move's length (:func:`helix_length`,
    :func:`distance`) and time (:meth:`StatsCanon._time`) added in order, the
    count of moves of no usable rate and the count of straight feeds. An arc
    whose square of its larger radius about its centre is not inside the box
    as it stands adds its extreme points to it, as :meth:`StatsCanon.arc`
    does. runtime._arc_stats.arc_sums does the same in C."""
    rest_low[:] = [min(low, *column) for low, column in zip(rest_low, rest)]
    rest_high[:] = [max(high, *column) for high, column in zip(rest_high, rest)]
    untimed = straights = 0
    start, end = [0.0, 0.0], [0.0, 0.0]
    plane = (0, 1, 2)
    at = [0.0, 0.0, 0.0]
    was = [0.0, 0.0, 0.0]
    turned = start_rest[:3]
    ends = zip(first_end, second_end, first_axis, second_axis, rotation, axis_end)
    for k, (e1, e2, c1, c2, turns, en) in enumerate(ends):
        at[f], at[s], at[n] = e1, e2, en
        for i in range(3):
            box[2 * i] = min(box[2 * i], at[i])
            box[2 * i + 1] = max(box[2 * i + 1], at[i])
        now = rest[0][k], rest[1][k], rest[2][k]
        if not turns:  # a straight feed
            was[f], was[s], was[n] = s1, s2, sn
            step = distance(was, at)
            feed_length += step
            straights += 1
            if step == 0.0:  # rotary axes alone: degrees at the same rate
                step = max(abs(now[i] - turned[i]) for i in range(3))
        else:
            start[0], start[1], end[0], end[1] = s1, s2, e1, e2
            sweep, r0, r1, theta0 = arc_geometry(start, end, plane, (c1, c2), turns)
            # whether the arc is inside the box with its end: the box only
            # grows and holds no point off the path, so an arc inside it is
            # inside the final one
            radius = r0 if r0 > r1 else r1
            if not (
                box[2 * f] <= c1 - radius
                and c1 + radius <= box[2 * f + 1]
                and box[2 * s] <= c2 - radius
                and c2 + radius <= box[2 * s + 1]
            ):
                # the plane's two coordinates of its extreme points (the
                # others lie between its ends')
                arc = Arc((s1, s2), (e1, e2), plane, (c1, c2), sweep, r0, r1, theta0)
                for first, second in arc.extreme_points()[2:]:
                    box[2 * f] = min(box[2 * f], first)
                    box[2 * f + 1] = max(box[2 * f + 1], first)
                    box[2 * s] = min(box[2 * s], second)
                    box[2 * s + 1] = max(box[2 * s + 1], second)
            step = helix_length(sweep, r0, r1, en - sn)
            length += step
        if step != 0.0:
            if rate <= 0.0:
                untimed += 1
            else:
                time += move_time(step, rate, acceleration)
        s1, s2, sn, turned = e1, e2, en, now
    return length, feed_length, time, untimed, straights


def python_straight_sums(
    start, columns, rate, acceleration, box, rest_low, rest_high, length, time
):
    """A run of straight moves from ``start`` through the points of
    ``columns`` (nine lists, X .. W, in millimetres). Every point goes into
    the extents (``box`` is Extents._xyz; ``rest_low``, ``rest_high``: changed
    in place). Returns ``(length, time, untimed)``: the totals with each
    move's length (:func:`distance`) and time (:func:`move_time`, of its
    rotary travel when X, Y and Z stand still) added in order, and the count
    of moves of no usable rate. runtime._arc_stats.straight_sums does the
    same in C."""
    for i, column in enumerate(columns[:3]):
        box[2 * i] = min(box[2 * i], *column)
        box[2 * i + 1] = max(box[2 * i + 1], *column)
    rest_low[:] = [min(low, *column) for low, column in zip(rest_low, columns[3:])]
    rest_high[:] = [max(high, *column) for high, column in zip(rest_high, columns[3:])]
    untimed = 0
    for point in zip(*columns):
        step = distance(start, point)
        length += step
        if step == 0.0:  # rotary axes alone: degrees at the same rate
            step = max(abs(point[i] - start[i]) for i in (3, 4, 5))
        if step != 0.0:
            if rate <= 0.0:
                untimed += 1
            else:
                time += move_time(step, rate, acceleration)
        start = point
    return length, time, untimed


def python_distances(x0, y0, z0, x1, y1, z1):
    """:func:`distance` from each point of the columns (x0, y0, z0) to the
    same point of (x1, y1, z1): a list. runtime._arc_stats.distances does
    the same in C."""
    return list(map(distance, zip(x0, y0, z0), zip(x1, y1, z1)))


def python_hole_sums(lengths, timed, kinds, rates, acceleration, sums):
    """Holes drilled alike (:meth:`StatsCanon.hole_moves`): ``lengths`` and
    ``timed`` a column each of a hole's moves (the move's length at each
    hole, and the travel it is timed by), ``kinds`` 0 (rapid) or 1 (feed)
    each, ``rates`` the two rates, ``sums`` the (rapid length, feed length,
    time) so far. Hole by hole, move by move, the length goes onto its
    kind's total and the move's time (:func:`move_time`) onto the time.
    Returns the three totals and the count of moves of no usable rate.
    runtime._arc_stats.hole_sums does the same in C."""
    totals = [sums[0], sums[1]]
    time = sums[2]
    untimed = 0
    for k in range(len(lengths[0]) if lengths else 0):
        for length, travel, kind in zip(lengths, timed, kinds):
            totals[kind] += length[k]
            rate = rates[kind]
            if rate <= 0.0:
                untimed += travel[k] != 0.0
            else:
                time += move_time(travel[k], rate, acceleration)
    return totals[0], totals[1], time, untimed


try:  # the same in C (runtime/_arc_stats.c)
    from runtime._arc_stats import arc_sums, distances, hole_sums, straight_sums
except ImportError:  # not built
    arc_sums, straight_sums = python_arc_sums, python_straight_sums
    distances, hole_sums = python_distances, python_hole_sums


class StatsCanon(ToolpathCanon):
    """Counts, lengths, extents and time of everything the program does."""

    def __init__(self, model: Optional[Model] = None) -> None:
        super().__init__()
        self.model = model or Model()
        self.extents = Extents()
        self.lengths = {"rapid": 0.0, "feed": 0.0, "arc": 0.0}
        self.counts = {"rapid": 0, "feed": 0, "arc": 0, "probe": 0}
        self.tool_changes = 0
        self.dwells = 0
        self.dwell_time = 0.0
        self.motion_time = 0.0
        self.untimed_moves = 0
        self.feed_rate = 0.0  # mm/min (or mm/rev)
        self.per_rev = False
        self.rpm = 0.0
        #: A subclass watches moves (its own line()): every move goes there.
        self._watched = type(self).line is not StatsCanon.line

    # --- rates -------------------------------------------------------------
    def set_feed_rate(self, rate):
        self.feed_rate = self.to_mm(rate)

    def set_feed_mode(self, spindle, mode):
        self.per_rev = mode == 1

    def set_spindle_speed(self, spindle, rpm):
        self.rpm = abs(rpm)

    def _feed_per_minute(self) -> float:
        return self.feed_rate * self.rpm if self.per_rev else self.feed_rate

    # --- events ----------------------------------------------------------
    def change_tool(self, slot):
        self.tool_changes += 1

    def dwell(self, seconds):
        self.dwells += 1
        self.dwell_time += seconds

    def line(self, kind: str, start: Point, end: Point) -> None:
        self.extents.add(end)
        length = distance(start, end)
        self.counts[kind] += 1
        self.lengths["rapid" if kind == "rapid" else "feed"] += length
        if kind == "rapid":
            rate = self.model.rapid_rate
        else:
            rate = self._feed_per_minute()
        if length == 0.0:
            # Rotary axes alone: degrees at the same numeric rate.
            length = max(abs(end[i] - start[i]) for i in (3, 4, 5))
        self._time(length, rate)

    def straight_traverse(self, x, y, z, a, b, c, u, v, w):
        if self._watched or self.inches:
            return super().straight_traverse(x, y, z, a, b, c, u, v, w)
        self._straight("rapid", self.model.rapid_rate, (x, y, z, a, b, c, u, v, w))

    def straight_feed(self, x, y, z, a, b, c, u, v, w):
        if self._watched or self.inches:
            return super().straight_feed(x, y, z, a, b, c, u, v, w)
        self._straight("feed", self._feed_per_minute(), (x, y, z, a, b, c, u, v, w))

    def _straight(self, kind: str, rate: float, end: Point) -> None:
        """A move in millimetres: ToolpathCanon's and :meth:`line`'s work in
        one call (the same arithmetic), the usual case of a canned cycle's
        moves and of a loop's, which come one call each."""
        if self.first_units is None:
            self.first_units = False
        start = self.position
        self.position = end
        self.extents.add(end)
        length = distance(start, end)
        self.counts[kind] += 1
        self.lengths[kind] += length
        if length == 0.0:
            # Rotary axes alone: degrees at the same numeric rate.
            length = max(abs(end[i] - start[i]) for i in (3, 4, 5))
            if length == 0.0:
                return
        if rate <= 0.0:
            self.untimed_moves += 1
        else:
            self.motion_time += move_time(length, rate, self.model.acceleration)

    def straight_moves(self, feed, lines, x, y, z, a, b, c, u, v, w):
        """A run of straight moves, a column at a time: the same counts,
        lengths, extents and times as one :meth:`line` a move, with the loop
        in C where it is built (:func:`straight_sums`)."""
        if type(self).line is not StatsCanon.line:  # a subclass watches moves
            return super().straight_moves(feed, lines, x, y, z, a, b, c, u, v, w)
        count = len(lines)
        if not count:
            return
        if self.first_units is None:
            self.first_units = self.inches
        columns = [x, y, z, a, b, c, u, v, w]
        if self.inches:
            for i in LINEAR:
                columns[i] = [value * MM_PER_INCH for value in columns[i]]
        kind = "feed" if feed else "rapid"
        rate = self._feed_per_minute() if feed else self.model.rapid_rate
        extents = self.extents
        arguments = (
            tuple(self.position),
            columns,
            rate,
            self.model.acceleration,
            extents._xyz,
            extents._rest_low,
            extents._rest_high,
            self.lengths[kind],
            self.motion_time,
        )
        sums = straight_sums(*arguments)
        if sums is None:  # a length overflowed in C
            sums = python_straight_sums(*arguments)
        self.lengths[kind], self.motion_time, untimed = sums
        self.untimed_moves += untimed
        self.counts[kind] += count
        self.position = tuple(column[-1] for column in columns)
        extents._rest = self.position[3:]

    def hole_moves(self, recording, lines, first, second, axes, start):
        """Holes drilled alike (runtime.canon.Canon.hole_moves), a column at a
        time: each recorded move's end points as columns, its lengths by one
        :func:`distances`, then the same counts, lengths, extents,
        times and dwells as one call a move (sums added in program order)."""
        names = {name for name, _, _ in recording}
        if self._watched or self.inches or not names <= _HOLE_CALLS:
            return super().hole_moves(recording, lines, first, second, axes, start)
        if self.first_units is None:
            self.first_units = False
        ia, ib = axes
        count = len(lines)
        before_first, before_second = [start[0]] + first[:-1], [start[1]] + second[:-1]
        places = {"hole": (first, second), "start": (before_first, before_second)}
        moves = [(name, args, where) for name, args, where in recording if where]
        dwells = [args[0] for name, args, _ in recording if name == "dwell"]
        kinds = [
            "rapid" if name == "straight_traverse" else "feed" for name, _, _ in moves
        ]

        def xyz(args, where: str, hole: int) -> list:
            """X Y Z of a move's end at hole number ``hole``."""
            point = list(args[:3])
            point[ia], point[ib] = places[where][0][hole], places[where][1][hole]
            return point

        def columns(args, where: str) -> list:
            """X Y Z of a move's end at every hole, as columns."""
            out = [[value] * count for value in args[:3]]
            out[ia], out[ib] = places[where]
            return out

        # Each move starts where the one before ended (the first of a hole
        # where the hole before ended, the very first at the position). A
        # move that starts and ends at the same place in the plane (down and
        # up at the hole) is as long at every hole: measured once, at the
        # first hole it is so for.
        lengths: List[list] = []
        #: each move's length where it is as long at every hole (else None)
        alike: List[Optional[float]] = []
        level = 3 - ia - ib
        # where the plane's two differences of a move within one place are
        # zeros (finite coordinates): its length is the very double of the
        # level's alone
        finite = {
            where: a - a == 0.0 and b - b == 0.0
            for where, (a, b) in (
                ("hole", (first[0], second[0])),
                ("start", (start[0], start[1])),
            )
        }
        _, was, place = moves[-1]
        for j, (_, args, where) in enumerate(moves):
            if j and place == where:
                if finite[where]:
                    length = distance((0.0, 0.0, was[level]), (0.0, 0.0, args[level]))
                else:
                    length = distance(xyz(was, where, 0), xyz(args, where, 0))
                lengths.append([length] * count)
                alike.append(length)
                was, place = args, where
                continue
            alike.append(None)
            if not j and place == "hole" and where == "start" and count > 1:
                # from the hole before to the point above it: alike but the first
                begin = [self.position[i] for i in range(3)]
                length = distance(xyz(was, where, 1), xyz(args, where, 1))
                lengths.append(
                    [distance(begin, xyz(args, where, 0))] + [length] * (count - 1)
                )
            else:
                finish = columns(args, where)
                if j:
                    begin = columns(was, place)
                else:
                    last = columns(was, place)
                    begin = [[self.position[i]] + last[i][:-1] for i in range(3)]
                lengths.append(
                    distances(*begin, *finish) or python_distances(*begin, *finish)
                )
            was, place = args, where
        timed = lengths[:]
        for j, (_, args, _) in enumerate(moves):
            same = alike[j]
            if 0.0 in lengths[j] if same is None else same == 0.0:
                # rotary axes alone: degrees at the same rate
                # (the same for every hole but the very first move's)
                turned = [
                    max(abs(args[i] - before[i]) for i in (3, 4, 5))
                    for before in (
                        self.position if not j else moves[j - 1][1],
                        moves[j - 1][1],
                    )
                ]
                timed[j] = [length or turned[1] for length in lengths[j]]
                timed[j][0] = lengths[j][0] or turned[0]
        feeds = kinds.count("feed")
        self.counts["feed"] += feeds * count
        self.counts["rapid"] += (len(kinds) - feeds) * count
        # the holes' box on the plane: each move's two corners of it
        boxes = {
            "hole": (min(first), min(second), max(first), max(second)),
            "start": (
                min(before_first),
                min(before_second),
                max(before_first),
                max(before_second),
            ),
        }
        # the corners of them all, axis by axis, the moves in order (min and
        # max keep the first of equals, as adding them one by one would):
        # the other axes from the moves' own ends, the plane's from the boxes
        ends = list(zip(*[args for _, args, _ in moves]))
        low, high = list(map(min, ends)), list(map(max, ends))
        corners = list(zip(*[boxes[where] for _, _, where in moves]))
        low[ia], low[ib] = min(corners[0]), min(corners[1])
        high[ia], high[ib] = max(corners[2]), max(corners[3])
        self.extents.add(low)
        self.extents.add(high)
        lengths_of = self.lengths
        rapid, feed, self.motion_time, untimed = hole_sums(
            lengths,
            timed,
            [1 if kind == "feed" else 0 for kind in kinds],
            (self.model.rapid_rate, self._feed_per_minute()),
            self.model.acceleration,
            (lengths_of["rapid"], lengths_of["feed"], self.motion_time),
        )
        lengths_of["rapid"], lengths_of["feed"] = rapid, feed
        self.untimed_moves += untimed
        if dwells:
            self.dwells += count * len(dwells)
            self.dwell_time = reduce(add, dwells * count, self.dwell_time)
        _, args, where = moves[-1]
        self.position = tuple(xyz(args, where, count - 1)) + tuple(args[3:])

    def arc_moves(self, lines, *columns, planes=None):
        """A batch of arcs (runtime.canon.Canon.arc_moves): as a contour of
        arcs alone (:meth:`contour_moves`)."""
        axes = PLANE_AXES.get(self.plane)
        if axes is None:  # a UVW plane: row by row
            return super().arc_moves(lines, *columns, planes=planes)
        self.contour_moves(axes, lines, *columns, planes=planes)

    def contour_moves(
        self, axes, lines, first_end, second_end, first_axis, *rest, planes=None
    ):
        """Arcs and the straight feeds between them (runtime.canon.Canon.
        contour_moves): the same counts, lengths, extents and times as one
        :meth:`arc` an arc and one :meth:`straight_feed` a line, the loop in
        C where it is built (:func:`arc_sums`). Every end goes into the
        extents at once; an arc adds more (its extreme points) only when the
        square of its radius about its centre is not inside them (the box
        only grows, so that is the same box as move by move)."""
        columns = (first_end, second_end, first_axis) + rest
        watched = type(self).line is not StatsCanon.line
        # Row by row: a subclass watching moves, inch conversions.
        if (
            watched
            or type(self).arc is not StatsCanon.arc
            or self.inches
            or (planes and not self._planes_told(planes))
        ):
            return super().contour_moves(axes, lines, *columns, planes=planes)
        count = len(lines)
        if not count:
            return
        if self.first_units is None:
            self.first_units = False
        f, s, n = axes
        second_axis, rotation, axis_end, *other = rest
        other = list(other)
        start = self.position
        extents = self.extents
        if rotation[0]:  # (an arc's start is one of its points)
            extents.add(start)
        rate = self._feed_per_minute()
        arguments = [
            start[f], start[s], start[n], tuple(start[3:]),
            first_end, second_end, first_axis, second_axis, rotation, axis_end,
            other, extents._xyz, extents._rest_low, extents._rest_high, f, s, n,
            self.lengths["arc"], self.lengths["feed"], self.motion_time,
            rate, self.model.acceleration,
        ]  # fmt: skip
        sums = arc_sums(*arguments)
        if sums is None:  # a straight feed's length overflowed in C
            sums = python_arc_sums(*arguments)
        arc_length, feed_length, self.motion_time, untimed, straights = sums
        self.lengths["arc"], self.lengths["feed"] = arc_length, feed_length
        self.counts["arc"] += count - straights
        self.counts["feed"] += straights
        self.untimed_moves += untimed
        end = [0.0] * 9
        end[f], end[s], end[n] = first_end[-1], second_end[-1], axis_end[-1]
        end[3:] = [column[-1] for column in other]
        self.position = tuple(end)
        extents._rest = self.position[3:]  # (Extents.add's last look)

    def arc(self, arc: Arc) -> None:
        extents = self.extents
        if extents.encloses(arc.axes, arc.centre, max(arc.r0, arc.r1)):
            # Its bulge is inside the box already (most arcs of a long
            # program): its ends carry what the other axes add.
            extents.add(arc.start)
            extents.add(arc.end)
        else:
            for point in arc.extreme_points():
                extents.add(point)
        length = arc.length
        self.counts["arc"] += 1
        self.lengths["arc"] += length
        self._time(length, self._feed_per_minute())

    def spline(self, path) -> None:
        # one feed move, along the polyline of the curve
        for point in path[1:]:
            self.extents.add(point)
        length = sum(distance(a, b) for a, b in zip(path, path[1:]))
        self.counts["feed"] += 1
        self.lengths["feed"] += length
        self._time(length, self._feed_per_minute())

    def _time(self, length: float, rate: float) -> None:
        if length == 0.0:
            return
        if rate <= 0.0:
            self.untimed_moves += 1
            return
        self.motion_time += move_time(length, rate, self.model.acceleration)

    # --- the report ------------------------------------------------------
    @property
    def cycle_time(self) -> float:
        """Estimated seconds: motion, dwells and tool changes."""
        changes = self.tool_changes * self.model.tool_change_time
        return self.motion_time + self.dwell_time + changes

    def report(self) -> Dict:
        """Everything as plain data (what ``ngc2py stats --json`` prints)."""
        inches = bool(self.first_units)
        scale = 1.0 / MM_PER_INCH if inches else 1.0
        extents = {}
        if not self.extents.empty:
            for i, name in enumerate(AXIS_NAMES):
                low, high = self.extents.low[i], self.extents.high[i]
                if name in "xyz" or low != 0.0 or high != 0.0:
                    if i in (3, 4, 5):  # degrees
                        extents[name] = [low, high]
                    else:
                        extents[name] = [low * scale, high * scale]
        lengths = {kind: value * scale for kind, value in self.lengths.items()}
        lengths["total"] = sum(lengths.values())
        return {
            "units": "inch" if inches else "mm",
            "extents": extents,
            "length": lengths,
            "moves": dict(self.counts, total=sum(self.counts.values())),
            "tool_changes": self.tool_changes,
            "dwells": self.dwells,
            "dwell_time": self.dwell_time,
            "untimed_moves": self.untimed_moves,
            "cycle_time": self.cycle_time,
            "model": {
                "rapid_rate": self.model.rapid_rate * scale,
                "acceleration": self.model.acceleration * scale,
                "tool_change_time": self.model.tool_change_time,
            },
        }


__all__ = [
    "DEFAULT_ACCELERATION",
    "DEFAULT_RAPID_RATE",
    "Model",
    "StatsCanon",
    "move_time",
]
