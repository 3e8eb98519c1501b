"""Differential tests on whole-language programs (tests/strategies.py,
``whole_language_programs``): canned cycles in every plane, compensated
pockets, lathe cycles, tool changes from a drawn tool table, probing,
splines, modal state saved in subroutines, I/O M codes, and deliberately
wrong lines. Each program runs with its own tool table (``-t tools.tbl``)
in rs274 and in ngc2py; both must agree byte for byte, in exit status and
in the error message. The profiles are those of tests/test_differential.py.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import pytest
from hypothesis import given, reject, settings

import rs274 as harness
import strategies
from test_differential import PROFILE, TIMEOUT

pytestmark = pytest.mark.rs274


def check_same(program: tuple, mode: str) -> None:
    text, table = program
    with tempfile.TemporaryDirectory() as tmp:
        # the runners copy this folder (program and tool table) to scratch
        path = Path(tmp) / "job.ngc"
        path.write_text(text)
        (Path(tmp) / "tools.tbl").write_text(table)
        args = ["-t", "tools.tbl"]
        expected = harness.run_rs274(path, args, timeout=TIMEOUT)
        if expected.timed_out or (expected.rc is not None and expected.rc < 0):
            reject()  # rs274 hung or crashed: no reference behaviour
        actual = harness.run_ngc2py(path, args, mode=mode, timeout=TIMEOUT * 3)
    problems = harness.compare(expected, actual)
    if problems:
        numbered = "\n".join(f"{i:4d}  {ln}" for i, ln in enumerate(text.splitlines(), 1))
        pytest.fail(
            f"ngc2py ({mode}) differs from rs274 on this program:\n{numbered}\n\n"
            f"tools.tbl:\n{table}\n" + "\n".join(problems),
            pytrace=False,
        )


@PROFILE
@given(strategies.whole_language_programs())
def test_whole_language_programs_run(program):
    check_same(program, "inprocess")


@settings(PROFILE, max_examples=max(5, PROFILE.max_examples // 4))
@given(strategies.whole_language_programs(errors=False, max_jobs=3))
def test_whole_language_programs_converted(program):
    """The generated module on its own."""
    check_same(program, "convert")


@settings(PROFILE, max_examples=max(10, PROFILE.max_examples // 2))
@given(strategies.whole_language_programs(errors=False))
def test_whole_language_generator_writes_valid_programs(program):
    """Checks the generator: without ``errors`` most jobs run to the end in
    rs274 (a few rules depend on values drawn together, e.g. a tool change
    right after a tapping cycle; those may still fail, and are counted)."""
    text, table = program
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "job.ngc"
        path.write_text(text)
        (Path(tmp) / "tools.tbl").write_text(table)
        result = harness.run_rs274(path, ["-t", "tools.tbl"], timeout=TIMEOUT)
    if result.timed_out:
        reject()
    assert result.rc == 0, f"rs274 rejects a generated valid program:\n{text}\n{table}\n{result.describe()}"


@settings(PROFILE, max_examples=max(10, PROFILE.max_examples // 2))
@given(strategies.broken_whole_language_programs())
def test_broken_whole_language_programs_run(program):
    """One line broken: errors inside cycles, compensation, lathe profiles."""
    check_same(program, "inprocess")
