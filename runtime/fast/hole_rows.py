"""Rows of holes: a canned cycle's next holes, replayed.

A drilling program is mostly rows of hole positions under a modal canned
cycle (``G81 X1 Y2 Z-3 R1`` then ``X3 Y4``, ``X5 Y6``...). The reference
path (``Machine.cycle_row``) drills each row: it announces the block, checks
and settles the cycle's words, works out the levels and makes the moves,
about ten microseconds a hole.

Once a row of the plane's two hole axes alone has been drilled, and it
changed nothing of the machine but its position, every next row of those
words alone makes the very same calls with only the hole's two coordinates
changed: the levels, the number of pecks, the dwell and the motion-mode
switches around each hole do not depend on where the hole is. So
:class:`HoleRows` drills one such row by the reference path while a stand-in
records the canon calls, checks that the row changed nothing but the
position (every other field of the machine and its world model compared)
and that every move of the hole is at the hole in the plane (G87's moves to
its offset are not, and are never replayed), and then replays the recording
for each next row of those words: the same calls with the new coordinates,
the position published as the reference path publishes it.

Anything else steps aside to the reference path: another shape of row, a
row with N, incremental distance, a plane of U V W, a call other than the
moves and the few switches a hole makes. A machine that keeps something of
its own for each row (the preview's line state) is told of each replayed
row (``hole_replayed``); the canon sees each row begin as it did, by the
``set_block_number`` call the hole starts with, the machine's line set.
"""

from __future__ import annotations

from itertools import repeat, takewhile
from marshal import dumps
from operator import attrgetter

from runtime.canon import Canon, TraceCanon, ignores_numbers, numbered_rows
from runtime.cycles import CyclesMixin
from runtime.fast.arc_rows import column_floats, table_lines

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import List, Optional

#: The plane's two hole axes: (first index, second index, their letters).
_HOLE_AXES = {"XY": (0, 1, "xy"), "YZ": (1, 2, "yz"), "XZ": (2, 0, "zx")}

#: The canon calls a hole may make (besides its moves) that carry no position.
HOLE_SWITCHES = frozenset(
    (
        "set_block_number",
        "dwell",
        "set_motion_control_mode",
        "set_naivecam_tolerance",
        "stop_spindle_turning",
        "start_spindle_clockwise",
        "start_spindle_counterclockwise",
        "enable_feed_override",
        "disable_feed_override",
        "enable_speed_override",
        "disable_speed_override",
        "program_stop",  # G88's stop for the manual retract
    )
)
HOLE_MOVES = frozenset(("straight_traverse", "straight_feed"))
#: ... and a cycle's own line restated (:meth:`HoleRows.restated`): its G98
#: or G99 comments the retract mode every time, its F sets the rate again.
RESTATED_SWITCHES = HOLE_SWITCHES | {"comment", "set_feed_rate"}

#: Stand-ins for a move's X and Y while a hole's trace template is made
#: (runtime.canon.TraceCanon prints them as below), at the hole and where
#: the tool was before it.
_STAND_INS = {
    "hole": (77777777777.0, 66666666666.0),
    "start": (55555555555.0, 44444444444.0),
}
_STAND_IN_TEXTS = {
    "hole": ("77777777777.0000", "66666666666.0000"),
    "start": ("55555555555.0000", "44444444444.0000"),
}

#: Rows of holes whose trace is made in one piece, at most.
_MOST = 4096

#: Rows of one shape that make a series worth replaying: the set-up (the
#: recording, its checks, a trace template) costs about what the reference
#: path spends on two rows, so fewer are drilled by the reference path.
_FEWEST = 3

#: Trace templates kept at most, of holes and of their calls (a file of
#: endless kinds of holes makes the rest when it needs them).
_MOST_KEPT = 4096

#: Machine fields a hole changes, which the replay sets itself.
_SET_BY_REPLAY = frozenset(("current", "line", "_block_n"))

#: Where a move of a hole is in the plane: at the hole, or where the tool
#: was before it (its first move, straight up to the R plane).
_AT_HOLE = "hole"
_AT_START = "start"


class _Recording:
    """Stands for the canon while holes are drilled: each call is made on
    the canon and kept as (name, positional arguments) in ``calls``. A
    name's stand-in is made at its first use, bound to the canon's method,
    and kept: one recording serves a table's holes (:meth:`restart` empties
    it), and a call costs one Python call more than the canon's (a stand-in
    looked up on the class and the canon on every call cost twice that)."""

    def __init__(self, canon) -> None:
        self.canon = canon
        self.calls: List[tuple] = []
        self.keywords = False

    def restart(self) -> "_Recording":
        self.calls.clear()  # (the stand-ins append to this very list)
        self.keywords = False
        return self

    def __getattr__(self, name: str):
        method = getattr(self.canon, name)
        if not callable(method):
            return method  # (a value: not kept, it may change)
        append = self.calls.append

        def record(*args, **keywords):
            append((name, args))
            if keywords:
                self.keywords = True
                return method(*args, **keywords)
            # (no keywords to pass on: the call is made without unpacking any)
            return method(*args)

        record.__name__ = name
        self.__dict__[name] = record
        return record


