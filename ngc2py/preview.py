"""A drop-in for LinuxCNC's ``gcode.parse``: the preview API of Axis and the
other LinuxCNC GUIs, on top of ngc2py's canon protocol.

``parse(filename, canon, unitcode, initcode)`` runs the program and calls
``canon``'s methods the way LinuxCNC 2.9's ``gcode`` module does
(src/emc/rs274ngc/gcodemodule.cc), so preview code written for it can
switch to ngc2py:

* lengths are always **inches** (the module divides by 25.4 while the
  program is in G21): positions, arc centres, offsets, feed rates (even in
  G93 inverse time, as LinuxCNC does); angles and dwell seconds are passed
  as they are;
* the interpreter starts in G20 (the module tells it the machine is in
  inches); ``unitcode`` and ``initcode`` (e.g. ``"G21"``, ``"G17 G90"``) run
  before the first line, and so does each string of the list in the
  ``parse(filename, canon, [codes...])`` form;
* ``next_line(linecode)`` comes before the first call made for a new line
  number (per file: a subroutine's lines carry their own file's numbers);
  ``linecode.sequence_number`` is that number, ``gcodes``/``mcodes`` the
  modal state as of the previous block (``active_g_codes`` and
  ``active_m_codes``), ``feed_rate`` and ``speed`` its settings;
* the calls it makes: ``set_g5x_offset(index, x..w)``, ``set_g92_offset``,
  ``set_xy_rotation``, ``set_plane(1..6)`` (XY, YZ, XZ, UV, VW, UW),
  ``set_feed_rate``, ``straight_traverse``/``straight_feed``/
  ``straight_probe`` (x..w), ``arc_feed(first_end, second_end, first_axis,
  second_axis, rotation, axis_end, a, b, c, u, v, w)``, ``rigid_tap(x, y,
  z)``, splines as ``straight_feed`` calls through points of their curve
  (``runtime.nurbs``), ``dwell``, ``change_tool(pocket)``, ``tool_offset(x..w)``,
  ``comment``, ``message``, ``user_defined_function(num, p, q)``; it asks
  ``get_external_length_units``, ``get_external_angular_units``,
  ``get_axis_mask``, ``get_tool(pocket)`` (pockets 0-1000, at start),
  ``get_block_delete`` (for each ``/`` line) and ``check_abort`` (about once
  a second: a true answer stops the run with ``KeyboardInterrupt("Load
  aborted")``); ``parameter_file``, if the canon has it, is the ``.var``
  file read at start (never written);
* it returns ``(result, last_sequence_number)``: ``result`` is
  LinuxCNC's code (1 after M2/M30, 3 at a closing ``%``, 4 when the file
  cannot be opened, 5 for an error: :func:`strerror` gives its message) and
  the line number, one past the line when the error came while reading it;
* an exception raised by a canon method stops the run and propagates
  (StopIteration raised in a batch of moves, which runs as an iterator of
  calls, comes out as a RuntimeError, as it would from a generator).

Differences, on purpose: ``(PRINT, ...)`` text goes to the canon's
``print_text`` method if it has one, never to stdout (the module prints it
itself); ``get_tool``'s answers are not used (ngc2py's ``tool_table=`` file
is, since the module itself crashes on T words outside a running LinuxCNC);
``get_axis_mask`` is asked but ngc2py reads the XYZABC words rs274 reads;
a file whose ``/`` lines carry O-words in the form that pairs them when
converting (``runtime.errors.SourceMap.block_delete``) is asked
``get_block_delete`` once more, before it runs, and with block delete on
its ``/`` lines are empty lines, asked no more;
the line code's entries that describe the last block rather than the modes
(``gcodes[2]``, ``mcodes[0]``, ``mcodes[1]``, ``mcodes[3]``) are only kept
for lines ngc2py runs as blocks (rs274 also rewrites them for lines that
only set parameters). Kept on purpose, because preview code sees them: the
module's canon answers a feed rate of 1 whenever the interpreter asks (at
start and on every G20/G21 change), and slot 0 as the loaded tool.
"""

from __future__ import annotations

import time
from operator import itemgetter, not_

from runtime.arcs import INVERSE_TIME, UNITS_PER_MINUTE, UNITS_PER_REVOLUTION
from runtime.blockcheck import M_USER
from runtime.budget import DEFAULT_MAX_STEPS, RUNAWAY
from runtime.canon import Canon, call_rows, marked
from runtime.codes import G0, G1, G2, G3, G4, M_OFFSET, g_code, m_code
from runtime.errors import GCodeError, g_code_frames, g_code_frames_of_stack, locate
from runtime.machine import Machine
from runtime.mcodes import ProgramEnd
from runtime.nurbs import preview_points
from runtime.params import unset_variable
from runtime.spindle_select import CONSTANT_RPM, m_code_of
from runtime.fast.hole_rows import hole_by_hole
from runtime.fast.rows import BatchesOnly
from runtime.lazy_re import Pattern

try:
    from runtime._libm_trig import divided
except ImportError:  # not built (setup.py): the very same quotients

    def divided(column, divisor):
        return [value / divisor for value in column]


TYPE_CHECKING = False  # typing and re are not imported by a parse: start-up cost
if TYPE_CHECKING:
    from typing import Any, List, Optional, Sequence, Tuple

INTERP_OK = 0
INTERP_EXIT = 1
INTERP_EXECUTE_FINISH = 2
INTERP_ENDFILE = 3
INTERP_FILE_NOT_OPEN = 4
INTERP_ERROR = 5
#: Results at or above this are errors (``gcode.MIN_ERROR``).
MIN_ERROR = INTERP_ENDFILE

MM_PER_INCH = 25.4
#: LinuxCNC's CANON_PLANE numbers.
PLANES = {"XY": 1, "YZ": 2, "XZ": 3, "UV": 4, "VW": 5, "UW": 6}
#: active_g_codes' plane entry for each plane.
_PLANE_CODES = {"XY": 170, "XZ": 180, "YZ": 190, "UV": 171, "UW": 181, "VW": 191}
#: The pockets LinuxCNC asks the canon about at start (CANON_POCKETS_MAX).
POCKETS = 1001
#: Seconds between check_abort questions.
ABORT_INTERVAL = 1.0

