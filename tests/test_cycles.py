"""Canned cycles: tables of hole rows, and where rs274 has no usable answer.

Cycles are pinned by golden/cycles (recorded from rs274) and the
differential tests. Here: tables of rows of hole words under a modal cycle
against rs274, and the replay of recorded holes (runtime.fast.hole_rows)
against the reference path for any canon; and a G73/G83 peck so small that
subtracting it no longer changes the depth, which makes rs274 peck at one
depth forever, printing without end -- too much output to record as a
golden ``.expect``. ngc2py must stop with a clear error after the first
peck instead.
"""

from __future__ import annotations

import io
import os
import subprocess
import tempfile
import time
from typing import List

import pytest
from hypothesis import given
from hypothesis import strategies as st

import rs274 as harness
from cam_strategies import cam_sized
from ngc2py.compiler import compile_text
from runtime import Machine, start
from runtime.canon import RecordingCanon
from runtime.errors import GCodeError
from runtime.canon import TraceCanon
from runtime.fast import hole_rows
from runtime.fast.hole_rows import HoleRows
from test_differential import PROFILE, check_same

#: Z starts at 1; Q is 1e-19, so 1 - Q == 1 in a double.
PROGRAM = "G21 F100\nG0 Z5\nG{code} X1 Z-1 R1 Q[1/10000000000000000000]\nM2\n"


@pytest.mark.parametrize("code", ["73", "83"])
def test_tiny_peck_is_an_error_not_a_hang(code, tmp_path):
    program = tmp_path / "tiny_peck.ngc"
    program.write_text(PROGRAM.format(code=code))
    result = harness.run_ngc2py(program, mode="inprocess", timeout=60)
    assert result.rc == 1
    assert (
        result.err
        == f"Q value too small with g{code}: the pecks never reach the bottom"
    )
    # The first peck is made, then the error: the first feed to depth 1 is the last one.
    lines = result.stdout.decode().splitlines()
    assert sum("STRAIGHT_FEED(1.0000, 0.0000, 1.0000" in line for line in lines) == 1


@pytest.mark.rs274
def test_rs274_pecks_forever_there(tmp_path):
    """The reason for the test above: rs274 is still pecking after seconds,
    having printed the same peck thousands of times."""
    if harness.rs274_path() is None:
        pytest.skip("rs274 not on PATH")
    program = tmp_path / "tiny_peck.ngc"
    program.write_text(PROGRAM.format(code="83"))
    home = tempfile.mkdtemp(dir=tmp_path)
    with open(tmp_path / "out.txt", "wb") as out:
        proc = subprocess.Popen(
            [harness.rs274_path(), "-g", program.name],
            cwd=tmp_path,
            stdout=out,
            stderr=subprocess.DEVNULL,
            env={**os.environ, "HOME": home},
        )
        try:
            deadline = time.monotonic() + 3.0
            while time.monotonic() < deadline and proc.poll() is None:
                if (tmp_path / "out.txt").stat().st_size > 2_000_000:
                    break
                time.sleep(0.05)
            still_running = proc.poll() is None
        finally:
            proc.kill()
            proc.wait()
    assert still_running
    with open(tmp_path / "out.txt", "rb") as out:
        head = out.read(2_000_000).decode("utf-8", "replace")
    assert head.count("STRAIGHT_FEED(1.0000, 0.0000, 1.0000") > 1000


