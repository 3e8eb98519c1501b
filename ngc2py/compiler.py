"""Glue: G-code file -> generated Python module text.

parse (parser.py) -> pair O-words (structure.py) -> find external
subroutines -> generate (codegen.py). Only I/O problems with the main file
fail here (:class:`CompileError`); everything else in the G-code becomes
code that fails at run time where rs274 would.

External subroutines: a call to a name the file does not define makes rs274
open ``<name>.ngc``, looking first in its program prefix (the current
directory when run stand-alone -- measured: not the program's folder) and
then in each SUBROUTINE_PATH directory of the ini file (see
:func:`subroutine_dirs`). The file is compiled
into the same module, keeping its own file name for error reports.
"""

from __future__ import annotations

import os

TYPE_CHECKING = (
    False  # `ngc2py run` of a cached program imports this module: keep it light
)
if TYPE_CHECKING:
    from typing import List, Optional, Tuple

    from ngc2py import structure as st

# The compiler's stages (structure, codegen) are imported where they are
# used: `ngc2py run` of a cached program needs this module's errors only,
# and importing the whole compiler cost every such run a visible moment.


class CompileError(Exception):
    """The main file cannot be compiled at all (missing, unreadable...)."""


class OpenError(CompileError):
    """The main file cannot be read. The text says why, for ``convert``;
    ``rs274_message`` is what rs274 reports when it cannot open it (a
    directory opens, but reads as an empty file)."""

    def __init__(self, text: str, rs274_message: str):
        super().__init__(text)
        self.rs274_message = rs274_message


def open_failure(path: str, error: OSError) -> OpenError:
    """The :class:`OpenError` for ``error`` raised reading ``path``."""
    from ngc2py import structure as st

    if isinstance(error, IsADirectoryError):
        return OpenError("%s: is a directory" % path, st.EOF_NO_PERCENT)
    unable = "Unable to open file <%s>" % path
    if isinstance(error, FileNotFoundError):
        return OpenError(unable, unable)
    return OpenError("%s: cannot read: %s" % (path, error.strerror or error), unable)


class Compiled:
    """A generated module and the files its text depends on.

    ``probes`` lists every external-subroutine path looked at, with whether
    it existed: the cache must be invalidated when any of them changes.
    """

    __slots__ = ("text", "probes")

    def __init__(self, text: str, probes: Optional[List[Tuple[str, bool]]] = None):
        self.text = text
        self.probes = [] if probes is None else probes


def subroutine_dirs(ini: Optional[str]) -> List[str]:
    """Where rs274 looks for ``<name>.ngc``, in its order: the program
    prefix (the ini's [DISPLAY]PROGRAM_PREFIX, else the current directory,
    written "" so that paths found there stay relative to it), then the
    ini's [RS274NGC]SUBROUTINE_PATH directories.

    Relative, not the current directory's absolute path: a module compiled
    in one copy of a folder is then the same module in every copy (the
    compile cache serves golden checks' scratch copies), and its error
    reports name a subroutine file as the user would, ``probe.ngc``."""
    if not ini:
        return [""]
    from runtime.inifile import load_ini

    settings = load_ini(ini)
    return [settings.program_prefix or "", *settings.subroutine_path]


def _parse(path: str, main_percent: Optional[bool] = None):
    from ngc2py import parser

    try:
        return parser.parse_file(path, runs=True, main_percent=main_percent)
    except OSError as error:
        raise open_failure(path, error) from None


def _program(parsed) -> st.Program:
    from ngc2py import structure as st

    return st.build(parsed.file, list(parsed.lines), parsed.demarcated)


def deletes_structure(lines) -> bool:
    """Does a block-deleted line of ``lines`` carry an O-word (an M98 or
    M99 of a Fanuc-style file included)? With block delete on rs274 reads
    such a line as an empty one (read_text), so the file's subroutines and
    control flow differ with ``-b``: the nested form, pairing O-words when
    it compiles, is written for one setting or the other."""
    for line in lines:
        if line.block_delete and (
            line.oword is not None
            or line.oword_unread
            or getattr(line, "fanuc_alt", None) is not None
        ):
            return True
    return False


def block_deleted(parsed):
    """``parsed`` as rs274 reads it with block delete on: each line that
    starts with ``/`` empty (its number and text kept for reports)."""
    from ngc2py.nodes import Line
    from ngc2py.records import replace

    lines = [
        Line(line.number, line.text, line.file) if line.block_delete else line
        for line in parsed.lines
    ]
    return replace(parsed, lines=lines)


class _SubFile:
    """A subroutine file rs274 may open: its lines, read once."""

    def __init__(self, path: str, parsed):
        self.path = path
        self.lines = list(parsed.lines)
        self.demarcated = parsed.demarcated
        last = None
        for line in self.lines:
            last = line
        from ngc2py.rowrun import RowRun

        if type(last) is RowRun:
            last = last.final()
        self.last = last
        #: (line searched from, name) -> what a call runs
        self.found: dict = {}

    def seek(self, after: int, name: str, fanuc: bool = False) -> st.Sub:
        """What rs274 finds seeking ``o<name> sub`` (``fanuc``: the
        ``O<name>`` of an M98) from line ``after`` of this file."""
        from ngc2py import structure as st

        key = (after, name, fanuc)
        if key not in self.found:
            seek = st.seek_fanuc if fanuc else st.seek_result
            self.found[key] = seek(
                self.path, self.lines, self.last, after, name, self.demarcated
            )
        return self.found[key]


