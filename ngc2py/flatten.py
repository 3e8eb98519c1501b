"""``ngc2py flatten``: a program as plain G-code, everything resolved.

The program runs against :class:`FlattenCanon`, a canon back end that
writes G-code back from the canonical calls: subroutines, loops,
conditionals, expressions and parameters are gone, and what is left is the
sequence of moves and settings they produced. rs274 runs the result to the
same STRAIGHT_TRAVERSE / STRAIGHT_FEED / ARC_FEED calls as the original.

How calls become G-code (decisions, see the README's "Flatten" section):

* Positions: canonical calls carry positions in the active coordinate
  system, in the active length units, so moves are written absolute (G90)
  with exactly those numbers. Each block's start point is the machine's own
  idea of the current point, which is what rs274 recomputes after offset,
  unit or tool-offset changes, so only the axes that change are written.
* Numbers are written with every digit Python's ``repr`` needs to read back
  the same double, in plain decimal notation (G-code has no exponents).
* Arcs are written in centre format (G2/G3 with I/J/K relative to the start
  point, P for extra turns) from ARC_FEED's centre and end point.
* Offsets: G5x selection becomes ``G10 L2 P.. ... R..`` (when the stored
  values differ from what the flat program already set) and the G5x code;
  a change of the active system's offset becomes ``G10 L2``; G92-type
  offsets (G92, G52, G92.1-G92.3) become ``G52`` with the resulting offset;
  tool length offsets (G43, G43.1, G49) become ``G43.1`` with the offset.
* Feed rates are written as F in units per minute: inverse-time (G93) moves
  come out as the per-minute rate rs274 computed, under G94.
* M2/M30's own resets are not written out: the flat program's M2 makes them.
* Each line ends with a ``;`` comment naming the source line (and the
  O-calls that led there); ``;`` comments make no COMMENT call. N words are
  kept as written, so the trace's N column stays the same.

Where the full trace cannot be the same (a G5x selection or G94 written out
adds a COMMENT or offset call rs274 did not make in the original), only
those bookkeeping calls differ; the motion calls never do. Calls that one
G-code makes are written as that G-code with literal values (G38.x probes,
G33 for synchronized feeds, G33.1, G5.2/G5.3 for any spline, M19, G10 L1
for tool table edits, G43 H / G43.2 H for U V W tool offsets). Calls with
no G-code at all stop the flattening with an error that names them.
"""

from __future__ import annotations

import math
from array import array
from marshal import dumps
from math import hypot
from itertools import chain, groupby, repeat
from operator import add, eq, itemgetter, ne, sub
import os
import sys

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import List, Optional, Sequence, Tuple

from runtime.canon import CALLS, Canon, trace_rows
from runtime.errors import g_code_frames_of_stack
from runtime.fast.hole_rows import HOLE_MOVES, RESTATED_SWITCHES, hole_by_hole
from runtime.lazy_re import Pattern

AXES6 = "XYZABC"
SYSTEM_CODES = ("G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3")
# rs274 reports the three U/V/W planes alike; any of them makes that call
PLANE_CODES = {"XY": "G17", "XZ": "G18", "YZ": "G19", "UNKNOWN": "G17.1"}
#: ARC_FEED's first/second axis and the axis-end axis per plane, and the
#: centre-offset letters of the first and second axis.
_AXIS_INDEX = {letter: k for k, letter in enumerate(AXES6)}
ARC_AXES = {
    "XY": ("X", "Y", "Z", "I", "J"),
    "XZ": ("Z", "X", "Y", "K", "I"),
    "YZ": ("Y", "Z", "X", "J", "K"),
}
#: Calls rs274's M2/M30 makes on its own before PROGRAM_END.
END_RESETS = {
    "set_g5x_offset",
    "set_g92_offset",
    "set_xy_rotation",
    "set_feed_mode",
    "set_feed_rate",
    "enable_feed_override",
    "enable_speed_override",
    "disable_adaptive_feed",
    "enable_feed_hold",
    "stop_spindle_turning",
    "set_spindle_mode",
    "select_plane",
    "set_motion_control_mode",
    "mist_off",
    "flood_off",
    "stop_cutter_radius_compensation",
    "use_length_units",
    "comment",
    "pallet_shuttle",
}
FEED_MODE_COMMENTS = {
    "interpreter: feed mode set to units per minute": "G94",
    "interpreter: feed mode set to units per revolution": "G95",
    # moves in inverse time come with the per-minute rate rs274 computed
    "interpreter: feed mode set to inverse time": "G94",
}
#: Calls after which the flat program's current point is rs274's to work
#: out again: the next move writes every axis.
MOVES_ORIGIN = {
    "use_length_units",
    "set_g5x_offset",
    "set_g92_offset",
    "set_xy_rotation",
    "use_tool_length_offset",
}
#: Longest line written with its location comment on the same line
#: (rs274 refuses lines of 253 characters and more).
MAX_LINE = 240
#: Parameters that G-codes read: G28 and G30 homes, G92 offsets, the active
#: system and the coordinate systems' offsets and rotations.
CODE_PARAMETERS = range(5161, 5391)
UNKNOWN = float("nan")
#: The calls that move the tool.
MOTION_CALLS = {
    "straight_traverse",
    "straight_feed",
    "straight_probe",
    "arc_feed",
    "rigid_tap",
    "nurbs_feed",
}
#: rs274's smallest arc radius (inch; times 25.4 in mm).
RADIUS_TOLERANCE_INCH = 0.00005
MM_PER_INCH = 25.4


#: The calls of a hole (besides its set_block_number) that
#: FlattenCanon.hole_moves writes from a template: every call a recorded hole
#: may hold (runtime.fast.hole_rows: moves, dwells, the path-control modes a
#: cycle sets around its moves, the spindle, override and stop switches of
#: the tapping and boring cycles, a restated line's retract mode comment;
#: not its F, which goes call by call); none of them changes what later
#: lines mean (what _texts keeps: units, plane, the current point).
_HOLE_CALLS = (HOLE_MOVES | RESTATED_SWITCHES) - {"set_block_number", "set_feed_rate"}


class FlattenError(Exception):
    """The program made a call flatten cannot write as G-code."""


def number(value: float) -> str:
    """``value`` in G-code: plain decimal, enough digits to read it back."""
    value = float(value)
    if value == int(value) and abs(value) < 1e15:
        return "%d" % value if value or str(value)[0] != "-" else "-0"
    text = repr(value)
    if "e" in text or "E" in text:
        from decimal import Decimal  # here: seldom needed, costly to import

        text = format(Decimal(text), "f")
    return text


def _python_words(prefix: str, values: Sequence[float]) -> Optional[List[str]]:
    """``prefix`` + repr of each of ``values`` without the ``.0`` of the
    integral ones (what number() writes below 1e15); None where a value
    needs number() itself (an exponent, nan, inf, 1e15 or more)."""
    texts = list(map(repr, values))
    joined = "".join(texts)  # (one look for exponents, nan and inf)
    if "e" in joined or "n" in joined or max(values) >= 1e15 or min(values) <= -1e15:
        return None
    return [prefix + (text[:-2] if text.endswith(".0") else text) for text in texts]


try:  # the same, in C (runtime/_fast_format.c); optional
    from runtime._fast_format import move_text as _fast_move
    from runtime._fast_format import words as _fast_words
except ImportError:  # pragma: no cover - the extension was not built
    _fast_words = _fast_move = None


def _words(prefix: str, values: Sequence[float]) -> List[str]:
    """``prefix`` + :func:`number` of each of ``values``, a column at a time."""
    if not values:
        return []
    if _fast_words is not None:
        made = _fast_words(prefix, values if type(values) is list else list(values))
    else:
        made = _python_words(prefix, values)
    if made is None:
        return [prefix + number(value) for value in values]
    return made


def _numbers(values: Sequence[float]) -> List[str]:
    """:func:`number` of each of ``values``."""
    return _words("", values)


def python_float_bits(values: List[float], start: int, stop: int) -> bytes:
    """The bits of ``values[start:stop]`` (runtime._fast_format.float_bits
    where it is built)."""
    return array("d", values[start:stop]).tobytes()


try:  # the same, in C (runtime/_fast_format.c); optional
    from runtime._fast_format import float_bits
except ImportError:  # pragma: no cover - the extension was not built
    float_bits = python_float_bits


def _bits(values: Sequence[float]) -> memoryview:
    """Each float's 64 bits as an integer: equal exactly where same() is
    (the trace has no NaN)."""
    return memoryview(array("d", values)).cast("B").cast("Q")


def _names(calls: List[tuple], start: int, count: Optional[int] = None) -> List[str]:
    """The names of the calls from ``start`` (``count`` of them, or all)."""
    stop = len(calls) if count is None else start + count
    return [name for name, _ in calls[start:stop]]


def _same_zero(a: float, b: float) -> bool:
    """Two zeros of the same sign (rs274 prints -0.0000)."""
    return math.copysign(1.0, a) == math.copysign(1.0, b)


def same(a: float, b: float) -> bool:
    """Equal, and with the same sign when zero (rs274 prints -0.0000)."""
    return a == b and math.copysign(1.0, a) == math.copysign(1.0, b)


def _python_short_offsets(starts: List[float], centres: List[float]) -> List[float]:
    """centre - start for each arc, or its four decimals (_short) where
    those added to the start give the very centre: _offset's first choice."""
    exact = list(map(sub, centres, starts))
    short = list(map(_short, exact))
    return [
        s if total == centre else e
        for s, e, total, centre in zip(short, exact, map(add, starts, short), centres)
    ]


def _short(offset: float) -> float:
    """``offset`` to four decimals: round half to even at the fourth, as C's
    nearbyint(offset * 10000) / 10000 (runtime._fast_format.short_offsets)."""
    if not math.isfinite(offset):
        return offset
    # (copysign: a zero keeps its sign, as C's does)
    return math.copysign(round(offset * 10000.0) / 10000.0, offset)