@st.composite
def cycle_tables(draw) -> str:
    """A canned cycle, then a table of rows of hole words alone (what
    Machine.cycle_row takes from runtime.fast.rows, and runtime.fast.hole_rows
    replays): X/Y/Z/R/P/Q/L/F in changing layouts, G90 or G91, G98 or G99,
    mm or inches, in every plane, every drilling cycle (taps, G87's offsets,
    G88's stop), a start below the R plane, the same hole twice, now and
    then a row whose R falls below its Z (rs274's error, at that row), and
    lines between rows that change a mode but keep the cycle (distance mode,
    retract mode, feed, speed): the first hole after such a line may begin
    at another level than the next ones; now and then every line has an N."""
    plane, first, second, hole = draw(
        st.sampled_from(
            [("G17", "X", "Y", "Z"), ("G18", "Z", "X", "Y"), ("G19", "Y", "Z", "X")]
        )
    )
    code = draw(
        st.sampled_from(
            [
                "G81",
                "G82",
                "G83",
                "G73",
                "G85",
                "G86",
                "G89",
                "G84",
                "G74",
                "G87",
                "G88",
            ]
        )
    )
    incremental = draw(st.integers(0, 3)) == 0
    retract = draw(st.sampled_from(["G98", "G99"]))
    r = draw(st.integers(0, 30)) / 10
    bottom = (
        -draw(st.integers(1, 30)) / 10
        if incremental
        else r - draw(st.integers(1, 30)) / 10
    )
    words = ["%s%.3f" % (hole, bottom), "R%.2f" % r]
    if code in ("G82", "G86", "G89", "G84", "G74", "G88"):
        words.append("P0.5")
    if code in ("G73", "G83"):
        words.append("Q%.2f" % (draw(st.integers(3, 20)) / 10))
    if code == "G87":
        words.append("I0.5 J0.3 K%.2f" % (bottom + 0.5 if incremental else 0.5))
    units = draw(st.sampled_from(["G21", "G20"]))
    spindle = "M4" if code == "G74" else "M3"
    start = draw(st.sampled_from(["5", "5", "-1"]))  # -1: below the R plane
    lines = [
        "%s G90 %s F300" % (units, plane),
        spindle + " S1000",
        "G0 %s%s" % (hole, start),
    ]
    # the cycle's own line as CAM posts write it, which tells the replay what
    # the rows after it make (runtime.fast.hole_rows._Capture), or with an N,
    # F or L that keep it from telling
    distance = "G91" if incremental else "G90"
    form = draw(st.integers(0, 5))
    if form == 1:
        lines.append(distance)
        distance = ""
    elif form == 2:
        words.append("F%d" % draw(st.integers(50, 900)))
    elif form == 3:
        words.append("L%d" % draw(st.integers(1, 3)))
    cycle_line = " ".join(filter(None, [distance, retract, code] + words))
    if form == 4:
        cycle_line = "N%d %s" % (draw(st.integers(1, 999)), cycle_line)
    lines.append(cycle_line)
    # or the cycle's own line restated at every hole, as some posts write
    # them (runtime.fast.hole_rows.HoleRows.restated), now and then with a
    # word changed, another retract mode or a row of hole words between
    restate = draw(st.integers(0, 2)) == 0
    rows: List[str] = []
    for k in range(draw(st.integers(8, 40))):
        shape = draw(st.integers(0, 9))
        row = []
        if shape != 0:
            row.append("%s%.3f" % (first, draw(st.integers(-500, 500)) / 10))
        if shape in (0, 1, 2, 3, 4) or not row:
            row.append("%s%.3f" % (second, draw(st.integers(-500, 500)) / 10))
        if shape == 9 and len(lines) > 4:
            row = lines[-1].split()  # the same hole again
        elif restate and draw(st.integers(0, 5)):
            again = cycle_line.split()
            row = [
                "%s%.3f" % (axis, draw(st.integers(-500, 500)) / 10)
                for axis in (first, second)
            ]
            change = draw(st.integers(0, 15))
            if change == 1:
                again = [
                    "G99" if w == "G98" else "G98" if w == "G99" else w for w in again
                ]
            elif change == 2:
                again.append("F%d" % draw(st.integers(50, 900)))
            elif change == 3:
                again = [("R%.2f" % (r + 0.5)) if w[0] == "R" else w for w in again]
            codes = [w for w in again if w[0] in "GN"]
            row = codes + row + [w for w in again if w[0] not in "GN"]
        extra = draw(st.integers(0, 12))
        if extra == 1:
            row.append("F%d" % draw(st.integers(50, 900)))
        elif extra == 2 and incremental:
            row.append("L%d" % draw(st.integers(1, 3)))
        elif extra == 3:
            row.append("R%.2f" % (r + 0.5))
        elif extra == 4 and draw(st.integers(0, 3)) == 0:
            row.append("R%.2f %s%.2f" % (r - 5, hole, r - 1))  # R below Z: an error
        elif extra == 5 and draw(st.integers(0, 2)) == 0:
            # a P, Q or L the cycle may not use (rs274's error, at that row)
            row.append(draw(st.sampled_from(["P0.2", "Q0.5", "L1"])))
        if draw(st.integers(0, 7)) == 0:
            lines.append(
                draw(st.sampled_from(["G90", "G91", "G98", "G99", "F200", "S800"]))
            )
        lines.append(" ".join(row))
        rows.append(lines[-1])
    if draw(st.booleans()):
        lines.append("(debug, at #5420 #5421 #5422)")  # the last hole, published
    lines += ["G80", "G90"]
    if draw(st.integers(0, 2)) == 0:
        # a second series drilled alike, the rotary axes at -0 or 0 now: its
        # trace (pieces of the first's template) prints them apart
        rotary = draw(st.sampled_from(["A-0", "A0", "B-0 C-0", "A0.5"]))
        mode = "G91" if incremental else "G90"
        lines += ["G0 %s%s %s" % (hole, start, rotary), mode, cycle_line]
        lines += rows[: draw(st.integers(1, len(rows)))]
        lines += ["G80", "G90"]
    lines.append("M2")
    if draw(st.integers(0, 3)) == 0:
        # every line numbered, as some posts write them: rows of hole words
        # with their N (the replay writes each hole's own), now and then
        # two alike, a long one or leading zeros
        number = draw(st.integers(0, 50))
        for k, line in enumerate(lines):
            if line.startswith(("(", "N")):
                continue
            number += draw(st.sampled_from([10, 10, 10, 1, 0, 12345678]))
            digits = draw(st.sampled_from(["%d", "%d", "%d", "%04d"])) % number
            lines[k] = "N%s %s" % (digits, line)
    text = "\n".join(lines) + "\n"
    return cam_sized(text) if draw(st.integers(0, 3)) else text


