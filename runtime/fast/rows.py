"""Constant blocks kept as data by the code generator, and their loop.

A run of at least ``codegen.MIN_ROWS`` G-code lines that hold only literal
words (a CAM file's moves: no expressions, settings, comments, block delete,
O-words or read errors) in a CAM-sized program (``codegen.MIN_PROGRAM_ROWS``;
elsewhere a run of ``MIN_VALUE_ROWS``) is compiled into a text table instead
of one statement per line, one row per text line::

    ROWS_1 = (triple quote)
    24 0 1.0 2.0
    25 0 3.5 2.0
    (triple quote)

Each row is the G-code line number, the index of its *shape* in the
module's ``SHAPES`` table (the row's G/M codes, as ``runtime.codes``
numbers, and the letters of its words), then one value per letter: a
float's shortest repr, except ``n`` (first when present), the N number's
digits as written (rs274's trace prints them that way).

Why text: a tuple of a million float literals takes Python seconds and
gigabytes to compile every time ``python prog.py`` runs (a script is never
cached as bytecode); one string constant per table compiles in
milliseconds, and ``float()`` of each value is exact (repr round-trips).

Rows whose shape is a plain straight move run through the machine's fast
path (:mod:`runtime.fast.moves`), arcs through :mod:`runtime.fast.arc_rows`; the
others through ``Machine.block``.
"""

from __future__ import annotations

from functools import partial
from itertools import count, repeat, starmap, takewhile
from operator import ne

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import List, Optional, Sequence, Tuple

    Shape = Tuple[Tuple[int, ...], Tuple[str, ...]]

from runtime.fast.arc_rows import ArcRows, column_floats, table_lines
from runtime.fast.hole_rows import HoleRows
from runtime.blockcheck import DRILL_CYCLES
from runtime.canon import Canon, TraceCanon, call_rows, ignores_numbers
from runtime.codes import (
    G0,
    G1,
    G2,
    G3,
    G4,
    G17,
    G18,
    G19,
    G20,
    G21,
    G80,
    G90,
    G91,
    G98,
    G99,
)
from runtime.cycles import ROW_CYCLE_LETTERS
from runtime.fast.printed_rows import BATCH, MOST, printed_rows

_AXES = "xyzabcuvw"
#: The protocol's own straight moves, which do nothing: a canon that keeps
#: them (NullCanon, one that only watches tool changes...) is not called
#: for a batch of rows at all (straight_batch).
_NO_OPS = (Canon.straight_feed, Canon.straight_traverse)
_STRAIGHT_MOVES = Canon.straight_moves
_ARC_LETTERS = "xyzabcijkrf"
#: Codes a line may restate beside its motion (Machine.restating_row).
_RESTATED = frozenset((G17, G90))
#: The codes of a cycle's own line that runtime.fast.hole_rows may learn
#: from: the cycle and the modes CAM posts set beside it.
_DRILL_CODES = frozenset(DRILL_CYCLES)
_CYCLE_LINE_CODES = _DRILL_CODES | {G17, G18, G19, G20, G21, G90, G91, G98, G99}


