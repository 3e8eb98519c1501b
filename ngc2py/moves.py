"""``ngc2py.toolpath()``: a program's moves as NumPy arrays, for people who
simulate in Python (material removal, collision checks, cycle-time models,
previews of their own).

    >>> path = ngc2py.toolpath("part.ngc")
    >>> path.end[path.kind == ngc2py.ARC]      # every arc's end, 9 axes, mm
    >>> path.length.sum()                      # mm of travel

One row per move, in program order, in millimetres (and degrees for A, B,
C) whatever units the program uses, in program coordinates as
``runtime.toolpath`` defines them (offsets taken off, as rs274's canon
reports positions). The program runs on the compiled fast path: its moves
reach :class:`Recorder` in batches of columns (``Canon.straight_moves`` /
``arc_moves``) or one call each, and are kept in typed arrays of the
standard library until the end, when they become NumPy arrays: no Python
object per move survives the run.
"""

from __future__ import annotations

import argparse
import io
import math
from array import array
from itertools import chain, repeat
from typing import List, Optional, Tuple

import numpy as np

from runtime.canon import Canon
from runtime.toolpath import LINEAR, MM_PER_INCH, PLANE_AXES, Point, ToolpathCanon

#: ``Toolpath.kind`` values.
RAPID, FEED, ARC, PROBE = 0, 1, 2, 3
KINDS = ("rapid", "feed", "arc", "probe")
_KIND = {"rapid": RAPID, "feed": FEED, "probe": PROBE}


class ProgramError(Exception):
    """The program stopped at a G-code error: ``str()`` is rs274's report
    (message, file and line); :attr:`toolpath` holds the moves made before."""

    def __init__(self, message: str, toolpath: "Toolpath") -> None:
        super().__init__(message)
        self.toolpath = toolpath


#: A straight move's centre.
_NO_CENTRE = (math.nan, math.nan)


