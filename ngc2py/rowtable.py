"""A row run's lines of a row table, made in bulk (see codegen.row_table).

A :class:`rowrun.RowRun` holds CAM lines as bytes. Its rows are the same
text ``codegen`` writes for each :class:`parser.RowLine` -- line number,
shape index, the values as written (the N digits first) -- and, for a
table written as printed, the values as rs274's trace prints them
(``12.3450``). Both are made here with whole-region ``bytes`` operations
(translate, replace, expandtabs), not a Python step per value:

* cells: G and M words dropped (they are the shape), every other letter
  and blank becomes one space, so each line reads `` v1 v2`` -- a space
  before each value, the N digits marked ``=``;
* printed: a value whose text has at most four decimals, at most eleven
  integer digits and no leading zero is printed by ``%.4f`` as its own
  digits with the decimals padded to four (a sign ``+`` dropped, ``.5``
  read as ``0.5``): the float nearest to it is within 0.00005 of it. Such
  values are padded with ``expandtabs``: each value's column restarts at
  its point and a tab after it pads to a fixed column. A run with any other
  value is checked value by value, as ``codegen.as_printed`` does.
"""

from __future__ import annotations

import re
from collections import namedtuple
from itertools import chain, compress

from ngc2py.rowrun import RowRun

# typing is for the checker only: importing it costs a conversion 5 ms
TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Dict, Iterable, List, Optional, Tuple

_LETTERS = b"ABCDEFGHIJKLMOPQRSTUVWXYZabcdefghijklmopqrstuvwxyz"
#: Letters to one space each, N to the marker ``=``, G and M to ``\x01``
#: (a byte no row holds: the mark of a word that is no value); blanks are
#: deleted (a row's blanks are only ever between words, so a G or M word's
#: digits follow its mark).
_TO_CELLS = bytes.maketrans(
    _LETTERS + b"Nn",
    bytes(1 if letter in b"GgMm" else 32 for letter in _LETTERS) + b"==",
)
#: A G or M word once marked: a literal first byte, which the regular
#: expression engine finds as fast as memchr (``[GgMm]`` first was read a
#: byte at a time: 10 ns a byte of a whole CAM file).
_GM_WORD = re.compile(rb"\x01[+-]?[0-9.]*")
_BLANKS = b" \t"
#: N cells, taken out while the values are padded.
_N_CELL = re.compile(rb" =([0-9]+)")
#: An integer value, in the reversed text (`` 008 `` is ``800``).
_REVERSED_INTEGER = re.compile(rb" (?=[0-9]+-? )")
#: Leading zeros show as `` 0`` then a digit (signs made blanks).
_LEADING = bytes.maketrans(b"123456789-", b"111111111 ")
#: Pad spaces to zeros, separators back to spaces.
_PADDED = bytes.maketrans(b" \x01", b"0 ")
#: A tab at column 0 (before a line's first value, or on a line without
#: values) expands to this; a value's pad is 1 to 5 spaces.
_TAB_AT_START = b" " * 6


class Kind(namedtuple("Kind", "numbered integers padded odd empty")):
    """What the values of every line of one kind look like: whether the row
    starts with the N digits (``numbered``), some value has no point
    (``integers``), every value pads to its printed text (``padded``: see
    the module's doc), some value starts with ``+`` or a point (``odd``),
    there is no value but the N digits (``empty``)."""

    __slots__ = ()


def kinds(run: RowRun, present: Iterable[int]) -> Dict[int, Kind]:
    """The :class:`Kind` of each of the ``present`` kinds of ``run``."""
    lane = run.lane
    return {kind: _kind(lane, kind) for kind in present}


def _kind(lane, kind: int) -> Kind:
    facts = lane.facts.get(kind)
    if facts is None:
        numbered = integers = odd = False
        padded = empty = True
        for value in cells(lane.kind_lines[kind] + b"\n").split():
            if value.startswith(b"="):
                numbered = True
                continue
            empty = False
            odd = odd or value[:1] in b"+." or value.startswith(b"-.")
            whole, point, decimals = value.lstrip(b"+-").partition(b".")
            integers = integers or not point
            padded = padded and len(decimals) <= 4 and len(whole) <= 11
        facts = lane.facts[kind] = Kind(numbered, integers, padded, odd, empty)
    return facts


def cells(data: bytes) -> bytes:
    """Each line's values as `` v1 v2`` (N digits as `` =123``), one line
    per row, from rows' bytes."""
    text = data.translate(_TO_CELLS, _BLANKS)
    if b"\x01" in text:
        text = _GM_WORD.sub(b"", text)
    return text.replace(b"=", b" =") if b"=" in text else text


def written(text: bytes) -> bytes:
    """Each row's values as written, from :func:`cells`' text."""
    return text.replace(b"=", b"")


def printed(
    run: RowRun, text: bytes, facts: Dict[int, Kind]
) -> Optional[Tuple[bytes, Optional[List[bytes]]]]:
    """Each row's values as the trace prints them, from :func:`cells`'
    text, or None when some value is not exactly its four-decimal text;
    ``facts``: the run's kinds. With the values, the N digits
    of every row when every row has them (else they are in the values)."""
    numbers: Optional[List[bytes]] = None
    if any(kind.numbered for kind in facts.values()):
        parts = _N_CELL.split(text)
        text = b"".join(parts[0::2])
        numbers = parts[1::2]
    if any(kind.odd for kind in facts.values()):
        text = text.replace(b" +", b" ").replace(b" .", b" 0.").replace(b" -.", b" -0.")
    zeros = text.translate(_LEADING)
    padded = all(kind.padded for kind in facts.values())
    if padded and b" 00" not in zeros and b" 01" not in zeros:
        integers = [k for k, kind in facts.items() if kind.integers]
        text = _points(run, text, integers) if integers else text
        if any(kind.empty for kind in facts.values()):
            text = _pad(text)
        else:
            text = _pad_rows(text)
    else:
        text = _exact(text)
        if text is None:
            return None
    if numbers is None or len(numbers) == run.count:
        return text, numbers
    return _with_numbers(run, text, numbers), None