try:  # the same, in C; optional
    from runtime._fast_format import short_offsets as _fast_short_offsets
except ImportError:  # pragma: no cover - the extension was not built
    _fast_short_offsets = None


def _short_offsets(starts: List[float], centres: List[float]) -> List[float]:
    if _fast_short_offsets is not None:
        made = _fast_short_offsets(list(starts), list(centres))
        if made is not None:
            return made
    return _python_short_offsets(starts, centres)


def _offset(start: float, centre: float) -> Optional[float]:
    """An offset that rs274 adds to ``start`` to get exactly ``centre``, or
    None (unknown start; or -0.0, which no sum of non-zeros gives)."""
    guess = centre - start
    if centre:
        # four decimals where they give the very centre (as the program
        # most likely wrote it: I-17.303, not I-17.302999999999997)
        short = _short(guess)
        if start + short == centre:
            return short
    if start + guess == centre and centre:  # the usual case, at once
        return guess
    for _ in range(4):
        if same(start + guess, centre):
            return guess
        guess = math.nextafter(guess, math.inf if start + guess < centre else -math.inf)
    return None


def _hole_calls(recording, axes, here, before) -> List[tuple]:
    """The calls of a recorded hole (runtime.canon.Canon.hole_moves) for
    the hole at ``here`` after the one at ``before``."""
    ia, ib = axes
    calls = []
    for name, args, at in recording[1:]:
        if at is not None:
            args = list(args)
            args[ia], args[ib] = here if at == "hole" else before
        calls.append((name, args))
    return calls


def _free_levels(recording, axes, pos):
    """A recorded hole with its levels (the hole axis' value of each move)
    taken out: (its shape: what a template of it is kept by, the levels' texts
    in the order they first come, which level each value is by its repr, which
    level the flat program's tool is at: len(levels) for none); None where
    a level is not a number (NaN, infinity) or there are too many."""
    level = 3 - sum(axes)
    values = [args[level] for _, args, at in recording if at is not None]
    if not values or not all(map(math.isfinite, values)):
        return None
    texts = list(map(repr, values))  # (equal exactly where same() is)
    index: dict = {}
    levels: List[float] = []
    for text, value in zip(texts, values):
        if text not in index:
            index[text] = len(levels)
            levels.append(value)
    if len(levels) > _MOST_LEVELS:
        return None
    # where the tool is on that axis matters only as the level it is at
    here = pos[level]
    at_level = (
        index.get(repr(here), len(levels)) if math.isfinite(here) else len(levels)
    )
    # a move's plane coordinates are each hole's own (_hole_calls), and the
    # first call, set_block_number, is written as the prefix (its N is not
    # the shape's: it may be each hole's own)
    calls = [
        (name, args if at is None else args[3:], at) for name, args, at in recording[1:]
    ]
    pattern = list(map(index.__getitem__, texts))
    shape = dumps((axes, calls, pattern, at_level, tuple(pos[3:6])))
    return shape, _numbers(levels), index, at_level


def _standing(recording, axes, index: dict) -> list:
    """``recording`` with a stand-in for each level (see _free_levels)."""
    level = 3 - sum(axes)
    standing = []
    for name, args, at in recording:
        if at is not None:
            args = list(args)
            args[level] = _LEVEL_STAND_IN + index[repr(args[level])]
            args = tuple(args)
        standing.append((name, args, at))
    return standing


def _numbered(numbers: Optional[List[Optional[str]]], texts: List[str]) -> List[str]:
    """A batch's blocks, each after its row's N where it has one."""
    if numbers is None:
        return texts
    if None not in numbers:
        return list(map("N%s %s".__mod__, zip(numbers, texts)))
    return [
        text if n is None else "N%s %s" % (n, text) for n, text in zip(numbers, texts)
    ]


def _with_planes(planes, lines, numbers, texts: List[str]):
    """A batch's lines and blocks (after each row's N, given ``numbers``),
    each row ``planes`` names after a line of its own, G17, as a block of
    SELECT_PLANE and its arc is written (the plane restated: no other
    change)."""
    if not planes:
        return lines, _numbered(numbers, texts)
    # each row once, or twice (its G17 first), in one pass
    times = [1] * len(texts)
    for row in planes:
        times[row] = 2
    lines = list(chain.from_iterable(map(repeat, lines, times)))
    texts = list(chain.from_iterable(map(repeat, texts, times)))
    for at in range(len(planes)):  # (row k now at k plus the G17 lines before)
        texts[planes[at] + at] = PLANE_CODES["XY"]
    if numbers is not None:
        numbers = list(chain.from_iterable(map(repeat, numbers, times)))
    return lines, _numbered(numbers, texts)


def _stand_in_numbers(numbers: List[Optional[str]]) -> bool:
    """Whether each hole's N can fill the N stand-in's place: every hole
    has one, none longer (a line's length decides where its comment goes)."""
    return None not in numbers and max(map(len, numbers)) <= len(_STAND_IN_N)


def _level_index(text: str) -> int:
    """Which level a stand-in's text stands for."""
    return int(float(text) - _LEVEL_STAND_IN)


#: Stand-ins for a hole's two coordinates, the hole before's, and its line,
#: while FlattenCanon._hole_template makes a hole's text: numbers no two of
#: whose texts hold one another.
_STAND_INS = (7777777.015625, 6666666.046875, 5555555.078125, 4444444.109375)
_STAND_IN_LINE = 987654321987
#: and for its N number, where each hole has its own (the template's prefix)
_STAND_IN_N = "765432198765"
_N_PREFIX = "N%s " % _STAND_IN_N
_STAND_IN_TEXTS = tuple(map(repr, _STAND_INS)) + ("%d" % _STAND_IN_LINE, _STAND_IN_N)
# (digits and a point: only the point is special in a pattern)
_STAND_IN_SPLIT = Pattern(
    "(%s)" % "|".join(text.replace(".", r"\.") for text in _STAND_IN_TEXTS)
)

#: Stand-ins for the levels of a hole's moves (the hole axis' values, in the
#: order they first come) while a template for every batch of holes drilled
#: alike is made (FlattenCanon._batch_template): numbers of one width, so no
#: text of one holds another's, and none of the hole stand-ins' width.
_LEVEL_STAND_IN = 3000000.0078125
_LEVEL_TEXT = Pattern(r"(?<![\d.])(3\d{6}\.0078125)(?!\d)")
_LEVEL_WIDTH = len(repr(_LEVEL_STAND_IN))
#: How much longer than a stand-in a level's number may be: the template's
#: lines keep that much more room (a line holds one level at most).
_LEVEL_ROOM = 30
#: Level-free templates kept at most (a file of endless kinds of holes makes
#: the rest batch by batch).
_MOST_TEMPLATES = 4096
#: Levels a hole may have at most for its template to be made level-free
#: (a deep peck cycle has two a peck): more go batch by batch.
_MOST_LEVELS = 999999


#: The straight moves, and the code :meth:`FlattenCanon._move` writes each with.
_PLAIN_MOVES = {"straight_feed": "G1", "straight_traverse": "G0"}


class _Group:
    """The calls of one executed block, and where it came from."""

    __slots__ = ("n", "where", "start", "calls", "compensated")

    def __init__(self, n, where, start, compensated=False):
        self.n = n
        self.where = where
        self.start = start
        self.calls: List[Tuple[str, tuple]] = []
        #: cutter compensation was on: moves do not start at the start
        self.compensated = compensated


