"""Progress bars: only on a terminal, never with -q, never in the output."""

from __future__ import annotations

import io
import os
import subprocess
import sys
from pathlib import Path

import pytest

from ngc2py import progress
from runtime.canon import RecordingCanon

REPO = Path(__file__).resolve().parent.parent


class FakeTerminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_wanted_only_on_a_terminal_and_not_quiet():
    assert progress.wanted(stream=FakeTerminal())
    assert not progress.wanted(quiet=True, stream=FakeTerminal())
    assert not progress.wanted(stream=io.StringIO())


def test_no_bar_means_the_canon_itself(monkeypatch):
    monkeypatch.setattr(sys, "stderr", io.StringIO())
    canon = RecordingCanon()
    assert progress.progress_canon(canon) is canon


def test_bar_on_a_terminal_forwards_every_call(monkeypatch):
    pytest.importorskip("tqdm")
    terminal = FakeTerminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    inner = RecordingCanon()
    canon = progress.progress_canon(inner)
    assert isinstance(canon, progress.ProgressCanon)
    for k in range(progress.MOVE_STRIDE + 1):
        canon.set_block_number(str(k))
        canon.straight_feed(k, 0, 0, 0, 0, 0, 0, 0, 0)
    canon.comment("done")
    canon.close()
    assert len(inner.calls) == progress.MOVE_STRIDE + 2
    assert inner.numbers[-1] == str(progress.MOVE_STRIDE)
    assert "move" in terminal.getvalue()  # the bar was drawn on "stderr"


def test_piped_run_has_no_bar(tmp_path):
    (tmp_path / "p.ngc").write_text("o1 repeat [3000]\nG1 X1 F10\nG1 X0\no1 endrepeat\nM2\n")
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
