"""``ngc2py.parse`` against LinuxCNC's own ``gcode.parse``.

Where an interpreter with LinuxCNC's ``gcode`` module is installed (Debian's
``/usr/bin/python3`` with linuxcnc-uspace; override with GCODE_PYTHON), every
program runs through both, with the same recording canon, and the call
sequences must be the same: every call, its arguments (floats to 1e-9
relative), every ``next_line`` with its sequence number and its modal codes
(all but ``mcodes[0]``, the number of the last block the interpreter wrote,
which ngc2py does not track), the result and the error message.

That module crashes (SIGSEGV) on T words and G43 outside a running LinuxCNC
(its tool data lives in shared memory): such programs are skipped with that
reason, as are golden programs that need rs274's -t/-v/-i/-b options.
"""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import subprocess
from pathlib import Path
from typing import Optional

import pytest
from hypothesis import given, reject, settings
from hypothesis import strategies as st

import cam_strategies
import test_cycles
from test_canon import AT, BATCHED, breaking, raises
import rs274 as harness
from gcode_answers import ANSWERS, QUESTIONS  # the canon's answers, shared
import strategies
from test_differential import PROFILE
from test_stats import scratch_run

import ngc2py
from ngc2py import preview
from ngc2py.preview import LineCode, MIN_ERROR, strerror
from runtime import canon as runtime_canon

GCODE_PYTHON = os.environ.get("GCODE_PYTHON", "/usr/bin/python3")
REFERENCE = Path(__file__).with_name("gcode_reference.py")
CRASH_REASON = "LinuxCNC's gcode module crashes on this program (T words, G43)"


def _has_gcode_module() -> bool:
    if not shutil.which(GCODE_PYTHON):
        return False
    probe = subprocess.run(
        [GCODE_PYTHON, "-c", "import gcode"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    return probe.returncode == 0


HAS_GCODE = _has_gcode_module()
needs_gcode = pytest.mark.skipif(
    not HAS_GCODE,
    reason="no Python with LinuxCNC's gcode module (%s; set GCODE_PYTHON)"
    % GCODE_PYTHON,
)


class Recorder:
    """The canon of tests/gcode_reference.py, on this side."""

    def __init__(self):
        self.calls = []
        self.questions = []

    def __getattr__(self, name):
        if name.startswith("__") or name in ("parameter_file", "print_text"):
            raise AttributeError(name)

        def method(*args):
            if name in QUESTIONS:
                self.questions.append(name)
                if name == "get_tool":
                    return (args[0],) + (0.0,) * 12 + (0,)
                return ANSWERS[name]
            if name == "next_line":
                line = args[0]
                args = (line.sequence_number, list(line.gcodes), list(line.mcodes))
                args += (line.feed_rate, line.speed)
            self.calls.append([name, list(args)])

        return method


def reference(scratch, name: str, extra) -> Optional[dict]:
    """gcode.parse's calls, or None when the module crashed."""
    out = scratch.tmp / "reference.json"
    proc = subprocess.run(
        [GCODE_PYTHON, str(REFERENCE), name, json.dumps(extra), str(out)],
        cwd=scratch.work,
        env=scratch.env({"PYTHONPATH": ""}),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        timeout=60,
    )
    if proc.returncode < 0 or not out.exists():
        return None
    return json.loads(out.read_text())


def ours(name: str, extra) -> dict:
    recorder = Recorder()
    result = list(ngc2py.parse(name, recorder, *extra))
    return {
        "calls": recorder.calls,
        "result": result,
        "message": strerror(result[0]) if result[0] >= MIN_ERROR else "",
        "questions": sorted(set(recorder.questions)),
    }


def _same(a, b) -> bool:
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a):
        return math.isnan(b)  # an R 0 arc's centre
    if isinstance(a, float) or isinstance(b, float):
        return math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-12)
    return a == b


#: Line code entries ngc2py does not reproduce: the last block's group 0 G
#: code, its stopping and tool change M codes and its number (rs274 writes
#: them for parameter-only lines too, which ngc2py does not see as blocks).
_BLOCK_FIELDS = ((1, 2), (2, 0), (2, 1), (2, 3))


def _comparable(call):
    name, args = call
    if name != "next_line":
        return call
    sequence, gcodes, mcodes, feed_rate, speed = args
    codes = [list(gcodes), list(mcodes)]
    for which, index in _BLOCK_FIELDS:
        codes[which - 1][index] = None
    return [name, [sequence] + codes + [feed_rate, speed]]


