"""Several spindles: ``[TRAJ]SPINDLES`` in the ``-i`` INI file, against rs274.

rs274 keeps the number as the INI file gives it (one without the key, or
when the value is not a plain int) and goes through that many spindles
where a code acts on all of them: M2/M30 stop each and set its mode, M6
stops each, M48/M49 and M51 switch each override, $-1 starts, stops or
sets the speed of each. The $ word may name any spindle below the number,
and the messages of an out-of-range $ say the number. 0, a negative number
or more than rs274's eight spindles are taken as they are (past eight rs274
writes over its own neighbouring fields, which ngc2py models). Found by a
sweep of real programs: lathe and router INI files set ``SPINDLES = 2``.
Every expected answer here is rs274's own, run on the spot.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, Phase, given, reject, settings
from hypothesis import strategies as st

import rs274 as harness
import strategies

pytestmark = pytest.mark.rs274

#: SPINDLES values as an INI file may spell them (None: no such key).
COUNTS = ["1", "2", "3", "8"]
ODD_COUNTS = [
    None,
    "0",
    "-1",
    "9",
    "12",
    "2.5",
    "abc",
    "+2",
    "02",
    "3x",
    "2147483648",
    "",
]


def ini_text(count) -> str:
    if count is None:
        return "[TRAJ]\nAXES = 3\n"
    return f"[TRAJ]\nSPINDLES = {count}\n"


def check_same(folder: Path, text: str, count, args=()) -> harness.Result:
    """rs274 and ngc2py on ``text`` with ``SPINDLES = count``: same trace,
    status and message. Returns rs274's result."""
    (folder / "m.ini").write_text(ini_text(count))
    program = folder / "p.ngc"
    program.write_text(text)
    options = ["-i", "m.ini", *args]
    expected = harness.run_rs274(program, options)
    actual = harness.run_ngc2py(program, options, mode="inprocess")
    problems = harness.compare(expected, actual)
    assert problems == [], f"SPINDLES = {count}\n{text}\n" + "\n".join(problems)
    return expected


#: Programs whose every line depends on the number of spindles somewhere.
EVERY_CODE = (
    "M3 S100\nM5\nS200 $-1\nM3 $-1\nM4 $-1\nM5 $-1\nG96 S10 D100\nG97 S20\n"
    "M48\nM49\nM51 P1\nM51 P0\nM50 P0\nM19 R10 Q2\nT1 M6\nM30\n"
)

