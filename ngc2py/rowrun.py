"""The parser's fast lane: a region of CAM lines recognised at once.

Most of a CAM file is lines such as ``X12.5 Y-3.25`` or ``G1 Z-1 F800``:
literal words only, which the parser keeps as data rows
(:class:`parser.RowLine`). Reading them one at a time costs microseconds of
Python each; this module recognises a whole region of them with a few
C-level operations on the bytes and keeps it as one :class:`RowRun`, one
item for the later passes (structure, definite assignment, code
generation) instead of thousands.

How a line is known to be a row without reading it: its *template*. A
region is a stretch of whole lines made only of letters, digits, ``. + -``
and blanks (and a CR before the newline). A line's template is its bytes
with every digit made ``0``, except in the values of G, M, H, L and T
words, which rs274 checks as it reads them and which decide the row's
shape: those stay as written. Two lines with the same template are read
the same way by the parser -- same words, letters and codes, the same
checks passing -- because the values a template hides are only ever
converted, never checked; the one exception is a negative F or S (``F-0``
reads, ``F-5`` fails), so templates with ``F-`` or ``S-`` are left to the
line reader. So the parser reads one line of each new template
(:func:`parser.read_row_line`) and its answer holds for every line with
that template. Lines it declines, lines with trailing blanks (their text
is stripped) and lines too long for rs274's buffer are read one at a time
as before; nothing else changes, so every line gets exactly the Line or
RowLine it got without this module.
"""

from __future__ import annotations

import re
from itertools import accumulate, count, repeat
from operator import add

from ngc2py import source

# typing is for the checker only: importing it costs a conversion 5 ms
TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Dict, List, Tuple, Union

#: The bytes a region's lines are made of.
_ALLOWED = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789.+- \t\r\n"
#: A CR that does not end its line (rs274 keeps it in the line).
_LONE_CR = re.compile(rb"\r(?!\n)")
#: Words whose values rs274 checks while reading (and G/M: the shape).
_CHECKED_WORD = re.compile(rb"([GgMmHhLlTt][+-]?[0-9.]*)")
#: Their digits and dots, moved out of the way of the next step.
_KEEP = bytes.maketrans(b"0123456789.", bytes(range(0x80, 0x8B)))
#: Every other digit.
_ZEROS = bytes.maketrans(b"123456789", b"000000000")
#: Values the parser checks for sign.
_SIGNED = re.compile(rb"[FfSs]-")
#: Longest line (CR included) that fits rs274's buffer with its newline.
_LONGEST = source.LINE_LIMIT - 2
#: Bytes looked at for one region; fewer lines than this are left alone
#: (the lane's fixed cost would exceed reading them).
REGION_BYTES = 1 << 18
MIN_LINES = 4

if TYPE_CHECKING:
    Shape = Tuple[Tuple[int, ...], Tuple[str, ...]]


class Lane:
    """The fast lane of one file's parse: templates seen and their shapes."""

    def __init__(self, file: str, axes: str, shapes: Dict):
        self.file = file
        self.axes = axes
        self.shapes = shapes  # the parser's interned shapes
        #: template -> index in ``kind_shapes``, or -1: not a row here
        self.kinds: Dict[bytes, int] = {}
        self.kind_shapes: List[Shape] = []
        #: the line read for each kind: its digits are laid out as in every
        #: line of the kind (ngc2py.rowtable reads that layout)
        self.kind_lines: List[bytes] = []
        self.facts: Dict[int, tuple] = {}  # ngc2py.rowtable's, per kind

    def region_end(self, data: bytes, pos: int) -> int:
        """Where the region of whole lane lines starting at ``pos`` ends
        (``pos`` when there is none worth the lane)."""
        stop = self._inside(data, pos, min(pos + REGION_BYTES, len(data)))
        end = data.rfind(b"\n", pos, stop) + 1
        if end <= pos:
            return pos
        if data.find(b"\r", pos, end) != -1:
            cr = _LONE_CR.search(data, pos, end)
            if cr is not None:
                end = data.rfind(b"\n", pos, cr.start()) + 1
        if end <= pos or data.count(b"\n", pos, end) < MIN_LINES:
            return pos
        return end

    @staticmethod
    def _inside(data: bytes, pos: int, limit: int) -> int:
        """Where the first byte a region never holds is, from ``pos`` on
        (``limit`` if none before it). Looked for in growing windows: a
        translate deleting the bytes allowed is cheaper than a search when
        there is none, and a window small to begin with keeps files of
        other lines from paying for a whole region each line."""
        window = 256
        while pos < limit:
            end = min(pos + window, limit)
            outside = data[pos:end].translate(None, _ALLOWED)
            if outside:
                return min(data.find(byte, pos, end) for byte in set(outside))
            pos, window = end, window * 4
        return limit

    def scan(
        self, data: bytes, pos: int, end: int, number: int
    ) -> Tuple[List[Union["RowRun", source.RawLine]], int, int]:
        """The region ``data[pos:end]`` (whole lines, the first numbered
        ``number``) as row runs and the raw lines the line reader must read,
        in order; and the position after it and its number of lines."""
        region = data[pos:end]
        templates = line_templates(region)
        kinds = self.kinds
        new = set(templates).difference(kinds)
        starts: List[int] = []
        if new:
            starts = _starts(templates)
        # each new template read at its first line, in the order of the lines
        for i, template in enumerate(templates):
            if not new:
                break
            if template in new:
                new.discard(template)
                kinds[template] = self._resolve(template, i, starts[i], region, number)
        row_kinds = list(map(kinds.__getitem__, templates))
        consumed = len(region)
        if -1 not in row_kinds:
            run = RowRun(number, _rows(region), row_kinds, self)
            return [run], pos + consumed, len(row_kinds)
        starts = starts or _starts(templates)
        items: List[Union[RowRun, source.RawLine]] = []
        at = 0
        while at < len(row_kinds):
            try:
                bad = row_kinds.index(-1, at)
            except ValueError:
                bad = len(row_kinds)
            if bad > at:
                rows = _rows(region[starts[at] : starts[bad]])
                items.append(RowRun(number + at, rows, row_kinds[at:bad], self))
            if bad < len(row_kinds):
                line = region[starts[bad] : starts[bad + 1] - 1]
                if len(line) > _LONGEST:  # as source.read_line reads it
                    raw = source.RawLine(
                        number + bad, source.decode(line[: source.LINE_LIMIT]), True
                    )
                else:
                    raw = source.RawLine(
                        number + bad, source.decode(line.rstrip(source.C_SPACE))
                    )
                items.append(raw)
            at = bad + 1
        return items, pos + consumed, len(row_kinds)

    def _resolve(
        self, template: bytes, i: int, start: int, region: bytes, number: int
    ) -> int:
        """The kind of the lines with ``template``: the parser reads the
        first of them, line ``i`` of the region, at byte ``start``."""
        if len(template) > _LONGEST:
            return -1  # too long for rs274's buffer: an error
        if template[-1:] in (b" ", b"\t") or template.endswith((b" \r", b"\t\r")):
            return -1  # rs274 strips trailing blanks: not the bytes as they are
        if _SIGNED.search(template):
            return -1
        from ngc2py.parser import read_row_line

        line = region[start : start + len(template)].rstrip(b"\r")
        row = read_row_line(
            line.decode("ascii"), number + i, self.file, self.axes, self.shapes
        )
        if row is None:
            return -1
        self.kind_shapes.append(row.shape)
        self.kind_lines.append(line)
        return len(self.kind_shapes) - 1


