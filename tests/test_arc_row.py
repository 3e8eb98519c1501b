"""The arc row loop in C (runtime/fast/_arc_row.c) against its Python.

runtime/fast/arc_rows.py takes ``arc_row`` (one row's arc) and ``rows``
(the loop over rows without N or F, for the trace) from the extension where
it was built. Both must leave the trace, every call a canon gets, the
machine's state and any error exactly as the Python loop does; the
programs' traces against rs274 are tests/test_rows.py's.
"""

from __future__ import annotations

import io
import math
import random
import struct

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

import cam_strategies
from ngc2py.compiler import compile_text
from runtime import canon as canon_module
from runtime.canon import Canon, RecordingCanon, TraceCanon
from runtime.errors import GCodeError
from runtime.fast import arc_rows
from test_differential import PROFILE, check_same

BUILT = arc_rows.rows_in_c is not None
needs_c = pytest.mark.skipif(
    not BUILT, reason="runtime.fast._arc_row not built here: the Python loop runs"
)


def _python_only(patch) -> None:
    patch.setattr(arc_rows, "arc_row", arc_rows.python_arc_row)
    patch.setattr(arc_rows, "rows_in_c", None)


def _run(code: str, out=None, drain_at=None):
    """The trace, the error (or None) and the machine's state after it."""
    namespace: dict = {"__name__": "arcs"}
    exec(compile(code, "arcs.py", "exec"), namespace)
    out = io.StringIO() if out is None else out
    canon = TraceCanon(out)
    if drain_at is not None:
        canon._drain_at = drain_at
    machines = []
    original = namespace["Machine"]

    def keep(*args, **kwargs):
        machine = original(*args, **kwargs)
        machines.append(machine)
        return machine

    namespace["Machine"] = keep
    error = None
    try:
        namespace["run"](canon)
    except (GCodeError, OSError) as raised:
        error = type(raised).__name__, str(raised)
    machine = machines[0]
    state = (
        machine.line,
        list(machine.current),
        machine.motion_mode,
        machine.feed_rate,
    )
    return out.getvalue() if isinstance(out, io.StringIO) else None, error, state


#: Arc programs, now and then with G17 (or G90) restated on their lines
#: (``G17 G2 X.. R..``: a SELECT_PLANE before the arc, in both loops).
ARC_PROGRAMS = cam_strategies.arc_programs() | cam_strategies.restating(
    cam_strategies.arc_programs()
)


@needs_c
@settings(PROFILE, max_examples=PROFILE.max_examples * 3)
@given(ARC_PROGRAMS)
def test_the_c_loop_writes_the_python_loops_trace(text):
    code = compile_text(text, "arcs.ngc")
    fast = _run(code)
    with pytest.MonkeyPatch.context() as patch:
        _python_only(patch)
        assert _run(code) == fast


class _Failing(io.StringIO):
    """A stream that fails at its n-th write (a full disk, a closed pipe)."""

    def __init__(self, fail_at: int) -> None:
        super().__init__()
        self.writes = 0
        self.fail_at = fail_at

    def write(self, text):
        self.writes += 1
        if self.writes >= self.fail_at:
            raise OSError("no space left on device")
        return super().write(text)


def _contour(rows: int, numbered: bool = False, restated: bool = False) -> str:
    """A contour of R and I J arcs with lines between; ``numbered``: an N
    on every line and now and then an F, as many CAM posts write them;
    ``restated``: G17 written on every arc (``G17 G2 X.. Y.. R..``)."""
    rng = random.Random(rows)
    lines = ["G21 G90 G17 G94 F300", "G0 X0 Y0 Z1", "G1 Z-1"]
    x = y = 0.0
    for k in range(rows):
        angle = rng.uniform(0, 2 * math.pi)
        radius = rng.uniform(1, 30)
        ex, ey = x + radius * math.cos(angle), y + radius * math.sin(angle)
        if k % 5 == 4:
            lines.append("G1 X%.4f Y%.4f" % (ex, ey))
        elif k % 2:
            lines.append("G%d X%.4f Y%.4f R%.4f" % (rng.choice((2, 3)), ex, ey, radius))
        else:
            cx, cy = (x + ex) / 2, (y + ey) / 2
            lines.append(
                "G%d X%.4f Y%.4f I%.4f J%.4f"
                % (rng.choice((2, 3)), ex, ey, cx - x, cy - y)
            )
        if restated and k % 5 != 4:
            lines[-1] = "G17 " + lines[-1]
        if numbered and k % 7 == 3:
            lines[-1] += " F%d" % rng.randint(100, 900)
        x, y = ex, ey
    if numbered:
        lines = ["N%d %s" % (10 * k, line) for k, line in enumerate(lines, 1)]
    return "\n".join(lines + ["M2", ""])


