"""Over-long statements laid out as black lays them out, without black.

Nearly every statement the code generator writes too long for one line is
a call: ``m.block(12, G1, x=.., comment=Comment("plain", ".."))``. Black
lays such a call out by a simple rule, applied again to each line it makes:

* split at the brackets of the call that ends the line: the head up to the
  opening bracket, the arguments indented by four, the closing bracket;
* if the arguments fit on one line, that is the layout;
* otherwise one argument a line, each followed by a comma (the "magic
  trailing comma"), and each of those lines laid out the same way if it is
  still too long (a string too long for any line stays as it is).

:func:`split_call` applies that rule and answers None for anything else
(operators to split, subscripts, starred arguments, non-ASCII text, a
comment): the code generator then asks black itself. Tests hold this
module to black on every statement of the corpus and on generated ones.
"""

from __future__ import annotations

# typing is for the checker only: importing it costs a conversion 5 ms
TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import List, Optional


LINE_LENGTH = 88
INDENT = "    "
_OPEN = {"(": ")", "[": "]", "{": "}"}
_CLOSE = {")", "]", "}"}


def split_call(code: str, indent: int) -> Optional[List[str]]:
    """The lines of ``code`` (a statement, written at ``indent`` columns)
    as black writes them, or None when the rule above does not cover it."""
    if not code.isascii() or "#" in _outside_strings(code):
        return None
    lines = _layout(code, indent)
    if lines is None:
        return None
    return [" " * depth + text for depth, text in lines]


def _layout(line: str, indent: int) -> Optional[List[tuple]]:
    if indent + len(line) <= LINE_LENGTH:
        return [(indent, line)]
    trailer = "," if line.endswith(",") else ""
    body_line = line[: len(line) - len(trailer)]
    if not body_line.endswith(")"):
        return None if _splittable(body_line) else [(indent, line)]
    opening = _matching_open(body_line)
    if opening is None:
        return None
    head, body = body_line[: opening + 1], body_line[opening + 1 : -1]
    if not body or not _plain_head(head):
        return None
    inner = indent + len(INDENT)
    items = _top_level_items(body)
    if items is None:
        return None
    if inner + len(body) <= LINE_LENGTH and not body.endswith(","):
        return [(indent, head), (inner, body), (indent, ")" + trailer)]
    if len(items) == 1:  # nothing to split at: the argument's own brackets
        lines = _layout(items[0], inner)
        if lines is None or items[0].startswith("*"):
            return None
        return [(indent, head)] + lines + [(indent, ")" + trailer)]
    out = [(indent, head)]
    for item in items:
        if item.startswith("*"):
            return None
        lines = _layout(item + ",", inner)
        if lines is None:
            return None
        out.extend(lines)
    out.append((indent, ")" + trailer))
    return out


def _plain_head(head: str) -> bool:
    """A head black splits after: a name, attribute or keyword argument
    and the call's opening bracket, with no bracket left open before it."""
    text = _outside_strings(head[:-1])
    return not any(c in text for c in "()[]{}") and not any(
        op in text for op in (" + ", " - ", " * ", " / ", " and ", " or ", " if ")
    )


def _splittable(line: str) -> bool:
    """Whether a line that does not end in a call has anything black could
    split (brackets or operators outside strings): an atom alone does not."""
    text = _outside_strings(line)
    return any(c in text for c in "()[]{} ")


def _matching_open(line: str) -> Optional[int]:
    """The index of the bracket the last character of ``line`` closes."""
    stack: List[int] = []
    for index, char in _code_chars(line):
        if char in _OPEN:
            stack.append(index)
        elif char in _CLOSE:
            if not stack:
                return None
            opened = stack.pop()
            if index == len(line) - 1:
                return opened
    return None


def _top_level_items(body: str) -> Optional[List[str]]:
    """``body`` split at the commas outside brackets and strings."""
    items, depth, start = [], 0, 0
    for index, char in _code_chars(body):
        if char in _OPEN:
            depth += 1
        elif char in _CLOSE:
            depth -= 1
            if depth < 0:
                return None
        elif char == "," and depth == 0:
            items.append(body[start:index].strip())
            start = index + 1
    last = body[start:].strip()
    if last:
        items.append(last)
    if depth != 0 or not all(items):
        return None
    return items


def _code_chars(text: str):
    """(index, character) of ``text`` outside string literals."""
    quote = None
    escaped = False
    for index, char in enumerate(text):
        if quote is not None:
            if escaped:
                escaped = False
            elif char == "\\":
                escaped = True
            elif char == quote:
                quote = None
            continue
        if char in "\"'":
            quote = char
            continue
        yield index, char


def _outside_strings(text: str) -> str:
    return "".join(char for _, char in _code_chars(text))


__all__ = ["split_call"]
