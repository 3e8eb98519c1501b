"""Errors raised by generated programs, and where in the G-code they happened.

A GCodeError carries rs274's message text. Where it happened (file, line,
subroutine call stack) is worked out when the error leaves the program, by
mapping the traceback's frames in generated modules back to G-code lines
through each module's ``__ngc__`` :class:`SourceMap` -- the way Jinja maps
template tracebacks, so the hot path pays nothing for it.
"""

from __future__ import annotations

import bisect
import sys
from types import TracebackType

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import List, Optional, Sequence, Tuple, Union


class GCodeError(Exception):
    """An error rs274 would report; ``message`` is rs274's exact wording.

    ``location`` is set only when rs274 names a line other than the one
    being executed (e.g. the last line of a file searched for a subroutine);
    otherwise the location comes from the traceback.
    """

    def __init__(self, message: str, location: Optional["Location"] = None):
        super().__init__(message)
        self.message = message
        self.location = location


class Location:
    """A G-code position: file, 1-based line and the line's text."""

    __slots__ = ("file", "line", "_text", "_source")

    def __init__(self, file: str, line: int, text: str):
        self.file, self.line, self._text, self._source = file, line, text, None

    @classmethod
    def of(cls, source: "SourceMap", index: int, line: int) -> "Location":
        """Line ``line`` of ``source``'s file ``index``, its text read only
        when asked for: most locations looked up only name the line (the
        flat file's comments), and a large file's text is compressed."""
        location = cls(source.files[index], line, "")
        location._source = source, index
        return location

    @property
    def text(self) -> str:
        if self._source is not None:
            source, index = self._source
            self._text, self._source = source.text(index, self.line), None
        return self._text

    def __reduce__(self):
        return Location, (self.file, self.line, self.text)

    def __eq__(self, other) -> bool:
        return isinstance(other, Location) and (
            (self.file, self.line, self.text) == (other.file, other.line, other.text)
        )

    def __hash__(self) -> int:
        return hash((self.file, self.line, self.text))

    def __repr__(self) -> str:
        return "Location(%r, %d, %r)" % (self.file, self.line, self.text)

    def __str__(self) -> str:
        # Line 0: the file itself (it could not be opened or read).
        return "%s:%d" % (self.file, self.line) if self.line else self.file


