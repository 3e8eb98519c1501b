"""Data rows straight to trace text, when the values are written as printed.

rs274's trace prints every position and feed rate with four decimals. Most
CAM output has at most four decimals too, so the code generator writes such
a table's values as the trace prints them (``12.3450`` for ``X12.345``):
the text is still the exact value (``float("12.3450") == 12.345``), and it
is also the text of the trace line. Such a table is run with
``as_printed=True`` (:func:`runtime.fast.rows.run_rows`).

For a :class:`runtime.canon.TraceCanon`, a plain straight move of such a row
then needs no float at all: the line is the row's cells put into the
``STRAIGHT_FEED(...)`` pattern, with the axes the row does not name taken
from the text of the previous move. That removes the two costs of a CAM
row's trace, reading each value as a float and formatting it back. Floats
are made once, at the end of the run, for the machine's state.

The loop is :meth:`runtime.fast.moves.FastPathMixin.plain_rows` with strings:
it runs while the machine is plain (see runtime.fast.moves) and stops, for
the general path, at the first row that is not a G0/G1 move of X Y Z A B C
and F, or whose feed rate would be an error. Like the canon, it owns the
canon's line counter and N column while it runs; the trace text of the
whole run is written at the end, in one piece, before anything else can be.
"""

from __future__ import annotations

from itertools import takewhile

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import List

from runtime.canon import trace_format, trace_rows
from runtime.codes import G0, G1, G4

_FEED = "%5d %sSTRAIGHT_FEED(%s, %s, %s, %s, %s, %s)\n"
_TRAVERSE = "%5d %sSTRAIGHT_TRAVERSE(%s, %s, %s, %s, %s, %s)\n"
_FEED_RATE = "%5d %sSET_FEED_RATE(%s)\n"
_DWELL = "%5d %sDWELL(%s)\n"
_PRINTED_AXES = 6  # the trace shows X Y Z A B C
_ENTRY = " ".join(["%.4f"] * _PRINTED_AXES)
_STRAIGHT = (G0, G1)


def _axis_of(slot) -> int:
    return slot[1]


def printed_rows(machine, by_index, cells: List[str], at: int, end: int, plans) -> int:
    """Write the trace of the rows from ``cells[at]`` while they are plain
    moves; returns where it stopped (a row for the general path, or
    ``end``). ``by_index``: each shape's ``_Plan.printed``."""
    if not machine._plain or by_index[int(cells[at + 1])] is None:
        return at
    canon = machine.canon
    count, column, block_n = canon._count, canon._column, machine._block_n
    cur = machine.current
    # (one C format for the six: a run between general lines may be a row)
    entry = trace_format(_ENTRY, tuple(cur[:_PRINTED_AXES])).split(" ")
    texts = entry[:]
    motion_mode, feed_rate = machine.motion_mode, machine.feed_rate
    out: List[str] = []
    write = out.append
    row = at
    try:
        while at < end:
            row = at
            printed = by_index[int(cells[at + 1])]
            if printed is None:
                break
            motion, has_n, f_at, width, run, slots = printed
            if motion == G4:  # a pause, G4 P alone (Machine.dwell_row's line)
                start = at + 2 + has_n
                if float(cells[start]) == -1.0:
                    break  # (rs274's "no P": block() raises it)
                at = start + width - has_n
                if has_n:
                    if cells[start - 1] != block_n:
                        block_n = cells[start - 1]
                        column = "N%-6s" % block_n
                elif block_n is not None:
                    column, block_n = "N..... ", None
                count += 1
                write(_DWELL % (count, column, cells[start]))
                continue
            if motion is None:
                motion = motion_mode
            stride = width + 2
            if (
                end - at >= stride * BATCH
                # (the last of BATCH rows of this shape, looked at first)
                and cells[at + 1 + stride * (BATCH - 1)] == cells[at + 1]
                and motion in _STRAIGHT
            ):
                batch = _batch(cells, at, end, printed, motion, feed_rate, texts, count)
                if batch is not None:
                    text, rows, count, last_f = batch
                    write(text)
                    at += rows * stride
                    row = at - stride  # the batch's last row
                    start = row + 2 + has_n
                    for i, axis in slots:
                        texts[axis] = cells[start + i]
                    if has_n:
                        block_n = cells[row + 2]
                        column = "N%-6s" % block_n
                    elif block_n is not None:
                        column, block_n = "N..... ", None
                    if last_f is not None:
                        feed_rate = last_f
                    motion_mode = motion
                    continue
            start = at + 2
            at = start + width
            if has_n:
                n = cells[start]
                start += 1
                if n != block_n:
                    column = "N%-6s" % n
                    block_n = n
            elif block_n is not None:
                column = "N..... "
                block_n = None
            if f_at >= 0:
                f_text = cells[start + f_at]
                f = float(f_text)
                if f < 0.0 or (motion == G1 and f == 0.0) or motion not in _STRAIGHT:
                    at = row
                    break
                feed_rate = f
                count += 1
                write(_FEED_RATE % (count, column, f_text))
            elif motion == G1:
                if feed_rate <= 0.0:
                    at = row
                    break
            elif motion != G0:
                at = row
                break
            if run is None:
                for i, axis in slots:
                    texts[axis] = cells[start + i]
            else:
                first, axis, k = run
                texts[axis : axis + k] = cells[start + first : start + first + k]
            count += 1
            line = _FEED if motion == G1 else _TRAVERSE
            write(trace_format(line, (count, column, *texts)))
            motion_mode = motion
    finally:
        if out:
            if len(out) < BATCH:  # (a row or two between others: the lines waiting)
                canon._pending += out
            else:
                canon._write_batch("".join(out))
            canon._count, canon._column = count, column
            if count >= canon._drain_at:
                canon._drain()
            point = cur[:]
            for axis in range(_PRINTED_AXES):
                if texts[axis] is not entry[axis]:  # a row named it
                    point[axis] = float(texts[axis])
            machine.current = machine.world.position = machine.params.position = point
            machine.motion_mode = motion_mode
            if feed_rate != machine.feed_rate:  # as plain_rows: see runtime.world
                machine.feed_rate = machine.world.feed_rate = feed_rate
            machine._block_n = block_n
            machine.line = int(cells[row])
    return at


