"""The parser's fast lane for CAM rows (ngc2py/rowrun.py) and the bulk
table writer (ngc2py/rowtable.py).

The lane reads regions of lines by their templates and must give every
program the very module the line-by-line reader gives it; programs of CAM
rows with odd lines mixed in (tests/cam_strategies.py: comments,
parameters, bad numbers, N words, blanks, case, block delete, CR, long
lines, checked values) are compiled both ways, with the region, table and
chunk sizes made small so that every cut is crossed, and run against
rs274.
"""

from __future__ import annotations

from contextlib import ExitStack
from unittest import mock

import pytest
from hypothesis import Phase, given, settings
from hypothesis import strategies as st

import cam_strategies
from ngc2py import codegen, parser, rowrun, rowtable
from ngc2py.compiler import compile_text
from test_differential import PROFILE, check_same

#: (region bytes, fewest lines for the lane, rows per table, statements per
#: chunk): small enough that generated programs cross every cut.
SIZES = st.tuples(
    st.integers(30, 3000), st.integers(1, 6), st.integers(2, 40), st.integers(2, 12)
)


def _sizes(stack: ExitStack, sizes) -> None:
    region, least, table, chunk = sizes
    stack.enter_context(mock.patch.object(rowrun, "REGION_BYTES", region))
    stack.enter_context(mock.patch.object(rowrun, "MIN_LINES", least))
    stack.enter_context(mock.patch.object(codegen, "ROWS_PER_TABLE", table))
    stack.enter_context(mock.patch.object(codegen, "CHUNK_STATEMENTS", chunk))


def _both(text: str):
    return compile_text(text, "cam.ngc"), compile_text(text, "cam.ngc", runs=False)


#: Derandomised and not shrunk, as the ci profile (tests/test_differential.py).
QUICK = settings(
    deadline=None,
    derandomize=True,
    database=None,
    phases=[Phase.explicit, Phase.generate],
)


@settings(QUICK, max_examples=150)
@given(cam_strategies.odd_cam_programs(), SIZES)
def test_the_lane_writes_the_module_the_line_reader_writes(text, sizes):
    with ExitStack() as stack:
        _sizes(stack, sizes)
        fast, slow = _both(text)
    assert fast == slow


@settings(QUICK, max_examples=50)
@given(cam_strategies.cam_programs())
def test_the_lane_on_plain_cam_programs(text):
    fast, slow = _both(text)
    assert fast == slow


@pytest.mark.skipif(
    rowrun.line_templates is rowrun.python_line_templates,
    reason="ngc2py._rowtext not built",
)
@given(
    st.lists(st.sampled_from(list(b"GgMmHhLlTtXxNn0123456789.+- \t\r\n")), max_size=80)
)
def test_the_templates_made_in_c_are_the_python_ones(region):
    """ngc2py._rowtext.line_templates against the regular expression and
    bytes passes it stands for, on lines of the lane's bytes (the checked
    words' digits, signs and points in every order)."""
    region = bytes(region)
    assert rowrun.line_templates(region) == rowrun.python_line_templates(region)
    region += b"\n"
    assert rowrun.line_templates(region) == rowrun.python_line_templates(region)


@pytest.mark.skipif(rowtable._printed_rows is None, reason="ngc2py._rowtext not built")
@settings(QUICK, max_examples=150)
@given(cam_strategies.odd_cam_programs(), SIZES)
def test_the_one_pass_rows_are_the_bytes_operations_rows(text, sizes):
    """ngc2py/_rowtext.c writes a run's rows as rowtable.py's bytes
    operations write them, or leaves the run to them."""
    with ExitStack() as stack:
        _sizes(stack, sizes)
        quick = compile_text(text, "cam.ngc")
        stack.enter_context(mock.patch.object(rowtable, "_printed_rows", None))
        assert compile_text(text, "cam.ngc") == quick


@pytest.mark.skipif(rowtable._printed_rows is None, reason="ngc2py._rowtext not built")
def test_which_runs_the_one_pass_takes():
    """Plain values (signs, a point first, integers, blanks between words,
    N numbers, lower case) take the one pass; a leading zero or a fifth
    decimal leave the run to the bytes operations, as do values of any
    other form."""

    def quick(rows: str):
        (run,) = [i for i in _items(rows * 6 + "M2\n") if type(i) is rowrun.RowRun]
        index = {kind: kind for kind in set(run.kinds)}
        return rowtable.quick_rows(run, index)

    assert quick("G1 X1 Y-.5 Z+2.25\n") == "\n".join(
        "%d 0 1.0000 -0.5000 2.2500" % k for k in range(1, 7)
    )
    assert quick("n0010 g1 x12.5 y-0\n").startswith("1 0 0010 12.5000 -0.0000\n2 0")
    assert quick("  G1 \tX1 \tY2\n").startswith("1 0 1.0000 2.0000\n2 0")
    assert quick("G0 X10.1234\n") is not None
    for odd in ("G0 X010\n", "G0 X1.23456\n", "G0 X123456789012\n"):
        assert quick(odd) is None, odd


