"""The canon back ends: TraceCanon's text against rs274, and the protocol.

The differential tests drive a TraceCanon directly with the calls a small
program makes and compare the printed lines with rs274's output for that
program (its lines after the six start-up calls), so the formats are
checked independently of the machine.
"""

from __future__ import annotations

import io

import pytest

import rs274 as harness
from runtime.machine import Machine
from runtime.canon import (
    BUFFERED_LINES,
    CALLS,
    Canon,
    NullCanon,
    RecordingCanon,
    TraceCanon,
)

START_LINES = 6  # rs274's start-up calls before the program's first line


def rs274_lines(program: str, tmp_path) -> list:
    if harness.rs274_path() is None:
        pytest.skip("rs274 not on PATH")
    path = tmp_path / "prog.ngc"
    path.write_text(program)
    return harness.run_rs274(path).stdout.decode().splitlines()


def traced(calls) -> list:
    """Lines a TraceCanon prints for ``calls`` = [(n, name, args)], numbered from 7."""
    out = io.StringIO()
    canon = TraceCanon(out)
    canon._count = START_LINES  # continue after rs274's start-up lines
    for n, name, args in calls:
        canon.set_block_number(n)
        getattr(canon, name)(*args)
    canon.flush()
    return out.getvalue().splitlines()


ZERO9 = (0.0,) * 9


@pytest.mark.rs274
def test_spindle_coolant_and_mode_calls(tmp_path):
    expected = rs274_lines(
        "N7 S1200 M3\nM4\nM5\nM7\nM8\nM9\nG61\nG61.1\nG64 P0.25\nG96 S10\nM2\n",
        tmp_path,
    )
    calls = [
        ("7", "set_spindle_speed", (0, 1200.0)),
        ("7", "start_spindle_clockwise", (0,)),
        (None, "start_spindle_counterclockwise", (0,)),
        (None, "stop_spindle_turning", (0,)),
        (None, "mist_on", ()),
        (None, "flood_on", ()),
        (None, "mist_off", ()),
        (None, "flood_off", ()),
        (None, "set_motion_control_mode", ("EXACT_PATH", 0.0)),
        (None, "set_motion_control_mode", ("EXACT_STOP", 0.0)),
        (None, "set_motion_control_mode", ("CONTINUOUS", 0.25)),
        (None, "set_naivecam_tolerance", (0.25,)),
        (None, "set_spindle_mode", (0, 1e30)),
        (None, "set_spindle_speed", (0, 10.0)),
    ]
    lines = traced(calls)
    assert lines == expected[START_LINES : START_LINES + len(lines)]


