"""rs274 behaviours ngc2py deliberately does NOT copy, and what it does instead.

ngc2py's rule is "rs274 is the truth", except where rs274 hangs or crashes:
there ngc2py must do better, and this module says so, case by case. The
crashes on over-long comment expansions are golden programs with an
``.expect`` file (golden/README.md); the rest is here:

1. A program that never ends (``o1 while [1]`` with nothing in it, a call
   chain that loops) runs rs274 forever. ngc2py counts loop iterations and
   calls (runtime.budget) and stops with an error naming the file and the
   loop line once ``--max-steps`` (default DEFAULT_MAX_STEPS) is spent;
   ``ngc2py.parse`` (``max_steps=``) returns that error where LinuxCNC's
   preview loads the file forever.
2. ``rs274 -n 0`` on a file that ends without ``%`` or M2 reports "File
   ended with no percent sign or program end" again and again, forever.
   ngc2py reports it once and exits 1.
3. ``-n 0``/``-n 1`` after an error in an expression or an O-word line:
   rs274 goes on with its next line; ngc2py cannot re-enter compiled code
   in the middle of a line and stops there, exit 1 (runtime.continue_mode).
   It does go on after errors in reading or executing a line's block, as
   rs274 does (golden/continue).
4. ``-n 1``: rs274 starts an interactive MDI prompt; ngc2py has no MDI, it
   refuses each line given, then asks whether to continue as rs274 does.
5. ``(py,CODE)`` comments (and lines beginning ``;py,``): rs274 runs CODE
   in its embedded Python. ngc2py never runs code from a G-code file: it
   evaluates simple assignments, arithmetic and the ``assert`` checks of
   the interpreter's state that LinuxCNC's tests write (``this.params``,
   ``this.call_level``, ``equal``...) itself (golden/comments/py_*) and
   stops with an error that says so on anything else, e.g. an import of
   another module. ``(pyrun,...)`` does nothing.
6. ``[RS274NGC]REMAP`` in the ``-i`` file: rs274 runs the remapped code's
   subroutine (or Python handler). ngc2py does not run remaps: a remapped
   code it does not know (``M400``) fails where it is used, a remap of a
   code it would run (``M6``) fails as the program starts, both saying
   that the code is remapped (runtime.remap).
7. ``[PYTHON]TOPLEVEL`` in the ``-i`` file: rs274 loads that Python, whose
   functions can be O-word subroutines and global parameters. ngc2py runs
   no embedded Python: a call no G-code defines, or a global no G-code
   set, fails saying so (runtime.remap), not with rs274's "not found".

Each case shows rs274's behaviour where it can be shown cheaply (a hang is
checked with a short timeout), then ngc2py's.
"""

from __future__ import annotations

import io
import os
import subprocess
import sys
from pathlib import Path

import pytest

import rs274 as harness
from runtime.budget import DEFAULT_MAX_STEPS, runaway_message
from runtime.canon import NullCanon, RecordingCanon
from runtime.errors import GCodeError
from runtime.machine import Machine
from runtime.main import parse_options

REPO = Path(__file__).resolve().parent.parent

ENDLESS = "G0 X1\no1 while [1]\no1 endwhile\nM2\n"


def ngc2py_run(tmp_path, text, *args, stdin=""):
    program = tmp_path / "prog.ngc"
    program.write_text(text)
    env = dict(os.environ, PYTHONPATH=str(REPO), NGC2PY_CACHE=str(tmp_path / "c"))
    return subprocess.run(
        [sys.executable, "-m", "ngc2py", "run", *args, program.name],
        cwd=tmp_path,
        env=env,
        input=stdin,
        capture_output=True,
        text=True,
        timeout=120,
    )


def compiled(program: str, folder: Path):
    """The generated module for G-code text ``program``, imported."""
    from ngc2py.cli import load_module
    from ngc2py.compiler import compile_text

    path = folder / "prog.py"
    path.write_text(compile_text(program, "prog.ngc"))
    return load_module(path)


# -- 1. endless programs ------------------------------------------------------


@pytest.mark.rs274
def test_rs274_hangs_on_an_endless_loop(tmp_path):
    result = harness.run_rs274(tmp_path / "endless.ngc", text=ENDLESS, timeout=3)
    assert result.timed_out