class _Plan:
    """How to run the rows of one shape."""

    __slots__ = (
        "codes",
        "letters",
        "width",
        "has_n",
        "motion",
        "slots",
        "f_at",
        "beyond_printed",
        "printed",
        "batch",
        "batch_n",
        "arc",
        "cycle",
        "cycle_n",
        "opens_cycle",
        "numbered_cycle_line",
        "dwell",
        "cancel",
        "restating",
        "plane_arc",
    )

    def __init__(self, shape: Shape, absolute_restated: bool = False):
        codes, letters = shape
        self.codes = codes
        # G90 beside the motion restates a mode the plain state is always in
        # (absolute distance), so the fast paths, which act only in that
        # state, read such a row as its motion alone (``absolute_restated``;
        # the rows they leave go to restating_row or block() with the row's
        # own codes)
        if absolute_restated and len(codes) == 2 and G90 in codes:
            codes = tuple(code for code in codes if code != G90)
        self.width = len(letters)
        self.has_n = bool(letters) and letters[0] == "n"
        #: The letters of the float values (the N text is apart).
        self.letters = letters[1:] if self.has_n else letters
        #: For a plain straight move: the motion code (None: the modal one),
        #: (value index, axis index) pairs and where F is; else slots is None.
        self.motion: Optional[int] = codes[0] if codes else None
        self.slots: Optional[List[Tuple[int, int]]] = None
        self.f_at = -1
        #: Names U, V or W, which the trace does not print (runtime.fast.printed_rows).
        self.beyond_printed = False
        plain = len(codes) <= 1 and (not codes or codes[0] in (G0, G1))
        axes = [(i, _AXES.index(x)) for i, x in enumerate(self.letters) if x in _AXES]
        others = [x for x in self.letters if x not in _AXES and x != "f"]
        if plain and axes and not others:
            self.slots = axes
            self.beyond_printed = any(axis >= 6 for _, axis in axes)
            if "f" in self.letters:
                self.f_at = self.letters.index("f")
        #: Rows of this shape can go in one batch (straight_batch): plain
        #: moves that set nothing but axes (no N, no F: one call a row).
        self.batch = self.slots is not None and not self.has_n and self.f_at < 0
        #: The same with an N: a batch for a canon that ignores N numbers
        #: (its set_block_number the protocol's no-op: stats, previews).
        self.batch_n = self.slots is not None and self.has_n and self.f_at < 0
        #: An arc (G2/G3 or the modal motion) for runtime.fast.arc_rows: axis
        #: words, I J K or R, F; no P (turns) and no U V W.
        self.arc = (
            len(codes) <= 1
            and (not codes or codes[0] in (G2, G3))
            and any(x in "xyzabc" for x in self.letters)
            and all(x in _ARC_LETTERS for x in self.letters)
        )
        #: Words a modal canned cycle may take a row of (Machine.cycle_row):
        #: no code, no N, an axis among them.
        self.cycle = (
            not codes
            and not self.has_n
            and ROW_CYCLE_LETTERS.issuperset(self.letters)
            and any(x in "xyz" for x in self.letters)
        )
        #: The same with an N number (posts that number every line): the
        #: replay takes them row by row (runtime.fast.hole_rows).
        self.cycle_n = (
            not codes
            and self.has_n
            and ROW_CYCLE_LETTERS.issuperset(self.letters)
            and any(x in "xyz" for x in self.letters)
        )
        #: A cycle's own line, as CAM posts write it (``G99 G81 X Y Z R``):
        #: its hole tells what the rows of hole words after it make
        #: (runtime.fast.hole_rows).
        self.opens_cycle = (
            not self.has_n
            and len(_DRILL_CODES.intersection(codes)) == 1
            and _CYCLE_LINE_CODES.issuperset(codes)
            and ROW_CYCLE_LETTERS.issuperset(self.letters)
        )
        #: The same with an N: restated at every hole, it is replayed
        #: (HoleRows.restated); a series' first, it goes by block().
        self.numbered_cycle_line = (
            self.has_n
            and len(_DRILL_CODES.intersection(codes)) == 1
            and _CYCLE_LINE_CODES.issuperset(codes)
            and ROW_CYCLE_LETTERS.issuperset(self.letters)
        )
        codes = self.codes  # (the row's own, from here on)
        #: A dwell, G4 and P alone (and N): Machine.dwell_row.
        self.dwell = codes == (G4,) and self.letters == ("p",)
        #: G80 alone (and N), the end of a series of holes: Machine.cancel_row.
        self.cancel = codes == (G80,) and not self.letters
        #: A move or arc whose other codes restate modes (G90, G17), as
        #: some posts write them on every line: (motion, G17 among them,
        #: an arc) for Machine.restating_row; else None.
        self.restating = None
        rest = [code for code in codes if code not in _RESTATED]
        if len(rest) == 1 and len(codes) > 1 and len(set(codes)) == len(codes):
            motion = rest[0]
            if motion in (G0, G1) and axes and not others:
                self.restating = (motion, G17 in codes, False)
            elif (
                motion in (G2, G3)
                and any(x in "xyzabc" for x in self.letters)
                and all(x in _ARC_LETTERS for x in self.letters)
            ):
                self.restating = (motion, G17 in codes, True)
        #: An arc whose one other code is G17 (``G17 G2 X Y R``): in the XY
        #: plane runtime.fast.arc_rows takes it, a SELECT_PLANE before it.
        self.plane_arc = (
            self.restating is not None
            and self.restating[2]
            and len(codes) == 2
            and G17 in codes
        )
        #: What runtime.fast.printed_rows needs, in one tuple (None: not for
        #: it); a pause (G4 P alone) is one, its motion G4.
        self.printed = None
        if self.dwell:
            self.printed = (G4, self.has_n, -1, self.width, None, None)
        elif self.slots is not None and not self.beyond_printed:
            self.printed = (
                self.motion,
                self.has_n,
                self.f_at,
                self.width,
                contiguous(self.slots),
                self.slots,
            )