@needs_c
@pytest.mark.parametrize("numbered", [False, True])
@pytest.mark.parametrize("fail_at", [1, 2, 5])
def test_a_stream_failing_inside_the_c_loop_leaves_the_python_loops_state(
    fail_at, numbered, monkeypatch
):
    """The C loop's state survives an exception from a canon call: the
    same error, at the same line, with the same point, motion and feed rate
    as the Python loop."""
    monkeypatch.setattr(canon_module, "BUFFERED_LINES", 40)  # a write every 40
    code = compile_text(_contour(400, numbered), "arcs.ngc")
    fast = _run(code, _Failing(fail_at), drain_at=40)
    assert fast[1] == ("OSError", "no space left on device")
    with pytest.MonkeyPatch.context() as patch:
        _python_only(patch)
        assert _run(code, _Failing(fail_at), drain_at=40) == fast


@pytest.mark.parametrize("numbered", [False, True])
@pytest.mark.parametrize("restated", [False, True])
def test_the_contour_runs_in_the_c_loop(numbered, restated, monkeypatch):
    """The loop above is the one taken, N and F words or not, G17 restated
    on every arc or not (else the tests above prove nothing)."""
    if not BUILT:
        pytest.skip("runtime.fast._arc_row not built here")
    done = []
    original = arc_rows.rows_in_c

    def counted(cells, at, *args):
        stop = original(cells, at, *args)
        done.append(stop - at)
        return stop

    monkeypatch.setattr(arc_rows, "rows_in_c", counted)
    text = _contour(400, numbered, restated)
    assert ("N50 G" in text) == numbered and (" F" in text[50:]) == numbered
    assert ("G17 G3 X" in text) == restated
    _run(compile_text(text, "arcs.ngc"))
    assert sum(done) > 300 * 5  # cells: most rows of the contour


@needs_c
@pytest.mark.rs274
@pytest.mark.parametrize("numbered", [False, True])
def test_a_contour_restating_g17_on_every_arc_is_rs274s(numbered):
    """Arcs with G17 restated (``G17 G2 X.. R..``) taken by the row loops:
    a SELECT_PLANE before each arc, in C as in Python, as rs274 prints it."""
    text = _contour(400, numbered, restated=True)
    code = compile_text(text, "arcs.ngc")
    fast = _run(code)
    assert fast[0].count("SELECT_PLANE(CANON_PLANE_XY)") > 300
    with pytest.MonkeyPatch.context() as patch:
        _python_only(patch)
        assert _run(code) == fast
    check_same(text, "inprocess")


