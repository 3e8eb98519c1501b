"""Golden tests for G-code programs: record what a program does, check it later.

A recording sits next to its program, one file per aspect, the same format
as this project's own corpus (``golden/README.md``)::

    PROG.ngc    the program
    PROG.out    its stdout (the canonical-call trace), byte for byte
    PROG.err    its error message (the first stderr line that is not the
                ``executing`` banner) and a newline, or empty
    PROG.rc     its exit status and a newline
    PROG.args   optional: the options it runs with (``-t tools.tbl -b``),
                as shell words

``ngc2py golden record`` writes them from ngc2py's own run (the user's
reference: "what my program does today"); ``ngc2py golden check`` runs the
program again and compares. This project records its corpus from LinuxCNC's
``rs274`` instead (``golden/record.py``) and compares with the same code.

Every run happens in a scratch folder with a private ``HOME``, holding
copies of the files the run can read (:func:`run_inputs`; the whole folder
where that cannot be told), and the program named by its relative name, so
that a ``-v`` parameter file rs274 rewrites, a ``(LOGOPEN,...)`` or a
parallel run cannot touch the user's files, and messages that echo the file
name do not depend on where the folder lives. Runs share the caller's
compile cache: its entries do not depend on the folder, so a library is
compiled once, not once per check.
"""

from __future__ import annotations

import difflib
import io
import os
import shlex
import shutil
import signal
import sys
import tempfile
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import Iterable, List, Optional, Sequence, Union

#: The files of a recording, by suffix.
RECORDING = (".out", ".err", ".rc")
ARGS = ".args"

#: A folder (or any folder above it) holding this file has recordings made
#: by rs274, not by ngc2py: ``record`` refuses to overwrite them.
REFERENCE_MARK = ".golden-from-rs274"

#: Folders larger than this are not copied for a run (only the program is).
MAX_COPY_BYTES = 5_000_000
#: What a scratch copy of a folder leaves out besides its recordings.
NOT_COPIED = ("__pycache__", ".ngc2py_cache", ".git")

#: Exit statuses of ``ngc2py golden``.
EXIT_OK, EXIT_CHANGED, EXIT_USAGE = 0, 1, 2


@dataclass(frozen=True)
class Result:
    """What one run did: ``stdout`` bytes, the error message ``err`` (first
    stderr line that is not ``executing``; "" when none), the exit status
    ``rc`` (None: timed out) and the whole ``stderr``."""

    stdout: bytes
    err: str
    rc: Optional[int]
    stderr: bytes = b""

    @property
    def timed_out(self) -> bool:
        return self.rc is None

    def describe(self) -> str:
        tail = self.stdout.decode("utf-8", "replace").splitlines()[-5:]
        return (
            f"rc={self.rc} err={self.err!r}\n"
            f"stderr={self.stderr.decode('utf-8', 'replace')[:600]!r}\n"
            "stdout tail:\n  " + "\n  ".join(tail)
        )


class GoldenError(Exception):
    """A golden run cannot be done (no recording, a reference folder...)."""


# ---------------------------------------------------------------------------
# The recording format
# ---------------------------------------------------------------------------


def first_error_line(stderr: Union[bytes, str]) -> str:
    """The error message: the first non-blank stderr line that is not
    rs274's ``executing`` banner."""
    if isinstance(stderr, bytes):
        stderr = stderr.decode("utf-8", "replace")
    for line in stderr.splitlines():
        if line.strip() in ("executing", ""):
            continue
        return line.rstrip("\r")
    return ""


def has_recording(program: Path) -> bool:
    return Path(program).with_suffix(".rc").exists()


def read_args(program: Path) -> List[str]:
    """The options of ``program`` from ``PROG.args`` (shell words), or []."""
    path = Path(program).with_suffix(ARGS)
    return shlex.split(path.read_text()) if path.exists() else []


def load(program: Path) -> Result:
    """The recorded result of ``program``."""
    program = Path(program)
    try:
        out = program.with_suffix(".out").read_bytes()
        err = program.with_suffix(".err").read_text().rstrip("\n")
        rc = int(program.with_suffix(".rc").read_text().strip())
    except (OSError, ValueError) as error:
        raise GoldenError(f"{program}: no usable recording ({error})") from None
    return Result(out, err, rc)