#: Stand-in for the hole axis' level of a move while its line's template
#: is made (eleven digits, as the others: no stand-in's text is another's).
_LEVEL = 10000000000.0


def _template(scratch, recorded: List[tuple], column: str, pieces: dict):
    """The trace text of one hole made of the recorded calls, as a template
    in two stages: the first has ``%s`` for each move's level (the hole
    axis), in order; what it makes has ``%5d`` for each line's number and,
    in a move's line, ``%s`` for its X and Y. So one template serves every
    series of holes drilled alike whatever their levels. Returns it with
    its layout (which column fills each slot: see _trace_piece), its
    number of lines and the N column after the hole; None where a call's
    line cannot be made so (_call_template). Each call's lines are made
    once and kept in ``pieces``. Moves in the XY plane only."""
    parts: List[str] = []
    slots: List[object] = []
    for name, args, move in recorded:
        # keyed by the arguments' bits: 0.0 and -0.0 are equal, but not
        # printed alike
        key = dumps((column, name, args[3:] if move is not None else args, move))
        piece = pieces.get(key)
        if piece is None:
            piece = pieces[key] = _call_template(scratch, name, args, move, column)
        if piece is False:
            return None
        parts += piece[0]
        slots += piece[1]
        column = piece[2]
    # each line's number, then a move's X and Y: at the hole, or where the
    # tool was before it (the columns after the lines' numbers)
    lines = len(slots)
    layout: List[int] = []
    for j, move in enumerate(slots):
        layout.append(j)
        if move is not None:
            layout += (lines, lines + 1) if move == _AT_HOLE else (lines + 2, lines + 3)
    return "".join(parts), tuple(layout), lines, column


#: A hole's N while its numbered template is made (no N is written so) and
#: the N column the trace writes for it, which becomes each line's slot.
_N_STAND_IN = "\x01\x02\x03"
_N_STAND_IN_COLUMN = "N%-6s" % _N_STAND_IN


def _numbered_template(template: str, layout: tuple, lines: int, column: str):
    """_template's answer for rows with their own N numbers: its N column
    (the stand-in's) a slot of every line, filled from the fifth column
    (each row's N column), after the line's number; None where the
    stand-in is not found once a line."""
    if template.count(_N_STAND_IN_COLUMN) != lines or column != _N_STAND_IN_COLUMN:
        return None
    numbered: List[int] = []
    for slot in layout:
        numbered.append(slot)
        if slot < lines:  # a line's number, first on the line: its N next
            numbered.append(lines + 4)
    return template.replace(_N_STAND_IN_COLUMN, "%%s"), tuple(numbered), lines, column


def _call_template(scratch, name: str, args: tuple, move, column: str):
    """The lines of one call of a hole as _template's pieces: (their
    templates, their slots, the N column after), or False where a stand-in's
    text is not found once. The call is made on ``scratch``, a trace, with
    stand-in values that are then replaced."""
    scratch._pending.clear()
    scratch._count, scratch._column = 0, column
    if move is not None:
        args = _STAND_INS[move] + (_LEVEL,) + args[3:]
    getattr(scratch, name)(*args)
    parts: List[str] = []
    for line in scratch._pending:
        body = line[6:].replace("%", "%%%%")
        if move is not None:
            x_text, y_text = _STAND_IN_TEXTS[move]
            found = x_text, y_text, "%.4f" % _LEVEL
            if any(body.count(text) != 1 for text in found):
                return False
            body = body.replace(x_text, "%%s").replace(y_text, "%%s")
            body = body.replace(found[2], "%s")
        parts.append("%%5d " + body)
    return tuple(parts), (move,) * len(parts), scratch._column


def _snapshot(machine) -> tuple:
    return dict(vars(machine)), _world_snapshot(machine)


def _world_snapshot(machine) -> tuple:
    """The canon's world model but its position: what a hole must leave
    as it found it."""
    world = machine.world
    kind = type(world)
    getter = _WORLD_GETTERS.get(kind)
    if getter is None:
        names = [name for name in kind.__slots__ if name != "position"]
        # (two names at least: attrgetter of one gives no tuple)
        getter = _WORLD_GETTERS[kind] = attrgetter(*names, *names[:1])
    return getter(world)


#: world model type -> attrgetter of its fields but the position
_WORLD_GETTERS: dict = {}


