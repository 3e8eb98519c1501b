"""Helpers that run the reference (LinuxCNC's ``rs274``) and ngc2py the same way.

Both runners take a G-code program (a path, or program text plus a name),
copy the program's folder into a fresh temporary directory, run there with a
relative file name, and return a :class:`Result`:

* ``stdout`` -- bytes, exactly as printed;
* ``err``    -- the first stderr line that is not rs274's ``executing``
  banner (rs274's error message; ``""`` when there is none);
* ``rc``     -- the exit status (``None`` if the run timed out).

Why a copy of the folder: rs274 rewrites the ``-v`` parameter file when it
exits, (LOGOPEN ...) creates files, and rs274 keeps its tool state in
``$HOME/.tool.mmap``. Running every program in its own scratch directory with
its own ``HOME`` keeps runs independent, parallel-safe and leaves the
repository untouched. Program names stay relative so messages that echo a
file name do not depend on where the scratch directory is.
"""

from __future__ import annotations

import os
import shlex
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Iterable, List, Optional, Sequence, Union

REPO = Path(__file__).resolve().parent.parent

#: Seconds before a run is declared hung.
DEFAULT_TIMEOUT = float(os.environ.get("NGC2PY_TEST_TIMEOUT", "60"))

#: Folders larger than this are not copied wholesale (only the program is).
_MAX_COPY_BYTES = 5_000_000


@dataclass(frozen=True)
class Result:
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


def rs274_path() -> Optional[str]:
    """The rs274 executable, or None when LinuxCNC is not installed."""
    override = os.environ.get("RS274")
    if override:
        return override if shutil.which(override) else None
    return shutil.which("rs274")


def first_error_line(stderr: Union[bytes, str]) -> str:
    """rs274's error message: the first stderr line that is not ``executing``."""
    if isinstance(stderr, bytes):
        stderr = stderr.decode("utf-8", "replace")
    for line in stderr.splitlines():
        if line.strip() == "executing":
            continue
        if line.strip() == "":
            continue
        return line.rstrip("\r")
    return ""


def read_args(path: Path) -> List[str]:
    """Extra options for a golden program from ``<name>.args`` (shell words)."""
    args_file = path.with_suffix(".args")
    if args_file.exists():
        return shlex.split(args_file.read_text())
    return []


def _folder_size(folder: Path) -> int:
    total = 0
    for p in folder.rglob("*"):
        if p.is_file():
            total += p.stat().st_size
            if total > _MAX_COPY_BYTES:
                break
    return total


class Scratch:
    """A temporary working copy of a program's folder plus a private HOME."""

    def __init__(self, program: Path, text: Optional[str] = None):
        self.tmp = Path(tempfile.mkdtemp(prefix="ngc2py-test-"))
        self.home = self.tmp / "home"
        self.home.mkdir()
        self.work = self.tmp / "work"
        src = program.parent
        if text is None and src.is_dir() and _folder_size(src) <= _MAX_COPY_BYTES:
            shutil.copytree(
                src,
                self.work,
                ignore=shutil.ignore_patterns(
                    "*.out", "*.err", "*.rc", "__pycache__", ".ngc2py_cache"
                ),
            )
        else:
            self.work.mkdir()
        self.program = self.work / program.name
        if text is not None:
            self.program.write_text(text)
        elif not self.program.exists():
            shutil.copy2(program, self.program)

    def env(self, extra: Optional[dict] = None) -> dict:
        env = dict(os.environ)
        env["HOME"] = str(self.home)
        env.pop("INI_FILE_NAME", None)
        env["PYTHONPATH"] = os.pathsep.join(
            [str(REPO)] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p]
        )
        env["PYTHONDONTWRITEBYTECODE"] = "1"
        env["LC_ALL"] = "C"
        if extra:
            env.update(extra)
        return env

    def cleanup(self) -> None:
        shutil.rmtree(self.tmp, ignore_errors=True)

    def __enter__(self) -> "Scratch":
        return self

    def __exit__(self, *exc) -> None:
        self.cleanup()