@st.composite
def restated_cycle_lines(draw) -> str:
    """A canned cycle's own line written again at every hole, the X and Y
    alone changing (``G99 G81 X.. Y.. Z-3 R2``, as some posts write every
    hole), which runtime.fast.hole_rows.HoleRows.restated replays: in every
    plane and unit, every drilling cycle, F on every line or not, now and then a line with a word
    changed (R, the depth, F, L, the retract mode), a row of hole words, a
    cancel and a new start, the same hole twice, or G91 for a while; every
    line numbered or none."""
    plane, first, second, hole = draw(
        st.sampled_from(
            [("G17", "X", "Y", "Z"), ("G18", "Z", "X", "Y"), ("G19", "Y", "Z", "X")]
        )
    )
    code = draw(st.sampled_from(["G81", "G82", "G83", "G73", "G85", "G86", "G89"]))
    code += {"G82": " P0.5", "G86": " P0.2", "G89": " P0.3"}.get(code, "")
    code += " Q%.2f" % (draw(st.integers(3, 20)) / 10) if code in ("G83", "G73") else ""
    retract = draw(st.sampled_from(["G98", "G99"]))
    r = draw(st.integers(0, 30)) / 10
    words = "%s%.3f R%.2f" % (hole, r - draw(st.integers(1, 40)) / 10, r)
    if draw(st.integers(0, 2)) == 0:  # F on every line, as some posts write
        words += " F%d" % draw(st.integers(50, 900))
    units = draw(st.sampled_from(["G21", "G20"]))
    lines = ["%s G90 %s F300" % (units, plane), "M3 S1000", "G0 %s5" % hole]
    a = b = 0.0
    for _ in range(draw(st.integers(10, 60))):
        a += draw(st.sampled_from([5.0, 7.5, 0.0, -2.5, 12.125]))
        b += draw(st.sampled_from([0.0, 0.5, -3.25, 10.0]))
        place = "%s%.3f %s%.3f" % (first, a, second, b)
        line = "%s %s %s %s" % (retract, code, place, words)
        change = draw(st.integers(0, 24))
        if change == 1:
            line = line.replace(" R", " R1") if r < 2 else line  # another R
        elif change == 2:
            line += " F%d" % draw(st.integers(50, 900))
        elif change == 3:
            line += " L2"
        elif change == 4:
            line = line.replace(retract, "G98" if retract == "G99" else "G99")
        elif change == 5:
            line = place  # a row of hole words
        elif change == 6:
            lines.append("G80")
        elif change == 7:
            lines.append(
                draw(st.sampled_from(["G91", "G90", "(a comment)", "M3 S900"]))
            )
        lines.append(line)
    lines += ["G80", "G90", "M2"]
    if draw(st.integers(0, 2)) == 0:  # every line numbered, as some posts do
        number = draw(st.integers(0, 9))
        for k, line in enumerate(lines):
            number += draw(st.sampled_from([10, 10, 5, 0, 1000000]))
            lines[k] = "N%d %s" % (number, line)
    return cam_sized("\n".join(lines) + "\n")