def straight_batch(
    call,
    cells: List[str],
    at: int,
    end: int,
    plan: "_Plan",
    cur,
    feed: bool = True,
    least: int = BATCH,
    told=None,
):
    """Make the canon call ``call`` (straight_feed or straight_traverse, as
    ``feed`` says) for the consecutive rows of ``plan``'s shape from
    ``cells[at]``, which set only axes: ``(rows done, the point after the last, None)``, or
    ``(rows done, ..., the exception)`` when a call raised (the next row's
    failed), or ``(0, None, None)`` for fewer than ``least`` such rows.
    ``told``: (the canon's set_block_number, the N it was told last), for
    rows with N and a canon that keeps them: each row's N told before its
    move where it is not the one before, as row by row.

    In a run of one shape the axes it does not name keep their values, so
    the calls' arguments are columns of the table (float() of slices) and
    constants, zipped and applied in C: the per-row cost is the call. A
    canon whose straight moves are the protocol's no-ops (NullCanon) is not
    called at all: only the last row's values are read, for the end point;
    one that overrides ``Canon.straight_moves`` gets the columns in one
    call. Rows with an N (``plan.batch_n``) are for a canon that ignores
    N numbers: their values follow it."""
    stride = plan.width + 2
    first = at + 3 if plan.has_n else at + 2  # (each row's first value)
    key = cells[at + 1]
    if cells[at + 1 : at + 1 + stride * least : stride].count(key) != least:
        return 0, None, None
    # a short look first: a run may be a single row (least 1)
    for most in (least + 8, MOST):
        shapes = cells[at + 1 : min(end, at + 1 + stride * most) : stride]
        rows = len(list(takewhile(key.__eq__, shapes)))
        if rows < most:
            break
    stop = at + rows * stride
    done = 0
    error = None
    function = getattr(call, "__func__", None)
    canon = getattr(call, "__self__", None)
    if told is not None:
        # the calls in C, each row's N where it changes (the announcement
        # and the move of a row, a counter first: where an error stopped)
        announce, before = told
        numbers = cells[at + 2 : stop : stride]
        changed = list(map(ne, numbers, [before] + numbers[:-1]))
        columns = [[value] for value in cur]
        for i, axis in plan.slots:
            columns[axis] = column_floats(cells[first + i : stop : stride])
        began = count()
        steps = ((began.__next__, ()), (announce, (numbers,), None, changed))
        try:
            call_rows(0, rows, steps + ((call, tuple(columns)),))
            done = rows
        except Exception as failed:  # noqa: BLE001 - handed back, raised by the caller
            done, error = next(began) - 1, failed
    elif function in _NO_OPS:
        done = rows  # the canon ignores these calls: only the end point counts
    elif type(canon).straight_moves is not _STRAIGHT_MOVES:
        # A canon that takes whole columns (statistics, toolpaths, previews):
        # one call for the run; an error it raises names the run's first row.
        columns = [[value] * rows for value in cur]
        for i, axis in plan.slots:
            columns[axis] = column_floats(cells[first + i : stop : stride])
        lines = table_lines(cells, at, stop, stride)
        try:
            if plan.has_n and canon.takes_numbers:
                numbers = cells[at + 2 : stop : stride]
                canon.straight_moves(feed, lines, *columns, numbers=numbers)
            else:
                canon.straight_moves(feed, lines, *columns)
            done = rows
        except Exception as failed:  # noqa: BLE001 - handed back, raised by the caller
            error = failed
    else:
        arguments = [repeat(value) for value in cur]
        for i, axis in plan.slots:
            arguments[axis] = column_floats(cells[first + i : stop : stride])
        try:
            for done, _ in enumerate(starmap(call, zip(*arguments)), 1):
                pass
            if done < rows:  # only a StopIteration the call raised ends it early
                raise RuntimeError("a canon method raised StopIteration")
        except Exception as failed:  # noqa: BLE001 - handed back, raised by the caller
            error = failed
    if not done:
        return 0, None, error
    point = list(cur)
    last = first + (done - 1) * stride
    for i, axis in plan.slots:
        point[axis] = float(cells[last + i])
    return done, point, error