def _final_line_after_error(calls):
    """After an error the module's last line code shows the failing block's
    half-done state; only its sequence number is compared."""
    if calls and calls[-1][0] == "next_line":
        calls[-1] = ["next_line", [calls[-1][1][0]]]


def assert_same_calls(expected: dict, actual: dict) -> None:
    want = [_comparable(c) for c in expected["calls"]]
    got = [_comparable(c) for c in actual["calls"]]
    if expected["result"][0] >= MIN_ERROR:
        _final_line_after_error(want)
        _final_line_after_error(got)
    for index, (w, g) in enumerate(zip(want, got)):
        same = w[0] == g[0] and len(w[1]) == len(g[1])
        same = same and all(
            _same(x, y) if not isinstance(x, list) else x == y
            for x, y in zip(w[1], g[1])
        )
        assert (
            same
        ), "call %d differs:\n  gcode.parse: %r\n  ngc2py:      %r\n  before: %r" % (
            index,
            w,
            g,
            want[max(0, index - 3) : index],
        )
    assert len(want) == len(got), (want[len(got) :], got[len(want) :])
    assert actual["result"] == expected["result"]
    assert actual["message"] == expected["message"]
    # check_abort is asked about once a second: whether a run asks it at
    # all depends on how fast the machine is, so it is left out
    timed = {"check_abort"}
    assert set(actual["questions"]) - timed == set(expected["questions"]) - timed


def compare(
    program: Path, extra=("G20", ""), text: Optional[str] = None, crashed=None
) -> None:
    """Both runs of ``program`` must make the same calls; when the module
    crashes, ``crashed()`` (default: skip the test, with the reason)."""
    with scratch_run(program, text, args=()) as s:
        expected = reference(s, s.program.name, list(extra))
        if expected is None:
            (crashed or (lambda: pytest.skip(CRASH_REASON)))()
            return
        actual = ours(s.program.name, list(extra))
    assert_same_calls(expected, actual)


_PY = (
    "deliberate: a (py, ...) comment's (or ;py, line's) error is reported by gcode.parse as "
    "py_execute(...) with the traceback of running the code in LinuxCNC's "
    "embedded Python; ngc2py never runs embedded Python and reports rs274 -g's "
    "run_string(...) (see tests/test_not_copied.py)"
)

_FANUC_LINE = (
    "gap: an M98 of an o-word sub read before it (runtime/fanuc_subs.py): gcode.parse"
    " makes no next_line for the sub's line before the error, ngc2py.parse does;"
    " the rs274 trace and message match (golden/fanuc_calls)"
)

#: Known differences between ngc2py.parse and gcode.parse: program (golden
#: name, or LinuxCNC sample file name) -> reason. Marked as strict expected
#: failures, so a fixed one shows up as XPASS(strict).
KNOWN_GAPS = {
    **{
        "comments/" + name: _PY
        for name in (
            "py_indented py_name_error py_syntax_error py_zero_division"
            " py_semicolon_error py_interpreter_check_fails"
            " py_interpreter_missing_param py_this_without_import"
        ).split()
    },
    "fanuc_calls/m98_osub_read_before": _FANUC_LINE,
}

#: Generated programs using a feature with a known gap (see KNOWN_GAPS):
#: (py, ...) comments and ;py, lines, whose errors are reported
#: differently on purpose.
_GAP_FEATURES = re.compile(r"\(\s*py\s*,|^;py,", re.I | re.M)


def _known_gap(name: str) -> list:
    reason = KNOWN_GAPS.get(name)
    return [pytest.mark.xfail(reason=reason, strict=True)] if reason else []


def _compare_generated(text: str) -> None:
    """compare() for a generated program; a mismatch in a program that uses
    a feature with a known gap is an expected failure, named as such."""
    try:
        compare(
            harness.REPO / "tests" / "_generated" / "preview.ngc",
            text=text,
            crashed=reject,
        )
    except AssertionError:
        found = _GAP_FEATURES.search(text)
        if found:
            pytest.xfail("known gap, the program uses %s (see KNOWN_GAPS)" % found[0])
        raise


def _golden():
    return [
        pytest.param(p, marks=_known_gap(_golden_id(p)))
        for p in harness.golden_programs()
        if p.with_suffix(".rc").exists() and not harness.read_args(p)
    ]


