"""Canned cycles where rs274 has no usable answer.

Everything else about cycles is pinned by golden/cycles (recorded from rs274)
and the differential tests. Here: a G73/G83 peck so small that subtracting it
no longer changes the depth makes rs274 peck at one depth forever, printing
without end -- too much output to record as a golden ``.expect``. ngc2py
must stop with a clear error after the first peck instead.
"""

from __future__ import annotations

import os
import subprocess
import tempfile
import time

import pytest

import rs274 as harness

#: Z starts at 1; Q is 1e-19, so 1 - Q == 1 in a double.
PROGRAM = "G21 F100\nG0 Z5\nG{code} X1 Z-1 R1 Q[1/10000000000000000000]\nM2\n"


@pytest.mark.parametrize("code", ["73", "83"])
def test_tiny_peck_is_an_error_not_a_hang(code, tmp_path):
    program = tmp_path / "tiny_peck.ngc"
    program.write_text(PROGRAM.format(code=code))
    result = harness.run_ngc2py(program, mode="inprocess", timeout=60)
    assert result.rc == 1
    assert result.err == f"Q value too small with g{code}: the pecks never reach the bottom"
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
