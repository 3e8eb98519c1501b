"""Canonical machining calls: the protocol and its back ends.

The machine (``runtime.machine``) turns G-code blocks into a stream of
canonical calls, exactly the calls LinuxCNC's interpreter makes on its
"canon" layer. What happens to the calls is up to the back end:

* :class:`TraceCanon` prints them the way ``rs274 -g`` does (the reference
  output ngc2py must reproduce byte for byte);
* :class:`NullCanon` ignores them (fast runs, statistics built elsewhere);
* :class:`RecordingCanon` keeps ``(name, args)`` tuples (tests, plotting).

Every call is one lower_snake_case method of :class:`Canon`, named after the
canon function (``STRAIGHT_FEED`` -> ``straight_feed``). Positions are in
program units, angles in degrees. Nothing here keeps machine state: the
interpreter never reads anything back from a canon (``runtime.machine``
models what rs274's stand-alone canon reports), so every back end behaves
the same way.

The only non-call method is :meth:`Canon.set_block_number`: the trace shows
the N number of the line being executed, so the machine announces it before
executing a line.
"""

from __future__ import annotations

from collections import deque
from itertools import compress, count, repeat, starmap
from math import copysign

from runtime.lazy_re import Pattern

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import IO, Iterator, List, Optional, Tuple

#: Runs an iterator to its end in C, keeping nothing
_drain = deque(maxlen=0).extend


def make_calls(rows: int, *calls: Iterator) -> None:
    """Run ``rows`` rows of the iterators of canon calls ``calls`` (a
    ``starmap`` or ``map`` of a method): a call of each in turn a row,
    asked by zip in C. A method raising StopIteration would only look like
    the end of its iterator and stop the batch in silence: counting the rows
    made turns that into an error."""
    made = count()
    _drain(zip(*calls, made))
    if next(made) != rows:
        raise RuntimeError("a canon method raised StopIteration")


def python_call_rows(start: int, stop: int, steps) -> None:
    """For each row from ``start`` to ``stop``, in turn, each step's call.
    A step is ``(method, columns[, kind[, mask]])``: ``columns`` a tuple of
    sequences, row k's call being ``method(*values)`` with ``values`` their
    k-th items, or ``method(kind(values))`` where a ``kind`` (a tuple type)
    is given; a step with a ``mask`` makes its call only on the rows whose
    item of it is true. The C extension ``runtime._call_rows`` does the same
    without an iterator step per column and row (tests/test_call_rows.py
    holds the two together); here map and zip run the rows in C."""
    iterators = []
    masks = []
    for step in steps:
        method, columns = step[0], step[1]
        kind = step[2] if len(step) > 2 else None
        mask = step[3] if len(step) > 3 else None
        values = zip(*[_rows_of(column, start, stop) for column in columns])
        if not columns:
            values = repeat((), stop - start)
        if mask is not None:
            mask = list(_rows_of(mask, start, stop))
            values = compress(values, mask)
        if kind is None:
            iterators.append(starmap(method, values))
        else:
            iterators.append(map(method, map(kind, values)))
        masks.append(mask)
    if not any(mask is not None for mask in masks):
        make_calls(stop - start, *iterators)
        return
    # rows where some step is left out: the calls in order, one next() each
    order = [
        calls
        for row in range(stop - start)
        for calls, mask in zip(iterators, masks)
        if mask is None or mask[row]
    ]
    made = count()
    _drain(zip(map(next, order), made))
    if next(made) != len(order):
        raise RuntimeError("a canon method raised StopIteration")


def _rows_of(column, start: int, stop: int):
    """A column's items for rows ``start`` to ``stop`` (one item: it, each row)."""
    if len(column) == 1:
        return repeat(column[0], stop - start)
    return column[start:stop]


try:
    from runtime._call_rows import call_rows
except ImportError:  # not built: the same calls by map and zip
    call_rows = python_call_rows


def _told_numbers(canon, steps: tuple, numbers, planes=None, count=0) -> tuple:
    """call_rows' ``steps`` with each row's set_block_number first, given
    ``numbers``, then the SELECT_PLANE of the rows ``planes`` names, of
    ``count`` (a batch method's default, for a canon that takes them)."""
    if planes:
        steps = ((canon.select_plane, (["XY"],), None, marked(planes, count)),) + steps
    if numbers is None:
        return steps
    return ((canon.set_block_number, (numbers,)),) + steps


