"""The canon that keeps a program's moves (:class:`Recorder`), in typed
arrays of the standard library, for ``ngc2py.toolpath()``
(:mod:`ngc2py.moves` makes them NumPy arrays) and the workflows built on it.

Recording needs no NumPy: ``ngc2py plot`` records in a child process
while its parent imports NumPy and matplotlib, and the child's moves cross
back as these arrays. Each batch of moves is packed into them column by
column in C (struct, strided memoryviews), not a Python object per value.
"""

from __future__ import annotations

import argparse
import io
import math
from array import array
from struct import pack
from typing import List, Optional, Tuple

from runtime.canon import Canon
from runtime.fast.hole_rows import hole_by_hole
from runtime.toolpath import LINEAR, MM_PER_INCH, PLANE_AXES, Point, ToolpathCanon

#: ``Toolpath.kind`` values.
RAPID, FEED, ARC, PROBE = 0, 1, 2, 3
KINDS = ("rapid", "feed", "arc", "probe")
_KIND = {"rapid": RAPID, "feed": FEED, "probe": PROBE}


#: A straight move's centre.
_NO_CENTRE = (math.nan, math.nan)


class Recorder(ToolpathCanon):
    """Keeps every move as a row of typed arrays (see ``ngc2py.moves.Toolpath``).

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
        self.ends += _rows_of(columns)
        self.centre += _same("d", math.nan, 2 * rows)
        self.normal += _same("b", -1, rows)
        self.turns += _same("l", 0, rows)
        self.position = self._last = tuple(column[-1] for column in columns)

    def arc_moves(self, lines, *columns, planes=None):
        """Arcs as ``Canon.arc_moves`` gives them (arc_feed's arguments as
        columns: first_end, second_end, first_axis, second_axis, rotation,
        axis_end, a, b, c, u, v, w)."""
        if self.plane not in PLANE_AXES:
            return super().arc_moves(lines, *columns, planes=planes)
        self.contour_moves(PLANE_AXES[self.plane], lines, *columns, planes=planes)

    def contour_moves(self, axes, lines, *columns, planes=None):
        """Arcs and the G1 lines between them as ``Canon.contour_moves``
        gives them (a line: rotation 0): a row each, as arc_feed and
        straight_feed make them."""
        if planes and not self._planes_told(planes):
            return super().contour_moves(axes, lines, *columns, planes=planes)
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
            self.kinds += _packed("b", [ARC if turns else FEED for turns in rotation])
            self.normal += _packed("b", [normal if turns else -1 for turns in rotation])
        else:
            self.kinds += _same("b", ARC, rows)
            self.normal += _same("b", normal, rows)
        self.lines += _packed("l", lines)
        self.tools += _same("l", self._current_tool(), rows)
        self.feeds += _same("d", self._rate, rows)
        self.ends += _rows_of(columns)
        self.centre += _rows_of((c1, c2))
        self.turns += _packed("l", rotation)
        self.position = self._last = tuple(column[-1] for column in columns)

    def hole_moves(self, recording, lines, first, second, axes, start):
        """Holes drilled alike (``Canon.hole_moves``): each hole's moves as
        rows, made from columns (each array extended once a batch)."""
        moves = [(name, args, where) for name, args, where in recording if where]
        ignored = all(
            getattr(type(self), name) is getattr(Canon, name)
            for name, _, where in recording
            if where is None
        )
        names = {name for name, _, _ in moves}
        if (
            not moves
            or not ignored
            or not names <= {"straight_traverse", "straight_feed"}
        ):
            # a move's line is the machine's: each hole at its own
            args = (recording, lines, first, second, axes, start)
            if self.machine is None:
                return super().hole_moves(*args)
            return hole_by_hole(self, self.machine, *args)
        count, per_hole = len(lines), len(moves)
        rows = count * per_hole
        self._begin(self.position, rows)
        k = MM_PER_INCH if self.inches else 1.0
        if k != 1.0:
            first, second = [v * k for v in first], [v * k for v in second]
            start = (start[0] * k, start[1] * k)
        # (each column packed once, written at every move of a hole there)
        hole = (memoryview(_packed("d", first)), memoryview(_packed("d", second)))
        places = {"hole": hole, "start": (hole[0][:-1], hole[1][:-1])}
        # one hole's moves (nine ends each, in millimetres) repeated for
        # every hole, then the plane's two coordinates of each move written
        # over them, a column with a stride (the first hole's start apart:
        # the tool's place before it)
        width = 9 * per_hole
        ends = array("d", [v for _, args, _ in moves for v in self._point(args)])
        ends *= count
        view = memoryview(ends)
        for j, (_, _, where) in enumerate(moves):
            for axis, column, before in zip(axes, places[where], start):
                if where == "hole":
                    view[9 * j + axis :: width] = column
                else:
                    view[9 * j + axis] = before
                    view[9 * j + axis + width :: width] = column
        numbers = _same("l", 0, rows)
        view = memoryview(numbers)
        column = memoryview(_packed("l", lines))
        for j in range(per_hole):
            view[j::per_hole] = column
        kinds = [RAPID if name == "straight_traverse" else FEED for name, _, _ in moves]
        feeds = [math.nan if kind == RAPID else self._rate for kind in kinds]
        self.kinds += array("b", kinds) * count
        self.lines += numbers
        self.tools += _same("l", self._current_tool(), rows)
        self.feeds += array("d", feeds) * count
        self.ends += ends
        self.centre += _same("d", math.nan, 2 * rows)
        self.normal += _same("b", -1, rows)
        self.turns += _same("l", 0, rows)
        self.position = self._last = tuple(ends[-9:])

    def _rows(self, kind: int, lines, rate: float) -> None:
        rows = len(lines)
        self.kinds += _same("b", kind, rows)
        self.lines += _packed("l", lines)
        self.tools += _same("l", self._current_tool(), rows)
        self.feeds += _same("d", rate, rows)

    def toolpath(self):
        """The moves so far as a :class:`ngc2py.moves.Toolpath`."""
        from ngc2py.moves import Toolpath

        return Toolpath.from_recorder(self)

    def moves(self) -> "Moves":
        """The moves so far, without the machine (standard-library arrays),
        made into NumPy arrays by ``Toolpath.from_recorder``."""
        moves = Moves()
        for name in Moves.__slots__:
            setattr(moves, name, getattr(self, name))
        return moves


def _packed(typecode: str, values) -> array:
    """The sequence ``values`` as an array of ``typecode``, packed in C by
    struct: array's own constructor and ``extend`` take a list item by
    item, several times slower (a batch of moves is nine such columns)."""
    return array(typecode, pack("%d%s" % (len(values), typecode), *values))


def _same(typecode: str, value, count: int) -> array:
    """``count`` times ``value`` as an array of ``typecode``."""
    return array(typecode, (value,)) * count


def _rows_of(columns) -> array:
    """Equally long columns of floats as one array of their rows, row after
    row (X Y Z A B C U V W of each move): each column packed and written
    with a stride, not a Python object per value."""
    width, count = len(columns), len(columns[0])
    rows = _same("d", 0.0, width * count)
    view = memoryview(rows)
    for i, column in enumerate(columns):
        view[i::width] = memoryview(_packed("d", column))
    return rows


class Moves:
    """What a :class:`Recorder` kept, as ``Toolpath.from_recorder`` reads it."""

    __slots__ = (
        "kinds",
        "lines",
        "tools",
        "feeds",
        "ends",
        "centre",
        "normal",
        "turns",
        "shifts",
        "first_units",
    )


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


__all__ = ["ARC", "FEED", "KINDS", "PROBE", "RAPID", "Moves", "Recorder", "record"]
