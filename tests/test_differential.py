"""Differential tests: generated programs run through rs274 and ngc2py.

Hypothesis writes programs (tests/strategies.py); each is run by the live
rs274 and by ngc2py in the same way (scratch folder, private HOME), and the
two must agree: byte-identical stdout, same exit status, same error message.
All tests here need rs274 and are skipped (with the reason, counted in the
session summary) without it.

Profiles (NGC2PY_HYPOTHESIS_PROFILE): ``ci`` (default) is derandomised --
the same examples on every run -- and does not shrink, so a failing run is
quick and reproducible; ``dev`` draws new examples each run, more of them,
and shrinks failures to a minimal program. NGC2PY_DIFF_EXAMPLES overrides the
number of examples per test.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, Phase, example, given, reject, settings

import rs274 as harness
import strategies

EXAMPLES = os.environ.get("NGC2PY_DIFF_EXAMPLES")

settings.register_profile(
    "ci",
    derandomize=True,
    database=None,
    deadline=None,
    max_examples=int(EXAMPLES or 40),
    phases=[Phase.explicit, Phase.generate],
    suppress_health_check=list(HealthCheck),
    print_blob=False,
)
settings.register_profile(
    "dev",
    deadline=None,
    max_examples=int(EXAMPLES or 200),
    suppress_health_check=list(HealthCheck),
)
PROFILE = settings.get_profile(os.environ.get("NGC2PY_HYPOTHESIS_PROFILE", "ci"))

#: rs274 on a generated program: if it hangs, the example is discarded
TIMEOUT = 20.0
#: a recorded program rs274 hangs on: the small programs of golden/ that
#: rs274 finishes take well under a second, so this long means it still hangs
HANG_TIMEOUT = 5.0

pytestmark = pytest.mark.rs274

# a folder name for the scratch copy; nothing is read from it
_PROGRAM = harness.REPO / "tests" / "_generated" / "prog.ngc"


def check_same(
    text: str,
    mode: str = "run",
    args=(),
    program=_PROGRAM,
    timeout: float = TIMEOUT,
    slack: float = 3,
) -> None:
    """rs274 and ngc2py (``mode``, with rs274's options ``args``) on ``text``
    must agree; an example rs274 hangs or crashes on is discarded (no
    reference behaviour to compare with). ngc2py gets ``slack`` times
    rs274's time limit."""
    expected = harness.run_rs274(program, args, text=text, timeout=timeout)
    if expected.timed_out or (expected.rc is not None and expected.rc < 0):
        reject()
    actual = harness.run_ngc2py(
        program, args, text=text, mode=mode, timeout=timeout * slack
    )
    problems = harness.compare(expected, actual)
    if problems:
        numbered = "\n".join(
            f"{i:4d}  {ln}" for i, ln in enumerate(text.splitlines(), 1)
        )
        options = f", options {list(args)}" if args else ""
        pytest.fail(
            f"ngc2py ({mode}{options}) differs from rs274 on this program:\n{numbered}\n\n"
            + "\n".join(problems),
            pytrace=False,
        )


@settings(PROFILE, max_examples=PROFILE.max_examples * 2)
@given(strategies.valid_programs())
def test_valid_programs_run(text):
    """`ngc2py run`, called in-process (tests/rs274.py) so more examples fit."""
    check_same(text, "inprocess")


@PROFILE
@given(strategies.valid_programs(feed_modes=True))
def test_valid_programs_with_feed_modes_run(text):
    """Inverse time, feed per revolution and the UVW planes as well."""
    check_same(text, "inprocess")


@PROFILE
@given(strategies.valid_programs(max_statements=6))
def test_valid_programs_converted(text):
    """The generated module on its own, not only `ngc2py run`."""
    check_same(text, "convert")


@PROFILE
@given(strategies.cycle_programs())
def test_cycle_programs_run(text):
    """Canned cycles in bulk: every plane, sticky values, repeats, series."""
    check_same(text, "inprocess")


@PROFILE
@given(strategies.cycle_programs(failing=True))
@example(
    # found by hypothesis: the failed lines' Q and P were kept for the next
    text="G21 G90 F50\nG91 G83 Z-0.1 R0 Q0.2\nG90\nG91 G83 Z-0.1 R0 Q0\nX0\n"
    "S100 M3\nG82 Z-1 R1 P2\nM4\nG84 Z-1 R1 P3\nX1\nM2\n"
)
def test_failing_cycles_go_on_as_rs274(text):
    """Cycles that fail after their first moves, under -n 0: rs274 keeps its
    current point where the failed line began (it sets it after the last
    hole), though its canon made the moves before the error, and keeps the
    sticky words (P, Q, R, depth, motion) of the last cycle that ended."""
    check_same(text, "inprocess", ["-n", "0"])


@settings(PROFILE, max_examples=PROFILE.max_examples * 2)
@given(strategies.invalid_programs())
def test_invalid_programs_run(text):
    check_same(text, "inprocess")


@settings(PROFILE, max_examples=max(10, PROFILE.max_examples // 2))
@given(strategies.invalid_programs(max_statements=6))
def test_invalid_programs_converted(text):
    check_same(text, "convert")


@pytest.mark.parametrize(
    "program",
    harness.golden_programs(),
    ids=lambda p: str(p.relative_to(harness.GOLDEN).with_suffix("")),
)
def test_golden_recording_is_current(program):
    """The recordings still match the installed rs274 (re-record with
    golden/record.py if LinuxCNC was upgraded on purpose)."""
    if program.with_suffix(".expect").exists():
        actual = harness.run_rs274(program, harness.read_args(program), timeout=HANG_TIMEOUT)
        assert actual.timed_out or actual.rc < 0, (
            f"rs274 no longer crashes or hangs on {program.name}: remove its .expect and record it\n"
            + actual.describe()
        )
        return
    expected = harness.load_expected(program)
    actual = harness.run_rs274(program, harness.read_args(program), timeout=TIMEOUT)
    problems = harness.compare(expected, actual)
    if problems:
        pytest.fail(
            "installed rs274 disagrees with the recording:\n" + "\n".join(problems),
            pytrace=False,
        )


@pytest.mark.parametrize(
    "program", sorted((harness.REPO / "examples").glob("*.ngc")), ids=lambda p: p.name
)
def test_bundled_example(program):
    """The README's example programs behave exactly as in rs274."""
    args = harness.read_args(program)
    expected = harness.run_rs274(program, args, timeout=TIMEOUT)
    assert expected.rc == 0, (
        "the bundled example must run cleanly in rs274:\n" + expected.describe()
    )
    for mode in ("run", "convert"):
        actual = harness.run_ngc2py(program, args, mode=mode, timeout=TIMEOUT * 3)
        problems = harness.compare(expected, actual)
        if problems:
            pytest.fail(
                f"{program.name} ({mode}):\n" + "\n".join(problems), pytrace=False
            )


@settings(PROFILE, max_examples=PROFILE.max_examples * 2)
@given(strategies.valid_programs())
def test_generator_writes_valid_programs(text):
    """Checks the generator, not ngc2py: rs274 runs every 'valid' program to
    its end, so the differential tests above really exercise the success path."""
    result = harness.run_rs274(_PROGRAM, text=text, timeout=TIMEOUT)
    if result.timed_out:
        reject()
    assert (
        result.rc == 0
    ), f"rs274 rejects a generated valid program:\n{text}\n{result.describe()}"


@settings(PROFILE, max_examples=PROFILE.max_examples * 2)
@given(strategies.compensated_programs())
def test_compensated_profiles_run(text):
    check_same(text, "inprocess")


#: Programs drawn with a tool table run in its folder (never written there).
_COMP_PROGRAM = harness.GOLDEN / "cutter_comp" / "_generated.ngc"


@PROFILE
@given(strategies.compensated_programs(tool_table=True))
def test_compensated_profiles_with_tool_table_run(text):
    # The runners copy a program's folder only for a program file, not for
    # program text: write both into a folder of their own.
    with tempfile.TemporaryDirectory() as tmp:
        program = Path(tmp) / _COMP_PROGRAM.name
        program.write_text(text)
        shutil.copy(_COMP_PROGRAM.parent / "tools.tbl", tmp)
        expected = harness.run_rs274(program, ["-t", "tools.tbl"], timeout=TIMEOUT)
        if expected.timed_out or (expected.rc is not None and expected.rc < 0):
            reject()
        actual = harness.run_ngc2py(
            program, ["-t", "tools.tbl"], mode="inprocess", timeout=TIMEOUT * 3
        )
    problems = harness.compare(expected, actual)
    if problems:
        pytest.fail(
            f"ngc2py differs from rs274 on this program:\n{text}\n"
            + "\n".join(problems),
            pytrace=False,
        )
