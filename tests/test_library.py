"""Library use: ``module.run(canon)`` writes nothing to stdout or stderr on
its own; everything the program says reaches the canon object.

(rs274's ``executing`` banner, the tool table's and ini file's complaints
and the parameter file's perror lines belong to the command line, which
prints them; tests/test_golden.py checks it still does, byte for byte.)
"""

from __future__ import annotations

import importlib.util

from runtime.canon import RecordingCanon

from ngc2py.compiler import compile_file
from ngc2py import cli

PROGRAM = """\
#1 = 2.5
(MSG, a message)
(DEBUG, debug #1)
(PRINT, printed #1)
(a plain comment)
G0 X#1
M2
"""


def load(tmp_path, text=PROGRAM):
    source = tmp_path / "prog.ngc"
    source.write_text(text)
    module_path = tmp_path / "prog.py"
    module_path.write_text(compile_file(str(source)))
    spec = importlib.util.spec_from_file_location("prog_module", str(module_path))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_run_writes_nothing_and_the_canon_hears_everything(tmp_path, capfd):
    module = load(tmp_path)
    canon = RecordingCanon()
    module.run(canon)
    assert capfd.readouterr() == ("", "")
    calls = canon.calls
    assert ("message", (" a message",)) in calls
    assert ("message", (" debug 2.500000",)) in calls
    assert ("print_text", (" printed 2.500000",)) in calls
    assert ("comment", ("a plain comment",)) in calls


def test_parameter_file_complaints_are_not_printed_by_the_library(tmp_path, capfd):
    module = load(tmp_path)
    var = tmp_path / "prog.var"
    var.write_text("5220\t1.000000\n")
    (tmp_path / "prog.var.bak").mkdir()  # the backup link cannot be made
    module.run(RecordingCanon(), var_file=str(var))
    assert capfd.readouterr() == ("", "")


def test_the_command_line_still_prints_them(tmp_path, capfd):
    source = tmp_path / "prog.ngc"
    source.write_text(PROGRAM)
    var = tmp_path / "prog.var"
    var.write_text("5220\t1.000000\n")
    (tmp_path / "prog.var.bak").mkdir()
    assert cli.main(["run", str(source), "-v", str(var)]) == 0
    out, err = capfd.readouterr()
    assert " printed 2.500000\n" in out  # PRINT in the trace, as rs274 has it
    assert err.startswith("executing\n")
    assert "link (updating variable file): " in err