def _golden_id(p) -> str:
    return str(p.relative_to(harness.GOLDEN).with_suffix(""))


@needs_gcode
@pytest.mark.parametrize(
    "program",
    _golden(),
    ids=_golden_id,
)
def test_golden_programs_match_gcode_parse(program):
    compare(program)


@needs_gcode
@pytest.mark.parametrize(
    "extra",
    [(), ("G21",), ("G20", "G17"), ("G21", "G18 G91"), (["G21", "G19", "G90"],)],
    ids=["none", "unitcode", "unit-and-init", "init-modes", "list-form"],
)
def test_init_codes_match_gcode_parse(extra):
    compare(harness.REPO / "examples" / "flange.ngc", extra)


#: What an init code's words are: a letter and a number, blanks around.
INIT_WORD = re.compile(r"\s*([A-Za-z])\s*([-+]?(?:\d+\.?\d*|\.\d+))")


def words_by_pattern(text):
    found, at = [], 0
    while at < len(text):
        match = INIT_WORD.match(text, at)
        if match is None:
            return None
        found.append(match.groups())
        at = match.end()
    return found


@given(
    st.lists(
        st.one_of(
            st.sampled_from(["G", "g", "M", "F", "x", "21", "-", "+", ".", "5.", ".5"]),
            st.sampled_from([" ", "\t", "\u00a0", "\u0663", "\u00b2", "Ä", "e", "%"]),
            st.text(max_size=3),
        ),
        max_size=10,
    ).map("".join)
)
def test_init_words_are_read_as_the_pattern_reads_them(text):
    # ngc2py.preview scans init codes by hand (a parse imports no re)
    text = text.strip()
    assert preview._init_words(text) == words_by_pattern(text)


@needs_gcode
@pytest.mark.parametrize(
    "text",
    [
        "G21\nG0 X1\n",  # no end: error at end of file
        "%\nG0 X1\n%\n",  # closing %
        "\n\n%\n\nG1 X1 F10\n%\n",  # % after blank lines
        "G1 X1 Y$3\nM2\n",  # read error
        "G21 F10\nG2 X1 Y1 I9 J9\nM2\n",  # execution error
        "o<s> sub\nG0 X1\nG1 X[1/0]\no<s> endsub\nG21\no<s> call\nM2\n",  # error in a call
        "G17.1\nG18.1\nG19.1\nG17\nM2\n",  # UVW planes
        "M0\nM1\nM60\nM30\n",
        "(PRINT, printed #5220)\n(DEBUG, shown)\n(MSG, hi)\nM2\n",
        # a local in a Python variable read unset: the store's error
        "o<s> sub\no1 if [#1 GT 1]\n#<a> = 4\no1 endif\nG0 X#<a>\no<s> endsub\n"
        "G21\no<s> call [2]\no<s> call [0]\nM2\n",
        "#<a> = 2 (comment)\n(MSG, a)\n(PRINT, #<a>)\nG0 X#<a>\n(abort, #<a>)\nM2\n",
        "G20 G0 X1\nG21 G1 X2 F3\nG93 G1 X3 F2\nM2\n",  # units and inverse time
        "/G0 X5\nG0 Y1\nM2\n",  # block delete is asked for
        # a spline's feeds keep the last straight move's Z; the interpreter
        # keeps its own (G88 left it at R): the next move shows it
        "G21 F100\nS222 M4 G91 G88 X5.1 Z-0.8 R1.4 P1\nG90 G80\n"
        "G5.1 I-1.5 J1 X0 Y5.7\nG1 Y-14.2\nM2\n",
    ],
)
def test_edge_cases_match_gcode_parse(tmp_path, text):
    compare(tmp_path / "prog.ngc", text=text)


def test_missing_file(tmp_path):
    recorder = Recorder()
    result = ngc2py.parse(str(tmp_path / "missing.ngc"), recorder, "G20")
    assert result == (4, 1)
    assert strerror(result[0]) == "File not open"


def test_user_m_codes_call_user_defined_function(tmp_path):
    path = tmp_path / "prog.ngc"
    path.write_text("M101 P2 Q3\nM2\n")
    recorder = Recorder()
    with scratch_run(path) as s:
        assert ngc2py.parse(s.program.name, recorder, "G20")[0] == 1
    # The module passes the number of the M code less 100.
    assert ["user_defined_function", [1, 2.0, 3.0]] in recorder.calls


