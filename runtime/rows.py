"""Constant blocks kept as data by the code generator, and their loop.

A run of at least ``codegen.MIN_ROWS`` G-code lines that hold only literal
words (a CAM file's moves: no expressions, settings, comments, block delete,
O-words or read errors) is compiled into one flat tuple of literals instead
of one statement per line. Each row is, in order:

* the G-code line number;
* the index of its *shape* in the module's ``SHAPES`` table: the row's G/M
  codes (``runtime.codes`` numbers) and the keyword letters of its words;
* one value per letter: floats, except ``"n"`` (first when present), whose
  value is the N number as written, a string (rs274 prints it that way).

``ROWS_1 = (24, 0, 1.0, 2.0, ...)`` with ``SHAPES = (((G1,), ("x", "y")),)``
means line 24 is ``G1 X1 Y2``; the generated module writes one row per text
line. Rows have different lengths, so they are walked by their shapes.
"""

from __future__ import annotations

from typing import Sequence, Tuple

Shape = Tuple[Tuple[int, ...], Tuple[str, ...]]


def run_rows(machine, shapes: Sequence[Shape], rows: Sequence) -> None:
    """Execute ``rows`` as ``machine.block(line, *codes, **words)`` calls.

    An error is tagged with the row's G-code line (``ngc_row_line``) so the
    source map can name it: the generated frame only knows which table ran.
    """
    line = 0
    at, end = 0, len(rows)
    try:
        while at < end:
            line = rows[at]
            codes, letters = shapes[rows[at + 1]]
            start = at + 2
            at = start + len(letters)
            machine.block(line, *codes, **dict(zip(letters, rows[start:at])))
    except Exception as error:
        error.ngc_row_line = line
        raise