def contiguous(slots: List[Tuple[int, int]]) -> Optional[Tuple[int, int, int]]:
    """(first value, first axis, count) when the values fill consecutive
    axes in order (``X Y``, ``X Y Z``, ``Z``): one slice assignment."""
    first_value, first_axis = slots[0]
    for k, (value, axis) in enumerate(slots):
        if value != first_value + k or axis != first_axis + k:
            return None
    return first_value, first_axis, len(slots)


#: id of a module's SHAPES -> (the SHAPES, their plans): a program whose
#: tables are cut by other lines (comments, calls) runs many tables of the
#: same shapes, whose plans are then made once
_PLANS: dict = {}
#: Modules' shapes kept at most (one program loads one; a test run many).
_MOST_PLANS = 64


def _plans(shapes: Sequence[Shape]) -> List[_Plan]:
    """The plans of ``shapes`` (G90 restated beside a motion read as the
    motion alone), made once while the module's SHAPES live (kept with
    them, so that their id is not another's)."""
    kept = _PLANS.get(id(shapes))
    if kept is None or kept[0] is not shapes:
        if len(_PLANS) >= _MOST_PLANS:
            _PLANS.clear()
        plans = [_Plan(shape, True) for shape in shapes]
        kept = _PLANS[id(shapes)] = shapes, plans
    return kept[1]


def run_rows(
    machine, shapes: Sequence[Shape], table: str, as_printed: bool = False
) -> None:
    """Execute the rows of ``table`` (see the module docstring).

    ``as_printed``: every value is written as the trace prints it, four
    decimals (see runtime.fast.printed_rows), so the trace can be written from
    the text itself.

    An error is tagged with the row's G-code line (``ngc_row_line``) so the
    source map can name it: the generated frame only knows which table ran.
    """
    # A machine whose moves must each be a line of their own (the preview's)
    # takes the rows the loops below leave as single lines, as the code
    # generator's m.move and m.arc lines would be taken.
    by_move = machine.rows_by_move
    plans = _plans(shapes)
    cells = table.split()
    at, end = 0, len(cells)
    fast = machine.plain_rows
    arc_rows = ArcRows(machine, plans, as_printed).run
    if as_printed and type(machine.canon) is TraceCanon:
        fast = partial(printed_rows, machine, [plan.printed for plan in plans])
    # The next holes of a canned cycle, replayed (runtime.fast.hole_rows).
    hole_rows = HoleRows(machine, plans, as_printed)
    holes, opening, restated = hole_rows.run, hole_rows.opening, hole_rows.restated
    # (a canon that looks up where the rows come from may keep the answer
    # while this call runs at one call level: the generated frames are then
    # the same, whatever row runs; see ngc2py.flatten)
    outer_run, machine.rows_run = machine.rows_run, object()
    try:
        while at < end:
            at = fast(cells, at, end, plans)
            if at == end:
                break
            stop = arc_rows(cells, at, end)
            if stop != at:
                at = stop
                continue
            plan = plans[int(cells[at + 1])]
            if plan.cycle or plan.cycle_n:
                # the first row of hole words is the one the replay records
                stop = holes(cells, at, end)
                if stop != at:
                    at = stop
                    continue
            elif plan.opens_cycle or plan.numbered_cycle_line:
                # restated row after row, or a series' own line
                stop = restated(cells, at, end)
                if stop != at:
                    at = stop
                    continue
                if plan.opens_cycle:
                    at = opening(cells, at, end)
                    continue
            machine.line = line = int(cells[at])
            start = at + 2
            at = start + plan.width
            n = None
            if plan.has_n:
                n = cells[start]
                start += 1
            words = dict(zip(plan.letters, map(float, cells[start:at])))
            if plan.cycle and machine.cycle_row(line, words):
                at = holes(cells, at, end)
                continue
            if plan.restating is not None:  # (G90, G17 beside a move or arc)
                machine.restating_row(line, plan.codes, plan.restating, n, words)
            elif by_move and plan.slots is not None:
                machine.move(line, plan.motion, n=n, **words)
            elif by_move and plan.arc and plan.motion is not None:
                machine.arc(line, plan.motion, n=n, **words)
            elif plan.dwell:
                machine.dwell_row(line, n, words["p"])
            elif plan.cancel and not by_move:
                machine.cancel_row(line, n)
            else:
                machine.block(line, *plan.codes, n=n, **words)
    except Exception as error:
        # (a batch's calls may have named the row that failed: the machine
        # is then at its line, as when its rows run one at a time)
        line = getattr(error, "ngc_row_line", None)
        if line is None:
            error.ngc_row_line = machine.line
        else:
            machine.line = line
        raise
    finally:
        machine.rows_run = outer_run