_last_error = ""


def strerror(code: int) -> str:
    """The message of the last error :func:`parse` returned (as
    ``gcode.strerror`` does, whatever ``code`` is)."""
    return _last_error


class _LineFields(tuple):
    """``gcode.linecode``'s fields, read from a tuple (gcodes, mcodes,
    settings). A tuple underneath, so that a batch makes its lines' in C
    (:class:`_RowCode`)."""

    __slots__ = ()

    gcodes = property(itemgetter(0))
    mcodes = property(itemgetter(1))
    settings = property(itemgetter(2))
    sequence_number = property(lambda self: self.gcodes[0])
    feed_rate = property(lambda self: self.settings[1])
    speed = property(lambda self: self.settings[2])
    motion_mode = property(lambda self: self.gcodes[1])
    block = property(lambda self: self.gcodes[2])
    plane = property(lambda self: self.gcodes[3])
    cutter_side = property(lambda self: self.gcodes[4])
    units = property(lambda self: self.gcodes[5])
    distance_mode = property(lambda self: self.gcodes[6])
    feed_mode = property(lambda self: self.gcodes[7])
    origin = property(lambda self: self.gcodes[8])
    tool_length_offset = property(lambda self: self.gcodes[9])
    retract_mode = property(lambda self: self.gcodes[10])
    path_mode = property(lambda self: self.gcodes[11])
    stopping = property(lambda self: self.mcodes[1])
    spindle = property(lambda self: self.mcodes[2])
    toolchange = property(lambda self: self.mcodes[3])
    mist = property(lambda self: self.mcodes[4])
    flood = property(lambda self: self.mcodes[5])
    overrides = property(lambda self: self.mcodes[6])

    def __repr__(self) -> str:
        return "<linecode %d %r %r>" % (self.sequence_number, self.gcodes, self.mcodes)


class LineCode(_LineFields):
    """What ``next_line`` receives."""

    __slots__ = ()

    def __new__(cls, gcodes: Tuple[int, ...], mcodes: Tuple[int, ...], settings):
        return tuple.__new__(cls, (gcodes, mcodes, settings))


class _RowCode(_LineFields):
    """A batch row's line code, made from a (sequence number, line, the
    modes after the line's own as :meth:`PreviewMachine.line_state` gives
    them) tuple by tuple's own constructor, in C (no ``__new__`` of its
    own: :class:`LineCode`'s would be a Python call a row); its fields are
    joined when read."""

    __slots__ = ()

    gcodes = property(lambda self: (self[0],) + self[2][0])
    mcodes = property(lambda self: (self[1],) + self[2][1])
    settings = property(lambda self: (float(self[1]),) + self[2][2])


def _sequence_numbers(lines: List[int], skipped: int) -> List[int]:
    """The sequence numbers the preview gives ``lines``: less the lines
    skipped before the program's first, if any (most files skip none)."""
    if not skipped:
        return lines
    return [line - skipped if line > skipped else line for line in lines]


def _in_inches(column: List[float]) -> List[float]:
    """A column of millimetres in inches, as :meth:`PreviewCanon._pose`
    divides each value; a column of zeros (U, V, W, seldom used) as it is:
    zero divided is the very same zero, its sign kept. A column of one value
    (``[v] * n``: ``count`` finds it by identity, in C) is divided once."""
    if not any(column):
        return column
    k = MM_PER_INCH
    first = column[0]
    if first is column[-1] and column.count(first) == len(column):
        return [first / k] * len(column)  # an axis the rows do not name
    return divided(column, k)


def _straight_move(name: str):
    """PreviewCanon's ``name`` (straight_traverse or straight_feed): the
    target's, announced as :meth:`PreviewCanon._motion` announces a call,
    of the move's :meth:`PreviewCanon._pose`, written out in one method (a
    loop's every move comes here)."""

    def straight(self, x, y, z, a, b, c, u, v, w):
        self._pos = (x, y, z, a, b, c, u, v, w)
        machine = self.machine
        sequence = machine.line if self.motion_line is None else self.motion_line
        if sequence > self.skipped:
            sequence -= self.skipped
        if sequence != self.last_sequence:
            self.new_line(self.motion_line)
        call = getattr(self.target, name)
        if machine.inches:
            call(x, y, z, a, b, c, u, v, w)
        else:
            k = MM_PER_INCH
            call(x / k, y / k, z / k, a, b, c, u / k, v / k, w / k)

    straight.__name__ = straight.__qualname__ = name
    return straight