def reference_folder(program: Path) -> Optional[Path]:
    """The folder marked as holding rs274's recordings, if ``program`` is in one."""
    for folder in Path(program).resolve().parents:
        if (folder / REFERENCE_MARK).exists():
            return folder
    return None


def save(program: Path, result: Result, args: Optional[Sequence[str]] = None) -> None:
    """Write ``result`` as the recording of ``program``; ``args`` (when not
    None) replace ``PROG.args`` (an empty list removes it)."""
    program = Path(program)
    _write(program.with_suffix(".out"), result.stdout)
    _write(program.with_suffix(".err"), (result.err + "\n" if result.err else "").encode())
    _write(program.with_suffix(".rc"), f"{result.rc}\n".encode())
    if args is not None:
        path = program.with_suffix(ARGS)
        if args:
            _write(path, (" ".join(shlex.quote(a) for a in args) + "\n").encode())
        elif path.exists():
            path.unlink()


def _write(path: Path, data: bytes) -> None:
    """Atomically: a check running in parallel never reads half a file."""
    from ngc2py.cache import write_atomic  # the compiler, only when recording

    write_atomic(path, data)


# ---------------------------------------------------------------------------
# Comparing
# ---------------------------------------------------------------------------


def unified_diff(
    expected: bytes,
    actual: bytes,
    names: Sequence[str] = ("recorded", "now"),
    context: int = 3,
    limit: Optional[int] = 60,
) -> str:
    """A unified diff of two outputs, at most ``limit`` lines of it."""
    a = expected.decode("utf-8", "replace").splitlines(keepends=True)
    b = actual.decode("utf-8", "replace").splitlines(keepends=True)
    lines = [
        line if line.endswith("\n") else line + "\n\\ No newline at end of file\n"
        for line in difflib.unified_diff(a, b, names[0], names[1], n=context)
    ]
    if not lines and expected != actual:
        return f"  (bytes differ at the end: {expected[-20:]!r} vs {actual[-20:]!r})\n"
    text = "".join(lines if limit is None else lines[:limit])
    if limit is not None and len(lines) > limit:
        text += f"... {len(lines) - limit} more diff lines\n"
    return text


def compare(
    expected: Result, actual: Result, names: Sequence[str] = ("recorded", "now")
) -> List[str]:
    """What differs between two results (empty when they are the same): the
    exit status, the error message, stdout byte for byte (as a diff)."""
    problems: List[str] = []
    if actual.timed_out:
        problems.append(f"{names[1]}: timed out")
    if expected.rc != actual.rc:
        problems.append(f"exit status: {names[0]} {expected.rc}, {names[1]} {actual.rc}")
    if expected.err != actual.err:
        problems.append(
            f"error message:\n  {names[0]}: {expected.err!r}\n  {names[1]}: {actual.err!r}"
        )
    if expected.stdout != actual.stdout:
        problems.append("stdout differs:\n" + unified_diff(expected.stdout, actual.stdout, names))
    return problems


# ---------------------------------------------------------------------------
# Finding programs
# ---------------------------------------------------------------------------


def is_subroutine_file(path: Path) -> bool:
    """A file only other programs call: its first line says ``(helper``
    (this project's convention), or its first statement is ``o<STEM> sub``
    (a LinuxCNC external subroutine file)."""
    try:
        with open(path, errors="replace") as handle:
            for number, line in enumerate(handle):
                text = line.strip().lower()
                if number == 0 and "(helper" in text:
                    return True
                if not text or text.startswith(("(", ";", "%")):
                    if number > 50:
                        return False
                    continue
                compact = text.replace(" ", "").replace("\t", "")
                return compact.startswith("o<%s>sub" % path.stem.lower())
    except OSError:
        return False
    return False


