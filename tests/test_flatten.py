"""``ngc2py flatten``: plain G-code that rs274 runs to the same moves.

The claim checked against rs274 itself: the original program and its
flattened form, both run by ``rs274 -g`` with the same options, make exactly
the same STRAIGHT_TRAVERSE / STRAIGHT_FEED / ARC_FEED calls (text of the
trace, N column included). On every golden program that runs to its end
and on Hypothesis-written programs. The full traces are compared too, and
the few bookkeeping calls allowed to differ are named (see ngc2py/flatten.py).
"""

from __future__ import annotations

import io
import re
import subprocess
import sys
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, reject, settings
from hypothesis import strategies as st

import cam_strategies
import rs274 as harness
import strategies
import test_cycles
from ngc2py import cli
from ngc2py.flatten import number

MOTION = re.compile(r"^(STRAIGHT_TRAVERSE|STRAIGHT_FEED|ARC_FEED)\(")
#: calls a flat program may add or lose against the original (no motion):
#: G94 written for G93, absolute/relative arc centre mode changes
BOOKKEEPING = {
    'COMMENT("interpreter: feed mode set to units per minute")',
    'COMMENT("interpreter: feed mode set to inverse time")',
    'COMMENT("interpreter: IJK distance mode changed to absolute")',
    'COMMENT("interpreter: IJK distance mode changed to incremental")',
    "SET_FEED_RATE(0.0000)",
    # G87's spindle orientation under M4 (rs274's direction 3) has no M19
    # spelling (P0-P2): written as M19 P2 (ngc2py/flatten.py)
    "ORIENT_SPINDLE(0, 0.0000, 3)",
}


def calls(stdout: bytes):
    """The trace's calls with the N column, without the sequence numbers."""
    return [line[6:] for line in stdout.decode("utf-8", "replace").splitlines()]


def motion(trace):
    return [c for c in trace if MOTION.match(c[7:])]


def flatten_and_run(
    program: Path, args, text=None, process: bool = False, recorded: bool = False
):
    """(original's rs274 result, flat's rs274 result, flat text). ``ngc2py
    flatten`` runs in this process (``ngc2py.cli.main``), or with
    ``process`` (or NGC2PY_TEST_PROCESSES) as ``python -m ngc2py flatten``.
    ``recorded``: the original's result is its golden recording (which
    test_golden_recording_is_current holds to rs274), not a new run."""
    with harness.Scratch(program, text, args=args) as s:
        env = s.env()
        command = ["flatten", "-q", s.program.name, *args, "-o", "flat.ngc"]
        if process or harness.PROCESSES:
            done = subprocess.run(
                [sys.executable, "-m", "ngc2py", *command],
                cwd=s.work,
                env=env,
                capture_output=True,
                timeout=120,
            )
            rc, stderr = done.returncode, done.stderr
        else:
            done = harness.golden.run_in(
                s, lambda: cli.main(command), harness.golden_cache(), 120
            )
            rc, stderr = done.rc, done.stderr
        refused = REFUSAL.search(stderr.decode("utf-8", "replace"))
        if rc != 0 and refused:
            raise Refused(refused.group(1))
        assert rc == 0, stderr.decode()
        flat = (s.work / "flat.ngc").read_text()
        exe = harness.rs274_path()
        if recorded:
            original = harness.load_expected(program)
        else:
            original = subprocess.run(
                [exe, "-g", *args, s.program.name],
                cwd=s.work,
                env=env,
                capture_output=True,
                timeout=60,
            )
        again = subprocess.run(
            [exe, "-g", *args, "flat.ngc"],
            cwd=s.work,
            env=env,
            capture_output=True,
            timeout=60,
        )
    return original, again, flat


def _ends_well(program: Path) -> bool:
    rc = program.with_suffix(".rc")
    return rc.exists() and rc.read_text().strip() == "0"


RUNNABLE = [p for p in harness.golden_programs() if _ends_well(p)]


def _name(program: Path) -> str:
    return str(program.relative_to(harness.GOLDEN))


#: flatten's deliberate refusal (ngc2py/flatten.py, FlattenError)
REFUSAL = re.compile(r"^flatten: (.+)$", re.M)

#: golden programs flatten gets wrong today, and what it cannot do there
KNOWN_GAPS = {
    "continue/comp_queue_dropped.ngc": (
        "cannot be written as G-code: under -n 0 an error drops the calls queued"
        " behind compensation (here M8's FLOOD_ON) while rs274 still counts the"
        " flood as on, so its M2 prints FLOOD_OFF; a flat program either turns the"
        " flood on (FLOOD_ON appears) or not (FLOOD_OFF does not)"
    ),
}


class Refused(Exception):
    """flatten refused the program: it makes a call flatten cannot write yet."""