def _externals(
    program: st.Program,
    dirs: List[str],
    main_percent: bool = False,
    block_delete: bool = False,
) -> Tuple[List[Tuple[str, bool]], bool]:
    """Find and compile the external subroutines ``program`` calls, and
    those they call in turn; return the paths probed, and whether a file
    read is compiled for ``block_delete`` (see :func:`deletes_structure`).

    rs274 resolves ``o<name> call`` when it runs: a name already defined
    (its ``sub`` line read, in any file) is called; otherwise it opens
    ``<name>.ngc`` on the subroutine path and skips from its top to
    ``o<name> sub``; without such a file it skips forward from the call in
    the file it is reading. What the two searches find is worked out here,
    per call site (``Call.found``); the machine keeps what is defined
    (``Machine.call_found``). A subroutine found in a file runs from its
    ``sub`` line to the first ``endsub`` or ``return`` it runs
    (:func:`structure.entry_sub`), and defines the names it finds in turn.
    """
    from ngc2py import structure as st

    probes: List[Tuple[str, bool]] = []
    dependent = []  # the files compiled for one block delete setting
    files: dict = {}  # path -> _SubFile, or None when it cannot be read
    by_file: dict = {}  # name -> what <name>.ngc gives (None: no such file)
    pending: List[st.Sub] = []
    seen: set = set()

    def take(sub: st.Sub) -> st.Sub:
        if id(sub) not in seen:
            seen.add(id(sub))
            program.externals.append(sub)
            pending.append(sub)
        return sub

    def from_file(name: str, fanuc: bool = False) -> Optional[st.Sub]:
        if (name, fanuc) not in by_file:
            by_file[name, fanuc] = None
            for folder in dirs:
                path = os.path.join(folder, name + ".ngc")
                found = os.path.isfile(path)
                probes.append((path, found))
                if not found:
                    continue
                if path not in files:
                    try:
                        parsed = _parse(path, main_percent)
                        if deletes_structure(parsed.lines):
                            dependent.append(path)
                            if block_delete:
                                parsed = block_deleted(parsed)
                        files[path] = _SubFile(path, parsed)
                    except CompileError:
                        files[path] = None
                if files[path] is not None:
                    by_file[name, fanuc] = take(files[path].seek(0, name, fanuc))
                break
        return by_file[name, fanuc]

    main_found = {}
    for name in st.called_names(program):
        sub = from_file(name)
        if sub is not None:
            main_found[name] = sub
    program.found = main_found
    for stmt in st.walk(program.body):
        # M98 P<n>: rs274 opens <n>.ngc before it reads ahead in the file
        if isinstance(stmt, st.FanucCall) and isinstance(stmt.line.oword.name, str):
            stmt.found = from_file(stmt.line.oword.name, fanuc=True)
    while pending:
        sub = pending.pop(0)
        here = files.get(sub.line.file)
        for stmt in st.walk(sub.body):
            fanuc = isinstance(stmt, st.FanucCall)
            if fanuc and isinstance(stmt.line.oword.name, str):
                name = stmt.line.oword.name
            elif isinstance(stmt, st.Call) and isinstance(stmt.name, str):
                name = stmt.name
            else:
                continue
            found = from_file(name, fanuc)
            if found is None and here is not None:
                # else rs274 reads ahead in the file the call is in
                found = take(here.seek(stmt.line.number, name, fanuc))
            stmt.found = found
    return probes, bool(dependent)


def _compile(
    parsed,
    name: str,
    ini: Optional[str],
    block_delete: bool = False,
    pack: bool = True,
) -> Compiled:
    from ngc2py import codegen
    from ngc2py import structure as st

    from ngc2py import lineflow

    program = _program(parsed)
    flat = lineflow.flat_program(program, list(parsed.lines), parsed.demarcated)
    # the line-by-line form follows block delete as it runs; the nested
    # form needs it when pairing O-words
    dependent = flat is None and deletes_structure(parsed.lines)
    if dependent and block_delete:
        parsed = block_deleted(parsed)
        program = _program(parsed)
        flat = lineflow.flat_program(program, list(parsed.lines), parsed.demarcated)
    if flat is not None:
        program = flat  # its O-words do not nest: written line by line
    probes, subs_dependent = _externals(
        program, subroutine_dirs(ini), parsed.demarcated, block_delete
    )
    if dependent or subs_dependent:
        program.block_delete = block_delete
    st.resolve_calls(program)
    opening = next((line for line in parsed.lines if line.percent), None)
    generate = codegen.generate if flat is None else lineflow.generate
    return Compiled(generate(program, name, opening, pack), probes)


def compile_program(
    path: str,
    ini: Optional[str] = None,
    block_delete: bool = False,
    pack: bool = True,
) -> Compiled:
    """Compile the G-code file ``path``; see :class:`Compiled`.
    ``block_delete``: for rs274's ``-b``, which the module of a file whose
    block-deleted lines carry O-words is written for (it refuses to run
    with the other setting); any other module runs with either. ``pack``:
    a large file's text goes into the module compressed (the cache's
    modules, never tokenized, take it as it is: codegen.plain_literal)."""
    return _compile(_parse(path), os.path.basename(path), ini, block_delete, pack)


def compile_file(
    path: str, ini: Optional[str] = None, block_delete: bool = False
) -> str:
    """The generated module text for the G-code file ``path``."""
    return compile_program(path, ini, block_delete).text


def compile_text(
    text: str,
    file: str = "program.ngc",
    ini: Optional[str] = None,
    runs: bool = True,
    block_delete: bool = False,
) -> str:
    """The generated module text for G-code ``text`` named ``file``
    (``runs=False``: every line read on its own, not by the parser's fast
    lane for CAM rows -- the same module, more slowly)."""
    from ngc2py import parser

    parsed = parser.parse_text(text, file, runs=runs)
    return _compile(parsed, os.path.basename(file), ini, block_delete).text
