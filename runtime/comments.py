"""Comments and active comments: MSG, DEBUG, PRINT, LOG*, ABORT, PY*.

Facts measured against rs274 (LinuxCNC 2.9) that shape this module:

* Only the exact prefixes ``msg,`` ``debug,`` ``print,`` ``log,``
  ``logopen,`` ``logappend,`` ``abort,`` (any case, after leading white
  space), ``py,`` ``pyrun,`` ``pyreload`` (runtime.py_comments) and the
  whole comment ``logclose`` are active; ``(MSG , x)`` or
  ``(PROBEOPEN f)`` are plain comments. A plain comment's text drops the
  leading white space only.
* DEBUG, PRINT, LOG and ABORT expand parameters in their text: ``#123`` and
  ``#<name>`` (white space inside the brackets removed, lower-cased) become
  the value printed ``%f``-style, or ``######`` when the parameter is unset,
  the number is outside 0..5601, or the text would be 30 characters or
  more. Values within 0.0001 of zero print as zero (no ``-0.000000``). A
  ``#`` followed by anything else is kept.
* The last comment of a line is the one acted on, and only when its text is
  not empty: ``()`` prints nothing and silences an earlier comment on the
  line; ``( )`` prints ``COMMENT("")``.  O-word lines act on no comment.
* ``%d``, ``%f`` and ``%.Nf`` (N one digit) in the text are not printed; they
  set the number of decimals for the parameters after them (``%d`` means 0,
  ``%f`` 4). Any
  other ``%.`` loses its ``%``; any other ``%`` is kept.
* DEBUG prints only while ``#5599`` is positive. PRINT writes the line to
  stdout (the same stream as the trace), not to stderr; here it goes to the
  canon's ``print_text``, which ``TraceCanon`` writes to the trace stream. LOG* are canon
  calls (the stand-alone rs274 prints them in the trace, opens no file).
  ABORT fails with the expanded text as the error message.
* An unterminated ``#<name`` or a trailing ``#`` makes rs274 print whatever
  bytes follow in its buffer; that cannot be reproduced, so the expansion
  simply stops there.
"""

from __future__ import annotations

from collections import namedtuple
from functools import lru_cache

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Optional, Tuple, Union

from runtime.errors import GCodeError
from runtime.ops import TOLERANCE_EQUAL
from runtime.params import MAX_PARAMETERS
from runtime.varfile import DEBUG_SWITCH

#: The kind of ``()``: a comment rs274 does not act on.
SILENT = "none"

#: Comment kinds whose text has parameters expanded.
EXPANDING_KINDS = frozenset({"debug", "print", "log", "abort"})

#: Active-comment prefixes in the order rs274 tries them: (prefix, kind).
_PREFIXES = (
    ("msg,", "msg"),
    ("debug,", "debug"),
    ("print,", "print"),
    ("log,", "log"),
    ("logopen,", "logopen"),
    ("logappend,", "logappend"),
    ("py,", "py"),
    ("pyrun,", "pyrun"),
    ("pyreload", "pyreload"),  # no comma: any comment starting so
    ("abort,", "abort"),
)

#: What rs274 prints for a value it cannot (or will not) show.
UNPRINTABLE = "######"
#: rs274's buffer for one printed value: the text must be shorter than this.
_VALUE_BUFFER = 30
#: Decimals of ``%lf``, the format until a ``%d``/``%.Nf`` directive.
_DEFAULT_DECIMALS = 6
#: rs274 only looks at the first 256 characters to classify a comment.
_CLASSIFY_LENGTH = 256
#: C's isspace.
_C_SPACE = " \t\n\v\f\r"


class Name(namedtuple("Name", "name")):
    """``#<name>`` inside a comment (normalised: lower case, no white space)."""

    __slots__ = ()


class Decimals(namedtuple("Decimals", "places")):
    """A ``%d`` (0) or ``%.Nf`` (N) directive: decimals for later values."""

    __slots__ = ()


if TYPE_CHECKING:
    Part = Union[str, int, Name, Decimals]


class Comment(namedtuple("Comment", "kind text parts values")):
    """The comment rs274 acts on for a line.

    ``text`` is what follows the prefix (``msg,`` etc.), the file name for
    logopen/logappend, or the whole comment (leading white space removed) for
    plain ones. ``parts`` is ``text`` split by :func:`split_parts`; leave it
    out and it is computed (and cached) from ``text``. ``values`` maps names
    of local parameters the text expands to their values, for names the
    generated code keeps in Python variables (ngc2py.fastlocals); any other
    name is looked up in the machine's stores as rs274 does.
    """

    __slots__ = ()

    def __new__(
        cls,
        kind: str,
        text: str,
        parts: Optional[Tuple[Part, ...]] = None,
        values: Optional[dict] = None,
    ):
        if parts is None and kind in EXPANDING_KINDS:
            parts = split_parts(text)
        return super().__new__(cls, kind, text, parts, values)


_new_comment = tuple.__new__  # Comment's fields, without __new__'s Python frame


def _expanding(kind: str, text: str, values: dict) -> Comment:
    return _new_comment(Comment, (kind, text, split_parts(text), values or None))


