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
import runpy
import shutil
import stat
import subprocess
import sys
from pathlib import Path
from typing import Iterable, List, Optional, Sequence, Union

REPO = Path(__file__).resolve().parent.parent
if str(REPO) not in sys.path:
    sys.path.insert(0, str(REPO))

# The recording format, the comparison and the in-process runner are the
# ones `ngc2py golden` uses for users' programs (ngc2py/golden.py); only the
# reference differs: this corpus is recorded from rs274.
from ngc2py import cli, golden  # noqa: E402
from ngc2py.golden import Result, first_error_line, read_args  # noqa: E402,F401

#: How the two sides of a comparison are named in messages and diffs.
SIDES = ("rs274", "ngc2py")

#: Seconds before a run is declared hung.
DEFAULT_TIMEOUT = float(os.environ.get("NGC2PY_TEST_TIMEOUT", "60"))

#: NGC2PY_TEST_PROCESSES=1: every ngc2py run of the tests in new processes,
#: as a user starts them (``inprocess`` as ``run``, ``convert`` as
#: ``convert-process``): slower, for a release check. By default those two
#: modes run in the test's own process, a new interpreter's start-up being
#: most of the cost of a small program; tests/test_golden.py keeps a share of
#: the corpus in new processes either way.
PROCESSES = os.environ.get("NGC2PY_TEST_PROCESSES", "") not in ("", "0")


def rs274_path() -> Optional[str]:
    """The rs274 executable, or None when LinuxCNC is not installed.

    Raises RuntimeError when this machine would make rs274's answers depend
    on chance (see :func:`null_device_problem`).
    """
    override = os.environ.get("RS274")
    if override:
        exe = shutil.which(override)
    else:
        exe = shutil.which("rs274")
    if exe is not None:
        problem = null_device_problem()
        if problem:
            raise RuntimeError(problem)
    return exe


def null_device_problem() -> Optional[str]:
    """Why rs274 cannot be trusted as the reference here, or None.

    When its parameter file does not exist yet (a missing ``-v`` file, or the
    default ``rs274ngc.var`` in a fresh folder), rs274 reads /dev/null in its
    place. Some container images ship /dev/null as a regular file holding
    whatever some process last wrote to it: rs274 then reads that text as
    parameters, and may silently skip saving them (no "link (updating
    variable file)" report), so a differential test would fail at random.
    """
    try:
        mode = os.stat(os.devnull).st_mode
    except OSError as exc:
        return f"{os.devnull}: {exc.strerror}"
    if stat.S_ISCHR(mode):
        return None
    return (
        f"{os.devnull} is not the null device on this machine (it is a regular file):"
        " rs274 reads it as its parameter file when that file does not exist yet, so"
        " its reports would depend on what was last written there. As root:"
        f" rm -f {os.devnull} && mknod -m 666 {os.devnull} c 1 3 (.ci/run does this)"
    )


class Scratch(golden.Scratch):
    """A temporary working copy of a program's folder plus a private HOME
    (ngc2py.golden's), with the environment for subprocesses.

    ``args``: the options of an ngc2py run; given, only the files that run
    can read are copied (``ngc2py.golden.run_inputs``: what ``ngc2py
    golden`` copies), not a golden folder of hundreds of programs. For
    ngc2py's side: rs274's own runs copy the whole folder, so a file
    ngc2py fails to look for still shows as a difference."""

    def __init__(self, program, text=None, inputs=None, *, args=None, linked=False):
        """``linked``: for rs274's runs, the program's folder is in the
        scratch folder whole, its G-code files linked rather than copied
        (golden/oword alone holds hundreds: copying them took five times
        the run), the files rs274 may write (var files, tool tables, logs)
        copied."""
        program = Path(program)
        if text is None and inputs is None and args is not None:
            inputs = golden.run_inputs(program, list(args))
        if linked and text is None and inputs is None and program.parent.is_dir():
            super().__init__(program, None, ())  # the program alone, copied
            _link_folder(program.parent, self.work, skip=program.name)
            return
        super().__init__(program, text, inputs)

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


#: Files rs274 only reads (subroutine files): linked into a scratch folder.
_READ_ONLY = (".ngc", ".nc")
#: What a golden folder holds beside its programs that no run reads.
_RECORDINGS = (".out", ".err", ".rc", ".expect", ".partial", ".args")


def _link_folder(source: Path, work: Path, skip: str) -> None:
    for entry in os.scandir(source):
        name = entry.name
        suffix = os.path.splitext(name)[1]
        if name == skip or suffix in _RECORDINGS or name in golden.NOT_COPIED:
            continue
        if entry.is_dir():
            shutil.copytree(entry.path, work / name, symlinks=True)
        elif suffix in _READ_ONLY:
            os.symlink(os.path.abspath(entry.path), work / name)
        else:
            shutil.copy2(entry.path, work / name)


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
    for _ in range(_HAL_TRIES):
        with Scratch(program, text, linked=True) as s:
            result = _run([exe, "-g", *args, s.program.name], s, timeout)
        if not result.err.startswith(_HAL_LEFT_OVER):
            break
    return result