class PreviewCanon(Canon):
    """Translates ngc2py's canon calls into ``gcode.parse``'s calls on ``target``."""

    #: arcs restating G17 come in batches, their set_plane made after their
    #: line is announced (runtime.canon.Canon.takes_planes)
    takes_planes = True

    def __init__(self, target: Any) -> None:
        self.target = target
        self.machine: Optional["PreviewMachine"] = None
        self.last_sequence = -1
        #: Blank lines before a leading %: rs274 does not number them.
        self.skipped = 0
        self._checked = time.monotonic()
        #: the module's own idea of the position (program units): set by
        #: straight moves only, never by arcs; splines feed along from it
        self._pos: Tuple[float, ...] = (0.0,) * 9
        #: the line number motion calls carry when it is not the line's
        #: (G70-G72's generated moves carry -1 in LinuxCNC)
        self.motion_line: Optional[int] = None

    # --- bookkeeping -------------------------------------------------------
    def new_line(self, sequence: Optional[int] = None) -> None:
        """``maybe_new_line``: announce a line number the first time a call
        is made for it."""
        machine = self.machine
        if sequence is None:
            sequence = machine.line
        if sequence > self.skipped:
            sequence -= self.skipped
        if sequence == self.last_sequence:
            return
        now = time.monotonic()
        if now - self._checked > ABORT_INTERVAL:
            self._checked = now
            if self.target.check_abort():
                raise KeyboardInterrupt("Load aborted")
        self.last_sequence = sequence
        gcodes, mcodes, settings = machine.active
        self.target.next_line(LineCode((sequence,) + gcodes[1:], mcodes, settings))

    def _length(self, value: float) -> float:
        return value if self.machine.inches else value / MM_PER_INCH

    def _pose(self, x, y, z, a, b, c, u, v, w) -> Tuple[float, ...]:
        if self.machine.inches:
            return (x, y, z, a, b, c, u, v, w)
        k = MM_PER_INCH
        return (x / k, y / k, z / k, a, b, c, u / k, v / k, w / k)

    def _call(self, name: str, *args) -> None:
        self.new_line()
        getattr(self.target, name)(*args)

    def _motion(self, name: str, *args) -> None:
        # the module announces a motion call's own line number argument
        self.new_line(self.motion_line)
        getattr(self.target, name)(*args)

    # --- calls the gcode module passes on ---------------------------------
    def set_g5x_offset(self, index, x, y, z, a, b, c, u, v, w):
        self._call("set_g5x_offset", index, *self._pose(x, y, z, a, b, c, u, v, w))

    def set_g92_offset(self, x, y, z, a, b, c, u, v, w):
        self._call("set_g92_offset", *self._pose(x, y, z, a, b, c, u, v, w))

    def set_xy_rotation(self, degrees):
        self._call("set_xy_rotation", degrees)

    def select_plane(self, plane):
        # The trace names UV/UW/VW planes "UNKNOWN"; the machine said which.
        self._call("set_plane", PLANES.get(plane) or PLANES[self.machine.new_plane])

    def set_traverse_rate(self, rate):
        self._call("set_traverse_rate", rate)

    def set_feed_rate(self, rate):
        self._call("set_feed_rate", self._length(rate))

    straight_traverse = _straight_move("straight_traverse")
    straight_feed = _straight_move("straight_feed")

    def straight_moves(self, feed, lines, x, y, z, a, b, c, u, v, w):
        """A batch of plain rows (runtime.fast.rows.BatchesOnly: one move a line,
        nothing else on it): each line announced with the modes the line
        before left, then its move, as :meth:`new_line` and
        :meth:`straight_feed` would, with the modes worked out once."""
        machine = self.machine
        if self.motion_line is not None or not isinstance(machine, PreviewMachine):
            return super().straight_moves(feed, lines, x, y, z, a, b, c, u, v, w)
        self._pos = tuple(column[-1] for column in (x, y, z, a, b, c, u, v, w))
        if not machine.inches:
            x, y, z, u, v, w = map(_in_inches, (x, y, z, u, v, w))
        target = self.target
        call = target.straight_feed if feed else target.straight_traverse
        self._announce_batch(
            lines,
            [G1 if feed else G0] * len(lines),
            ((call, (x, y, z, a, b, c, u, v, w)),),
        )

    def arc_moves(self, lines, *columns, planes=None):
        """A batch of plain arc rows (arc_feed's arguments as columns),
        announced line by line as :meth:`straight_moves` does (G2 and G3
        may alternate); the rows ``planes`` names restate G17 (their
        set_plane after their announcement)."""
        machine = self.machine
        if self.motion_line is not None or not isinstance(machine, PreviewMachine):
            return super().arc_moves(lines, *columns, planes=planes)
        first_end, second_end, first_axis, second_axis, rotation, axis_end = columns[:6]
        a, b, c, u, v, w = columns[6:]
        lengths = [first_end, second_end, first_axis, second_axis, axis_end, u, v, w]
        if not machine.inches:
            lengths = list(map(_in_inches, lengths))
        e1, e2, c1, c2, normal, u, v, w = lengths
        arguments = (e1, e2, c1, c2, rotation, normal, a, b, c, u, v, w)
        self._announce_batch(
            lines,
            [G3 if turn > 0 else G2 for turn in rotation],
            self._planes_set(planes, len(lines)) + ((self.target.arc_feed, arguments),),
        )

    def _planes_set(self, planes, count: int) -> tuple:
        """call_rows' step of the set_plane calls of the rows ``planes``
        names (of ``count``), as :meth:`select_plane` makes one; none
        without them."""
        if not planes:
            return ()
        return (
            (self.target.set_plane, ([PLANES["XY"]],), None, marked(planes, count)),
        )

    def contour_moves(self, axes, lines, *columns, planes=None):
        """A contour (runtime.canon.Canon.contour_moves): arcs and the plain
        G1 rows between them, announced line by line as :meth:`arc_moves`
        and :meth:`straight_moves` do, in one batch. The arcs' calls and the
        lines' are two iterators of calls; a list of which one each row
        takes is walked by ``map(next, ...)``, so no row costs a Python
        statement."""
        machine = self.machine
        rotation = columns[4]
        if self.motion_line is not None or not isinstance(machine, PreviewMachine):
            return super().contour_moves(axes, lines, *columns, planes=planes)
        if 0 not in rotation:
            return self.arc_moves(lines, *columns, planes=planes)
        f, s, n = axes
        # the module's own position: the last straight row's end
        last = len(rotation) - 1 - rotation[::-1].index(0)
        pose = [column[last] for column in columns[6:]]
        pose[0:0] = [0.0, 0.0, 0.0]
        pose[f], pose[s], pose[n] = columns[0][last], columns[1][last], columns[5][last]
        target = self.target
        e1, e2, c1, c2, _, en, a, b, c, u, v, w = columns
        if not machine.inches:
            e1, e2, c1, c2, en, u, v, w = map(_in_inches, (e1, e2, c1, c2, en, u, v, w))
        # a line's straight_feed: its pose (as _pose has it) a column at a time
        line_columns = [None, None, None, a, b, c, u, v, w]
        line_columns[f], line_columns[s], line_columns[n] = e1, e2, en
        arcs = (e1, e2, c1, c2, rotation, en, a, b, c, u, v, w)
        # each row one call or the other: an arc where its rotation is not 0
        steps = self._planes_set(planes, len(lines)) + (
            (target.arc_feed, arcs, None, rotation),
            (
                target.straight_feed,
                tuple(line_columns),
                None,
                list(map(not_, rotation)),
            ),
        )
        self._announce_batch(
            lines,
            [G1 if not turn else G3 if turn > 0 else G2 for turn in rotation],
            steps,
        )
        self._pos = tuple(pose)

    def hole_moves(self, recording, lines, first, second, axes, start):
        """Holes drilled alike (runtime.canon.Canon.hole_moves): each hole's
        line announced as its first call would announce it (with the modes
        the hole before left, which a hole changes only by its line number),
        then its calls on the target, lengths converted a column at a time.
        The calls are made from columns by ``call_rows``: no Python statement
        per move. Holes with a call this does not know go hole by hole."""
        machine = self.machine
        if self.motion_line is not None or not isinstance(machine, PreviewMachine):
            return self._hole_by_hole(recording, lines, first, second, axes, start)
        target = self.target
        k = 1.0 if machine.inches else MM_PER_INCH
        places = {
            "hole": (first, second),
            "start": ([start[0]] + first[:-1], [start[1]] + second[:-1]),
        }
        shown = places  # the places in the target's units, each divided once
        if k != 1.0:
            first, second = divided(first, k), divided(second, k)
            shown = {
                "hole": (first, second),
                "start": ([start[0] / k] + first[:-1], [start[1] / k] + second[:-1]),
            }
        columns = []  # per call of a hole: (the target's method, its columns)
        for name, args, where in recording:
            if where is not None:
                # (every move's two hole axes are columns of a value a hole,
                # the others of one, which serves every hole)
                steps = [[value] for value in self._pose(*args)]
                for axis, values in zip(axes, shown[where]):
                    steps[axis] = values
                columns.append((getattr(target, name), tuple(steps)))
            elif name in ("dwell", "comment"):  # (a restated line's G98/G99)
                columns.append((getattr(target, name), ([args[0]],)))
            elif name == "set_feed_rate":  # (a restated line's F)
                columns.append((target.set_feed_rate, ([self._length(args[0])],)))
            elif getattr(type(self), name) is not getattr(Canon, name):
                # a call the module passes on that a hole seldom makes
                return self._hole_by_hole(recording, lines, first, second, axes, start)
        numbers = _sequence_numbers(lines, self.skipped)
        if numbers[0] == self.last_sequence:  # announced already: row by row
            return self._hole_by_hole(recording, lines, first, second, axes, start)
        now = time.monotonic()  # asked once a batch: a batch takes milliseconds
        if now - self._checked > ABORT_INTERVAL:
            self._checked = now
            if target.check_abort():
                raise KeyboardInterrupt("Load aborted")
        gcodes, mcodes, settings = machine.active
        code = LineCode((numbers[0],) + gcodes[1:], mcodes, settings)
        state = (gcodes[1:], mcodes[1:], settings[1:])
        # the calls in program order, hole after hole
        self._announce_rows(code, numbers, lines, [state], tuple(columns))
        self.last_sequence = numbers[-1]
        for _, args, where in reversed(recording):
            if where is not None:  # the module's own position: the last move's
                position = list(args)
                for axis, values in zip(axes, places[where]):
                    position[axis] = values[-1]
                self._pos = tuple(position)
                break

    def _hole_by_hole(self, recording, lines, first, second, axes, start):
        # each hole announced at its own line, with its own line state
        hole_by_hole(self, self.machine, recording, lines, first, second, axes, start)

    def _announce_batch(self, lines, motions, steps) -> None:
        """Each line of a batch announced with the modes the line before
        left (those of ``motions[k - 1]``, its motion mode, since nothing
        else changes), then its move made (``steps``: as
        :meth:`_announce_rows` takes them)."""
        machine = self.machine
        target = self.target
        modes = {motion: machine.line_state(motion) for motion in set(motions)}
        now = time.monotonic()  # asked once a batch: a batch takes milliseconds
        if now - self._checked > ABORT_INTERVAL:
            self._checked = now
            if target.check_abort():
                raise KeyboardInterrupt("Load aborted")
        numbers = _sequence_numbers(lines, self.skipped)
        if len(modes) == 1:
            states = [modes[motions[0]]]  # (one: every row's)
        else:  # (row k is announced with the modes of line k - 1)
            states = [None, *map(modes.__getitem__, motions[:-1])]
        first = None
        if numbers[0] != self.last_sequence:  # (else announced already)
            g, m, s = machine.active
            first = LineCode((numbers[0],) + g[1:], m, s)
        self._announce_rows(first, numbers, lines, states, steps)
        self.last_sequence = numbers[-1]
        last = lines[-1]
        gcodes, mcodes, settings = modes[motions[-1]]
        machine.active = ((last,) + gcodes, (last,) + mcodes, (float(last),) + settings)

    def _announce_rows(self, first, numbers, lines, states, steps) -> None:
        """Row by row, each row's line announced, then its calls: ``steps``
        as runtime.canon.call_rows takes them (a method, its arguments'
        columns). Row 0 is announced with ``first`` (none: it was already),
        row k after it with a code of its number, the line before and
        ``states[k]`` (or ``states[0]``, if that is all), made in C
        (call_rows' ``kind``) as the row is."""
        if not lines:
            return
        next_line = self.target.next_line
        if first is not None:
            next_line(first)
        call_rows(0, 1, steps)
        if len(lines) > 1:
            announce = (next_line, (numbers, [None, *lines], states), _RowCode)
            call_rows(1, len(lines), (announce, *steps))

    def straight_probe(self, x, y, z, a, b, c, u, v, w, probe_type):
        self._pos = (x, y, z, a, b, c, u, v, w)
        self._motion("straight_probe", *self._pose(x, y, z, a, b, c, u, v, w))

    def nurbs_feed(self, control_points, order):
        # the module draws a spline as straight feeds through points of the
        # curve (runtime/nurbs.py), the other axes where the last straight
        # move left them
        for x, y in preview_points(control_points, order):
            self.straight_feed(x, y, *self._pos[2:])

    def rigid_tap(self, x, y, z, scale):
        self._call("rigid_tap", self._length(x), self._length(y), self._length(z))

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
        n = self._length
        self._motion(
            "arc_feed",
            n(first_end),
            n(second_end),
            n(first_axis),
            n(second_axis),
            rotation,
            n(axis_end),
            a,
            b,
            c,
            n(u),
            n(v),
            n(w),
        )

    def dwell(self, seconds):
        self._call("dwell", seconds)

    def change_tool(self, slot):
        self._call("change_tool", slot)

    def change_tool_number(self, tool):
        self.new_line()  # the module announces the line, then does nothing

    def use_tool_length_offset(self, x, y, z, a, b, c, u, v, w):
        self._call("tool_offset", *self._pose(x, y, z, a, b, c, u, v, w))

    def comment(self, text):
        self._call("comment", text)

    def message(self, text):
        self._call("message", text)

    def print_text(self, text):
        handler = getattr(self.target, "print_text", None)
        if handler is not None:
            handler(text)

    def user_defined_function(self, number, p, q):
        self._call("user_defined_function", number, p, q)