class Recorder(ToolpathCanon):
    """Keeps every move as a row of typed arrays (see :class:`Toolpath`).

    The start of a move is the end of the one before, except where an
    offset change shifted the position between them (``runtime.toolpath``):
    only those starts are kept, as (row, point)."""

    reads_lines = True

    def __init__(self) -> None:
        super().__init__()
        self.machine = None
        self.kinds = array("b")
        self.lines = array("l")
        self.tools = array("l")
        self.feeds = array("d")
        #: Row by row: nine ends a move (X Y Z A B C U V W), two centre
        #: coordinates a move; a single move extends each in one call.
        self.ends = array("d")
        self.centre = array("d")
        self.normal = array("b")
        self.turns = array("l")
        self.shifts: List[Tuple[int, Point]] = []
        self._last: Optional[Point] = self.position
        self._rate = 0.0  # mm/min (mm/rev under G95)
        self._tool = 0
        self._tool_known = False

    # --- what each move carries ---------------------------------------
    def set_feed_rate(self, rate):
        self._rate = self.to_mm(rate)

    def change_tool(self, slot):
        self._tool_known = False

    change_tool_number = change_tool

    def _current_tool(self) -> int:
        if not self._tool_known and self.machine is not None:
            self._tool = int(self.machine.params[5400])
            self._tool_known = True
        return self._tool

    def _line_number(self) -> int:
        return self.machine.line if self.machine is not None else 0

    def _begin(self, start: Point, rows: int) -> None:
        if start is not self._last:
            self.shifts.append((len(self.kinds), start))
        if self.first_units is None:
            self.first_units = self.inches

    # --- one call a move ---------------------------------------------
    def line(self, kind: str, start: Point, end: Point) -> None:
        self._begin(start, 1)
        self.kinds.append(_KIND[kind])
        self.lines.append(self._line_number())
        self.tools.append(self._current_tool())
        self.feeds.append(math.nan if kind == "rapid" else self._rate)
        self.ends.extend(end)
        self.centre.extend(_NO_CENTRE)
        self.normal.append(-1)
        self.turns.append(0)
        self._last = end

    def arc_feed(self, *args):
        axes = PLANE_AXES.get(self.plane)
        if axes is None or args[2] != args[2]:
            # a UVW plane, or a centre that is not a number: a straight feed
            return super().arc_feed(*args)
        first_end, second_end, first_axis, second_axis, rotation, axis_end = args[:6]
        start = self.position
        self._begin(start, 1)
        end = list(start[:3]) + list(self._point((0, 0, 0) + args[6:])[3:])
        first, second, normal = axes
        k = MM_PER_INCH if self.inches else 1.0
        end[first], end[second], end[normal] = (
            first_end * k,
            second_end * k,
            axis_end * k,
        )
        self.kinds.append(ARC)
        self.lines.append(self._line_number())
        self.tools.append(self._current_tool())
        self.feeds.append(self._rate)
        self.ends.extend(end)
        self.centre.extend((first_axis * k, second_axis * k))
        self.normal.append(normal)
        self.turns.append(rotation)
        self.position = self._last = tuple(end)

    # --- batches (runtime.fast.rows, runtime.fast.arc_rows) ---------------------
    def straight_moves(self, feed, lines, x, y, z, a, b, c, u, v, w):
        rows = len(lines)
        if not rows:
            return
        self._begin(self.position, rows)
        columns = [x, y, z, a, b, c, u, v, w]
        if self.inches:
            for i in LINEAR:
                columns[i] = [value * MM_PER_INCH for value in columns[i]]
        self._rows(FEED if feed else RAPID, lines, self._rate if feed else math.nan)
        self.ends.extend(chain.from_iterable(zip(*columns)))
        self.centre.extend(repeat(math.nan, 2 * rows))
        self.normal.extend(repeat(-1, rows))
        self.turns.extend(repeat(0, rows))
        self.position = self._last = tuple(column[-1] for column in columns)

    def arc_moves(self, lines, *columns):
        """Arcs as ``Canon.arc_moves`` gives them (arc_feed's arguments as
        columns: first_end, second_end, first_axis, second_axis, rotation,
        axis_end, a, b, c, u, v, w)."""
        if self.plane not in PLANE_AXES:
            return super().arc_moves(lines, *columns)
        self.contour_moves(PLANE_AXES[self.plane], lines, *columns)

    def contour_moves(self, axes, lines, *columns):
        """Arcs and the G1 lines between them as ``Canon.contour_moves``
        gives them (a line: rotation 0): a row each, as arc_feed and
        straight_feed make them."""
        rows = len(lines)
        if not rows:
            return
        first_end, second_end, first_axis, second_axis, rotation, axis_end = columns[:6]
        a, b, c, u, v, w = columns[6:]
        self._begin(self.position, rows)
        first, second, normal = axes
        lengths = [first_end, second_end, axis_end, first_axis, second_axis, u, v, w]
        if self.inches:
            lengths = [[value * MM_PER_INCH for value in column] for column in lengths]
        e1, e2, en, c1, c2, u, v, w = lengths
        columns = [None, None, None, a, b, c, u, v, w]
        columns[first], columns[second], columns[normal] = e1, e2, en
        if 0 in rotation:  # lines among the arcs: no centre, no normal
            nan = math.nan
            c1 = [value if turns else nan for value, turns in zip(c1, rotation)]
            c2 = [value if turns else nan for value, turns in zip(c2, rotation)]
            self.kinds.extend([ARC if turns else FEED for turns in rotation])
            self.normal.extend([normal if turns else -1 for turns in rotation])
        else:
            self.kinds.extend(repeat(ARC, rows))
            self.normal.extend(repeat(normal, rows))
        self.lines.extend(lines)
        self.tools.extend(repeat(self._current_tool(), rows))
        self.feeds.extend(repeat(self._rate, rows))
        self.ends.extend(chain.from_iterable(zip(*columns)))
        self.centre.extend(chain.from_iterable(zip(c1, c2)))
        self.turns.extend(rotation)
        self.position = self._last = tuple(column[-1] for column in columns)

    def hole_moves(self, recording, lines, first, second, axes, start):
        """Holes drilled alike (``Canon.hole_moves``): each hole's moves as
        rows, made from columns (one ``extend`` per array and batch)."""
        moves = [(name, args, where) for name, args, where in recording if where]
        ignored = all(
            getattr(type(self), name) is getattr(Canon, name)
            for name, _, where in recording
            if where is None
        )
        names = {name for name, _, _ in moves}
        if not ignored or not names <= {"straight_traverse", "straight_feed"}:
            return super().hole_moves(recording, lines, first, second, axes, start)
        count, per_hole = len(lines), len(moves)
        self._begin(self.position, count * per_hole)
        places = {
            "hole": (first, second),
            "start": ([start[0]] + first[:-1], [start[1]] + second[:-1]),
        }
        # hole by hole, move by move: nine ends, in millimetres
        ends = np.empty((count, per_hole, 9))
        k = MM_PER_INCH if self.inches else 1.0
        for j, (_, args, where) in enumerate(moves):
            ends[:, j, :] = self._point(args)
            for axis, values in zip(axes, places[where]):
                ends[:, j, axis] = values
                if k != 1.0:
                    ends[:, j, axis] *= k
        kinds = [RAPID if name == "straight_traverse" else FEED for name, _, _ in moves]
        feeds = [math.nan if kind == RAPID else self._rate for kind in kinds]
        rows = count * per_hole
        self.kinds.extend(kinds * count)
        self.lines.extend(chain.from_iterable(zip(*[lines] * per_hole)))
        self.tools.extend(repeat(self._current_tool(), rows))
        self.feeds.extend(feeds * count)
        self.ends.frombytes(ends.tobytes())
        self.centre.frombytes(np.full(2 * rows, math.nan).tobytes())
        self.normal.extend(repeat(-1, rows))
        self.turns.extend(repeat(0, rows))
        self.position = self._last = tuple(ends[-1, -1].tolist())

    def _rows(self, kind: int, lines, rate: float) -> None:
        rows = len(lines)
        self.kinds.extend(repeat(kind, rows))
        self.lines.extend(lines)
        self.tools.extend(repeat(self._current_tool(), rows))
        self.feeds.extend(repeat(rate, rows))

    def toolpath(self) -> "Toolpath":
        return Toolpath.from_recorder(self)