#: Under HAL_PIN_VARS rs274 makes a HAL component named after its process
#: id and never removes it: once process ids wrap round (a machine up for
#: days of test runs), a new rs274 may meet its own name, left in HAL's
#: shared memory by an earlier one. Not the program's doing: run it again
#: (another process id).
_HAL_LEFT_OVER = "HAL: ERROR: duplicate component name 'interp"
_HAL_TRIES = 5


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
    ``mode="inprocess"``: see :func:`run_ngc2py_inprocess`.
    ``mode="convert-process"``: ``python -m ngc2py convert PROGRAM -o
    prog.py`` then ``python prog.py [args]`` -- the generated module on its
    own. A failing conversion is reported as the result (its stderr, its
    exit status).
    ``mode="convert"``: the same two commands run in this process (the
    module file run as ``python prog.py`` runs it, as ``__main__`` with its
    own ``sys.argv``).
    :data:`PROCESSES` turns ``inprocess`` into ``run`` and ``convert`` into
    ``convert-process``.
    """
    program = Path(program)
    args = list(args)
    if PROCESSES:
        mode = {"inprocess": "run", "convert": "convert-process"}.get(mode, mode)
    if mode == "inprocess":
        return run_ngc2py_inprocess(program, args, text=text, timeout=timeout)
    if mode not in ("run", "convert", "convert-process"):
        raise ValueError(f"unknown mode {mode!r}")
    with Scratch(program, text, args=args) as s:
        if mode == "run":
            return _run(
                [sys.executable, "-m", "ngc2py", "run", s.program.name, *args], s, timeout
            )
        module = s.tmp / "generated" / (_module_name(program.stem) + ".py")
        module.parent.mkdir()
        convert = ["convert", s.program.name, *_convert_options(args), "-o", str(module)]
        if mode == "convert":
            cache = golden_cache()
            conv = golden.run_in(s, lambda: cli.main(convert), cache, timeout)
        else:
            conv = _run([sys.executable, "-m", "ngc2py", *convert], s, timeout)
        if conv.rc != 0 or not module.exists():
            return Result(
                conv.stdout,
                conv.err or "ngc2py convert failed",
                conv.rc if conv.rc else 99,
                conv.stderr,
            )
        if mode == "convert":
            return golden.run_in(s, lambda: _run_script(module, args), cache, timeout)
        return _run([sys.executable, str(module), *args], s, timeout)


def _convert_options(args: List[str]) -> List[str]:
    """The options of a run that ``ngc2py convert`` takes too."""
    # the ini file's SUBROUTINE_PATH matters at compile time too
    options = []
    if "-i" in args and args.index("-i") + 1 < len(args):
        options = ["-i", args[args.index("-i") + 1]]
    # and block delete, where /-lines carry O-words (compiler.py)
    if args.count("-b") % 2:
        options.append("-b")
    return options


def _run_script(module: Path, args: List[str]):
    """``python MODULE ARGS`` in this process: the file run as ``__main__``
    with its own ``sys.argv``; its exit status is the SystemExit it raises."""
    saved = sys.argv
    sys.argv = [str(module), *args]
    try:
        runpy.run_path(str(module), run_name="__main__")
    finally:
        sys.argv = saved
    return 0


def golden_cache() -> str:
    """The compile cache in-process runs share (ngc2py.golden.run's)."""
    from ngc2py.cache import cache_dir

    return cache_dir()


def run_ngc2py_inprocess(
    program: Union[str, Path],
    args: Iterable[str] = (),
    *,
    text: Optional[str] = None,
    timeout: float = DEFAULT_TIMEOUT,
) -> Result:
    """``ngc2py run`` without a new interpreter: ``ngc2py.cli.main`` called in
    this process in a scratch copy of the folder, as ``ngc2py golden`` runs a
    user's program (:func:`ngc2py.golden.run`). Saves the interpreter
    start-up and imports (most of the cost of a small program); the
    subprocess runner stays the reference because it is exactly what a user
    runs. The timeout uses SIGALRM, so it applies in the main thread only
    (pytest and pytest-xdist workers run tests there).
    """
    return golden.run(Path(program), list(args), text=text, timeout=timeout)


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
    return golden.compare(expected, actual, SIDES)


def stdout_diff(expected: bytes, actual: bytes, context: int = 3, limit: int = 40) -> str:
    return golden.unified_diff(expected, actual, SIDES, context, limit)


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
    return golden.load(program)


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
