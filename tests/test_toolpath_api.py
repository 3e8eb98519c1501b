"""``ngc2py.toolpath()``: a program's moves as NumPy arrays.

The arrays are held to ``runtime.toolpath.ToolpathCanon`` taking the same
program one call a move (the path ``ngc2py stats`` measures, itself held to
rs274's trace): the recorder takes batches of columns from the fast paths,
so every row, start, centre, line number and length must come out the same.
"""

from __future__ import annotations

import argparse
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import cam_strategies
import test_cycles
from test_differential import PROFILE
from test_stats import scratch_run

import ngc2py
from ngc2py.simulate import run_program
from ngc2py.moves import ARC, FEED, PROBE, RAPID, ProgramError, toolpath
from runtime.toolpath import ToolpathCanon, distance

KIND = {"rapid": RAPID, "feed": FEED, "probe": PROBE}


class OneByOne(ToolpathCanon):
    """The reference: one call a move, each kept as Python values."""

    def __init__(self) -> None:
        super().__init__()
        self.machine = None
        self.moves = []
        self.feeds = []
        self.rate = 0.0

    def set_feed_rate(self, rate):
        self.rate = self.to_mm(rate)

    def line(self, kind, start, end):
        self.moves.append(
            (KIND[kind], start, end, None, self.machine.line, distance(start, end))
        )
        self.feeds.append(math.nan if kind == "rapid" else self.rate)

    def arc(self, arc):
        self.moves.append((ARC, arc.start, arc.end, arc, self.machine.line, arc.length))
        self.feeds.append(self.rate)


def reference(program: str) -> OneByOne:
    """The moves of ``program`` made one call a move, with no batch (whose
    calls come with the lines as a column, not one by one)."""
    import runtime.fast.arc_rows
    import runtime.fast.moves
    import runtime.fast.rows

    canon = OneByOne()
    canon.reads_lines = True
    with pytest.MonkeyPatch.context() as patch:
        for module, name in (
            (runtime.fast.moves, "BATCH"),
            (runtime.fast.rows, "BATCH"),
            (runtime.fast.arc_rows, "_BATCH"),
        ):
            patch.setattr(module, name, 10**9)
        run_reference(program, canon)
    return canon


def run_reference(program: str, canon: OneByOne) -> None:

    def bind(machine):
        canon.machine = machine

    args = argparse.Namespace(
        program=program, tool_table=None, var_file=None, ini=None, block_delete=False
    )
    run_program(args, canon, on_machine=bind)


def compare(tmp_path, text: str) -> None:
    program = tmp_path / "prog.ngc"
    program.write_text(text)
    with scratch_run(program) as s:
        expected = reference(s.program.name)
        try:
            path = toolpath(s.program.name)
        except ProgramError as error:
            path = error.toolpath
    moves = expected.moves
    assert len(path) == len(moves)
    assert path.units == ("inch" if expected.first_units else "mm")
    if not moves:
        return
    assert path.kind.tolist() == [m[0] for m in moves]
    assert path.line.tolist() == [m[4] for m in moves]
    # the rate in force at each move: a batch must not outrun an F word
    assert np.array_equal(path.feed, np.array(expected.feeds), equal_nan=True)
    assert np.array_equal(path.start, np.array([m[1] for m in moves]))
    assert np.array_equal(path.end, np.array([m[2] for m in moves]))
    np.testing.assert_allclose(
        path.length, [m[5] for m in moves], rtol=1e-12, atol=1e-12
    )
    rows, first, second, theta0, sweep, r0, r1 = path.arc_frame()
    arcs = [m[3] for m in moves if m[3] is not None]
    assert len(rows) == len(arcs)
    for k, arc in enumerate(arcs):
        assert (first[k], second[k], path.normal[rows[k]]) == arc.axes
        assert tuple(path.centre[rows[k]]) == arc.centre
        assert sweep[k] == pytest.approx(arc.sweep, rel=1e-12, abs=1e-12)
        assert (r0[k], r1[k]) == pytest.approx((arc.r0, arc.r1), rel=1e-12)
    straight = path.kind != ARC
    assert np.isnan(path.centre[straight]).all()
    assert (path.normal[straight] == -1).all() and (path.turns[straight] == 0).all()