class _LineState:
    """What a line of one plain move leaves as ``PreviewMachine.active``
    (gcodes, mcodes, settings, each with the line first), made into those
    tuples when it is read (unpacked)."""

    __slots__ = ("line", "state", "key")

    def __init__(self, line: int, state: tuple, key: tuple = ()) -> None:
        self.line, self.state, self.key = line, state, key

    def __iter__(self):
        gcodes, mcodes, settings = self.state
        line = self.line
        return iter(((line,) + gcodes, (line,) + mcodes, (float(line),) + settings))


_NO_LINE_STATE = _LineState(-1, ())


def _preview_xyz(motion: int):
    """PreviewMachine's ``m.feed`` (G1) or ``m.rapid`` (G0) with X, Y and/or
    Z: what BatchesOnly's single line (runtime.fast.rows), the machine's
    XYZ move (runtime.fast.moves) and PreviewCanon's straight move do for
    such a line, in one method, while the modes are plain and the canon is
    the preview's own: the target's call announced as the general path
    announces it, then the state the line leaves (_line_ended). Anything
    else goes the general way (``general``)."""
    general = BatchesOnly.feed if motion == G1 else BatchesOnly.rapid
    name = "straight_feed" if motion == G1 else "straight_traverse"
    feed = motion == G1

    def move(self, line, x=None, y=None, z=None) -> None:
        canon = self.canon
        if (
            not self._batchable
            or self.reading_profile
            or (feed and not self.feed_rate > 0.0)
            or self._block_n is not None
            or type(canon) is not PreviewCanon
            or canon.motion_line is not None
        ):
            return general(self, line, x, y, z)
        cur = self.current
        # (the end point as runtime.fast.moves' XYZ move writes it out: a
        # helper's call would cost what this method saves)
        end = [
            cur[0] if x is None else x,
            cur[1] if y is None else y,
            cur[2] if z is None else z,
            cur[3],
            cur[4],
            cur[5],
            cur[6],
            cur[7],
            cur[8],
        ]
        self.line = line
        canon._pos = tuple(end)
        sequence = line - canon.skipped if line > canon.skipped else line
        if sequence != canon.last_sequence:
            canon.new_line(None)
        call = getattr(canon.target, name)
        if self.inches:
            call(*end)
        else:
            k = MM_PER_INCH
            a, b, c, u, v, w = end[3:]
            call(end[0] / k, end[1] / k, end[2] / k, a, b, c, u / k, v / k, w / k)
        self.motion_mode = motion
        self.current = self.world.position = self.params.position = end
        # the state the line leaves (_line_ended)
        key = (motion, self.feed_rate, self.params.values[5210])
        last = self._last_line_state
        if last.line == line and last.key == key:
            self.active = last
        else:
            state = self.line_state(motion)
            self.active = self._last_line_state = _LineState(line, state, key)

    move.__name__ = move.__qualname__ = "feed" if feed else "rapid"
    return move