@needs_c
def test_one_row_is_the_python_rows_arc():
    """arc_row against python_arc_row on random rows of each form, near
    semicircles, R arcs too short, zero radii, ends at the start, F words."""
    rng = random.Random(11)
    geometry = (0, 1, 2, False, 0.000001, 0.0002)
    for _ in range(20000):
        cur = [rng.uniform(-50, 50) for _ in range(9)]
        e1, e2 = rng.choice(
            [
                (cur[0], cur[1]),
                (rng.uniform(-50, 50), rng.uniform(-50, 50)),
                (round(cur[0] + 1, 4), cur[1]),
            ]
        )
        half = math.hypot(e1 - cur[0], e2 - cur[1]) / 2
        has_f = rng.random() < 0.3
        f = ["%.1f" % rng.choice([-1, 0, 0, 250])] if has_f else []
        if rng.random() < 0.5:
            radius = rng.choice(
                [0.0, half, half * (1 + 1e-13), half * 0.9, half * 1.5, -half * 2]
            )
            cells = ["7", "3", repr(e1), repr(e2), repr(radius)] + f
            recipe = (
                rng.choice([20, 30, None]),
                False,
                3 if has_f else -1,
                0,
                ((0, 0), (1, 1)),
                2,
                -1,
                -1,
            )
        else:
            c1, c2 = (cur[0] + e1) / 2 + rng.uniform(-1e-3, 1e-3), (cur[1] + e2) / 2
            cells = ["7", "3", repr(e1), repr(e2), repr(c1 - cur[0]), repr(c2 - cur[1])]
            cells += f
            recipe = (
                rng.choice([20, 30, None]),
                False,
                4 if has_f else -1,
                0,
                ((0, 0), (1, 1)),
                -1,
                2,
                3,
            )
        motion_mode = rng.choice([0, 10, 20, 30])
        feed = rng.choice([0.0, 100.0])
        got = arc_rows.arc_row(cells, 0, recipe, motion_mode, cur, feed, geometry)
        want = arc_rows.python_arc_row(
            cells, 0, recipe, motion_mode, cur, feed, geometry
        )
        assert got == want, (cells, recipe, cur)
        if got is not None:  # the very bits of the centre (a -0.0 shows)
            assert [math.copysign(1, v) for v in got[4:]] == [
                math.copysign(1, v) for v in want[4:]
            ]


class _Batches(RecordingCanon):
    """Takes arcs in batches (arc_moves): records each arc with its G-code
    line and its start, the machine's point for the first of a batch (the
    protocol's promise) and the arc before's end for the others, so that
    batches cut anywhere record alike."""

    machine = None
    #: where the moves so far ended (None: not known, after an offset)
    end = None

    def arc_moves(self, lines, *columns):
        start = list(self.machine.current)
        if self.end is not None:  # the machine is at the batch's start
            assert tuple(start) == self.end, (lines[0], start, self.end)
        p1, p2, p3 = arc_rows.PLANE_AXES[self.machine.plane]
        for line, *args in zip(lines, *columns):
            self._record("arc", (line, tuple(start), *args))
            start[p1], start[p2], start[p3] = args[0], args[1], args[5]
            start[3:] = args[6:]
        self.end = tuple(start)

    def straight_feed(self, *args):
        super().straight_feed(*args)
        self.end = tuple(args)

    def straight_traverse(self, *args):
        super().straight_traverse(*args)
        self.end = tuple(args)

    def arc_feed(self, *args):
        super().arc_feed(*args)
        self.end = None

    def _record(self, name, args):
        super()._record(name, args)
        if name not in ("arc", "straight_feed", "straight_traverse", "arc_feed"):
            self.end = None  # an offset, units...: not followed here


class _LineBatches(_Batches):
    """A batch canon that reads the machine's line (as ngc2py.moves does):
    records the line each call outside a batch finds."""

    reads_lines = True

    def _record(self, name, args):
        if name != "arc":
            line = self.machine.line if self.machine is not None else None
            args = (("line", line),) + tuple(args)
        super()._record(name, args)


class _Contours(_Batches):
    """Takes contours (contour_moves: arcs and the straight feeds between
    them): records each arc as _Batches does and each straight feed as the
    call it stands for, so that a contour records what arcs and calls do."""

    def contour_moves(self, axes, lines, *columns):
        start = list(self.machine.current)
        if self.end is not None:  # the machine is at the batch's start
            assert tuple(start) == self.end, (lines[0], start, self.end)
        assert axes == arc_rows.PLANE_AXES[self.machine.plane]
        p1, p2, p3 = axes
        for line, *args in zip(lines, *columns):
            if args[4] == 0:
                point = [0.0] * 9
                point[p1], point[p2], point[p3] = args[0], args[1], args[5]
                point[3:] = args[6:]
                RecordingCanon._record(self, "straight_feed", tuple(point))
            else:
                self._record("arc", (line, tuple(start), *args))
            start[p1], start[p2], start[p3] = args[0], args[1], args[5]
            start[3:] = args[6:]
        self.end = tuple(start)


