"""ngc2py against the recorded rs274 behaviour of every golden program.

One test per program in golden/<feature>/<name>.ngc and per way of running it:

* ``inprocess`` -- ``ngc2py run PROG [args]`` through ``ngc2py.cli.main`` in
  this process (the same code path as the console script, without paying
  for a new interpreter per program; tests/test_cli.py runs the real
  subprocess)
* ``convert``   -- ``ngc2py convert PROG -o prog.py`` then ``python prog.py
  [args]`` (the generated module on its own), both run in this process
  (tests/rs274.py)

and, for every SAMPLE-th program (a tenth of the corpus, spread over every
folder), one of the two in a new interpreter, as a user starts it, in turn:
``run`` (``python -m ngc2py run``) or ``convert-process`` (``python
prog.py``). They hold the in-process runners to what the processes print,
byte for byte.

Pass = stdout byte-identical to ``<name>.out``, the same exit status as
``<name>.rc`` and the same error message as ``<name>.err``. These tests use
only the recordings, so they run without rs274 installed. Programs with a
``<name>.expect`` (rs274 crashes or hangs on them) are checked against the
better behaviour it describes. Set NGC2PY_GOLDEN_MODES=inprocess (or convert) to
run every program one way only (``run`` and ``convert-process`` are also
accepted); NGC2PY_TEST_PROCESSES=1 runs them all in new processes.
"""

from __future__ import annotations

import os
import time

import pytest

import rs274 as harness

MODES = [m for m in os.environ.get("NGC2PY_GOLDEN_MODES", "inprocess,convert").split(",") if m]
PROGRAMS = harness.golden_programs()
#: One program in SAMPLE also runs in a new process (PROCESS_MODES in turn).
SAMPLE = 10
PROCESS_MODES = [m for m in ("run", "convert-process") if m not in MODES]


def _id(path):
    return str(path.relative_to(harness.GOLDEN).with_suffix(""))


def test_corpus_is_recorded():
    """The corpus is there and every recording is complete."""
    assert len(PROGRAMS) >= 150, f"only {len(PROGRAMS)} golden programs"
    for p in PROGRAMS:
        if p.with_suffix(".expect").exists():
            continue
        for ext in (".out", ".err", ".rc"):
            assert p.with_suffix(ext).exists(), f"{_id(p)}: missing {ext} (run golden/record.py)"


def _cases():
    for index, program in enumerate(PROGRAMS):
        extra = []
        if index % SAMPLE == 0 and PROCESS_MODES:
            extra = [PROCESS_MODES[index // SAMPLE % len(PROCESS_MODES)]]
        for mode in MODES + extra:
            yield pytest.param(program, mode, id="%s-%s" % (_id(program), mode))


@pytest.mark.parametrize("program, mode", list(_cases()))
def test_golden(program, mode):
    args = harness.read_args(program)
    if program.with_suffix(".expect").exists():
        _check_expect(program, args, mode)
        return
    expected = harness.load_expected(program)
    actual = harness.run_ngc2py(program, args, mode=mode)
    problems = harness.compare(expected, actual)
    if problems:
        pytest.fail(f"{_id(program)} ({mode}):\n" + "\n".join(problems), pytrace=False)


def _check_expect(program, args, mode):
    spec = harness.load_expect(program)
    limit = float(spec.get("max_seconds", harness.DEFAULT_TIMEOUT))
    start = time.monotonic()
    actual = harness.run_ngc2py(program, args, mode=mode, timeout=limit)
    elapsed = time.monotonic() - start
    where = f"{_id(program)} ({mode}), expected behaviour from .expect"
    assert not actual.timed_out, f"{where}: did not finish within {limit}s"
    assert elapsed <= limit, f"{where}: took {elapsed:.1f}s > {limit}s"
    if "rc" in spec:
        assert actual.rc == int(spec["rc"]), f"{where}: rc {actual.rc}\n{actual.describe()}"
    if "err" in spec:
        assert actual.err == spec["err"], f"{where}: {actual.describe()}"
    if "err_contains" in spec:
        assert spec["err_contains"] in actual.err, f"{where}: {actual.describe()}"
    if "stdout_prefix" in spec:
        prefix = (program.parent / spec["stdout_prefix"]).read_bytes()
        assert actual.stdout.startswith(prefix), (
            f"{where}: stdout does not start with {spec['stdout_prefix']}\n"
            + harness.stdout_diff(prefix, actual.stdout[: len(prefix)])
        )