def _run(cmd: Sequence[str], scratch: Scratch, timeout: float) -> Result:
    try:
        proc = subprocess.run(
            list(cmd),
            cwd=scratch.work,
            env=scratch.env(),
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            timeout=timeout,
        )
    except subprocess.TimeoutExpired as exc:
        out = exc.stdout or b""
        err = exc.stderr or b""
        return Result(out, first_error_line(err), None, err)
    return Result(proc.stdout, first_error_line(proc.stderr), proc.returncode, proc.stderr)


def run_rs274(
    program: Union[str, Path],
    args: Iterable[str] = (),
    *,
    text: Optional[str] = None,
    timeout: float = DEFAULT_TIMEOUT,
) -> Result:
    """Run ``rs274 -g [args] PROGRAM`` in a scratch copy of the program's folder.

    ``text``: run this program text instead of the file's contents (the file
    name still decides the folder that is copied; it need not exist).
    """
    exe = rs274_path()
    if exe is None:
        raise RuntimeError("rs274 is not installed (LinuxCNC's linuxcnc-uspace package)")
    program = Path(program)
    with Scratch(program, text) as s:
        return _run([exe, "-g", *args, s.program.name], s, timeout)


def run_ngc2py(
    program: Union[str, Path],
    args: Iterable[str] = (),
    *,
    text: Optional[str] = None,
    mode: str = "run",
    timeout: float = DEFAULT_TIMEOUT,
) -> Result:
    """Run ngc2py on a program the way rs274 is run by :func:`run_rs274`.

    ``mode="run"``: ``python -m ngc2py run PROGRAM [args]``.
    ``mode="convert"``: ``python -m ngc2py convert PROGRAM -o prog.py`` then
    ``python prog.py [args]`` -- the generated module on its own. A failing
    conversion is reported as the result (its stderr, its exit status).
    ``mode="inprocess"``: see :func:`run_ngc2py_inprocess`.
    """
    program = Path(program)
    args = list(args)
    if mode == "inprocess":
        return run_ngc2py_inprocess(program, args, text=text, timeout=timeout)
    with Scratch(program, text) as s:
        if mode == "run":
            return _run(
                [sys.executable, "-m", "ngc2py", "run", s.program.name, *args], s, timeout
            )
        if mode == "convert":
            module = s.tmp / "generated" / (_module_name(program.stem) + ".py")
            module.parent.mkdir()
            # the ini file's SUBROUTINE_PATH matters at compile time too
            ini = []
            if "-i" in args and args.index("-i") + 1 < len(args):
                ini = ["-i", args[args.index("-i") + 1]]
            conv = _run(
                [sys.executable, "-m", "ngc2py", "convert", s.program.name, *ini, "-o", str(module)],
                s,
                timeout,
            )
            if conv.rc != 0 or not module.exists():
                return Result(
                    conv.stdout,
                    conv.err or "ngc2py convert failed",
                    conv.rc if conv.rc else 99,
                    conv.stderr,
                )
            return _run([sys.executable, str(module), *args], s, timeout)
        raise ValueError(f"unknown mode {mode!r}")


class _InProcessTimeout(Exception):
    pass


def run_ngc2py_inprocess(
    program: Union[str, Path],
    args: Iterable[str] = (),
    *,
    text: Optional[str] = None,
    timeout: float = DEFAULT_TIMEOUT,
) -> Result:
    """``ngc2py run`` without a new interpreter: ``ngc2py.cli.main`` called in
    this process, with stdout/stderr captured as bytes, the scratch folder as
    cwd and a private HOME and compile cache. Saves the interpreter start-up
    and imports (most of the cost of a small program); the subprocess runner
    stays the reference because it is exactly what a user runs. The timeout
    uses SIGALRM, so this works only in the main thread (pytest and
    pytest-xdist workers run tests there).
    """
    import io
    import signal

    from ngc2py import cli  # imported here: the harness must load without ngc2py

    program = Path(program)
    with Scratch(program, text) as s:
        out, err = io.BytesIO(), io.BytesIO()
        new_out = io.TextIOWrapper(out, encoding="utf-8", write_through=True)
        new_err = io.TextIOWrapper(err, encoding="utf-8", write_through=True)
        saved = (sys.stdout, sys.stderr, os.getcwd(), dict(os.environ))

        def on_alarm(signum, frame):
            raise _InProcessTimeout()

        old_handler = signal.signal(signal.SIGALRM, on_alarm)
        os.environ["HOME"] = str(s.home)
        os.environ["NGC2PY_CACHE"] = str(s.tmp / "cache")
        os.chdir(s.work)
        sys.stdout, sys.stderr = new_out, new_err
        signal.setitimer(signal.ITIMER_REAL, timeout)
        try:
            rc: Optional[int] = cli.main(["run", s.program.name, *args])
        except SystemExit as exc:
            rc = exc.code if isinstance(exc.code, int) else 1
        except _InProcessTimeout:
            rc = None
        finally:
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