PROGRAMS = [
    EVERY_CODE,
    "M2\n",
    "S100 M3\nT1 M6\nM2\n",
    "S100 M3 $-1\n(debug,#<_spindle_on> #<_rpm> #<_speed_override>)\nM49\n"
    "(debug,#<_spindle_on> #<_spindle_cw> #<_speed_override>)\nM2\n",
    "M4 $0\nM2\n",
    "M3 $1\nM2\n",
    "M5 $2\nM2\n",
    "M4 $7\nM2\n",
    "M3 $8\nM2\n",
    "M5 $-2\nM2\n",
    "S500 $1\n(debug,#<_rpm>)\nM2\n",
    "S500 $-1\n(debug,#<_rpm>)\nM2\n",
    "S500 $3\nM2\n",
    "S500 $-2\nM2\n",
    "M19 R5 $1\nM2\n",
    "M19 Q1 $2\nM2\n",
    "M3 S10\nM19 R5 $-1\nM2\n",
    "M51 P0 $1\nM2\n",
    "M51 P1 $0\nM2\n",
    "M51 P0 $2\nM2\n",
    "M51 P0\nM48\nM2\n",
    "G96 $1 S100 D50\n(debug,#<_spindle_css_mode>)\nM2\n",
    "G96 $-1 S100\nM2\n",
    "G97 $2 S100\nM2\n",
    "G95 $1 S100\nG1 X1 F1\nM2\n",
    "G95 $1 S0\nG1 X1 F1\nM2\n",
    "S100 M3\nG95 $1 S0\nG2 X1 R1 F1\nM2\n",
    "S100 $1\nG95\nG1 X1 F1\nM2\n",
    "G94 $1 S200\nG95 F1\nG1 X1\nM2\n",
    "S100 M3 $1\nG33 X1 K0.1 $1\nM2\n",
    "S100 M3\nG33 X1 K0.1 $1\nM2\n",
    "S100 M3 $-1\nG33.1 Z-1 K0.1 $1\nG33.1 Z-2 K0.1\nM2\n",
    "S100 M4 $1\nG76 P0.1 Z-1 I-0.1 J0.05 K0.1 $1\nM2\n",
    "S100 M3\nG76 P0.1 Z-1 I-0.1 J0.05 K0.1 $1\nM2\n",
    "S100 M3\nG76 P0.1 Z-1 I-0.1 J0.05 K0.1 $3\nM2\n",
    "M3 S100 $1\nG84 X1 Y1 Z-1 R1 F10 M3 $1\nM2\n",
    "M3 S100\nG84 X1 Y1 Z-1 R1 F10 S100 $1\nM2\n",
    "M4 S100 $1\nG74 X1 Y1 Z-1 R1 F10 S100 $1\nX2\nM2\n",
    "M3 S100\nM5 $1\nG84 X1 Y1 Z-1 R1 F10 S100 $1\nM2\n",
    "M3 S100 $-1\nG18 G84 X1 Y-1 Z1 R1 F10 S100 $1\nM2\n",
    "M3 S100 $-1\nG18 G84 X1 Y-1 Z1 R1 F10 S100 $9\nM2\n",
    "M3 S100 $0\nM4 $1\nG19 G74 X-1 Y1 Z1 R1 F10 S100 $1\nM2\n",
    "M4 S100 $0\nM3 $1\nG19 G84 X-1 Y1 Z1 R1 F10 S100 $1\nM2\n",
    "M3 S100 $-1\nM51 P0 $1\nG84 X1 Y1 Z-1 R1 F10\nM2\n",
    "M3 S100 $1\nG95 $1 S100\nG94 F10\nG86 X1 Y1 Z-1 R1 P1\nM2\n",
    "M4 S100 $1\nG96 $1 S100\nG87 X1 Y1 Z-1 R1 I1 J1 K-0.5 F10\nM2\n",
    "M3 S100\nG96 $1 S100\nG88 X1 Y1 Z-1 R1 P1 F10\nM2\n",
    "M3 S100 $-1\nM49\nM70\nM5 $-1\nM72\nM2\n",
    "S100 M3 $1\nT1 M6\nG33 X1 K0.1 $1\nM2\n",
]


@pytest.mark.parametrize("count", COUNTS)
@pytest.mark.parametrize("text", PROGRAMS)
def test_spindle_codes_as_rs274(tmp_path, text, count):
    check_same(tmp_path, text, count)


#: Programs that tell apart the odd numbers of spindles.
ODD_PROGRAMS = [
    EVERY_CODE,
    "M3 S100\nM5\nM4 $0\nS200 $-1\nG96 S10\nG95 F1\nG1 X1\nM2\n",
    "M49\n(debug,#<_spindle_on> #<_spindle_cw>)\nM48\nM2\n",
    "M49\nS100 M3\nG84 X1 Z-1 R1 F10\nM2\n",
    "S100 $-1\n(debug,#<_spindle_css_mode> #<_rpm> #<_speed_override>)\nM2\n",
    "G96 S5 $8\nS7 $-1\n(debug,#<_spindle_css_mode> #<_speed_override>)\nM2\n",
    "S100 $-1\nM3 $-1\nG95 $8 S100\nG1 X1 F1\nM19 R1\nM2\n",
    "M3 $-1\nG84 X1 Y1 Z-1 R1 F10 S100 $8\nM2\n",
]


@pytest.mark.parametrize("count", ODD_COUNTS)
@pytest.mark.parametrize("text", ODD_PROGRAMS)
def test_odd_spindle_counts_as_rs274(tmp_path, text, count):
    check_same(tmp_path, text, count)


#: Programs whose errors leave a state the next lines read (rs274's -n 0
#: goes on after an error): M19 stops every spindle before it checks $, a
#: cycle or a thread makes its $ the active spindle before it fails.
CONTINUED_PROGRAMS = [
    "M3 S100 $-1\nM19 R1 $5\n(debug,#<_spindle_on>)\nG33 X1 K0.1 $1\nM2\n",
    # (G0 to all three axes: after a failed cycle under -i, rs274 keeps a
    # position of its own that ngc2py does not follow, spindles or not)
    "M4 S100 $1\nG84 X1 Y1 Z-1 R1 F10 S100 $1\nG80 G0 X0 Y0 Z0\nG33 X1 K0.1\nM2\n",
    "S100 M3\nG33 X1 K0.1 $1\nG33 X2 K0.1\nG95 F1\nG33 X3 K0.1\nM2\n",
    "S100 M3\nG76 P0.1 Z-1 I-0.1 J0.05 K0.1 $1\nG95 $1 F1\nG1 X3\nM2\n",
    "M3 $-1\nS100 $-1\nM3 $7\nG1 X1 F1\nM2\n",
]