class _NumberedContours(_Contours):
    """Takes N numbers with its contours (``takes_numbers``): each row
    recorded with its own N, as if told it just before (the N a row's calls
    are recorded with when every N is told by set_block_number)."""

    takes_numbers = True

    def contour_moves(self, axes, lines, *columns, numbers=None):
        if numbers is None:
            return super().contour_moves(axes, lines, *columns)
        assert len(numbers) == len(lines)
        start = self.machine.current
        for k, n in enumerate(numbers):
            self._n = n
            self.machine.current = start
            row = [column[k : k + 1] for column in columns]
            super().contour_moves(axes, lines[k : k + 1], *row)
            start = list(self.end)
        # (the N the machine keeps is the last row's: told again by no call)


def _batches_only_machine():
    from runtime import Machine
    from runtime.fast.rows import BatchesOnly

    class Announcing(BatchesOnly, Machine):  # (as flatten's machine)
        def _line_begins(self, line, n):
            self.line = line
            self.announce_block(n)

    return Announcing


def _batched(code: str, kind=_Batches, machine_class=None):
    from runtime import Machine, start

    namespace: dict = {"__name__": "arcs"}
    exec(compile(code, "arcs.py", "exec"), namespace)
    canon = kind()
    machine_class = machine_class or Machine
    machine = canon.machine = machine_class(canon, source=namespace["__ngc__"])
    try:
        start(machine, namespace["main"])
        error = None
    except GCodeError as raised:
        error = str(raised)
    state = (machine.line, list(machine.current), machine.motion_mode)
    return canon.calls, canon.numbers, error, state


def _as_in_python(code: str, *how) -> tuple:
    """_batched(code, *how) with the C loop, held to the same with the
    Python loop alone; returns it."""
    fast = _batched(code, *how)
    with pytest.MonkeyPatch.context() as patch:
        _python_only(patch)
        assert _batched(code, *how) == fast
    return fast


@needs_c
@settings(PROFILE, max_examples=PROFILE.max_examples * 3)
@given(ARC_PROGRAMS)
def test_the_c_loop_holds_the_python_loops_arcs(text):
    """For a canon that takes arcs in batches, the C loop holds the arcs
    the Python loop holds: the same arcs, lines, calls between them, N
    numbers and end state (batches may be cut differently)."""
    code = compile_text(text, "arcs.ngc")
    _as_in_python(code)


class _Unnumbered(RecordingCanon):
    """Records calls and ignores N numbers (the protocol's no-op
    set_block_number), as a user's canon counting moves does."""

    set_block_number = Canon.set_block_number


class _RowByRow(_Unnumbered):
    """Reads lines (so each row's calls reach it alone, the reference for
    the default batches)."""

    reads_lines = True


@settings(PROFILE, max_examples=PROFILE.max_examples * 2)
@given(ARC_PROGRAMS)
def test_a_canon_without_batch_methods_gets_the_calls_row_by_row(text):
    """A canon with the protocol's default arc_moves (a user's) gets arcs
    held by the loops and made one arc_feed an arc in C: the very calls,
    N numbers, error and end state it gets row by row."""
    code = compile_text(text, "arcs.ngc")
    assert _batched(code, _Unnumbered) == _batched(code, _RowByRow)


def test_a_canon_without_batch_methods_takes_the_default_batches(batch_rows):
    """The default batch is taken (so the test above compares two paths):
    contours, the straight feeds between the arcs held with them."""
    sizes = batch_rows("contour_moves")
    # (R and IJ arcs in turn, a line between them: no run of one shape,
    # which goes as one batch by the loops' own columns whatever the canon)
    rows = ("G2 X10 Y0 R6", "G1 X12", "G3 X2 Y0 I-5 J0", "G1 X0") * 10
    text = cam_strategies.cam_sized(
        "G21 G17 F100\nG0 X0 Y0\n%s\nM2\n" % "\n".join(rows)
    )
    code = compile_text(text, "arcs.ngc")
    calls = _batched(code, _Unnumbered)[0]
    assert max(sizes) > 30
    assert sum(name == "arc_feed" for name, _ in calls) == 20
    assert sum(name == "straight_feed" for name, _ in calls) == 20
    # a canon keeping N numbers (its own set_block_number) gets each row
    # alone: every N would cut a batch
    sizes.clear()
    assert _batched(code, RecordingCanon)[0] == calls and not sizes


