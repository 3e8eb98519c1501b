"""Progress bars: only on a terminal, never with -q, never in the output."""

from __future__ import annotations

import io
import os
import subprocess
import sys
from pathlib import Path

import pytest

from ngc2py import progress
from runtime.canon import RecordingCanon, TraceCanon

REPO = Path(__file__).resolve().parent.parent


class FakeTerminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_wanted_only_on_a_terminal_and_not_quiet():
    assert progress.wanted(stream=FakeTerminal())
    assert not progress.wanted(quiet=True, stream=FakeTerminal())
    assert not progress.wanted(stream=io.StringIO())


def test_no_bar_means_nothing_to_watch(monkeypatch):
    monkeypatch.setattr(sys, "stderr", io.StringIO())
    watcher = progress.watch_run(RecordingCanon())
    watcher.close()
    assert sys.stderr.getvalue() == ""


def test_bar_on_a_terminal_counts_the_canons_lines(monkeypatch):
    pytest.importorskip("tqdm")
    terminal = FakeTerminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    canon = TraceCanon(io.StringIO())
    watcher = progress.watch_run(canon)
    for k in range(5000):
        canon.straight_feed(k, 0, 0, 0, 0, 0, 0, 0, 0)
    watcher.close()
    assert watcher._shown == 5000
    assert "line" in terminal.getvalue()  # the bar was drawn on "stderr"


def test_a_run_on_a_terminal_takes_the_fast_paths(tmp_path):
    """The bar watches the canon, never wraps it: a run on a terminal makes
    the trace a pipe gets (a wrapper once lacked the batch methods the arc
    rows ask the canon's class for, and failed)."""
    lines = ["G21 G17 F300", "G0 X0 Y0"]
    for k in range(80):  # a CAM-sized table of arcs
        lines.append("G%d X%d Y0 R%d.5" % (2 + k % 2, (k + 1) % 2 * 2, 1 + k % 3))
    (tmp_path / "a.ngc").write_text("\n".join(lines + ["M2", ""]))
    env = dict(os.environ, PYTHONPATH=str(REPO), HOME=str(tmp_path))
    piped = subprocess.run(
        [sys.executable, "-m", "ngc2py", "run", "a.ngc"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        env=env,
    )
    assert piped.returncode == 0 and "ARC_FEED" in piped.stdout
    script = (
        "import sys, pty, os;"
        "os.environ['TERM']='dumb';"
        "sys.exit(os.waitstatus_to_exitcode(pty.spawn([sys.executable, '-c',"
        ' \'import sys, runpy; sys.stdout = open("out.txt", "w");'
        ' sys.argv = ["ngc2py", "run", "a.ngc"];'
        ' runpy.run_module("ngc2py", run_name="__main__")\'])))'
    )
    tty = subprocess.run(
        [sys.executable, "-c", script],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        env=env,
    )
    assert tty.returncode == 0, tty.stdout
    assert (tmp_path / "out.txt").read_text() == piped.stdout


def test_piped_run_has_no_bar(tmp_path):
    (tmp_path / "p.ngc").write_text(
        "o1 repeat [3000]\nG1 X1 F10\nG1 X0\no1 endrepeat\nM2\n"
    )
    done = subprocess.run(
        [sys.executable, "-m", "ngc2py", "run", "p.ngc"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        env=dict(os.environ, PYTHONPATH=str(REPO)),
    )
    assert done.returncode == 0
    assert done.stderr == "executing\n"


def test_spinner_is_silent_when_piped(monkeypatch):
    err = io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    with progress.spinner("converting x"):
        pass
    assert err.getvalue() == ""