class FlattenCanon(Canon):
    """Collects canonical calls block by block and writes them as G-code.

    ``machine`` must be set before the program runs (it gives each block's
    start point and source line).
    """

    def __init__(self, main_file: str = "") -> None:
        self.machine = None
        self.main_file = main_file
        #: the flat program's lines; an item may hold several (a hole's, made
        #: from one template), joined by newlines as text() joins them all
        self.lines: List[str] = []
        self.started = False
        self.ended = False
        self.finished = False
        self._group: Optional[_Group] = None
        #: _where's last walk of the stack, and the generated frame it was
        #: made in, or the run of rows and call (_generated_frames)
        self._frames_key = None
        self._rows_key = None
        self._frames: list = []
        #: _where_format's last answer, and the frames it was made of
        self._where_frames: Optional[list] = None
        self._where_text = ""
        self._stored = {}  # coordinate system -> (offsets, rotation, inches)
        self._system = 1
        self._startup = (0.0,) * 6
        self._inches = False
        self._plane = "XY"
        self._ijk_absolute = False
        self._params: Optional[List[float]] = None
        self._params_bytes = b""
        #: a batch of moves was written since the last block: parameters
        #: set after it are written before the next block
        self._after_batch = False
        #: the pitch while spindle and feed are synchronized (G33, G76)
        self._pitch: Optional[float] = None
        #: the last tool length offset written (program units)
        self._tool_offset = [0.0] * 9
        #: the flat program's current point as far as moves tell it; UNKNOWN
        #: after an offset, unit or tool-offset change until the next move
        self._pos = [UNKNOWN] * 6
        #: _batch_template's templates of holes, whatever their levels
        self._level_free: dict = {}

    # --- bookkeeping ---------------------------------------------------
    def set_block_number(self, n) -> None:
        self._flush()
        if self._after_batch:
            self._after_batch = False
            self.lines.extend(self._parameter_changes())
        if self.started and self._params is None:
            # what the program starts with: parameters, and the start point
            # (the same for the flat program, run with the same options)
            self._parameter_changes()
            self._pos = [float(v) for v in self.machine.current[:6]]
        if not self.started or self.ended:
            return
        machine = self.machine
        self._group = _Group(
            n, self._where(), list(machine.current[:6]), bool(machine.cutter_comp)
        )

    def _generated_frames(self) -> list:
        """g_code_frames_of_stack(), as far as its users read it: the file of
        the innermost generated frame and the calls that led there (not the
        line: each block's is the machine's). Those are the same while that
        frame is alive, whatever line it runs, so the stack is walked whole
        once a frame; and the same while one run of data rows runs in one
        call (``machine.rows_run``, the call's level and named locals, a
        store of each call's own): its rows' blocks need no walk at all."""
        machine = self.machine
        run = machine.rows_run
        if run is not None:
            key = run, machine.call_level, machine.locals
            if key != self._rows_key:
                self._rows_key, self._frames_key = key, None
                # (the rows' own frame found too: its file is theirs)
                self._frames = g_code_frames_of_stack(machine.line)
            return self._frames
        frame = sys._getframe(1)
        while frame is not None and "__ngc__" not in frame.f_globals:
            frame = frame.f_back
        if frame is None or frame is not self._frames_key:
            self._frames_key, self._frames = frame, g_code_frames_of_stack()
        return self._frames

    def _where(self) -> str:
        """Where the block that begins comes from: its file and line, and
        the calls that led there (:meth:`_where_format` of its line)."""
        return self._where_format() % self.machine.line

    def _record(self, name: str, args: tuple) -> None:
        if name == "on_reset":
            # the first one ends rs274's start-up; the last ones its closing
            self.started = True
            return
        if not self.started:
            # rs274's start-up: what the flat program starts with as well
            if name == "set_g5x_offset":
                self._system, self._startup = args[0], tuple(args[1:7])
            elif name == "set_xy_rotation":
                self._stored[self._system] = (self._startup, args[0], False)
            return
        if self.ended:
            return
        if self._group is None:
            self._group = _Group(None, "", list(self.machine.current[:6]))
        self._group.calls.append((name, args))
        if name == "program_end":
            self._flush()
            self.ended = True
        elif name == "finish":
            self._flush()
            self.ended = self.finished = True

    def close(self) -> None:
        self._flush()

    #: straight_moves takes numbered rows' N (runtime.canon.Canon)
    takes_numbers = True
    #: arc batches take restated G17 rows, written G17 then the arc
    #: (runtime.canon.Canon.takes_planes)
    takes_planes = True

    def straight_moves(self, feed, lines, x, y, z, a, b, c, u, v, w, numbers=None):
        """A run of plain moves, each a block of its own (runtime.fast.rows'
        batches: no F, nothing else on the line; ``numbers``: each row's N,
        where the rows have one), written a column at a time: the axis
        words that change, as :meth:`_move` writes them."""
        if self._pitch is not None or not self.started or self.ended:
            columns = (x, y, z, a, b, c, u, v, w)
            return super().straight_moves(feed, lines, *columns, numbers=numbers)
        texts = self._straight_texts(feed, x, y, z, a, b, c)
        self._write_batch(lines, _numbered(numbers, texts))

    def _straight_texts(self, feed, x, y, z, a, b, c) -> List[str]:
        """The blocks of a run of plain moves (straight_moves)."""
        self._flush()
        count = len(x)
        pos = self._pos
        if count == 1:  # (a row between arcs, say): as _move writes one
            move = (x[0], y[0], z[0], a[0], b[0], c[0])
            return [self._move("G1" if feed else "G0", move, pos)]
        # a column of words for each axis that moves: an axis moving on
        # every row (a CAM file's X and Y) is written a column at a time
        words, gaps = [], False
        for k, column in enumerate((x, y, z, a, b, c)):
            bits = array("d", column)
            # not same(): the bits differ (a zero's sign counts too)
            if bits.tobytes() == array("d", (pos[k],)).tobytes() * count:
                continue  # (an axis the run leaves alone: one look)
            previous = [pos[k]] + column[:-1]
            moved = list(map(ne, memoryview(bits).cast("B").cast("Q"), _bits(previous)))
            pos[k] = column[-1]
            letter = AXES6[k]
            if all(moved):
                words.append(_words(letter, column))
            elif any(moved):
                changed = [i for i, differs in enumerate(moved) if differs]
                texts = _words(letter, [column[i] for i in changed])
                some = [""] * count
                for i, text in zip(changed, texts):
                    some[i] = text
                words.append(some)
                gaps = True
        code = "G1 " if feed else "G0 "
        if words and not gaps:
            words[0] = list(map(code.__add__, words[0]))
            return list(map(" ".join, zip(*words)))
        rows = [" ".join(filter(None, row)) for row in zip(*words)] or [""] * count
        # (a move to where it is: still one axis word)
        return [code + (row or "X" + number(x[i])) for i, row in enumerate(rows)]

    def arc_moves(self, lines, *columns, numbers=None, planes=None):
        """A run of plain arcs (arc_feed's arguments as columns), each a
        block of its own, written as :meth:`_arc` writes one (after its N,
        given ``numbers``; after G17, for the rows ``planes`` names)."""
        if self._pitch is not None or not self.started or self.ended:
            return super().arc_moves(lines, *columns, numbers=numbers, planes=planes)
        self._flush()
        pos = self._pos
        # Only the first arc can start away from the last move's end.
        self._check_arc_start(self.machine.current, pos)
        texts = self._arc_texts(columns, pos)
        self._write_batch(*_with_planes(planes, lines, numbers, texts))

    def contour_moves(self, axes, lines, *columns, numbers=None, planes=None):
        """A contour (runtime.canon.Canon.contour_moves): its arcs written
        as :meth:`arc_moves` writes them, the G1 lines between them as
        :meth:`straight_moves` writes one, in one batch."""
        if self._pitch is not None or not self.started or self.ended:
            return super().contour_moves(
                axes, lines, *columns, numbers=numbers, planes=planes
            )
        self._flush()
        pos = self._pos
        if columns[4][0]:  # (only the first arc can start away from the last end)
            self._check_arc_start(self.machine.current, pos)
        texts = self._contour_texts(axes, columns, pos)
        if texts is None:
            texts = self._contour_pieces(axes, columns, pos)
        self._write_batch(*_with_planes(planes, lines, numbers, texts))

    def _contour_pieces(self, axes, columns, pos: List[float]) -> List[str]:
        """A contour's text where :meth:`_contour_texts` steps aside: cut
        at the arcs _arc treats apart (:meth:`_apart`), each written alone
        (:meth:`_contour_runs`), the pieces between them in one go as
        before. (One such arc in thousands, a centre no offset gives
        exactly, had made a whole contour go a row at a time.)"""
        rotation = columns[4]
        count = len(rotation)
        f, s, _ = axes
        arcs = [i for i, turns in enumerate(rotation) if turns]
        if ARC_AXES.get(self._plane) is None or not arcs:
            return self._contour_runs(axes, columns, pos)
        first_end, second_end = columns[0], columns[1]
        starts = ([pos[f]] + first_end[:-1], [pos[s]] + second_end[:-1])
        pick = itemgetter(*arcs) if len(arcs) > 1 else lambda column: (column[arcs[0]],)
        apart = self._apart(
            [list(pick(column)) for column in columns[:4]],
            [list(pick(column)) for column in starts],
        )
        cuts = [row for row, alone in zip(arcs, apart) if alone]
        texts: List[str] = []
        at = 0
        for row in cuts + [count]:
            if at < row:
                piece = [column[at:row] for column in columns]
                made = self._contour_texts(axes, piece, pos)
                texts += self._contour_runs(axes, piece, pos) if made is None else made
            if row < count:
                piece = [column[row : row + 1] for column in columns]
                texts += self._contour_runs(axes, piece, pos)
            at = row + 1
        return texts

    def _contour_runs(self, axes, columns, pos: List[float]) -> List[str]:
        """A contour's text a run of arcs at a time (:meth:`_arc_texts`)
        and a line at a time (:meth:`_move`): where :meth:`_contour_texts`
        steps aside."""
        rotation = columns[4]
        f, s, n = axes
        texts = []
        count, at = len(rotation), 0
        while at < count:
            if rotation[at]:  # a run of arcs, to the next line or the end
                stop = at + 1
                while stop < count and rotation[stop]:
                    stop += 1
                run = [column[at:stop] for column in columns]
                texts += self._arc_texts(run, pos)
                at = stop
                continue
            e1, e2, _, _, _, en, a, b, c = (column[at] for column in columns[:9])
            move = [0.0, 0.0, 0.0, a, b, c]
            move[f], move[s], move[n] = e1, e2, en
            texts.append(self._move("G1", move, pos))
            at += 1
        return texts

    def hole_moves(self, recording, lines, first, second, axes, start, numbers=None):
        """Holes drilled alike (runtime.canon.Canon.hole_moves): each hole a
        block of its own, its calls written as :meth:`_flush` writes them,
        without recording them call by call (from templates: see below).
        Holes whose calls include one not in _HOLE_CALLS go call by call.
        ``numbers``: each hole's N (a slot of the template, the N stand-in's),
        where the rows have their own."""
        names = [name for name, _, _ in recording]
        if numbers is not None and numbers.count(None) == len(numbers):
            numbers, recording = (
                None,
                [("set_block_number", (None,), None)] + recording[1:],
            )
        if (
            self._pitch is not None
            or not self.started
            or self.ended
            or names[0] != "set_block_number"
            or not set(names[1:]) <= _HOLE_CALLS
            or (numbers is not None and not _stand_in_numbers(numbers))
        ):
            # call by call, each hole's block at its own line
            args = (recording, lines, first, second, axes, start, numbers)
            hole_by_hole(self, self.machine, *args)
            return
        # (the block before, written)
        self.set_block_number(recording[0][1][0] if numbers is None else numbers[0])
        group, self._group = self._group, None
        prefix = "N%s " % group.n if group.n is not None else ""
        if numbers is not None:  # (the template's N: each hole's own)
            prefix = _N_PREFIX

        def prefixed(j: int) -> str:
            """Hole j's own prefix, where it is written apart."""
            return prefix if numbers is None else "N%s " % numbers[j]

        where = "  ; " + self._where_format()
        ia, ib = axes
        pos = self._pos
        # A hole's text differs from the one before's only by its two
        # coordinates and its line, and by whether each coordinate moved at
        # all (a move writes the axes that changed): one template for each
        # of those four cases (_hole_template), filled in for every hole.
        # The first starts where the recorded hole left the tool; if the
        # flat program's point is not known to be there, it is written as
        # _flush writes a block, and the template starts after it.
        first_texts, second_texts = _numbers(first), _numbers(second)
        firsts, seconds = _bits([start[0]] + first), _bits([start[1]] + second)
        begin = 0
        if not (same(pos[ia], start[0]) and same(pos[ib], start[1])):
            here = (first[0], second[0])
            calls = _hole_calls(recording, axes, here, start)
            self._write_block(self._texts(group, calls), prefixed(0), where % lines[0])
            begin = 1
        columns = (
            first_texts,
            second_texts,
            _numbers(start[:1]) + first_texts,
            _numbers(start[1:2]) + second_texts,
            lines,
            numbers,
        )
        cases = groupby(
            zip(map(eq, firsts[1:], firsts[:-1]), map(eq, seconds[1:], seconds[:-1]))
        )
        templates: dict = {}
        free = False  # (the hole's levels taken out, once a batch: _free_levels)
        texts: List[str] = []
        k = 0
        for case, run in cases:
            stop = k + len(list(run))
            at, k = max(k, begin), stop
            if at >= stop:
                continue
            made = templates.get(case)
            if made is None:
                if free is False:
                    free = _free_levels(recording, axes, pos)
                made = templates[case] = self._batch_template(
                    group, recording, axes, case, prefix, where, free
                )
            if made is False:  # (a template not to be trusted: hole by hole)
                if texts:
                    self.lines += texts
                    texts = []
                for j in range(at, stop):
                    before = start if j == 0 else (first[j - 1], second[j - 1])
                    calls = _hole_calls(recording, axes, (first[j], second[j]), before)
                    self._write_block(
                        self._texts(group, calls), prefixed(j), where % lines[j]
                    )
                continue
            template, slots = made
            # the run's holes in one item of lines (text() joins them all)
            filled = trace_rows(template + "\n", [columns[j][at:stop] for j in slots])
            texts.append(filled[:-1])
        if texts:
            self.lines += texts
        pos[ia], pos[ib] = first[-1], second[-1]
        # (what the holes leave of parameters is written before the next block)
        self._after_batch = True

    def _batch_template(
        self, group, recording, axes, case, prefix: str, where: str, free
    ):
        """:meth:`_hole_template` for this batch, made from one that serves
        every batch of holes drilled alike whatever their levels (the hole
        axis' values of its moves, which differ from one series of holes to
        the next): that one has stand-ins for the levels, which each batch
        fills in. Which moves write the hole axis depends only on which
        levels are equal (to each other, and to where the flat program's
        tool is), so that is part of what the template is kept by. Made for
        this batch alone where the levels cannot be stood in for
        (``free``: what _free_levels tells of the batch's hole)."""
        if free is None:
            return self._hole_template(group, recording, axes, case, prefix, where)
        shape, texts, index, at_level = free
        key = (shape, case, prefix, where)
        made = self._level_free.get(key)
        if made is None:
            standing = _standing(recording, axes, index), _LEVEL_STAND_IN + at_level
            made = self._level_free_template(group, standing, axes, case, prefix, where)
            if len(self._level_free) < _MOST_TEMPLATES:  # (memory stays bounded)
                self._level_free[key] = made
        if made is False or max(map(len, texts)) > _LEVEL_WIDTH + _LEVEL_ROOM:
            # (a longer number could change where a long line's comment goes:
            # a line has a level at most, its move's)
            return self._hole_template(group, recording, axes, case, prefix, where)
        pieces, order, slots = made
        filled = [None] * (2 * len(order) + 1)
        filled[0::2] = pieces
        filled[1::2] = [texts[k] for k in order]
        return "".join(filled), slots

    def _level_free_template(self, group, standing, axes, case, prefix, where):
        """:meth:`_hole_template` of a hole whose levels are stand-ins
        (``standing``: the recording with them, and the hole axis' place
        before the hole), cut at each level: (the text between levels,
        which level each is, the slots), or False."""
        recording, here = standing
        # a stand-in's text must be the stand-in's alone: not in the comment,
        # the N word or another number of the hole (a number written as one
        # is the stand-in itself, or its negative: so is its repr)
        written = [where] if prefix == _N_PREFIX else [prefix, where]
        for _, args, at in recording:
            values = args if at is None else args[3:]
            written += [repr(value) for value in values if type(value) is float]
        if _LEVEL_TEXT.search(" ".join(written)):
            return False
        pos = self._pos
        level = 3 - sum(axes)
        saved = pos[level]
        pos[level] = here
        try:
            made = self._hole_template(
                group, recording, axes, case, prefix, where, 60 + _LEVEL_ROOM
            )
        finally:
            pos[level] = saved
        if made is False:
            return False
        template, slots = made
        pieces = _LEVEL_TEXT.split(template)
        order = [_level_index(text) for text in pieces[1::2]]
        return pieces[0::2], order, slots

    def _hole_template(
        self, group, recording, axes, case, prefix: str, where: str, room: int = 60
    ):
        """The lines of a hole of a batch as one %-template, and its slots'
        values (0, 1: the hole's coordinates as text; 2, 3: the hole
        before's; 4: the hole's line; 5: its N, with the N stand-in's
        ``prefix``), for ``case``: whether each coordinate
        is the one before. Made by :meth:`_texts` on stand-in values
        (_STAND_INS), from where the hole before left the tool; False where a
        stand-in's text is met elsewhere (in an argument, the comment) or a
        line is long enough that real numbers could change where its
        comment goes (_write_block)."""
        marks = _STAND_IN_TEXTS
        comment = where % _STAND_IN_LINE
        values = {value for _, args, _ in recording for value in args}
        written = [where] if prefix == _N_PREFIX else [prefix, where]
        written += [repr(value) for value in values if type(value) is float]
        if _STAND_IN_SPLIT.search(" ".join(written)):
            return False
        ia, ib = axes
        pos = self._pos
        saved = pos[:]
        before = _STAND_INS[2:]
        here = tuple(b if kept else h for kept, b, h in zip(case, before, _STAND_INS))
        pos[ia], pos[ib] = before
        try:
            texts = self._texts(group, _hole_calls(recording, axes, here, before))
        finally:
            pos[:] = saved
        if any(len(prefix + text + comment) > MAX_LINE - room for text in texts):
            return False
        pieces = _STAND_IN_SPLIT.split(
            "\n".join(prefix + text + comment for text in texts).replace("%", "%%")
        )
        # the text between stand-ins, and which value each stand-in is (the
        # line, an int, as %d: runtime.canon.trace_rows' quick conversions)
        slots = tuple(marks.index(m) for m in pieces[1::2])
        conversions = ["%d" if slot == 4 else "%s" for slot in slots] + [""]
        return "".join(map(add, pieces[0::2], conversions)), slots

    def _where_format(self) -> str:
        """Where the current data rows come from (:meth:`_where`), as a
        format of a row's line: its file and the calls that led there."""
        frames = self._generated_frames()
        if frames is self._where_frames:  # (the same rows' run as last time)
            return self._where_text
        file = frames[-1].file if frames else self.main_file
        callers = " <- ".join("%s:%d" % (f.file, f.line) for f in reversed(frames[:-1]))
        tail = " <- " + callers if callers else ""
        self._where_frames = frames
        self._where_text = "%s:%%d%s" % (
            file.replace("%", "%%"),
            tail.replace("%", "%%"),
        )
        return self._where_text

    def _write_batch(self, lines, texts: List[str]) -> None:
        """A batch's blocks, each with its source comment (the batch's rows
        share a file and a call stack)."""
        out = self.lines
        where = "  ; " + self._where_format()
        # (the longest comment is the one of the line of most digits)
        if texts and max(map(len, texts)) + len(where % max(lines)) <= MAX_LINE:
            # one C format for the batch, one item of lines (text() joins them)
            out.append(trace_rows("%s" + where + "\n", [texts, lines])[:-1])
            self._after_batch = True
            return
        comments = list(map(where.__mod__, lines))
        for text, comment in zip(texts, comments):
            if len(text) + len(comment) > MAX_LINE:
                out.append(comment.strip())
                out.append(text)
            else:
                out.append(text + comment)
        self._after_batch = True

    # --- writing -------------------------------------------------------
    def _flush(self) -> None:
        """The G-code lines of the group of calls of the block that ended."""
        group, self._group = self._group, None
        if group is None or not group.calls:
            return
        calls = group.calls
        if len(calls) == 1 and calls[0][0] in _PLAIN_MOVES and self._pitch is None:
            # a line of one straight move (a loop's): what _texts writes for
            # it, without its cursor
            name, args = calls[0]
            out = [self._move(_PLAIN_MOVES[name], args, self._pos)]
        else:
            if calls[-1][0] == "program_end":
                keep = len(calls) - 1
                while keep > 0 and calls[keep - 1][0] in END_RESETS:
                    keep -= 1
                shuttle = any(name == "pallet_shuttle" for name, _ in calls[keep:])
                calls = calls[:keep] + [("program_end", (shuttle,))]
            out = self._texts(group, calls)
        if calls[-1][0] != "program_end":
            # changed by this block or by assignments after it (the flush
            # runs as the next block starts)
            out.extend(self._parameter_changes())
        prefix = "N%s " % group.n if group.n is not None else ""
        self._write_block(out, prefix, "  ; " + group.where if group.where else "")

    def _write_block(self, texts: List[str], prefix: str, comment: str) -> None:
        """A block's lines: each with the N ``prefix`` and the source
        ``comment``, which goes on a line of its own before a long one."""
        for text in texts:
            if len(prefix + text + comment) > MAX_LINE and comment:
                self.lines.append(comment.strip())
                self.lines.append(prefix + text)
            else:
                self.lines.append(prefix + text + comment)

    def _texts(self, group: "_Group", calls: List[tuple]) -> List[str]:
        """The G-code of ``calls``: one line a call, or one for several
        (_WRITERS: what writes each call that is not written alone)."""
        pos = self._pos
        at = _Cursor(calls, group, pos)
        pending_f: Optional[str] = None
        out: List[str] = []
        i = 0
        while i < len(calls):
            if i in at.taken:
                i += 1
                continue
            name, args = calls[i]
            if name in _PLAIN_MOVES and pending_f is None and self._pitch is None:
                # a straight move (a hole's every move): what its writer
                # writes, without the cursor's look at the calls around it
                # (G33's passes, which a writer may begin in this loop, not)
                out.append(self._move(_PLAIN_MOVES[name], args, pos))
                i += 1
                continue
            if name in _SPINDLE_ALONE:
                self._check_spindle(name, args[0])
            at.i = i
            at.nxt = nxt = calls[i + 1][0] if i + 1 < len(calls) else None
            if name == "set_feed_rate" and nxt in ("straight_feed", "arc_feed"):
                pending_f = "F" + number(args[0])  # on the move's line
                i += 1
                continue
            # G20/G21 that changes nothing leaves the current point alone
            same_units = name == "use_length_units" and bool(args[0]) == self._inches
            writer = _WRITERS.get(name)
            if writer is None:
                text, used = self._single(name, args), 1
            else:
                text, used = writer(self, at, args)
            if not same_units and (
                name in MOVES_ORIGIN
                if used == 1
                else any(c[0] in MOVES_ORIGIN for c in calls[i : i + used])
            ):
                pos[:] = [UNKNOWN] * 6
            if text is not None:
                if pending_f is not None:
                    text = pending_f + " " + text
                    pending_f = None
                out.extend(text.split("\n"))
            i += used
        if pending_f is not None:
            out.append(pending_f)
        return out

    # --- calls written with others, or not as _single writes them ------
    # Each takes the cursor and the call's arguments and returns (the
    # text or None, how many calls it wrote).
    def _w_traverse(self, at: "_Cursor", args) -> Tuple[Optional[str], int]:
        return self._move("G0", args, at.pos), 1

    def _w_feed(self, at: "_Cursor", args) -> Tuple[Optional[str], int]:
        if self._pitch is not None:
            # inside START/STOP_SPEED_FEED_SYNCH (G33, G76 passes)
            return self._move("G33", args, at.pos) + " K" + number(self._pitch), 1
        return self._move("G1", args, at.pos), 1

    def _w_synch_start(self, at: "_Cursor", args) -> Tuple[Optional[str], int]:
        # each G33/G33.1 line makes its own START/STOP pair
        self._pitch = args[1]
        return None, 1

    def _w_synch_stop(self, at: "_Cursor", args) -> Tuple[Optional[str], int]:
        self._pitch = None
        return None, 1

    def _w_rigid_tap(self, at: "_Cursor", args) -> Tuple[Optional[str], int]:
        x, y, z, scale = args
        text = "G33.1 X%s Y%s Z%s K%s" % (
            number(x),
            number(y),
            number(z),
            number(self._pitch or 0.0),
        )
        if scale != 1:
            text += " I" + number(scale)
        at.pos[:] = [UNKNOWN] * 6  # the tool comes back where it was
        return text, 1

    def _w_probe(self, at: "_Cursor", args) -> Tuple[Optional[str], int]:
        if _names(at.calls, at.i + 1, 2) != ["straight_probe", "turn_probe_off"]:
            return self._single("turn_probe_on", args), 1
        probe = at.calls[at.i + 1][1]
        text = self._move("G38.%d" % (2 + probe[9]), probe[:6], at.pos)
        at.pos[:] = [UNKNOWN] * 6  # it stops where the probe trips
        return text, 3

    def _w_nurbs(self, at: "_Cursor", args) -> Tuple[Optional[str], int]:
        text = self._nurbs(*args)
        at.pos[:] = [UNKNOWN] * 6  # see runtime/splines.py: rs274 reads past its list
        return text, 1

    def _w_tool_entry(self, at: "_Cursor", args) -> Tuple[Optional[str], int]:
        text = self._tool_entry(args)
        if at.nxt == "set_tool_table_entry" and at.calls[at.i + 1][1][0] == 0:
            return text, 2  # the loaded tool's copy: the G10 L1 makes it too
        return text, 1

    def _w_arc(self, at: "_Cursor", args) -> Tuple[Optional[str], int]:
        group = at.group
        first = not any(c[0] in MOTION_CALLS for c in at.calls[: at.i])
        if first and not (group.compensated or self.machine.cutter_comp):
            self._check_arc_start(group.start, at.pos)
        return self._arc(args, at.pos), 1

    def _w_g5x(self, at: "_Cursor", args) -> Tuple[Optional[str], int]:
        return self._g5x(args, at.calls[at.i + 1 : at.i + 3])

    def _w_rotation(self, at: "_Cursor", args) -> Tuple[Optional[str], int]:
        stored = self._stored.get(self._system)
        offsets = stored[0] if stored else (0.0,) * 6
        return self._g10(self._system, offsets, args[0]), 1

    def _w_comment(self, at: "_Cursor", args) -> Tuple[Optional[str], int]:
        if args[0] not in FEED_MODE_COMMENTS or at.nxt != "set_feed_mode":
            return self._single("comment", args), 1
        text = FEED_MODE_COMMENTS[args[0]]
        # G94's own SET_FEED_RATE(0) is made again by the written G94; any
        # other rate (a G93 move's, queued behind cutter compensation) is
        # written as F
        calls, i = at.calls, at.i
        zero = _names(calls, i + 2, 1) == ["set_feed_rate"] and calls[i + 2][1][0] == 0
        return text, 3 if text == "G94" and zero else 2

    def _w_control_mode(self, at: "_Cursor", args) -> Tuple[Optional[str], int]:
        mode, tolerance = args
        if mode != "CONTINUOUS":
            return ("G61" if mode == "EXACT_PATH" else "G61.1"), 1
        text = "G64 P" + number(tolerance)
        if at.nxt == "set_naivecam_tolerance":
            return text + " Q" + number(at.calls[at.i + 1][1][0]), 2
        return text, 1

    def _w_start_change(self, at: "_Cursor", args) -> Tuple[Optional[str], int]:
        following = _names(at.calls, at.i + 1)
        if "change_tool" not in following:
            return self._single("start_change", args), 1
        # M6 makes everything up to CHANGE_TOOL (spindle stop, the ini's
        # tool-change moves) itself
        return "M6", 2 + following.index("change_tool")

    def _w_pair(self, at: "_Cursor", args) -> Tuple[Optional[str], int]:
        name = at.calls[at.i][0]
        pair = _PAIRS.get((name, at.nxt))
        if pair:
            return pair, 2
        return self._single(name, args), 1

    def _w_orient(self, at: "_Cursor", args) -> Tuple[Optional[str], int]:
        # M19 (or G87's orientation): R is the angle before the INI's
        # ORIENT_OFFSET is added
        _spindle, orientation, direction = args
        angle = orientation - self.machine.settings.orient_offset
        # G87 orients with rs274's spindle direction (2 clockwise, 3
        # counterclockwise); M19 takes P0-P2 only, so 3 is written as P2:
        # the one call that differs, never a move
        text = "M19 R%s P%d" % (number(angle), min(direction, 2))
        if at.nxt == "wait_spindle_orient_complete":
            return text + " Q" + number(at.calls[at.i + 1][1][1]), 2
        return text, 1

    def _w_orient_wait(self, at: "_Cursor", args) -> Tuple[Optional[str], int]:
        return "M19 Q" + number(args[1]), 1  # M19 Q without R or P

    def _w_spindle_mode(self, at: "_Cursor", args) -> Tuple[Optional[str], int]:
        if args[1] == 0:
            return self._single("set_spindle_mode", args), 1
        # G96: the mode's value is D (1e30 when not given); rs274 wants its
        # S on the same line, wherever the call came
        text = "G96" + (" D" + number(args[1]) if args[1] < 1e29 else "")
        following = _names(at.calls, at.i + 1)
        if "set_spindle_speed" in following:
            speed = following.index("set_spindle_speed")
            if "set_spindle_mode" not in following[:speed]:
                text += " S" + number(at.calls[at.i + 1 + speed][1][1])
                at.taken.add(at.i + 1 + speed)
        return text, 1

    def _w_shuttle(self, at: "_Cursor", args) -> Tuple[Optional[str], int]:
        if at.nxt == "program_stop":
            return "M60", 2
        return self._single("pallet_shuttle", args), 1

    def _parameter_changes(self) -> List[str]:
        """Assignments for the parameters G-codes read (G28/G30 homes, G92
        and coordinate-system offsets) that changed since the last look:
        they have no canonical call, but later codes read them.

        Called after every block, so the common case (nothing changed) is
        one comparison of the range's bytes with the last look's (bytes, so
        that -0.0 against 0.0 and NaNs count as changes, as :func:`same`
        has them); only a changed range is compared number by number."""
        values = self.machine.params.values
        first, stop = CODE_PARAMETERS.start, CODE_PARAMETERS.stop
        look = float_bits(values, first, stop)
        if self._params is None:
            self._params = list(values[first:stop])
            self._params_bytes = look
            return []
        if look == self._params_bytes:
            return []
        self._params_bytes = look
        changes = []
        known = self._params
        for k, value in enumerate(values[first:stop]):
            if not same(value, known[k]):
                known[k] = value
                changes.append("#%d = %s" % (first + k, number(value)))
        return changes

    def _move(self, code: str, args: Sequence[float], pos: List[float]) -> str:
        """A straight move's line: ``code``, then the axes that changed
        from ``pos`` (which it then holds); in C where it is built (every
        move of a line of its own: a hole's way in, a shop's single moves)."""
        if _fast_move is not None:
            text = _fast_move(code, args, pos)
            if text is not None:
                return text
        return self._python_move(code, args, pos)

    def _python_move(self, code: str, args: Sequence[float], pos: List[float]) -> str:
        """:meth:`_move` in Python (runtime._fast_format.move_text's twin)."""
        words = []
        for k in range(6):
            value, was = args[k], pos[k]
            # same(value, was), written out (this runs for every move); the
            # axes a move leaves alone hold the very same float object
            if value is was or (value == was and (value or _same_zero(value, was))):
                continue
            words.append(AXES6[k] + number(value))
        pos[:6] = args[:6]
        if not words:  # a move to where it is: still one axis word
            words.append("X" + number(args[0]))
        return code + " " + " ".join(words)

    def _check_arc_start(self, start: Sequence[float], pos: Sequence[float]) -> None:
        """rs274 starts an arc at its interpreter's current point. After a
        canned cycle in the XZ or YZ plane that is not where the cycle's
        last move ended, and no plain G-code puts it there."""
        for interp, flat in zip(start[:3], pos[:3]):
            if not math.isnan(flat) and abs(interp - flat) > 1e-6 * max(1.0, abs(flat)):
                raise FlattenError(
                    "flatten: an arc starts where rs274's interpreter left the tool, "
                    "not where the last move ended (as after a canned cycle in the XZ "
                    "or YZ plane): plain G-code cannot start it there"
                )

    def _contour_texts(self, axes, columns, pos: List[float]) -> Optional[List[str]]:
        """A contour's text with all its arcs written in one go
        (:meth:`_arc_words`, each arc starting where the row before ended),
        its lines as :meth:`_move` writes them; None (nothing written) where
        an arc is one _arc treats apart, or the axes are not the plane's."""
        plane = ARC_AXES.get(self._plane)
        index = _AXIS_INDEX
        if plane is None or tuple(axes) != tuple(index[letter] for letter in plane[:3]):
            return None
        f, s, n = axes
        rotation = columns[4]
        arcs = [i for i, turns in enumerate(rotation) if turns]
        if not arcs:
            return None
        # where each row starts: where the row before ended
        befores = [
            [pos[axis]] + columns[k][:-1] for k, axis in ((0, f), (1, s), (5, n))
        ]
        befores += [[pos[3 + k]] + columns[6 + k][:-1] for k in range(3)]
        pick = itemgetter(*arcs) if len(arcs) > 1 else lambda column: (column[arcs[0]],)
        texts: List[Optional[str]] = [None] * len(rotation)
        made = self._arc_words(
            [list(pick(column)) for column in columns[:9]],
            [list(pick(befores[0])), list(pick(befores[1]))],
            [list(pick(column)) for column in befores[3:]],
        )
        if made is None:
            return None
        for i, text in zip(arcs, made):
            texts[i] = text
        moves = [i for i, turns in enumerate(rotation) if not turns]
        if moves:
            # G1 lines, from where the row before ended: the axis words that
            # change, a column at a time, as _move writes them
            pick = itemgetter(*moves) if len(moves) > 1 else lambda c: (c[moves[0]],)
            ends = [columns[0], columns[1], columns[5], *columns[6:9]]
            order = (f, s, n, 3, 4, 5)  # (the axis of each of ends and befores)
            words = []
            for k in sorted(range(6), key=order.__getitem__):
                now, was = list(pick(ends[k])), list(pick(befores[k]))
                moved = list(map(ne, _bits(now), _bits(was)))
                if any(moved):
                    column = [""] * len(moves)
                    changed = [j for j, differs in enumerate(moved) if differs]
                    letter = AXES6[order[k]]
                    for j, text in zip(
                        changed, _words(letter, [now[j] for j in changed])
                    ):
                        column[j] = text
                    words.append(column)
            rows = [" ".join(filter(None, row)) for row in zip(*words)]
            xs = pick(ends[order.index(0)])
            for j, i in enumerate(moves):
                # (a move to where it is: still one axis word)
                row = rows[j] if rows else ""
                texts[i] = "G1 " + (row or "X" + number(xs[j]))
        pos[f], pos[s], pos[n] = columns[0][-1], columns[1][-1], columns[5][-1]
        pos[3:6] = [column[-1] for column in columns[6:9]]
        return texts

    def _arc_texts(self, columns, pos: List[float], cut: bool = True) -> List[str]:
        """:meth:`_arc` of each arc of a batch (arc_feed's arguments as
        columns), a column of numbers at a time: the very same text. Arcs
        _arc treats apart (no centre, a radius under the tolerance, a centre
        no relative offset gives exactly) go arc by arc, the batch ``cut``
        at them (else all of it arc by arc)."""
        plane = ARC_AXES.get(self._plane)
        first_end, second_end = columns[:2]
        if plane is not None and first_end:
            index = _AXIS_INDEX
            i1, i2 = index[plane[0]], index[plane[1]]
            starts = ([pos[i1]] + first_end[:-1], [pos[i2]] + second_end[:-1])
            befores = [[pos[3 + k]] + columns[6 + k][:-1] for k in range(3)]
            texts = self._arc_words(columns, starts, befores)
            if texts is not None:
                pos[i1], pos[i2] = first_end[-1], second_end[-1]
                pos[index[plane[2]]] = columns[5][-1]
                pos[3:6] = [column[-1] for column in columns[6:9]]
                return texts
            if cut:  # the arcs apart alone, the runs between them in one go
                apart = self._apart(columns[:4], starts)
                cuts = [k for k, alone in enumerate(apart) if alone]
                if cuts and len(cuts) < len(first_end):
                    texts, at = [], 0
                    for k in cuts + [len(first_end)]:
                        if at < k:
                            run = [column[at:k] for column in columns]
                            texts += self._arc_texts(run, pos, cut=False)
                        if k < len(first_end):
                            texts.append(self._arc(tuple(c[k] for c in columns), pos))
                        at = k + 1
                    return texts
        return [self._arc(args, pos) for args in zip(*columns)]

    def _apart(self, columns, starts) -> List[bool]:
        """Which of the arcs (ends and centres: arc_feed's first four
        columns) starting at ``starts`` :meth:`_arc_words` treats apart,
        an arc at a time (its checks of a whole batch, one by one)."""
        first_end, second_end, first_c, second_c = columns[:4]
        offsets1 = _short_offsets(starts[0], first_c)
        offsets2 = _short_offsets(starts[1], second_c)
        tolerance = RADIUS_TOLERANCE_INCH * (1.0 if self._inches else MM_PER_INCH)
        apart = []
        for s1, s2, o1, o2, e1, e2, c1, c2 in zip(
            *starts, offsets1, offsets2, first_end, second_end, first_c, second_c
        ):
            try:
                alone = (
                    s1 + o1 != c1
                    or s2 + o2 != c2
                    or c1 == 0.0
                    or c2 == 0.0
                    or hypot(o1, o2) < tolerance
                    or hypot(e1 - c1, e2 - c2) < tolerance
                )
            except TypeError:  # (no offset at all)
                alone = True
            apart.append(alone)
        return apart

    def _arc_words(self, columns, starts, befores) -> Optional[List[str]]:
        """The text of arcs (arc_feed's arguments as columns) that start at
        ``starts`` (columns of the plane's two axes) where the A, B and C
        axes were ``befores``, as :meth:`_arc` writes each; None where an arc
        is one _arc treats apart (no centre, a radius under the tolerance, a
        centre no relative offset gives exactly)."""
        first_end, second_end, first_c, second_c, rotation, axis_end = columns[:6]
        first, second, axis, first_letter, second_letter = ARC_AXES[self._plane]
        starts1, starts2 = starts
        offsets1 = _short_offsets(starts1, first_c)
        offsets2 = _short_offsets(starts2, second_c)
        tolerance = RADIUS_TOLERANCE_INCH * (1.0 if self._inches else MM_PER_INCH)
        if (
            # rs274 adds I/J/K to the start point: each offset must give back
            # the very centre (which also rules out NaN centres and -0.0)
            list(map(add, starts1, offsets1)) != first_c
            or list(map(add, starts2, offsets2)) != second_c
            or 0.0 in first_c
            or 0.0 in second_c
            or min(map(hypot, offsets1, offsets2)) < tolerance
            or min(
                map(hypot, map(sub, first_end, first_c), map(sub, second_end, second_c))
            )
            < tolerance
        ):
            return None
        words = [
            _words(first, first_end),
            _words(second, second_end),
            _words(axis, axis_end),
        ]
        gaps = False
        for k, letter in enumerate("ABC"):
            column, previous = columns[6 + k], befores[k]
            if array("d", column).tobytes() == array("d", previous).tobytes():
                continue  # (the usual case: the axis does not move)
            changed = [
                i
                for i, differs in enumerate(map(ne, _bits(column), _bits(previous)))
                if differs
            ]
            moved = [""] * len(column)
            for i, text in zip(changed, _words(letter, [column[i] for i in changed])):
                moved[i] = text
            words.append(moved)
            gaps = True
        words.append(_words(first_letter, offsets1))
        words.append(_words(second_letter, offsets2))
        codes = ["G3" if turns > 0 else "G2" for turns in rotation]
        if rotation.count(1) + rotation.count(-1) != len(rotation):
            words.append(
                ["" if abs(turns) == 1 else "P%d" % abs(turns) for turns in rotation]
            )
            gaps = True
        if self._ijk_absolute:
            codes[0], self._ijk_absolute = "G91.1 " + codes[0], False
        if gaps:
            return [
                " ".join([code] + [word for word in row if word])
                for code, row in zip(codes, zip(*words))
            ]
        return list(map(" ".join, zip(codes, *words)))

    def _arc(self, args: Sequence, pos: List[float]) -> str:
        first_end, second_end, first_c, second_c, rotation, axis_end = args[:6]
        plane = ARC_AXES.get(self._plane)
        if plane is None:
            raise FlattenError("flatten: arcs in the %s plane" % self._plane)
        first, second, axis, first_letter, second_letter = plane
        index = _AXIS_INDEX
        start = pos[index[first]], pos[index[second]]
        # rs274 refuses arcs of (almost) no radius in G-code, but cutter
        # compensation can make one (tool radius equal to the arc's)
        tolerance = RADIUS_TOLERANCE_INCH * (1.0 if self._inches else MM_PER_INCH)
        radii = (
            math.hypot(start[0] - first_c, start[1] - second_c),
            math.hypot(first_end - first_c, second_end - second_c),
        )
        # An R 0 arc whose end is within the tolerance of its start has a
        # centre that is not a number (rs274 divides 0 by 0): written as R0.
        no_centre = first_c != first_c
        if min(radii) < tolerance:
            raise FlattenError(
                "flatten: an arc of zero radius (cutter compensation makes one where "
                "the tool radius equals the arc's): rs274 refuses it written as G-code"
            )
        offsets = _offset(start[0], first_c), _offset(start[1], second_c)
        # rs274 adds I/J/K to the start point: relative centres only when
        # that gives back the very centre (known start, no rounding)
        exact = None not in offsets
        mode = ""
        if no_centre:
            pass
        elif exact and self._ijk_absolute:
            mode, self._ijk_absolute = "G91.1 ", False
        elif not exact and not self._ijk_absolute:
            mode, self._ijk_absolute = "G90.1 ", True
        centre = (first_c, second_c) if self._ijk_absolute else offsets
        code = mode + ("G3" if rotation > 0 else "G2")
        words = [
            first + number(first_end),
            second + number(second_end),
            axis + number(axis_end),
        ]
        for k, (letter, value) in enumerate(zip("ABC", args[6:9])):
            if not same(value, pos[3 + k]):
                words.append(letter + number(value))
        if no_centre:
            words.append("R0")
        else:
            words.append(first_letter + number(centre[0]))
            words.append(second_letter + number(centre[1]))
        if abs(rotation) != 1:
            words.append("P%d" % abs(rotation))
        pos[index[first]], pos[index[second]], pos[index[axis]] = (
            first_end,
            second_end,
            axis_end,
        )
        pos[3:6] = list(args[6:9])
        return code + " " + " ".join(words)

    def _nurbs(self, points, order) -> str:
        """A NURBS_FEED (G5, G5.1, G5.2) as G5.2 control points and G5.3.
        The first point is the current point: only its weight is written."""
        first_weight = points[0][2]
        lines = []
        rest = points[1:]
        if first_weight != 1.0 or not rest:
            lines.append("G5.2 P%s L%d" % (number(first_weight), order))
        else:
            x, y, w = rest[0]
            lines.append(
                "G5.2 X%s Y%s P%s L%d" % (number(x), number(y), number(w), order)
            )
            rest = rest[1:]
        lines += ["X%s Y%s P%s" % (number(x), number(y), number(w)) for x, y, w in rest]
        lines.append("G5.3")
        return "\n".join(lines)

    def _tool_entry(self, args) -> str:
        """SET_TOOL_TABLE_ENTRY as a G10 L1 with every value literal. The
        entry holds user units; G10 L1 reads program units. rs274 -g knows
        no U V W words: those columns can only come from the tool table."""
        _index, tool, offsets, diameter, front, back, orientation = args
        machine = self.machine
        values = machine._user_to_program(list(offsets))
        radius = machine._user_to_program([diameter / 2.0])[0]
        words = " ".join(l + number(v) for l, v in zip(AXES6, values[:6]))
        return "G10 L1 P%d %s R%s I%s J%s Q%d" % (
            tool,
            words,
            number(radius),
            number(front),
            number(back),
            orientation,
        )

    def _tool_length_offset(self, offset: List[float]) -> str:
        """A tool length offset in G-code. rs274 -g has no U V W words, but
        G43.1 keeps the axes it is not given: U V W come from what is in
        force, from the tool table (G43 H, G43.2 H added to what is in
        force), or are lost (the one call that then differs)."""
        before = self._tool_offset
        six = "G43.1 " + " ".join(l + number(v) for l, v in zip(AXES6, offset[:6]))
        if not any(offset):
            text = "G49"
        elif offset[6:] == before[6:]:
            text = six
        else:
            text = self._tool_length_from_table(before, offset)
            if text is None:
                text = ("G49\n" if not any(offset[6:]) else "") + six
                if any(offset[6:]):
                    offset = offset[:6] + before[6:]
        self._tool_offset = offset
        return text

    def _tool_length_from_table(self, before, offset) -> Optional[str]:
        machine = self.machine
        tools = sorted({e.tool for e in machine.tools.slots.values() if e.tool >= 0})
        for tool in tools:
            try:
                entry = machine._entry(machine._pocket_of(tool))
            except Exception:  # noqa: BLE001 - a tool the table cannot give
                continue
            extra = machine._user_to_program(entry.offsets)
            if extra == offset:
                return "G43 H%d" % tool
            if [a + b for a, b in zip(before, extra)] == offset:
                return "G43.2 H%d" % tool
        return None

    def _g10(self, index: int, offsets: Sequence[float], rotation: float) -> str:
        words = " ".join(letter + number(v) for letter, v in zip(AXES6, offsets))
        self._stored[index] = (tuple(offsets), rotation, self._inches)
        return "G10 L2 P%d %s R%s" % (index, words, number(rotation))

    def _g5x(self, args, after) -> Tuple[str, int]:
        index, offsets = args[0], tuple(args[1:7])
        names = [c[0] for c in after]
        if names == ["set_g92_offset", "set_xy_rotation"]:
            # a G5x selection: offsets, G92 offsets and rotation
            # it loads the system from its parameters, which the flat
            # program has set (see _parameter_changes)
            self._system = index
            return SYSTEM_CODES[index - 1], 3
        rotation = after[0][1][0] if names[:1] == ["set_xy_rotation"] else 0.0
        self._system = index
        return self._g10(index, offsets, rotation), (
            2 if names[:1] == ["set_xy_rotation"] else 1
        )

    def _single(self, name: str, args: tuple) -> Optional[str]:
        """The G-code for one call on its own."""
        if name == "use_length_units":
            self._inches = bool(args[0])
            return "G20" if args[0] else "G21"
        if name == "select_plane":
            self._plane = args[0]
            return PLANE_CODES[args[0]]
        if name == "set_g92_offset":
            return "G52 " + " ".join(l + number(v) for l, v in zip(AXES6, args[:6]))
        if name == "use_tool_length_offset":
            return self._tool_length_offset(list(args))
        if name == "set_feed_rate":
            return "F" + number(args[0])
        if name == "set_feed_mode":
            return "G95" if args[1] == 1 else "G94"
        if name in ("print", "print_text"):
            return "(PRINT,%s)" % args[0]
        if name == "dwell":
            return "G4 P" + number(args[0])
        if name == "set_spindle_speed":
            return "S" + number(args[1]) + _dollar(args[0])
        if name in _SPINDLE_CODES:
            return _SPINDLE_CODES[name] + _dollar(args[0])
        if name == "set_spindle_mode":
            return "G97" if args[1] == 0 else None
        simple = {
            "mist_on": "M7",
            "flood_on": "M8",
            "program_stop": "M0",
            "optional_program_stop": "M1",
            "enable_feed_override": "M50 P1",
            "disable_feed_override": "M50 P0",
            "enable_adaptive_feed": "M52 P1",
            "disable_adaptive_feed": "M52 P0",
            "enable_feed_hold": "M53 P1",
            "disable_feed_hold": "M53 P0",
            "logclose": "(LOGCLOSE)",
            "finish": None,
        }
        if name in simple:
            return simple[name]
        if name == "program_end":
            return "M30" if args and args[0] else "M2"
        if name == "enable_speed_override":
            return "M51 P1"
        if name == "disable_speed_override":
            return "M51 P0"
        if name == "select_tool":
            return "T%d" % args[0]
        if name == "change_tool_number":
            # the call names the pocket, M61 the tool in it
            entry = self.machine.tools.slots.get(args[0]) if args[0] else None
            return "M61 Q%d" % (entry.tool if entry is not None else args[0])
        texts = {
            "comment": "(%s)",
            "message": "(MSG,%s)",
            "log": "(LOG,%s)",
            "logopen": "(LOGOPEN,%s)",
            "logappend": "(LOGAPPEND,%s)",
        }
        if name == "comment" and not args[0]:
            # rs274 makes no call for "()"; "( )" gives COMMENT("")
            return "( )"
        if name in texts:
            return texts[name] % args[0]
        if name in ("set_motion_output_bit", "clear_motion_output_bit"):
            return ("M62 P%d" if name.startswith("set") else "M63 P%d") % args[0]
        if name in ("set_aux_output_bit", "clear_aux_output_bit"):
            return ("M64 P%d" if name.startswith("set") else "M65 P%d") % args[0]
        if name == "set_motion_output_value":
            return "M67 E%d Q%s" % (args[0], number(args[1]))
        if name == "set_aux_output_value":
            return "M68 E%d Q%s" % (args[0], number(args[1]))
        if name in (
            "set_feed_reference",
            "set_traverse_rate",
            "set_naivecam_tolerance",
        ):
            return None
        raise FlattenError(
            "flatten: the program makes a %s call, which flatten cannot write as G-code yet"
            % name.upper()
        )

    def _check_spindle(self, name: str, spindle: int) -> None:
        """A spindle's call that flatten writes without ``$``: the first
        spindle's, on a machine of one spindle for the override switches
        (M48-M51 without ``$`` switch every spindle, and rs274 refuses
        ``M51 $0``)."""
        if spindle != 0 or (
            name in _SPINDLE_SWITCHES and self.machine.num_spindles > 1
        ):
            raise FlattenError(
                "flatten: the program makes %s(%d) on a machine of %d spindles,"
                " which flatten cannot write as G-code yet"
                % (name.upper(), spindle, self.machine.num_spindles)
            )

    def text(self, header: Sequence[str] = ()) -> str:
        """The flat program."""
        self._flush()
        lines = ["; " + h for h in header]
        lines.append("G90  ; absolute positions (no canonical call)")
        lines += self.lines
        if self.finished:
            lines = ["%"] + lines + ["%"]
        return "\n".join(lines) + "\n"


