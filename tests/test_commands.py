"""Every command has --help, documents its exit status, and takes '-'."""

from __future__ import annotations

import io
import os
import subprocess
import sys
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pytest

from ngc2py import cli

REPO = Path(__file__).resolve().parent.parent
COMMANDS = ["convert", "run", "golden", "flatten"]


def main(*args):
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        rc = cli.main(list(args))
    return rc, out.getvalue(), err.getvalue()


@pytest.mark.parametrize("command", COMMANDS)
def test_every_command_has_help(command):
    rc, out, _ = main(command, "--help")
    assert rc == 0 and out.startswith("usage: ngc2py " + command)


def test_top_level_help_lists_commands_and_exit_status():
    rc, out, _ = main("--help")
    assert rc == 0
    for command in COMMANDS:
        assert command in out
    assert "exit status" in out


def test_readme_documents_exit_status_and_each_workflow():
    readme = (REPO / "README.md").read_text()
    for heading in ("## Exit status", "## Golden tests", "## Flatten", "## Errors"):
        assert heading in readme


def _run(args, cwd, stdin=None):
    return subprocess.run(
        [sys.executable, "-m", "ngc2py", *args],
        cwd=cwd,
        input=stdin,
        capture_output=True,
        text=True,
        env=dict(os.environ, PYTHONPATH=str(REPO)),
    )


def test_run_and_convert_read_stdin(tmp_path):
    program = "G21\nG0 X1 Y[2*3]\nM2\n"
    (tmp_path / "p.ngc").write_text(program)
    from_file = _run(["run", "p.ngc"], tmp_path)
    from_stdin = _run(["run", "-"], tmp_path, program)
    assert from_stdin.returncode == 0 and from_stdin.stdout == from_file.stdout
    module = _run(["convert", "-"], tmp_path, program)
    assert module.returncode == 0 and "def main(m" in module.stdout


def test_stdin_errors_name_stdin(tmp_path):
    done = _run(["run", "-"], tmp_path, "G0 X1\nG1 X[1/0]\nM2\n")
    assert done.returncode == 1
    assert done.stderr.splitlines()[1] == "Attempt to divide by zero"
    assert "<stdin>:2" in done.stderr


def test_internal_error_traceback_shows_gcode_frames(tmp_path):
    from runtime.errors import format_traceback
    from ngc2py.compiler import compile_text

    namespace = {"__name__": "generated"}
    exec(compile(compile_text("o<s> sub\nG0 X1\no<s> endsub\no<s> call\nM2\n", "t.ngc"), "t.py", "exec"), namespace)

    from runtime.canon import Canon

    class Broken(Canon):
        def straight_traverse(self, *args):
            raise ZeroDivisionError("canon broke")

    from runtime.machine import Machine

    machine = Machine(Broken())
    try:
        machine.run(namespace["main"])
    except ZeroDivisionError as error:
        text = format_traceback(error)
    else:
        pytest.fail("the broken canon did not raise")
    assert 'File "t.ngc", line 2 (G-code)' in text and "G0 X1" in text
    assert 'File "t.ngc", line 4 (G-code)' in text and "o<s> call" in text
    assert text.rstrip().endswith("ZeroDivisionError: canon broke")