def _rows_called(lines, steps: tuple) -> None:
    """A batch method's default: ``call_rows`` over the rows of ``lines``
    (each row's G-code line). An exception a call raises names its row's
    line (``ngc_row_line``, what runtime.fast.rows tags a row's error
    with), as when the rows' calls were made one row at a time: a user's
    canon that stops the program at a move is told where."""
    began = count()
    try:
        call_rows(0, len(lines), ((began.__next__, ()),) + steps)
    except Exception as error:
        if getattr(error, "ngc_row_line", None) is None:
            error.ngc_row_line = lines[next(began) - 1]
        raise


def marked(rows, count: int) -> List[bool]:
    """A mask of ``count`` rows, true at the indexes ``rows``."""
    mask = [False] * count
    for row in rows:
        mask[row] = True
    return mask


class Canon:
    """The canonical call protocol. Every method does nothing here.

    Subclass and override what a back end cares about; calls it does not
    override are silently accepted, which is what a protocol for optional
    consumers (statistics, plotting) wants.
    """

    #: True for a canon that reads ``machine.line`` while its calls are made:
    #: the fast loops over data rows then keep it current row by row.
    reads_lines = False

    #: True for a canon whose batch methods (straight_moves, arc_moves,
    #: contour_moves, hole_moves) take the rows' N numbers (``numbers=``:
    #: each row's N as written, or None) in place of a set_block_number a
    #: row: batches of numbered rows then reach it too. (A canon whose
    #: set_block_number is the no-op gets them without.)
    takes_numbers = False

    #: True for a canon whose arc_moves and contour_moves take, for a machine
    #: that takes arcs only in batches (runtime.fast.rows.BatchesOnly: the
    #: canon sees each line begin), the rows that restate G17 beside their
    #: arc (``planes=``: their indexes in the batch), whose SELECT_PLANE
    #: ("XY") comes after the row's line begins and its N, before its arc:
    #: such rows then join the batches.
    takes_planes = False

    def set_block_number(self, n: Optional[str]) -> None:
        """The N number (its digits as written) of the line now executing, or None."""

    # --- representation -------------------------------------------------
    def set_g5x_offset(self, index, x, y, z, a, b, c, u, v, w): ...
    def set_g92_offset(self, x, y, z, a, b, c, u, v, w): ...
    def set_xy_rotation(self, degrees): ...
    def use_length_units(self, inches: bool): ...
    def select_plane(self, plane: str): ...

    # --- motion ----------------------------------------------------------
    def set_traverse_rate(self, rate): ...
    def straight_traverse(self, x, y, z, a, b, c, u, v, w): ...
    def straight_feed(self, x, y, z, a, b, c, u, v, w): ...
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
    ): ...
    def straight_probe(self, x, y, z, a, b, c, u, v, w, probe_type): ...

    # --- batches of moves (the fast path's protocol) ----------------------
    # A run of moves with nothing else between them (no feed rate, N number,
    # plane or offset change) reaches a canon as one call whose arguments are
    # columns: ``lines[k]`` is move k's G-code line and ``x[k]`` .. ``w[k]``
    # (or the arc_feed arguments' k-th entries) its values. Every column is a
    # list of floats of len(lines) (an axis the moves leave alone is one
    # value repeated); ``lines`` is a list or a range of ints. The defaults
    # make one ordinary call per move, in order, so a canon that defines only
    # straight_feed & co. sees exactly the calls it always saw; a back end
    # that wants speed (statistics, toolpaths, previews) overrides these and
    # takes whole columns at once. Both are called in program order with
    # every other canon call, so state a canon keeps stays in step.
    # ``numbers`` (only for a canon that ``takes_numbers``): each row's N,
    # which by default it is told of before the row's calls.
    def straight_moves(
        self, feed: bool, lines, x, y, z, a, b, c, u, v, w, numbers=None
    ):
        """Straight moves, all feeds (``feed``) or all traverses."""
        call = self.straight_feed if feed else self.straight_traverse
        steps = ((call, (x, y, z, a, b, c, u, v, w)),)
        _rows_called(lines, _told_numbers(self, steps, numbers))

    def arc_moves(
        self,
        lines,
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
        numbers=None,
        planes=None,
    ):
        """Arcs, each as arc_feed's arguments (``rotation``: ints), and the
        G-code line of each in ``lines``. The fast loops give a canon that
        defines its own ``arc_moves`` the arcs between its other calls as
        one batch (``machine.line`` is then the batch's last line); by
        default, one ``arc_feed`` an arc (after its SELECT_PLANE, given
        ``planes``: see ``takes_planes``)."""
        columns = (first_end, second_end, first_axis, second_axis, rotation)
        arguments = (*columns, axis_end, a, b, c, u, v, w)
        steps = ((self.arc_feed, arguments),)
        _rows_called(lines, _told_numbers(self, steps, numbers, planes, len(lines)))

    def contour_moves(
        self,
        axes,
        lines,
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
        numbers=None,
        planes=None,
    ):
        """A contour: arcs and the plain straight feeds between them, in the
        columns of :meth:`arc_moves`, a straight feed being a row of
        ``rotation`` 0 (its end point in the ends' columns; its centre
        columns mean nothing). ``axes`` are the plane's (first, second,
        normal) axis indexes among the nine. Only a canon that overrides
        this gets contours, in place of its ``arc_moves`` batches (fewer and
        longer: the lines between a contour's arcs no longer cut it); by
        default, one ``arc_feed`` or ``straight_feed`` a row."""
        f, s, n = axes
        arcs = (first_end, second_end, first_axis, second_axis, rotation, axis_end)
        point = [None, None, None, a, b, c, u, v, w]
        point[f], point[s], point[n] = first_end, second_end, axis_end
        # each row one call or the other: an arc where its rotation is not 0
        steps = (
            (self.arc_feed, (*arcs, a, b, c, u, v, w), None, rotation),
            (self.straight_feed, tuple(point), None, [not turn for turn in rotation]),
        )
        _rows_called(lines, _told_numbers(self, steps, numbers, planes, len(lines)))

    def hole_moves(self, recording, lines, first, second, axes, start, numbers=None):
        """Holes of a canned cycle drilled alike (runtime.fast.hole_rows):
        ``recording`` is one hole's calls, ``(name, arguments, where)``,
        where a move's ``where`` is ``"hole"`` (its coordinates on the
        plane's two hole axes, indexes ``axes``, are the hole's), ``"start"``
        (they are where the tool was before the hole: the hole before, or
        ``start`` for the first) or None for a call that is not a move.
        Hole k is at ``(first[k], second[k])``, on G-code line ``lines[k]``
        (and has N ``numbers[k]``, which its first call, set_block_number,
        tells, where the recording's told the recorded hole's). By default
        the recorded calls again, hole by hole, made from columns by
        ``call_rows``: no Python statement per call."""
        ia, ib = axes
        places = {
            "hole": (first, second),
            "start": ([start[0]] + first[:-1], [start[1]] + second[:-1]),
        }
        steps = []
        for name, args, where in recording:
            # (a column of one value serves every hole)
            columns = [[value] for value in args]
            if where is not None:
                columns[ia], columns[ib] = places[where]
            steps.append((getattr(self, name), tuple(columns)))
        if numbers is not None:  # (the first call: each hole's own N)
            steps[0] = (self.set_block_number, (numbers,))
        _rows_called(lines, tuple(steps))

    def rigid_tap(self, x, y, z, scale): ...
    def nurbs_feed(self, control_points, order): ...
    def dwell(self, seconds): ...

    # --- machining attributes -----------------------------------------
    def set_feed_mode(self, spindle, mode): ...
    def set_feed_rate(self, rate): ...
    def set_feed_reference(self, workpiece: bool): ...
    def set_motion_control_mode(self, mode: str, tolerance): ...
    def set_naivecam_tolerance(self, tolerance): ...
    def set_cutter_radius_compensation(self, radius): ...
    def start_cutter_radius_compensation(self, side: str): ...
    def stop_cutter_radius_compensation(self): ...
    def start_speed_feed_synch(self, spindle, sync, velocity_mode: bool): ...
    def stop_speed_feed_synch(self): ...

    # --- spindle ---------------------------------------------------------
    def set_spindle_mode(self, spindle, mode): ...
    def set_spindle_speed(self, spindle, rpm): ...
    def start_spindle_clockwise(self, spindle): ...
    def start_spindle_counterclockwise(self, spindle): ...
    def stop_spindle_turning(self, spindle): ...
    def spindle_retract(self): ...
    def spindle_retract_traverse(self): ...
    def orient_spindle(self, spindle, orientation, mode): ...
    def wait_spindle_orient_complete(self, spindle, timeout): ...
    def use_no_spindle_force(self): ...

    # --- tools -----------------------------------------------------------
    def select_tool(self, tool): ...
    def start_change(self): ...
    def change_tool(self, slot): ...
    def change_tool_number(self, tool): ...
    def use_tool_length_offset(self, x, y, z, a, b, c, u, v, w): ...
    def set_tool_table_entry(
        self, index, toolno, offset, diameter, frontangle, backangle, orientation
    ): ...
    def reload_tooldata(self): ...

    # --- miscellaneous -------------------------------------------------
    def comment(self, text): ...
    def message(self, text): ...
    def log(self, text): ...
    def logopen(self, name): ...
    def logappend(self, name): ...
    def logclose(self): ...
    def flood_on(self): ...
    def flood_off(self): ...
    def mist_on(self): ...
    def mist_off(self): ...
    def enable_feed_override(self): ...
    def disable_feed_override(self): ...
    def enable_speed_override(self, spindle): ...
    def disable_speed_override(self, spindle): ...
    def enable_adaptive_feed(self): ...
    def disable_adaptive_feed(self): ...
    def enable_feed_hold(self): ...
    def disable_feed_hold(self): ...
    def turn_probe_on(self): ...
    def turn_probe_off(self): ...
    def clamp_axis(self, axis: str): ...
    def unclamp_axis(self, axis: str): ...
    def set_motion_output_bit(self, index): ...
    def clear_motion_output_bit(self, index): ...
    def set_motion_output_value(self, index, value): ...
    def set_aux_output_bit(self, index): ...
    def clear_aux_output_bit(self, index): ...
    def set_aux_output_value(self, index, value): ...
    def canon_error(self, text): ...
    def flush(self):
        """Output kept back (the trace's buffered lines) goes out now: the
        machine calls this when a run ends, errors or not."""

    def print_text(self, text):
        """Text rs274 writes to stdout itself, outside the canon: a
        ``(PRINT,...)`` comment's expansion, G7x's "Oops" diagnostics. A
        method here so that a library caller gets it and nothing is written
        behind its back."""

    # --- program flow --------------------------------------------------
    def program_stop(self): ...
    def optional_program_stop(self): ...
    def pallet_shuttle(self): ...
    def program_end(self): ...
    def finish(self): ...
    def on_reset(self): ...


