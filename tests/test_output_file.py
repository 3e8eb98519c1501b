"""rs274's output file: ``rs274 -g PROG OUT`` writes the trace to OUT.

rs274 takes ``[input file [output file]]``: with the second name its canon
writes the trace there, while what it prints itself (the tool table's
complaints, PRINT text) stays on stdout and its messages on stderr; a file
it cannot open is "could not open output file OUT" and exit status 1,
before the ini and parameter files are read. ``ngc2py run PROG OUT`` and a
module's ``python prog.py OUT`` do the same, and write the file atomically
(a temporary file beside it takes its name when the run ends, with the
trace up to an error as rs274's file holds it).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings

import rs274 as harness
import strategies

pytestmark = pytest.mark.rs274

#: A tool table with a line rs274 skips (its complaint goes to stdout).
TOOLS = "T1 P1 D0.5 Z1 ;ok\nT2 P2 Q9 bogus\n"

PROGRAMS = {
    "print": "G0 X1\n(PRINT,hello #<_x>)\n(DEBUG,dbg)\nG1 X2 F10\nM2\n",
    "error": "G0 X1\n(PRINT,before)\nG1 X2\nM2\n",
    "non_ascii": "G0 X1 (caf\xe9)\n(MSG,\xe9t\xe9)\nM2\n",
}


def _run(command, tmp_path: Path, text: str, out: str, before_out=()):
    """Run ``command`` (rs274 -g, ngc2py run or the module) on ``text`` in a
    scratch folder with the tool table; returns (result, the output file's
    bytes or None, the folder's names after the run)."""
    with harness.Scratch(tmp_path / "p.ngc", text) as s:
        (s.work / "tools.tbl").write_text(TOOLS)
        (s.work / "old").mkdir()
        if command == "module":
            module = s.tmp / "p_module.py"
            subprocess.run(
                [sys.executable, "-m", "ngc2py", "convert", "p.ngc", "-o", str(module), "-q"],
                cwd=s.work, env=s.env(), check=True,
            )  # fmt: skip
            cmd = [sys.executable, str(module), "-t", "tools.tbl", *before_out, out]
        elif command == "run":
            cmd = [sys.executable, "-m", "ngc2py", "run", "p.ngc", "-t", "tools.tbl", *before_out, out]  # fmt: skip
        else:
            cmd = [
                harness.rs274_path(),
                "-g",
                "-t",
                "tools.tbl",
                *before_out,
                "p.ngc",
                out,
            ]
        result = harness._run(cmd, s, 60)
        target = s.work / out
        written = target.read_bytes() if target.is_file() else None
        names = sorted(p.name for p in s.work.iterdir())
    return result, written, names


@pytest.mark.parametrize("command", ["run", "module"])
@pytest.mark.parametrize("name", sorted(PROGRAMS))
def test_the_trace_goes_to_the_output_file(name, command, tmp_path):
    """The file holds rs274's trace byte for byte (up to an error), stdout
    what rs274 prints itself, stderr its message; nothing else is left in
    the folder."""
    text = PROGRAMS[name]
    expected, expected_file, expected_names = _run("rs274", tmp_path, text, "trace.txt")
    actual, actual_file, actual_names = _run(command, tmp_path, text, "trace.txt")
    assert expected_file is not None and actual_file == expected_file
    assert actual.stdout == expected.stdout
    assert (actual.rc, actual.err) == (expected.rc, expected.err)
    assert actual_names == expected_names  # no temporary file left behind


@pytest.mark.parametrize("command", ["run", "module"])
@pytest.mark.parametrize("out", ["missing/trace.txt", "old"])
def test_an_output_file_that_cannot_be_opened(out, command, tmp_path):
    """No such folder, or a folder of that name: rs274's message and exit
    status, after the tool table's complaints; no trace anywhere."""
    text = PROGRAMS["print"]
    expected, _, _ = _run("rs274", tmp_path, text, out)
    actual, _, _ = _run(command, tmp_path, text, out)
    assert expected.rc == 1 and expected.err == "could not open output file " + out
    assert (actual.stdout, actual.rc, actual.err) == (expected.stdout, 1, expected.err)


def test_the_output_file_may_follow_options(tmp_path):
    """``run P.ngc -b OUT``: the output file after options that follow the
    program, as rs274's getopt takes it (argparse alone would refuse it)."""
    text = "G0 X1\n/G0 X2\nM2\n"
    expected, expected_file, _ = _run("rs274", tmp_path, text, "t.txt", ["-b"])
    actual, actual_file, _ = _run(
        "run", tmp_path, text, "t.txt", ["-b", "--max-steps=100"]
    )
    assert actual_file == expected_file and b"2.0000" not in actual_file
    assert (actual.rc, actual.stdout) == (expected.rc, expected.stdout)


def test_an_existing_output_file_is_replaced_whole(tmp_path):
    """A longer file of the same name is replaced, not written over."""
    with harness.Scratch(tmp_path / "p.ngc", "G0 X1\nM2\n") as s:
        target = s.work / "trace.txt"
        target.write_text("x" * 100000)
        result = harness._run(
            [sys.executable, "-m", "ngc2py", "run", "p.ngc", "trace.txt"], s, 60
        )
        assert result.rc == 0 and result.stdout == b""
        assert target.read_text().startswith("    1 N..... ")
        assert "x" not in target.read_text()


def test_a_missing_program_leaves_the_start_up_calls_in_the_file(tmp_path):
    """rs274 opens the output file before the program: a program it cannot
    open leaves the start-up calls there, and its message on stderr."""
    files = []
    for cmd in ([harness.rs274_path(), "-g"], [sys.executable, "-m", "ngc2py", "run"]):
        with harness.Scratch(tmp_path / "p.ngc", "M2\n") as s:
            result = harness._run(cmd + ["nofile.ngc", "t.txt"], s, 60)
            files.append((result.rc, result.err, (s.work / "t.txt").read_bytes()))
    assert files[0] == files[1]
    assert files[0][0] == 1 and b"SET_FEED_REFERENCE" in files[0][2]


@settings(max_examples=25, deadline=None, suppress_health_check=list(HealthCheck))
@given(strategies.language_programs())
def test_generated_programs_with_an_output_file(program):
    """Generated O-word programs (PRINT and DEBUG comments, errors, -b given
    up to three times) with an output file: the file, stdout, the message
    and the exit status as rs274's."""
    text, args = program
    runs = []
    for cmd in (
        [harness.rs274_path(), "-g", *args, "p.ngc", "t.txt"],
        [sys.executable, "-m", "ngc2py", "run", "p.ngc", *args, "t.txt"],
    ):
        with harness.Scratch(
            harness.REPO / "tests" / "_generated" / "p.ngc", text
        ) as s:
            result = harness._run(cmd, s, harness.DEFAULT_TIMEOUT)
            if result.timed_out:
                return  # rs274 hangs: no reference (ngc2py stops by --max-steps)
            target = s.work / "t.txt"
            runs.append((result.stdout, result.rc, result.err, target.read_bytes()))
    assert runs[0] == runs[1]


@pytest.mark.parametrize("option", [[], ["-t", "keep.txt"], ["-v", "keep.txt"]])
def test_the_trace_never_overwrites_the_program_or_its_files(option, tmp_path):
    """rs274 would truncate the program (or its tool table, parameter file)
    named as the output file; ngc2py refuses before running, and the file
    is as it was."""
    program = tmp_path / "keep.txt" if not option else tmp_path / "p.ngc"
    (tmp_path / "p.ngc").write_text("G0 X1\nM2\n")
    kept = tmp_path / "keep.txt"
    kept.write_text("G0 X1\nM2\n" if not option else "T1 P1\n")
    before = kept.read_bytes()
    proc = subprocess.run(
        [sys.executable, "-m", "ngc2py", "run", program.name, *option, "keep.txt"],
        cwd=tmp_path, capture_output=True, text=True,
    )  # fmt: skip
    assert proc.returncode == 1 and proc.stdout == ""
    assert proc.stderr == "executing\nkeep.txt: the trace would overwrite it\n"
    assert kept.read_bytes() == before


def test_an_output_file_that_cannot_take_its_name_is_an_error(tmp_path):
    """Where the finished trace cannot take the file's name (here its
    temporary file is removed before the end, as when its folder goes
    away), commit says so and answers False, which run_cli makes exit
    status 1: no traceback."""
    import os
    import runtime.main as cli_main

    folder = tmp_path / "out"
    folder.mkdir()
    target = cli_main._open_output(str(folder / "t.txt"))
    target.write("    1 N..... ON_RESET()\n")
    os.unlink(target.temporary)  # the temporary file is gone: rename fails
    import io

    stderr = io.StringIO()
    assert target.commit(stderr) is False
    assert stderr.getvalue().startswith("could not write output file ")
    assert not (folder / "t.txt").exists()


def test_the_output_file_has_the_mode_fopen_gives_it(tmp_path):
    """A new output file gets 0666 less the umask, an existing one keeps its
    mode, as rs274's fopen leaves them (not a temporary file's 0600)."""
    import os

    for existing in (None, 0o640):
        with harness.Scratch(tmp_path / "p.ngc", "G0 X1\nM2\n") as s:
            modes = []
            for cmd in (
                [harness.rs274_path(), "-g"],
                [sys.executable, "-m", "ngc2py", "run"],
            ):
                target = s.work / "t.txt"
                if existing is not None:
                    target.write_text("old\n")
                    os.chmod(target, existing)
                elif target.exists():
                    target.unlink()
                assert harness._run(cmd + ["p.ngc", "t.txt"], s, 60).rc == 0
                modes.append(os.stat(target).st_mode & 0o7777)
            assert modes[0] == modes[1]
            assert modes[0] == (existing or modes[0]) and modes[0] != 0o600


@pytest.mark.parametrize("command", ["run", "convert"])
def test_a_device_or_a_pipe_is_written_to_not_replaced(command, tmp_path):
    """``-o /dev/null`` or a FIFO a reader waits on: the output goes into it,
    as rs274's fopen sends it, and it stays what it was (a rename over it
    would put a regular file in its place: as root, /dev/null itself)."""
    import os
    import stat
    import threading

    (tmp_path / "p.ngc").write_text("G0 X1\nM2\n")
    fifo = tmp_path / "out.fifo"
    os.mkfifo(fifo)
    got = []
    # (a daemon: where the FIFO was replaced, no writer ever releases it)
    reader = threading.Thread(target=lambda: got.append(fifo.read_bytes()), daemon=True)
    reader.start()
    if command == "run":
        cmd = [sys.executable, "-m", "ngc2py", "run", "p.ngc", str(fifo)]
    else:
        cmd = [sys.executable, "-m", "ngc2py", "convert", "p.ngc", "-o", str(fifo), "-q"]
    env = dict(os.environ, PYTHONPATH=str(harness.REPO))
    done = subprocess.run(cmd, cwd=tmp_path, env=env, capture_output=True, timeout=60)
    reader.join(timeout=20)
    assert done.returncode == 0, done.stderr
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    assert got and (b"STRAIGHT_TRAVERSE(1.0000" in got[0] or b"def main" in got[0])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.fifo", "p.ngc"]


def test_a_temporary_file_is_new_private_and_beside_its_target(tmp_path):
    from runtime.atomic import temporary_beside

    target = tmp_path / "trace.txt"
    made = [temporary_beside(str(target)) for _ in range(50)]
    made.append(temporary_beside(str(target), ".tmp-", ".py"))
    for fd, _ in made:
        os.close(fd)
    paths = [path for _, path in made]
    assert len(set(paths)) == len(paths)  # each made by its own call
    for path in paths:
        assert os.path.dirname(path) == str(tmp_path)
        assert os.stat(path).st_mode & 0o777 == 0o600
    assert all(os.path.basename(p).startswith(".trace.txt.") for p in paths[:-1])
    name = os.path.basename(paths[-1])
    assert name.startswith(".tmp-") and name.endswith(".py")