def test_endless_loop_stops_with_an_error_naming_the_loop(tmp_path):
    proc = ngc2py_run(tmp_path, ENDLESS, "--max-steps", "1000")
    assert proc.returncode == 1
    lines = [l for l in proc.stderr.splitlines() if l != "executing"]
    assert lines[:3] == [runaway_message(1000), "o1 while [1]", "  at prog.ngc:2"]
    # Everything before the loop was printed, then rs274's closing calls.
    assert "STRAIGHT_TRAVERSE(1.0000" in proc.stdout
    assert proc.stdout.endswith("ON_RESET()\n")


def test_the_preview_of_an_endless_loop_returns_an_error(tmp_path, monkeypatch):
    """LinuxCNC's preview (gcode.parse) loads such a file forever, as rs274
    runs it; ``ngc2py.parse`` returns the runaway error, at the loop's line,
    after the calls made before it."""
    import ngc2py
    from ngc2py.preview import INTERP_ERROR
    from test_preview import Recorder

    monkeypatch.setenv("NGC2PY_CACHE", str(tmp_path / "c"))
    (tmp_path / "prog.ngc").write_text(ENDLESS)
    canon = Recorder()
    result = ngc2py.parse(str(tmp_path / "prog.ngc"), canon, max_steps=1000)
    assert result == (INTERP_ERROR, 2)
    assert ngc2py.strerror(result[0]) == runaway_message(1000)
    # the G0's move, then the loop's line announced, as an error's line is
    (move, _), (announced, (line, *_)) = canon.calls[-2:]
    assert (move, announced, line) == ("straight_traverse", "next_line", 2)


@pytest.mark.parametrize(
    "program, lines",
    [
        ("o1 do\no1 while [1]\nM2\n", {1}),
        ("o1 repeat [100000000]\no1 endrepeat\nM2\n", {1}),
        # A loop of calls: the loop or the call spends the last step.
        ("o<s> sub\no<s> endsub\no2 while [1]\no<s> call\no2 endwhile\nM2\n", {3, 4}),
        ("M98 P100 L100000000\nM2\nO100\nM99\n", {1}),
    ],
    ids=["do-while", "repeat", "calls", "m98"],
)
def test_every_kind_of_step_is_counted(program, lines, tmp_path):
    module = compiled(program, tmp_path)
    machine = Machine(NullCanon(), max_steps=500, source=module.__ngc__)
    with pytest.raises(GCodeError) as caught:
        machine.run(module.main)
    assert caught.value.message == runaway_message(500)
    from runtime.errors import locate

    assert locate(caught.value)[-1].line in lines


def test_a_long_but_finite_program_is_not_stopped_by_the_default(tmp_path):
    program = "#1=0\no1 while [#1 LT 20000]\n#1=[#1+1]\no1 endwhile\nM2\n"
    module = compiled(program, tmp_path)
    canon = RecordingCanon()
    Machine(canon, source=module.__ngc__).run(module.main)
    assert ("program_end", ()) in canon.calls
    assert DEFAULT_MAX_STEPS >= 1_000_000


def test_an_endless_loop_stops_in_continue_mode_too(tmp_path):
    # -n 0 goes on after errors; the spent budget still stops the program.
    proc = ngc2py_run(tmp_path, ENDLESS, "-n", "0", "--max-steps", "100")
    assert proc.returncode == 1 and runaway_message(100) in proc.stderr
    assert proc.stdout.endswith("ON_RESET()\n")


def test_zero_means_no_limit():
    machine = Machine(NullCanon(), max_steps=0)
    for _ in range(100_000):
        machine.step()


def test_max_steps_on_the_module_command_line():
    assert parse_options(["--max-steps", "7"])["max_steps"] == 7
    assert parse_options(["--max-steps=0", "-n", "0"]) == {
        "block_delete": False,
        "max_steps": 0,
        "continue_mode": 0,
    }
    with pytest.raises(Exception):
        parse_options(["--max-steps", "lots"])