class _FailingAt(RecordingCanon):
    """Keeps N numbers (RecordingCanon's own set_block_number) and fails at
    its ``fail_at``-th move, as a user's collision check would."""

    fail_at = None
    moves = 0

    def _record(self, name: str, args: tuple) -> None:
        if name in ("arc_feed", "straight_feed", "straight_traverse"):
            self.moves += 1
            if self.moves == self.fail_at:
                raise GCodeError("collision at move %d" % self.moves)
        super()._record(name, args)


@needs_c
@settings(PROFILE, max_examples=PROFILE.max_examples * 2)
@given(ARC_PROGRAMS, st.sampled_from([None, 1, 2, 3, 5, 8, 13]))
def test_a_canon_keeping_numbers_gets_the_python_loops_calls_from_the_c_loop(
    text, fail_at
):
    """A canon keeping N numbers, with the default batch methods, gets each
    row's calls made one by one in C (every N would cut a batch): the very
    calls, N numbers, error and end state the Python loop gives it, also
    when one of its moves fails."""

    class Failing(_FailingAt):
        pass

    Failing.fail_at = fail_at
    code = compile_text(text, "arcs.ngc")
    _as_in_python(code, Failing)


@needs_c
def test_a_canon_keeping_numbers_takes_the_c_loop(monkeypatch):
    """The C loop is taken (so the test above compares two paths)."""
    taken = []
    default = arc_rows.rows_in_c

    def counted(*args):
        taken.append(args[1])
        return default(*args)

    monkeypatch.setattr(arc_rows, "rows_in_c", counted)
    rows = ("N10 G2 X10 Y0 R6", "N20 G3 X0 Y0 I-5 J0") * 10
    text = cam_strategies.cam_sized(
        "G21 G17 F100\nG0 X0 Y0\n%s\nM2\n" % "\n".join(rows)
    )
    calls = _batched(compile_text(text, "arcs.ngc"), RecordingCanon)[0]
    assert taken and sum(name == "arc_feed" for name, _ in calls) == 20


class _LinesRecorded(RecordingCanon):
    """Records the machine's line with each call's arguments."""

    reads_lines = True

    def _record(self, name: str, args: tuple) -> None:
        super()._record(name, args + (self.machine.line,))


def test_a_canon_reading_lines_without_batch_methods_gets_each_arc_at_its_line():
    """A canon with the default arc_moves that reads the machine's line gets
    each arc alone, at its own line (a batch would be at its last row's)."""
    arcs = ("G2 X10 Y0 R6", "G3 X0 Y0 I-5 J0") * 20
    text = cam_strategies.cam_sized(
        "G21 G17 F100\nG0 X0 Y0\n%s\nM2\n" % "\n".join(arcs)
    )
    lines = [
        k
        for k, line in enumerate(text.splitlines(), 1)
        if line.startswith(("G2 ", "G3 "))
    ]
    calls = _batched(compile_text(text, "arcs.ngc"), _LinesRecorded)[0]
    assert [args[-1] for name, args in calls if name == "arc_feed"] == lines


def test_a_batches_only_machine_begins_each_arc_line_for_a_canon_without_them():
    """A machine whose canon sees each block begin (flatten's, the
    preview's kind) begins each arc's line for a canon with the default
    arc_moves: such a canon gets no batches from the loops."""
    begun = []

    class Counting(_batches_only_machine()):
        def _line_begins(self, line, n):
            begun.append(line)
            super()._line_begins(line, n)

    arcs = ("G2 X10 Y0 R6", "G3 X0 Y0 I-5 J0") * 20
    text = cam_strategies.cam_sized(
        "G21 G17 F100\nG0 X0 Y0\n%s\nM2\n" % "\n".join(arcs)
    )
    _batched(compile_text(text, "arcs.ngc"), RecordingCanon, Counting)
    assert len(begun) >= 40


