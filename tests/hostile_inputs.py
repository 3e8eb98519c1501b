"""Helpers for tests/test_hostile.py: run rs274 and ngc2py on raw bytes in a
scratch folder, compare them, and check a generated module for anything that
is not plain runtime-API code.

Everything runs in a fresh temporary folder with its own ``HOME`` (rs274
keeps tool state in ``$HOME``) and its own ``NGC2PY_CACHE``; program files are
written as *bytes* so invalid UTF-8, NUL bytes and CR-only line endings reach
both tools unchanged.
"""

from __future__ import annotations

import ast
import os
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, Iterable, List, Optional, Sequence, Union

REPO = Path(__file__).resolve().parent.parent

#: Seconds before a run counts as a hang.
TIMEOUT = float(os.environ.get("NGC2PY_HOSTILE_TIMEOUT", "60"))

TRACEBACK = b"Traceback (most recent call last)"


def rs274_exe() -> Optional[str]:
    return shutil.which("rs274")


@dataclass(frozen=True)
class Outcome:
    stdout: bytes
    stderr: bytes
    rc: Optional[int]  # None: timed out

    @property
    def timed_out(self) -> bool:
        return self.rc is None

    @property
    def crashed(self) -> bool:
        """Killed by a signal (segfault, abort...)."""
        return self.rc is not None and self.rc < 0

    @property
    def err(self) -> bytes:
        """The first stderr line that is not ``executing`` (nor blank)."""
        for line in self.stderr.split(b"\n"):
            if line.strip() in (b"", b"executing"):
                continue
            return line.rstrip(b"\r")
        return b""

    def error_lines(self) -> List[bytes]:
        """stderr lines after rs274's ``executing`` banner."""
        lines = self.stderr.split(b"\n")
        if lines and lines[0] == b"executing":
            lines = lines[1:]
        return lines

    def describe(self) -> str:
        return "rc=%r\nstderr=%r\nstdout tail=%r" % (
            self.rc,
            self.stderr[:800],
            self.stdout[-400:],
        )


class Workdir:
    """A scratch folder (``work``) with a private HOME and compile cache."""

    def __init__(self, files: Optional[Dict[str, Union[bytes, str]]] = None):
        self.root = Path(tempfile.mkdtemp(prefix="ngc2py-hostile-"))
        self.work = self.root / "work"
        self.work.mkdir()
        self.home = self.root / "home"
        self.home.mkdir()
        for name, data in (files or {}).items():
            self.write(name, data)

    def write(self, name: str, data: Union[bytes, str]) -> Path:
        path = self.work / name
        if isinstance(data, str):
            data = data.encode("utf-8", "surrogateescape")
        path.write_bytes(data)
        return path

    def env(self, extra: Optional[dict] = None) -> dict:
        env = dict(os.environ)
        env.pop("INI_FILE_NAME", None)
        env["HOME"] = str(self.home)
        env["NGC2PY_CACHE"] = str(self.root / "cache")
        env["PYTHONPATH"] = str(REPO)
        env["PYTHONDONTWRITEBYTECODE"] = "1"
        env["LC_ALL"] = "C"
        env.update(extra or {})
        return env

    def run(
        self,
        cmd: Sequence[str],
        *,
        cwd: Optional[Path] = None,
        env_extra: Optional[dict] = None,
        timeout: float = TIMEOUT,
        user: Optional[int] = None,
    ) -> Outcome:
        kwargs = {}
        if user is not None:
            kwargs["user"] = user
            kwargs["group"] = user
            kwargs["extra_groups"] = []
        try:
            proc = subprocess.run(
                list(cmd),
                cwd=str(cwd or self.work),
                env=self.env(env_extra),
                stdin=subprocess.DEVNULL,
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                timeout=timeout,
                **kwargs,
            )
        except subprocess.TimeoutExpired as exc:
            return Outcome(exc.stdout or b"", exc.stderr or b"", None)
        return Outcome(proc.stdout, proc.stderr, proc.returncode)

    def rs274(self, *args: str, **kw) -> Outcome:
        exe = rs274_exe()
        assert exe is not None, "rs274 is not installed"
        return self.run([exe, "-g", *args], **kw)

    def ngc2py(self, *args: str, **kw) -> Outcome:
        return self.run([sys.executable, "-m", "ngc2py", *args], **kw)

    def cleanup(self) -> None:
        shutil.rmtree(self.root, ignore_errors=True)

    def __enter__(self) -> "Workdir":
        return self

    def __exit__(self, *exc) -> None:
        self.cleanup()


def rs274_run_args(program: str, options: Iterable[str] = ()) -> List[str]:
    """``rs274 -g [options] PROG`` arguments (options first, like getopt wants)."""
    return [*options, program]


def ngc2py_run_args(program: str, options: Iterable[str] = ()) -> List[str]:
    return ["run", program, *options]


def problems_if_unclean(out: Outcome, what: str = "ngc2py") -> List[str]:
    """Why ``out`` is not a clean ending: a traceback, a hang, a crash, an
    exit status other than 0/1, or an "internal error" instead of a G-code
    error."""
    found = []
    if out.timed_out:
        found.append("%s hung (no exit within %ss)" % (what, TIMEOUT))
    if TRACEBACK in out.stderr or TRACEBACK in out.stdout:
        found.append("%s printed a Python traceback" % what)
    if out.rc not in (0, 1, None):
        found.append("%s exit status %r (must be 0 or 1)" % (what, out.rc))
    if b"internal error" in out.stderr:
        found.append("%s reported an internal error: %r" % (what, out.err[:300]))
    return found


def assert_clean(out: Outcome, what: str = "ngc2py") -> None:
    problems = problems_if_unclean(out, what)
    assert not problems, "\n".join(problems) + "\n" + out.describe()