class SourceMap:
    """Python line -> G-code (file, line) for one generated module.

    ``lines`` is the code generator's compact encoding: ``;``-separated
    ``py,file,line[,count]`` runs (``count`` consecutive Python lines map to
    consecutive G-code lines). G-code line 0 means the statement runs data
    rows: the row's line number is attached to the error by ``run_rows``.
    ``texts`` holds, per file, the G-code lines joined by newlines (for a
    large file, that text deflated and in base64, as bytes).
    ``subs`` maps every subroutine name defined in the main file to its
    function, so a call to a sub not yet defined can seek it the way rs274
    reads ahead; ``end`` is the main file's last line number and whether
    that line is a closing ``%`` (it decides the message when seeking fails).
    ``open_error`` is set when rs274 already fails while *opening* the main
    file: (its message, the G-code line it names, 0 for none). Such a
    program never starts (see :meth:`opening_error`). ``block_delete`` is
    the setting of rs274's ``-b`` the module was compiled for, where the
    file's block-deleted O-word lines make it matter (None: either).
    """

    def __init__(
        self,
        files: Sequence[str],
        lines: str,
        texts: Sequence[Union[str, bytes]],
        subs: Optional[dict] = None,
        end: Tuple[int, bool] = (0, False),
        open_error: Optional[Tuple[str, int]] = None,
        unskippable: Optional[dict] = None,
        block_delete: Optional[bool] = None,
    ):
        self.files = tuple(files)
        self.block_delete = block_delete
        #: main-file lines rs274 fails on even while skipping: line -> message
        self.unskippable = unskippable or {}
        self.open_error = open_error
        self.subs = dict(subs or {})
        self.end = end
        self._encoded = lines
        self._texts = tuple(texts)
        self._runs: Optional[List[Tuple[int, int, int, int]]] = None
        self._split: dict = {}

    def _decoded(self) -> List[Tuple[int, int, int, int]]:
        # Decoded on first use only: most runs never raise.
        if self._runs is None:
            runs = []
            for part in filter(None, self._encoded.split(";")):
                fields = [int(x) for x in part.split(",")]
                if len(fields) == 3:
                    fields.append(1)
                runs.append(tuple(fields))
            self._runs = runs
        return self._runs

    def lookup(
        self, py_line: int, row_line: Optional[int] = None
    ) -> Optional[Location]:
        """The G-code location of Python line ``py_line``, if it has one."""
        runs = self._decoded()
        index = bisect.bisect_right(runs, (py_line, 1 << 30)) - 1
        if index < 0:
            return None
        start, file, line, count = runs[index]
        if line < 0:  # (a line of the module's own: main calling its chunks)
            return None
        if line == 0:
            if row_line is None:
                return None
            line = row_line
        else:
            line += min(py_line - start, count - 1)
        return Location.of(self, file, line)

    def text(self, file: int, line: int) -> str:
        """The text of G-code ``line`` of file number ``file`` ("" if unknown)."""
        if file not in self._split:
            text = self._texts[file] if file < len(self._texts) else ""
            if isinstance(text, bytes):  # a large file's text, compressed
                import binascii
                import zlib

                text = zlib.decompress(binascii.a2b_base64(text))
                text = text.decode("utf-8", "surrogateescape")
            self._split[file] = text.split("\n") if text else []
        lines = self._split[file]
        return lines[line - 1] if 0 < line <= len(lines) else ""

    def first_line(self) -> str:
        """The main file's first line that is not blank, stripped ("" if
        none), found without unpacking a large file's whole text: every
        program that ends asks (is it a ``%`` file?)."""
        text = self._texts[0] if self._texts else ""
        if isinstance(text, str) and 0 not in self._split:
            # (a large text as it is: its lines up to the first not blank)
            last = self.end[0] if self.end else 0
            at = 0
            for _ in range(last):
                stop = text.find("\n", at)
                line = text[at:] if stop < 0 else text[at:stop]
                if line.strip():
                    return line.strip()
                if stop < 0:
                    break
                at = stop + 1
            return ""
        if isinstance(text, bytes) and 0 not in self._split:
            import binascii
            import zlib

            head = text[: 1 << 12].replace(b"\n", b"")
            head = head[: len(head) // 4 * 4]  # whole base64 groups
            part = zlib.decompressobj().decompress(binascii.a2b_base64(head), 1 << 16)
            complete = part[: part.rfind(b"\n") + 1]  # whole lines only
            for line in complete.decode("utf-8", "surrogateescape").split("\n"):
                if line.strip():
                    return line.strip()
        last = self.end[0] if self.end else 0
        for number in range(1, last + 1):
            line = self.text(0, number).strip()
            if line:
                return line
        return ""

    def opening_error(self) -> Optional[Tuple[str, Location]]:
        """(message, location) of the failure rs274 meets opening the main
        file, or None when it opens fine."""
        if self.open_error is None:
            return None
        message, line = self.open_error
        return message, Location(self.files[0], line, self.text(0, line))

    def other_block_delete(self, block_delete: bool) -> Optional[str]:
        """Why this module cannot run with block delete ``block_delete``
        (compiled for the other setting, see ``block_delete``), or None."""
        if self.block_delete is None or bool(block_delete) == self.block_delete:
            return None
        wanted = "with" if block_delete else "without"
        return (
            "%s: converted for block delete %s, and lines of it that start"
            " with '/' carry O-words, which block delete empties: convert it"
            " %s -b to run it %s -b"
            % (self.files[0], "on" if self.block_delete else "off", wanted, wanted)
        )

    def missing_sub(self, name: str, row_line: Optional[int] = None) -> GCodeError:
        """rs274's error for calling ``name`` when neither a definition nor
        a file ``name.ngc`` exists: it reads to the end of the main file
        looking for the ``sub`` line, and reports that last line.
        ``row_line``: the line being executed, for a call made from a data
        row (a G71 Q word), whose frame has no line of its own."""
        last, closed = self.end
        location = Location(self.files[0], last, self.text(0, last))
        if closed:
            message = "Failed to find sub 'O%s' before EOF" % name
        else:
            calls = g_code_frames_of_stack(row_line)
            line = calls[-1].line if calls else 0
            message = "EOF in file:%s seeking o-word: o<%s> from line: %d" % (
                self.files[0],
                name,
                line,
            )
        return GCodeError(message, location)


def g_code_frames_of_stack(row_line: Optional[int] = None) -> List[Location]:
    """The G-code locations of the generated frames now on the stack
    (``row_line``: the line of a data-row frame, see SourceMap.lookup)."""
    found: List[Location] = []
    frame = sys._getframe(1)
    while frame is not None:
        source_map = frame.f_globals.get("__ngc__")
        if isinstance(source_map, SourceMap):
            location = source_map.lookup(frame.f_lineno, row_line)
            if location is not None:
                found.append(location)
        frame = frame.f_back
    found.reverse()
    return found


def g_code_frames(
    tb: Optional[TracebackType], row_line: Optional[int] = None
) -> List[Location]:
    """The G-code locations of a traceback's generated-module frames,
    outermost first: the last one is where the error happened, the ones
    before it are the O-calls that led there."""
    found: List[Location] = []
    while tb is not None:
        frame = tb.tb_frame
        source_map = frame.f_globals.get("__ngc__")
        if isinstance(source_map, SourceMap):
            location = source_map.lookup(tb.tb_lineno, row_line)
            if location is not None:
                found.append(location)
        tb = tb.tb_next
    return found


def locate(error: BaseException) -> List[Location]:
    """The G-code call stack of ``error`` (see :func:`g_code_frames`); an
    explicit ``location`` replaces the innermost frame."""
    frames = g_code_frames(error.__traceback__, getattr(error, "ngc_row_line", None))
    # An error caught on its way out (runtime.continue_mode) keeps the
    # frames that were still running then.
    frames = list(getattr(error, "ngc_outer_frames", ())) + frames
    explicit = getattr(error, "location", None)
    if explicit is not None:
        frames = frames[:-1] + [explicit] if frames else [explicit]
    return frames


def format_traceback(error: BaseException) -> str:
    """``error``'s traceback with each frame of a generated module shown as
    the G-code it runs (file, line, text) instead of the generated Python;
    other frames as Python shows them. For reports of internal errors."""
    import traceback

    out = ["Traceback (most recent call last; G-code frames as G-code):\n"]
    tb = error.__traceback__
    row_line = getattr(error, "ngc_row_line", None)
    while tb is not None:
        frame = tb.tb_frame
        source_map = frame.f_globals.get("__ngc__")
        location = (
            source_map.lookup(tb.tb_lineno, row_line)
            if isinstance(source_map, SourceMap)
            else None
        )
        if location is not None:
            out.append(
                '  File "%s", line %d (G-code)\n' % (location.file, location.line)
            )
            out.append("    %s\n" % location.text.strip())
        else:
            summary = traceback.extract_tb(tb, limit=1)
            out.extend(traceback.format_list(summary))
        tb = tb.tb_next
    out.extend(traceback.format_exception_only(type(error), error))
    return "".join(out)


def describe(error: BaseException) -> str:
    """One line for a Python exception that escaped a program: what and where."""
    frames = locate(error)
    where = " at %s" % frames[-1] if frames else ""
    return "internal error%s: %s: %s" % (where, type(error).__name__, error)