@needs_c
@settings(PROFILE, max_examples=PROFILE.max_examples * 2)
@given(ARC_PROGRAMS)
def test_a_canon_reading_lines_finds_them_as_the_python_loop_sets_them(text):
    """Held arcs handed over before a straight row, an N or an F: every call
    outside a batch finds the machine at the line the Python loop sets."""
    code = compile_text(text, "arcs.ngc")
    _as_in_python(code, _LineBatches)


@needs_c
@settings(PROFILE, max_examples=PROFILE.max_examples * 2)
@given(ARC_PROGRAMS)
def test_a_contour_holds_the_lines_between_arcs_the_python_loop_calls(text):
    """For a canon taking contours, the C loop holds plain G1 rows between
    arcs with them (rotation 0): the same moves, in the same order with the
    same calls between them, as the Python loop's arcs and straight_feed
    calls."""
    code = compile_text(text, "arcs.ngc")
    _as_in_python(code, _Contours)


@needs_c
@settings(PROFILE, max_examples=PROFILE.max_examples * 4)
@given(
    st.tuples(
        st.sampled_from(["", "-", "+"]),
        st.text("0123456789", max_size=20),
        st.sampled_from(["", "."]),
        st.text("0123456789", max_size=24),
        st.sampled_from(["", "", "e3", "_", " ", "x"]),
    ).map("".join)
)
@example("900719925474099.5")  # digits past 2**53: float() must read it
@example("-0.00000000000000000000001")  # 23 decimals
def test_a_cell_is_read_as_float_reads_it(text):
    # a plain decimal goes by the quick path (runtime/plain_decimal.h), in an
    # arc row's words and in a column of a table
    from runtime.fast._arc_row import cell_value

    try:
        expected = float(text)
    except ValueError:
        with pytest.raises(ValueError):
            cell_value(text)
        with pytest.raises(ValueError):
            arc_rows.column_floats([text])
        return
    for found in (cell_value(text), arc_rows.column_floats([text])[0]):
        assert struct.pack("<d", found) == struct.pack("<d", expected), text


_COORD = st.floats(-500, 500, allow_nan=False)


@needs_c
@given(
    st.booleans(),
    _COORD,
    _COORD,
    _COORD,
    _COORD,
    st.floats(-600, 600, allow_nan=False) | st.sampled_from([0.5, -0.5, 1e-9]),
    st.sampled_from([1e-6, 1e-12, 0.0]),
    st.sampled_from([None, 1.0, 1.0 + 1e-13, 1.0 - 1e-13]),
)
@settings(max_examples=500)
def test_an_r_arcs_centre_in_c_is_its_python_to_the_bit(
    clockwise, s1, s2, e1, e2, radius, zero, semicircle
):
    """quick_radius_centre (Machine.plain_arc's, in C) against radius_centre
    (runtime.arcs' operations): the same centre to the bit, or None alike;
    semicircles (R half the chord, and a hair either side) included."""
    if semicircle is not None:
        radius = math.copysign(math.hypot(e1 - s1, e2 - s2) / 2 * semicircle, radius)
    made = arc_rows.quick_radius_centre(clockwise, s1, s2, e1, e2, radius, zero)
    twin = arc_rows.radius_centre(clockwise, s1, s2, e1, e2, radius, zero)
    assert (made is None) == (twin is None)
    if made is not None:
        assert [struct.pack("<d", v) for v in made] == [
            struct.pack("<d", v) for v in twin
        ]


@needs_c
@settings(PROFILE, max_examples=PROFILE.max_examples * 2)
@given(ARC_PROGRAMS, st.booleans())
def test_numbered_rows_are_held_with_their_numbers(text, batches_only):
    """For a canon that takes N numbers with its batches, numbered arcs and
    contour lines are held with each row's N, in C as in Python: the same
    calls, each with the N in force, as when every N is told by
    set_block_number (and the batches cut at each)."""
    code = compile_text(text, "arcs.ngc")
    machine = _batches_only_machine() if batches_only else None
    fast = _as_in_python(code, _NumberedContours, machine)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(_NumberedContours, "takes_numbers", False)
        told = _batched(code, _NumberedContours, machine)
    # (an arc of a batch, or not, as its arc_feed call)
    assert _as_arc_feeds(told) == _as_arc_feeds(fast)