def _only_position_changed(before: tuple, machine) -> bool:
    fields, world_before = before
    after = vars(machine)
    if after != fields:  # (compared in one go; then without what may change)
        if after.keys() != fields.keys():
            return False
        probe = dict(after)
        for name in _SET_BY_REPLAY | type(machine).replayed_fields:
            if name in fields:
                probe[name] = fields[name]
        if probe != fields:
            return False
    return _world_snapshot(machine) == world_before


class _Capture:
    """What a cycle's own line (``G99 G81 X.. Y.. Z.. R..``) tells of the rows
    of hole words after it, told by ``CyclesMixin._plane_cycle`` while the
    line runs with the canon recorded: marks where the hole begins, where
    the moves into it begin and end, and its end. A row after the line
    makes the same calls as the line's hole, but for its way in: it starts
    at the level the line's hole left (rs274's clear level) and goes down
    to R from there. So the line's hole is the recording, and the first of
    those rows need not be drilled by the reference path to make one."""

    __slots__ = ("recording", "marks", "start", "world", "fields", "told")

    def __init__(self, recording: _Recording) -> None:
        self.recording = recording
        #: where each stage begins in the recorded calls
        self.marks: List[int] = []
        self.start = None
        self.world = None
        self.fields = None
        #: (calls to replay, end point), or None: not to be replayed
        self.told = None

    def mark(self, machine) -> None:
        marks = self.marks
        marks.append(len(self.recording.calls))
        if len(marks) == 1:  # the hole begins: where, and the world then
            self.start = machine.current[:]
            self.world = _world_snapshot(machine)
        elif len(marks) == 2:  # its words settled: the fields then
            self.fields = dict(vars(machine))

    def ended(self, machine, r: float, clear: float) -> None:
        if len(self.marks) != 3:
            return
        begin, enter, body = self.marks
        calls = self.recording.calls
        way_in = calls[enter:body]
        if not way_in or way_in[0][0] != "straight_traverse":
            return
        # a row's way in: along the plane at the clear level, then down to R
        ia, ib, _ = _HOLE_AXES[machine.plane]
        level = 3 - ia - ib
        moves = []
        for height in (clear, r) if clear > r else (clear,):
            args = list(way_in[0][1])
            args[level] = height
            moves.append(("straight_traverse", tuple(args)))
        row = [("set_block_number", (None,))] + calls[begin:enter] + moves
        self.told = row + calls[body:], machine.current[:]
        # the row's hole changes nothing but the position, as the line's did
        # (the fields a row's hole leaves as they are taken as they are now)
        fields, after = self.fields, vars(machine)
        for name in _TOLD_APART | type(machine).replayed_fields:
            if name in after:
                fields[name] = after[name]
            else:
                fields.pop(name, None)
        if fields != after or _world_snapshot(machine) != self.world:
            self.told = None


#: Fields the cycle line's hole sets that a row's hole leaves as they are
#: (the depth, P and Q are the line's, kept once its holes are drilled).
_TOLD_APART = frozenset(("current", "line", "cycle_depth", "cycle_p", "cycle_q"))


def hole_by_hole(
    canon, machine, recording, lines, first, second, axes, start, numbers=None
):
    """``Canon.hole_moves``' default (the recorded calls again) a hole at a
    time, each at its own line: ``machine.line`` and the machine's own line
    state (``hole_replayed``) the hole's row's while its calls are made, as
    the reference path leaves them (a batch leaves them at its last row).
    For a canon whose batch method takes only some holes and reads the
    machine's line in its calls (announces lines, keeps them)."""
    befores = zip([start[0]] + first[:-1], [start[1]] + second[:-1])
    for k, (line, before) in enumerate(zip(lines, befores)):
        machine.line = line
        hole = first[k : k + 1], second[k : k + 1]
        n = None if numbers is None else numbers[k : k + 1]
        Canon.hole_moves(canon, recording, [line], *hole, axes, before, n)
        machine.hole_replayed(line)


def _alike(cells: List[str], at: int, end: int, stride: int, checks) -> int:
    """How many rows of ``stride`` cells from ``cells[at]`` have each
    check's cell as it says (``(offset in the row, its text)``), looked at
    in growing steps (a series is usually a few dozen rows)."""
    rows, step = 0, 32
    most = (end - at) // stride
    while rows < most:
        step = min(step, most - rows)
        begin = at + rows * stride
        found = step
        for offset, text in checks:
            looked = cells[begin + offset : begin + offset + found * stride : stride]
            found = len(list(takewhile(text.__eq__, looked)))
            if not found:
                break
        rows += found
        if found < step:
            break
        step *= 4
    return rows