@PROFILE
@given(cam_strategies.cam_programs())
def test_cam_programs_give_the_moves_of_one_call_a_move(tmp_path_factory, text):
    compare(tmp_path_factory.mktemp("cam"), text)


@settings(PROFILE, max_examples=PROFILE.max_examples * 2)
@given(cam_strategies.arc_programs())
def test_arc_programs_give_the_moves_of_one_call_a_move(tmp_path_factory, text):
    compare(tmp_path_factory.mktemp("arcs"), text)


@PROFILE
@given(st.one_of(test_cycles.cycle_tables(), test_cycles.restated_cycle_lines()))
def test_cycle_tables_give_the_moves_of_one_call_a_move(tmp_path_factory, text):
    """Holes in batches (Recorder.hole_moves) against one call a move."""
    compare(tmp_path_factory.mktemp("holes"), text)


@pytest.mark.parametrize("inches", [False, True])
def test_holes_that_climb_to_r_first_where_the_tool_was(tmp_path, inches):
    """From below R (the series' initial level), each hole first goes
    straight up where the tool was, the hole before's place (the first's,
    the tool's before the series): Recorder.hole_moves' moves at the start,
    against one call a move."""
    rows = "\n".join("X%d Y%d" % (k, k % 3) for k in range(2, 40))
    units = "G20" if inches else "G21"
    compare(
        tmp_path,
        cam_strategies.cam_sized(
            units
            + " G17 F100\nG0 X-3 Y-4 Z0\nG98 G81 X1 Y1 Z-2 R1\n"
            + rows
            + "\nG80\nM2\n"
        ),
    )


def test_offsets_units_cycles_and_probes(tmp_path):
    compare(
        tmp_path,
        "G20 G0 X1 Y1\nG1 Z-0.1 F10\nG92 X0 Y0\nG1 X1\nG21 G55 G0 X5\n"
        "G10 L2 P2 X3\nG0 Y2\nG81 X1 Y1 Z-1 R1 F100\nX2\nG80\n"
        "G38.2 Z-10 F50\nG18 G2 X0 Z0 I-1 K0\nG52 X2\nG17 G3 X3 Y0 R1 P2\nM2\n",
    )


def test_feed_tool_and_line_of_each_move(tmp_path):
    program = tmp_path / "p.ngc"
    program.write_text(
        "G21 F300\nT2 M6\nG0 X1\nG1 X2\nF500\nG2 X4 Y0 I1 J0\nT1 M6\nG1 Y3\nM2\n"
    )
    with scratch_run(program) as s:
        path = ngc2py.toolpath(s.program.name)
    assert path.line.tolist() == [3, 4, 6, 8]
    assert path.tool.tolist() == [2, 2, 2, 1]
    assert math.isnan(path.feed[0])
    assert path.feed[1:].tolist() == [300.0, 500.0, 500.0]
    assert path.kind.tolist() == [RAPID, FEED, ARC, FEED]
    assert path.centre[2].tolist() == [3.0, 0.0]
    assert path.turns[2] == -1 and path.normal[2] == 2


def test_inch_programs_are_in_millimetres(tmp_path):
    program = tmp_path / "p.ngc"
    program.write_text("G20\nF10\nG1 X1 Y2\nG3 X2 Y3 R1\nM2\n")
    with scratch_run(program) as s:
        path = ngc2py.toolpath(s.program.name)
    assert path.units == "inch"
    assert path.end[0, :2].tolist() == [25.4, 50.8]
    assert path.feed[0] == pytest.approx(254.0)


def test_an_error_gives_rs274s_report_and_the_moves_before(tmp_path):
    program = tmp_path / "p.ngc"
    program.write_text("G21 G0 X1\nG1 X2 F100\nG1 X3 F0\nM2\n")
    with scratch_run(program) as s:
        with pytest.raises(ProgramError) as caught:
            ngc2py.toolpath(s.program.name)
    assert str(caught.value).startswith("Cannot do g1 with zero feed rate")
    assert str(caught.value).endswith("at p.ngc:3:1")
    assert caught.value.toolpath.end[:, 0].tolist() == [1.0, 2.0]