def find_programs(targets: Iterable[Union[str, Path]], recorded_only: bool) -> List[Path]:
    """The programs named by ``targets`` (files, or folders searched
    recursively for ``*.ngc``), without subroutine files; with
    ``recorded_only`` only those in folders that have a recording. A file
    named explicitly is always kept (the caller reports what is missing)."""
    found: List[Path] = []
    for target in targets:
        target = Path(target)
        if target.is_dir():
            for path in sorted(target.rglob("*.ngc")):
                if recorded_only and not has_recording(path):
                    continue
                if not is_subroutine_file(path):
                    found.append(path)
        else:
            found.append(target)
    seen, unique = set(), []
    for path in found:
        key = os.path.abspath(path)
        if key not in seen:
            seen.add(key)
            unique.append(path)
    return unique


# ---------------------------------------------------------------------------
# Running
# ---------------------------------------------------------------------------


class Scratch:
    """A temporary copy of a program's folder, a private HOME and cache."""

    def __init__(
        self,
        program: Path,
        text: Optional[str] = None,
        inputs: Optional[Sequence[str]] = None,
    ):
        """``inputs``: the only files of the folder the run needs (names
        relative to it); None copies the whole folder (up to
        MAX_COPY_BYTES)."""
        self.tmp = Path(tempfile.mkdtemp(prefix="ngc2py-golden-"))
        self.home = self.tmp / "home"
        self.home.mkdir()
        self.cache = self.tmp / "cache"
        self.work = self.tmp / "work"
        source = program.parent
        if inputs is not None:
            self.work.mkdir()
            for name in inputs:
                target = self.work / name
                target.parent.mkdir(parents=True, exist_ok=True)
                shutil.copy2(source / name, target)
        elif text is None and source.is_dir() and _folder_size(source) <= MAX_COPY_BYTES:
            shutil.copytree(
                source,
                self.work,
                ignore=shutil.ignore_patterns("*.out", "*.err", "*.rc", *NOT_COPIED),
                symlinks=True,
            )
        else:
            self.work.mkdir()
        self.program = self.work / program.name
        if text is not None:
            self.program.write_text(text)
        elif not self.program.exists():
            shutil.copy2(program, self.program)

    def __enter__(self) -> "Scratch":
        return self

    def __exit__(self, *exc) -> None:
        shutil.rmtree(self.tmp, ignore_errors=True)


def run_inputs(program: Path, args: Sequence[str]) -> Optional[List[str]]:
    """The files of ``program``'s folder a run of it can read, found without
    copying the folder: the program, the ``-t``/``-v`` files, and the
    external subroutine files its compiled module was made from (the
    compile cache's probes; compiling here, in the folder, is what the run
    in the scratch copy then finds in the cache). None where that cannot be
    told (an ini file, which can name more files; a path outside the
    folder; a compile error): the caller copies the whole folder."""
    from ngc2py.cache import cached_module, module_probes

    folder = program.parent
    names = [program.name]
    words = list(args)
    for flag, value in zip(words, words[1:] + [""]):
        if flag == "-i":
            return None
        if flag in ("-t", "-v"):
            if os.path.isabs(value) or ".." in Path(value).parts:
                return None
            if (folder / value).is_file():
                names.append(value)
    saved = os.getcwd()
    try:
        os.chdir(folder)
        probes = module_probes(cached_module(program.name, None))
    except Exception:  # noqa: BLE001 - any doubt: copy the folder
        return None
    finally:
        os.chdir(saved)
    for path, digest in probes:
        if digest is None:
            continue
        if os.path.isabs(path) or ".." in Path(path).parts:
            return None
        names.append(path)
    return list(dict.fromkeys(names))


def _folder_size(folder: Path) -> int:
    total = 0
    for path in folder.rglob("*"):
        if path.is_file():
            total += path.stat().st_size
            if total > MAX_COPY_BYTES:
                break
    return total


class _Timeout(Exception):
    pass