class HoleRows:
    """The replay of hole rows for one table (runtime.fast.rows)."""

    __slots__ = (
        "machine",
        "plans",
        "printed",
        "holes",
        "numbered",
        "recorded",
        "templates",
        "hole_templates",
        "shape",
        "scratch",
        "told",
        "recording",
    )

    def __init__(self, machine, plans, printed: bool = False) -> None:
        self.machine = machine
        self.plans = plans
        #: The table's values are written as the trace prints them.
        self.printed = printed
        #: The last recorded hole's calls: (name, arguments, _AT_HOLE,
        #: _AT_START or None for a call that is not a move).
        self.recorded: List[tuple] = []
        #: The trace templates of a hole's calls, of whole holes by their
        #: calls' shape (_template; the last recorded hole's shape, once
        #: worked out), and the trace they are made on.
        self.templates: dict = {}
        self.hole_templates: dict = {}
        self.shape = None
        self.scratch = None
        #: plane -> {shape cell: the hole axes' value indexes, or None}
        self.holes: dict = {}
        #: the same for rows with or without an N (_numbered_words)
        self.numbered: dict = {}
        #: (the row after a cycle's own line, what that line's hole told)
        self.told = None
        #: what stands for the canon while a hole is recorded (_Recording)
        self.recording: Optional[_Recording] = None

    def _recording(self, canon) -> _Recording:
        """An empty recording of ``canon``'s calls: the table's, while its
        canon is the same."""
        recording = self.recording
        if recording is None or recording.canon is not canon:
            recording = self.recording = _Recording(canon)
        return recording.restart()

    def opening(self, cells: List[str], at: int, end: int) -> int:
        """Run the cycle's own line at ``cells[at]`` by ``block`` and, when a
        row of hole words follows it, keep what its hole tells of that row
        (_Capture); returns where the row after the line begins."""
        machine = self.machine
        plan = self.plans[int(cells[at + 1])]
        line = machine.line = int(cells[at])
        after = at + 2 + plan.width
        words = dict(zip(plan.letters, map(float, cells[at + 2 : after])))
        self.told = None
        if (
            not self._series(cells, after, end)
            or machine.cutter_comp
            or machine.plane not in _HOLE_AXES
        ):
            machine.block(line, *plan.codes, **words)
            return after
        canon = machine.canon
        recording = machine.canon = self._recording(canon)
        capture = machine._hole_capture = _Capture(recording)
        try:
            machine.block(line, *plan.codes, **words)
        finally:
            machine.canon = canon
            machine._hole_capture = None
        if capture.told is not None and not recording.keywords:
            self.told = after, capture
        return after

    def restated(self, cells: List[str], at: int, end: int) -> int:
        """A cycle's own line restated row after row, as some posts write
        every hole (``G99 G81 X.. Y.. Z-3 R2`` again and again, the X and Y
        alone changing): the row at ``cells[at]`` drilled by the reference
        path, recorded, and when it changed nothing of the machine but its
        position, the next rows of that very text but for the plane's two
        hole axes replayed from it as rows of hole words are (the same
        machine, the same words: the same calls, at another place). Lines
        with N numbers too (each hole then begun with its own). Returns
        where it stopped (``at``: nothing done, not such a row)."""
        machine = self.machine
        key = cells[at + 1]
        plan = self.plans[int(key)]
        stride = 2 + plan.width
        before = at - stride
        plane = machine.plane
        if (
            before < 0
            or cells[before + 1] != key
            or machine.distance_incremental
            or machine.cutter_comp
            or plane not in _HOLE_AXES
        ):
            return at
        ia, ib, letters = _HOLE_AXES[plane]
        # the row before restated the same words (a cheap first look: the
        # recording below decides); an N is each line's own
        shift = 1 if plan.has_n else 0
        checks = [(1, key)]
        for i, letter in enumerate(plan.letters, 2 + shift):
            if letter not in letters:
                if cells[at + i] != cells[before + i]:
                    return at
                checks.append((i, cells[at + i]))
        stop = at + stride * _alike(cells, at, end, stride, checks)
        if stop - at < stride * _FEWEST:
            return at
        final = self._drilled(cells, at, ia, ib, RESTATED_SWITCHES)
        at += stride
        if final is False:
            return at
        # the rows after it read as rows of hole words, while this runs
        hole = [
            shift + plan.letters.index(x) if x in plan.letters else -1 for x in letters
        ]
        hole = (hole[0], hole[1], stride)
        if shift:  # (numbered rows: each hole's own N, see _replay)
            known = self.numbered.setdefault(plane, {})
            hole += (True,)
        else:
            known = self.holes.setdefault(plane, {})
        kept = known.get(key, False)
        known[key] = hole
        try:
            if type(machine.canon) is TraceCanon and (ia, ib) == (0, 1):
                return self._trace_text(cells, at, stop, final, bool(shift))
            return self._replay(cells, at, stop, final, ia, ib, bool(shift))
        finally:
            if kept is False:
                del known[key]
            else:
                known[key] = kept

    def _series(self, cells: List[str], at: int, end: int) -> bool:
        """Whether the rows from ``cells[at]`` begin with _FEWEST rows of one
        shape that a canned cycle reads: a series worth replaying."""
        if at >= end:
            return False
        key = cells[at + 1]
        plan = self.plans[int(key)]
        stride = 2 + plan.width
        last = at + 1 + (_FEWEST - 1) * stride
        return (
            (plan.cycle or plan.cycle_n)
            and last < end
            and cells[at + 1 : last + 1 : stride].count(key) == _FEWEST
        )

    def _hole_words(self, plane: str, key: str):
        """For a row of shape ``key``: (index of the first hole axis' value
        or -1, of the second or -1, the row's cells), or None when the row
        has other words (or an N: see _numbered_words)."""
        known = self.holes.setdefault(plane, {})
        if key not in known:
            known[key] = self._numbered_words(plane, key)
            if known[key] is not None:
                first, second, stride, has_n = known[key]
                known[key] = None if has_n else (first, second, stride)
        return known[key]

    def _numbered_words(self, plane: str, key: str):
        """:meth:`_hole_words` for rows with or without an N number:
        (first, second, stride, whether the row has an N), the indexes
        counting the N's cell."""
        known = self.numbered.setdefault(plane, {})
        if key not in known:
            plan = self.plans[int(key)]
            letters = _HOLE_AXES[plane][2]
            known[key] = None
            if (plan.cycle or plan.cycle_n) and set(plan.letters) <= set(letters):
                shift = 1 if plan.has_n else 0
                found = [
                    shift + plan.letters.index(x) if x in plan.letters else -1
                    for x in letters
                ]
                known[key] = (found[0], found[1], 2 + plan.width, plan.has_n)
        return known[key]

    def run(self, cells: List[str], at: int, end: int) -> int:
        """While a canned cycle is the modal motion: drill the rows from
        ``cells[at]`` while they are holes of the plane's axes alone, the
        first by the reference path (recorded), the others by replaying it;
        returns where it stopped (``at``: nothing done, the row is not
        such a hole or the reference path must decide)."""
        machine = self.machine
        plane = machine.plane
        if at >= end or machine.distance_incremental or plane not in _HOLE_AXES:
            return at
        hole = self._numbered_words(plane, cells[at + 1])
        if hole is None:
            return at
        ia, ib, _ = _HOLE_AXES[plane]
        told, self.told = self.told, None
        replay = False
        if told is not None and told[0] == at:
            replay = self._told(told[1], ia, ib)
        if replay is False:
            if not self._series(cells, at, end):
                return at  # a row or two: the reference path is quicker
            replay = self._record(cells, at, hole, ia, ib)
            if replay is None:
                return at
            at += 2 + self.plans[int(cells[at + 1])].width
        if replay is False:
            return at  # drilled, but not to be replayed
        # rows with N numbers (the recorded one, or the next): row by row
        numbered = self.recorded[0][1] != (None,)
        if not numbered and at < end:
            hole = self._numbered_words(plane, cells[at + 1])
            numbered = hole is not None and hole[3]
        if type(machine.canon) is TraceCanon and (ia, ib) == (0, 1):
            return self._trace_text(cells, at, end, replay, numbered)
        if numbered:
            return self._replay(cells, at, end, replay, ia, ib, numbered=True)
        return self._replay(cells, at, end, replay, ia, ib)

    def _trace_text(
        self, cells: List[str], at: int, end: int, final, numbered=False
    ) -> int:
        """For the trace, in the XY plane: the text of the next rows of hole
        words, a piece of at most _MOST rows at a time (_trace_piece);
        returns where it stopped."""
        while True:
            stop, rows = self._trace_piece(cells, at, end, final, numbered)
            if rows < _MOST or stop == at:  # (a piece short of full: no more)
                return stop
            at = stop

    def _trace_piece(
        self, cells: List[str], at: int, end: int, final, numbered=False
    ) -> tuple:
        """The trace text of at most _MOST next rows of hole words, made from
        one hole's template (_template), written in one piece: their X and
        Y as the trace prints them (a table written as printed gives them as
        they are); returns where it stopped and the number of rows.
        ``numbered``: rows with N numbers too, each line's N column the
        row's own (a slot of the template, _numbered_template)."""
        begin = at
        runs, at = self._runs(cells, at, end, "XY", numbered)
        if not runs:
            return at, 0
        machine = self.machine
        canon = machine.canon
        cur = machine.current
        xs, ys = ["%.4f" % cur[0]], ["%.4f" % cur[1]]
        last = [None, None]  # the last X and Y cells written
        ns: List[str] = []  # (numbered) each row's N column, as the trace writes it
        for start, stop, first, second, stride, *has_n in runs:
            if numbered:
                if has_n[0]:
                    ns += map("N%-6s".__mod__, cells[start + 2 : stop : stride])
                    last_n = cells[stop - stride + 2]
                else:
                    ns += repeat("N..... ", (stop - start) // stride)
                    last_n = None
            # a run of rows of one shape, a column at a time
            for axis, index, written in ((0, first, xs), (1, second, ys)):
                if index < 0:
                    written += repeat(written[-1], (stop - start) // stride)
                    continue
                found = cells[start + 2 + index : stop : stride]
                last[axis] = found[-1]
                if self.printed:
                    written += found
                else:
                    written += map("%.4f".__mod__, map(float, found))
            row = stop - stride
        rows = len(xs) - 1
        # one template for every series of holes drilled alike, whatever
        # their levels (the moves' Z, written in at the first stage)
        recorded = self.recorded
        if numbered:  # (a stand-in for the N, a shape of its own)
            recorded = [(recorded[0][0], (_N_STAND_IN,), None)] + recorded[1:]
            self.shape = None
        levels = []  # each move's level: the hole axis' value
        if self.shape is None:
            shape = []
            for name, args, move in recorded:
                if move:
                    levels.append(args[2])
                    shape.append((name, args[3:], move))
                else:
                    shape.append((name, args, move))
            self.shape = dumps(shape)
        else:
            levels = [args[2] for _, args, move in recorded if move]
        key = canon._column, self.shape
        made = self.hole_templates.get(key, False)
        if made is False:
            if self.scratch is None:
                import io

                self.scratch = TraceCanon(io.StringIO())
            if len(self.templates) > _MOST_KEPT:  # (memory stays bounded)
                self.templates.clear()
            made = _template(self.scratch, recorded, canon._column, self.templates)
            if numbered and made is not None:
                made = _numbered_template(*made)
            if len(self.hole_templates) < _MOST_KEPT:
                self.hole_templates[key] = made
        levels = tuple(map("%.4f".__mod__, levels))
        if made is None or "n" in "".join(levels):  # (nan, inf: C's own words)
            return begin, 0  # no template: the holes go by the reference path
        template, layout, lines, column = made
        base = canon._count
        places = xs[1:], ys[1:], xs[:-1], ys[:-1]  # at the hole, where it was
        if numbered:
            places += (ns,)
            column = ns[-1]
            machine._block_n = last_n
        text = numbered_rows(template % levels, base + 1, lines, rows, layout, places)
        canon._write_batch(text)
        canon._count, canon._column = base + lines * rows, column
        if canon._count >= canon._drain_at:
            canon._drain()
        point = final[:]
        point[0] = cur[0] if last[0] is None else float(last[0])
        point[1] = cur[1] if last[1] is None else float(last[1])
        machine.world.position = point
        machine.current = point[:]
        machine.params.position = tuple(point)
        machine.line = int(cells[row])
        return at, rows

    def _replay(
        self, cells, at: int, end: int, final, ia: int, ib: int, numbered=False
    ) -> int:
        """The recorded calls again for each next row of hole words, at its
        point, ending at ``final`` but in the plane; returns where it
        stopped. ``numbered``: rows with N numbers among them, each hole
        begun with its own (the recording's first call, set_block_number),
        one at a time whatever the canon takes."""
        machine = self.machine
        canon = machine.canon
        # a canon that takes holes in batches, or takes the protocol's
        # default batches (the calls made in C) and never looks at the
        # machine's line as its calls are made, on a machine keeping nothing
        # of its own for each row (the preview's line state, by
        # hole_replayed) whose canon need not see each block begin
        # (BatchesOnly: flatten's groups are the machine's lines)
        batches = type(canon).hole_moves is not Canon.hole_moves or not (
            canon.reads_lines
            or machine.batches_only
            or type(machine).hole_replayed is not CyclesMixin.hole_replayed
        )
        if numbered:
            if self.recorded[0][0] != "set_block_number":
                return at
            if batches and (
                canon.takes_numbers
                or ignores_numbers(canon)
                or type(canon).hole_moves is Canon.hole_moves
            ):
                # (a batch canon that takes N numbers, or ignores them; the
                # default batch tells each hole's N, as a hole row by row)
                return self._batches(cells, at, end, final, ia, ib, numbered=True)
            lookup = self._numbered_words
            known = self.numbered.setdefault(machine.plane, {})
        elif batches:
            return self._batches(cells, at, end, final, ia, ib)
        else:
            lookup = self._hole_words
            known = self.holes.setdefault(machine.plane, {})
        # each bound to the canon (X and Y of a move in the XY plane go
        # first: the usual case, quicker)
        calls = [
            (
                getattr(canon, name),
                args[2:] if move and ia == 0 and ib == 1 else args,
                move,
            )
            for name, args, move in self.recorded
        ]
        announce = calls[0][0]
        world, params = machine.world, machine.params
        # what a subclass keeps for each row (the preview's line state)
        kept = None
        if type(machine).hole_replayed is not CyclesMixin.hole_replayed:
            kept = machine.hole_replayed
        while at < end:
            key = cells[at + 1]
            hole = known.get(key, False)
            if hole is False:
                hole = lookup(machine.plane, key)
            if hole is None:
                break
            first, second, stride = hole[:3]
            if numbered:
                n = cells[at + 2] if hole[3] else None
                calls[0] = announce, (n,), None
                machine._block_n = n
            machine.line = line = int(cells[at])
            cur = machine.current
            sa, sb = cur[ia], cur[ib]
            aa = sa if first < 0 else float(cells[at + 2 + first])
            bb = sb if second < 0 else float(cells[at + 2 + second])
            if ia == 0 and ib == 1:
                # XY: the moves' first two arguments (the usual case, quicker)
                for method, args, move in calls:
                    if move is None:
                        method(*args)
                    elif move is _AT_HOLE:
                        method(aa, bb, *args)
                    else:
                        method(sa, sb, *args)
            else:
                for method, args, move in calls:
                    if move is not None:
                        args = list(args)
                        args[ia], args[ib] = (aa, bb) if move is _AT_HOLE else (sa, sb)
                    method(*args)
            end_point = final[:]
            end_point[ia], end_point[ib] = aa, bb
            world.position = end_point
            machine.current = end_point[:]
            params.position = tuple(end_point)
            if kept is not None:
                kept(line)
            at += stride
        return at

    def _batches(
        self, cells, at: int, end: int, final, ia: int, ib: int, numbered=False
    ) -> int:
        """For a canon that takes holes in batches (``Canon.hole_moves``):
        the next rows of hole words, at most _MOST in one call; returns
        where it stopped. While the canon works, ``machine.line`` is the
        batch's last line and its point the batch's start. ``numbered``:
        rows with N numbers too, for a canon that ignores them or takes
        them with the batch (``numbers=``; the machine keeps the last row's)."""
        machine = self.machine
        hole_moves = machine.canon.hole_moves
        # (the default hole_moves tells each hole's N, given numbers; a
        # canon ignoring them is told none)
        takes = machine.canon.takes_numbers
        default = type(machine.canon).hole_moves is Canon.hole_moves and not (
            ignores_numbers(machine.canon)
        )
        world, params = machine.world, machine.params
        numbers = None
        while at < end:
            cur = machine.current
            aa, bb = start = cur[ia], cur[ib]
            lines: List[int] = []
            firsts: List[float] = []
            seconds: List[float] = []
            if numbered and (takes or default):
                numbers = []
            runs, at = self._runs(cells, at, end, machine.plane, numbered)
            for row, stop, first, second, stride, *has_n in runs:
                count = (stop - row) // stride
                lines += table_lines(cells, row, stop, stride)
                if numbers is not None:
                    numbers += (
                        cells[row + 2 : stop : stride] if has_n[0] else [None] * count
                    )
                if first >= 0:
                    firsts += column_floats(cells[row + 2 + first : stop : stride])
                else:
                    firsts += repeat(aa, count)
                if second >= 0:
                    seconds += column_floats(cells[row + 2 + second : stop : stride])
                else:
                    seconds += repeat(bb, count)
                aa, bb = firsts[-1], seconds[-1]
            if not lines:
                break
            machine.line = lines[-1]
            if numbered:  # (the N the last row announced, or None)
                machine._block_n = cells[stop - stride + 2] if has_n[0] else None
            if numbers is None:
                hole_moves(self.recorded, lines, firsts, seconds, (ia, ib), start)
            else:
                args = (self.recorded, lines, firsts, seconds, (ia, ib), start)
                hole_moves(*args, numbers=numbers)
            end_point = final[:]
            end_point[ia], end_point[ib] = aa, bb
            world.position = end_point
            machine.current = end_point[:]
            params.position = tuple(end_point)
            # what a subclass keeps for each row (the preview's line state)
            if type(machine).hole_replayed is not CyclesMixin.hole_replayed:
                machine.hole_replayed(lines[-1])
        return at

    def _runs(self, cells: List[str], at: int, end: int, plane: str, numbered=False):
        """The next rows of hole words from ``cells[at]``, at most _MOST, as
        runs of rows of one shape: ([(first cell, end, index of the first
        hole axis' value or -1, of the second or -1, stride)...], where
        they end). ``numbered``: rows with N numbers too (_numbered_words:
        each run's tuple then ends with whether its rows have one)."""
        if numbered:
            known, lookup = self.numbered.setdefault(plane, {}), self._numbered_words
        else:
            known, lookup = self.holes.setdefault(plane, {}), self._hole_words
        runs: List[tuple] = []
        room = _MOST
        while at < end and room:
            key = cells[at + 1]
            hole = known.get(key, False)
            if hole is False:
                hole = lookup(plane, key)
            if hole is None:
                break
            first, second, stride = hole[:3]
            # a series is usually a few dozen rows: look ahead in growing
            # steps rather than slicing as many rows as a piece may take
            count, step = 0, 32
            while True:
                step = min(step, room - count, (end - at) // stride - count)
                begin = at + 1 + count * stride
                looked = cells[begin : begin + step * stride : stride]
                found = len(list(takewhile(key.__eq__, looked)))
                count += found
                if found < step or not step:
                    break
                step *= 4
            stop = at + count * stride
            runs.append((at, stop, first, second, stride) + hole[3:])
            room -= count
            at = stop
        return runs, at

    def _record(self, cells: List[str], at: int, hole, ia: int, ib: int):
        """Drill the row at ``at`` by the reference path, recording it: its
        end point (its calls kept in ``recorded``: _replayable), False when
        it may not be replayed, or None when the reference path did not take
        the row (nothing done)."""
        return self._drilled(cells, at, ia, ib, HOLE_SWITCHES)

    def _drilled(self, cells: List[str], at: int, ia: int, ib: int, switches):
        """The row at ``at`` run by the reference path with the canon
        recorded (a row of hole words by ``cycle_row``, a cycle's own line by
        ``block``): its end point when it may be replayed (its calls kept in
        ``recorded``), False when not, None when ``cycle_row`` did not take
        the row (nothing done)."""
        machine = self.machine
        plan = self.plans[int(cells[at + 1])]
        line = int(cells[at])
        values = cells[at + 2 : at + 2 + plan.width]
        n = values.pop(0) if plan.has_n else None
        words = dict(zip(plan.letters, map(float, values)))
        before = _snapshot(machine)
        origin = machine.current
        canon = machine.canon
        recording = machine.canon = self._recording(canon)
        try:
            if plan.codes:  # a cycle's own line
                machine.block(line, *plan.codes, n=n, **words)
                done = True
            else:
                # (without an N as a subclass of old may take it)
                row = (line, words) + ((n,) if n is not None else ())
                done = machine.cycle_row(*row)
        finally:
            machine.canon = canon
        if not done:
            return None
        final = list(machine.current)
        level = 3 - ia - ib
        if final[level] != origin[level] or final[3:] != origin[3:]:
            # it ended off the level it began at (the first hole after the
            # tool came from elsewhere): the next hole begins elsewhere
            return False
        if recording.keywords or not _only_position_changed(before, machine):
            return False
        return self._replayable(recording.calls, origin, final, ia, ib, switches)

    def _told(self, capture: _Capture, ia: int, ib: int):
        """What a cycle's own line told of the row after it (_Capture), as
        _record gives it, without drilling the row; False when it may not
        be replayed."""
        machine = self.machine
        calls, final = capture.told
        kind = type(machine)
        if (
            # a machine that keeps something of its own for each row it
            # drills tells it by hole_replayed, or every row is drilled
            kind.cycle_row is not CyclesMixin.cycle_row
            and kind.hole_replayed is CyclesMixin.hole_replayed
        ):
            return False
        # (the plane's three axes are 0, 1 and 2: the others must stay)
        if machine.cycle_row_refused({}) or final[3:] != capture.start[3:]:
            return False
        return self._replayable(calls, capture.start, final, ia, ib)

    def _replayable(
        self, recorded_calls, origin, final, ia: int, ib: int, switches=HOLE_SWITCHES
    ):
        """The end point of a hole drilled from ``origin`` to ``final``, its
        calls kept to be replayed (``recorded``: its moves told apart, at
        the hole or where the tool was before it), or False where a call is
        not a hole's or which moves are at the hole is not to be told."""
        start = origin[ia], origin[ib]
        hole = final[ia], final[ib]
        if hole == start:
            return False  # which moves are at the hole is not to be told
        recorded = []
        add = recorded.append
        for name, args in recorded_calls:
            if name in HOLE_MOVES:
                # at the hole, or (up to the R plane first) where it was
                spot = args[ia], args[ib]
                if spot == hole:
                    add((name, args, _AT_HOLE))
                elif spot == start:
                    add((name, args, _AT_START))
                else:
                    return False  # elsewhere (G87's offsets)
            elif name in switches:
                add((name, args, None))
            else:
                return False
        self.recorded, self.shape = recorded, None
        return final
