"""Which word of a G-code line an error is about: the column for a caret.

Two sources, best first:

* the generated code: when a word's value fails to evaluate (a division by
  zero in ``X[1/0]``), the traceback's position inside the generated line
  (Python 3.11+ ``co_positions``) falls in that word's keyword argument
  (``x=div(1.0, 0.0)``), which names the word's letter;
* the message: rs274 names the word in many of its messages ("F word
  missing ...", "Bad character 'u' used", "Unknown g code used").

The letter is then found in the line's text, outside comments. No column
(None) when neither says anything: the report then shows no caret.
"""

from __future__ import annotations

import linecache
import re
from types import TracebackType

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Optional

_KEYWORD = re.compile(r"\b([a-z])=(?!=)")
_MESSAGE_PATTERNS = (
    (re.compile(r"Bad character '(.)' used"), None),
    (re.compile(r"\b([A-Za-z]) word", re.I), None),
    (re.compile(r"^(?!Two)(?:Unknown|Bad|Illegal).*\b([gmGM]) ?codes?\b"), None),
    (re.compile(r"\b(?:do|use|with) ([gmGM])\d"), None),
    (re.compile(r"\b([A-Z])-?axis"), None),
)


def column(error: BaseException, text: str) -> Optional[int]:
    """The 1-based column in ``text`` (the failing line) of the word the
    error is about, or None."""
    letter = _letter_from_traceback(error.__traceback__) or _letter_from_message(
        getattr(error, "message", str(error))
    )
    if letter is None:
        return None
    return find_word(text, letter)


def find_word(text: str, letter: str) -> Optional[int]:
    """The 1-based column of the first word starting with ``letter`` in
    ``text`` (case-insensitive), skipping ``(...)`` and ``;`` comments."""
    letter = letter.lower()
    depth = 0
    for index, char in enumerate(text):
        if char == "(":
            depth += 1
        elif char == ")" and depth:
            depth -= 1
        elif depth == 0 and char == ";":
            return None
        elif depth == 0 and char.lower() == letter:
            # a letter inside a name (#<x>) or function (ATAN) is not a word
            before = text[:index]
            if before.count("<") > before.count(">"):
                continue
            if index and text[index - 1].isalpha():
                continue
            if index + 1 < len(text) and text[index + 1].isalpha():
                continue
            return index + 1
    return None


def _letter_from_message(message: str) -> Optional[str]:
    for pattern, _ in _MESSAGE_PATTERNS:
        found = pattern.search(message)
        if found:
            return found.group(1)
    return None


def _letter_from_traceback(tb: Optional[TracebackType]) -> Optional[str]:
    """The keyword letter being evaluated in the innermost generated frame."""
    innermost = None
    while tb is not None:
        if "__ngc__" in tb.tb_frame.f_globals:
            innermost = tb
        tb = tb.tb_next
    if innermost is None:
        return None
    code = innermost.tb_frame.f_code
    positions = getattr(code, "co_positions", None)
    if positions is None:  # before Python 3.11: no columns
        return None
    try:
        line, _end, col, _end_col = list(positions())[innermost.tb_lasti // 2]
    except (IndexError, ValueError):
        return None
    if line is None or col is None:
        return None
    source = linecache.getline(code.co_filename, line)
    if not source:
        return None
    head = source[:col]
    if head.rstrip().endswith("m.block(") or "m.block(" in source[col : col + 8]:
        return None  # the failure is the block itself, not one word
    found = list(_KEYWORD.finditer(head))
    return found[-1].group(1) if found else None