def _recorder(name: str):
    def record(self, *args):
        self._record(name, args)

    record.__name__ = name
    return record


for _name in CALLS:
    setattr(FlattenCanon, _name, _recorder(_name))
del _name


#: The calls FlattenCanon._texts does not leave to _single: the method
#: that writes each (with the calls after it, or in its own way).
_WRITERS = {
    "straight_traverse": FlattenCanon._w_traverse,
    "straight_feed": FlattenCanon._w_feed,
    "start_speed_feed_synch": FlattenCanon._w_synch_start,
    "stop_speed_feed_synch": FlattenCanon._w_synch_stop,
    "rigid_tap": FlattenCanon._w_rigid_tap,
    "turn_probe_on": FlattenCanon._w_probe,
    "nurbs_feed": FlattenCanon._w_nurbs,
    "set_tool_table_entry": FlattenCanon._w_tool_entry,
    "arc_feed": FlattenCanon._w_arc,
    "set_g5x_offset": FlattenCanon._w_g5x,
    "set_xy_rotation": FlattenCanon._w_rotation,
    "comment": FlattenCanon._w_comment,
    "set_motion_control_mode": FlattenCanon._w_control_mode,
    "start_change": FlattenCanon._w_start_change,
    "mist_off": FlattenCanon._w_pair,
    "disable_feed_override": FlattenCanon._w_pair,
    "enable_feed_override": FlattenCanon._w_pair,
    "orient_spindle": FlattenCanon._w_orient,
    "wait_spindle_orient_complete": FlattenCanon._w_orient_wait,
    "set_spindle_mode": FlattenCanon._w_spindle_mode,
    "pallet_shuttle": FlattenCanon._w_shuttle,
}