def run(
    program: Union[str, Path],
    args: Sequence[str] = (),
    *,
    text: Optional[str] = None,
    timeout: Optional[float] = None,
) -> Result:
    """Run ``ngc2py run PROGRAM ARGS`` in this process, in a scratch copy of
    the program's folder, capturing stdout and stderr as bytes.

    ``text`` runs that program text instead of the file's content (the
    path still names the folder and the file). ``timeout`` (seconds) uses
    SIGALRM, so it only applies in the main thread; elsewhere it is ignored.
    Not thread-safe: it changes the working directory while it runs.
    """
    from ngc2py import cli
    from ngc2py.cache import cache_dir

    program = Path(program)
    # The caller's compile cache, not the scratch copy's: entries are keyed
    # by content and options, not by folder (ngc2py/cache.py), so checking
    # a library again compiles nothing that has not changed.
    cache = cache_dir()
    inputs = None
    if text is None:
        saved_environ = dict(os.environ)
        os.environ["NGC2PY_CACHE"] = cache  # the same entries as the run's
        try:
            inputs = run_inputs(program, args)
        finally:
            os.environ.clear()
            os.environ.update(saved_environ)
    with Scratch(program, text, inputs) as scratch:
        argv = ["run", "-q", scratch.program.name, *args]
        return run_in(scratch, lambda: cli.main(argv), cache, timeout)


def run_in(
    scratch: "Scratch", call, cache: str, timeout: Optional[float] = None
) -> Result:
    """``call()`` as a command run in ``scratch``'s folder with its HOME and
    the compile cache ``cache``: what it prints captured as bytes, its exit
    status what it returns or the SystemExit it raises (None when it ran
    past ``timeout`` seconds: SIGALRM, in the main thread only). The
    process's folder, environment and streams are restored after."""
    out, err = io.BytesIO(), io.BytesIO()
    new_out = io.TextIOWrapper(out, encoding="utf-8", write_through=True)
    new_err = io.TextIOWrapper(err, encoding="utf-8", write_through=True)
    saved = (sys.stdout, sys.stderr, os.getcwd(), dict(os.environ))
    alarm = timeout is not None and threading.current_thread() is threading.main_thread()

    def on_alarm(signum, frame):
        raise _Timeout()

    old_handler = signal.signal(signal.SIGALRM, on_alarm) if alarm else None
    os.environ["HOME"] = str(scratch.home)
    os.environ["NGC2PY_CACHE"] = cache
    os.environ.pop("INI_FILE_NAME", None)
    os.chdir(scratch.work)
    sys.stdout, sys.stderr = new_out, new_err
    if alarm:
        signal.setitimer(signal.ITIMER_REAL, timeout)
    try:
        rc: Optional[int] = call()
    except SystemExit as stop:
        rc = stop.code if isinstance(stop.code, int) else 1
    except _Timeout:
        rc = None
    finally:
        if alarm:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, old_handler)
        for stream in (new_out, new_err):
            try:
                stream.flush()
            except ValueError:
                pass
        sys.stdout, sys.stderr = saved[0], saved[1]
        os.chdir(saved[2])
        os.environ.clear()
        os.environ.update(saved[3])
    return Result(out.getvalue(), first_error_line(err.getvalue()), rc, err.getvalue())


def record(program: Path, args: Optional[Sequence[str]] = None, timeout: Optional[float] = None) -> Result:
    """Run ``program`` and save what it did as its recording. ``args`` None:
    the program's own ``PROG.args``; a list replaces them."""
    program = Path(program)
    reference = reference_folder(program)
    if reference is not None:
        raise GoldenError(
            f"{program}: {reference} holds recordings made by rs274 "
            f"({REFERENCE_MARK}); re-record them with its own recorder"
        )
    if not program.is_file():
        raise GoldenError(f"{program}: no such program")
    options = read_args(program) if args is None else list(args)
    result = run(program, options, timeout=timeout)
    if result.timed_out:
        raise GoldenError(f"{program}: timed out after {timeout}s; nothing recorded")
    save(program, result, None if args is None else options)
    return result


def check(
    program: Path, args: Optional[Sequence[str]] = None, timeout: Optional[float] = None
) -> List[str]:
    """Run ``program`` and compare with its recording: the differences, or []."""
    program = Path(program)
    if not has_recording(program):
        raise GoldenError(f"{program}: not recorded (run `ngc2py golden record {program}`)")
    expected = load(program)
    options = read_args(program) if args is None else list(args)
    return compare(expected, run(program, options, timeout=timeout))


# ---------------------------------------------------------------------------
# The ``ngc2py golden`` command
# ---------------------------------------------------------------------------