def _module_name(stem: str) -> str:
    name = "".join(c if c.isalnum() else "_" for c in stem)
    if not name or name[0].isdigit():
        name = "p_" + name
    return name


def compare(expected: Result, actual: Result) -> List[str]:
    """Human-readable differences between two results (empty when equal).

    Equal means: byte-identical stdout, same exit status, same first error
    line (rs274's message).
    """
    problems: List[str] = []
    if actual.timed_out:
        problems.append("ngc2py timed out")
    if expected.rc != actual.rc:
        problems.append(f"exit status: expected {expected.rc}, got {actual.rc}")
    if expected.err != actual.err:
        problems.append(f"error message: expected {expected.err!r}, got {actual.err!r}")
    if expected.stdout != actual.stdout:
        problems.append("stdout differs:\n" + stdout_diff(expected.stdout, actual.stdout))
    return problems


def stdout_diff(expected: bytes, actual: bytes, context: int = 3, limit: int = 40) -> str:
    import difflib

    a = expected.decode("utf-8", "replace").splitlines(keepends=True)
    b = actual.decode("utf-8", "replace").splitlines(keepends=True)
    lines = list(difflib.unified_diff(a, b, "rs274", "ngc2py", n=context))
    if not lines and expected != actual:
        return f"  (line endings/trailing bytes differ: {expected[-20:]!r} vs {actual[-20:]!r})"
    more = len(lines) - limit
    text = "".join(lines[:limit])
    if more > 0:
        text += f"... {more} more diff lines\n"
    return text


# --------------------------------------------------------------------------
# The golden corpus (golden/<feature>/<name>.ngc + .out/.err/.rc/.args/.expect)
# --------------------------------------------------------------------------

GOLDEN = REPO / "golden"


def golden_programs(root: Path = GOLDEN) -> List[Path]:
    """Every golden program: ``golden/<feature>/<name>.ngc`` that has a recording
    (``.rc``) or a better-behaviour description (``.expect``).

    Programs in a folder that are only called by others (external subroutine
    files) have neither and are not tests of their own.
    """
    found = []
    for p in sorted(root.glob("*/**/*.ngc")):
        if p.with_suffix(".rc").exists() or p.with_suffix(".expect").exists():
            found.append(p)
    return found


def load_expected(program: Path) -> Result:
    """The recorded rs274 result of a golden program."""
    out = program.with_suffix(".out").read_bytes()
    err = program.with_suffix(".err").read_text().rstrip("\n")
    rc = int(program.with_suffix(".rc").read_text().strip())
    return Result(out, err, rc)


def load_expect(program: Path) -> dict:
    """A ``<name>.expect`` file: ``key: value`` lines describing the behaviour
    ngc2py must show where rs274 crashes or hangs.

    Keys: ``rc`` (exit status), ``err`` (exact first error line),
    ``err_contains`` (substring of it), ``stdout_prefix`` (a file in the same
    folder whose bytes stdout must start with), ``max_seconds`` (time limit),
    ``why`` (free text, what rs274 does).
    """
    spec = {}
    for raw in program.with_suffix(".expect").read_text().splitlines():
        if not raw.strip() or raw.lstrip().startswith("#"):
            continue
        key, _, value = raw.partition(":")
        spec[key.strip()] = value.strip()
    return spec