#: Spindle calls written with the spindle's ``$`` (none for the first).
_SPINDLE_CODES = {
    "start_spindle_clockwise": "M3",
    "start_spindle_counterclockwise": "M4",
    "stop_spindle_turning": "M5",
}
#: The spindle's override switch (M48-M51).
_SPINDLE_SWITCHES = ("enable_speed_override", "disable_speed_override")
#: The other calls with a spindle: written without ``$`` (_check_spindle).
_SPINDLE_ALONE = frozenset(
    (
        "set_spindle_mode",
        "orient_spindle",
        "wait_spindle_orient_complete",
        "start_speed_feed_synch",
        "set_feed_mode",
    )
    + _SPINDLE_SWITCHES
)


def _dollar(spindle: int) -> str:
    """The ``$`` word of a spindle's call: none for the first spindle, the
    one a program without ``$`` drives."""
    return " $%d" % spindle if spindle else ""


#: Two calls one M code makes (None: no code makes that pair).
_PAIRS = {
    ("mist_off", "flood_off"): "M9",
    ("enable_feed_override", "enable_speed_override"): "M48",
    ("disable_feed_override", "enable_speed_override"): None,
    ("disable_feed_override", "disable_speed_override"): "M49",
}


class _Cursor:
    """Where FlattenCanon._texts is in a group's calls (the writers' view)."""

    __slots__ = ("calls", "group", "pos", "taken", "i", "nxt")

    def __init__(self, calls: List[tuple], group: "_Group", pos: List[float]) -> None:
        self.calls, self.group, self.pos = calls, group, pos
        self.taken: set = set()  # calls a line further up has already written
        self.i = 0
        self.nxt: Optional[str] = None  # the next call's name