def test_check_abort_stops_the_run(tmp_path, monkeypatch):
    import ngc2py.preview as preview

    monkeypatch.setattr(preview, "ABORT_INTERVAL", -1.0)  # ask at every line
    path = tmp_path / "prog.ngc"
    path.write_text("G0 X1\nG0 X2\nM2\n")

    class Abort(Recorder):
        def check_abort(self):
            return True

    with scratch_run(path) as s, pytest.raises(KeyboardInterrupt):
        ngc2py.parse(s.program.name, Abort())


def test_canon_exceptions_propagate(tmp_path):
    path = tmp_path / "prog.ngc"
    path.write_text("G0 X1\nM2\n")

    class Broken(Recorder):
        def straight_traverse(self, *args):
            raise ValueError("preview broke")

    with scratch_run(path) as s, pytest.raises(ValueError, match="preview broke"):
        ngc2py.parse(s.program.name, Broken())


@pytest.mark.parametrize("program", sorted(BATCHED))
@pytest.mark.parametrize("raised", [ValueError, StopIteration])
def test_an_exception_in_a_batch_stops_the_run_at_that_call(tmp_path, program, raised):
    """A canon method's exception stops the run at the very call, batch or
    not. StopIteration would only end the iterator of calls a batch is
    made from, silently: there it becomes a RuntimeError (as in a
    generator); a call made alone raises it as it is."""
    path = tmp_path / "prog.ngc"
    path.write_text(BATCHED[program])
    made: list = []
    with scratch_run(path) as s, raises(raised):
        ngc2py.parse(s.program.name, breaking(Recorder, raised, made)())
    assert len(made) == AT


def test_print_reaches_the_canon_not_stdout(tmp_path, capfd):
    path = tmp_path / "prog.ngc"
    path.write_text("(PRINT, hello)\nM2\n")
    printed = []

    class Printing(Recorder):
        def print_text(self, text):
            printed.append(text)

    with scratch_run(path) as s:
        ngc2py.parse(s.program.name, Printing())
    assert printed == [" hello"]
    assert capfd.readouterr() == ("", "")


def test_linecode_fields():
    line = LineCode(
        (7, 10) + (0,) * 15, (6, -1, 3) + (0,) * 7, (7.0, 100.0, 2000.0, 0.0, 0.0)
    )
    assert (line.sequence_number, line.motion_mode, line.spindle) == (7, 10, 3)
    assert (line.feed_rate, line.speed) == (100.0, 2000.0)


@needs_gcode
@settings(PROFILE)
@given(strategies.valid_programs(feed_modes=True))
def test_generated_programs_match_gcode_parse(text):
    _compare_generated(text)


@needs_gcode
@settings(PROFILE)
@given(strategies.compensated_programs())
def test_compensated_programs_match_gcode_parse(text):
    """Under cutter compensation rs274 holds each move until the next one
    settles its end: gcode.parse announces a held move with the line that
    queued it (the motion call's own line number), not the line flushing
    it (once a known gap, on five golden programs)."""
    _compare_generated(text)


@needs_gcode
@settings(PROFILE)
@given(cam_strategies.cam_programs(), st.sampled_from(("G21", "G20", "")))
def test_cam_tables_match_gcode_parse(text, units):
    """CAM tables: their batches of plain rows reach the preview as one
    straight_moves call each (runtime.fast.rows.BatchesOnly); every next_line
    and move must still be gcode.parse's."""
    _compare_generated(units + "\n" + text)


@needs_gcode
@settings(PROFILE)
@given(st.one_of(test_cycles.cycle_tables(), test_cycles.restated_cycle_lines()))
def test_cycle_tables_match_gcode_parse(text):
    """Rows of hole words under a modal canned cycle (Machine.cycle_row):
    every move, line code and error line must still be gcode.parse's."""
    _compare_generated(text)