@PROFILE
@given(restated_cycle_lines())
def test_restated_cycle_lines_match_rs274(text):
    """A cycle's own line restated at every hole: replayed from the one
    before (HoleRows.restated), the same trace and errors as rs274."""
    check_same(text, "run")


@PROFILE
@given(restated_cycle_lines())
def test_restated_cycle_lines_give_a_canon_the_reference_calls(
    replay_every_series, text
):
    """Restated cycle lines replayed give any canon (one that records; one
    that takes holes in batches by the protocol's default) the very calls,
    N numbers, error and end point that block() gives it line by line."""
    reference = _without_replay(_cycle_calls, text)
    assert _cycle_calls(text) == reference
    assert _cycle_calls(text, _HoleBatches) == reference


def test_restated_cycle_lines_are_replayed():
    """The replay is taken (so the tests above compare two paths): a row
    drilled by block, one recorded, the others replayed."""
    holes = "\n".join("G99 G81 X%d Y%d Z-3 R2" % (k, k % 3) for k in range(2, 40))
    text = cam_sized("G21 G17 F100\nG0 Z5\n" + holes + "\nG80\nM2\n")
    canon = _HoleBatches()
    start(Machine(canon), _main_of(text))
    assert canon.batches == 1
    assert sum(name == "straight_feed" for name, _ in canon.calls) == 38


@st.composite
def series_drilled_alike(draw) -> str:
    """Several series of holes in one program, a cycle line and rows of hole
    words each: the same cycle again at other levels (its R, its depth, a
    peck's Q, where the tool comes from), at the very levels of an earlier
    series, at 0 or -0, and now and then another cycle, retract mode or
    plane between them. The trace's and flatten's templates of a hole are
    kept whatever its levels and reused by the next series drilled alike;
    pecks make levels whose numbers are long (``R - 3 Q + 0.254``); now and
    then every line has an N (each hole's own in its trace)."""
    plane, first, second, hole = draw(
        st.sampled_from(
            [("G17", "X", "Y", "Z"), ("G18", "Z", "X", "Y"), ("G19", "Y", "Z", "X")]
        )
    )
    units = draw(st.sampled_from(["G21", "G20"]))
    lines = ["%s G90 %s F300" % (units, plane), "M3 S1000", "G0 %s5" % hole]
    codes = ["G81", "G82 P0.5", "G83", "G73", "G85", "G89 P0.2"]
    code = draw(st.sampled_from(codes))
    for _ in range(draw(st.integers(2, 5))):
        if draw(st.integers(0, 3)) == 0:
            code = draw(st.sampled_from(codes))
        retract = draw(st.sampled_from(["G98", "G99"]))
        r = draw(st.sampled_from(["0", "-0", "1", "1.5", "2.25", "0.1"]))
        depth = float(r) - draw(st.sampled_from([0.5, 1.0, 2.7, 3.3]))
        words = "%s%.4g R%s" % (hole, depth, r)
        if code in ("G83", "G73"):
            words += " Q%s" % draw(st.sampled_from(["0.3", "0.7", "1.1"]))
        a, b = draw(st.integers(-20, 20)), draw(st.integers(-20, 20))
        lines.append("%s %s %s%d %s%d %s" % (retract, code, first, a, second, b, words))
        for _ in range(draw(st.integers(3, 9))):
            a += draw(st.sampled_from([1, 2, 2.5, 0]))
            b += draw(st.sampled_from([0, 1, -1.5]))
            lines.append("%s%g %s%g" % (first, a, second, b))
        if draw(st.booleans()):
            lines.append("G80")
            if draw(st.booleans()):  # the tool elsewhere on the hole axis
                lines.append(
                    "G0 %s%s" % (hole, draw(st.sampled_from(["5", "1.5", "-0"])))
                )
    lines += ["G80", "M2"]
    if draw(st.integers(0, 2)) == 0:  # every line numbered, as some posts do
        number = draw(st.integers(0, 9))
        for k, line in enumerate(lines):
            number += draw(st.sampled_from([10, 10, 5, 0]))
            lines[k] = "N%d %s" % (number, line)
    return cam_sized("\n".join(lines) + "\n")