HELP = """\
Golden tests for your own G-code programs.

  ngc2py golden record PATH...   run each program and store what it did
  ngc2py golden check  PATH...   run each again; print a diff where it changed

PATH is a program or a folder (searched recursively for *.ngc; external
subroutine files, whose first statement is o<NAME> sub, are skipped). The
recording sits next to PROG.ngc: PROG.out (stdout, the canonical-call
trace), PROG.err (the error message, or empty), PROG.rc (exit status) and,
when options were given, PROG.args. Each run happens in a scratch copy of
the program's folder, so -v files and logs are left alone.

Exit status: 0 all recorded / all unchanged; 1 some program changed (check)
or could not be recorded; 2 nothing to do (no programs, or a program has no
recording)."""


def register(commands) -> None:
    """Add ``golden`` to the CLI's sub-command parser."""
    import argparse

    from ngc2py.flags import add_block_delete

    parser = commands.add_parser(
        "golden",
        help="record or check golden traces of your programs",
        description=HELP,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("action", choices=("record", "check"))
    parser.add_argument("paths", nargs="+", metavar="PATH", help="programs or folders")
    parser.add_argument("-t", dest="tool_table", metavar="TBL", help="tool table file")
    parser.add_argument("-v", dest="var_file", metavar="VAR", help="parameter (.var) file")
    parser.add_argument("-i", dest="ini", metavar="INI", help="ini file")
    add_block_delete(parser, "block delete on")
    parser.add_argument("-q", "--quiet", action="store_true", help="print only changes and the summary")
    parser.add_argument(
        "--timeout", type=float, default=None, metavar="S", help="seconds before a run counts as hung"
    )
    parser.set_defaults(handler=main)


def options_of(args) -> Optional[List[str]]:
    """The rs274 options given on the command line, or None for none."""
    options: List[str] = []
    for flag, value in (("-t", args.tool_table), ("-v", args.var_file), ("-i", args.ini)):
        if value is not None:
            # relative to the program's folder, where the run happens
            options += [flag, value]
    if args.block_delete:
        options.append("-b")
    return options or None


def main(args) -> int:
    """``ngc2py golden record|check``: returns the exit status."""
    from ngc2py.progress import progress

    recording = args.action == "record"
    programs = find_programs(args.paths, recorded_only=not recording)
    if not programs:
        sys.stderr.write("ngc2py golden: no programs found in %s\n" % " ".join(args.paths))
        return EXIT_USAGE
    options = options_of(args)
    changed, missing, done = [], [], 0
    with progress(len(programs), "golden " + args.action, "program", quiet=args.quiet) as bar:
        for program in programs:
            bar.update(1)
            name = str(program)
            try:
                if recording:
                    result = record(program, options, args.timeout)
                    if not args.quiet:
                        bar.write(f"recorded {name} (rc={result.rc}{', ' + result.err if result.err else ''})")
                else:
                    problems = check(program, options, args.timeout)
                    if problems:
                        changed.append(name)
                        bar.write(f"CHANGED {name}\n" + _indent("\n".join(problems)))
                    elif not args.quiet:
                        bar.write(f"ok {name}")
                done += 1
            except GoldenError as error:
                missing.append(name)
                bar.write(f"ngc2py golden: {error}", error=True)
    verb = "recorded" if recording else "checked"
    summary = f"{verb} {done} of {len(programs)} programs"
    if not recording:
        summary += f": {done - len(changed)} unchanged, {len(changed)} changed"
    if missing:
        summary += f"; {len(missing)} could not be {verb}"
    sys.stdout.write(summary + "\n")
    if changed:
        return EXIT_CHANGED
    if missing:
        return EXIT_USAGE if not recording else EXIT_CHANGED
    return EXIT_OK


def _indent(text: str) -> str:
    return "".join("    " + line + "\n" for line in text.rstrip("\n").split("\n"))


__all__ = [
    "Result",
    "GoldenError",
    "first_error_line",
    "read_args",
    "load",
    "save",
    "compare",
    "unified_diff",
    "find_programs",
    "run",
    "record",
    "check",
]