class PreviewMachine(BatchesOnly, Machine):
    """The machine as the gcode module's interpreter sees it: it starts in
    inches, asks the canon about block delete line by line, and records
    the modal state the way ``active_g_codes``/``active_m_codes`` do.

    Blocks take the general path (block() records the modal state each line
    is announced with), except whole batches of plain rows, which
    PreviewCanon.straight_moves announces and moves itself (BatchesOnly)."""

    def __init__(self, canon: PreviewCanon, **options) -> None:
        super().__init__(canon, **options)
        self.inches = True
        self.current_pocket = 0  # the module's canon reports slot 0 loaded
        self.feed_rate = 1.0  # and a feed rate of 1, always
        self.reading = True
        self.reached_end = False
        self.new_plane = "XY"
        self.path_mode_set = False
        self._path_mode_set_in = {}
        self._m98_passes = {}
        # Nothing written yet: the first line code is all zeros.
        self.active = ((0,) * 17, (0,) * 10, (0.0,) * 5)
        #: (motion, feed rate, #5210) -> the state a plain move line leaves
        self._line_states: dict = {}
        #: the last plain move line's state (a loop's line leaves it again)
        self._last_line_state = _NO_LINE_STATE

    def _emit_probe(self, end, probe_type) -> None:
        # The module's canon (gcodemodule.cc) ends a probe move at its
        # target: no back-off as rs274's stand-alone canon does.
        self.canon.straight_probe(*end, probe_type)
        self._probe_point = list(end[:6]) + [0.0, 0.0, 0.0]
        self.world.position = list(end[:6])

    def _emit_nurbs(self, order: int) -> None:
        # The module's canon knows where a spline ends (its last control
        # point), where rs274's stand-alone canon reads past its list.
        last = self._nurbs_points[-1]
        super()._emit_nurbs(order)
        self.world.position = [last[0], last[1]] + list(self.world.position[2:6])

    def _left_frame(self, level: int) -> None:
        # An M73 restore after a return runs as the caller's line (the
        # module announces it at the restore's first call).
        saved = self._contexts.get(level) if self._contexts else None
        if saved is not None and saved.auto_restore and saved.state is not None:
            frames = g_code_frames_of_stack()
            if frames:
                self.line = frames[-1].line
                # rs274 repeats an M98 by reading its line again: between
                # passes it stands on the line before
                if self._m98_passes.get(level, 0) > 1:
                    self.line -= 1
        if level in self._m98_passes:
            self._m98_passes[level] -= 1
        super()._left_frame(level)

    # rs274's own control mode starts as G61.1 (the line code says so until
    # a path mode is set; ngc2py keeps G64, what the trace shows): a state
    # saved before any path mode brings that back when restored.
    def _modal_state(self):
        state = super()._modal_state()
        self._path_mode_set_in[id(state)] = self.path_mode_set
        return state

    def _restore(self, saved) -> bool:
        ran = super()._restore(saved)
        if not self._path_mode_set_in.get(id(saved), True):
            self.path_mode_set = False
            self.active = self._active(None, self.line)
        return ran

    def _run_restore_line(self, codes, words) -> None:
        # Each line of restore text is a block of its own to the module's
        # interpreter: the modal state the next call's line code shows is
        # written after each.
        super()._run_restore_line(codes, words)
        self.active = self._active(tuple(codes), self.line)

    #: the line of an M98 .. L0 (see _failed)
    l0_call_line: Optional[int] = None

    def m98(self, line, fn, *codes, **words) -> None:
        if words.get("l", 1) == 0 and self.l0_call_line is None:
            self.l0_call_line = line
        # passes of M98 P.. L.. still to run, by the call level they run at
        level = self.call_level + 1
        self._m98_passes[level] = int(words.get("l", 1))
        try:
            super().m98(line, fn, *codes, **words)
        finally:
            self._m98_passes.pop(level, None)

    def _g7x_moves(self, move, *args) -> None:
        # G70-G72's moves after the profile is read carry line number -1
        self.canon.motion_line = -1
        try:
            move(*args)
        finally:
            self.canon.motion_line = None

    def _g7x_rapid(self, end) -> None:
        self._g7x_moves(super()._g7x_rapid, end)

    def _g7x_straight(self, end) -> None:
        self._g7x_moves(super()._g7x_straight, end)

    def _g7x_arc(self, ccw, centre, end) -> None:
        self._g7x_moves(super()._g7x_arc, ccw, centre, end)

    @property
    def block_delete(self) -> bool:
        return bool(self.canon.target.get_block_delete())

    @block_delete.setter
    def block_delete(self, value) -> None:
        pass  # the canon answers instead

    # Lines of a single straight move or arc (what a loop's body is made
    # of) take the machine's fast paths when the modes are plain: their
    # canon calls announce the line with the state the block before left,
    # as the general path's do; the state this line leaves differs from
    # it only in the motion mode, the feed rate and the line number, so
    # it is worked out once per (motion, feed) until a general block runs.
    def refresh_plain(self) -> None:
        super().refresh_plain()
        self._line_states = {}
        self._last_line_state = _NO_LINE_STATE

    # m.feed and m.rapid (a loop's every move): the calls of BatchesOnly's
    # single line, the machine's XYZ move and PreviewCanon's straight move
    # in one method (tests/test_preview.py holds it to them)
    feed = _preview_xyz(G1)
    rapid = _preview_xyz(G0)

    def _line_begins(self, line, n):
        return self.active

    def line_state(self, motion):
        """The state (gcodes, mcodes, settings without the line) a line of
        one plain move in ``motion`` leaves, worked out once per motion
        and feed until a general block runs."""
        key = (motion, self.feed_rate, self.params.get_internal(5210))
        state = self._line_states.get(key)
        if state is None:
            saved, self.motion_mode = self.motion_mode, motion
            gcodes, mcodes, settings = self._active((), 0)
            self.motion_mode = saved
            state = self._line_states[key] = (gcodes[1:], mcodes[1:], settings[1:])
        return state

    def _line_ended(self, line, before) -> None:
        if self.active is before:  # the fast path took it: no block wrote the state
            # made into tuples only if read: a loop's line is announced once,
            # and leaves the state its last run left (the same object)
            key = (self.motion_mode, self.feed_rate, self.params.values[5210])
            last = self._last_line_state
            if last.line == line and last.key == key:
                self.active = last
            else:
                state = self.line_state(key[0])
                self.active = self._last_line_state = _LineState(line, state, key)

    def _dwell_ended(self, line, before) -> None:
        # a G4 line's state shows its G4 (group 0), as block() writes it
        self.active = self._active((G4,), line)

    replayed_fields = frozenset(("active",))

    def hole_replayed(self, line: int) -> None:
        # the state cycle_row leaves (the rows replayed change no mode)
        gcodes, mcodes, settings = self.active
        self.active = (
            (line,) + gcodes[1:],
            (line,) + mcodes[1:],
            (float(line),) + settings[1:],
        )

    def cycle_row(self, line, words, n=None) -> bool:
        # A row of hole words is executed, never read past (an error in
        # its cycle reports the row itself), and leaves the state block()
        # would write for a line with no codes.
        self.reading = False
        done = super().cycle_row(line, words, n)
        self.reading = True
        if done:
            self.active = self._active((), line)
        return done

    def block(self, line, *codes, n=None, comment=None, **words):
        try:
            super().block(line, *codes, n=n, comment=comment, **words)
        except ProgramEnd:
            self.active = self._active(codes, line)  # M2 writes its state too
            raise
        if not self.path_mode_set:
            self.path_mode_set = not _PATH_MODES.isdisjoint(codes)
        self.active = self._active(codes, line)

    def _set_plane(self, plane: str) -> None:
        self.new_plane = plane
        super()._set_plane(plane)

    def _execute(self, block, comment) -> None:
        # An error while executing leaves reading False: the module's
        # reported line then does not count the line as read past.
        self.reading = False
        super()._execute(block, comment)
        self.reading = True

    def _execute_m(self, block) -> None:
        user = block.m.pop(M_USER, None)
        # True: an M72 ran restore lines and the rest of the line is lost
        stop = super()._execute_m(block)
        if user is not None:
            words = block.words
            self.canon.user_defined_function(
                user - 100, words.get("p", 0.0), words.get("q", 0.0)
            )
        return stop

    # The module's interpreter reads, then executes: an error while reading
    # a line reports the line after it. O-word control (entering a call,
    # a definition, labels) is executed, not read; seeking a subroutine
    # not yet defined is reading.
    def _unread(self, method, *args):
        # (an error leaves it False; a G7x profile's call, inside the
        # executing G7x line, leaves it as it was)
        before, self.reading = self.reading, False
        result = method(*args)
        self.reading = before
        return result

    def _enter_sub(self):
        return self._unread(super()._enter_sub)

    def define(self, name, fn):
        return self._unread(super().define, name, fn)

    def _set_units(self, inches: bool) -> None:
        changed = inches != self.inches
        super()._set_units(inches)
        if changed:
            # The interpreter rereads the feed from its canon, and the
            # module's canon always answers 1.
            self.feed_rate = 1.0

    def end_of_file(self, demarcated: bool, closed: bool) -> None:
        self.reached_end = closed
        super().end_of_file(demarcated, closed)

    def _active(self, codes: Optional[Sequence[int]], line: int):
        """(gcodes, mcodes, settings) as rs274's write_g_codes,
        write_m_codes and write_settings leave them after a block."""
        group0 = -1
        stopping = toolchange = -1
        for code in codes or ():
            if code >= M_OFFSET:
                number = code - M_OFFSET
                if number in (0, 1, 2, 30, 60):
                    stopping = number
                elif number in (6, 61):
                    toolchange = number
            elif code in _GROUP0:
                group0 = code
        motion = self.motion_mode if self.motion_mode is not None else -1
        gcodes = (
            line,
            motion,
            group0,
            _PLANE_CODES[self.plane],
            (400, 410, 420)[self._cc.side],  # G41.1/G42.1 show as G41/G42
            200 if self.inches else 210,
            910 if self.distance_incremental else 900,
            _FEED_MODE_CODES[self.feed_mode],
            (
                530 + 10 * self.origin_index
                if self.origin_index < 7
                else 584 + self.origin_index
            ),
            430 if any(self.tool_offset) else 490,
            990 if self.retract_r_plane else 980,
            self.control_mode if self.path_mode_set else 611,  # starts in G61.1
            -1,
            970 if self.spindles.mode(0) == CONSTANT_RPM else 960,
            901 if self.ijk_absolute else 911,
            70 if self.lathe_diameter else 80,
            923 if self.params.get_internal(5210) else 922,
        )
        spindle = m_code_of(self.spindles.turning(0))
        mist = 7 if self.mist else (-1 if self.flood else 9)
        # rs274's write_m_codes tests its per-spindle speed_override array
        # itself, never empty: speed override always reads as on
        overrides = 48 if self.feed_override else 51
        mcodes = (
            line,
            stopping,
            spindle,
            toolchange,
            mist,
            8 if self.flood else -1,
            overrides,
            52 if self.adaptive_feed else -1,
            53 if self.feed_hold else -1,
            0,
        )
        speed = self.spindles.speed(0)
        return gcodes, mcodes, (float(line), self.feed_rate, speed, 0.0, 0.0)


