"""Runs of literal-only lines (CAM output) against rs274.

The code generator keeps such runs as data tables, written as the trace
prints their numbers when that is exact (runtime/fast/rows.py,
runtime/fast/printed_rows.py). Generated CAM programs (tests/cam_strategies.py)
must give rs274's trace byte for byte through both table forms, and a
table written as printed must drive a non-trace canon with the same calls
and values as one written as the G-code was.
"""

from __future__ import annotations

import io

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import cam_strategies
import test_cycles
from ngc2py import codegen, rowtable
from ngc2py.compiler import compile_text
from runtime.fast import rows as rows_module
from runtime.fast.arc_rows import ArcRows
from runtime.canon import Canon, RecordingCanon, TraceCanon
from runtime.errors import GCodeError
from runtime import codes
from runtime.machine import Machine
from test_differential import PROFILE, check_same

FOUR_PLACES = cam_strategies.cam_sized(
    "\n".join(
        ["G21 G90 F500"] + ["G1 X%d.125 Y-0.5 Z3" % i for i in range(12)] + ["M2"]
    )
    + "\n"
)


@pytest.mark.rs274
@settings(PROFILE, max_examples=PROFILE.max_examples * 2)
@given(cam_strategies.cam_programs())
def test_cam_programs_run(text):
    check_same(text, "inprocess")


@pytest.mark.rs274
@PROFILE
@given(cam_strategies.cam_programs())
def test_cam_programs_converted(text):
    check_same(text, "convert")


@pytest.mark.rs274
@PROFILE
@given(cam_strategies.reordered_row_programs())
def test_rows_with_words_out_of_axis_order_run(text):
    """Rows of one shape whose words are not in axis order, run as one
    batch: each value on its letter's axis (a real CAM file found the
    printed batch putting them in written order)."""
    check_same(text, "inprocess")


@pytest.mark.rs274
@settings(PROFILE, max_examples=PROFILE.max_examples * 2)
@given(cam_strategies.arc_programs())
def test_arc_programs_run(text):
    check_same(text, "inprocess")


@pytest.mark.rs274
@PROFILE
@given(cam_strategies.arc_programs())
def test_arc_programs_converted(text):
    check_same(text, "convert")


def _calls(code: str, error: bool = False):
    namespace: dict = {"__name__": "cam"}
    exec(compile(code, "cam.py", "exec"), namespace)
    canon = RecordingCanon()
    try:
        namespace["run"](canon)
    except GCodeError as raised:
        if not error:
            raise
        return canon.calls, canon.numbers, str(raised)
    return (canon.calls, canon.numbers, None) if error else canon.calls


def _trace(code: str):
    """The trace text (runtime/fast/arc_rows.py writes batches of it itself)."""
    namespace: dict = {"__name__": "cam"}
    exec(compile(code, "cam.py", "exec"), namespace)
    out = io.StringIO()
    try:
        namespace["run"](TraceCanon(out))
    except GCodeError as raised:
        return out.getvalue(), str(raised)
    return out.getvalue(), None


def _without_arc_fast_paths(monkeypatch) -> None:
    """Every arc through Machine.block, as rs274's pipeline runs it."""
    monkeypatch.setattr(ArcRows, "run", lambda self, cells, at, end: at)
    monkeypatch.setattr(Machine, "plain_arc", lambda self, *args: False)


def _same_as_the_general_path(text: str, general) -> None:
    """``text`` run with the fast paths and again with ``general(patch)``
    sending what they take back to the general path: a recording canon's
    calls, values and error, and the trace, the same."""
    code = compile_text(text, "prog.ngc")
    fast = _calls(code, error=True), _trace(code)
    with pytest.MonkeyPatch.context() as patch:
        general(patch)
        assert (_calls(code, error=True), _trace(code)) == fast


@settings(PROFILE, max_examples=PROFILE.max_examples * 3)
@given(cam_strategies.arc_programs())
def test_arc_fast_paths_give_a_canon_the_general_paths_calls(text):
    """Any canon (here one that records) gets from the arc fast paths
    (runtime/fast/arc_rows.py, Machine.plain_arc) the calls, values, N numbers
    and error the general path gives it, and a trace the same text."""
    _same_as_the_general_path(text, _without_arc_fast_paths)


