"""One raw line -> the normalised text rs274's readers work on.

rs274 never tokenises: its readers walk a character array that
``close_and_downcase`` has prepared by dropping blanks and lower-casing
everything outside comments.  Quirks of the language (``G1 X 1 . 5`` is
``X1.5``, ``#<my name>`` is ``#<myname>``, a ``(`` inside ``#<...>`` opens a
comment) all follow from that, so ngc2py reproduces the same preparation
rather than a token grammar.
"""

from __future__ import annotations

import re

from ngc2py.records import Frozen

# typing is for the checker only: importing it costs a conversion 5 ms
TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import List, Optional

#: rs274's messages for badly formed comments.
NESTED_COMMENT = "Nested comment found"
UNCLOSED_COMMENT = "Unclosed comment found"

#: Characters dropped outside comments (C: blank, tab, carriage return).
_BLANKS = " \t\r"


#: C's tolower in the "C" locale: A-Z only.
_LOWER = str.maketrans("ABCDEFGHIJKLMNOPQRSTUVWXYZ", "abcdefghijklmnopqrstuvwxyz")

#: Outside comments: a run of ordinary text, a whole ``(...)`` comment (or
#: an unclosed one), or everything from ``;`` on.
_SEGMENT = re.compile(r"[^(;]+|\([^)]*\)?|;.*", re.S)


class Normalised(Frozen):
    """A line as rs274's readers see it.

    ``text`` is the prepared line; ``columns[i]`` is the column in the raw line
    of ``text[i]`` (for error carets).  ``error`` is set when the comment
    structure is broken; rs274 then reads nothing from the line.
    """

    __slots__ = ("text", "columns", "error")

    def __init__(
        self, text: str, columns: List[int], error: Optional[str] = None
    ) -> None:
        object.__setattr__(self, "text", text)
        object.__setattr__(self, "columns", columns)
        object.__setattr__(self, "error", error)


def normalise(raw: str) -> Normalised:
    """Apply rs274's close_and_downcase to one line (no trailing newline)."""
    out: List[str] = []
    columns: List[int] = []
    for segment in _SEGMENT.finditer(raw):
        text, start = segment.group(), segment.start()
        if text[0] == "(":
            # Comment text is kept verbatim: case and blanks matter to MSG etc.
            out.append(text)
            columns.extend(range(start, segment.end()))
            if "(" in text[1:]:
                return Normalised("".join(out), columns, NESTED_COMMENT)
            if not text.endswith(")"):
                return Normalised("".join(out), columns, UNCLOSED_COMMENT)
        elif text[0] == ";":
            out.append(text)
            columns.extend(range(start, segment.end()))
        else:
            kept = [i for i, char in enumerate(text, start) if char not in _BLANKS]
            out.append("".join(raw[i] for i in kept).translate(_LOWER))
            columns.extend(kept)
    return Normalised("".join(out), columns)