#: O-word errors rs274 finds while executing control flow: "<line>: ..."
_CONTROL_ERROR = Pattern(r"\d+: ")
#: Errors rs274 finds while executing a line (its parameter settings, an
#: endsub's control function), not while reading it.
_EXECUTE_PREFIXES = (
    "Cannot assign to read-only parameter",
    "Not in subroutine definition",
    # a call finding the wrong kind of subroutine (runtime.fanuc_subs)
    "Fanuc 'O....' subroutine must be called with",
    "'O.... sub' subroutine must be called with",
    "Fanuc 'O....' subroutine definition must end with",
    # ngc2py's own (rs274 runs on): a loop or call spent the step budget
    RUNAWAY,
)
#: G61, G61.1, G64.
_PATH_MODES = frozenset((610, 611, 640))
#: active_g_codes' feed mode entry: units per minute, inverse time, per rev.
_FEED_MODE_CODES = {UNITS_PER_MINUTE: 940, INVERSE_TIME: 930, UNITS_PER_REVOLUTION: 950}


#: G codes of modal group 0 (non-modal): G4, G10, G28, G30, G52, G53, G92...
_GROUP0 = frozenset((40, 100, 280, 281, 300, 301, 520, 530, 920))


def _init_words(text: str):
    """The words of an init code string: (letter, number text) pairs, or
    None where it is not words alone. Each is a letter, then a number
    (``[-+]?(digits[.digits]|.digits)``), blanks around either; scanned by
    hand, as the regular expression would, so a parse never imports ``re``."""
    words = []
    at, end = 0, len(text)
    while at < end:
        while at < end and text[at].isspace():
            at += 1
        letter = text[at : at + 1]
        if not (letter.isascii() and letter.isalpha()):
            return None
        at += 1
        while at < end and text[at].isspace():
            at += 1
        begin = at
        if text[at : at + 1] in ("+", "-") and at < end:
            at += 1
        digits = at
        while at < end and text[at].isdecimal():
            at += 1
        whole = at > digits
        if text[at : at + 1] == ".":
            at += 1
            fraction = at
            while at < end and text[at].isdecimal():
                at += 1
            if not whole and at == fraction:
                return None
        elif not whole:
            return None
        words.append((letter, text[begin:at]))
    return words