@pytest.mark.rs274
@pytest.mark.parametrize(
    "program",
    [
        (
            pytest.param(
                p, marks=pytest.mark.xfail(reason=KNOWN_GAPS[_name(p)], strict=True)
            )
            if _name(p) in KNOWN_GAPS
            else p
        )
        for p in RUNNABLE
    ],
    ids=_name,
)
def test_flat_golden_program_makes_the_same_moves_in_rs274(program, rs274):
    args = harness.read_args(program)
    # one program in ten flattened by a new `ngc2py flatten` process
    process = RUNNABLE.index(program) % 10 == 0
    try:
        original, flat_run, flat = flatten_and_run(
            program, args, process=process, recorded=True
        )
    except Refused as refusal:
        pytest.xfail(str(refusal))
    assert flat_run.returncode == 0, (
        harness.first_error_line(flat_run.stderr) + "\n" + flat
    )
    a, b = calls(original.stdout), calls(flat_run.stdout)
    assert motion(b) == motion(a), harness.stdout_diff(original.stdout, flat_run.stdout)
    # everything else differs at most by the named bookkeeping calls
    extra = [c[7:] for c in set(a) ^ set(b)]
    assert set(extra) <= BOOKKEEPING | {
        c for c in extra if c.startswith('COMMENT("e')
    }, extra


#: Generated programs flattened: few, the same ones every run (each runs
#: rs274 twice).
GENERATED = settings(
    max_examples=25,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=list(HealthCheck),
)


@pytest.mark.rs274
@GENERATED
@given(strategies.valid_programs())
def test_flat_generated_program_makes_the_same_moves(text):
    # a program flatten deliberately refuses (probing, ...) is rejected: the
    # golden programs' xfails name each refusal; the property holds for the rest
    assert_flat_makes_the_same_moves("prog.ngc", text)


def assert_flat_makes_the_same_moves(name: str, text: str) -> None:
    """``text``, run by rs274 and flattened, makes the same moves flat
    (programs rs274 does not run to their end, or flatten refuses, are
    rejected)."""
    program = harness.REPO / "tests" / "_generated" / name
    expected = harness.run_rs274(program, text=text, timeout=20)
    if expected.rc != 0:
        reject()
    try:
        original, flat_run, flat = flatten_and_run(program, [], text=text)
    except Refused:
        reject()
    assert flat_run.returncode == 0, (
        harness.first_error_line(flat_run.stderr) + "\n" + flat
    )
    assert motion(calls(flat_run.stdout)) == motion(calls(original.stdout)), (
        text + "\n----\n" + flat + harness.stdout_diff(original.stdout, flat_run.stdout)
    )


@st.composite
def cam_programs_with_parameters(draw):
    """CAM tables (runtime.fast.rows' batches of plain moves, which flatten
    writes a column at a time) with settings of the parameters G-codes read
    between them, and G28/G30/G92 that read them."""
    text = draw(cam_strategies.cam_programs())
    # a motion mode and a feed first, and a feed again after each change of
    # units (which sets it to zero): without them most CAM programs drawn
    # fail in rs274 early on, and are drawn again
    lines = ["G0 F500"] + [
        line + " F500" if line.startswith(("G20", "G21")) and "F" not in line else line
        for line in text.splitlines()
    ]
    for _ in range(draw(st.integers(0, 3))):
        at = draw(st.integers(0, len(lines) - 1))
        number = draw(st.sampled_from((5161, 5162, 5163, 5181, 5211, 5221, 5222)))
        value = draw(st.sampled_from(("0", "-0", "1.5", "-2.25", "10")))
        after = draw(st.sampled_from(("G28", "G30", "G92 X1", "G55", "G0 X1")))
        lines[at:at] = ["#%d = %s" % (number, value), after]
    return "\n".join(lines) + "\n"


@pytest.mark.rs274
@GENERATED
@given(cam_programs_with_parameters())
def test_flat_cam_program_makes_the_same_moves(text):
    assert_flat_makes_the_same_moves("cam.ngc", text)


@pytest.mark.rs274
@GENERATED
@given(cam_strategies.arc_programs())
def test_flat_arc_program_makes_the_same_moves(text):
    """Arc tables: runs of one layout reach flatten as one arc_moves call."""
    assert_flat_makes_the_same_moves("arcs.ngc", text)


@pytest.mark.rs274
@GENERATED
@given(st.one_of(test_cycles.cycle_tables(), test_cycles.restated_cycle_lines()))
def test_flat_cycle_table_makes_the_same_moves(text):
    """Tables of hole rows: holes replayed from a recorded one
    (runtime.fast.hole_rows) reach flatten as a block each, as drilled."""
    assert_flat_makes_the_same_moves("holes.ngc", text)


def _compensated_table() -> str:
    """A CAM-sized program whose rows run under cutter compensation (its
    queue then stands for the machine's canon), a pause among them."""
    lines = ["G21 G90 G17 F300", "G0 X0 Y0 Z1", "G1 Z-1", "G41 D0", "G1 X10 Y0"]
    lines += ["G1 X%d Y%d" % (10 + k, (k * 7) % 13) for k in range(30)]
    lines += ["G4 P0.5", "G1 X50 Y3", "G40", "G0 Z5", "M2"]
    return cam_strategies.cam_sized("\n".join(lines) + "\n")


def rows_past_the_end(text: str) -> str:
    """``text`` (ending at its M2 or M30) CAM-sized by rows past its end,
    which no run reads: its runs of constant blocks become data tables."""
    return text + "G0 X0\n" * cam_strategies.MIN_PROGRAM_ROWS


@pytest.mark.rs274
@GENERATED
@given(strategies.compensated_programs().map(rows_past_the_end))
def test_flat_compensated_tables_make_the_same_moves(text):
    """Cutter compensation's programs as data tables (its queue stands for
    the canon while it is on): flat, the same moves."""
    assert_flat_makes_the_same_moves("comp.ngc", text)