@lru_cache(maxsize=1024)
def _fixed(kind: str, text: str) -> Comment:
    """The (immutable) Comment of a kind that expands nothing."""
    return Comment(kind, text)


class CommentLines:
    """A line with one comment and nothing else, as the generated code
    writes it: ``m.comment(3, "text")``, ``m.debug(5, "x is #<x>", x=x)``.

    Each is exactly ``block(line, comment=...)`` (the comment is the block's
    first action; the block then publishes the position as any other does,
    and a G7x profile's reader, which replaces ``block``, sees it too). Line
    and text are positional-only, so any name can be a keyword: the values
    of the names the text expands that are Python variables of the caller
    (``Comment.values``); the other names are read from the stores.
    """

    __slots__ = ()

    def comment(self, line: int, text: str, /) -> None:
        """``(text)``: COMMENT(text)."""
        self.block(line, comment=text)

    def message(self, line: int, text: str, /) -> None:
        """``(MSG,text)``: MESSAGE(text)."""
        self.block(line, comment=_fixed("msg", text))

    def debug(self, line: int, text: str, /, **values: float) -> None:
        """``(DEBUG,text)``: MESSAGE(text expanded) while #5599 is positive."""
        self.block(line, comment=_expanding("debug", text, values))

    def print(self, line: int, text: str, /, **values: float) -> None:
        """``(PRINT,text)``: the expanded text on the trace's stream."""
        self.block(line, comment=_expanding("print", text, values))

    def log(self, line: int, text: str, /, **values: float) -> None:
        """``(LOG,text)``: LOG(text expanded)."""
        self.block(line, comment=_expanding("log", text, values))

    def abort(self, line: int, text: str, /, **values: float) -> None:
        """``(ABORT,text)``: the program stops here, failing with the
        expanded text as its error message. Never returns."""
        self.block(line, comment=_expanding("abort", text, values))

    def logopen(self, line: int, path: str, /) -> None:
        """``(LOGOPEN,path)``: LOGOPEN(path)."""
        self.block(line, comment=_fixed("logopen", path))

    def logappend(self, line: int, path: str, /) -> None:
        """``(LOGAPPEND,path)``: LOGAPPEND(path)."""
        self.block(line, comment=_fixed("logappend", path))

    def logclose(self, line: int, /) -> None:
        """``(LOGCLOSE)``: LOGCLOSE()."""
        self.block(line, comment=_fixed("logclose", ""))

    def py(self, line: int, text: str, /) -> None:
        """``(PY,text)``: runtime.py_comments reads it; nothing is run."""
        self.block(line, comment=_fixed("py", text))

    def pyrun(self, line: int, text: str, /) -> None:
        """``(PYRUN,text)``: rs274 runs embedded Python; ngc2py does not."""
        self.block(line, comment=_fixed("pyrun", text))

    def pyreload(self, line: int, text: str, /) -> None:
        """``(PYRELOAD...)``: as PYRUN."""
        self.block(line, comment=_fixed("pyreload", text))


#: The CommentLines method of each kind of comment (codegen writes these).
LINE_METHODS = {
    "plain": "comment",
    "msg": "message",
    "debug": "debug",
    "print": "print",
    "log": "log",
    "abort": "abort",
    "logopen": "logopen",
    "logappend": "logappend",
    "logclose": "logclose",
    "py": "py",
    "pyrun": "pyrun",
    "pyreload": "pyreload",
}


def classify(comment: str) -> Comment:
    """The :class:`Comment` for the text between ``(`` and ``)`` (or after ``;``)."""
    if not comment:
        # rs274 keeps only the last comment of a line in a buffer and acts
        # on it when the buffer is not empty: ``()`` does nothing, and as the
        # last comment it silences an earlier one (``(foo) ()``).  ``( )`` is
        # not empty and prints COMMENT("").
        return Comment(SILENT, "")
    start = len(comment) - len(comment.lstrip(_C_SPACE))
    body = comment[start:]
    lowered = ascii_lower(body[:_CLASSIFY_LENGTH])
    for prefix, kind in _PREFIXES:
        if lowered.startswith(prefix):
            return Comment(kind, body[len(prefix) :])
    if lowered == "logclose":
        return Comment("logclose", "")
    return Comment("plain", body)


@lru_cache(maxsize=1024)
def split_parts(text: str) -> Tuple[Part, ...]:
    """``text`` as literal strings, parameter references and directives."""
    parts = []
    literal = []
    i, end = 0, len(text)

    def flush():
        if literal:
            parts.append("".join(literal))
            literal.clear()

    while i < end:
        char = text[i]
        nxt = text[i + 1] if i + 1 < end else ""
        if char == "#":
            if nxt.isdigit() and nxt.isascii():
                j = i + 1
                while j < end and text[j].isdigit() and text[j].isascii():
                    j += 1
                flush()
                parts.append(_c_atoi(text[i + 1 : j]))
                i = j
            elif nxt == "<":
                close = _name_end(text, i + 2)
                if close is None:
                    break  # unterminated: rs274 prints buffer garbage
                flush()
                parts.append(Name(_normalise(text[i + 2 : close])))
                i = close + 1
            elif nxt == "":
                break  # a trailing '#': rs274 prints buffer garbage
            else:
                literal.append("#")
                i += 1
        elif char == "%" and nxt in ("d", "f"):
            flush()
            parts.append(Decimals(0 if nxt == "d" else 4))
            i += 2
        elif char == "%" and nxt == ".":
            digit, f = text[i + 2 : i + 3], text[i + 3 : i + 4]
            if digit.isdigit() and digit.isascii() and f == "f":
                flush()
                parts.append(Decimals(int(digit)))
                i += 4
            else:
                i += 1  # rs274 drops the '%' and goes on from the '.'
        else:
            literal.append(char)
            i += 1
    flush()
    return tuple(parts)