@pytest.mark.rs274
def test_motion_and_tool_calls(tmp_path):
    expected = rs274_lines(
        "N0042 G0 X1 Y-2 Z3.12345\nF12.5 G2 X3 Y-2 R1\nG4 P2\nG43.1 Z-1.5\nM62 P3\nM67 E1 Q2.5\nM2\n",
        tmp_path,
    )
    calls = [
        (
            "0042",
            "straight_traverse",
            (1.0, -2.0, 3.12345, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
        ),
        (None, "set_feed_rate", (12.5,)),
        (
            None,
            "arc_feed",
            (3.0, -2.0, 2.0, -2.0, -1, 3.12345, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
        ),
        (None, "dwell", (2.0,)),
        (
            None,
            "use_tool_length_offset",
            (0.0, 0.0, -1.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
        ),
        (None, "set_motion_output_bit", (3,)),
        (None, "set_motion_output_value", (1, 2.5)),
    ]
    lines = traced(calls)
    assert lines == expected[START_LINES : START_LINES + len(lines)]


@pytest.mark.rs274
def test_start_up_lines(tmp_path):
    expected = rs274_lines("M2\n", tmp_path)
    out = io.StringIO()
    canon = TraceCanon(out)
    canon.use_length_units(False)
    canon.set_g5x_offset(1, *ZERO9)
    canon.set_g92_offset(*ZERO9)
    canon.set_xy_rotation(0.0)
    canon.set_feed_reference(False)
    canon.on_reset()
    canon.flush()
    assert out.getvalue().splitlines() == expected[:START_LINES]


def test_n_column_pads_to_six_and_never_truncates():
    out = io.StringIO()
    canon = TraceCanon(out)
    canon.set_block_number("10")
    canon.program_end()
    canon.set_block_number("1234567")
    canon.program_end()
    canon.set_block_number(None)
    canon.program_end()
    canon.flush()
    assert out.getvalue().splitlines() == [
        "    1 N10    PROGRAM_END()",
        "    2 N1234567PROGRAM_END()",
        "    3 N..... PROGRAM_END()",
    ]


def test_trace_canon_implements_every_call():
    for name in CALLS:
        assert getattr(TraceCanon, name) is not getattr(Canon, name), name


def test_recording_canon_keeps_calls_and_block_numbers():
    canon = RecordingCanon()
    canon.set_block_number("5")
    canon.straight_feed(1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    canon.set_block_number(None)
    canon.comment("hi")
    assert canon.calls == [
        ("straight_feed", (1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)),
        ("comment", ("hi",)),
    ]
    assert canon.numbers == ["5", None]


def test_null_canon_accepts_every_call():
    canon = NullCanon()
    for name in CALLS:
        method = getattr(canon, name)
        arity = method.__code__.co_argcount - 1
        assert method(*([0] * arity)) is None


def test_trace_lines_are_written_in_batches_and_all_by_flush():
    # The trace keeps lines back (a write per line costs as much as the
    # formatting); nothing may be lost or reordered, whatever the count.
    out = io.StringIO()
    canon = TraceCanon(out)
    total = 3 * BUFFERED_LINES + 7
    for k in range(total):
        if k % 3 == 0:
            canon.straight_feed(float(k), *ZERO9[1:])
        elif k % 3 == 1:
            canon.set_feed_rate(float(k))
        else:
            canon.print_text("text %d" % k)
    written = out.getvalue().splitlines()
    assert 0 < len(written) < total  # batches went out on the way
    canon.flush()
    lines = out.getvalue().splitlines()
    assert len(lines) == total
    assert lines[: len(written)] == written
    assert [line.split()[0] for line in lines[:2]] == ["1", "2"]
    assert lines[2] == "text 2" and lines[-1].startswith("%5d" % (total - total // 3))


#: Programs whose moves reach a canon in batches: a CAM table, a contour
#: (arcs with lines between), a series of drilled holes.
BATCHED = {
    "rows": "G21 G1 F500\n"
    + "".join("X%d.5 Y%d\n" % (k, k % 7) for k in range(300))
    + "M2\n",
    "contour": "G21 G0 X0 Y0\nG1 F500\n"
    + "".join(
        (
            "G2 X%d Y0 R0.5\nG1 X%d.5\n" % (k + 1, k + 1)
            if k % 2
            else "G3 X%d Y0 R0.6\n" % (k + 1)
        )
        for k in range(200)
    )
    + "M2\n",
    "holes": "G21 G0 Z5\nF100\nG99 G81 X0 Y0 Z-1 R1\n"
    + "".join("X%d Y%d\n" % (k, k % 3) for k in range(1, 60))
    + "G80\nM2\n",
}


#: the call that raises: one inside a batch (the holes' first is drilled alone)
AT = 150


def breaking(base: type, raised: type, made: list) -> type:
    """A canon class of ``base`` whose moves are kept in ``made`` and whose
    move number AT raises ``raised``."""

    class Broken(base):
        def _move(self, *args):
            made.append(args)
            if len(made) == AT:
                raise raised("canon broke")

        straight_feed = straight_traverse = arc_feed = _move

    return Broken


def raises(raised: type):
    """What a run raises for a canon's ``raised``: StopIteration becomes a
    RuntimeError in a batch, and comes out as it is from a call made alone."""
    if raised is StopIteration:
        return pytest.raises((RuntimeError, StopIteration))
    return pytest.raises(raised, match="canon broke")


@pytest.mark.parametrize("program", sorted(BATCHED))
@pytest.mark.parametrize("raised", [ValueError, StopIteration])
def test_a_canon_exception_in_a_batch_stops_the_run_at_that_call(
    tmp_path, program, raised
):
    """A user's canon that defines only straight_feed & co. gets batches one
    call a move (Canon.straight_moves, the rows' C loops): its exception
    stops the run at the very call. A StopIteration (a ``next()`` on an
    iterator of its own run out) is neither swallowed by the iterator a
    batch's calls are made from (there it becomes a RuntimeError) nor taken
    for the step budget running out (runtime.budget)."""
    from test_not_copied import compiled

    module = compiled(BATCHED[program], tmp_path)
    made: list = []
    with raises(raised):
        Machine(breaking(Canon, raised, made)(), source=module.__ngc__).run(module.main)
    assert len(made) == AT


class _Stopping(Canon):
    """Raises at the ``at``-th call of ``name`` (a user's canon stopping a
    simulation at a collision); takes the protocol's default batches."""

    def __init__(self, name: str, at: int) -> None:
        self.name, self.at, self.made = name, at, 0

    def _made(self, name: str) -> None:
        if name == self.name:
            self.made += 1
            if self.made == self.at:
                raise RuntimeError("collision")

    def arc_feed(self, *args):
        self._made("arc_feed")

    def straight_feed(self, *args):
        self._made("straight_feed")

    def dwell(self, *args):
        self._made("dwell")


class _StoppingRowByRow(_Stopping):
    reads_lines = True  # (each row's calls alone, at its line: the reference)


_CONTOUR = ("G2 X10 Y0 R6", "G1 X12", "G3 X2 Y0 I-5 J0", "G1 X0") * 10
_HOLES = ["G99 G82 X1 Y1 Z-1 R2 P0.5"] + ["X%d Y%d" % (k, k % 3) for k in range(2, 40)]


@pytest.mark.parametrize(
    "rows, name, at",
    [
        (_CONTOUR, "arc_feed", 7),
        (_CONTOUR, "straight_feed", 9),
        (_HOLES, "dwell", 12),
    ],
)
def test_a_canon_raising_in_a_batch_names_the_row_that_failed(rows, name, at):
    """A canon's exception in the middle of a default batch (the arcs of a
    contour, holes) names the row whose call raised, and leaves the
    machine at its line, as one row at a time does."""
    from cam_strategies import cam_sized
    from ngc2py.compiler import compile_text
    from runtime import start
    from runtime.errors import locate

    text = cam_sized("G21 G17 F100\nG0 X0 Y0 Z5\n%s\nG80\nM2\n" % "\n".join(rows))
    namespace: dict = {"__name__": "stopping"}
    exec(compile(compile_text(text, "stop.ngc"), "stop.py", "exec"), namespace)
    found = []
    for kind in (_Stopping, _StoppingRowByRow):
        machine = Machine(kind(name, at), source=namespace["__ngc__"])
        with pytest.raises(RuntimeError) as raised:
            start(machine, namespace["main"])
        found.append((locate(raised.value)[-1].line, machine.line))
    assert found[0] == found[1]
    assert found[0][0] == found[0][1] < len(text.splitlines()) - 5