def _as_arc_feeds(batched):
    calls, numbers, *rest = batched
    calls = [
        ("arc_feed", args[2:]) if name == "arc" else (name, args)
        for name, args in calls
    ]
    return calls, numbers, *rest


def test_a_numbered_contour_reaches_a_canon_taking_numbers_in_one_batch():
    """A numbered contour is held with its rows' N: only its F words cut
    it (now and then: 400 rows, an F every seventh)."""
    batches = []

    class Counting(_NumberedContours):
        def contour_moves(self, axes, lines, *columns, numbers=None):
            batches.append(numbers)
            super().contour_moves(axes, lines, *columns, numbers=numbers)

    code = compile_text(_contour(400, numbered=True), "arcs.ngc")
    _batched(code, Counting)
    numbered = [b for b in batches if b]
    assert sum(map(len, numbered)) > 350 and len(numbered) < 70, batches
    assert None not in sum(numbered, [])


class _IgnoringPlanes(_Batches):
    """Takes arcs in batches, its select_plane the protocol's no-op (as
    the statistics' and the toolpath's): a restated G17 does not cut them."""

    select_plane = Canon.select_plane


@needs_c
@pytest.mark.parametrize("kind", [_Batches, _IgnoringPlanes, _Contours])
def test_arcs_restating_g17_reach_a_batch_canon_as_by_the_general_path(kind):
    """A batch canon gets the restated arcs' calls (SELECT_PLANE, held arcs
    handed over first, where it has one) as when such rows go by block(),
    in C as in Python."""
    from runtime.fast import rows

    code = compile_text(_contour(400, restated=True), "arcs.ngc")
    fast = _as_in_python(code, kind)
    plan = rows._Plan

    def made(shape, restated=False):
        made = plan(shape, restated)
        made.plane_arc = False
        return made

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(rows, "_Plan", made)
        patch.setattr(rows, "_PLANS", {})
        general = _batched(code, kind)
    assert _as_arc_feeds(general) == _as_arc_feeds(fast)


class _PlaneContours(_NumberedContours):
    """Takes arcs restating G17 with its contours (``takes_planes``): each
    row ``planes`` names recorded after a select_plane("XY"), as the row
    made it (N, SELECT_PLANE, arc) when it went by its line."""

    takes_planes = True

    def contour_moves(self, axes, lines, *columns, numbers=None, planes=None):
        self.batches.append((len(lines), list(planes or ())))
        if not planes:
            return super().contour_moves(axes, lines, *columns, numbers=numbers)
        start, at = self.machine.current, 0
        for k in list(planes) + [len(lines)]:
            for part in ((at, k), (k, k + 1)) if k < len(lines) else ((at, k),):
                begin, stop = part
                if begin == stop:
                    continue
                if begin == k:  # the restated row: its plane first, after its N
                    if numbers is not None:
                        self._n = numbers[k]
                    RecordingCanon._record(self, "select_plane", ("XY",))
                self.machine.current = start
                cut = [column[begin:stop] for column in columns]
                told = None if numbers is None else numbers[begin:stop]
                super().contour_moves(axes, lines[begin:stop], *cut, numbers=told)
                start = list(self.end)
            at = k + 1

    def arc_moves(self, lines, *columns, numbers=None, planes=None):
        axes = arc_rows.PLANE_AXES[self.machine.plane]
        self.contour_moves(axes, lines, *columns, numbers=numbers, planes=planes)

    @property
    def batches(self):
        return self.__dict__.setdefault("_batches", [])