@pytest.mark.rs274
def test_rows_under_cutter_compensation_are_flattened():
    """Data rows under cutter compensation go by the general path (the
    batches' tests of the canon never meet the compensation's queue: an
    AttributeError, once)."""
    assert_flat_makes_the_same_moves("comp.ngc", _compensated_table())


def test_a_batch_of_moves_is_written_as_one_block_a_move(tmp_path):
    rows = "".join("X%d.25 Y%d\n" % (k, k % 3) for k in range(40))
    text = cam_strategies.cam_sized(
        "G21 G90\nG1 Z-1 F100\n" + rows + "#5161 = 7\nG28\nM2\n"
    )
    rc, flat, err = run_flatten(tmp_path, text)
    assert rc == 0, err
    moves = [line for line in flat.splitlines() if line.startswith("G1 X")]
    assert len(moves) == 40
    assert moves[1].startswith("G1 X1.25 Y1  ; ") and moves[1].endswith("p.ngc:4")
    assert moves[3].startswith("G1 X3.25 Y0  ; ")
    body = flat.splitlines()
    # G28's moves (written as G0, line 44) read the home set after the batch
    g28 = next(i for i, text in enumerate(body) if text.endswith("p.ngc:44"))
    assert body.index("#5161 = 7") < g28


# --- the text itself ---------------------------------------------------------


def run_flatten(tmp_path, text, *args):
    (tmp_path / "p.ngc").write_text(text)
    out, err = io.StringIO(), io.StringIO()
    import os

    here = os.getcwd()
    os.chdir(tmp_path)
    try:
        with redirect_stdout(out), redirect_stderr(err):
            rc = cli.main(["flatten", "p.ngc", *args])
    finally:
        os.chdir(here)
    return rc, out.getvalue(), err.getvalue()


def test_loops_subroutines_and_expressions_are_resolved(tmp_path):
    rc, out, err = run_flatten(
        tmp_path,
        "o<step> sub\n  G1 X[#1 * 2] F100\no<step> endsub\n"
        "#1 = 0\no1 while [#1 LT 3]\n  o<step> call [#1]\n  #1 = [#1 + 1]\no1 endwhile\nM2\n",
    )
    assert rc == 0, err
    body = [l for l in out.splitlines() if not l.startswith(";")]
    assert [l.split(";")[0].strip() for l in body] == [
        "G90",
        "F100 G1 X0",
        "F100 G1 X2",
        "F100 G1 X4",
        "M2",
    ]
    # each block names its source line and the call that led there
    assert body[2].endswith("; p.ngc:2 <- p.ngc:6")
    assert "o1" not in out and "#" not in out.replace("; ", "")


def test_numbers_round_trip_in_plain_decimal():
    assert number(1.0) == "1"
    assert number(-0.0) == "-0"
    assert number(0.1 + 0.2) == "0.30000000000000004"
    assert number(1e-20) == "0.00000000000000000001"
    assert float(number(123456.789e10)) == 123456.789e10
    for value in (1 / 3, -2 / 7, 25.4 / 3, 1e-7):
        assert float(number(value)) == value and "e" not in number(value)


def test_an_arc_centre_offset_is_written_as_the_program_most_likely_wrote_it():
    """Four decimals where added to the start they give the very centre
    (rs274 adds I/J/K to the start), every digit where they do not."""
    from ngc2py.flatten import _offset, _short_offsets

    assert _offset(0.1, 0.1 + 0.2) == 0.2  # not 0.20000000000000004
    assert 0.1 + _offset(0.1, 0.1 + 0.2) == 0.1 + 0.2
    near = 1.0 + 2.0**-40  # no four decimals give it
    assert _offset(1.0, near) == near - 1.0
    assert _short_offsets([0.1, 1.0], [0.1 + 0.2, near]) == [0.2, near - 1.0]


def test_a_failing_program_is_not_flattened(tmp_path):
    rc, out, err = run_flatten(tmp_path, "G0 X1\nG1 X[1/0]\nM2\n")
    assert rc == 1 and out == ""
    assert err.splitlines()[0] == "Attempt to divide by zero"