def _c_atoi(digits: str) -> int:
    """glibc's ``atoi``: ``strtol`` clamped to a C long, then truncated to an int."""
    value = min(int(digits), 2**63 - 1)
    return (value + 2**31) % 2**32 - 2**31


def _name_end(text: str, start: int) -> Optional[int]:
    """Index of the ``>`` closing a name that starts at ``start``, if any."""
    for j in range(start, len(text)):
        if text[j] == ">":
            return j
        if text[j] == ")":
            return None
    return None


def _normalise(name: str) -> str:
    return ascii_lower("".join(c for c in name if c not in _C_SPACE))


def ascii_lower(text: str) -> str:
    """C's tolower in the "C" locale: only A-Z change."""
    return text.translate(_ASCII_LOWER)


_ASCII_LOWER = str.maketrans("ABCDEFGHIJKLMNOPQRSTUVWXYZ", "abcdefghijklmnopqrstuvwxyz")


# --------------------------------------------------------------------------
# Execution
# --------------------------------------------------------------------------


def execute_comment(machine, comment: Union[Comment, str, Tuple[str, str]]) -> None:
    """Do what rs274 does with the comment of a block (its first action).

    ``comment`` is a :class:`Comment`, the text of a plain comment, or
    ``(kind, text)`` (what generated code writes for a line with words)."""
    canon = machine.canon
    if type(comment) is str:
        canon.comment(comment)
        return
    if type(comment) is tuple:
        comment = Comment(*comment)
    kind = comment.kind
    if kind == SILENT:
        return
    if kind == "msg":
        canon.message(comment.text)
    elif kind == "debug":
        if machine.params.get_internal(DEBUG_SWITCH) > 0.0:
            canon.message(expand(machine, comment.parts, comment.values))
    elif kind == "print":
        canon.print_text(expand(machine, comment.parts, comment.values))
    elif kind == "log":
        canon.log(expand(machine, comment.parts, comment.values))
    elif kind == "logopen":
        canon.logopen(comment.text)
    elif kind == "logappend":
        canon.logappend(comment.text)
    elif kind == "logclose":
        canon.logclose()
    elif kind == "abort":
        raise GCodeError(expand(machine, comment.parts, comment.values))
    elif kind == "py":
        # imported here: its ast tables cost every run's start-up otherwise
        from runtime.py_comments import run_py_comment

        run_py_comment(machine, comment.text)
    elif kind in ("pyrun", "pyreload"):
        pass  # rs274 ignores their errors; ngc2py runs no Python (runtime.py_comments)
    else:  # plain, and file commands rs274 does not act on (PROBEOPEN...)
        canon.comment(comment.text)


def expand(machine, parts: Tuple[Part, ...], values: Optional[dict] = None) -> str:
    """The text of ``parts`` with parameter values, as rs274 prints it;
    ``values``: those of names held in the caller's Python variables."""
    out = []
    decimals = _DEFAULT_DECIMALS
    for part in parts:
        if isinstance(part, str):
            out.append(part)
        elif isinstance(part, Decimals):
            decimals = part.places
        else:
            if values is not None and type(part) is Name and part.name in values:
                value = values[part.name]
            else:
                value = _lookup(machine, part)
            out.append(format_value(value, decimals))
    return "".join(out)


def _lookup(machine, part: Union[int, Name]) -> Optional[float]:
    """A parameter's value for printing, or None when rs274 prints ``######``."""
    if isinstance(part, int):
        if 0 <= part < MAX_PARAMETERS:
            return machine.params.get_internal(part)
        return None
    store = machine.globals if part.name.startswith("_") else machine.locals
    try:
        return store[part.name]
    except GCodeError:
        return None


def format_value(value: Optional[float], decimals: int = _DEFAULT_DECIMALS) -> str:
    """One value as DEBUG/PRINT/LOG/ABORT print it."""
    if value is None:
        return UNPRINTABLE
    if abs(value) < TOLERANCE_EQUAL:
        value = 0.0
    text = "%.*f" % (decimals, value)
    return text if len(text) < _VALUE_BUFFER else UNPRINTABLE


__all__ = [
    "Comment",
    "CommentLines",
    "LINE_METHODS",
    "Name",
    "Decimals",
    "EXPANDING_KINDS",
    "classify",
    "split_parts",
    "execute_comment",
    "expand",
    "format_value",
]