class _PrintCatcher:
    """Stands in for stdout while the program runs: (PRINT,...) writes its
    text there (as rs274 does), and the flat program must say it again."""

    def __init__(self, canon: FlattenCanon) -> None:
        self.canon = canon
        self.pending = ""

    def write(self, text: str) -> int:
        self.pending += text
        while "\n" in self.pending:
            line, self.pending = self.pending.split("\n", 1)
            self.canon._record("print", (line,))
        return len(text)

    def flush(self) -> None:
        pass

    def __enter__(self) -> "_PrintCatcher":
        self.saved = sys.stdout
        sys.stdout = self
        return self

    def __exit__(self, *exc) -> None:
        sys.stdout = self.saved


def _flatten_machine():
    """A Machine whose blocks each announce their start (FlattenCanon groups
    calls by block; the fast path alone announces only changes of N): lines
    of one plain move or arc announce it and take the fast path
    (runtime.fast.rows.BatchesOnly), whole batches of plain rows reach
    FlattenCanon.straight_moves and arc_moves."""
    from runtime.machine import Machine
    from runtime.fast.rows import BatchesOnly

    class FlattenMachine(BatchesOnly, Machine):
        def _line_begins(self, line, n):
            # the block starts: FlattenCanon groups its calls from here
            self.line = line
            self.announce_block(n)

    return FlattenMachine