@PROFILE
@given(series_drilled_alike())
def test_series_drilled_alike_match_rs274(text):
    """Series of holes whose trace comes from one template made level-free
    (runtime.fast.hole_rows): the same trace as rs274."""
    check_same(text, "run")


@PROFILE
@given(cycle_tables())
def test_tables_of_cycle_rows_match_rs274(text):
    """Rows under a modal canned cycle take Machine.cycle_row: the same
    trace, and the same error at the same row, as rs274."""
    check_same(text, "run")


def _main_of(text: str):
    """The ``main`` of ``text`` compiled (as holes.ngc)."""
    namespace: dict = {"__name__": "holes"}
    exec(compile(compile_text(text, "holes.ngc"), "holes.py", "exec"), namespace)
    return namespace["main"]


def _cycle_calls(text: str, canon_class=RecordingCanon):
    """The calls a recording canon gets from ``text``, with the N numbers,
    the error (or None) and the machine's last point."""
    main = _main_of(text)
    canon = canon_class()
    machine = Machine(canon)
    try:
        start(machine, main)
        error = None
    except GCodeError as raised:
        error = str(raised)
    return canon.calls, canon.numbers, error, machine.current


def _block_alone(self, cells, at: int, end: int) -> int:
    """HoleRows.opening without the capture: the cycle's line by block."""
    plan = self.plans[int(cells[at + 1])]
    after = at + 2 + plan.width
    words = dict(zip(plan.letters, map(float, cells[at + 2 : after])))
    self.machine.block(int(cells[at]), *plan.codes, **words)
    return after


def _without_replay(run, text: str):
    """``run(text)`` with every hole row drilled by the reference path (and
    every cycle's own line, restated or not, run by block alone)."""
    saved = HoleRows.run, HoleRows.opening, HoleRows.restated
    HoleRows.run = HoleRows.restated = lambda self, cells, at, end: at
    HoleRows.opening = _block_alone
    try:
        return run(text)
    finally:
        HoleRows.run, HoleRows.opening, HoleRows.restated = saved


@pytest.fixture
def replay_every_series():
    """Replay series of any length (hole_rows._FEWEST 1): the tables drawn
    mix rows of one, two and three hole words, so fewer runs of rows would
    be long enough to be replayed by default."""
    saved = hole_rows._FEWEST
    hole_rows._FEWEST = 1
    yield
    hole_rows._FEWEST = saved


@PROFILE
@given(cycle_tables())
def test_replayed_holes_give_a_canon_the_reference_calls(replay_every_series, text):
    """runtime.fast.hole_rows replays a recorded hole for the next rows of
    hole words: any canon (here one that records) gets the very calls,
    values, N numbers and error the reference path gives it row by row, and
    the machine ends at the same point."""
    assert _cycle_calls(text) == _without_replay(_cycle_calls, text)


class NumbersTold(RecordingCanon):
    """Records each set_block_number as a call too (a canon keeping N
    numbers: every one it is told counts)."""

    def set_block_number(self, n) -> None:
        super().set_block_number(n)
        self._record("set_block_number", (n,))


@PROFILE
@given(cycle_tables())
def test_a_canon_keeping_numbers_is_told_each_holes_number(replay_every_series, text):
    """Holes replayed for a canon keeping N numbers (numbered rows included,
    in the protocol's default batches) tell it every set_block_number the
    reference path tells it, row by row."""
    kept = _cycle_calls(text, NumbersTold)
    assert kept == _without_replay(lambda text: _cycle_calls(text, NumbersTold), text)


class _HoleBatches(RecordingCanon):
    """Takes holes in batches by the protocol's default (Canon.hole_moves:
    the recorded calls again, hole by hole), and counts the batches."""

    batches = 0

    def hole_moves(self, *args):
        self.batches += 1
        super().hole_moves(*args)