def test_output_file_and_stdin(tmp_path):
    (tmp_path / "p.ngc").write_text("G0 X1 Y2\nM2\n")
    to_file = subprocess.run(
        [sys.executable, "-m", "ngc2py", "flatten", "p.ngc", "-o", "flat.ngc"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        env=dict(__import__("os").environ, PYTHONPATH=str(harness.REPO)),
    )
    assert to_file.returncode == 0 and to_file.stdout == ""
    from_stdin = subprocess.run(
        [sys.executable, "-m", "ngc2py", "flatten", "-"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        input="G0 X1 Y2\nM2\n",
        env=dict(__import__("os").environ, PYTHONPATH=str(harness.REPO)),
    )
    assert from_stdin.returncode == 0
    strip = lambda text: [
        l.split(";")[0] for l in text.splitlines() if not l.startswith(";")
    ]
    assert strip(from_stdin.stdout) == strip((tmp_path / "flat.ngc").read_text())


def test_var_file_is_read_but_never_rewritten(tmp_path):
    (tmp_path / "p.var").write_text("5161\t7.000000\n")
    before = (tmp_path / "p.var").read_bytes()
    rc, out, err = run_flatten(tmp_path, "G0 X#5161\n#5161 = 3\nM2\n", "-v", "p.var")
    assert rc == 0, err
    assert "G0 X7" in out
    assert (tmp_path / "p.var").read_bytes() == before


def test_what_no_plain_g_code_can_say_is_refused_by_name(tmp_path):
    # Cutter compensation with the tool radius equal to the arc's makes an
    # ARC_FEED of zero radius, which rs274 refuses when it is written out.
    (tmp_path / "p.tbl").write_text("T1 P1 D0.125\n")
    rc, out, err = run_flatten(
        tmp_path,
        "G20 F60 T1 M6\nG0 X0.0625 Y0.0625\nG41 G0 X0 Y0.0625\n"
        "G3 X0 Y0.0625 I0 J-0.0625 Z-0.01\nG40 G0 X1 Y1\nM2\n",
        "-t",
        "p.tbl",
    )
    assert rc == 1 and out == ""
    assert err.startswith("flatten: an arc of zero radius")
    # G84 in the XZ plane leaves rs274's current point away from where its
    # last move ended: the next arc starts at the former
    rc, out, err = run_flatten(
        tmp_path,
        "G18 G21 G90 F100\nG0 X-8.6 Z-13.2\nS1000 M3 G84 X-50 Z6.3 Y-5.5 R-3\nG80\n"
        "G19 G91 G3 Y5.656351 Z4.185480 J-3.809147 K11.062567\nM2\n",
    )
    assert rc == 1 and out == ""
    assert err.startswith(
        "flatten: an arc starts where rs274's interpreter left the tool"
    )


#: Spindle words a flat program writes with the spindle's $ on a machine of
#: several spindles ([TRAJ]SPINDLES), and what it refuses.
SPINDLE_PROGRAMS = [
    "S100 M3 $1\nS200 M4 $0\nM5 $1\nS300 M3\nM5\nS50 $1\nM3 $1\nG1 X1 F100\nM2\n",
    "M3 $-1 S20\nG0 X1\nM5 $-1\nS10 M4 $2\nM5 $2\nM30\n",
    "S1000 M3 $1\nM51 P1\nM48\nM2\n",
]


@pytest.mark.rs274
@pytest.mark.parametrize("spindles", [2, 3])
@pytest.mark.parametrize("text", SPINDLE_PROGRAMS)
def test_several_spindles_are_written_with_their_dollar_or_refused(
    text, spindles, tmp_path
):
    (tmp_path / "m.ini").write_text("[TRAJ]\nSPINDLES = %d\n" % spindles)
    program = tmp_path / "p.ngc"
    program.write_text(text)
    expected = harness.run_rs274(program, ["-i", "m.ini"])
    if expected.rc != 0:
        # (a spindle number the machine does not have: nothing to flatten)
        assert "$" in text and spindles == 2, expected.describe()
        return
    if "M51" in text or "M48" in text:
        # M48-M51 without $ switch every spindle, and rs274 refuses M51 $0:
        # the first spindle's switch alone has no G-code; said by name
        rc, out, err = run_flatten(tmp_path, text, "-i", "m.ini")
        assert rc == 1 and out == ""
        assert err.startswith("flatten: the program makes ENABLE_SPEED_OVERRIDE(0)")
        return
    original, flat_run, flat = flatten_and_run(program, ["-i", "m.ini"])
    assert flat_run.returncode == 0, flat
    assert calls(flat_run.stdout) == calls(original.stdout), flat


def _centres_a_short_offset_away(data, columns, pos, plane: str) -> None:
    """Now and then an arc's centre four decimals from where it starts (the
    row before's end), as a program's I and J put it: the offset flatten
    writes is then those four decimals."""
    from ngc2py.flatten import ARC_AXES

    first, second = ("XYZABC".index(letter) for letter in ARC_AXES[plane][:2])
    for k in range(len(columns[0])):
        if data.draw(st.integers(0, 2)) == 0:
            starts = (
                (columns[0][k - 1], columns[1][k - 1])
                if k
                else (pos[first], pos[second])
            )
            for column, start in zip(columns[2:4], starts):
                if start == start:  # (not from an UNKNOWN point)
                    offset = data.draw(st.sampled_from([0.2, -17.303, 2.3456]))
                    column[k] = start + offset


@settings(max_examples=300, deadline=None)
@given(
    st.data(),
    st.sampled_from(["XY", "XZ", "YZ"]),
    st.booleans(),
    st.booleans(),
)
def test_a_batch_of_arcs_is_written_as_one_arc_at_a_time(data, plane, inches, absolute):
    """FlattenCanon._arc_texts (a column of numbers at a time) writes the
    very text of _arc arc by arc, and leaves the same point and IJK mode."""
    from ngc2py.flatten import UNKNOWN, FlattenCanon, FlattenError

    value = (
        st.floats(-1e4, 1e4, allow_nan=False)
        | st.sampled_from([0.0, -0.0, 1.0, 1e15, 2.5e-7, 0.1])
        | st.integers(-50, 50).map(float)
    )
    count = data.draw(st.integers(1, 6))
    columns = [[data.draw(value) for _ in range(count)] for _ in range(4)]
    columns.append([data.draw(st.sampled_from([-2, -1, 1, 3])) for _ in range(count)])
    columns += [[data.draw(value) for _ in range(count)] for _ in range(7)]
    for k in range(count):  # centres nearby, some exactly at a whole offset
        if data.draw(st.booleans()):
            columns[2][k] = columns[0][k] + data.draw(
                st.sampled_from([3.0, -7.5, 0.25])
            )
            columns[3][k] = columns[1][k] + data.draw(st.sampled_from([1.0, -2.0]))
    pos = [data.draw(value | st.just(UNKNOWN)) for _ in range(6)]
    _centres_a_short_offset_away(data, columns, pos, plane)
    answers = []
    for batch in (True, False):
        canon = FlattenCanon()
        canon._plane, canon._inches, canon._ijk_absolute = plane, inches, absolute
        where = list(pos)
        try:
            if batch:
                texts = canon._arc_texts([list(c) for c in columns], where)
            else:
                texts = [canon._arc(args, where) for args in zip(*columns)]
        except FlattenError as error:
            texts = str(error)
        answers.append((texts, repr(where), canon._ijk_absolute))
    assert answers[0] == answers[1]
    # _apart's checks (an arc at a time) are _arc_words' (a batch at once):
    # a batch is written whole exactly when no arc of it is apart
    from ngc2py.flatten import _AXIS_INDEX, ARC_AXES

    canon = FlattenCanon()
    canon._plane, canon._inches, canon._ijk_absolute = plane, inches, absolute
    i1, i2 = (_AXIS_INDEX[letter] for letter in ARC_AXES[plane][:2])
    starts = ([pos[i1]] + columns[0][:-1], [pos[i2]] + columns[1][:-1])
    befores = [[pos[3 + k]] + columns[6 + k][:-1] for k in range(3)]
    try:
        whole = canon._arc_words([list(c) for c in columns], starts, befores)
    except FlattenError:
        return
    assert any(canon._apart(columns[:4], starts)) == (whole is None)


@settings(max_examples=300, deadline=None)
@given(st.data(), st.sampled_from(["XY", "XZ", "YZ"]), st.booleans())
def test_a_contour_is_written_as_a_run_of_arcs_and_a_line_at_a_time(
    data, plane, absolute
):
    """FlattenCanon._contour_texts (all of a contour's arcs in one go, its
    lines a column at a time) writes the very text of _contour_runs (a run
    of arcs, then a line, ...) and leaves the same point and IJK mode."""
    from ngc2py.flatten import ARC_AXES, UNKNOWN, FlattenCanon, FlattenError

    value = (
        st.floats(-1e4, 1e4, allow_nan=False)
        | st.sampled_from([0.0, -0.0, 1.0, 2.5e-7, 0.1])
        | st.integers(-50, 50).map(float)
    )
    axes = ["XYZABC".index(letter) for letter in ARC_AXES[plane][:3]]
    pos = [data.draw(value | st.just(UNKNOWN)) for _ in range(6)]
    # the point before the contour on a column's axis (ends: 0, 1, 5; A B C)
    pos_of = {
        0: pos[axes[0]],
        1: pos[axes[1]],
        5: pos[axes[2]],
        6: pos[3],
        7: pos[4],
        8: pos[5],
    }.get
    count = data.draw(st.integers(1, 8))
    rotation = [data.draw(st.sampled_from([-2, -1, 0, 0, 1, 3])) for _ in range(count)]
    columns = [[data.draw(value) for _ in range(count)] for _ in range(4)]
    columns.append(rotation)
    columns += [[data.draw(value) for _ in range(count)] for _ in range(7)]
    for k in range(count):
        if data.draw(st.booleans()):  # an axis that stays, and -0.0 after 0.0
            column = columns[data.draw(st.sampled_from([0, 1, 5, 6, 7, 8]))]
            column[k] = column[k - 1] if k else data.draw(st.sampled_from([0.0, -0.0]))
        if not rotation[k] and data.draw(st.integers(0, 3)) == 0:
            for j in (0, 1, 5, 6, 7, 8):  # a line to where it is: still one word
                was = columns[j][k - 1] if k else pos_of(j)
                columns[j][k] = was if was == was else columns[j][k]  # (not UNKNOWN)
        if data.draw(st.booleans()):  # centres nearby, some at a whole offset
            columns[2][k] = columns[0][k] + data.draw(st.sampled_from([3.0, -7.5]))
            columns[3][k] = columns[1][k] + data.draw(st.sampled_from([1.0, -2.0]))
    _centres_a_short_offset_away(data, columns, pos, plane)
    answers = []
    for way in ("whole", "pieces", "runs"):
        canon = FlattenCanon()
        canon._plane, canon._ijk_absolute = plane, absolute
        where = list(pos)
        try:
            texts = None
            if way == "whole":
                texts = canon._contour_texts(axes, [list(c) for c in columns], where)
            elif way == "pieces":  # (cut at the arcs _arc treats apart)
                texts = canon._contour_pieces(axes, [list(c) for c in columns], where)
            if texts is None:  # (stepped aside: the same as the runs, surely)
                where = list(pos)
                texts = canon._contour_runs(axes, [list(c) for c in columns], where)
        except FlattenError as error:
            texts = str(error)
        answers.append((texts, repr(where), canon._ijk_absolute))
    assert answers[0] == answers[2] and answers[1] == answers[2]


def test_a_contour_line_to_where_it_is_still_writes_an_axis_word():
    """A contour's G1 line that moves nowhere is written "G1 X<x>", as
    _move writes one, by the whole contour's path as by the runs'."""
    from ngc2py.flatten import FlattenCanon

    # XY: an arc (counterclockwise) from (0, 0) to (2, 0) about (1, 0.5),
    # then a line to (2, 0)
    columns = [[2.0, 2.0], [0.0, 0.0], [1.0, 0.0], [0.5, 0.0], [1, 0], [-1.0, -1.0]]
    columns += [[0.0, 0.0] for _ in range(6)]
    texts = []
    for method in ("_contour_texts", "_contour_runs"):
        canon = FlattenCanon()
        canon._plane = "XY"
        texts.append(
            getattr(canon, method)((0, 1, 2), columns, [0.0, 0.0, -1.0, 0.0, 0.0, 0.0])
        )
    assert texts[0] == texts[1] == ["G3 X2 Y0 Z-1 I1 J0.5", "G1 X2"]


def _flat_each_way(text, folder, ways, name):
    """flatten's text of ``text`` (or its error) once for each of ``ways``:
    the FlattenCanon attributes set for that run."""
    from ngc2py import flatten as flat
    from runtime.errors import GCodeError

    program = folder / name
    program.write_text(text)
    answers = []
    for way in ways:
        with pytest.MonkeyPatch.context() as patch:
            patch.setenv("NGC2PY_CACHE", str(folder / "cache"))
            for attribute, value in way.items():
                patch.setattr(flat.FlattenCanon, attribute, value)
            try:
                answers.append(flat.flatten(str(program)))
            except (GCodeError, flat.FlattenError) as error:
                answers.append(type(error).__name__ + str(error))
    return answers


def _flat_by_batches_and_hole_by_hole(text, folder, name="holes.ngc"):
    """flatten's text of ``text`` with FlattenCanon.hole_moves, and with
    the protocol's default (the recorded calls again, hole by hole)."""
    from runtime.canon import Canon

    return _flat_each_way(text, folder, ({}, {"hole_moves": Canon.hole_moves}), name)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(text=st.one_of(test_cycles.cycle_tables(), test_cycles.restated_cycle_lines()))
def test_holes_in_batches_are_written_as_hole_by_hole(text, tmp_path_factory):
    """FlattenCanon.hole_moves (each hole's text made from a template of the
    recorded hole's calls) writes the very text of the holes replayed call
    by call, line comments included; a hole with other calls goes call by
    call."""
    answers = _flat_by_batches_and_hole_by_hole(text, tmp_path_factory.mktemp("holes"))
    assert answers[0] == answers[1]


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(text=test_cycles.series_drilled_alike())
def test_series_drilled_alike_are_written_as_hole_by_hole(text, tmp_path_factory):
    """One template of a hole serves every series drilled alike whatever
    its levels (FlattenCanon._batch_template): each batch fills in its own,
    and the text is the holes' written call by call."""
    answers = _flat_by_batches_and_hole_by_hole(text, tmp_path_factory.mktemp("holes"))
    assert answers[0] == answers[1]


def test_series_at_other_levels_share_a_template(tmp_path, monkeypatch):
    """Series of one cycle at other depths and R planes (pecks included)
    are written from templates made once, not once a series."""
    from ngc2py import flatten as flat

    made = []
    making = flat.FlattenCanon._level_free_template

    def counting(self, *args):
        made.append(1)
        return making(self, *args)

    monkeypatch.setattr(flat.FlattenCanon, "_level_free_template", counting)
    lines = ["G21 G90 G17 F300", "M3 S1000", "G0 Z5"]
    for k in range(12):
        cycle = "G81" if k % 2 else "G83 Q0.7"
        lines.append("G98 %s X%d Y0 Z%g R%g" % (cycle, 10 * k, -1 - k / 7, 1 + k / 9))
        lines += ["X%d Y%d" % (10 * k, j) for j in range(1, 8)]
        lines.append("G80")
    lines.append("M2")
    text = "\n".join(lines) + "\n"
    answers = _flat_by_batches_and_hole_by_hole(text, tmp_path)
    assert answers[0] == answers[1]
    # a G81 hole is one shape whatever its levels; a G83 hole's pecks differ
    # with its depth, so its series make a few
    assert 2 <= len(made) < 12


def test_level_free_templates_kept_are_bounded(tmp_path, monkeypatch):
    """Past _MOST_TEMPLATES kinds of holes the rest are made batch by batch:
    the same text, no more kept."""
    from ngc2py import flatten as flat

    kept = []
    original = flat.FlattenCanon._batch_template

    def watching(self, *args):
        made = original(self, *args)
        kept.append(len(self._level_free))
        return made

    monkeypatch.setattr(flat, "_MOST_TEMPLATES", 1)
    monkeypatch.setattr(flat.FlattenCanon, "_batch_template", watching)
    lines = ["G21 G90 G17 F300", "M3 S1000", "G0 Z5"]
    for k in range(6):  # a dwell of its own each: six kinds of holes
        lines.append("G98 G82 X0 Y%d Z-1 R1 P0.%d" % (10 * k, k + 1))
        lines += ["X%d Y%d" % (j, 10 * k) for j in range(1, 6)]
        lines.append("G80")
    lines.append("M2")
    text = cam_strategies.cam_sized("\n".join(lines) + "\n")
    answers = _flat_by_batches_and_hole_by_hole(text, tmp_path)
    assert answers[0] == answers[1]
    assert kept and max(kept) == 1


@pytest.mark.parametrize(
    "words",
    [
        "P3000001.0078125",  # a dwell of a level stand-in's text
        "P13000002.0078125",  # ... holding one
    ],
)
def test_a_number_like_a_level_stand_in_is_kept_apart(words, tmp_path):
    """A hole whose other numbers hold a level stand-in's text is written
    from a template of its own levels: the same text as hole by hole."""
    lines = ["G21 G90 G17 F300", "M3 S1000", "G0 Z5"]
    for k in range(3):
        lines.append("G98 G82 X0 Y%d Z%g R1 %s" % (10 * k, -1 - k / 3, words))
        lines += ["X%d Y%d" % (j, 10 * k) for j in range(1, 6)]
        lines.append("G80")
    lines.append("M2")
    answers = _flat_by_batches_and_hole_by_hole(
        cam_strategies.cam_sized("\n".join(lines) + "\n"), tmp_path
    )
    assert answers[0] == answers[1]
    assert words[1:] in answers[0]


#: A table of holes (as long as the code generator writes as a row table):
#: both coordinates moving, one, none.
HOLES = (
    "G21 G90 G17 F300\nG0 Z{clear}\nG98 G81 X1 Y1 Z-2 R1\n"
    + "".join("X%g Y%g\n" % (2 + k // 2, 2 + k // 3) for k in range(60))
    + "G80\nM2\n"
)


@pytest.mark.parametrize(
    "clear, name",
    [
        ("10", "holes.ngc"),
        # a number of the program's that is one of the template's stand-ins
        ("7777777.015625", "holes.ngc"),
        # a name so long that a hole's line comment could move to its own line
        ("10", "h" * 190 + ".ngc"),
    ],
)
def test_holes_whose_template_cannot_be_trusted_go_hole_by_hole(clear, name, tmp_path):
    """Where a hole's template could be wrong (a stand-in's text is the
    program's own, a line near the length at which its comment moves),
    flatten writes those holes call by call: the same text."""
    from ngc2py import flatten as flat

    answers = _flat_by_batches_and_hole_by_hole(
        HOLES.format(clear=clear), tmp_path, name
    )
    assert answers[0] == answers[1]
    for move in ("X5 Y4", "Y3", "X6"):  # both coordinates moving, Y alone, X alone
        assert re.search(r"^G0 %s\b" % move, answers[0], re.M)
    assert (clear in answers[0]) and not any(
        text in answers[0].replace("Z" + clear, "") for text in flat._STAND_IN_TEXTS
    )


def _flat_with_and_without_numbers(text, folder):
    """flatten's text of ``text`` with numbered rows in batches (each row's N
    with them: FlattenCanon.takes_numbers), and with every N told by
    set_block_number, row by row."""
    ways = ({"takes_numbers": True}, {"takes_numbers": False})
    return _flat_each_way(text, folder, ways, "numbered.ngc")


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    text=st.one_of(
        cam_strategies.arc_programs(),
        cam_strategies.cam_programs(),
        test_cycles.cycle_tables(),
        test_cycles.restated_cycle_lines(),
        test_cycles.series_drilled_alike(),
    )
)
def test_numbered_rows_in_batches_are_written_as_row_by_row(text, tmp_path_factory):
    """Numbered moves, arcs, contours and holes taken in batches with their
    N numbers (a slot of a hole's template) are written as when each row's
    N starts a block of its own: the same text, N words and line comments
    included."""
    answers = _flat_with_and_without_numbers(text, tmp_path_factory.mktemp("n"))
    assert answers[0] == answers[1]


def test_numbered_series_and_arcs_reach_flatten_in_batches(tmp_path, monkeypatch):
    """A numbered drilling file's holes and a numbered contour's arcs reach
    FlattenCanon in batches with their N numbers (not a block a row), and
    every row's N is written."""
    from ngc2py import flatten as flat

    batches = []
    for name in ("hole_moves", "contour_moves"):
        original = getattr(flat.FlattenCanon, name)

        def counting(self, *args, numbers=None, _original=original, _name=name):
            batches.append((_name, numbers))
            return _original(self, *args, numbers=numbers)

        monkeypatch.setattr(flat.FlattenCanon, name, counting)
    lines = ["G21 G90 G17 F300", "M3 S1000", "G0 Z5"]
    for k in range(4):
        lines.append("G98 G81 X0 Y%d Z%g R1" % (10 * k, -1 - k / 3))
        lines += ["X%d Y%d" % (j, 10 * k) for j in range(1, 20)]
        lines.append("G80")
    lines += ["G0 X0 Y0", "G1 Z-1"]
    lines += ["G%d X%d Y0 R5" % (2 + k % 2, 10 * (k + 1)) for k in range(40)]
    lines.append("M2")
    numbered = ["N%d %s" % (10 * k, line) for k, line in enumerate(lines, 1)]
    text = "\n".join(numbered) + "\n"
    answers = _flat_with_and_without_numbers(cam_strategies.cam_sized(text), tmp_path)
    assert answers[0] == answers[1]
    holes = [numbers for name, numbers in batches if name == "hole_moves" and numbers]
    arcs = [numbers for name, numbers in batches if name == "contour_moves" and numbers]
    assert sum(map(len, holes)) >= 4 * 18 and sum(map(len, arcs)) >= 39
    assert all(n is not None for numbers in holes + arcs for n in numbers)
    for line in numbered[3:-1]:  # every row's N, before its words
        assert re.search(r"^%s " % line.split()[0], answers[0], re.M), line


def _where_walked(self) -> list:
    """FlattenCanon._generated_frames without what it keeps: the whole
    stack walked for every block (only its generated frames count, a run
    of data rows' frame at the row's line)."""
    from runtime.errors import g_code_frames_of_stack

    machine = self.machine
    return g_code_frames_of_stack(machine.line if machine.rows_run else None)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    text=st.one_of(
        strategies.valid_programs(),
        cam_strategies.commented(cam_strategies.cam_programs()),
        cam_strategies.restating(cam_strategies.arc_programs()),
    )
)
def test_where_each_block_comes_from_is_the_stacks(text, tmp_path_factory):
    """The line comment of every block (its file and line, and the calls
    that led there) is what a walk of the stack at that block finds:
    flatten keeps a walk while its generated frame runs, or while one run
    of data rows runs in one call (machine.rows_run)."""
    ways = ({}, {"_generated_frames": _where_walked})
    answers = _flat_each_way(text, tmp_path_factory.mktemp("where"), ways, "w.ngc")
    assert answers[0] == answers[1]


def test_a_subroutines_rows_name_their_call(tmp_path):
    """Data rows in a subroutine called from two places: each row's comment
    names its own line and the call that led there (it had named the call's
    file and no call: the rows' own frame was not found)."""
    rows = "".join("  G1 X%d Y%d\n" % (k, k % 3) for k in range(40))
    text = (
        "o<cut> sub\n" + rows + "o<cut> endsub\n"
        "G21 G90 F100\no<cut> call\nG0 X0\no<cut> call\nM2\n"
    )
    program = cam_strategies.cam_sized(text)
    answers = _flat_each_way(
        program, tmp_path, ({}, {"_generated_frames": _where_walked}), "s.ngc"
    )
    assert answers[0] == answers[1]
    calls = re.findall(
        r"^G1 X5 Y2  ; \S*s\.ngc:7 <- \S*s\.ngc:(\d+)$", answers[0], re.M
    )
    assert calls == ["44", "46"]
    # and the lines after each call name no call
    assert re.search(r"^G0 X0  ; \S*s\.ngc:45$", answers[0], re.M)
    assert re.search(r"^M2  ; \S*s\.ngc:47$", answers[0], re.M)


def test_the_line_after_a_call_names_no_call(tmp_path):
    """A statement's comment names the calls that led to it, walked again
    whenever its generated frame is another: the call's lines name their
    call, the line after the loop of calls names none."""
    text = (
        "o<step> sub\n  G1 X[#1 * 2] F100\no<step> endsub\n#1 = 0\n"
        "o1 while [#1 LT 3]\n  o<step> call [#1]\n  #1 = [#1 + 1]\no1 endwhile\n"
        "G0 X9\nM2\n"
    )
    answers = _flat_each_way(
        text, tmp_path, ({}, {"_generated_frames": _where_walked}), "p.ngc"
    )
    assert answers[0] == answers[1]
    assert re.search(r"^F100 G1 X4  ; \S*p\.ngc:2 <- \S*p\.ngc:6$", answers[0], re.M)
    assert re.search(r"^G0 X9  ; \S*p\.ngc:9$", answers[0], re.M)


def test_a_long_contour_is_cut_at_its_arcs_written_apart(monkeypatch):
    """An arc _arc writes apart (here: a centre on an axis, 0.0) cuts a
    contour or a run of arcs there: the rest is written in pieces
    (_arc_words once a piece), not a row at a time, and the text is the
    rows' own."""
    from ngc2py import flatten as flat

    rows = 300
    first, second, c1, c2, turns = [], [], [], [], []
    for k in range(rows):
        x, y = 10.0 * (k + 1), 0.0
        first.append(x)
        second.append(y)
        # the centre halfway, 2 above the X axis, now and then on it
        c1.append(10.0 * k + 5.0)
        c2.append(2.0 if k % 50 != 7 else 0.0)
        turns.append(0 if k % 4 == 3 else 1)
    zeros = [[0.0] * rows for _ in range(7)]
    columns = [first, second, c1, c2, turns] + zeros
    counted = []
    original = flat.FlattenCanon._arc_words

    def counting(self, *args):
        made = original(self, *args)
        counted.append(made is not None)
        return made

    monkeypatch.setattr(flat.FlattenCanon, "_arc_words", counting)
    answers = []
    for way in ("_contour_pieces", "_contour_runs"):
        canon = flat.FlattenCanon()
        where = [0.0] * 6
        texts = getattr(canon, way)((0, 1, 2), [list(c) for c in columns], where)
        answers.append((texts, where))
        if way == "_contour_pieces":
            # the pieces between the arcs apart in one go each, every arc
            # apart tried alone (and written by _arc)
            apart = sum(1 for k in range(rows) if k % 50 == 7 and turns[k])
            assert apart == 3 and counted.count(False) == apart, counted
            assert counted.count(True) <= apart + 1, counted
    assert answers[0] == answers[1]
    arcs = [list(c) for c in columns]
    arcs[4] = [1] * rows
    del counted[:]
    canon = flat.FlattenCanon()
    where = [0.0] * 6
    texts = canon._arc_texts(arcs, where)
    # the batch tried whole, then each piece between the six arcs apart
    assert counted == [False] + [True] * 7, counted
    where_each = [0.0] * 6
    assert texts == [canon._arc(args, where_each) for args in zip(*arcs)]