LOOP_BODIES = [
    "G1 X[#<i> * 2] F[100 + #<i>]\nG0 Y[#<i>]",
    "G1 X[#<i>] Y1 F200\nG1 Y2 F300\nX[#<i> + 1]",
    "G2 X[#<i> + 2] Y0 I1 J0 F150\nG3 X[#<i> + 4] Y0 R1\nG1 Z[-#<i>]",
    "G0 X[#<i>]\nG92 X0\nG1 Y[#<i>] F50\nG92.1\nG1 Y0",
    "G1 X[#<i>] F[10 * [#<i> + 1]]\nM3 S[100 * #<i>]\nG1 Y[#<i>]",
    # one move line alone: run again and again, it is announced once, and
    # the line after the loop is announced with what its last run left
    "G1 X[#<i> * 2] F[100 + #<i>]",
    "G1 X[#<i>] F100\no2 if [#<i> EQ 4]\nG92 X0\no2 endif",
    "G1 X[#<i>] F100\no2 if [#<i> EQ 4]\nM3 S500\no2 endif",
]


@needs_gcode
@pytest.mark.parametrize("body", LOOP_BODIES)
@pytest.mark.parametrize("units", ["G21", "G20"])
def test_loops_of_plain_lines_match_gcode_parse(body, units):
    """A loop's plain move and arc lines take the fast paths in the preview
    too: each line must still be announced with the modes (motion, feed,
    speed, G92 flag) the line before left, as gcode.parse announces it."""
    text = "%s G90 G17\n#<i> = 0\no1 while [#<i> LT 6]\n%s\n#<i> = [#<i> + 1]\no1 endwhile\nM2\n"
    _compare_generated(text % (units, body))


#: Lines a loop's body is made of: plain moves (the one-method path) and
#: lines that make the next moves take the general one, or announce them
#: with other modes.
_LOOP_LINES = st.sampled_from(
    [
        # the one-method path: G0/G1 with X, Y and/or Z alone
        "G1 X[#<i> * 2]",
        "G0 Y[#<i> - 3] Z[#<i> + 1]",
        "G1 X[#<i>] Y[#<i> / 2] Z-1",
        "G1 Z[1 - #<i>]",
        "G0 X[3 - #<i>] Z2",
        "G1 X[#5420 + 1] Y[#5421 / 2]",  # where the move before left the tool
        # lines that change what the next moves are announced with, or
        # send them the general way
        "F[50 + #<i>]",
        "G1 Z1 F[50 + #<i>]",
        "F0",
        "N7 G1 X[#<i> + 1]",
        "G91 G1 X1",
        "G90",
        "G92 X1 Z-2",
        "G92.1",
        "M3 S[100 * #<i>]",
        "G20",
        "G21",
        "G0 X1 A[#<i>]",
        "G2 X[#<i> + 2] Y0 I1 J0 F150",
        "(a comment)",
    ]
)


@settings(PROFILE)
@given(
    st.lists(_LOOP_LINES, min_size=1, max_size=8), st.sampled_from(("G21", "G20", ""))
)
def test_a_loops_moves_in_one_method_make_the_general_calls(
    monkeypatch_moves, tmp_path_factory, body, units
):
    """The preview's m.feed and m.rapid in one method (a loop's every move)
    make every call, argument and line code that the general single line,
    XYZ move and PreviewCanon's straight move make, whatever the lines
    around them change."""
    text = (
        "%s G90 G17 F100\n#<i> = 0\no1 while [#<i> LT 4]\n%s\n"
        "#<i> = [#<i> + 1]\no1 endwhile\nM2\n"
    )
    path = tmp_path_factory.mktemp("moves") / "loop.ngc"
    path.write_text(text % (units, "\n".join(body)))
    fused = ours(str(path), ())
    with monkeypatch_moves():
        general = ours(str(path), ())
    assert fused == general


@pytest.fixture
def monkeypatch_moves(monkeypatch):
    """A context in which the preview's moves take the general path."""
    from contextlib import contextmanager

    from runtime.fast.rows import BatchesOnly

    @contextmanager
    def general():
        with monkeypatch.context() as patched:
            patched.setattr(preview.PreviewMachine, "feed", BatchesOnly.feed)
            patched.setattr(preview.PreviewMachine, "rapid", BatchesOnly.rapid)
            yield

    return general


@needs_gcode
@settings(PROFILE)
@given(cam_strategies.arc_programs(), st.sampled_from(("G21", "G20", "")))
def test_arc_tables_match_gcode_parse(text, units):
    """Arc tables: runs of arc rows of one layout reach the preview as one
    arc_moves call each (G2 and G3 mixed); every next_line, with the motion
    mode the line before left, and every arc must still be gcode.parse's."""
    _compare_generated(units + "\n" + text)