def own_method(canon, name: str):
    """``canon``'s method ``name``, or None where it is the protocol's no-op
    (the fast loops then make no such call: see runtime.fast.arc_rows)."""
    if getattr(type(canon), name) is getattr(Canon, name):
        return None
    return getattr(canon, name)


def ignores_numbers(canon) -> bool:
    """Whether ``canon`` ignores N numbers (its set_block_number is the
    protocol's no-op): the fast loops then hand it numbered rows in the
    batches rows without take (runtime.fast), calling no set_block_number."""
    return type(canon).set_block_number is Canon.set_block_number


class NullCanon(Canon):
    """Accepts every call and does nothing."""


#: The batch methods: not calls of their own but runs of the calls above.
BATCHES = ("straight_moves", "arc_moves", "contour_moves", "hole_moves")


def _call_names() -> Tuple[str, ...]:
    """The canonical call methods of the protocol (everything but bookkeeping)."""
    return tuple(
        name
        for name, value in vars(Canon).items()
        if callable(value)
        and not name.startswith("_")
        and name not in ("set_block_number", "flush") + BATCHES
    )


CALLS = _call_names()


class RecordingCanon(Canon):
    """Records every call as ``(name, args)`` in :attr:`calls`.

    The N number in force when a call was made is kept in :attr:`numbers`,
    index for index, so tests can check it too.
    """

    def __init__(self) -> None:
        self.calls: List[Tuple[str, tuple]] = []
        self.numbers: List[Optional[str]] = []
        self._n: Optional[str] = None

    def set_block_number(self, n: Optional[str]) -> None:
        self._n = n

    def _record(self, name: str, args: tuple) -> None:
        self.calls.append((name, args))
        self.numbers.append(self._n)