#: Rows of one shape in a row, at least, for the batch form below (and
#: runtime.fast.rows.straight_batch); at most (bounds the slices a batch takes).
BATCH = 8
MOST = 4096


def _batch(cells, at, end, printed, motion, feed_rate, texts, count):
    """The trace of the consecutive rows of the shape of the row at ``at``,
    made in one go: ``(text, rows, new line count, last F or None)``; None
    for fewer than ``BATCH`` such rows, or a feed rate that would be an
    error (the row-by-row loop stops at it).

    Rows of one shape sit ``width + 2`` cells apart, so each of their
    columns is one slice of ``cells``, and one format with the axes the
    shape does not name filled in makes each line: the per-row work is
    C's. The scan stops at the first row of another shape, whose shape
    cell is where a row of this shape would have had its own."""
    _, has_n, f_at, width, _, slots = printed
    stride = width + 2
    key = cells[at + 1]
    shapes = cells[at + 1 : at + 1 + stride * BATCH : stride]
    if shapes.count(key) != BATCH:
        return None
    shapes = cells[at + 1 : min(end, at + 1 + stride * MOST) : stride]
    rows = len(list(takewhile(key.__eq__, shapes)))
    stop = at + rows * stride
    values = at + 2 + has_n  # the first value cell of the first row
    column = "N%-6s" if has_n else "N....."
    axes = list(texts)
    for _, axis in slots:
        axes[axis] = "%s"
    move = "%%5d %s%s(%s)\n" % (
        column if has_n else column + " ",
        "STRAIGHT_FEED" if motion == G1 else "STRAIGHT_TRAVERSE",
        ", ".join(axes),
    )
    # the format's %s stand in axis order, whatever order the row's words
    # were written in (G1 Y1 X2)
    columns = [
        cells[values + i : stop : stride] for i, _ in sorted(slots, key=_axis_of)
    ]
    last_f = None
    if f_at >= 0:
        rates_text = cells[values + f_at : stop : stride]
        rates = list(map(float, rates_text))
        lowest = min(rates)
        if lowest < 0.0 or (motion == G1 and lowest == 0.0):
            return None
        last_f = rates[-1]
        fmt = (
            "%%5d %sSET_FEED_RATE(%%s)\n" % (column if has_n else column + " ")
        ) + move
        numbers = cells[at + 2 : stop : stride] if has_n else None
        parts = [range(count + 1, count + 2 * rows, 2)]
        parts += [numbers, rates_text] if has_n else [rates_text]
        parts.append(range(count + 2, count + 2 * rows + 1, 2))
        parts += [numbers] if has_n else []
        count += 2 * rows
    else:
        if motion == G1 and feed_rate <= 0.0:
            return None
        fmt = move
        parts = [range(count + 1, count + rows + 1)]
        parts += [cells[at + 2 : stop : stride]] if has_n else []
        count += rows
    text = trace_rows(fmt, [*parts, *columns])
    return text, rows, count, last_f