class Toolpath:
    """Every move of a program, one row each (``len(path)`` rows):

    ``kind``      RAPID, FEED, ARC or PROBE (int8)
    ``start``     (n, 9) the point the move starts from: X Y Z A B C U V W
    ``end``       (n, 9) where it ends (mm; degrees for A B C)
    ``centre``    (n, 2) an arc's centre in its plane's first and second axis
                  (X Y for G17, Z X for G18, Y Z for G19); NaN for straight moves
    ``normal``    the axis normal to an arc's plane (0 X, 1 Y, 2 Z; -1 straight)
    ``turns``     an arc's turns as ARC_FEED gives them: > 0 counter-clockwise,
                  < 0 clockwise, abs(turns) - 1 extra full turns; 0 straight
    ``feed``      the feed rate in force (mm/min; mm/rev under G95); NaN for rapids
    ``line``      the G-code line the move comes from (in the file running it)
    ``tool``      the tool number in the spindle
    ``units``     "inch" or "mm": the program's units at its first move
    """

    def __init__(
        self, kind, start, end, centre, normal, turns, feed, line, tool, units
    ):
        self.kind = kind
        self.start = start
        self.end = end
        self.centre = centre
        self.normal = normal
        self.turns = turns
        self.feed = feed
        self.line = line
        self.tool = tool
        self.units = units

    @classmethod
    def from_recorder(cls, recorder: Recorder) -> "Toolpath":
        count = len(recorder.kinds)
        end = np.frombuffer(recorder.ends, dtype=np.float64, count=count * 9)
        end = end.reshape(count, 9).copy()
        start = np.empty_like(end)
        start[1:] = end[:-1]
        if count:
            start[0] = 0.0
        for row, point in recorder.shifts:
            if row < count:
                start[row] = point
        centre = np.frombuffer(recorder.centre, dtype=np.float64, count=count * 2)
        centre = centre.reshape(count, 2).copy()
        return cls(
            kind=np.array(recorder.kinds, dtype=np.int8),
            start=start,
            end=end,
            centre=centre,
            normal=np.array(recorder.normal, dtype=np.int8),
            turns=np.array(recorder.turns, dtype=np.int32),
            feed=np.frombuffer(recorder.feeds, dtype=np.float64, count=count).copy(),
            line=np.array(recorder.lines, dtype=np.int64),
            tool=np.array(recorder.tools, dtype=np.int64),
            units="inch" if recorder.first_units else "mm",
        )

    def __len__(self) -> int:
        return len(self.kind)

    def __repr__(self) -> str:
        counts = ", ".join(
            "%d %s" % (int((self.kind == k).sum()), name)
            for k, name in enumerate(KINDS)
        )
        return "<Toolpath of %d moves: %s>" % (len(self), counts)

    # --- arc geometry, every arc at once ------------------------------
    def arc_frame(self):
        """For the arcs (``kind == ARC``): their row indexes, the plane's
        first and second axis indexes per arc, the start angle, the signed
        sweep (radians) and the start and end radius, as
        ``runtime.toolpath.make_arc`` works them out for one arc."""
        rows = np.flatnonzero(self.kind == ARC)
        normal = self.normal[rows]
        first = np.choose(normal, [1, 2, 0])
        second = np.choose(normal, [2, 0, 1])
        s1 = self.start[rows, first] - self.centre[rows, 0]
        s2 = self.start[rows, second] - self.centre[rows, 1]
        f1 = self.end[rows, first] - self.centre[rows, 0]
        f2 = self.end[rows, second] - self.centre[rows, 1]
        theta0 = np.arctan2(s2, s1)
        theta1 = np.arctan2(f2, f1)
        chord = np.hypot(
            self.end[rows, first] - self.start[rows, first],
            self.end[rows, second] - self.start[rows, second],
        )
        closed = chord < 1e-9
        turns = self.turns[rows]
        ccw = turns >= 0
        tau = 2.0 * math.pi
        sweep = np.where(
            ccw, np.mod(theta1 - theta0, tau), -np.mod(theta0 - theta1, tau)
        )
        whole = closed | (sweep == 0.0)
        sweep = np.where(whole, np.where(ccw, tau, -tau), sweep)
        extra = np.maximum(np.abs(turns) - 1, 0)
        sweep = sweep + np.where(ccw, tau, -tau) * extra
        return rows, first, second, theta0, sweep, np.hypot(s1, s2), np.hypot(f1, f2)

    @property
    def length(self):
        """Each move's path length (mm): straight moves over X, Y and Z;
        arcs and helices as ``runtime.toolpath.Arc.length``."""
        delta = self.end[:, :3] - self.start[:, :3]
        length = np.sqrt((delta * delta).sum(axis=1))
        rows, _, _, _, sweep, r0, r1 = self.arc_frame()
        if len(rows):
            normal = self.normal[rows]
            rise = self.end[rows, normal] - self.start[rows, normal]
            length[rows] = np.hypot(np.abs(sweep) * (r0 + r1) / 2.0, rise)
        return length

    def points(self, rows, resolution: float, most: Optional[int] = None, frame=None):
        """Points of X, Y and Z along the arcs ``rows`` (row indexes of
        arcs), each arc from its start to its end through points no further
        than ``resolution`` (mm) off the true curve, at least one every
        quarter turn (and, if ``most`` is given, no more than ``most`` a
        turn): ``(points (m, 3), owner (m,))``, ``owner`` giving each
        point's row. ``frame``: :meth:`arc_frame`, if the caller has it."""
        every, first, second, theta0, sweep, r0, r1 = frame or self.arc_frame()
        rows = np.asarray(rows, dtype=np.int64)
        where = np.searchsorted(every, rows)
        first, second = first[where], second[where]
        theta0, sweep, r0, r1 = theta0[where], sweep[where], r0[where], r1[where]
        radius = np.maximum(np.maximum(r0, r1), 1e-12)
        # a chord of angle a is r (1 - cos(a / 2)) off the arc at its middle
        ratio = np.clip(1.0 - resolution / radius, -1.0, 1.0)
        finest = 2.0 * math.pi / most if most else 1e-6
        step = np.clip(2.0 * np.arccos(ratio), finest, math.pi / 2)
        counts = np.maximum(np.ceil(np.abs(sweep) / step).astype(np.int64), 1)
        local = np.repeat(np.arange(len(rows)), counts + 1)
        offsets = np.concatenate(([0], np.cumsum(counts + 1)[:-1]))
        t = (np.arange(len(local)) - offsets[local]) / counts[local]
        start = self.start[rows, :3][local]
        points = start + (self.end[rows, :3][local] - start) * t[:, None]
        theta = theta0[local] + sweep[local] * t
        r = r0[local] + (r1 - r0)[local] * t
        centre = self.centre[rows][local]
        index = np.arange(len(local))
        points[index, first[local]] = centre[:, 0] + r * np.cos(theta)
        points[index, second[local]] = centre[:, 1] + r * np.sin(theta)
        return points, rows[local]