@PROFILE
@given(cycle_tables())
def test_holes_in_batches_give_a_canon_the_reference_calls(replay_every_series, text):
    """A canon that takes holes in batches (Canon.hole_moves), by the
    protocol's default, gets the calls the reference path makes row by
    row: the batch's recording, lines and coordinates say it all."""
    batched = _cycle_calls(text, _HoleBatches)
    assert batched == _without_replay(_cycle_calls, text)


def _stats_report(text: str):
    from runtime.stats import StatsCanon

    main = _main_of(text)
    canon = StatsCanon()
    try:
        start(Machine(canon), main)
        error = None
    except GCodeError as raised:
        error = str(raised)
    return canon.report(), error


@PROFILE
@given(cycle_tables())
def test_stats_of_holes_in_batches_are_the_stats_of_each_call(
    replay_every_series, text
):
    """StatsCanon.hole_moves (columns, sums in program order) against its
    own per-call path: the same report to the last bit."""
    from runtime.canon import Canon
    from runtime.stats import StatsCanon

    batched = _stats_report(text)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(StatsCanon, "hole_moves", Canon.hole_moves)
        assert _stats_report(text) == batched


class _LineReading(RecordingCanon):
    """Reads the machine's line in each call (``reads_lines``), and records
    it with the call's arguments."""

    reads_lines = True
    machine = None

    def _record(self, name: str, args: tuple) -> None:
        super()._record(name, args + (self.machine.line,))


def _lines_read(text: str):
    """The calls (each with the line the machine was at) a canon reading
    lines gets from ``text``, with the error (or None)."""
    main = _main_of(text)
    canon = _LineReading()
    canon.machine = Machine(canon)
    try:
        start(canon.machine, main)
        error = None
    except GCodeError as raised:
        error = str(raised)
    return canon.calls, canon.numbers, error


@PROFILE
@given(cycle_tables())
def test_a_canon_reading_lines_gets_each_hole_at_its_own_line(
    replay_every_series, text
):
    """Holes replayed for a canon that reads the machine's line go row by
    row (a batch would be at its last row's line): each call is made at its
    own hole's line, as the reference path makes it."""
    assert _lines_read(text) == _without_replay(_lines_read, text)


def test_holes_go_in_batches_to_a_canon_taking_the_protocols_default(batch_rows):
    """A canon that neither takes holes its own way nor reads lines (a
    user's, NullCanon) gets them by the protocol's default batch, whose
    calls are made in C (the tests above hold them to the reference's)."""
    batches = batch_rows("hole_moves")
    rows = "\n".join("X%d Y%d" % (k, k % 3) for k in range(2, 40))
    text = cam_sized(
        "G21 G17 F100\nG0 Z5\nG99 G82 X1 Y1 Z-1 R2 P0.5\n" + rows + "\nG80\nM2\n"
    )
    canon = RecordingCanon()
    start(Machine(canon), _main_of(text))
    assert batches == [38]
    assert sum(name == "dwell" for name, _ in canon.calls) == 39


def test_holes_go_to_a_batch_canon_in_batches():
    """The batch path is taken (so the tests above compare two paths)."""
    rows = "\n".join("X%d Y%d" % (k, k % 3) for k in range(2, 40))
    text = cam_sized(
        "G21 G17 F100\nG0 Z5\nG99 G82 X1 Y1 Z-1 R2 P0.5\n" + rows + "\nG80\nM2\n"
    )
    main = _main_of(text)
    canon = _HoleBatches()
    start(Machine(canon), main)
    assert canon.batches == 1
    assert sum(name == "dwell" for name, _ in canon.calls) == 39


def _cycle_trace(text: str) -> tuple:
    main = _main_of(text)
    out = io.StringIO()
    canon = TraceCanon(out)
    try:
        start(Machine(canon), main)
        error = None
    except GCodeError as raised:
        error = str(raised)
    canon.flush()
    return out.getvalue(), error


@PROFILE
@given(cycle_tables())
def test_replayed_holes_trace_the_reference_text(replay_every_series, text):
    """For the trace, runtime.fast.hole_rows writes the text of many holes
    at once from one hole's template, a piece of at most _MOST rows at a
    time (three here, so that pieces follow pieces): the very text and
    error of the reference path."""
    saved_most = hole_rows._MOST
    hole_rows._MOST = 3
    try:
        replayed = _cycle_trace(text)
    finally:
        hole_rows._MOST = saved_most
    assert replayed == _without_replay(_cycle_trace, text)