@needs_c
@pytest.mark.parametrize("batches_only", [True, False])
@pytest.mark.parametrize("numbered", [False, True])
def test_arcs_restating_g17_join_the_batches_of_a_canon_taking_planes(
    numbered, batches_only
):
    """On a machine taking arcs only in batches (the preview's, flatten's)
    or not (the statistics', the toolpath's), arcs restating G17 reach a
    canon that ``takes_planes`` in its batches, the restated rows named
    (``planes``), in C as in Python; their calls are those of the rows going
    by their lines or cutting the batches (a canon without takes_planes)."""
    machine = _batches_only_machine() if batches_only else None
    code = compile_text(_contour(400, numbered=numbered, restated=True), "arcs.ngc")
    batches = []

    class Counting(_PlaneContours):
        @property
        def batches(self):
            return batches

    done = []  # the cells the C loop took (else the comparison proves nothing)
    original = arc_rows.rows_in_c

    def counted(cells, at, *args):
        stop = original(cells, at, *args)
        done.append(stop - at)
        return stop

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(arc_rows, "rows_in_c", counted)
        fast = _batched(code, Counting, machine)
    assert sum(done) > 250 * 5, done  # (the restated arcs' cells, most of them)
    held = [planes for _, planes in batches if planes]
    # the restated arcs (320, but those with an F: numbered, one in seven)
    # in batches of several (the lines between cut them here: this canon
    # takes no straight rows in batches)
    assert sum(map(len, held)) > 250, batches
    assert sum(rows for rows, _ in batches) > 2.5 * len(batches), batches
    del batches[:]
    with pytest.MonkeyPatch.context() as patch:
        _python_only(patch)
        assert _batched(code, Counting, machine) == fast
    assert sum(len(planes) for _, planes in batches) == sum(map(len, held))
    if numbered and not batches_only:
        # (there, without planes, the row's N is held with its arc, told
        # after the SELECT_PLANE the row makes first: no reference)
        return
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(Counting, "takes_planes", False)
        by_lines = _batched(code, Counting, machine)
    assert _as_arc_feeds(by_lines) == _as_arc_feeds(fast)


@pytest.mark.parametrize("numbered", [False, True])
def test_the_default_batch_methods_make_a_restated_planes_select_plane(numbered):
    """Canon.arc_moves and contour_moves, given ``planes``: each such row's
    SELECT_PLANE after its N, before its move."""
    lines = [7, 8, 9]
    ends = [[1.0, 2.0, 3.0], [0.5, 0.5, 0.5], [0.0] * 3, [0.0] * 3]
    columns = ends + [[1, 0, -1], [0.0] * 3] + [[0.0] * 3] * 6
    numbers = ["7", "8", "9"] if numbered else None
    for method in ("arc_moves", "contour_moves"):
        canon = RecordingCanon()
        args = ((0, 1, 2),) if method == "contour_moves" else ()
        getattr(canon, method)(*args, lines, *columns, numbers=numbers, planes=[0, 2])
        names = [name for name, _ in canon.calls]
        middle = "arc_feed" if method == "arc_moves" else "straight_feed"
        want = ["select_plane", "arc_feed", middle, "select_plane", "arc_feed"]
        assert names == want, (method, names)
        # (each call made with its row's N in force: told before it)
        told = ["7", "7", "8", "9", "9"] if numbered else [None] * 5
        assert canon.numbers == told, (method, canon.numbers)
        planes = [args for name, args in canon.calls if name == "select_plane"]
        assert planes == [("XY",), ("XY",)]


def test_the_tables_of_one_program_share_what_their_shapes_tell():
    """What ArcRows works out from the plans alone (arc_rows._Derived) is
    made once for all the tables of a module's SHAPES, and never served for
    other plans, even where a freed list's id comes back."""
    from runtime.codes import G2
    from runtime.fast.rows import _Plan

    shapes = [((G2,), ("x", "y", "r")), ((), ("x", "y"))]
    plans = [_Plan(shape) for shape in shapes]
    derived = arc_rows._derived(plans)
    assert arc_rows._derived(plans) is derived
    assert set(derived.straight) == {"1"} and set(derived.groups) == {"0"}
    others = [_Plan(shape) for shape in reversed(shapes)]
    assert arc_rows._derived(others) is not derived
    assert set(arc_rows._derived(others).straight) == {"0"}
    # a stale entry under a reused id is made again
    arc_rows._DERIVED[id(others)] = derived
    assert arc_rows._derived(others).plans is others
