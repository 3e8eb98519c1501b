"""Golden tests for users' own programs: ``ngc2py golden`` and the pytest plugin.

Recordings here are made by ngc2py itself on purpose: that is the workflow
being tested (a user guards *their* programs against change). The project's
own corpus is recorded from rs274 (golden/record.py) and the same code
compares it (tests/test_golden.py, through tests/rs274.py).
"""

from __future__ import annotations

import io
import os
import shutil
import subprocess
import sys
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pytest

from ngc2py import cli, golden

REPO = Path(__file__).resolve().parent.parent
pytest_plugins = ["pytester"]

GOOD = "G21\nG0 X1 Y2\nG1 X3 F100\nM2\n"
BAD = "G21\nG0 X1\nG1 X[1/0] F100\nM2\n"
SUB = "o<helper> sub\nG0 X#1\no<helper> endsub\nM2\n"


def ngc2py(cwd, *args):
    out, err = io.StringIO(), io.StringIO()
    here = os.getcwd()
    os.chdir(cwd)
    try:
        with redirect_stdout(out), redirect_stderr(err):
            rc = cli.main(list(args))
    finally:
        os.chdir(here)
    return rc, out.getvalue(), err.getvalue()


@pytest.fixture
def folder(tmp_path):
    (tmp_path / "good.ngc").write_text(GOOD)
    (tmp_path / "bad.ngc").write_text(BAD)
    (tmp_path / "helper.ngc").write_text(SUB)
    return tmp_path


def test_record_writes_the_documented_files(folder):
    rc, out, err = ngc2py(folder, "golden", "record", ".")
    assert rc == 0, err
    assert (folder / "good.out").read_bytes().startswith(b"    1 N..... USE_LENGTH_UNITS")
    assert (folder / "good.err").read_text() == ""
    assert (folder / "good.rc").read_text() == "0\n"
    # a program that ends in an error: its message and exit status
    assert (folder / "bad.err").read_text() == "Attempt to divide by zero\n"
    assert (folder / "bad.rc").read_text() == "1\n"
    # an external subroutine file is not a program of its own
    assert not (folder / "helper.rc").exists()
    assert "recorded 2 of 2 programs" in out


def test_record_is_deterministic(folder):
    ngc2py(folder, "golden", "record", ".")
    first = {p.name: p.read_bytes() for p in folder.iterdir() if p.suffix != ".ngc"}
    ngc2py(folder, "golden", "record", ".")
    assert first == {p.name: p.read_bytes() for p in folder.iterdir() if p.suffix != ".ngc"}


def test_check_passes_then_fails_with_a_diff_on_an_edit(folder):
    ngc2py(folder, "golden", "record", ".")
    assert ngc2py(folder, "golden", "check", ".")[0] == golden.EXIT_OK
    (folder / "good.ngc").write_text(GOOD.replace("F100", "F250"))
    rc, out, err = ngc2py(folder, "golden", "check", ".")
    assert rc == golden.EXIT_CHANGED
    assert "CHANGED good.ngc" in out or "CHANGED ./good.ngc" in out
    assert "-    9 N..... SET_FEED_RATE(100.0000)" in out
    assert "+    9 N..... SET_FEED_RATE(250.0000)" in out
    assert "1 unchanged, 1 changed" in out


def test_check_notices_a_changed_error(folder):
    ngc2py(folder, "golden", "record", "bad.ngc")
    (folder / "bad.ngc").write_text(BAD.replace("1/0", "1/0.5"))
    rc, out, _ = ngc2py(folder, "golden", "check", "bad.ngc")
    assert rc == golden.EXIT_CHANGED
    assert "exit status: recorded 1, now 0" in out
    assert "'Attempt to divide by zero'" in out


def test_nothing_to_check_and_unrecorded_programs(folder):
    rc, _, err = ngc2py(folder, "golden", "check", ".")
    assert rc == golden.EXIT_USAGE and "no programs found" in err
    rc, _, err = ngc2py(folder, "golden", "check", "good.ngc")
    assert rc == golden.EXIT_USAGE and "not recorded" in err


def test_options_are_recorded_and_used(folder):
    (folder / "tools.tbl").write_text("T1 P1 Z10 D4 ;one\n")
    (folder / "tool.ngc").write_text("T1 M6\nG43\nG0 Z0\nM2\n")
    rc, _, err = ngc2py(folder, "golden", "record", "tool.ngc", "-t", "tools.tbl")
    assert rc == 0, err
    assert golden.read_args(folder / "tool.ngc") == ["-t", "tools.tbl"]
    assert b"254.0000" in (folder / "tool.out").read_bytes()  # the table is in inches
    assert ngc2py(folder, "golden", "check", "tool.ngc")[0] == 0


def test_runs_leave_the_users_files_alone(folder):
    (folder / "p.var").write_text("5161\t1.000000\n")
    (folder / "v.ngc").write_text("#5161 = 42\nM2\n")
    before = (folder / "p.var").read_bytes()
    assert ngc2py(folder, "golden", "record", "v.ngc", "-v", "p.var")[0] == 0
    assert (folder / "p.var").read_bytes() == before
    assert not list(folder.glob("*.bak"))