def _recorder(name: str):
    def record(self, *args):
        self._record(name, args)

    record.__name__ = name
    record.__doc__ = f"Record a ``{name}`` call."
    return record


for _name in CALLS:
    setattr(RecordingCanon, _name, _recorder(_name))
del _name


def _axes6(x, y, z, a, b, c) -> str:
    """Six positions as rs274 prints them: the trace shows XYZABC, never UVW."""
    return f"{x:.4f}, {y:.4f}, {z:.4f}, {a:.4f}, {b:.4f}, {c:.4f}"


def _pose9(x, y, z, a, b, c, u, v, w) -> str:
    """A nine-axis pose as USE_TOOL_LENGTH_OFFSET prints it: spaces within a triple."""
    return f"{x:.4f} {y:.4f} {z:.4f}, {a:.4f} {b:.4f} {c:.4f}, {u:.4f} {v:.4f} {w:.4f}"


def _c_double(value: float) -> str:
    """C's ``%f`` (six decimals) for the few calls that print that way."""
    return f"{value:f}"


def _no_arguments(call: str):
    """A TraceCanon method for a call rs274 prints with no arguments."""

    def emit(self) -> None:
        self._emit(call + "()")

    emit.__name__ = call.lower()
    return emit


try:
    # template % args, about three times faster for trace lines (setup.py);
    # trace_rows: a batch of lines, one per row of columns, in one string
    from runtime._fast_format import percent as trace_format
    from runtime._fast_format import percent_rows as trace_rows
    from runtime._fast_format import numbered_rows