@settings(PROFILE, max_examples=PROFILE.max_examples * 2)
@given(
    cam_strategies.commented(
        cam_strategies.arc_programs() | cam_strategies.cam_programs()
    )
)
def test_moves_and_arcs_with_a_comment_keep_the_general_paths_calls(text):
    """A move or arc line with a plain comment takes the fast path
    (Machine.move, Machine.arc): the comment first, after the N number, then
    the F word and the motion, the very calls, values and error of the
    general path, and the same trace."""

    def general(patch):
        _without_arc_fast_paths(patch)
        patch.setattr(
            Machine,
            "move",
            lambda self, line, motion=None, *, n=None, comment=None, f=None, **axes: self._general_move(
                line, motion, tuple(axes.get(a) for a in "xyzabcuvw"), f, n, comment
            ),
        )

    _same_as_the_general_path(text, general)


@settings(PROFILE)
@given(cam_strategies.hand_drilling())
def test_dwell_rows_keep_the_general_paths_calls(text):
    """A table's G4 P rows (Machine.dwell_row) give a canon the calls,
    values and error of the general path, and the same trace."""
    _same_as_the_general_path(
        text,
        lambda patch: patch.setattr(
            Machine,
            "dwell_row",
            lambda self, line, n, p: self.block(line, codes.G4, n=n, p=p),
        ),
    )


@st.composite
def back_to_back_series(draw):
    """Series of holes each closed by G80 and the next opened at once (no
    motion between: the next series' initial level is where the tool is,
    which G80 makes it take), in either retract mode."""
    lines = ["G21 G90 G17 F300", "G0 Z%d" % draw(st.integers(5, 30))]
    for k in range(draw(st.integers(2, 4))):
        # (the first retracting to R: the next series starts below where
        # the first began)
        retract = "G99" if k == 0 else draw(st.sampled_from(["G98", "G99"]))
        code = draw(st.sampled_from(["G81", "G82 P0.5", "G83 Q1.5", "G73 Q1"]))
        r = draw(st.integers(1, 9))
        lines.append(
            "%s %s X%d Y%d Z-%d R%d"
            % (
                retract,
                code,
                draw(st.integers(0, 99)),
                draw(st.integers(0, 99)),
                draw(st.integers(1, 9)),
                r,
            )
        )
        for _ in range(draw(st.integers(0, 12))):
            lines.append(
                "X%d Y%d" % (draw(st.integers(0, 99)), draw(st.integers(0, 99)))
            )
        lines.append(draw(st.sampled_from(["G80", "G80", "N5 G80"])))
    return cam_strategies.cam_sized("\n".join(lines + ["M2"]) + "\n")


@settings(PROFILE, max_examples=PROFILE.max_examples * 2)
@given(
    st.one_of(
        back_to_back_series(),
        test_cycles.cycle_tables(),
        cam_strategies.hand_drilling(),
    )
)
def test_cancel_rows_keep_the_general_paths_calls(text):
    """A table's G80 rows (Machine.cancel_row, the end of each series of
    holes) give a canon the calls, values and error of the general path,
    and the same trace."""
    _same_as_the_general_path(
        text,
        lambda patch: patch.setattr(
            Machine,
            "cancel_row",
            lambda self, line, n: self.block(line, codes.G80, n=n),
        ),
    )


@pytest.mark.rs274
@settings(PROFILE)
@given(cam_strategies.hand_drilling())
def test_hand_drilling_matches_rs274(text):
    check_same(text, "inprocess")


@settings(PROFILE)
@given(
    cam_strategies.restating(
        cam_strategies.arc_programs() | cam_strategies.cam_programs()
    )
)
def test_rows_that_restate_modes_keep_the_general_paths_calls(text):
    """Rows of a move or arc with G90 or G17 restated beside it
    (Machine.restating_row, and the batches that read G90 G1 rows as G1
    rows) give a canon the calls, values and error of the general path,
    and the same trace."""
    from runtime.fast import rows as fast_rows

    plan = fast_rows._Plan

    def made(shape, restated=False):
        made = plan(shape)
        made.plane_arc = False  # (G17 G2 rows by block() too)
        return made

    def general(patch):
        patch.setattr(fast_rows, "_Plan", made)
        patch.setattr(
            Machine,
            "restating_row",
            lambda self, line, codes, how, n, words: self.block(
                line, *codes, n=n, **words
            ),
        )

    _same_as_the_general_path(text, general)