def _learnt(monkeypatch) -> List[str]:
    """How each run of hole rows learns what to replay, from now on: "told"
    (by the cycle's own line, HoleRows._told) or "recorded" (its first row
    drilled by the reference path, HoleRows._record), each once it works."""
    learnt: List[str] = []
    for name, how in (("_told", "told"), ("_record", "recorded")):

        def counting(self, *args, _method=getattr(HoleRows, name), _how=how):
            found = _method(self, *args)
            if found:
                learnt.append(_how)
            return found

        monkeypatch.setattr(HoleRows, name, counting)
    return learnt


def test_holes_are_replayed(monkeypatch):
    """The replay is taken, learnt once for a run of hole rows, so the tests
    above compare two paths: G81 rows in the XY plane after a cycle line CAM
    posts write (its hole tells the rows'), pecks with a start below the R
    plane in XZ, and a cycle line with an N (which does not tell: the first
    row is recorded)."""
    learnt = _learnt(monkeypatch)
    rows = "\n".join("X%d Y%d" % (k, k % 3) for k in range(2, 40))
    text = "G21 G17 F100\nG0 Z5\nG90 G99 G81 X1 Y1 Z-1 R2\n" + rows + "\nG80\nM2\n"
    _cycle_calls(cam_sized(text))
    assert learnt == ["told"]
    learnt.clear()
    _cycle_calls(cam_sized(text.replace("G90 G99", "N5 G99")))
    assert learnt == ["recorded"]
    rows = "\n".join("Z%d" % k for k in range(2, 40))
    learnt.clear()
    _cycle_calls(
        cam_sized(
            "G21 G18 F100\nG0 Y-1\nG98 G83 Z1 X1 Y-3 R2 Q0.5\n" + rows + "\nG80\nM2\n"
        )
    )
    assert learnt == ["told"]


@pytest.mark.parametrize("rows", [1, 2, 3, 4, 5])
@pytest.mark.parametrize(
    "opening", ["G98 G83 X1 Y1 Z-1 R2 Q0.4", "N5 G99 G81 X1 Y1 Z-1 R2"]
)
def test_a_row_or_two_go_by_the_reference_path(monkeypatch, rows, opening):
    """A replay's set-up costs about what the reference path spends on two
    rows: a series of fewer than hole_rows._FEWEST rows of one shape is
    drilled row by row, a longer one replayed (told by its cycle's line, or
    its first row recorded), with the same calls and trace either way."""
    learnt = _learnt(monkeypatch)
    holes = "\n".join("X%d Y%d" % (k, k % 3) for k in range(2, 2 + rows))
    text = cam_sized(
        "G21 G17 F100\nG0 Z5\n%s\n%s\nG80\nG0 X0 Y0\nM2\n" % (opening, holes)
    )
    assert _cycle_calls(text) == _without_replay(_cycle_calls, text)
    assert _cycle_trace(text) == _without_replay(_cycle_trace, text)
    if opening.startswith("N"):
        # a line with an N does not tell: its first row is recorded (the N
        # it changes is the replay's to write, row by row)
        how, series = "recorded", rows
    else:
        how, series = "told", rows
    assert learnt == ([how, how] if series >= hole_rows._FEWEST else [])


def test_a_cycle_line_tells_the_rows_after_it(monkeypatch):
    """In G99 the cycle's own hole goes down from the start level and the
    rows' from the R plane; in G98 both from the start level; in the
    default G64 with a tolerance, each hole switches to exact path and back.
    Told by the line, the rows make the reference path's calls, with no row
    recorded."""
    learnt = _learnt(monkeypatch)
    rows = "\n".join("X%d Y%d" % (k, k % 3) for k in range(2, 12))
    for retract in ("G98", "G99"):
        for path in ("G61", "G64 P0.01"):
            text = cam_sized(
                "G21 G17 F100 M3 S500 %s\nG0 Z5\n%s G84 X1 Y1 Z-1 R2 P0.3\n"
                "%s\nG80\nM2\n" % (path, retract, rows)
            )
            learnt.clear()
            assert _cycle_calls(text) == _without_replay(_cycle_calls, text)
            assert _cycle_trace(text) == _without_replay(_cycle_trace, text)
            assert learnt == ["told", "told"]