except ImportError:  # not built (no C compiler): the very same strings

    def trace_format(template: str, args: tuple) -> str:
        text = template % args
        return text if "nan" not in text else c_nans(template, args)

    def trace_rows(template: str, columns) -> str:
        return "".join(trace_format(template, row) for row in zip(*columns))

    numbered_rows = None  # (python_numbered_rows, below)


def python_numbered_rows(template, first, lines, rows, layout, columns) -> str:
    """``rows`` rows of a template of ``lines`` trace lines (a canned
    cycle's hole), numbered on from ``first``: conversion k is, by
    layout[k], the number of that line of the row (below ``lines``) or the
    row's item of ``columns[layout[k] - lines]``. runtime._fast_format's
    numbered_rows makes the same text without a range for each line."""
    span = lines * rows
    pool = [range(b, b + span, lines) for b in range(first, first + lines)]
    pool += [column[:rows] for column in columns]
    return trace_rows(template, [pool[i] for i in layout]) if layout else ""


if numbered_rows is None:
    numbered_rows = python_numbered_rows


#: A conversion of a trace template (the few kinds trace lines use).
_CONVERSION = Pattern(r"%[-\d]*(?:\.\d+)?[sdf%]")


def c_nans(template: str, args: tuple) -> str:
    """``template % args`` with each NaN printed by ``%f`` as C's printf
    prints it: ``-nan`` when its sign bit is set (an R 0 arc's centre in
    rs274's trace), where Python always writes ``nan``."""
    values = iter(args)
    out = []
    at = 0
    for found in _CONVERSION.finditer(template):
        out.append(template[at : found.start()])
        at = found.end()
        spec = found.group()
        if spec == "%%":
            out.append("%")
            continue
        value = next(values)
        if spec[-1] == "f" and value != value:
            out.append("-nan" if copysign(1.0, value) < 0 else "nan")
        else:
            out.append(spec % value)
    out.append(template[at:])
    return "".join(out)


_TRAVERSE = "%5d %sSTRAIGHT_TRAVERSE(%.4f, %.4f, %.4f, %s)\n"
_FEED = "%5d %sSTRAIGHT_FEED(%.4f, %.4f, %.4f, %s)\n"
_ABC = "%.4f, %.4f, %.4f"
_ARC = "%5d %sARC_FEED(%.4f, %.4f, %.4f, %.4f, %d, %.4f, %.4f, %.4f, %.4f)\n"
_FEED_RATE = "%5d %sSET_FEED_RATE(%.4f)\n"

#: Trace lines kept before one write to the stream: writing a line to a
#: text stream costs about a microsecond, as much as formatting it.
BUFFERED_LINES = 1024