def python_line_templates(region: bytes) -> List[bytes]:
    """Each line's template (see the module's doc) of ``region``, whole
    lines: what ngc2py._rowtext.line_templates makes in one pass."""
    parts = _CHECKED_WORD.split(region)
    parts[1::2] = map(bytes.translate, parts[1::2], repeat(_KEEP))
    templates = b"".join(parts).translate(_ZEROS).split(b"\n")
    templates.pop()  # after the last newline
    return templates


try:
    from ngc2py._rowtext import line_templates
except ImportError:  # not built
    line_templates = python_line_templates


def _starts(templates: List[bytes]) -> List[int]:
    """Where each line of a region begins, and the end of the last (its
    newline counted): the lengths summed in C, which a region of thousands
    of lines that are all known rows need not pay for at all."""
    return list(map(add, accumulate(map(len, templates), initial=0), count()))


def _rows(region: bytes) -> bytes:
    """A region's lines as the parser sees their text (no CR)."""
    return region.replace(b"\r\n", b"\n") if b"\r" in region else region


class RowRun:
    """Consecutive lines that are all data rows, kept as their bytes (each
    line ending in a newline) and each line's kind (``lane.kind_shapes``).

    It reads like one line without O-word, error or comment to the passes
    that pair O-words and find skip errors; the code generator writes its
    rows in bulk (ngc2py.rowtable) and reads single lines only for a run
    too short for a table."""

    __slots__ = ("number", "data", "kinds", "lane")
    oword = error = None
    oword_unread = False
    percent = block_delete = is_blank = False
    comments = ()

    def __init__(self, number: int, data: bytes, kinds: List[int], lane: Lane):
        self.number = number  # of the first line
        self.data = data
        self.kinds = kinds
        self.lane = lane

    @property
    def count(self) -> int:
        return len(self.kinds)

    @property
    def file(self) -> str:
        return self.lane.file

    def text(self) -> str:
        """The lines' texts joined by newlines."""
        return self.data[:-1].decode("ascii")

    def lines(self) -> list:
        """Each line as its :class:`parser.RowLine`."""
        from ngc2py.parser import read_row_line

        lane = self.lane
        lines = []
        for i, text in enumerate(self.text().split("\n")):
            row = read_row_line(
                text, self.number + i, lane.file, lane.axes, lane.shapes
            )
            assert row is not None
            lines.append(row)
        return lines

    def final(self):
        """The last line (a :class:`parser.RowLine`)."""
        return self.split(self.count - 1)[1].lines()[0]

    def split(self, k: int) -> Tuple["RowRun", "RowRun"]:
        """The first ``k`` lines and the rest (``0 < k < count``)."""
        at = len(self.data) - len(self.data.split(b"\n", k)[-1])
        return (
            RowRun(self.number, self.data[:at], self.kinds[:k], self.lane),
            RowRun(self.number + k, self.data[at:], self.kinds[k:], self.lane),
        )