def differences(expected: Outcome, actual: Outcome) -> List[str]:
    """Where ngc2py (``actual``) differs from rs274 (``expected``): stdout
    bytes, exit status, first error line."""
    found = problems_if_unclean(actual)
    if expected.rc != actual.rc:
        found.append("exit status: rs274 %r, ngc2py %r" % (expected.rc, actual.rc))
    if expected.err != actual.err:
        found.append(
            "first error line: rs274 %r, ngc2py %r"
            % (expected.err[:300], actual.err[:300])
        )
    if expected.stdout != actual.stdout:
        found.append("stdout differs:\n" + stdout_diff(expected.stdout, actual.stdout))
    return found


def stdout_diff(a: bytes, b: bytes, limit: int = 30) -> str:
    import difflib

    lines = list(
        difflib.unified_diff(
            a.decode("utf-8", "replace").splitlines(keepends=True),
            b.decode("utf-8", "replace").splitlines(keepends=True),
            "rs274",
            "ngc2py",
            n=2,
        )
    )
    if not lines:
        return "  (trailing bytes differ: %r vs %r)" % (a[-30:], b[-30:])
    return "".join(lines[:limit])


def compare_programs(
    files: Dict[str, Union[bytes, str]],
    program: str = "prog.ngc",
    options: Sequence[str] = (),
    rs274_timeout: float = 20,
) -> List[str]:
    """Run rs274 and ngc2py on ``program`` (in separate, identical scratch
    folders); return the differences. Where rs274 crashes or hangs, ngc2py
    must instead end cleanly with exit status 1 and a message."""
    with Workdir(files) as a, Workdir(files) as b:
        expected = a.rs274(*rs274_run_args(program, options), timeout=rs274_timeout)
        actual = b.ngc2py(*ngc2py_run_args(program, options))
    return judge(expected, actual)


def judge(expected: Outcome, actual: Outcome) -> List[str]:
    """:func:`differences`, except where rs274 crashed or hung: then ngc2py
    must end cleanly with exit status 1 and a message."""
    if expected.crashed or expected.timed_out:
        found = problems_if_unclean(actual)
        if actual.rc != 1 or not actual.err:
            found.append(
                "rs274 %s; ngc2py must do better (exit 1 with a message), got rc=%r err=%r"
                % ("crashed" if expected.crashed else "hung", actual.rc, actual.err)
            )
        return found
    return differences(expected, actual)


# --------------------------------------------------------------------------
# Generated-module safety
# --------------------------------------------------------------------------

#: Builtins a generated module may use.
SAFE_BUILTINS = frozenset(
    ["float", "SystemExit", "__name__", "True", "False", "None", "range", "tuple"]
)


def unsafe_constructs(code: str) -> List[str]:
    """Anything in ``code`` beyond plain runtime-API code.

    * imports only ``from runtime[.x] import names``;
    * every name read is imported, defined or assigned in the module, a
      function parameter, or one of :data:`SAFE_BUILTINS`;
    * no dunder attribute access (``x.__class__``...);
    * every call is to such a name or to an attribute.
    """
    tree = ast.parse(code)
    found: List[str] = []
    known = set(SAFE_BUILTINS)
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.append("import %s" % ", ".join(a.name for a in node.names))
        elif isinstance(node, ast.ImportFrom):
            mod = node.module or ""
            if node.level or not (mod == "runtime" or mod.startswith("runtime.")):
                found.append("from %s import ..." % mod)
            for alias in node.names:
                if alias.name == "*":
                    found.append("star import from %s" % mod)
                known.add(alias.asname or alias.name)
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            known.add(node.name)
        elif isinstance(node, ast.arg):
            known.add(node.arg)
        elif isinstance(node, ast.Name) and isinstance(node.ctx, (ast.Store, ast.Del)):
            known.add(node.id)
        elif isinstance(node, ast.Global) or isinstance(node, ast.Nonlocal):
            found.append("global/nonlocal %s" % node.names)
    for node in ast.walk(tree):
        if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load):
            if node.id not in known:
                found.append("reads unknown name %r (line %d)" % (node.id, node.lineno))
        elif isinstance(node, ast.Attribute):
            if node.attr.startswith("__") and node.attr.endswith("__"):
                found.append("dunder attribute .%s (line %d)" % (node.attr, node.lineno))
        elif isinstance(node, ast.Call):
            func = node.func
            if not isinstance(func, (ast.Name, ast.Attribute)):
                found.append("call of a computed callable (line %d)" % node.lineno)
        elif isinstance(node, (ast.Lambda, ast.Await, ast.Yield, ast.YieldFrom)):
            found.append("%s (line %d)" % (type(node).__name__, node.lineno))
    return found


def module_problems(code: str, payload_markers: Iterable[str] = ()) -> List[str]:
    """(a) compiles, (b) black-stable, (c) no unsafe constructs; also no
    payload marker appears in an identifier or attribute name."""
    import black

    problems: List[str] = []
    try:
        compile(code, "<generated>", "exec")
    except (SyntaxError, ValueError) as error:
        return ["does not compile: %s" % error]
    try:
        formatted = black.format_str(code, mode=black.Mode())
    except Exception as error:  # noqa: BLE001
        problems.append("black cannot format it: %s" % error)
    else:
        if formatted != code:
            problems.append("not black-stable")
    problems += unsafe_constructs(code)
    tree = ast.parse(code)
    names = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
    names |= {n.attr for n in ast.walk(tree) if isinstance(n, ast.Attribute)}
    for marker in payload_markers:
        if marker in names:
            problems.append("payload name %r is code" % marker)
    return problems