class PythonTraceLines:
    """TraceCanon's commonest calls, in Python: its base where the C
    extension ``runtime._fast_format`` was not built (whose ``TraceLines``
    does the same in C, held to these by tests/test_fast_format.py).

    The state is TraceCanon's (its ``__init__`` sets it): ``_count``,
    ``_column``, ``_pending``/``_write``, ``_drain_at``, ``_a``/``_b``/``_c``
    and ``_abc``.
    """

    def straight_traverse(self, x, y, z, a, b, c, u, v, w):
        self._straight(_TRAVERSE, x, y, z, a, b, c)

    def straight_feed(self, x, y, z, a, b, c, u, v, w):
        self._straight(_FEED, x, y, z, a, b, c)

    def _straight(self, template, x, y, z, a, b, c):
        # One %-format (f-strings with format specs are slower), the line
        # number folded in; the A/B/C text reused while they are the same.
        self._count += 1
        if a is not self._a or b is not self._b or c is not self._c:
            self._a, self._b, self._c = a, b, c
            self._abc = trace_format(_ABC, (a, b, c))
        self._write(
            trace_format(template, (self._count, self._column, x, y, z, self._abc))
        )
        if self._count >= self._drain_at:
            self._drain()

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
        self._count += 1
        line = (
            self._count,
            self._column,
            first_end,
            second_end,
            first_axis,
            second_axis,
            rotation,
            axis_end,
            a,
            b,
            c,
        )
        self._write(trace_format(_ARC, line))
        if self._count >= self._drain_at:
            self._drain()

    def set_feed_rate(self, rate):
        self._count += 1
        self._write(trace_format(_FEED_RATE, (self._count, self._column, rate)))
        if self._count >= self._drain_at:
            self._drain()

    def _emit(self, text: str) -> None:
        """A line of any other call (its text made by TraceCanon)."""
        self._count += 1
        self._write(f"{self._count:5d} {self._column}{text}\n")
        if self._count >= self._drain_at:
            self._drain()


try:
    from runtime._fast_format import TraceLines as _TraceLines
except ImportError:  # not built: the Python versions
    _TraceLines = PythonTraceLines