def _single_xyz(feed: bool):
    """BatchesOnly's ``m.feed`` or ``m.rapid`` (a loop's every move):
    :meth:`BatchesOnly._single_line` for X, Y and Z passed on as they come,
    no N, written out in one method."""

    def single(self, line, x=None, y=None, z=None) -> None:
        run = self._plain_feed if feed else self._plain_rapid
        if not self._batchable or self.reading_profile:
            return run(line, x, y, z)
        token = self._line_begins(line, None)
        self._plain = True
        try:
            run(line, x, y, z)
        finally:
            self._plain = False
        self._line_ended(line, token)

    single.__name__ = single.__qualname__ = "feed" if feed else "rapid"
    return single


class BatchesOnly:
    """For a Machine whose canon must see every block begin (flatten groups
    calls by block, the preview announces each line with the modes as of
    the block before): blocks take the general path, except whole batches
    of plain straight rows (:func:`straight_batch`: one move a block,
    nothing else on the line), which reach the canon's ``straight_moves``
    in one call and which it handles knowing exactly that."""

    #: run_rows hands rows the batches leave to move() and arc(), as lines of
    #: the program would be, not to block(): see _single_line.
    rows_by_move = True
    #: refresh_plain keeps the plain flag in _batchable
    batches_only = True

    # A line of a single plain move or arc (m.move, m.feed, m.rapid, m.arc,
    # and the data rows run_rows hands them) takes the fast path while the
    # modes are plain, between _line_begins and _line_ended, which a
    # subclass defines to keep its canon's view of blocks (the preview's
    # line codes, flatten's groups): the fast path makes the very calls of
    # the general one.
    def _single_line(self, run, line, *args, **words) -> None:
        if not self._batchable or self.reading_profile:
            # the general path (a G7x profile's lines go to its reader)
            return run(line, *args, **words)
        token = self._line_begins(line, words.get("n"))
        self._plain = True  # the fast path, for this line only
        try:
            run(line, *args, **words)
        finally:
            self._plain = False
        self._line_ended(line, token)

    def _line_begins(self, line: int, n: Optional[str]):
        """A line is about to take the fast path; returns what _line_ended gets."""

    def _line_ended(self, line: int, token) -> None:
        """The line has run (by the fast path or, stepping aside, by block())."""

    def move(self, line, *args, **words) -> None:
        self._single_line(super().move, line, *args, **words)

    def __init_subclass__(cls, **kwargs) -> None:
        super().__init_subclass__(**kwargs)
        # the machine's own feed and rapid, found once (a loop's every move)
        cls._plain_feed = super(BatchesOnly, cls).feed
        cls._plain_rapid = super(BatchesOnly, cls).rapid

    feed = _single_xyz(feed=True)
    rapid = _single_xyz(feed=False)

    def arc(self, line, *args, **words) -> None:
        self._single_line(super().arc, line, *args, **words)

    def dwell_row(self, line: int, n: Optional[str], seconds: float) -> None:
        """A row of G4 and P alone (FastPathMixin.dwell_row), its line begun
        and ended around its DWELL (:meth:`_dwell_ended`), as block() would
        run it: in the plain state such a line changes nothing else."""
        if (
            not self._batchable  # (the plain state: _plain is a line's own here)
            or self.reading_profile
            or seconds == -1.0  # (rs274's "no P": block() raises it)
        ):
            return self.block(line, G4, n=n, p=seconds)
        token = self._line_begins(line, n)
        self.line = line
        if n != self._block_n:  # (as a move's line: told once, at its start)
            self.announce_block(n)
        self.canon.dwell(seconds)
        self._dwell_ended(line, token)

    def _dwell_ended(self, line: int, token) -> None:
        """A G4 line has run by the fast path: what _line_ended does for a
        line of a move (a subclass whose line state shows the G4 says so)."""
        self._line_ended(line, token)

    def restating_row(self, line, codes, restating, n, words) -> None:
        """A row of a move or arc with G90 or G17 restated beside it
        (FastPathMixin.restating_row): taken as :meth:`move` and :meth:`arc`
        take a line, the machine's line begun and ended around it."""
        self._single_line(self._restating_row, line, codes, restating, n=n, words=words)

    def _restating_row(self, line, codes, restating, n, words) -> None:
        motion, plane, arc = restating
        if self._plain and not (plane or arc):  # (G90 beside a move: its motion)
            super().move(line, motion, n=n, **words)
        else:
            super().restating_row(line, codes, restating, n, words)

    def plain_rows(self, cells: List[str], at: int, end: int, plans) -> int:
        if not self._batchable:
            return at  # (cutter compensation's queue may stand for the canon)
        canon = self.canon
        # a canon that ignores N numbers, or takes them with the batch, takes
        # rows with one in batches too (the machine keeps the last row's, as
        # block() would)
        ignores_n = ignores_numbers(canon)
        ignores_n = ignores_n or canon.takes_numbers
        if self._block_n is not None and not ignores_n:
            return at
        cur, motion_mode = self.current, self.motion_mode
        # A canon that takes columns (the preview's, flatten's) writes rows
        # of them as it writes a batch, from two rows on; a single plain row
        # (between arcs, a pause, a plunge) costs less as a line of its own
        # (run_rows hands it to move(): the fast path, between the line's
        # announcements) than as a batch (the shop workload's preview 2161M
        # -> 1943M instructions, its flatten 3954M -> 2402M).
        least = BATCH if type(canon).straight_moves is Canon.straight_moves else 2
        row = at
        try:
            while at < end:
                row = at
                key = cells[at + 1]
                plan = plans[int(key)]
                motion = motion_mode if plan.motion is None else plan.motion
                stride = plan.width + 2
                if not (
                    (plan.batch or (plan.batch_n and ignores_n))
                    and end - at >= stride * least
                    # (a batch is of rows of one shape, two at least: the
                    # next row's first)
                    and cells[at + 1 + stride] == key
                    and (motion == G0 or (motion == G1 and self.feed_rate > 0.0))
                ):
                    break
                feed = motion == G1
                call = canon.straight_feed if feed else canon.straight_traverse
                rows, point, error = straight_batch(
                    call, cells, at, end, plan, cur, feed, least
                )
                if error is not None:
                    raise error
                if not rows:
                    break
                at += rows * (plan.width + 2)
                cur, motion_mode = point, motion
                if ignores_n:  # (the N the last row announced, or None)
                    self._block_n = cells[at - plan.width] if plan.has_n else None
        finally:
            self.line = int(cells[row])
            if cur is not self.current:
                self.current = self.world.position = self.params.position = cur
                self.motion_mode = motion_mode
        return at