@pytest.mark.rs274
@settings(PROFILE)
@given(
    cam_strategies.restating(
        cam_strategies.arc_programs() | cam_strategies.cam_programs()
    )
)
def test_rows_that_restate_modes_match_rs274(text):
    check_same(text, "inprocess")


def test_values_with_four_decimals_are_written_as_printed():
    code = compile_text(FOUR_PLACES, "cam.ngc")
    assert "run_rows(m, SHAPES, ROWS_1, as_printed=True)" in code
    assert "\n3 1 1.1250 -0.5000 3.0000\n" in code


def test_a_fifth_decimal_keeps_the_table_as_written():
    code = compile_text(FOUR_PLACES.replace("Y-0.5 ", "Y-0.50001 ", 1), "cam.ngc")
    assert "run_rows(m, SHAPES, ROWS_1)" in code
    assert "\n2 1 0.125 -0.50001 3\n3 1 1.125 -0.5 3\n" in code


def test_printed_tables_give_a_canon_the_same_calls(monkeypatch):
    printed = _calls(compile_text(FOUR_PLACES, "cam.ngc"))
    monkeypatch.setattr(codegen, "as_printed", lambda rows: None)
    monkeypatch.setattr(rowtable, "printed", lambda run, text, facts: None)
    as_written = compile_text(FOUR_PLACES, "cam.ngc")
    assert "as_printed" not in as_written
    assert _calls(as_written) == printed
    assert (
        "straight_feed",
        (11.125, -0.5, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
    ) in printed


def test_converting_rows_never_reads_a_row_line_again(monkeypatch):
    """A CAM line is kept as its compact data row; any pass that asks it for
    more (its words, its error) makes the parser read the line again, which
    for a million-line file costs as much as the whole conversion."""
    from ngc2py import parser

    reads = []
    full = parser.RowLine.full
    monkeypatch.setattr(
        parser.RowLine, "full", lambda self: reads.append(self) or full(self)
    )
    lines = ["G21 G90 F300"] + ["G1 X%d.25 Y%d Z-1" % (i, i % 9) for i in range(500)]
    compile_text("\n".join(lines + ["M2"]) + "\n", "cam.ngc")
    assert reads == []


def _stretch(template: str, count: int) -> str:
    return "\n".join(template.format(k=k, x=k * 1.25, y=-k * 0.5) for k in range(count))


BATCHES = {
    # long stretches of one shape: runtime.fast.printed_rows writes each in one go
    "xy": "G21 G90 G17 F500\nG1 Z-1\n" + _stretch("X{x:.3f} Y{y:.3f}", 60) + "\nM2\n",
    "numbered_with_feed": "G90\n"
    + _stretch("N{k} G1 X{x:.2f} Z{y:.4f} F{k}1.5", 40)
    + "\nM2\n",
    "rapids_then_other_shapes": "G90\n"
    + _stretch("G0 Y{y:.1f}", 20)
    + "\n"
    + _stretch("X{x:.1f} Y{y:.1f} A{k}", 12)
    + "\nG1 F0\n"
    + _stretch("G1 X{x:.1f}", 10)
    + "\nM2\n",
    "zero_feed_inside": "G90 F100\n"
    + "\n".join("G1 X%d F%d" % (k, abs(k - 15)) for k in range(30))
    + "\nM2\n",
}


@pytest.mark.rs274
@pytest.mark.parametrize("name", sorted(BATCHES))
def test_stretches_of_one_shape_match_rs274(name):
    text = cam_strategies.cam_sized(BATCHES[name])
    assert "as_printed=True" in compile_text(text, "cam.ngc")
    check_same(text, "inprocess")


def _run_recorded(code: str, canon) -> tuple:
    """Run generated ``code`` against ``canon``: (error text or None, the
    machine's line and position afterwards)."""
    from runtime import Machine
    from runtime.errors import GCodeError
    from runtime.main import start

    namespace: dict = {"__name__": "cam"}
    exec(compile(code, "cam.py", "exec"), namespace)
    machine = Machine(canon, source=namespace["__ngc__"])
    try:
        start(machine, namespace["main"])
        error = None
    except (GCodeError, RuntimeError) as failed:
        error = str(failed)
    return error, machine.line, list(machine.current)


class _FailingCanon(RecordingCanon):
    """Records calls, and raises at the ``fail_at``-th straight move."""

    def __init__(self, fail_at: int) -> None:
        super().__init__()
        self.fail_at = fail_at
        self.moves = 0

    def straight_feed(self, *args):
        self.moves += 1
        if self.moves == self.fail_at:
            raise RuntimeError("canon failed at move %d" % self.moves)
        self._record("straight_feed", args)


_NumbersTold = test_cycles.NumbersTold  # (a canon keeping N numbers)


@PROFILE
@given(cam_strategies.cam_programs())
def test_batched_rows_give_a_canon_the_calls_of_row_by_row(text):
    """runtime.fast.rows.straight_batch (runs of one shape, applied in C) against
    the row-by-row loop: the same calls, values and N numbers, and for a
    canon keeping N numbers (numbered rows in batches too) the very
    set_block_number calls."""
    import runtime.fast.moves

    code = compile_text(text, "cam.ngc")
    for kind in (RecordingCanon, _NumbersTold):
        batched = kind()
        outcome = _run_recorded(code, batched)
        saved = runtime.fast.moves.BATCH
        runtime.fast.moves.BATCH = 10**9  # never a batch
        try:
            single = kind()
            assert _run_recorded(code, single) == outcome
        finally:
            runtime.fast.moves.BATCH = saved
        assert (batched.calls, batched.numbers) == (single.calls, single.numbers)


class _LinesRead(_NumbersTold):
    """Keeps N numbers and reads the machine's line with each call
    (``reads_lines``): each row's calls at its own line."""

    reads_lines = True
    machine = None

    def _record(self, name: str, args: tuple) -> None:
        super()._record(name, args + (self.machine.line,))


def test_numbered_rows_reach_a_canon_reading_lines_at_their_lines(monkeypatch):
    """A canon that keeps N numbers and reads lines gets numbered rows row by
    row: each call at its own row's line (a batch would be at its last)."""
    text = "G21 G90 F500\nN5 G1 X0\n" + "".join(
        "N%d X%d.5 Y%d\n" % (10 * k + 10, k, -k) for k in range(30)
    )
    code = compile_text(cam_strategies.cam_sized(text + "M2\n"), "cam.ngc")
    namespace: dict = {"__name__": "cam"}
    exec(compile(code, "cam.py", "exec"), namespace)
    canon = _LinesRead()
    canon.machine = Machine(canon, source=namespace["__ngc__"])
    from runtime.main import start

    start(canon.machine, namespace["main"])
    moved = [args[-1] for name, args in canon.calls if name == "straight_feed"]
    assert moved == sorted(set(moved)) and len(moved) == 31


@pytest.mark.parametrize("fail_at", [None, 2, 3, 5, 12])
def test_numbered_rows_reach_a_canon_keeping_numbers_in_batches(fail_at, monkeypatch):
    """Rows with N (some repeated, as posts that number blocks in tens then
    restate one write them) go in batches to a canon that keeps N numbers:
    each N told where it changes, as row by row; a move that fails stops
    where row by row stops."""
    numbers = [10, 20, 20, 30, 40, 40, 40, 50] * 3
    text = "G21 G90 F500\nN5 G1 X0\n" + "".join(
        "N%d X%d.5 Y%d\n" % (n, k, -k) for k, n in enumerate(numbers)
    )
    code = compile_text(cam_strategies.cam_sized(text + "M2\n"), "cam.ngc")
    assert "run_rows(" in code
    batches = []
    default = rows_module.call_rows

    def counted(start, stop, steps):
        batches.append(stop - start)
        default(start, stop, steps)

    monkeypatch.setattr("runtime.fast.rows.call_rows", counted)

    class Failing(_NumbersTold):
        moves = 0

        def straight_feed(self, *args):
            self.moves += 1
            if self.moves == fail_at:
                raise RuntimeError("canon failed at move %d" % self.moves)
            super().straight_feed(*args)

    batched = Failing()
    outcome = _run_recorded(code, batched)
    assert batches and max(batches) >= 8  # (the batch path was taken)
    monkeypatch.setattr("runtime.fast.moves.BATCH", 10**9)
    single = Failing()
    assert _run_recorded(code, single) == outcome
    assert (batched.calls, batched.numbers) == (single.calls, single.numbers)


@pytest.mark.parametrize("fail_at", [1, 2, 9, 17, 30])
def test_a_canon_failing_inside_a_batch_stops_where_row_by_row_stops(
    fail_at, monkeypatch
):
    text = (
        "G21 G90 F500\nG1 X0\n"
        + "".join("X%d.5 Y%d\n" % (k, -k) for k in range(30))
        + "M2\n"
    )
    code = compile_text(cam_strategies.cam_sized(text), "cam.ngc")
    assert "run_rows(" in code
    batched = _FailingCanon(fail_at)
    outcome = _run_recorded(code, batched)
    assert outcome[0] == "canon failed at move %d" % fail_at
    monkeypatch.setattr("runtime.fast.moves.BATCH", 10**9)
    single = _FailingCanon(fail_at)
    assert _run_recorded(code, single) == outcome
    assert batched.calls == single.calls


class _MovesIgnored(RecordingCanon):
    """Records every call but the straight moves, which it leaves to the
    protocol's no-ops (as NullCanon does): batches are not called at all."""

    straight_feed = Canon.straight_feed
    straight_traverse = Canon.straight_traverse


@PROFILE
@given(cam_strategies.cam_programs())
def test_a_canon_that_ignores_straight_moves_ends_in_the_same_state(text):
    """runtime.fast.rows.straight_batch skips a batch's calls when the canon's
    straight moves are Canon's no-ops: every other call, the error and the
    state after the program must be those of a canon that gets them all."""
    code = compile_text(text, "cam.ngc")
    everything = RecordingCanon()
    outcome = _run_recorded(code, everything)
    ignoring = _MovesIgnored()
    assert _run_recorded(code, ignoring) == outcome
    moves = ("straight_feed", "straight_traverse")
    assert ignoring.calls == [c for c in everything.calls if c[0] not in moves]


def test_a_batch_for_a_canon_that_ignores_straight_moves_makes_no_calls(monkeypatch):
    text = "G21 G90 F500\nG1 X0\n" + "".join("X%d.5 Y%d\n" % (k, -k) for k in range(30))
    code = compile_text(text + "M2\n", "cam.ngc")
    expected = _run_recorded(code, RecordingCanon())

    def no_calls(*args):
        raise AssertionError("the batch called the canon")

    monkeypatch.setattr("runtime.fast.rows.starmap", no_calls)
    assert _run_recorded(code, _MovesIgnored()) == expected
    assert expected[2][:2] == [29.5, -29.0]


@pytest.mark.rs274
def test_tables_cut_by_other_lines_share_their_shapes_plans(monkeypatch):
    """A program whose tables are cut by other lines (a comment on a move)
    runs many tables of one SHAPES: their plans are made once, and another
    module's SHAPES (equal, not the same) gets its own; the trace is the
    one rs274's pipeline makes."""
    from runtime.fast import rows

    made = []

    class Counting(rows._Plan):
        def __init__(self, *args):
            made.append(args[0])
            super().__init__(*args)

    monkeypatch.setattr(rows, "_Plan", Counting)
    monkeypatch.setattr(rows, "_PLANS", {})
    lines = ["G21 G90 G17 F300"]
    for k in range(6):
        lines += ["G1 X%d Y%d" % (j, k) for j in range(40)]
        lines.append("G1 X0 Y0 (pass %d)" % k)
    lines.append("M2")
    text = cam_strategies.cam_sized("\n".join(lines) + "\n")
    code = compile_text(text, "cam.ngc")
    assert code.count("run_rows(m, SHAPES") >= 6
    trace = _trace(code)
    shapes = code.count("),  # ")  # (SHAPES: a comment after each)
    assert 0 < len(made) == shapes
    assert _trace(code) == trace and len(made) == 2 * shapes  # (a module of its own)
    check_same(text, "inprocess")