def _init_block(machine: PreviewMachine, text: str, line: int) -> None:
    """Run one init code string (plain words: ``G21 G17 G90 F10``) before
    the program, as the module's ``read(code)``/``execute()`` do: at the
    line number opening the file left (``line``)."""
    codes: List[int] = []
    words = {}
    text = text.strip()
    found = _init_words(text)
    if found is None:
        raise GCodeError("Bad init code: %s" % text)
    for letter, number in found:
        letter, value = letter.lower(), float(number)
        if letter == "g":
            codes.append(g_code(value))
        elif letter == "m":
            codes.append(m_code(value))
        else:
            words[letter] = value
    if codes or words:
        machine.block(line, *codes, **words)


def _init_codes(args: Sequence[Any]) -> List[str]:
    """The init code strings of either form of the call (the interpreter
    name of both forms is accepted and ignored: ngc2py is the interpreter)."""
    if args and isinstance(args[0], list):
        if len(args) > 2:
            raise TypeError("parse(filename, canon, initcodes[, interpname])")
        return [str(code) for code in args[0]]
    if len(args) > 3:
        raise TypeError("parse(filename, canon[, unitcode[, initcode[, interpname]]])")
    return [code for code in args[:2] if code]


def _ask_start_questions(target: Any) -> None:
    """The questions the module's interpreter asks while it initialises."""
    for name in ("get_external_length_units",) * 3 + (
        "get_external_angular_units",
    ) * 3:
        answer = getattr(target, name)()
        if not isinstance(answer, float):
            raise TypeError(
                "%s: Expected float, got %s"
                % (name.replace("angular", "angle"), type(answer).__name__)
            )