def toolpath(
    program: str,
    *,
    tool_table: Optional[str] = None,
    var_file: Optional[str] = None,
    ini: Optional[str] = None,
    block_delete: bool = False,
) -> Toolpath:
    """Run ``program`` (a G-code file, compiled and cached as ``ngc2py run``
    does, with rs274's options) and return its moves as a :class:`Toolpath`.
    A G-code error raises :class:`ProgramError` (rs274's report; the moves
    made before it on ``.toolpath``)."""
    from ngc2py.simulate import EXIT_OK

    recorder, status, report = record(
        argparse.Namespace(
            program=program,
            tool_table=tool_table,
            var_file=var_file,
            ini=ini,
            block_delete=block_delete,
        )
    )
    if status != EXIT_OK:
        raise ProgramError(report.strip(), recorder.toolpath())
    return recorder.toolpath()


def record(args: argparse.Namespace) -> Tuple[Recorder, int, str]:
    """Run the program ``args`` names (as the workflow commands take them)
    into a :class:`Recorder`: ``(recorder, exit status, what rs274 would
    have written to stderr)``."""
    from ngc2py.simulate import run_program

    recorder = Recorder()
    errors = io.StringIO()

    def bind(machine) -> None:
        recorder.machine = machine

    status = run_program(args, recorder, errors, on_machine=bind)
    return recorder, status, errors.getvalue()


__all__ = [
    "ARC",
    "FEED",
    "KINDS",
    "PROBE",
    "RAPID",
    "ProgramError",
    "Recorder",
    "Toolpath",
    "record",
    "toolpath",
]