def _points(run: RowRun, text: bytes, integers: List[int]) -> bytes:
    """``text`` with a point after each value that has none (``800.``);
    ``integers``: the kinds of the lines with such values."""
    which = list(map(set(integers).__contains__, run.kinds))
    if sum(which) * 8 > len(which):  # many: in one pass over the text
        flipped = text.replace(b"\n", b" \n")[::-1]
        flipped = b" .".join(_REVERSED_INTEGER.split(flipped))
        return flipped[::-1].replace(b" \n", b"\n")
    lines = text.split(b"\n")
    for i in compress(range(len(which)), which):
        values = lines[i].split(b" ")
        lines[i] = b" ".join(v if not v or b"." in v else v + b"." for v in values)
    return b"\n".join(lines)


def _pad(text: bytes) -> bytes:
    """Values (all with a point) with their decimals padded to four."""
    # Each value: separator \x01, digits, then "\r" (column 0) before the
    # point and a tab after the decimals, which pads to column 6: 5 - k
    # spaces for k decimals, one more than wanted.
    text = text.replace(b" ", b"\t\x01").replace(b".", b"\r.")
    text = text.replace(b"\n", b"\t\n").expandtabs(6)
    text = text.replace(_TAB_AT_START, b"")
    text = text.replace(b" \x01", b"\x01").replace(b" \n", b"\n")
    return text.translate(_PADDED, b"\r")


def _pad_rows(text: bytes) -> bytes:
    """:func:`_pad` for rows that all have a value: the tab after each line's
    last value goes in with the next line's first separator, and nothing
    lands at column 0. Each line keeps a blank at its end (for
    :func:`rows`)."""
    text = b"\x01" + text[1:] + b" "  # the first separator; the last line end
    text = text.replace(b"\n ", b"\t\x01\n\x01").replace(b" ", b"\t\x01")
    text = text.replace(b".", b"\r.").expandtabs(6).replace(b" \x01", b"\x01")
    return text[:-1].translate(_PADDED, b"\r")


def _exact(text: bytes) -> Optional[bytes]:
    """The printed values of each line when every ``%.4f`` reads back as
    the same float (the general rule of codegen.as_printed), else None."""
    lines = text.decode("ascii").split("\n")
    lines.pop()
    values = " ".join(lines).split()
    numbers = list(map(float, values))
    texts = list(map("%.4f".__mod__, numbers))
    if list(map(float, texts)) != numbers:
        return None
    out = []
    at = 0
    for line in lines:
        width = line.count(" ")
        out.append("".join(" " + t for t in texts[at : at + width]))
        at += width
    return ("\n".join(out) + "\n").encode("ascii")


def _with_numbers(run: RowRun, text: bytes, numbers: List[bytes]) -> bytes:
    """``text`` with the N digits put back first on the rows that have them."""
    shapes = run.lane.kind_shapes
    taken = iter(numbers)
    lines = text.split(b"\n")
    for i, kind in enumerate(run.kinds):
        if shapes[kind][1][:1] == ("n",):
            lines[i] = b" " + next(taken) + lines[i]
    return b"\n".join(lines)


try:
    from ngc2py._rowtext import printed_rows as _printed_rows
except ImportError:  # not built: the bytes operations below alone
    _printed_rows = None


def quick_rows(run: RowRun, index: Dict[int, int]) -> Optional[str]:
    """What :func:`rows` makes of :func:`printed`'s values, made in one pass
    (ngc2py/_rowtext.c) where every value of the run is plain (see the
    module's doc: a sign, at most eleven integer digits and no leading zero,
    at most four decimals); None for any other run, or without the C
    extension. ``index``: as for :func:`rows`."""
    if _printed_rows is None:
        return None
    shapes = [-1] * len(run.lane.kind_shapes)
    for kind, shape in index.items():
        shapes[kind] = shape
    return _printed_rows(run.data, run.kinds, shapes, run.number)


def rows(
    run: RowRun, index: Dict[int, int], text: bytes, numbers: Optional[List[bytes]]
) -> str:
    """The run's table rows, ``line shape values`` one per text line, from
    the values' text and the N digits of every row (if they are apart);
    ``index``: the shape index in the module's SHAPES of each kind the run
    has."""
    # Formats over the whole run (the values hold no "%"): the line numbers
    # first, then the shapes (written in when there is one) and N digits.
    shapes = {kind: b"%d" % shape for kind, shape in index.items()}
    one = next(iter(shapes.values())) if len(shapes) == 1 else None
    head = b"%d " + (b"%%b" if one is None else one)
    if numbers is not None:
        head += b" %%b"
    end = b" \n" if text.endswith(b" \n") else b"\n"  # (from _pad_rows)
    form = head + text[: -len(end)].replace(end, b"\n" + head)
    first = run.number
    text = form % tuple(range(first, first + run.count))
    if one is None and numbers is not None:
        shaped = map(shapes.__getitem__, run.kinds)
        text %= tuple(chain.from_iterable(zip(shaped, numbers)))
    elif one is None:
        text %= tuple(map(shapes.__getitem__, run.kinds))
    elif numbers is not None:
        text %= tuple(numbers)
    return text.decode("ascii")