def flatten(
    program: str,
    tool_table: Optional[str] = None,
    var_file: Optional[str] = None,
    ini: Optional[str] = None,
    block_delete: bool = False,
    continue_mode: Optional[int] = None,
) -> str:
    """The flat G-code of ``program`` run with rs274's options. Raises
    GCodeError where the program fails, FlattenError for what flatten
    cannot write. With ``continue_mode`` 0 (rs274's ``-n 0``) errors are
    reported on stderr and the flat program holds what the other lines made."""
    from ngc2py.loading import load_program, unopened
    from ngc2py.compiler import OpenError
    from runtime import continue_mode as continuing
    from runtime.main import report, start

    def run(machine) -> None:
        canon.machine = machine
        if continue_mode is not None:
            continuing.enable(
                machine,
                continue_mode,
                lambda e: report(e, sys.stderr),
                sys.stdin,
                sys.stderr,
            )
        with catcher:
            start(machine, main)

    Machine = _flatten_machine()

    try:
        module = load_program(program, ini, block_delete)
        main, source_map = module.main, module.__ngc__
    except OpenError as error:
        main, source_map = None, unopened(program, error)
    canon = FlattenCanon(program)
    catcher = _PrintCatcher(canon)
    options = dict(
        tool_table=tool_table, var_file=None, ini=ini, block_delete=block_delete
    )
    if var_file is not None and os.path.isfile(var_file):
        # read it, but never rewrite the user's file: flatten runs nothing
        import shutil
        import tempfile

        with tempfile.TemporaryDirectory() as folder:
            copy = shutil.copy(var_file, folder)
            run(Machine(canon, source=source_map, **{**options, "var_file": copy}))
    else:
        run(Machine(canon, source=source_map, **options))
    header = ["flattened by ngc2py from %s" % program]
    given = (
        " ".join(
            flag + " " + value
            for flag, value in (("-t", tool_table), ("-v", var_file), ("-i", ini))
            if value
        )
        + (" -b" if block_delete else "")
        + (" -n %d" % continue_mode if continue_mode is not None else "")
    )
    if given.strip():
        header.append("run it with the same options: %s" % given.strip())
    return canon.text(header)