@needs_gcode
@settings(PROFILE)
@given(
    cam_strategies.restating(
        cam_strategies.arc_programs() | cam_strategies.cam_programs()
    )
    | cam_strategies.commented(cam_strategies.cam_programs())
    | cam_strategies.hand_drilling()
)
def test_shop_programs_match_gcode_parse(text):
    """What shops' programs add to CAM rows: modes restated on every line
    (``G17 G2 X.. R..`` a row the preview takes as an arc's line, with its
    SELECT_PLANE), comments on moves, a hole at a time with G4 pauses:
    every next_line, call and error line must still be gcode.parse's."""
    _compare_generated(text)


@settings(PROFILE)
@given(text=cam_strategies.hand_drilling())
def test_a_pause_row_leaves_the_modes_block_leaves(text, tmp_path_factory):
    """A G4 row taken by the fast path (BatchesOnly.dwell_row) leaves the
    line codes block() writes, its G4 in group 0 too (which the comparison
    with gcode.parse leaves out): every call and line code the same."""
    from runtime.fast import rows

    folder = tmp_path_factory.mktemp("pause")
    program = folder / "pause.ngc"
    program.write_text(text)
    answers = []
    for fast in (True, False):
        with pytest.MonkeyPatch.context() as patch:
            if not fast:  # every pause by block()
                patch.setattr(
                    rows.BatchesOnly,
                    "dwell_row",
                    lambda m, line, n, p: m.block(line, rows.G4, n=n, p=p),
                )
            recorder = Recorder()
            result = list(ngc2py.parse(str(program), recorder, "G20", ""))
            answers.append((recorder.calls, result))
    assert answers[0] == answers[1]


@settings(PROFILE)
@given(
    text=st.just(None)
    | strategies.compensated_programs().map(
        # (rows past its end make its runs data tables)
        lambda text: text
        + "G0 X0\n" * cam_strategies.MIN_PROGRAM_ROWS
    )
)
def test_rows_under_cutter_compensation_go_by_the_general_path(text, tmp_path_factory):
    """Data rows under cutter compensation (its queue stands for the canon)
    go by the general path: the same calls as with no fast path for rows
    at all (an AttributeError, once). gcode.parse crashes on such programs."""
    from runtime.fast import rows
    from test_flatten import _compensated_table

    program = tmp_path_factory.mktemp("comp") / "comp.ngc"
    program.write_text(_compensated_table() if text is None else text)
    answers = []
    for fast in (True, False):
        with pytest.MonkeyPatch.context() as patch:
            if not fast:
                patch.setattr(rows.BatchesOnly, "plain_rows", lambda m, c, at, e, p: at)
            recorder = Recorder()
            result = list(ngc2py.parse(str(program), recorder, "G20", ""))
            answers.append((recorder.calls, result))
    assert answers[0] == answers[1]
    if text is None:
        assert answers[0][1][0] < MIN_ERROR and len(answers[0][0]) > 60


@needs_gcode
def test_a_contour_restating_g17_on_its_arcs_matches_gcode_parse():
    """A table of lines and arcs with G17 restated on each arc: the arcs
    are taken as arcs' lines (runtime.fast.rows.BatchesOnly.plane_arc), each
    with its SELECT_PLANE, as gcode.parse makes them."""
    lines = ["G21 G90 G17 G94 F300", "G0 X0 Y0 Z1", "G1 Z-1"]
    x = 0.0
    for k in range(60):
        lines.append("G1 X%.3f Y0" % (x + 1))
        lines.append("G17 G%d X%.3f Y0 R%.3f" % (2 + k % 2, x + 5, 2.0))
        x += 5
    lines.append("M2")
    _compare_generated(cam_strategies.cam_sized("\n".join(lines) + "\n"))