def test_converted_module_takes_max_steps(tmp_path):
    (tmp_path / "endless.ngc").write_text(ENDLESS)
    env = dict(os.environ, PYTHONPATH=str(REPO))
    subprocess.run(
        [sys.executable, "-m", "ngc2py", "convert", "endless.ngc"],
        cwd=tmp_path,
        env=env,
        check=True,
        timeout=60,
    )
    proc = subprocess.run(
        [sys.executable, "endless.py", "--max-steps", "50"],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert proc.returncode == 1
    assert runaway_message(50) in proc.stderr


# -- 2. -n 0 at the end of an unterminated file ---------------------------------

UNTERMINATED = "G0 X1\nG1 X2\n"


@pytest.mark.rs274
def test_rs274_repeats_the_end_of_file_error_forever_with_n0(tmp_path):
    result = harness.run_rs274(
        tmp_path / "p.ngc", ["-n", "0"], text=UNTERMINATED, timeout=3
    )
    assert result.timed_out
    assert result.stderr.count(b"File ended with no percent sign") > 100


def test_ngc2py_reports_the_end_of_file_once_with_n0(tmp_path):
    proc = ngc2py_run(tmp_path, UNTERMINATED, "-n", "0")
    assert proc.returncode == 1
    assert proc.stderr.count("File ended with no percent sign or program end") == 1
    assert "Cannot do g1 with zero feed rate" in proc.stderr  # reported, went on


# -- 3. -n 0 after an expression error ------------------------------------------

EXPRESSION_ERROR = "G0 X1\nG0 Y[1/0]\nG0 X3\nM2\n"


@pytest.mark.rs274
def test_rs274_goes_on_after_an_expression_error_with_n0(tmp_path):
    result = harness.run_rs274(tmp_path / "p.ngc", ["-n", "0"], text=EXPRESSION_ERROR)
    assert result.rc == 0 and b"STRAIGHT_TRAVERSE(3.0000" in result.stdout


def test_ngc2py_stops_at_an_expression_error_even_with_n0(tmp_path):
    proc = ngc2py_run(tmp_path, EXPRESSION_ERROR, "-n", "0")
    assert proc.returncode == 1
    assert "Attempt to divide by zero" in proc.stderr
    assert "STRAIGHT_TRAVERSE(3.0000" not in proc.stdout


# -- 4. -n 1: no MDI ------------------------------------------------------------


def test_mdi_lines_are_refused_and_a_yes_goes_on(tmp_path):
    proc = ngc2py_run(
        tmp_path, "G1 X2\nG0 X3\nM2\n", "-n", "1", stdin="G0 X9\nquit\ny\n"
    )
    assert proc.returncode == 0
    assert "starting MDI" in proc.stderr
    assert "line ignored: G0 X9" in proc.stderr
    assert "STRAIGHT_TRAVERSE(3.0000" in proc.stdout
    assert "STRAIGHT_TRAVERSE(9.0000" not in proc.stdout


def test_mdi_without_an_answer_stops(tmp_path):
    proc = ngc2py_run(tmp_path, "G1 X2\nG0 X3\nM2\n", "-n", "1")
    assert proc.returncode == 1
    assert proc.stderr.endswith("continue program? y/n =>")
    assert "STRAIGHT_TRAVERSE(3.0000" not in proc.stdout


def test_run_cli_without_stdin_does_not_crash():
    """Under pytest stdin cannot be read: MDI then behaves as at its end."""
    from runtime import continue_mode

    err = io.StringIO()
    assert continue_mode._mdi(sys.stdin, err) is False
    assert err.getvalue() == "starting MDI\ncontinue program? y/n =>"


# -- 5. embedded Python ---------------------------------------------------------

IMPORT = "(py,import os)\nG0 X1\nM2\n"


@pytest.mark.rs274
def test_rs274_runs_embedded_python(tmp_path):
    result = harness.run_rs274(tmp_path / "p.ngc", text=IMPORT)
    assert result.rc == 0 and b"STRAIGHT_TRAVERSE(1.0000" in result.stdout


def test_ngc2py_refuses_python_it_does_not_evaluate(tmp_path):
    proc = ngc2py_run(tmp_path, IMPORT)
    assert proc.returncode == 1
    assert "ngc2py does not run embedded Python" in proc.stderr
    assert "(py,import os)" in proc.stderr


# -- 6. REMAP ------------------------------------------------------------------

REMAP_PROGRAM = "G0 X1\nM400\nG0 X2\nM2\n"
REMAP_SUB = "o<m400> sub\n(PRINT,remap ran)\nG0 X4\no<m400> endsub\nM2\n"


def remap_folder(tmp_path, entry):
    (tmp_path / "r.ini").write_text("[RS274NGC]\nSUBROUTINE_PATH=.\n" + entry + "\n")
    (tmp_path / "m400.ngc").write_text(REMAP_SUB)
    return tmp_path / "p.ngc"


@pytest.mark.rs274
def test_rs274_runs_a_remapped_code(tmp_path):
    program = remap_folder(tmp_path, "REMAP=M400 modalgroup=10 ngc=m400")
    program.write_text(REMAP_PROGRAM)
    result = harness.run_rs274(program, ["-i", "r.ini"])
    assert result.rc == 0 and b"remap ran" in result.stdout


def test_ngc2py_refuses_a_remapped_code_where_it_is_used(tmp_path):
    remap_folder(tmp_path, "REMAP=M400 modalgroup=10 ngc=m400")
    proc = ngc2py_run(tmp_path, REMAP_PROGRAM, "-i", "r.ini")
    assert proc.returncode == 1
    assert "STRAIGHT_TRAVERSE(1.0000" in proc.stdout  # the line before ran
    assert (
        "M400 is remapped by the INI file ([RS274NGC]REMAP); "
        "ngc2py does not run remapped codes"
    ) in proc.stderr


def test_ngc2py_refuses_a_remapped_standard_code_at_the_start(tmp_path):
    remap_folder(tmp_path, "REMAP=m6 modalgroup=6 ngc=m400")
    proc = ngc2py_run(tmp_path, "G0 X1\nM2\n", "-i", "r.ini")
    assert proc.returncode == 1
    assert "STRAIGHT_TRAVERSE" not in proc.stdout
    assert "M6 is remapped by the INI file" in proc.stderr


def test_an_unremapped_unknown_code_keeps_rs274s_message(tmp_path):
    remap_folder(tmp_path, "REMAP=M401 modalgroup=10 ngc=m400")
    proc = ngc2py_run(tmp_path, REMAP_PROGRAM, "-i", "r.ini")
    assert proc.returncode == 1
    assert "M-code greater than 199: M400" in proc.stderr


# -- 7. Python the INI file loads ([PYTHON]TOPLEVEL) ----------------------------

PY_INI = (
    "[RS274NGC]\nSUBROUTINE_PATH = .\n[PYTHON]\nPATH_PREPEND = .\nTOPLEVEL = top.py\n"
)
PY_CALL = "o<twice> call [21]\n(debug, got #<_value>)\nG0 X#<_value>\nM2\n"


def python_folder(tmp_path):
    """An INI file whose Python defines O-word subroutine o<twice> (the
    ``oword`` module rs274's Python plugin looks subroutines up in)."""
    (tmp_path / "p.ini").write_text(PY_INI)
    (tmp_path / "top.py").write_text("import oword\n")
    (tmp_path / "oword.py").write_text(
        "def twice(self, *args):\n    return 2 * args[0]\n"
    )
    return tmp_path / "p.ngc"


@pytest.mark.rs274
def test_rs274_runs_a_subroutine_the_ini_files_python_defines(tmp_path):
    program = python_folder(tmp_path)
    program.write_text(PY_CALL)
    result = harness.run_rs274(program, ["-i", "p.ini"])
    assert result.rc == 0 and b"STRAIGHT_TRAVERSE(42.0000" in result.stdout


def test_ngc2py_refuses_a_call_the_ini_files_python_may_answer(tmp_path):
    python_folder(tmp_path)
    proc = ngc2py_run(tmp_path, PY_CALL, "-i", "p.ini")
    assert proc.returncode == 1
    assert (
        "o<twice> is not a G-code subroutine, and the INI file loads Python "
        "([PYTHON]TOPLEVEL) that may define it; ngc2py does not run embedded Python"
    ) in proc.stderr
    # without that Python, rs274's own message
    (tmp_path / "p.ini").write_text("[RS274NGC]\nSUBROUTINE_PATH = .\n")
    proc = ngc2py_run(tmp_path, PY_CALL, "-i", "p.ini")
    assert "EOF in file:prog.ngc seeking o-word: o<twice>" in proc.stderr


def test_ngc2py_refuses_a_global_the_ini_files_python_may_define(tmp_path):
    python_folder(tmp_path)
    text = "G0 X1\nG0 X#<_from_python>\nM2\n"
    proc = ngc2py_run(tmp_path, text, "-i", "p.ini")
    assert proc.returncode == 1
    assert "STRAIGHT_TRAVERSE(1.0000" in proc.stdout
    assert (
        "Named parameter #<_from_python> not defined in G-code, and the INI file "
        "loads Python"
    ) in proc.stderr
    checked = ";py,from interpreter import *\n;py,assert this.params['_from_python'] == 1\nM2\n"
    proc = ngc2py_run(tmp_path, checked, "-i", "p.ini")
    assert "ngc2py does not run embedded Python beyond simple statements" in proc.stderr