@pytest.mark.rs274
@settings(PROFILE, max_examples=PROFILE.max_examples * 3)
@given(cam_strategies.odd_cam_programs(failing=False), SIZES)
def test_odd_cam_programs_run(text, sizes):
    with ExitStack() as stack:
        _sizes(stack, sizes)
        check_same(text, "inprocess")


@pytest.mark.rs274
@settings(PROFILE, max_examples=PROFILE.max_examples * 2)
@given(cam_strategies.odd_cam_programs(), SIZES)
def test_odd_cam_programs_that_may_fail_run(text, sizes):
    with ExitStack() as stack:
        _sizes(stack, sizes)
        check_same(text, "inprocess")


@pytest.mark.rs274
@PROFILE
@given(cam_strategies.odd_cam_programs())
def test_odd_cam_programs_converted(text):
    check_same(text, "convert")


# -- the lane's own decisions ------------------------------------------------


def _items(text: str):
    return parser.parse_text(text, "cam.ngc", runs=True).lines


def _kinds(text: str):
    return [type(item).__name__ for item in _items(text)]


ROWS = "".join("G1 X%d.5 Y-%d\n" % (k, k) for k in range(6))


def test_a_stretch_of_rows_is_one_run():
    items = _items("G21 G90 F500\n" + ROWS + "M2\n")
    assert [type(i).__name__ for i in items] == ["RowRun", "Line"]
    run = items[0]
    assert (run.number, run.count) == (1, 7)
    assert [line.text for line in run.lines()] == ["G21 G90 F500"] + ROWS.split("\n")[
        :6
    ]
    assert run.final().number == 7


def test_lines_the_lane_leaves_to_the_line_reader():
    odd = [
        "G1 X1 ",  # trailing blank: its text is stripped
        "F-5",  # a negative F fails ...
        "F-0",  # ... but -0 does not: same template, not a row here
        "G1 X1.2.3",  # not a number
        "",  # blank
        "x" * 253,  # too long for rs274's buffer
        "G1 N5 X1",  # N not first
    ]
    for line in odd:
        kinds = _kinds(ROWS + line + "\n" + ROWS + "M2\n")
        assert kinds[0] == kinds[2] == "RowRun" and kinds[1] != "RowRun", line


def test_cr_line_ends_and_lone_crs():
    crlf = (ROWS + "M2\n").replace("\n", "\r\n")
    items = _items(crlf)
    assert _kinds(crlf) == ["RowRun", "Line"]
    assert "\r" not in items[0].text()
    lone = ROWS + "G1 X1\rY2\n" + ROWS + "M2\n"
    assert _kinds(lone)[1] == "Line"
    assert _items(lone)[1].text == "G1 X1\rY2"


def test_templates_keep_checked_values():
    """G, M, H, L and T values decide a line's shape and checks: lines that
    differ only there are different kinds."""
    text = "G0 X1\nG1 X1\nT1\nT2\nG0 X1\nG1 X2\nM2\n"
    run = _items(text)[0]
    shapes = [run.lane.kind_shapes[kind] for kind in run.kinds]
    assert shapes[0] != shapes[1] and shapes[0] == shapes[4] and shapes[1] == shapes[5]
    assert len(set(run.kinds[2:4])) == 2


def test_rows_tables_from_runs_are_the_line_readers():
    numbered = "".join(
        "N%04d G1 X%d.25 Y%d F%d\n" % (k, k, -k, 100 + k) for k in range(12)
    )
    mixed = ROWS + "N7 X1\n" + ROWS + "X1.23456\n" + "M2\n"
    for text in (numbered + "M2\n", mixed, ROWS * 3 + "X+.5 Y-.5 Z5.\n" * 9 + "M2\n"):
        fast, slow = _both(cam_strategies.cam_sized(text))
        assert fast == slow
        assert "ROWS_1" in fast


def test_a_cam_file_is_read_once_per_template(monkeypatch):
    """The lane reads one line of each new template; the rows of a table are
    never read one by one again (not by the parser, the structure pass or
    the code generator)."""
    reads = []
    read = parser.read_row_line
    monkeypatch.setattr(
        parser, "read_row_line", lambda *args: reads.append(args[0]) or read(*args)
    )
    monkeypatch.setattr(rowrun.RowRun, "lines", lambda self: pytest.fail("read again"))
    rows = ["G1 X%d.%03d Y-%d.5 Z%d" % (k, k % 1000, k % 7, k % 3) for k in range(3000)]
    code = compile_text("G21 G90 F300\n" + "\n".join(rows) + "\nM2\n", "cam.ngc")
    assert "ROWS_1" in code
    assert len(reads) < 30