HELP = """\
Write PROG.ngc as plain G-code: subroutines, loops, conditionals,
expressions and parameters resolved into the moves and settings they make,
each line ending with a ';' comment naming its source line (and the O-calls
that led there). rs274 runs the result to the same STRAIGHT_TRAVERSE,
STRAIGHT_FEED and ARC_FEED calls as the original; run it with the same
-t/-v/-i options. A program that fails is not flattened: the error is
reported as `ngc2py run` reports it, exit status 1."""


def register(commands) -> None:
    import argparse

    from ngc2py.flags import add_block_delete

    parser = commands.add_parser(
        "flatten",
        help="write the program as plain G-code with everything resolved",
        description=HELP,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument(
        "program", metavar="PROG.ngc", help="the G-code file ('-': stdin)"
    )
    parser.add_argument(
        "-o",
        "--output",
        metavar="FLAT.ngc",
        help="where to write it (default and '-': standard output); written atomically",
    )
    parser.add_argument("-t", dest="tool_table", metavar="TBL", help="tool table file")
    parser.add_argument(
        "-v",
        dest="var_file",
        metavar="VAR",
        help="parameter (.var) file (read, not rewritten)",
    )
    parser.add_argument("-i", dest="ini", metavar="INI", help="ini file")
    add_block_delete(parser, "block delete on")
    parser.add_argument(
        "-n",
        dest="continue_mode",
        metavar="0|1|2",
        help="after an error: 0 report it and go on (the flat program holds what "
        "the other lines made), 1 rs274's MDI prompt, 2 stop (default), as rs274's -n",
    )
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    parser.set_defaults(**DEFAULTS)


def main(args) -> int:
    from ngc2py.cache import write_atomic
    from ngc2py.progress import spinner
    from runtime.errors import GCodeError
    from runtime.main import _atoi, report

    try:
        with spinner("flattening " + args.program, args.quiet):
            text = flatten(
                args.program,
                args.tool_table,
                args.var_file,
                args.ini,
                args.block_delete,
                None if args.continue_mode is None else _atoi(args.continue_mode),
            )
    except GCodeError as error:
        if not getattr(error, "reported", False):  # -n 1 has reported it
            report(error, sys.stderr)
        return 1
    except FlattenError as error:
        sys.stderr.write("%s\n" % error)
        return 1
    if args.output == "-":
        sys.stdout.write(text)
    else:
        write_atomic(args.output, text)
    return 0


#: What no option of the command line sets (argparse's defaults, and those
#: of ngc2py.cli.quick_args), the command's handler among them.
DEFAULTS = {"handler": main, "output": "-"}