def test_one_trace_template_serves_holes_drilled_alike_at_other_levels(
    monkeypatch,
):
    """The trace's template of a hole leaves its moves' levels to be written
    in (hole_rows._template's first stage) and is made of each call's lines,
    made once: series of pecks at other depths, R planes and start levels
    make no line anew, and each gets its own levels, the reference path's
    text."""
    made = []
    call_template = hole_rows._call_template
    monkeypatch.setattr(
        hole_rows,
        "_call_template",
        lambda *args: made.append(1) or call_template(*args),
    )
    rows = "\n".join("X%d Y%d" % (k, k % 3) for k in range(2, 12))
    series = [
        "G99 G83 X1 Y1 Z-2.5 R2 Q1\n" + rows + "\nG80",
        "G0 Z7\nG99 G83 X1 Y1 Z-2.7 R2.2 Q1\n" + rows + "\nG80",
        "G0 Z6\nG99 G83 X1 Y1 Z-2.9 R1.4 Q1\n" + rows + "\nG80",
    ]
    head = "G21 G17 F100 M3 S1000\nG0 Z5\n"
    _cycle_trace(cam_sized(head + series[0] + "\nM2\n"))
    first = len(made)
    text = head + "\n".join(series) + "\nM2\n"
    traced = _cycle_trace(cam_sized(text))
    assert len(made) == 2 * first
    assert traced == _without_replay(_cycle_trace, cam_sized(text))


def test_trace_templates_kept_are_bounded(monkeypatch):
    """With no room to keep templates (hole_rows._MOST_KEPT 0), each series
    makes its own and none is kept: the reference path's text all the same."""
    kept = []
    trace_piece = HoleRows._trace_piece

    def watching(self, *args):
        answer = trace_piece(self, *args)
        kept.append(len(self.hole_templates))
        return answer

    monkeypatch.setattr(hole_rows, "_MOST_KEPT", 0)
    monkeypatch.setattr(HoleRows, "_trace_piece", watching)
    rows = "\n".join("X%d Y%d" % (k, k % 3) for k in range(2, 12))
    series = [
        "G0 Z5\nG98 G82 X1 Y1 Z-%d R2 P0.%d\n%s\nG80" % (k, k, rows)
        for k in range(1, 5)
    ]
    text = cam_sized("G21 G17 F100 M3 S1000\n" + "\n".join(series) + "\nM2\n")
    traced = _cycle_trace(text)
    assert kept and max(kept) == 0
    assert traced == _without_replay(_cycle_trace, text)


def test_rotary_axes_at_minus_zero_are_not_those_at_zero():
    """Two series of holes drilled alike but for an A axis at 0 and then at
    -0 (equal numbers, printed apart): the second's lines are its own."""
    rows = "\n".join("X%d Y%d" % (k, k % 3) for k in range(2, 12))
    series = "G99 G81 X1 Y1 Z-1 R2\n" + rows + "\nG80\n"
    text = "G21 G17 F100\nG0 Z5 A0\n" + series + "G0 A-0\n" + series + "M2\n"
    check_same(cam_sized(text), "run")
    traced, error = _cycle_trace(cam_sized(text))
    assert error is None and "-0.0000, 0.0000, 0.0000)" in traced


class _CountingMachine(Machine):
    """Keeps something of its own for each row it drills (a count) and does
    not declare it in ``replayed_fields``: no hole may be replayed past it."""

    def cycle_row(self, line: int, words) -> bool:
        done = super().cycle_row(line, words)
        if done:
            self.drilled = getattr(self, "drilled", 0) + 1
        return done


def test_a_hole_that_changes_the_machine_is_not_replayed():
    """runtime.fast.hole_rows replays a recorded hole only where it changed
    nothing of the machine but its position: a machine field that changes
    with each row keeps every row on the reference path, drilled and
    counted."""
    rows = "\n".join("X%d Y%d" % (k, k % 3) for k in range(2, 40))
    text = cam_sized(
        "G21 G17 F100\nG0 Z5\nG99 G81 X1 Y1 Z-1 R2\n" + rows + "\nG80\nM2\n"
    )
    main = _main_of(text)
    canon = RecordingCanon()
    machine = _CountingMachine(canon)
    start(machine, main)
    assert machine.drilled == 38
    assert canon.calls == _without_replay(_cycle_calls, text)[0]