def parse(
    filename: str,
    canon: Any,
    *args: Any,
    tool_table: Optional[str] = None,
    ini: Optional[str] = None,
    max_steps: int = DEFAULT_MAX_STEPS,
):
    """Run ``filename`` against ``canon`` as ``gcode.parse`` does; see the
    module docstring. ``tool_table`` and ``ini`` are ngc2py's: rs274's
    ``-t`` and ``-i`` files; ``max_steps`` the loop iterations and calls
    allowed (runtime.budget; 0: no limit): a program that never ends,
    which LinuxCNC's preview loads forever, returns an error result.
    Returns ``(result, last_sequence_number)``."""
    global _last_error
    from ngc2py.loading import load_program, unopened
    from ngc2py.compiler import OpenError

    init_codes = _init_codes(args)
    try:
        module = load_program(filename, ini)
        if module.__ngc__.block_delete is not None and canon.get_block_delete():
            # its O-words pair otherwise with block delete on (SourceMap):
            # asked once before the run, only for such a file
            module = load_program(filename, ini, block_delete=True)
        main, source_map = module.main, module.__ngc__
    except OpenError as error:
        main, source_map = None, unopened(filename, error)
    _ask_start_questions(canon)
    adapter = PreviewCanon(canon)
    var_file = getattr(canon, "parameter_file", None) or None
    machine = PreviewMachine(
        adapter,
        tool_table=tool_table,
        var_file=var_file,
        ini=ini,
        source=source_map,
        max_steps=max_steps,
    )
    adapter.machine = machine
    _last_error = ""
    result = INTERP_OK
    ended_in_sub = None
    try:
        machine._initialise()
        machine.var_file = None  # read (and normalised) at start, as the
        # module's interpreter does, but never written back at the end
        machine.active = machine._active(None, 0)
        # The module announces the line reached by opening the file: the
        # first line when it is a % (opening reads it), else none.
        opened_at = _opening_line(filename)
        if opened_at:
            adapter.skipped = opened_at - 1
        adapter.new_line(opened_at)
        canon.get_axis_mask()
        for pocket in range(POCKETS):
            canon.get_tool(pocket)
        for code in init_codes:
            _init_block(machine, code, opened_at)
        opening = source_map.opening_error()
        if opening is not None:
            raise GCodeError(*opening)
        machine._start()
        main(machine)
        result = INTERP_ENDFILE if machine.reached_end else INTERP_EXIT
    except ProgramEnd as end:
        result = INTERP_ENDFILE if machine.reached_end else INTERP_EXIT
        # M2 in a subroutine: rs274 is back at the outermost call's line.
        frames = locate(end)
        if frames and not machine.reached_end:
            machine.line = frames[0].line
        elif frames and len(frames) > 1:
            # a lone % in a subroutine file ended the program: its line
            ended_in_sub = frames[-1].line
    except (GCodeError, UnboundLocalError, StopIteration) as caught:
        # a named local held in a Python variable read unset: the store's
        # error (runtime.params.unset_variable); the step budget spent: the
        # runaway error (runtime.budget), at the loop or call that spent it
        if type(caught) is UnboundLocalError:
            error = unset_variable(caught)
        elif type(caught) is StopIteration and machine.budget_spent():
            error = machine.runaway().with_traceback(caught.__traceback__)
        else:
            error = caught
        if not isinstance(error, GCodeError):
            raise
        _last_error = error.message
        return _failed(machine, adapter, error)
    line = machine.line
    if result == INTERP_ENDFILE:
        line = source_map.end[0] if ended_in_sub is None else ended_in_sub
    adapter.new_line(line)
    return result, adapter.last_sequence + (1 if result == INTERP_ENDFILE else 0)


def _opening_line(filename: str) -> int:
    """The line number rs274's open() leaves behind: that of a leading ``%``
    (after blank lines), or 0 (it reads back to the start otherwise)."""
    try:
        with open(filename, "rb") as handle:
            for number, raw in enumerate(handle, 1):
                text = raw.strip()
                if text:
                    return number if text.startswith(b"%") else 0
    except OSError:
        pass
    return 0


def _failed(machine: PreviewMachine, adapter: PreviewCanon, error: GCodeError):
    """The result of a run that stopped on ``error``: the module reports the
    line of the outermost call in progress (rs274 unwinds its subroutine
    calls first), one past it when the error came while reading."""
    global _last_error
    if error.message.startswith("Unable to open file"):
        _last_error = "File not open"  # the module's words: it fails reading
        return INTERP_FILE_NOT_OPEN, adapter.last_sequence + 1
    # Where the program was, not the line an error message may name (a
    # search for a subroutine names the last line it read).
    frames = g_code_frames(error.__traceback__, getattr(error, "ngc_row_line", None))
    line = frames[0].line if frames else machine.line
    if machine.l0_call_line is not None and machine.call_level > 0 and len(frames) <= 1:
        # after M98 L0 the main program runs one call level down, with no
        # frame of its own: that call is the outermost one
        line = machine.l0_call_line
    if error.message.startswith("File ended") and len(frames) <= 1:
        # (inside a call the outermost call's line is reported, as above)
        line = machine.source.end[0] if machine.source else line
    adapter.new_line(line)
    message = error.message
    executed = _CONTROL_ERROR.match(message) or message.startswith(_EXECUTE_PREFIXES)
    reading = machine.reading and not executed
    return INTERP_ERROR, adapter.last_sequence + (1 if reading else 0)


__all__ = ["LineCode", "MIN_ERROR", "PreviewCanon", "parse", "strerror"]