@needs_gcode
@settings(PROFILE, max_examples=max(10, PROFILE.max_examples // 2))
@given(strategies.invalid_programs())
def test_generated_broken_programs_match_gcode_parse(text):
    _compare_generated(text)


def _ncfiles():
    from test_ncfiles import NCFILES

    if not NCFILES.is_dir():
        return []
    return [
        pytest.param(p, marks=_known_gap(p.name)) for p in sorted(NCFILES.glob("*.ngc"))
    ]


@needs_gcode
@pytest.mark.parametrize("program", _ncfiles(), ids=lambda p: p.name)
def test_linuxcnc_samples_match_gcode_parse(program):
    """LinuxCNC's own samples, used in place (programs nobody here wrote)."""
    from test_ncfiles import out_of_scope

    codes = out_of_scope(program)
    if codes:
        pytest.skip("out of ngc2py's scope: %s" % ", ".join(codes))
    compare(program)


@needs_gcode
def test_parameter_file_attribute(tmp_path):
    """``canon.parameter_file`` is the .var file both read at start."""
    (tmp_path / "prog.var").write_text(
        "5220\t1.000000\n5221\t2.000000\n5222\t3.000000\n"
    )
    path = tmp_path / "prog.ngc"
    path.write_text("G21 G0 X1\n(DEBUG, #5221 #5222)\nM2\n")

    class WithFile(Recorder):
        parameter_file = "prog.var"

    with scratch_run(path) as s:
        expected_out = s.tmp / "with-file.json"
        script = (
            "import sys; sys.argv = sys.argv[:1] + %r;"
            "import gcode_reference as g;"
            "g.Recorder.parameter_file = 'prog.var';"
            "g.main()"
        ) % (
            [s.program.name, '["G20", ""]', str(expected_out)],
        )
        subprocess.run(
            [GCODE_PYTHON, "-c", script],
            cwd=s.work,
            env=s.env({"PYTHONPATH": str(REFERENCE.parent)}),
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            timeout=60,
        )
        expected = json.loads(expected_out.read_text())
        recorder = WithFile()
        result = list(ngc2py.parse(s.program.name, recorder, "G20", ""))
    messages = [c for c in recorder.calls if c[0] == "message"]
    assert messages == [["message", [" 2.000000 3.000000"]]]
    assert messages == [c for c in expected["calls"] if c[0] == "message"]
    assert result == expected["result"]


@given(
    st.lists(
        st.one_of(
            st.floats(allow_nan=True, allow_infinity=True),
            st.integers(-(10**20), 10**20),
            st.sampled_from([0.0, -0.0, 1e-320, 5e-324]),
        ),
        max_size=40,
    ),
    st.sampled_from([25.4, 1.0, -3.5, 1e-300]),
)
def test_columns_are_divided_as_a_comprehension_divides_them(column, divisor):
    # ngc2py.preview's columns in inches (runtime/fast/_columns.c where built)
    expected = [value / divisor for value in column]
    found = preview.divided(column, divisor)
    assert [repr(v) for v in found] == [repr(v) for v in expected]
    assert [type(v) for v in found] == [type(v) for v in expected]


@pytest.mark.skipif(
    preview.call_rows is runtime_canon.python_call_rows,
    reason="runtime._call_rows not built here: the preview uses the twin already",
)
@settings(PROFILE)
@given(
    st.one_of(
        cam_strategies.cam_programs(),
        cam_strategies.arc_programs(),
        test_cycles.cycle_tables(),
    ),
    st.sampled_from(("G21", "G20")),
)
def test_the_preview_makes_the_same_calls_without_the_c_batches(text, units):
    """The preview's batches (straight, arc, contour and hole rows) make
    their calls by runtime._call_rows; by its Python twin, where it is not
    built, every call and line code must be the same."""
    scratch = harness.REPO / "tests" / "_generated" / ("twin-%d.ngc" % os.getpid())
    scratch.parent.mkdir(exist_ok=True)
    scratch.write_text(units + "\n" + text)
    with_c = ours(str(scratch), ())
    original = preview.call_rows
    preview.call_rows = runtime_canon.python_call_rows
    try:
        with_twin = ours(str(scratch), ())
    finally:
        preview.call_rows = original
    assert with_twin == with_c


@settings(PROFILE)
@given(st.one_of(test_cycles.cycle_tables(), test_cycles.restated_cycle_lines()))
def test_holes_made_hole_by_hole_are_announced_as_in_batches(text):
    """Holes with a call the preview's batch does not know go hole by hole
    (PreviewCanon._hole_by_hole): each at its own line, so every call and
    line code is the batch's."""
    scratch = harness.REPO / "tests" / "_generated" / ("holes-%d.ngc" % os.getpid())
    scratch.parent.mkdir(exist_ok=True)
    scratch.write_text(text)
    batched = ours(str(scratch), ())
    original = preview.PreviewCanon.hole_moves
    preview.PreviewCanon.hole_moves = preview.PreviewCanon._hole_by_hole
    try:
        by_hole = ours(str(scratch), ())
    finally:
        preview.PreviewCanon.hole_moves = original
    assert by_hole == batched