def test_rs274_recordings_are_never_overwritten(tmp_path):
    (tmp_path / golden.REFERENCE_MARK).write_text("")
    (tmp_path / "f").mkdir()
    (tmp_path / "f" / "p.ngc").write_text(GOOD)
    rc, _, err = ngc2py(tmp_path, "golden", "record", "f")
    assert rc != 0 and "rs274" in err
    assert not (tmp_path / "f" / "p.out").exists()


def test_project_corpus_is_marked_as_rs274s():
    assert golden.reference_folder(REPO / "golden" / "arcs" / "arc_inches.ngc") is not None


def test_help_documents_file_names_and_exit_status():
    rc, out, _ = ngc2py(REPO, "golden", "--help")
    assert rc == 0
    for text in ("PROG.out", "PROG.err", "PROG.rc", "PROG.args", "Exit status"):
        assert text in out


# --- the pytest plugin -------------------------------------------------------


def _plugin_args():
    """``-p ngc2py.pytest_plugin`` unless an installed ngc2py already loads
    it through its pytest11 entry point (pytest refuses it twice)."""
    from importlib.metadata import entry_points

    found = entry_points()
    group = found.select(group="pytest11") if hasattr(found, "select") else found.get("pytest11", [])
    if any(e.value == "ngc2py.pytest_plugin" for e in group):
        return []
    return ["-p", "ngc2py.pytest_plugin"]


def _user_folder(pytester):
    folder = pytester.path
    (folder / "good.ngc").write_text(GOOD)
    (folder / "bad.ngc").write_text(BAD)
    (folder / "helper.ngc").write_text(SUB)
    return folder


def test_pytest_collects_and_passes_recorded_programs(pytester):
    folder = _user_folder(pytester)
    ngc2py(folder, "golden", "record", ".")
    (folder / "new.ngc").write_text(GOOD)  # not recorded: not a test
    result = pytester.runpytest_subprocess(*_plugin_args(), "-v")
    result.assert_outcomes(passed=2)
    result.stdout.fnmatch_lines(["*bad.ngc::bad.ngc PASSED*", "*good.ngc::good.ngc PASSED*"])


def test_pytest_fails_a_changed_program_with_a_diff(pytester):
    folder = _user_folder(pytester)
    ngc2py(folder, "golden", "record", ".")
    (folder / "good.ngc").write_text(GOOD.replace("X3", "X4"))
    result = pytester.runpytest_subprocess(*_plugin_args())
    result.assert_outcomes(passed=1, failed=1)
    result.stdout.fnmatch_lines(
        ["*good.ngc changed against its recording*", "-*STRAIGHT_FEED(3.0000*", "+*STRAIGHT_FEED(4.0000*"]
    )


def test_pytest_ngc_record_records_then_checks(pytester):
    folder = _user_folder(pytester)
    result = pytester.runpytest_subprocess(*_plugin_args(), "--ngc-record")
    result.assert_outcomes(passed=2)  # the subroutine file is not a program
    assert (folder / "good.rc").exists() and not (folder / "helper.rc").exists()
    pytester.runpytest_subprocess(*_plugin_args()).assert_outcomes(passed=2)


def test_pytest_plugin_runs_in_parallel(pytester):
    folder = _user_folder(pytester)
    for k in range(6):
        (folder / f"p{k}.ngc").write_text(GOOD.replace("X3", f"X{k}"))
    ngc2py(folder, "golden", "record", ".")
    result = pytester.runpytest_subprocess(*_plugin_args(), "-n", "2")
    result.assert_outcomes(passed=8)


def test_plugin_is_registered_as_a_pytest11_entry_point():
    text = (REPO / "pyproject.toml").read_text()
    assert '[project.entry-points.pytest11]\nngc2py = "ngc2py.pytest_plugin"' in text


def test_plugin_passes_the_projects_rs274_recordings(pytester):
    """The corpus recorded from rs274, checked by the plugin (a sample folder)."""
    shutil.copytree(REPO / "golden" / "arcs", pytester.path / "arcs")
    recorded = len(list((pytester.path / "arcs").glob("*.rc")))
    result = pytester.runpytest_subprocess(*_plugin_args(), "arcs")
    result.assert_outcomes(passed=recorded)


def test_console_script_golden_check_exit_status(folder):
    env = dict(os.environ, PYTHONPATH=str(REPO))
    subprocess.run([sys.executable, "-m", "ngc2py", "golden", "record", "."], cwd=folder, env=env, check=True, capture_output=True)
    (folder / "good.ngc").write_text(GOOD.replace("Y2", "Y5"))
    done = subprocess.run(
        [sys.executable, "-m", "ngc2py", "golden", "check", "-q", "."], cwd=folder, env=env, capture_output=True, text=True
    )
    assert done.returncode == 1
    assert "CHANGED" in done.stdout and "ok " not in done.stdout