class TraceCanon(_TraceLines, Canon):
    """Prints calls exactly as ``rs274 -g`` does.

    Each line is ``%5d`` sequence number, a space, the N column and the call:
    the N column is ``N`` plus the line's N-word digits padded to six
    characters (``N10    ``), or ``N..... `` when the line has no N word.
    Numbers are ``%.4f`` unless a call prints otherwise (those quirks are
    rs274's, kept on purpose).
    """

    def __init__(self, out: IO[str], text_out: Optional[IO[str]] = None):
        self._out = out
        #: Where PRINT text goes when it is not the trace's stream (rs274's
        #: output file takes the trace; its PRINT text stays on stdout).
        self._text_out = text_out
        self._pending: List[str] = []
        self._write = self._pending.append
        self._count = 0
        self._column = "N..... "
        self._drain_at = BUFFERED_LINES
        # The rotary axes of the last move, and their text: a straight move
        # that passes the very same float objects on (an axis its block does
        # not name) reuses the text instead of formatting three more floats.
        self._a = self._b = self._c = None
        self._abc = ""

    # The lines wait in a list and go to the stream in batches: each method
    # that adds a line checks ``_drain_at``. Machine.run flushes at the end,
    # errors or not; whoever writes to the same stream meanwhile (run_cli)
    # flushes first.
    def flush(self) -> None:
        """Write every pending line to the stream, and flush the stream."""
        self._drain()
        flush = getattr(self._out, "flush", None)
        if flush is not None:
            flush()

    def _drain(self) -> None:
        if self._pending:
            self._out.write("".join(self._pending))
            self._pending.clear()
        self._drain_at = self._count + BUFFERED_LINES

    def _write_batch(self, text: str) -> None:
        """A batch of lines made in one piece (runtime.fast's rows): written
        to the stream as it is, after the lines waiting, where joining it
        with them would copy it once more (a batch is thousands of lines).
        The caller then counts its lines (``_count``) as it would have."""
        self._drain()
        self._out.write(text)

    def set_block_number(self, n: Optional[str]) -> None:
        self._column = "N..... " if n is None else f"N{n:<6}"

    # --- representation -------------------------------------------------
    def set_g5x_offset(self, index, x, y, z, a, b, c, u, v, w):
        self._emit(f"SET_G5X_OFFSET({index}, {_axes6(x, y, z, a, b, c)})")

    def set_g92_offset(self, x, y, z, a, b, c, u, v, w):
        self._emit(f"SET_G92_OFFSET({_axes6(x, y, z, a, b, c)})")

    def set_xy_rotation(self, degrees):
        self._emit(f"SET_XY_ROTATION({degrees:.4f})")

    def use_length_units(self, inches):
        self._emit(f"USE_LENGTH_UNITS(CANON_UNITS_{'INCHES' if inches else 'MM'})")

    def select_plane(self, plane):
        self._emit(f"SELECT_PLANE(CANON_PLANE_{plane})")

    # --- motion ----------------------------------------------------------
    def set_traverse_rate(self, rate):
        self._emit(f"SET_TRAVERSE_RATE({rate:.4f})")

    def straight_probe(self, x, y, z, a, b, c, u, v, w, probe_type):
        self._emit(f"STRAIGHT_PROBE({_axes6(x, y, z, a, b, c)})")

    def rigid_tap(self, x, y, z, scale):
        self._emit(f"RIGID_TAP({x:.4f}, {y:.4f}, {z:.4f})")

    def nurbs_feed(self, control_points, order):
        self._emit(f"NURBS_FEED({len(control_points)}, ...)")

    def dwell(self, seconds):
        self._emit(f"DWELL({seconds:.4f})")

    # --- machining attributes -----------------------------------------
    def set_feed_mode(self, spindle, mode):
        self._emit(f"SET_FEED_MODE({spindle}, {mode})")

    def set_feed_reference(self, workpiece):
        self._emit(
            f"SET_FEED_REFERENCE({'CANON_WORKPIECE' if workpiece else 'CANON_XYZ'})"
        )

    def set_motion_control_mode(self, mode, tolerance):
        # Only the continuous mode prints its tolerance, and with %f.
        if mode == "CONTINUOUS":
            self._emit(
                f"SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, {_c_double(tolerance)})"
            )
        else:
            self._emit(f"SET_MOTION_CONTROL_MODE(CANON_{mode})")

    def set_naivecam_tolerance(self, tolerance):
        self._emit(f"SET_NAIVECAM_TOLERANCE({tolerance:.4f})")

    def set_cutter_radius_compensation(self, radius):
        self._emit(f"SET_CUTTER_RADIUS_COMPENSATION({radius:.4f})")

    def start_cutter_radius_compensation(self, side):
        self._emit(f"START_CUTTER_RADIUS_COMPENSATION({side})")

    stop_cutter_radius_compensation = _no_arguments("STOP_CUTTER_RADIUS_COMPENSATION")

    def start_speed_feed_synch(self, spindle, sync, velocity_mode):
        # rs274 prints the name without the final H here.
        self._emit(f"START_SPEED_FEED_SYNC({_c_double(sync)},{int(velocity_mode)})")

    stop_speed_feed_synch = _no_arguments("STOP_SPEED_FEED_SYNCH")

    # --- spindle ---------------------------------------------------------
    def set_spindle_mode(self, spindle, mode):
        self._emit(f"SET_SPINDLE_MODE({spindle} {mode:.4f})")  # no comma: rs274's

    def set_spindle_speed(self, spindle, rpm):
        self._emit(f"SET_SPINDLE_SPEED({spindle}, {rpm:.4f})")

    def start_spindle_clockwise(self, spindle):
        self._emit(f"START_SPINDLE_CLOCKWISE({spindle})")

    def start_spindle_counterclockwise(self, spindle):
        self._emit(f"START_SPINDLE_COUNTERCLOCKWISE({spindle})")

    def stop_spindle_turning(self, spindle):
        self._emit(f"STOP_SPINDLE_TURNING({spindle})")

    spindle_retract = _no_arguments("SPINDLE_RETRACT")

    spindle_retract_traverse = _no_arguments("SPINDLE_RETRACT_TRAVERSE")

    def orient_spindle(self, spindle, orientation, mode):
        self._emit(f"ORIENT_SPINDLE({spindle}, {orientation:.4f}, {mode})")

    def wait_spindle_orient_complete(self, spindle, timeout):
        self._emit(f"SPINDLE.{spindle}.WAIT_ORIENT_COMPLETE({timeout:.4f})")

    use_no_spindle_force = _no_arguments("USE_NO_SPINDLE_FORCE")

    # --- tools -----------------------------------------------------------
    def select_tool(self, tool):
        self._emit(f"SELECT_TOOL({tool})")

    start_change = _no_arguments("START_CHANGE")

    def change_tool(self, slot):
        self._emit(f"CHANGE_TOOL({slot})")

    def change_tool_number(self, tool):
        self._emit(f"CHANGE_TOOL_NUMBER({tool})")

    def use_tool_length_offset(self, x, y, z, a, b, c, u, v, w):
        self._emit(f"USE_TOOL_LENGTH_OFFSET({_pose9(x, y, z, a, b, c, u, v, w)})")

    def set_tool_table_entry(
        self, index, toolno, offset, diameter, frontangle, backangle, orientation
    ):
        # The diameter is not printed, as in rs274.
        self._emit(
            f"SET_TOOL_TABLE_ENTRY({index}, {toolno}, "
            + " ".join(f"{v:.4f}" for v in offset)
            + f", {frontangle:.4f}, {backangle:.4f}, {orientation})"
        )

    reload_tooldata = _no_arguments("RELOAD_TOOLDATA")

    # --- miscellaneous -------------------------------------------------
    def comment(self, text):
        self._emit(f'COMMENT("{text}")')

    def message(self, text):
        self._emit(f'MESSAGE("{text}")')

    def log(self, text):
        self._emit(f'LOG("{text}")')

    def logopen(self, name):
        self._emit(f'LOGOPEN("{name}")')

    def logappend(self, name):
        self._emit(f'LOGAPPEND("{name}")')

    logclose = _no_arguments("LOGCLOSE")

    flood_on = _no_arguments("FLOOD_ON")

    flood_off = _no_arguments("FLOOD_OFF")

    mist_on = _no_arguments("MIST_ON")

    mist_off = _no_arguments("MIST_OFF")

    enable_feed_override = _no_arguments("ENABLE_FEED_OVERRIDE")

    disable_feed_override = _no_arguments("DISABLE_FEED_OVERRIDE")

    def enable_speed_override(self, spindle):
        self._emit(f"ENABLE_SPEED_OVERRIDE({spindle})")

    def disable_speed_override(self, spindle):
        self._emit(f"DISABLE_SPEED_OVERRIDE({spindle})")

    enable_adaptive_feed = _no_arguments("ENABLE_ADAPTIVE_FEED")

    disable_adaptive_feed = _no_arguments("DISABLE_ADAPTIVE_FEED")

    enable_feed_hold = _no_arguments("ENABLE_FEED_HOLD")

    disable_feed_hold = _no_arguments("DISABLE_FEED_HOLD")

    turn_probe_on = _no_arguments("TURN_PROBE_ON")

    turn_probe_off = _no_arguments("TURN_PROBE_OFF")

    def clamp_axis(self, axis):
        self._emit(f"CLAMP_AXIS(CANON_AXIS_{axis})")

    def unclamp_axis(self, axis):
        self._emit(f"UNCLAMP_AXIS(CANON_AXIS_{axis})")

    def set_motion_output_bit(self, index):
        self._emit(f"SET_MOTION_OUTPUT_BIT({index})")

    def clear_motion_output_bit(self, index):
        self._emit(f"CLEAR_MOTION_OUTPUT_BIT({index})")

    def set_motion_output_value(self, index, value):
        self._emit(f"SET_MOTION_OUTPUT_VALUE({index},{_c_double(value)})")

    def set_aux_output_bit(self, index):
        self._emit(f"SET_AUX_OUTPUT_BIT({index})")

    def clear_aux_output_bit(self, index):
        self._emit(f"CLEAR_AUX_OUTPUT_BIT({index})")

    def set_aux_output_value(self, index, value):
        self._emit(f"SET_AUX_OUTPUT_VALUE({index},{_c_double(value)})")

    def canon_error(self, text):
        self._emit(f"CANON_ERROR({text})")

    def print_text(self, text):
        # rs274 prints the line itself, between trace lines, unnumbered.
        if self._text_out is not None:
            self._text_out.write(text + "\n")
            return
        self._write(text + "\n")
        if self._count >= self._drain_at:
            self._drain()

    # --- program flow --------------------------------------------------
    program_stop = _no_arguments("PROGRAM_STOP")

    optional_program_stop = _no_arguments("OPTIONAL_PROGRAM_STOP")

    pallet_shuttle = _no_arguments("PALLET_SHUTTLE")

    program_end = _no_arguments("PROGRAM_END")

    finish = _no_arguments("FINISH")

    on_reset = _no_arguments("ON_RESET")


__all__ = ["Canon", "NullCanon", "RecordingCanon", "TraceCanon", "CALLS"]