@pytest.mark.parametrize("count", ["0", "2", "3"])
@pytest.mark.parametrize("text", CONTINUED_PROGRAMS)
def test_state_after_errors_as_rs274(tmp_path, text, count):
    check_same(tmp_path, text, count, ["-n", "0"])


def _cam_program() -> str:
    """Over 64 constant lines, spindle codes among the moves: the compiler
    writes them as data rows (runtime.fast.rows), which must step aside
    for each spindle line."""
    lines = ["G21 G90 G94 F100"]
    for i in range(90):
        lines.append(f"G1 X{i % 7}.5 Y{i % 5}.25")
        if i % 9 == 0:
            lines.append(f"S{100 + i} M3 $1")
        if i % 13 == 0:
            lines.append(f"S{200 + i} $-1")
        if i % 17 == 0:
            lines.append("M5 $-1")
        if i % 19 == 0:
            lines += [f"G95 $1 S{i}", "G1 X1 F0.1", "G94 F100"]
        if i % 23 == 0:
            lines.append("M51 P0 $1")
        if i % 29 == 0:
            lines.append("M19 R10 $1")
    return "\n".join(lines + ["M2"]) + "\n"


@pytest.mark.parametrize("count", ["1", "2", "8"])
def test_data_rows_of_spindle_codes_as_rs274(tmp_path, count):
    check_same(tmp_path, _cam_program(), count)


@pytest.mark.parametrize("text", [EVERY_CODE, PROGRAMS[3], _cam_program()])
def test_converted_module_reads_spindles_as_rs274(tmp_path, text):
    """A generated module on its own takes -i too."""
    (tmp_path / "m.ini").write_text(ini_text("3"))
    program = tmp_path / "p.ngc"
    program.write_text(text)
    expected = harness.run_rs274(program, ["-i", "m.ini"])
    actual = harness.run_ngc2py(program, ["-i", "m.ini"], mode="convert")
    assert harness.compare(expected, actual) == []


def test_the_number_of_spindles_shows(tmp_path):
    """The comparisons above would pass if SPINDLES had no effect on either
    side: rs274's M2 really stops one spindle more for each one more."""
    one = check_same(tmp_path, "M2\n", "1").stdout.count(b"STOP_SPINDLE_TURNING")
    three = check_same(tmp_path, "M2\n", "3").stdout.count(b"STOP_SPINDLE_TURNING")
    assert (one, three) == (1, 3)


# --------------------------------------------------------------------------
# Generated programs: spindle codes with $ words under SPINDLES 1..8
# --------------------------------------------------------------------------

PROFILE = settings(
    derandomize=os.environ.get("NGC2PY_HYPOTHESIS_PROFILE", "ci") == "ci",
    database=None,
    deadline=None,
    max_examples=int(os.environ.get("NGC2PY_DIFF_EXAMPLES") or 40),
    phases=[Phase.explicit, Phase.generate],
    suppress_health_check=list(HealthCheck),
    print_blob=False,
)


@PROFILE
@given(
    st.integers(1, 8).flatmap(
        lambda n: st.tuples(st.just(n), strategies.spindle_programs(n))
    )
)
def test_generated_spindle_programs(drawn):
    count, text = drawn
    # the runners copy a program's folder: the INI file goes beside it
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "m.ini").write_text(strategies.spindles_ini(str(count)))
        program = folder / "p.ngc"
        program.write_text(text)
        expected = harness.run_rs274(program, ["-i", "m.ini"], timeout=20)
        if expected.timed_out or (expected.rc is not None and expected.rc < 0):
            reject()
        actual = harness.run_ngc2py(program, ["-i", "m.ini"], mode="inprocess")
    problems = harness.compare(expected, actual)
    assert problems == [], f"SPINDLES = {count}\n{text}\n" + "\n".join(problems)
